"""A noisy channel's value, rate and acceleration: filterpy's Kalman filter and Rauch-Tung-Striebel smoother.

Each channel group is smoothed on a constant-acceleration model:

- state x = (s, ds/dt, d^2s/dt^2) of the smoothed quantity s; x_{k+1} = F x_k + w_k with
  F = [[1, dt, dt^2 / 2], [0, 1, dt], [0, 0, 1]], w_k the continuous white jerk of spectral density q integrated
  over the step (``filterpy.common.Q_continuous_white_noise``: the acceleration a continuous random walk, so an
  exact log's smoothed acceleration is an interpolating quintic spline's). The discrete white-noise model holds the
  acceleration constant over each step, and its smoothed acceleration lags half a sample wherever it changes (a
  rudder moving): 3-4 % of dv/dt and dr/dt in exact logs of a known ship, which put its hard-over turn's rate 6 %
  off (``docs/results/free_running.md``);
- measurement z_k = H x_k + e_k, e_k ~ N(0, R): the quantity itself, z = s, and its rate where a channel measures
  it, z = (s, ds/dt) (a heading with its rate gyro).

R is each channel's own noise, estimated from its samples (:func:`noise_of`: the third differences of white noise
have variance 20 sigma^2; their median absolute deviation is robust to the manoeuvre's own jerk). q is chosen
by maximum likelihood of the filter's innovations over a grid of decades (:func:`jerk_intensity`), so the
smoothing follows the channel's sampling and noise, not a setting. A channel sampled at unequal intervals is
interpolated onto equal ones first (:func:`uniform`).

The fitting stage's :mod:`~ship_env.workbench.fitting.smoothing` smooths a whole run into the states inverse
dynamics needs; :attr:`Log.rate_of_turn_or_smoothed <ship_env.workbench.logs.logs.Log.rate_of_turn_or_smoothed>`
takes a log's rate of turn from its heading where it has no rate gyro (:func:`smoothed_rate`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from filterpy.common import Q_continuous_white_noise
from numpy.polynomial.polynomial import polyfit
from scipy.linalg import solve_discrete_are

from ship_env.model.kernel import kernel

#: The jerk intensities tried, as q dt^5 / sigma^2 (the filter's behaviour depends on this ratio alone): from heavy
#: smoothing to interpolation (a log with no noise but its digits', whose innovations are likeliest at the largest).
JERK_RATIOS = 10.0 ** np.arange(-9.0, 7.0)
#: The samples a filter's start is fitted to.
START_SAMPLES = 10
#: The smallest measurement noise assumed, as a fraction of the channel's range (an exact log's noise is 0).
NOISE_FLOOR = 1e-9


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


def smoothed_rate(time: np.ndarray, values: np.ndarray) -> np.ndarray:
    """The rate of a channel sampled at ``time``, at its samples: the second state of :func:`smooth_channels` on
    the channel alone, at equally spaced times (:func:`uniform`, interpolated back to the samples' own)."""
    times, dt = uniform(time)
    if times is time:
        return smooth_channels(values[:, None], dt)[:, 1]
    rate = smooth_channels(np.interp(times, time, values)[:, None], dt)[:, 1]
    return np.interp(time, times, rate)


def uniform(time: np.ndarray) -> tuple[np.ndarray, float]:
    """The sample times a channel sampled at ``time`` (without gaps) is smoothed at, and their interval: its own
    where they are equally spaced (within 1 %), else its median interval from its first sample to its last, the
    channel interpolated linearly there."""
    steps = np.diff(time)
    dt = float(np.median(steps))
    if np.max(np.abs(steps - dt)) <= 0.01 * dt:
        return time, dt
    return time[0] + dt * np.arange(int((time[-1] - time[0]) / dt) + 1), dt


__all__ = [
    "JERK_RATIOS",
    "NOISE_FLOOR",
    "START_SAMPLES",
    "SteadyFilter",
    "jerk_intensity",
    "noise_of",
    "smooth_channels",
    "smoothed_rate",
    "uniform",
]
