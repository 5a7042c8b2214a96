"""The data's coverage: the conditions the fitted runs reached, and the samples of other runs beyond them.

A fitted model is known where its runs went. A fit's *coverage* is the range, over all samples of
the runs it was fitted to, of

- ``speed``: the speed through the water u, m/s (where the logs measure it);
- ``rate``: the non-dimensional rate of turn |r*| = L |r| / max(U, u_min) (2.40), with the ship's
  length L, the sample's speed U (the log's speed channel, else its or the ship's service speed)
  and the ship's ``minimum_speed`` u_min, the floor the model itself divides by;
- ``drift``: the drift angle |beta|, rad (heading against the course over ground,
  :func:`~.envelope.drift_angle`), where the ship moves at u_min or faster;
- ``rudder``: the rudder angle |delta|, rad;
- ``propeller``: the propeller rate n, rps (where the logs measure it).

The ranges are robust: the ``COVERAGE_PERCENTILE`` (99th) percentile of the pooled samples is the
upper limit and, for speed and propeller rate, the 1st percentile the lower one (the magnitudes
reach down to 0), so that a few noisy samples cannot widen the coverage. A sample of a run the fit
did not see lies *beyond* the coverage where any quantity lies above its upper limit or below its
lower one; there the model extrapolates. :func:`check_coverage` gives, per run, the share of samples
beyond and why ("r* up to 2.30x the fitted runs' largest (1.05 against 0.46) 58 % of the time; ..."),
the ratio taken at the run's own 99th (or 1st) percentile. A limit counts for a run where at least
``MIN_SHARE_BEYOND`` (5 %) of its samples lie beyond it, well above the 1 % the fitted runs' own have.
"""

from __future__ import annotations

import json
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ship_env.model import ShipModel
from ship_env.model.operating_point import COVERAGE_QUANTITIES
from ship_env.workbench.fitting.envelope import _percent, drift_angle
from ship_env.workbench.fitting.errors import RunErrors, split_errors
from ship_env.workbench.fitting.fit import FitError
from ship_env.workbench.fitting.replay import Simulated
from ship_env.workbench.logs.logs import Log

#: Percentile of the fitted runs' samples taken as a quantity's upper limit (100 minus it: the lower one).
COVERAGE_PERCENTILE = 99.0
#: Smallest share of a run's samples beyond a limit for that limit to count (a run like the fitted ones
#: has 1 % beyond each limit by construction, more or less by chance).
MIN_SHARE_BEYOND = 0.05


#: The quantities of a coverage, by key (see the module docstring), shared with the simulators that check them.
QUANTITIES = COVERAGE_QUANTITIES


def coverage_samples(log: Log, model: ShipModel) -> dict[str, np.ndarray]:
    """Per quantity the log has, its value at each sample, SI units (NaN where it is not defined)."""
    minimum = model.parameter("minimum_speed")
    service = model.service_speed if log.service_speed is None else log.service_speed
    speed = np.full(log.samples, service) if log.speed is None else log.speed
    rate = log.rate_of_turn_or_smoothed
    values = {"rate": model.length * np.abs(rate) / np.maximum(speed, minimum), "rudder": np.abs(log.rudder)}
    if log.speed is not None:
        values["speed"] = log.speed
    drift = drift_angle(log, model.length)
    if drift is not None:
        values["drift"] = np.where(speed >= minimum, np.abs(drift), np.nan)
    if log.propeller_rate is not None:
        values["propeller"] = log.propeller_rate
    return values


@dataclass(frozen=True)
class Range:
    """The range of one quantity, SI units; ``low`` None for a magnitude (no lower limit)."""

    low: float | None
    high: float


