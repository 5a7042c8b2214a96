"""Error measures between a run and its replay: RMS per channel, pooled over runs, and one score.

Channels (each an RMS over the run's samples):

- heading, rad, rate of turn, rad/s, and speed through the water, m/s, of the free simulation (the
  speed where the log has a speed channel: the model's own, ``replay.SPEED``, never the measured one);
- position, m: distance between the measured and the freely simulated track;
- track, m: distance between the measured track and the track replayed with the measured
  heading (see :mod:`ship_env.workbench.fitting.replay`): the error of the track effects alone.

The **score** puts them on one scale: ``sqrt(mean_c (RMS_c / scale_c)^2)`` over heading, rate of
turn, speed and track (those measured), where the scales are the errors one accepts. The free
position is reported but left out of the score: it integrates the heading error, which the heading
channel already counts.

A replay that leaves the model's validity (a state not finite, the ship going astern) is
*diverged*: from the sample where it left, its outputs hold the last valid state
(:mod:`ship_env.workbench.fitting.replay`). Its run keeps its place in the pooled errors and score, with
the error of that held replay -- dropping it would reward a model for diverging -- and is flagged:
``diverged_at`` says when it left, a pooled row counts its ``diverged`` runs, the tables and the
fit's JSON show both, and the error ladder adds no effect whose held-out replays diverge.

By default the scales are **scale-free** (:meth:`ErrorScales.for_ship`), so that a score means the
same on a 3 m model and a 320 m tanker: with L the ship's length and U the mean speed through the
water over the runs' samples (:func:`mean_speed`),

- heading: 1 deg (an angle is already free of the ship's size);
- rate of turn: 1 deg per ship length sailed, (1 deg) x U / L;
- speed: (1 deg) x U, the error of the velocity's length that equals, across it, the heading's 1 deg
  (1.7 % of the speed);
- track: L / 30.

On the 3 m Esso Osaka model at 0.27 m/s these are 1 deg, 0.091 deg/s, 0.0047 m/s and 0.100 m; on a 320 m
tanker at 7.7 m/s, 1 deg, 0.024 deg/s, 0.13 m/s and 10.7 m. Absolute scales (``ErrorScales(heading, rate,
position, speed_error)``) may be given instead, channel by channel.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from ship_env.model import ShipModel
from ship_env.workbench.fitting.replay import Simulated
from ship_env.workbench.logs.logs import Log

#: The channels of an error report, with their display units.
CHANNEL_UNITS = {"heading": "deg", "rate_of_turn": "deg/s", "speed": "m/s", "position": "m", "track": "m"}
#: Scale-free error scales: the heading error, rad, and the heading change per ship length sailed, rad,
#: worth one unit; and the track error worth one unit as a fraction of the ship's length.
SCALE_FREE_HEADING = math.radians(1.0)
SCALE_FREE_TURN_PER_LENGTH = math.radians(1.0)
#: The speed error worth one unit as a fraction of the speed: the heading's 1 deg, in radians.
SCALE_FREE_SPEED_FRACTION = math.radians(1.0)
SCALE_FREE_TRACK_LENGTHS = 1.0 / 30.0


@dataclass(frozen=True)
class ErrorScales:
    """The error per channel that counts as one unit of the score (and weighs the fit's residuals).

    Attributes:
        heading: rad.
        rate_of_turn: rad/s.
        position: m, of the distance between measured and simulated track.
        speed_error: m/s, of the speed through the water.
        length, speed: the ship's length, m, and speed, m/s, that scale-free scales were derived from
            (:meth:`for_ship`; None for absolute scales): they only explain the scales in words.
    """

    heading: float = math.radians(1.0)
    rate_of_turn: float = math.radians(0.1)
    position: float = 0.1
    speed_error: float = 0.005
    length: float | None = None
    speed: float | None = None

    def __post_init__(self) -> None:
        for name in ("heading", "rate_of_turn", "position", "speed_error"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0.0):
                raise ValueError(f"error scale {name!r} must be positive, got {value!r}")

    @classmethod
    def for_ship(cls, length: float, speed: float) -> ErrorScales:
        """Scale-free scales for a ship of ``length`` (m) at ``speed`` (m/s): heading 1 deg, rate of turn
        (1 deg) x U / L (1 deg per ship length sailed), speed (1 deg) x U, track L / 30."""
        if not (math.isfinite(length) and length > 0.0):
            raise ValueError(f"error scales: the ship's length must be positive, got {length!r} m")
        if not (math.isfinite(speed) and speed > 0.0):
            raise ValueError(f"error scales: the mean speed through the water must be positive, got {speed!r} m/s")
        return cls(
            heading=SCALE_FREE_HEADING,
            rate_of_turn=SCALE_FREE_TURN_PER_LENGTH * speed / length,
            position=SCALE_FREE_TRACK_LENGTHS * length,
            speed_error=SCALE_FREE_SPEED_FRACTION * speed,
            length=length,
            speed=speed,
        )

    @classmethod
    def for_runs(cls, model: ShipModel, logs: Sequence[Log]) -> ErrorScales:
        """Scale-free scales for the model's ship sailing ``logs`` (:meth:`for_ship` at their :func:`mean_speed`)."""
        return cls.for_ship(model.length, mean_speed(model, logs))

    def describe(self) -> str:
        """The scales in words, saying which are scale-free and what they were derived from."""
        rate = f"rate of turn {math.degrees(self.rate_of_turn):.3g} deg/s"
        track = f"track {self.position:.3g} m"
        speed = f"speed {self.speed_error:.3g} m/s"
        if self.length is not None and self.speed is not None:
            per_length = self.rate_of_turn * self.length / self.speed
            if math.isclose(per_length, SCALE_FREE_TURN_PER_LENGTH):
                rate += f" (1 deg per ship length at {self.speed:.3g} m/s)"
            if math.isclose(self.speed_error, SCALE_FREE_SPEED_FRACTION * self.speed):
                speed += f" ({100.0 * SCALE_FREE_SPEED_FRACTION:.2g} % of {self.speed:.3g} m/s)"
            if math.isclose(self.position, SCALE_FREE_TRACK_LENGTHS * self.length):
                track += f" (L/{1.0 / SCALE_FREE_TRACK_LENGTHS:.0f}, L = {self.length:g} m)"
        return f"heading {math.degrees(self.heading):.3g} deg, {rate}, {speed}, {track}"


def mean_speed(model: ShipModel, logs: Sequence[Log]) -> float:
    """The mean speed through the water over all samples of ``logs``, m/s: the speed channel's magnitude where a
    log has one (a ship going astern sails its lengths too), else its service speed (or the ship's)."""
    total = samples = 0.0
    for log in logs:
        if log.speed is not None:
            total += float(np.sum(np.abs(log.speed)))
        else:
            total += log.samples * (log.service_speed if log.service_speed is not None else model.service_speed)
        samples += log.samples
    return total / samples if samples else model.service_speed


@dataclass(frozen=True)
class RunErrors:
    """RMS errors of one run (or pooled over runs), SI units; NaN where a channel is not measured (the speed
    where a log has no speed channel).

    ``samples`` counts the samples behind the RMS values (for pooling); ``diverged`` the runs behind
    them whose replay left the model's validity, and ``diverged_at`` when a run's did, s (NaN if it
    did not, or for a pooled row).
    """

    name: str
    samples: int
    heading: float
    rate_of_turn: float
    position: float
    track: float
    speed: float = math.nan
    diverged: int = 0
    diverged_at: float = math.nan

    def score(self, scales: ErrorScales) -> float:
        """sqrt(mean (RMS / scale)^2) over heading, rate of turn, speed and track (those measured)."""
        parts = [
            self.heading / scales.heading,
            self.rate_of_turn / scales.rate_of_turn,
            self.speed / scales.speed_error,
            self.track / scales.position,
        ]
        measured = [part**2 for part in parts if math.isfinite(part)]
        return math.sqrt(sum(measured) / len(measured)) if measured else math.nan

    def in_display_units(self) -> dict[str, float]:
        """The RMS values in deg, deg/s, m/s and m (``CHANNEL_UNITS``)."""
        return {
            "heading": math.degrees(self.heading),
            "rate_of_turn": math.degrees(self.rate_of_turn),
            "speed": self.speed,
            "position": self.position,
            "track": self.track,
        }


def _rms(values: np.ndarray) -> float:
    return float(np.sqrt(np.mean(values**2)))


def run_errors(log: Log, simulated: Simulated, where: np.ndarray | None = None) -> RunErrors:
    """The RMS errors of one replayed run, over all its samples or those ``where`` is True (NaN if none)."""
    nan = math.nan
    keep = np.ones(log.samples, dtype=bool) if where is None else where
    count = int(np.count_nonzero(keep))
    if count == 0:
        return RunErrors(name=log.name, samples=0, heading=nan, rate_of_turn=nan, position=nan, track=nan)
    diverged_at = simulated.diverged_at
    position = track = nan
    if log.has_position:
        position = _rms(np.hypot(simulated.north - log.north, simulated.east - log.east)[keep])
        track = _rms(np.hypot(simulated.track_north - log.north, simulated.track_east - log.east)[keep])
    return RunErrors(
        name=log.name,
        samples=count,
        heading=_rms((simulated.heading - log.heading)[keep]),
        rate_of_turn=nan if log.rate_of_turn is None else _rms((simulated.rate_of_turn - log.rate_of_turn)[keep]),
        position=position,
        track=track,
        speed=nan if log.speed is None else _rms((simulated.speed - np.maximum(log.speed, 0.0))[keep]),
        diverged=int(math.isfinite(diverged_at)),
        diverged_at=diverged_at,
    )


def split_errors(
    logs: Sequence[Log], replays: Sequence[Simulated], masks: Sequence[np.ndarray]
) -> tuple[list[RunErrors], list[RunErrors]]:
    """Per run, its RMS errors over the samples its mask leaves out and over those it selects (NaN where none)."""
    triples = list(zip(logs, replays, masks, strict=True))
    return (
        [run_errors(log, replay, ~mask) for log, replay, mask in triples],
        [run_errors(log, replay, mask) for log, replay, mask in triples],
    )


def pooled(errors: Sequence[RunErrors], name: str = "pooled") -> RunErrors:
    """RMS over all samples of several runs (runs weigh by their length); NaN-channels skipped."""

    def pool(channel: str) -> float:
        pairs = [(e.samples, getattr(e, channel)) for e in errors if math.isfinite(getattr(e, channel))]
        if not pairs or not sum(n for n, _ in pairs):
            return math.nan
        return math.sqrt(sum(n * value**2 for n, value in pairs) / sum(n for n, _ in pairs))

    return _over_runs(name, errors, pool, diverged=sum(e.diverged for e in errors))


def pooled_jackknife(errors: Sequence[RunErrors]) -> RunErrors:
    """Jackknife standard errors, over the runs, of the pooled errors (:func:`pooled`), channel by channel.

    With E_i a channel's pooled RMS with run i left out, sqrt((n - 1) / n * sum_i (E_i - mean E)^2) over
    the n runs: how much a pooled figure owes to which runs were measured (two runs: half their
    difference). NaN with fewer than two runs.
    """
    count = len(errors)
    without = [pooled([e for j, e in enumerate(errors) if j != i]) for i in range(count)]

    def spread(channel: str) -> float:
        if count < 2:
            return math.nan
        values = np.array([getattr(e, channel) for e in without])
        return float(math.sqrt((count - 1) / count * np.sum((values - values.mean()) ** 2)))

    return _over_runs("jackknife", errors, spread)


def _over_runs(name: str, errors: Sequence[RunErrors], figure: Callable[[str], float], diverged: int = 0) -> RunErrors:
    """A row over several runs: each channel's figure (``CHANNEL_UNITS``) from ``figure``, their samples summed."""
    figures = {channel: figure(channel) for channel in CHANNEL_UNITS}
    return RunErrors(name=name, samples=sum(e.samples for e in errors), diverged=diverged, **figures)
