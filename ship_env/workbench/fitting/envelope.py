"""Where the model holds: each sample of a run inside or outside the model's validity envelope, and why.

A ship preset states the conditions its base model is valid for, and an effect that models what the
base model leaves out widens them (:class:`~ship_env.model.declarations.Envelope`,
:attr:`ShipModel.envelope <ship_env.model.ShipModel.envelope>`). A sample lies outside when

- the speed through the water is below the minimum speed or Froude number (a ship going astern too);
- the propeller turns astern (n < 0) where the model holds for a propeller turning ahead only;
- the drift angle (course over ground against heading, from the measured track) exceeds the maximum
  (:func:`drift_angle`: the track smoothed as its own noise asks, the angle unknown where the noise would set it);
- the rate of turn exceeds the maximum.

:func:`check_envelope` gives, per run, the share outside and why ("61 % below 0.1 m/s; propeller
astern 28 % of the time"); :func:`segments_inside` cuts a run into the stretches inside, each a log of
its own that a replay restarts from its measured state.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, replace

import numpy as np
from scipy.signal import savgol_filter

from ship_env.model.declarations import Envelope
from ship_env.model.effects.wave_spectrum import GRAVITY
from ship_env.workbench.defaults import MIN_SEGMENT
from ship_env.workbench.fitting.replay import highest_speed
from ship_env.workbench.logs.channel_smoother import noise_of
from ship_env.workbench.logs.logs import MIN_SAMPLES, Log

#: The course over ground's standard error that the track's smoothing aims at (:func:`course_over_ground`), rad.
COURSE_ERROR = math.radians(1.0)
#: A sample's drift angle is unknown (NaN) where its course's standard error exceeds this, rad: the position
#: fixes' noise, not the ship, would set it there (a ship too slow for its fixes).
MAX_COURSE_ERROR = math.radians(3.0)
#: The longest window the track is smoothed over, in ship lengths sailed (L / U seconds): the drift follows the
#: rate of turn within about half of one (a sway time constant).
COURSE_WINDOW_LENGTHS = 0.5
#: The shortest window, samples: a quadratic through five fixes.
MIN_COURSE_WINDOW = 5
#: The percentile of a run's ground speed at which the window meets ``COURSE_ERROR``: the slower part of a run
#: (a hard-over turn's) is as sure as the rest.
SPEED_PERCENTILE = 10.0


@dataclass(frozen=True)
class EnvelopeCheck:
    """One run against an envelope: per reason, the samples outside.

    Attributes:
        run: the run's name.
        envelope: the envelope checked.
        outside_by: reason (``speed``, ``froude``, ``propeller``, ``drift``, ``rate``) -> samples outside.
    """

    run: str
    envelope: Envelope
    outside_by: dict[str, np.ndarray]

    @property
    def outside(self) -> np.ndarray:
        """Whether each sample lies outside for any reason."""
        masks = list(self.outside_by.values())
        return np.logical_or.reduce(masks) if masks else np.zeros(0, dtype=bool)

    @property
    def share(self) -> float:
        """The share of samples outside, 0..1."""
        return float(np.mean(self.outside)) if len(self.outside) else 0.0

    def reasons(self) -> str:
        """Why, in words: '61 % below 0.1 m/s; propeller astern 28 % of the time' (empty when all inside)."""
        limits = self.envelope
        words = {
            "speed": lambda p: f"{p} % below {limits.minimum_speed:.3g} m/s",
            "froude": lambda p: f"{p} % below Froude number {limits.minimum_froude:g}",
            "propeller": lambda p: f"propeller astern {p} % of the time",
            "drift": lambda p: (
                f"drift angle above {math.degrees(limits.maximum_drift or 0.0):.0f} deg {p} % of the time"
            ),
            "rate": lambda p: (
                f"rate of turn above {math.degrees(limits.maximum_rate or 0.0):.3g} deg/s {p} % of the time"
            ),
        }
        shares = {reason: 100.0 * float(np.mean(mask)) for reason, mask in self.outside_by.items()}
        return "; ".join(words[reason](_percent(share)) for reason, share in shares.items() if share > 0.0)

    def describe(self) -> str:
        """The share outside and why; a run wholly outside says so."""
        if self.share == 0.0:
            return "inside the envelope"
        if self.share == 1.0:
            return f"wholly outside the model's envelope: {self.reasons()}"
        return f"{_percent(100.0 * self.share)} % outside: {self.reasons()}"


def _percent(value: float) -> str:
    """A percentage rounded to whole numbers, '<1' for a small one that is not zero."""
    return "<1" if 0.0 < value < 0.5 else f"{value:.0f}"


def drift_angle(log: Log, length: float) -> np.ndarray | None:
    """The drift angle at each sample, rad: heading minus course over ground (:func:`course_over_ground`, the ship's
    ``length`` in m); NaN where the course is unknown; None without position."""
    if not log.has_position:
        return None
    assert log.north is not None and log.east is not None
    course = course_over_ground(log.time, log.north, log.east, length)
    return np.angle(np.exp(1j * (log.heading - course)))


def course_over_ground(time: np.ndarray, north: np.ndarray, east: np.ndarray, length: float) -> np.ndarray:
    """The course over ground at each sample, rad; NaN where the track's noise would set it.

    The course is the direction of the ground velocity, the slope of a quadratic fitted to the track over a
    centred window of w samples (Savitzky-Golay, ``scipy.signal.savgol_filter``): in a steady turn the slope at a
    window's centre is the tangent's, whatever the window. The window follows the track's own noise: the fixes'
    standard deviation sigma (:func:`~ship_env.workbench.logs.channel_smoother.noise_of`) gives the slope's, sigma_V =
    sigma sqrt(12 / (dt^2 w (w^2 - 1))), and w is the shortest (at least ``MIN_COURSE_WINDOW``) for which
    sigma_V / U stays within ``COURSE_ERROR`` at the run's slower ground speeds U (``SPEED_PERCENTILE``), and at most
    ``COURSE_WINDOW_LENGTHS`` ship lengths sailed (L / U s), over which the drift itself moves. Where a sample's
    course error sigma_V / |V| exceeds ``MAX_COURSE_ERROR`` (a ship slow for its fixes) the course is NaN:
    unknown, not wild. Sea-trial fixes of 3 m at 1 Hz on a 320 m ship at about 7 m/s make w 21 samples (21 s);
    a basin's 2 cm fixes at 5 Hz on a 7 m model at 1.2 m/s make w 7 (1.4 s). A log that holds each fix until
    the next (most samples repeat the last) is read at its fixes and the course interpolated between them; a
    track of fewer than ``MIN_COURSE_WINDOW`` fixes has no known course.
    """
    unknown = np.full(len(time), np.nan)
    fresh = np.r_[True, (np.diff(north) != 0.0) | (np.diff(east) != 0.0)]
    if 2 * np.count_nonzero(fresh) < len(time):
        course = course_over_ground(time[fresh], north[fresh], east[fresh], length)
        known = np.isfinite(course)
        if np.count_nonzero(known) < 2:
            return unknown
        return np.interp(time, time[fresh][known], np.unwrap(course[known]), left=np.nan, right=np.nan)
    if len(time) < MIN_COURSE_WINDOW:
        return unknown
    step = float(np.median(np.diff(time)))
    sigma = math.sqrt(0.5 * (noise_of(north) ** 2 + noise_of(east) ** 2))
    window = MIN_COURSE_WINDOW
    for _ in range(2):  # U from five samples is the noise's as much as the ship's; again from the window it gave
        speed = float(np.percentile(np.hypot(*_ground_velocity(north, east, window, step)), SPEED_PERCENTILE))
        if not speed > 0.0:
            return unknown
        # sigma_V <= U COURSE_ERROR where w (w^2 - 1) >= 12 sigma^2 / (dt U COURSE_ERROR)^2.
        needed = 12.0 * (sigma / (step * speed * COURSE_ERROR)) ** 2
        longest = min(COURSE_WINDOW_LENGTHS * length / (speed * step), len(time))
        window = MIN_COURSE_WINDOW
        while window * (window**2 - 1) < needed and window + 2 <= longest:
            window += 2
    velocity_north, velocity_east = _ground_velocity(north, east, window, step)
    slope_error = sigma * math.sqrt(12.0 / (step**2 * window * (window**2 - 1)))
    known = slope_error <= MAX_COURSE_ERROR * np.hypot(velocity_north, velocity_east)
    return np.where(known, np.arctan2(velocity_east, velocity_north), np.nan)


def _ground_velocity(north: np.ndarray, east: np.ndarray, window: int, step: float) -> tuple[np.ndarray, np.ndarray]:
    """The track's velocity north and east, m/s: the slope of a quadratic over ``window`` samples about each."""
    return (
        savgol_filter(north, window, 2, deriv=1, delta=step, mode="interp"),
        savgol_filter(east, window, 2, deriv=1, delta=step, mode="interp"),
    )


