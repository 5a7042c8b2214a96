"""A measured run's motion smoothed into states and their rates: u, v, r and du/dt, dv/dt, dr/dt.

Inverse dynamics (:mod:`.inverse_dynamics`) needs the accelerations, which no log measures, and the sway
velocity v, which few do. Both come from the measured channels through filterpy's Kalman filter and
Rauch-Tung-Striebel smoother on a constant-acceleration model, one per channel group:

- state x = (s, ds/dt, d^2s/dt^2) of the smoothed quantity s; x_{k+1} = F x_k + w_k with
  F = [[1, dt, dt^2 / 2], [0, 1, dt], [0, 0, 1]], w_k the continuous white jerk of spectral density q integrated
  over the step (``filterpy.common.Q_continuous_white_noise``: the acceleration a continuous random walk, so an
  exact log's smoothed acceleration is an interpolating quintic spline's). The discrete white-noise model holds the
  acceleration constant over each step, and its smoothed acceleration lags half a sample wherever it changes (a
  rudder moving): 3-4 % of dv/dt and dr/dt in exact logs of a known ship, which put its hard-over turn's rate 6 %
  off (``docs/results/free_running.md``);
- measurement z_k = H x_k + e_k, e_k ~ N(0, R):

  - the position north and east (one filter each), s the position, z = s;
  - the heading psi with the rate gyro, z = (psi, r) where the log has a rate channel, else z = psi;
  - the speed through the water u, z = u.

R is each channel's own noise, estimated from the log (:func:`noise_of`: the third differences of white noise
have variance 20 sigma^2; their median absolute deviation is robust to the manoeuvre's own jerk). q is chosen
by maximum likelihood of the filter's innovations over a grid of decades (:func:`jerk_intensity`), so the
smoothing follows the log's sampling and noise, not a setting. The body-frame sway velocity and its rate come
from the smoothed ground velocity (V_N, V_E) and acceleration (A_N, A_E) in the water (no current):

    v = -V_N sin(psi) + V_E cos(psi),    dv/dt = -A_N sin(psi) + A_E cos(psi) - r (V_N cos(psi) + V_E sin(psi)).

A run sampled at unequal intervals is interpolated onto equal ones first (:func:`uniform`); one with a gap in its
time (more than ``LONGEST_GAP`` sample intervals: a logger that dropped samples) is smoothed piece by piece between
its gaps (:func:`pieces_between_gaps`), since no filter should bridge them. A log of rudder orders is turned into the
actual rudder by the steering machine's rate (:func:`actual_rudder`). The smoothed rates are poor within a few
samples of a piece's ends; :attr:`SmoothedRun.kept` leaves out the first and last ``EDGE_LENGTHS`` ship lengths
sailed of each.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields, replace
from typing import Any

import numpy as np
from filterpy.common import Q_continuous_white_noise
from numpy.polynomial.polynomial import polyfit
from scipy.linalg import solve_discrete_are

from ship_env.model.kernel import kernel
from ship_env.workbench.logs.logs import MIN_SAMPLES, Log

#: Ship lengths sailed at each end of a run whose smoothed rates are left out.
EDGE_LENGTHS = 0.5
#: The jerk intensities tried, as q dt^5 / sigma^2 (the filter's behaviour depends on this ratio alone): from heavy
#: smoothing to interpolation (a log with no noise but its digits', whose innovations are likeliest at the largest).
JERK_RATIOS = 10.0 ** np.arange(-9.0, 7.0)
#: The channels a run must have to be smoothed into states, in words (the position gives the sway).
REQUIRED_CHANNELS = {
    "north": "position (channels 'north' and 'east')",
    "speed": "speed through the water (channel 'speed')",
    "propeller_rate": "propeller rate (channel 'propeller_rate')",
}
#: The longest gap in a run's time, in median sample intervals, across which its channels are interpolated; a run is
#: smoothed piece by piece between longer ones.
LONGEST_GAP = 5.0
#: The samples a filter's start is fitted to.
START_SAMPLES = 10
#: The smallest measurement noise assumed, as a fraction of the channel's range (an exact log's noise is 0).
NOISE_FLOOR = 1e-9


class SmoothingError(ValueError):
    """A run that cannot be smoothed into the states inverse dynamics needs (naming the run and the channel)."""


@dataclass(frozen=True)
class SmoothedRun:
    """A run's smoothed motion, each an array over its samples.

    Attributes:
        name: the run's name.
        time: s.
        surge, sway, rate_of_turn: u and v (m/s, in the water, body frame) and r (rad/s).
        surge_rate, sway_rate, yaw_acceleration: du/dt, dv/dt (m/s^2) and dr/dt (rad/s^2).
        heading: psi, rad.
        rudder, propeller_rate: as measured, rad and rps.
        kept: the samples away from the run's ends, where the rates hold.
        noise: each channel's estimated noise standard deviation (SI units).
    """

    name: str
    time: np.ndarray
    surge: np.ndarray
    sway: np.ndarray
    rate_of_turn: np.ndarray
    surge_rate: np.ndarray
    sway_rate: np.ndarray
    yaw_acceleration: np.ndarray
    heading: np.ndarray
    rudder: np.ndarray
    propeller_rate: np.ndarray
    kept: np.ndarray
    noise: dict[str, float]


def noise_of(values: np.ndarray) -> float:
    """A channel's white-noise standard deviation: the third differences' median absolute deviation over
    sqrt(20) (their variance is 20 sigma^2 for white noise), scaled to a standard deviation (1.4826); at least
    :data:`NOISE_FLOOR` times the channel's range."""
    third = np.diff(values, 3)
    spread = 1.4826 * float(np.median(np.abs(third - np.median(third)))) / math.sqrt(20.0)
    return max(spread, NOISE_FLOOR * max(float(np.ptp(values)), 1.0))


