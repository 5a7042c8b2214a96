"""A measured run's motion smoothed into states and their rates: u, v, r and du/dt, dv/dt, dr/dt.

Inverse dynamics (:mod:`.inverse_dynamics`) needs the accelerations, which no log measures, and the sway
velocity v, which few do. Both come from the measured channels through filterpy's Kalman filter and
Rauch-Tung-Striebel smoother on a constant-acceleration model (:mod:`~ship_env.workbench.logs.channel_smoother`:
the state, the model, the noise and how the jerk's intensity follows the log), one per channel group:

- the position north and east (one filter each), s the position, z = s;
- the heading psi with the rate gyro, z = (psi, r) where the log has a rate channel, else z = psi;
- the speed through the water u, z = u.

The body-frame sway velocity and its rate come from the smoothed ground velocity (V_N, V_E) and acceleration
(A_N, A_E) in the water (no current):

    v = -V_N sin(psi) + V_E cos(psi),    dv/dt = -A_N sin(psi) + A_E cos(psi) - r (V_N cos(psi) + V_E sin(psi)).

A run sampled at unequal intervals is interpolated onto equal ones first (``channel_smoother.uniform``); one with a
gap in its time (more than ``LONGEST_GAP`` sample intervals: a logger that dropped samples) is smoothed piece by
piece between its gaps (:func:`pieces_between_gaps`), since no filter should bridge them. A log of rudder orders is
turned into the actual rudder by the steering machine's rate (:func:`actual_rudder`). The smoothed rates are poor
within a few samples of a piece's ends; :attr:`SmoothedRun.kept` leaves out the first and last ``EDGE_LENGTHS``
ship lengths sailed of each.
"""

from __future__ import annotations

from dataclasses import dataclass, fields, replace
from typing import Any

import numpy as np

from ship_env.workbench.logs.channel_smoother import START_SAMPLES, noise_of, smooth_channels, uniform
from ship_env.workbench.logs.logs import MIN_SAMPLES, Log

#: Ship lengths sailed at each end of a run whose smoothed rates are left out.
EDGE_LENGTHS = 0.5
#: The channels a run must have to be smoothed into states, in words (the position gives the sway).
REQUIRED_CHANNELS = {
    "north": "position (channels 'north' and 'east')",
    "speed": "speed through the water (channel 'speed')",
    "propeller_rate": "propeller rate (channel 'propeller_rate')",
}
#: The longest gap in a run's time, in median sample intervals, across which its channels are interpolated; a run is
#: smoothed piece by piece between longer ones.
LONGEST_GAP = 5.0


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
    times, dt = uniform(log.time)

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
    "smooth_run",
]