def check_envelope(log: Log, envelope: Envelope, length: float) -> EnvelopeCheck:
    """Which samples of ``log`` lie outside ``envelope`` and why (``length``: the ship's, for the Froude number).

    A log without a channel cannot leave the envelope on it (no speed channel: the service speed
    holds; no position: no drift angle).
    """
    outside: dict[str, np.ndarray] = {}
    if log.speed is not None and envelope.minimum_speed is not None:
        outside["speed"] = log.speed < envelope.minimum_speed
    if log.speed is not None and envelope.minimum_froude is not None:
        outside["froude"] = log.speed / math.sqrt(GRAVITY * length) < envelope.minimum_froude
    if log.propeller_rate is not None and envelope.propeller_ahead_only:
        outside["propeller"] = log.propeller_rate < 0.0
    drift = drift_angle(log, length)
    if drift is not None and envelope.maximum_drift is not None:
        # Where the ship barely moves, its course over ground means nothing: no drift angle there.
        moving = np.ones(log.samples, dtype=bool)
        if log.speed is not None and envelope.minimum_speed is not None:
            moving = log.speed >= envelope.minimum_speed
        outside["drift"] = moving & (np.abs(drift) > envelope.maximum_drift)
    if envelope.maximum_rate is not None:
        rate = log.rate_of_turn_or_smoothed
        outside["rate"] = np.abs(rate) > envelope.maximum_rate
    return EnvelopeCheck(log.name, envelope, outside)


