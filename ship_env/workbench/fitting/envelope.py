"""Where the model holds: each sample of a run inside or outside the model's validity envelope, and why.

A ship preset states the conditions its base model is valid for, and an effect that models what the
base model leaves out widens them (:class:`~ship_env.model.declarations.Envelope`,
:attr:`ShipModel.envelope <ship_env.model.ShipModel.envelope>`). A sample lies outside when

- the speed through the water is below the minimum speed or Froude number (a ship going astern too);
- the propeller turns astern (n < 0) where the model holds for a propeller turning ahead only;
- the drift angle (course over ground against heading, from the measured track) exceeds the maximum;
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
from scipy.ndimage import uniform_filter1d

from ship_env.model.declarations import Envelope
from ship_env.model.effects.wave_spectrum import GRAVITY
from ship_env.workbench.defaults import MIN_SEGMENT
from ship_env.workbench.fitting.replay import highest_speed
from ship_env.workbench.logs.logs import MIN_SAMPLES, Log

#: Seconds over which the track is smoothed before the course over ground is taken from it.
COURSE_WINDOW = 1.0


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
            "speed": lambda p: f"{p} % below {limits.minimum_speed:g} m/s",
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


def drift_angle(log: Log, window: float = COURSE_WINDOW) -> np.ndarray | None:
    """The drift angle, rad: heading minus course over ground (from the smoothed track); None without position."""
    if not log.has_position:
        return None
    step = float(np.median(np.diff(log.time)))
    width = max(1, int(round(window / step)))
    north = uniform_filter1d(log.north, width, mode="nearest")
    east = uniform_filter1d(log.east, width, mode="nearest")
    course = np.arctan2(np.gradient(east, log.time), np.gradient(north, log.time))
    return np.angle(np.exp(1j * (log.heading - course)))


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
    drift = drift_angle(log)
    if drift is not None and envelope.maximum_drift is not None:
        # Where the ship barely moves, its course over ground means nothing: no drift angle there.
        moving = np.ones(log.samples, dtype=bool)
        if log.speed is not None and envelope.minimum_speed is not None:
            moving = log.speed >= envelope.minimum_speed
        outside["drift"] = moving & (np.abs(drift) > envelope.maximum_drift)
    if envelope.maximum_rate is not None:
        rate = log.rate_of_turn_or_gradient
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


__all__ = ["MIN_SEGMENT", "EnvelopeCheck", "check_envelope", "drift_angle", "inside_logs", "segments_inside"]
