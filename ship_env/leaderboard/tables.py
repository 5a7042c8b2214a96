"""The leaderboard's rankings: each suite's scores with their statistics, ranked, and the learned entrants' verdicts.

An entrant's scores on a suite are a (training seeds x episodes) matrix of the suite's ranking
metric (a classic autopilot, deterministic, has one row). Each row of a suite's table gives the
statistics of :mod:`ship_env.leaderboard.statistics`: the IQM of the ranking metric and of the
normalised score (1 = the environment's reference autopilot) with 95 % stratified-bootstrap
intervals, and its probability of improvement over the best classic autopilot (the lowest IQM).
The other metrics are plain aggregates over all its episodes. Rows are ranked by the IQM, lower first (ties by name).

Each learned entrant gets a *verdict* against the best classic autopilot, from the 95 % interval
of its probability of improvement over it (:attr:`Comparison.verdict`): **better** where the whole
interval lies above parity (0.5), with at most :data:`TRAVEL_ALLOWANCE` times the autopilot's rudder
travel, completing (every training seed) each episode that a classic autopilot completes; **worse**
where the whole interval lies below parity; **tied** otherwise (the interval includes parity, no
interval, or better by the interval but over the rudder allowance or missing an episode). More
episodes narrow the interval, so they can resolve a tie but, short of the 5 % chance of any 95 %
interval, not turn better into worse. Other learned entrants do not change the verdict.
On the nominal TrackFollow suite the thesis's navigators (Table 6.4: 117 m with parallel indexing,
95 m with the ground-speed vector, 33 m with the track predictor) are ranked beside them as human rows.
:mod:`ship_env.leaderboard.rendering` writes the rankings out as markdown and CSV.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence

import numpy as np

from ship_env.envs.metrics import THESIS_NAVIGATOR_RMS
from ship_env.leaderboard.sailing import EpisodeResult
from ship_env.leaderboard.statistics import PARITY, REFERENCES, Estimate, improvements, interval_estimates
from ship_env.leaderboard.suites import FIRST_WAYPOINT, NOMINAL, TRACK_FOLLOW, Metric, Suite

#: A learned policy beats a baseline only with at most this multiple of its rudder travel.
TRAVEL_ALLOWANCE = 1.5
#: The human rows of the nominal TrackFollow table (thesis Table 6.4), by their names there.
HUMAN_ROWS = {
    "navigators, parallel indexing (thesis)": THESIS_NAVIGATOR_RMS["parallel_indexing"],
    "navigators, ground-speed vector (thesis)": THESIS_NAVIGATOR_RMS["ground_speed_vector"],
    "navigators, track predictor (thesis)": THESIS_NAVIGATOR_RMS["track_predictor"],
}
HUMAN = "human"
NO_ESTIMATE = Estimate(math.nan)
#: A learned entrant's verdicts against the best classic autopilot (:attr:`Comparison.verdict`).
BETTER, TIED, WORSE = "better", "tied", "worse"
VERDICTS = (BETTER, TIED, WORSE)


@dataclasses.dataclass(frozen=True)
class Standing:
    """One row of a suite's table.

    Attributes:
        rank: 1 for the lowest IQM of the ranking metric.
        entrant: the controller's name.
        kind: ``"classic"``, ``"learned"`` or ``"human"``.
        score: the IQM of the ranking metric with its interval.
        normalised: the IQM of the normalised score (1 = the reference autopilot) with its interval.
        improvement: the probability of improvement over the best classic autopilot with its
            interval (``None`` for that autopilot itself and the human rows).
        values: metric key -> the aggregate over all the episodes (NaN where there is none).
        seeds: the training seeds sailed (1 for a classic autopilot, 0 for a human row).
        episodes: the episodes sailed per seed.
        completed: the episodes completed, all seeds together (:data:`~ship_env.leaderboard.suites.COMPLETION`).
        missed: the episodes (label, seed) that some training seed did not complete.
    """

    rank: int
    entrant: str
    kind: str
    score: Estimate
    normalised: Estimate
    improvement: Estimate | None
    values: dict[str, float]
    seeds: int
    episodes: int
    completed: int
    missed: frozenset[tuple[str, int]] = frozenset()

    @property
    def sample(self) -> str:
        """What the intervals are over: ``"5 seeds x 10 episodes"``, ``"10 episodes (deterministic)"``..."""
        if self.kind == HUMAN:
            return ""
        if not self.score.has_interval:
            return f"{self.seeds} x {self.episodes}: no interval"
        if self.kind == "classic":
            return f"{self.episodes} episodes (deterministic)"
        if self.seeds == 1:
            return f"1 seed x {self.episodes} episodes (episodes only)"
        return f"{self.seeds} seeds x {self.episodes} episodes"


@dataclasses.dataclass(frozen=True)
class SuiteRanking:
    """A suite's ranked standings."""

    suite: Suite
    standings: tuple[Standing, ...]

    def standing(self, entrant: str) -> Standing:
        """The row of ``entrant``; ``KeyError`` if it did not sail this suite."""
        for standing in self.standings:
            if standing.entrant == entrant:
                return standing
        raise KeyError(f"{entrant!r} did not sail {self.suite.name}")


