"""Reading events off a recorded time series: level crossings and values between samples.

Every manoeuvre reads its figures the same way: find the instant a signal crosses a level (the
heading passing 90 deg, the rate of turn passing zero at the peak of a zig-zag swing) by linear
interpolation between the two samples around it, then read the other signals at that instant.
"""

from __future__ import annotations

import math

import numpy as np


def crossing_times(time: np.ndarray, values: np.ndarray, level: float) -> np.ndarray:
    """All instants where ``values`` crosses ``level``, linearly interpolated between samples.

    A sample exactly on the level counts as being above it, so a signal that touches the level
    and turns back is not a crossing, and one that starts on the level is not either.
    """
    offset = np.asarray(values, dtype=float) - level
    below = offset < 0.0
    before = np.flatnonzero(below[:-1] != below[1:])
    fraction = offset[before] / (offset[before] - offset[before + 1])
    return time[before] + fraction * (time[before + 1] - time[before])


def first_crossing(time: np.ndarray, values: np.ndarray, level: float, after: float = -math.inf) -> float:
    """The first instant at or after ``after`` where ``values`` crosses ``level``.

    NaN if there is none, or if ``after`` is NaN (an earlier event that was not reached).
    """
    instants = crossing_times(time, values, level)
    instants = instants[instants >= after]
    return float(instants[0]) if instants.size else math.nan


def value_at(time: np.ndarray, values: np.ndarray, instant: float) -> float:
    """``values`` at ``instant``, linearly interpolated; NaN for a NaN instant (an event not reached)."""
    if math.isnan(instant):
        return math.nan
    return float(np.interp(instant, time, values))


def distance_sailed(north: np.ndarray, east: np.ndarray) -> np.ndarray:
    """Cumulative length of the track from its first sample, m (one value per sample)."""
    return np.concatenate(([0.0], np.cumsum(np.hypot(np.diff(north), np.diff(east)))))


def velocity_over_ground(time: np.ndarray, north: np.ndarray, east: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(north, east) velocity of the midship point along the track, m/s (central differences)."""
    return np.gradient(north, time), np.gradient(east, time)


def wrap_angle(angle: np.ndarray | float) -> np.ndarray:
    """Angles wrapped to [-pi, pi) (an array, 0-d for a scalar)."""
    return (np.asarray(angle) + math.pi) % (2.0 * math.pi) - math.pi
