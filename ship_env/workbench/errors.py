"""Error measures between a run and its replay: RMS per channel, pooled over runs, and one score.

Channels (each an RMS over the run's samples):

- heading, rad, and rate of turn, rad/s, of the free simulation;
- position, m: distance between the measured and the freely simulated track;
- track, m: distance between the measured track and the track replayed with the measured
  heading (see :mod:`ship_env.workbench.replay`): the error of the track effects alone.

The **score** puts them on one scale: ``sqrt(mean_c (RMS_c / scale_c)^2)`` over heading, rate of
turn and track, where the scales are the errors one accepts (by default near sensor noise). The
free position is reported but left out of the score: it integrates the heading error, which the
heading channel already counts.

A replay that leaves the model's validity (a state not finite, the ship going astern) is
*diverged*: from the sample where it left, its outputs hold the last valid state
(:mod:`ship_env.workbench.replay`). Its run keeps its place in the pooled errors and score, with
the error of that held replay -- dropping it would reward a model for diverging -- and is flagged:
``diverged_at`` says when it left, a pooled row counts its ``diverged`` runs, the tables and the
fit's JSON show both, and the error ladder adds no effect whose held-out replays diverge.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from ship_env.workbench.logs import Log
from ship_env.workbench.replay import Simulated

#: The channels of an error report, with their display units.
CHANNEL_UNITS = {"heading": "deg", "rate_of_turn": "deg/s", "position": "m", "track": "m"}


@dataclass(frozen=True)
class ErrorScales:
    """The error per channel that counts as one unit of the score (and weighs the fit's residuals).

    Attributes:
        heading: rad.
        rate_of_turn: rad/s.
        position: m, of the distance between measured and simulated track.
    """

    heading: float = math.radians(1.0)
    rate_of_turn: float = math.radians(0.1)
    position: float = 0.1

    def __post_init__(self) -> None:
        for name in ("heading", "rate_of_turn", "position"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0.0):
                raise ValueError(f"error scale {name!r} must be positive, got {value!r}")


@dataclass(frozen=True)
class RunErrors:
    """RMS errors of one run (or pooled over runs), SI units; NaN where a channel is not measured.

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
    diverged: int = 0
    diverged_at: float = math.nan

    def score(self, scales: ErrorScales) -> float:
        """sqrt(mean (RMS / scale)^2) over heading, rate of turn and track (those measured)."""
        parts = [
            self.heading / scales.heading,
            self.rate_of_turn / scales.rate_of_turn,
            self.track / scales.position,
        ]
        measured = [part**2 for part in parts if math.isfinite(part)]
        return math.sqrt(sum(measured) / len(measured)) if measured else math.nan

    def in_display_units(self) -> dict[str, float]:
        """The RMS values in deg, deg/s and m."""
        return {
            "heading": math.degrees(self.heading),
            "rate_of_turn": math.degrees(self.rate_of_turn),
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
        diverged=int(math.isfinite(diverged_at)),
        diverged_at=diverged_at,
    )


def pooled(errors: Sequence[RunErrors], name: str = "pooled") -> RunErrors:
    """RMS over all samples of several runs (runs weigh by their length); NaN-channels skipped."""

    def pool(channel: str) -> float:
        pairs = [(e.samples, getattr(e, channel)) for e in errors if math.isfinite(getattr(e, channel))]
        if not pairs or not sum(n for n, _ in pairs):
            return math.nan
        return math.sqrt(sum(n * value**2 for n, value in pairs) / sum(n for n, _ in pairs))

    return RunErrors(
        name=name,
        samples=sum(e.samples for e in errors),
        heading=pool("heading"),
        rate_of_turn=pool("rate_of_turn"),
        position=pool("position"),
        track=pool("track"),
        diverged=sum(e.diverged for e in errors),
    )