@dataclasses.dataclass(frozen=True)
class Comparison:
    """A learned entrant against the best classic autopilot of a suite.

    Attributes:
        learned, classic: the two entrants' names.
        improvement: the learned entrant's probability of improvement over the classic one.
        score_ratio: learned / classic IQM of the ranking metric.
        travel_ratio: learned / classic rudder travel (means over the episodes).
        settles: completed, with every training seed, each episode a classic autopilot completed.
    """

    learned: str
    classic: str
    improvement: Estimate
    score_ratio: float
    travel_ratio: float
    settles: bool

    @property
    def verdict(self) -> str:
        """:data:`BETTER`: the probability of improvement's interval above parity, with at most
        :data:`TRAVEL_ALLOWANCE` times the rudder travel, completing every episode a classic
        autopilot completes; :data:`WORSE`: the interval below parity; :data:`TIED` otherwise."""
        if self.improvement.above(PARITY) and self.travel_ratio <= TRAVEL_ALLOWANCE and self.settles:
            return BETTER
        return WORSE if self.improvement.below(PARITY) else TIED

    @property
    def reason(self) -> str:
        """What decided :attr:`verdict`, in words."""
        if not self.improvement.has_interval:
            return "no interval: a single score"
        if self.improvement.above(PARITY):
            if self.travel_ratio > TRAVEL_ALLOWANCE:
                return f"the interval lies above parity, 0.5, with more than x{TRAVEL_ALLOWANCE:g} the rudder travel"
            if not self.settles:
                return "the interval lies above parity, 0.5, missing an episode a classic autopilot completes"
            return "the interval lies above parity, 0.5"
        if self.improvement.below(PARITY):
            return "the interval lies below parity, 0.5"
        return "the interval includes parity, 0.5"


def _aggregate(metric: Metric, values: list[float]) -> float:
    if metric.aggregate == "max":
        return max(values)
    if metric.aggregate == "finite mean":
        values = [value for value in values if math.isfinite(value)]
    return math.fsum(values) / len(values) if values else math.nan


def _completed(result: EpisodeResult) -> bool:
    """Settled (a finite settling time) on a course change, the last waypoint passed on a track."""
    settling_time = result.metrics.get("settling_time")
    return result.finished if settling_time is None else math.isfinite(settling_time)


def score_matrix(suite: Suite, results: Sequence[EpisodeResult]) -> np.ndarray:
    """One entrant's ranking metric on ``suite`` as (training seeds x episodes), seeds in
    ascending order, episodes in the suite's order; ``ValueError`` if an episode is missing."""
    key = suite.metrics[0].key
    column = {(episode.label, episode.seed): k for k, episode in enumerate(suite.episodes)}
    seeds = sorted({result.training_seed for result in results}, key=lambda seed: -1 if seed is None else seed)
    matrix = np.full((len(seeds), len(suite.episodes)), np.nan)
    for result in results:
        matrix[seeds.index(result.training_seed), column[result.episode, result.seed]] = result.metrics[key]
    if np.isnan(matrix).any():
        raise ValueError(f"{results[0].entrant} on {suite.name}: not every seed sailed every episode")
    return matrix