@dataclass(frozen=True)
class Coverage:
    """The ranges the fitted runs covered (see the module docstring).

    Attributes:
        ranges: quantity (a key of ``QUANTITIES``) -> its range; a quantity no fitted log measures is absent.
        runs: the fitted runs' names.
        percentile: the percentile taken as the upper limit (100 minus it as the lower one).
    """

    ranges: Mapping[str, Range]
    runs: tuple[str, ...]
    percentile: float = COVERAGE_PERCENTILE

    def describe(self) -> str:
        """The ranges in words: 'speed 0.12-0.45 m/s, r* <= 0.38, ...'."""
        parts = [QUANTITIES[key].range_words(limits.low, limits.high) for key, limits in self.ranges.items()]
        return ", ".join(parts) or "nothing measured"

    def as_dict(self) -> dict:
        """The coverage for a fit's JSON (SI units)."""
        return {
            "percentile": self.percentile,
            "runs": list(self.runs),
            "ranges": {key: {"low": limits.low, "high": limits.high} for key, limits in self.ranges.items()},
        }

    @classmethod
    def from_dict(cls, document: Mapping) -> Coverage:
        """The coverage from :meth:`as_dict`'s form; a KeyError, TypeError or ValueError naming the field if not."""
        ranges = {}
        for key, limits in document["ranges"].items():
            if key not in QUANTITIES:
                raise ValueError(f"coverage: unknown quantity {key!r}; known: {', '.join(QUANTITIES)}")
            low = None if limits["low"] is None else float(limits["low"])
            ranges[key] = Range(low, float(limits["high"]))
        return cls(ranges, tuple(str(run) for run in document["runs"]), float(document["percentile"]))


def coverage_of(logs: Sequence[Log], model: ShipModel, percentile: float = COVERAGE_PERCENTILE) -> Coverage:
    """The ranges the ``logs`` cover, each quantity's samples pooled over the logs that have it."""
    pooled: dict[str, list[np.ndarray]] = {}
    for log in logs:
        for key, values in coverage_samples(log, model).items():
            pooled.setdefault(key, []).append(values)
    ranges = {}
    for key in QUANTITIES:
        values = np.concatenate(pooled[key]) if key in pooled else np.zeros(0)
        values = values[np.isfinite(values)]
        if not len(values):
            continue
        low = float(np.percentile(values, 100.0 - percentile)) if QUANTITIES[key].two_sided else None
        ranges[key] = Range(low, float(np.percentile(values, percentile)))
    return Coverage(ranges, tuple(log.name for log in logs), percentile)


@dataclass(frozen=True)
class Exceedance:
    """A run beyond one limit of a coverage.

    Attributes:
        quantity: a key of ``QUANTITIES``.
        above: True beyond the upper limit, False below the lower one.
        beyond: whether each of the run's samples lies beyond that limit.
        extreme: the run's own percentile on that side (the 99th above, the 1st below), SI units.
        limit: the coverage's limit, SI units.
    """

    quantity: str
    above: bool
    beyond: np.ndarray
    extreme: float
    limit: float

    @property
    def share(self) -> float:
        """The share of the run's samples beyond the limit, 0..1."""
        return float(np.mean(self.beyond))

    def ratio(self) -> str:
        """The run's extreme against the limit, '2.30x' ('' where a ratio means nothing: a limit at or below 0)."""
        return f"{self.extreme / self.limit:.2f}x" if self.limit > 0.0 and self.extreme > 0.0 else ""

    def words(self) -> str:
        """E.g. "r* up to 2.30x the fitted runs' largest (1.05 against 0.46) 58 % of the time"."""
        quantity = QUANTITIES[self.quantity]
        unit = f" {quantity.unit}" if quantity.unit else ""
        side, extreme = ("up to", "largest") if self.above else ("down to", "lowest")
        ratio = f"{self.ratio()} " if self.ratio() else ""
        return (
            f"{quantity.words} {side} {ratio}the fitted runs' {extreme} ({self.extreme * quantity.factor:.3g} "
            f"against {self.limit * quantity.factor:.3g}{unit}) {_percent(100.0 * self.share)} % of the time"
        )