@dataclass(frozen=True)
class SteadyFilter:
    """The steady-state Kalman filter and Rauch-Tung-Striebel smoother of one channel group: the gains the
    time-varying ones converge to (Anderson & Moore 1979, ch. 4 and 7), from the discrete algebraic Riccati
    equation (``scipy.linalg.solve_discrete_are``).

    Attributes:
        transition: F, (3, 3).
        measurement: H, (m, 3).
        gain: the Kalman gain K, (3, m).
        innovation: the innovations' covariance S = H P H^T + R, (m, m), P the predicted state's covariance.
        smoother_gain: the smoother's C = P_f F^T P^-1, (3, 3), P_f the filtered state's covariance.
    """

    transition: np.ndarray
    measurement: np.ndarray
    gain: np.ndarray
    innovation: np.ndarray
    smoother_gain: np.ndarray

    @classmethod
    def of(cls, noises: np.ndarray, dt: float, ratio: float) -> SteadyFilter:
        """The filter of the first ``len(noises)`` state components measured with these noises, the jerk's
        intensity q = ``ratio`` sigma^2 / dt^5 (sigma the first channel's noise)."""
        transition = np.array([[1.0, dt, 0.5 * dt**2], [0.0, 1.0, dt], [0.0, 0.0, 1.0]])
        measurement = np.eye(3)[: len(noises)]
        jerk = Q_continuous_white_noise(3, dt, ratio * noises[0] ** 2 / dt**5)
        noise = np.diag(noises**2)
        predicted = solve_discrete_are(transition.T, measurement.T, jerk, noise)
        innovation = measurement @ predicted @ measurement.T + noise
        gain = predicted @ measurement.T @ np.linalg.inv(innovation)
        filtered = (np.eye(3) - gain @ measurement) @ predicted
        smoother_gain = filtered @ transition.T @ np.linalg.inv(predicted)
        return cls(transition, measurement, gain, innovation, smoother_gain)

    def filtered(self, measured: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(samples, 3) filtered states and (samples, m) innovations of ``measured`` (samples, m), started from a
        quadratic through the first :data:`START_SAMPLES` values (its value, slope and curvature at the first)."""
        count = min(START_SAMPLES, len(measured))
        dt = self.transition[0, 1]
        value, slope, half_curvature = polyfit(dt * np.arange(count), measured[:count, 0], 2)
        start = np.array([value, slope, 2.0 * half_curvature])
        return _filter_pass(measured, start, self.transition, self.measurement, self.gain)

    def smoothed(self, measured: np.ndarray) -> np.ndarray:
        """(samples, 3): the smoothed states (the filter forward, the smoother backward)."""
        filtered, _ = self.filtered(measured)
        return _smoother_pass(filtered, self.transition, self.smoother_gain)

    def log_likelihood(self, measured: np.ndarray, settle: int) -> float:
        """The innovations' log-likelihood (constant left out), the first ``settle`` samples left out."""
        _, innovations = self.filtered(measured)
        kept = innovations[settle:]
        weighted = np.linalg.solve(self.innovation, kept.T)
        return -0.5 * float(len(kept) * np.linalg.slogdet(self.innovation)[1] + np.sum(kept.T * weighted))


@kernel
def _filter_pass(measured, start, transition, measurement, gain):
    """The filter's recursion from the first sample's predicted state ``start``: innovation e = z - H x, update
    x += K e, predict x = F x."""
    count = measured.shape[0]
    states = np.empty((count, 3))
    innovations = np.empty(measured.shape)
    state = start.copy()
    for k in range(count):
        predicted = transition @ state if k > 0 else state
        innovations[k] = measured[k] - measurement @ predicted
        state = predicted + gain @ innovations[k]
        states[k] = state
    return states, innovations


@kernel
def _smoother_pass(filtered, transition, smoother_gain):
    """The smoother's recursion, backward: x_s[k] = x_f[k] + C (x_s[k + 1] - F x_f[k])."""
    smoothed = filtered.copy()
    for k in range(filtered.shape[0] - 2, -1, -1):
        smoothed[k] = filtered[k] + smoother_gain @ (smoothed[k + 1] - transition @ filtered[k])
    return smoothed


def jerk_intensity(measured: np.ndarray, noises: np.ndarray, dt: float) -> float:
    """The ratio of :data:`JERK_RATIOS` whose filter's innovations are most likely (the first samples, while the
    filter settles from its start, left out)."""
    settle = min(20, len(measured) // 4)
    likelihoods = [SteadyFilter.of(noises, dt, float(ratio)).log_likelihood(measured, settle) for ratio in JERK_RATIOS]
    return float(JERK_RATIOS[int(np.argmax(likelihoods))])


def smooth_channels(measured: np.ndarray, dt: float) -> np.ndarray:
    """(samples, 3): the smoothed value, rate and acceleration of the first column of ``measured`` (samples,
    channels: the value, then its rate where measured)."""
    noises = np.array([noise_of(measured[:, k]) for k in range(measured.shape[1])])
    return SteadyFilter.of(noises, dt, jerk_intensity(measured, noises, dt)).smoothed(measured)


def pieces_between_gaps(log: Log) -> list[Log]:
    """``log`` cut at each gap in its time of more than :data:`LONGEST_GAP` median sample intervals, each piece of
    :data:`START_SAMPLES` samples or more, as many as a log holds (``[log]`` where it has no gap)."""
    steps = np.diff(log.time)
    cuts = np.flatnonzero(steps > LONGEST_GAP * float(np.median(steps))) + 1
    if len(cuts) == 0:
        return [log]
    edges = [0, *cuts.tolist(), len(log.time)]
    return [
        replace(log, **{name: getattr(log, name)[first:stop] for name in log.channels()})
        for first, stop in zip(edges[:-1], edges[1:], strict=True)
        if stop - first >= max(START_SAMPLES, MIN_SAMPLES)
    ]


def uniform(log: Log) -> tuple[np.ndarray, float]:
    """The sample times a run without gaps (:func:`pieces_between_gaps`) is smoothed at, and their interval: its own
    where they are equally spaced (within 1 %), else its median interval from its first sample to its last, each
    channel interpolated linearly there."""
    steps = np.diff(log.time)
    dt = float(np.median(steps))
    if np.max(np.abs(steps - dt)) <= 0.01 * dt:
        return log.time, dt
    return log.time[0] + dt * np.arange(int((log.time[-1] - log.time[0]) / dt) + 1), dt


def actual_rudder(log: Log, times: np.ndarray, rudder_rate: float) -> np.ndarray:
    """The rudder angle at ``times``: measured, or, where the log records the order, the order followed at the
    steering machine's ``rudder_rate`` (rad/s) from the first order."""
    ordered = np.interp(times, log.time, log.rudder)
    if log.rudder_kind == "actual":
        return ordered
    actual = np.empty_like(ordered)
    actual[0] = ordered[0]
    for k in range(1, len(times)):
        largest = rudder_rate * (times[k] - times[k - 1])
        actual[k] = actual[k - 1] + np.clip(ordered[k - 1] - actual[k - 1], -largest, largest)
    return actual


def smooth_run(log: Log, length: float, rudder_rate: float, propeller_rate: float | None = None) -> SmoothedRun:
    """``log``'s motion smoothed (the module docstring) at equally spaced times (:func:`uniform`); ``length`` the
    ship's, m (the ends left out); ``rudder_rate`` its steering machine's, rad/s (for a log of rudder orders,
    :func:`actual_rudder`); ``propeller_rate`` the rate, rps, of a log without a propeller channel.

    A run with gaps in its time is smoothed piece by piece (:func:`pieces_between_gaps`), its pieces' samples
    concatenated, each piece's ends left out.

    Raises:
        SmoothingError: a log without the position or speed, or without the propeller rate where none is given;
            one whose pieces between gaps are each too short to keep a sample; naming the run and the channel.
    """
    for channel, words in REQUIRED_CHANNELS.items():
        if getattr(log, channel) is None and not (channel == "propeller_rate" and propeller_rate is not None):
            raise SmoothingError(f"log {log.name!r}: inverse dynamics needs the {words}, which this log lacks")
    noise = {
        channel: noise_of(values)
        for channel, values in (
            ("north", log.north),
            ("east", log.east),
            ("heading", log.heading),
            ("speed", log.speed),
            ("rate_of_turn", log.rate_of_turn),
        )
        if values is not None
    }
    pieces = pieces_between_gaps(log)
    parts = [_smooth_piece(piece, length, rudder_rate, propeller_rate, noise) for piece in pieces]
    if not any(np.any(part.kept) for part in parts):
        raise SmoothingError(
            f"log {log.name!r}: time: its {len(parts)} piece(s) between gaps of more than {LONGEST_GAP:g} sample "
            f"intervals each sail less than {2 * EDGE_LENGTHS:g} ship length, the ends the smoothed rates leave out"
        )
    if len(parts) == 1:
        return parts[0]
    sampled = [f.name for f in fields(SmoothedRun) if isinstance(getattr(parts[0], f.name), np.ndarray)]
    stacked: dict[str, Any] = {name: np.concatenate([getattr(part, name) for part in parts]) for name in sampled}
    return replace(parts[0], **stacked)


def _smooth_piece(
    log: Log, length: float, rudder_rate: float, propeller_rate: float | None, noise: dict[str, float]
) -> SmoothedRun:
    """One piece of a run without gaps, smoothed (:func:`smooth_run`), with the whole run's ``noise``."""
    assert log.north is not None and log.east is not None and log.speed is not None  # checked by smooth_run
    times, dt = uniform(log)

    def sampled(values: np.ndarray) -> np.ndarray:
        return values if times is log.time else np.interp(times, log.time, values)

    north = smooth_channels(sampled(log.north)[:, None], dt)
    east = smooth_channels(sampled(log.east)[:, None], dt)
    heading_measured = sampled(log.heading)
    if log.rate_of_turn is None:
        yaw = smooth_channels(heading_measured[:, None], dt)
    else:
        yaw = smooth_channels(np.column_stack((heading_measured, sampled(log.rate_of_turn))), dt)
    surge = smooth_channels(sampled(log.speed)[:, None], dt)
    heading, rate = yaw[:, 0], yaw[:, 1]
    cos, sin = np.cos(heading), np.sin(heading)
    sway = -north[:, 1] * sin + east[:, 1] * cos
    sway_rate = -north[:, 2] * sin + east[:, 2] * cos - rate * (north[:, 1] * cos + east[:, 1] * sin)
    sailed = np.concatenate(([0.0], np.cumsum(np.hypot(np.diff(north[:, 0]), np.diff(east[:, 0])))))
    kept = (sailed >= EDGE_LENGTHS * length) & (sailed <= sailed[-1] - EDGE_LENGTHS * length)
    rates = np.full(len(times), propeller_rate) if log.propeller_rate is None else sampled(log.propeller_rate)
    return SmoothedRun(
        name=log.name,
        time=times,
        surge=surge[:, 0],
        sway=sway,
        rate_of_turn=rate,
        surge_rate=surge[:, 1],
        sway_rate=sway_rate,
        yaw_acceleration=yaw[:, 2],
        heading=heading,
        rudder=actual_rudder(log, times, rudder_rate),
        propeller_rate=rates,
        kept=kept,
        noise=noise,
    )


__all__ = [
    "EDGE_LENGTHS",
    "SmoothedRun",
    "actual_rudder",
    "pieces_between_gaps",
    "SmoothingError",
    "jerk_intensity",
    "noise_of",
    "smooth_channels",
    "smooth_run",
    "uniform",
]