def grouped_estimates(layers: dict[str, list[np.ndarray]], aggregates: Sequence[str]) -> dict[str, list[Estimate]]:
    """Each entrant's layers (matrices of the same shape) aggregated (``aggregates``: one per layer,
    ``"iqm"`` or ``"mean"``) with intervals: one bootstrap for all the entrants whose matrices have
    the same shape (as many seeds and episodes), so one or two per table."""
    by_shape: dict[tuple[int, ...], list[str]] = {}
    for name, matrices in layers.items():
        by_shape.setdefault(matrices[0].shape, []).append(name)
    found = {}
    for names in by_shape.values():
        stacked = np.stack([matrix for name in names for matrix in layers[name]], axis=2)
        estimates = interval_estimates(stacked, list(aggregates) * len(names))
        width = len(aggregates)
        for k, name in enumerate(names):
            found[name] = estimates[k * width : (k + 1) * width]
    return found


def rank(suite: Suite, results: Sequence[EpisodeResult]) -> SuiteRanking:
    """The table of ``suite`` from its episodes in ``results`` (others are ignored)."""
    by_entrant: dict[str, list[EpisodeResult]] = {}
    for result in results:
        if result.suite == suite.name:
            by_entrant.setdefault(result.entrant, []).append(result)
    kinds = {name: episodes[0].kind for name, episodes in by_entrant.items()}
    matrices = {name: score_matrix(suite, episodes) for name, episodes in by_entrant.items()}
    reference = matrices.get(REFERENCES.get(suite.env_id, ""))
    iqms = grouped_estimates(
        {
            name: [matrix, matrix / reference if reference is not None else np.full_like(matrix, np.nan)]
            for name, matrix in matrices.items()
        },
        ["iqm", "iqm"],
    )
    classic = [name for name in matrices if kinds[name] == "classic"]
    best = min(classic, key=lambda name: (iqms[name][0].value, name)) if classic else None
    others = [name for name in matrices if name != best]
    chances = (
        {}
        if best is None
        else grouped_estimates({n: [improvements(matrices[n], matrices[best])] for n in others}, ["mean"])
    )
    rows = [
        Standing(
            0,
            name,
            kinds[name],
            iqms[name][0],
            iqms[name][1],
            chances[name][0] if name in chances else None,
            {metric.key: _aggregate(metric, [e.metrics[metric.key] for e in episodes]) for metric in suite.metrics},
            matrices[name].shape[0],
            len(suite.episodes),
            sum(_completed(e) for e in episodes),
            frozenset((e.episode, e.seed) for e in episodes if not _completed(e)),
        )
        for name, episodes in by_entrant.items()
    ]
    whole_track = suite.env_kwargs.get("start", FIRST_WAYPOINT) == FIRST_WAYPOINT
    if suite.env_id == TRACK_FOLLOW and suite.condition == NOMINAL and whole_track:  # the thesis's runs
        for name, rms in HUMAN_ROWS.items():
            values = {metric.key: math.nan for metric in suite.metrics} | {suite.metrics[0].key: rms}
            rows.append(Standing(0, name, HUMAN, Estimate(rms), NO_ESTIMATE, None, values, 0, 0, 0))
    rows.sort(key=lambda row: (math.isnan(row.score.value), row.score.value, row.entrant))
    return SuiteRanking(suite, tuple(dataclasses.replace(row, rank=k + 1) for k, row in enumerate(rows)))


def best_classic(table: SuiteRanking) -> Standing | None:
    """The classic autopilot with the lowest IQM (``None`` if none sailed)."""
    return next((standing for standing in table.standings if standing.kind == "classic"), None)


def comparisons(table: SuiteRanking) -> list[Comparison]:
    """Each learned entrant of ``table`` against the best classic autopilot (none without either)."""
    best = best_classic(table)
    if best is None:
        return []
    classics_missed = [s.missed for s in table.standings if s.kind == "classic"]
    missed_by_all = frozenset.intersection(*classics_missed)
    return [
        Comparison(
            standing.entrant,
            best.entrant,
            standing.improvement if standing.improvement is not None else NO_ESTIMATE,
            standing.score.value / best.score.value,
            standing.values["rudder_travel"] / best.values["rudder_travel"],
            standing.missed <= missed_by_all,
        )
        for standing in table.standings
        if standing.kind == "learned"
    ]


def learned_verdicts(tables: Sequence[SuiteRanking], entrant: str) -> dict[str, Comparison]:
    """Suite name -> ``entrant``'s comparison with the best classic autopilot, on each suite it sailed."""
    return {t.suite.name: c for t in tables for c in comparisons(t) if c.learned == entrant}