@dataclass(frozen=True)
class CoverageCheck:
    """One run against a coverage: the limits it goes beyond, largest share first.

    Attributes:
        run: the run's name.
        samples: its number of samples.
        exceedances: the limits the run goes beyond (see :func:`check_coverage`).
    """

    run: str
    samples: int
    exceedances: tuple[Exceedance, ...]

    @property
    def beyond(self) -> np.ndarray:
        """Whether each sample lies beyond the coverage: the model extrapolates there."""
        return np.logical_or.reduce([np.zeros(self.samples, dtype=bool), *(e.beyond for e in self.exceedances)])

    @property
    def share(self) -> float:
        """The share of samples beyond, 0..1."""
        return float(np.mean(self.beyond))

    def reasons(self) -> str:
        """Why, in words: "r* up to 2.30x the fitted runs' largest (1.05 against 0.46) 58 % of the time; ..."."""
        return "; ".join(exceedance.words() for exceedance in self.exceedances)

    def describe(self) -> str:
        """The share beyond and why: "64 % of samples extrapolated: r* up to 2.30x ..."."""
        if not self.exceedances:
            return "within the fitted runs' coverage"
        return f"{_percent(100.0 * self.share)} % of samples extrapolated: {self.reasons()}"


def check_coverage(log: Log, coverage: Coverage, model: ShipModel) -> CoverageCheck:
    """Which samples of ``log`` lie beyond ``coverage`` and why (``model``: the ship's length, speeds).

    A limit counts where at least ``MIN_SHARE_BEYOND`` (5 %) of the run's samples lie beyond it: a run
    like the fitted ones has 1 % of its samples beyond each limit by construction, and a few noisy
    samples over a limit do not make a run extrapolate (its 99th or 1st percentile, the extreme shown,
    then lies beyond the limit). A quantity the log or the coverage lacks takes no sample beyond.
    """
    exceedances = []
    for key, values in coverage_samples(log, model).items():
        limits = coverage.ranges.get(key)
        finite = values[np.isfinite(values)]
        if limits is None or not len(finite):
            continue
        sides = [(True, limits.high, values > limits.high, coverage.percentile)]
        if limits.low is not None:
            sides.append((False, limits.low, values < limits.low, 100.0 - coverage.percentile))
        for above, limit, beyond, percentile in sides:
            if np.mean(beyond) >= MIN_SHARE_BEYOND:
                exceedances.append(Exceedance(key, above, beyond, float(np.percentile(finite, percentile)), limit))
    exceedances.sort(key=lambda exceedance: -exceedance.share)
    return CoverageCheck(log.name, log.samples, tuple(exceedances))


def beyond_in_words(checks: Sequence[CoverageCheck]) -> str:
    """The quantities in which runs go beyond the coverage, with their pooled shares of the samples:
    "beyond the fitted runs' r* 58 %, rudder 40 % of their samples" (empty where none is beyond)."""
    samples = sum(check.samples for check in checks)
    counts: dict[str, int] = {}
    for check in checks:
        for exceedance in check.exceedances:
            counts[exceedance.quantity] = counts.get(exceedance.quantity, 0) + int(np.sum(exceedance.beyond))
    if not counts or not samples:
        return ""
    ranked = sorted(counts.items(), key=lambda item: -item[1])
    shown = ", ".join(f"{QUANTITIES[key].words} {_percent(100.0 * count / samples)} %" for key, count in ranked)
    return f"beyond the fitted runs' {shown} of their samples"


def errors_inside_beyond(
    logs: Sequence[Log], replays: Sequence[Simulated], checks: Sequence[CoverageCheck]
) -> tuple[list[RunErrors], list[RunErrors]]:
    """Per run, its RMS errors over the samples inside the coverage, and over those beyond (NaN where none)."""
    return split_errors(logs, replays, [check.beyond for check in checks])


def fitted_coverage(path: Path) -> Coverage | None:
    """The coverage stored in a fit's JSON (``ship-env fit --json``), or None where it holds none."""
    try:
        document = json.loads(path.read_text())
        return Coverage.from_dict(document["coverage"]) if "coverage" in document else None
    except OSError as error:
        raise FitError(f"cannot read {str(path)!r}: {error.strerror}") from None
    except (ValueError, KeyError, TypeError) as error:
        raise FitError(f"{path}: its 'coverage' is not a fit's coverage: {error}") from None


__all__ = [
    "COVERAGE_PERCENTILE",
    "MIN_SHARE_BEYOND",
    "QUANTITIES",
    "Coverage",
    "CoverageCheck",
    "Exceedance",
    "Range",
    "beyond_in_words",
    "check_coverage",
    "coverage_of",
    "coverage_samples",
    "errors_inside_beyond",
    "fitted_coverage",
]