def segments_inside(
    log: Log, check: EnvelopeCheck, min_duration: float = MIN_SEGMENT, length: float | None = None
) -> list[Log]:
    """The stretches of ``log`` inside the envelope, each at least ``min_duration`` long, as logs of their own.

    Each segment is cut cleanly at the first and last sample inside and named after its run and
    times (``run@12.3-45.6s``); a replay restarts it from its own measured state. With the ship's
    ``length`` (m), a run with a speed channel gives its segments its own service speed
    (:func:`~.replay.highest_speed`), which a stretch inside a turn does not show.
    """
    whole_run = highest_speed(log, length) if length is not None and log.service_speed is None else None
    service_speed = log.service_speed if whole_run is None else whole_run
    inside = ~check.outside
    edges = np.flatnonzero(np.diff(np.concatenate([[0], inside.astype(np.int8), [0]])))
    segments = []
    for first, stop in zip(edges[::2], edges[1::2], strict=True):
        if stop - first < MIN_SAMPLES or log.time[stop - 1] - log.time[first] < min_duration:
            continue
        kept = {name: getattr(log, name)[first:stop] for name in log.channels()}
        start, end = log.time[first] - log.time[0], log.time[stop - 1] - log.time[0]
        segments.append(
            replace(
                log,
                name=f"{log.name}@{start:.1f}-{end:.1f}s",
                notes=log.notes + (f"segment inside the envelope, t = {start:.1f}..{end:.1f} s",),
                service_speed=service_speed,
                **kept,
            )
        )
    return segments


def inside_logs(
    logs: Sequence[Log], envelope: Envelope, length: float, min_duration: float = MIN_SEGMENT
) -> tuple[list[Log], list[str]]:
    """Every run's segments inside the envelope, and for each segment the run it comes from (its group)."""
    segments, groups = [], []
    for log in logs:
        for segment in segments_inside(log, check_envelope(log, envelope, length), min_duration, length):
            segments.append(segment)
            groups.append(log.name)
    return segments, groups


__all__ = [
    "MIN_SEGMENT",
    "EnvelopeCheck",
    "check_envelope",
    "course_over_ground",
    "drift_angle",
    "inside_logs",
    "segments_inside",
]
