"""The leaderboard's tables: the episodes aggregated per entrant, ranked per suite, as markdown and CSV.

Each suite's table ranks its entrants by the suite's first metric, lower first (ties by name).
On the nominal TrackFollow suite the thesis's navigators (Table 6.4: 117 m with parallel
indexing, 95 m with the ground-speed vector, 33 m with the track predictor) are ranked beside
them as human rows. Under each table with learned entrants, each is compared with
the best classic baseline (the lowest first metric): it *beats* it when its first metric is lower
and its rudder travel at most :data:`TRAVEL_ALLOWANCE` times the baseline's.
"""

from __future__ import annotations

import csv
import math
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from ship_env.envs.metrics import THESIS_NAVIGATOR_RMS
from ship_env.leaderboard.sailing import EpisodeResult
from ship_env.leaderboard.suites import COMPLETION, NOMINAL, TRACK_FOLLOW, Metric, Suite

#: A learned policy beats a baseline only with at most this multiple of its rudder travel.
TRAVEL_ALLOWANCE = 1.5
#: The human rows of the nominal TrackFollow table (thesis Table 6.4), by their names there.
HUMAN_ROWS = {
    "navigators, parallel indexing (thesis)": THESIS_NAVIGATOR_RMS["parallel_indexing"],
    "navigators, ground-speed vector (thesis)": THESIS_NAVIGATOR_RMS["ground_speed_vector"],
    "navigators, track predictor (thesis)": THESIS_NAVIGATOR_RMS["track_predictor"],
}
HUMAN = "human"


@dataclass(frozen=True)
class Standing:
    """One row of a suite's table.

    Attributes:
        rank: 1 for the lowest first metric.
        entrant: the controller's name.
        kind: ``"classic"``, ``"learned"`` or ``"human"``.
        values: metric key -> the episodes' aggregate (NaN where there is none).
        episodes: the episodes sailed (0 for a human row).
        completed: the episodes completed (:data:`~ship_env.leaderboard.suites.COMPLETION`).
    """

    rank: int
    entrant: str
    kind: str
    values: dict[str, float]
    episodes: int
    completed: int


@dataclass(frozen=True)
class Table:
    """A suite's ranked standings."""

    suite: Suite
    standings: tuple[Standing, ...]

    def standing(self, entrant: str) -> Standing:
        """The row of ``entrant``; ``KeyError`` if it did not sail this suite."""
        for standing in self.standings:
            if standing.entrant == entrant:
                return standing
        raise KeyError(f"{entrant!r} did not sail {self.suite.name}")


@dataclass(frozen=True)
class Comparison:
    """A learned entrant against the best classic baseline of a suite.

    Attributes:
        learned, classic: the two entrants' names.
        score_ratio: learned / classic first metric.
        travel_ratio: learned / classic rudder travel.
    """

    learned: str
    classic: str
    score_ratio: float
    travel_ratio: float

    @property
    def beats(self) -> bool:
        """Lower first metric with at most :data:`TRAVEL_ALLOWANCE` times the rudder travel."""
        return self.score_ratio < 1.0 and self.travel_ratio <= TRAVEL_ALLOWANCE


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


def rank(suite: Suite, results: Sequence[EpisodeResult]) -> Table:
    """The table of ``suite`` from its episodes in ``results`` (others are ignored)."""
    by_entrant: dict[str, list[EpisodeResult]] = {}
    for result in results:
        if result.suite == suite.name:
            by_entrant.setdefault(result.entrant, []).append(result)
    rows = [
        (
            name,
            episodes[0].kind,
            {metric.key: _aggregate(metric, [e.metrics[metric.key] for e in episodes]) for metric in suite.metrics},
            len(episodes),
            sum(_completed(e) for e in episodes),
        )
        for name, episodes in by_entrant.items()
    ]
    if suite.env_id == TRACK_FOLLOW and suite.condition == NOMINAL:
        for name, rms in HUMAN_ROWS.items():
            values = {metric.key: math.nan for metric in suite.metrics} | {suite.metrics[0].key: rms}
            rows.append((name, HUMAN, values, 0, 0))
    score = suite.metrics[0].key
    rows.sort(key=lambda row: (math.isnan(row[2][score]), row[2][score], row[0]))
    return Table(suite, tuple(Standing(k + 1, *row) for k, row in enumerate(rows)))


def comparisons(table: Table) -> list[Comparison]:
    """Each learned entrant of ``table`` against its best classic baseline (none without either)."""
    classic = [standing for standing in table.standings if standing.kind == "classic"]
    if not classic:
        return []
    score = table.suite.metrics[0].key
    best = min(classic, key=lambda standing: standing.values[score])
    return [
        Comparison(
            standing.entrant,
            best.entrant,
            standing.values[score] / best.values[score],
            standing.values["rudder_travel"] / best.values["rudder_travel"],
        )
        for standing in table.standings
        if standing.kind == "learned"
    ]


def _cell(value: float, digits: int) -> str:
    return "" if math.isnan(value) else f"{value:.{digits}f}"


def markdown(table: Table) -> str:
    """The table in markdown, with a heading naming the suite and, below, the comparisons."""
    suite = table.suite
    completion = COMPLETION[suite.env_id]
    lines = [
        f"### {suite.name}",
        "",
        f"Episodes per controller: {len(suite.episodes)}; ranked by {suite.metrics[0].heading}, lower is better.",
        "",
        "| rank | controller | kind | " + " | ".join(metric.heading for metric in suite.metrics) + f" | {completion} |",
        "|---:|---|---|" + "---:|" * (len(suite.metrics) + 1),
    ]
    for standing in table.standings:
        cells = [_cell(standing.values[metric.key], metric.digits) for metric in suite.metrics]
        done = f"{standing.completed}/{standing.episodes}" if standing.episodes else ""
        lines.append(f"| {standing.rank} | {standing.entrant} | {standing.kind} | {' | '.join(cells)} | {done} |")
    for comparison in comparisons(table):
        verdict = "beats it" if comparison.beats else "does not beat it"
        lines.append(
            f"\n{comparison.learned} against the best classic baseline, {comparison.classic}: "
            f"{suite.metrics[0].key.replace('_', ' ')} x{comparison.score_ratio:.4f}, "
            f"rudder travel x{comparison.travel_ratio:.2f} (allowed x{TRAVEL_ALLOWANCE:g}): {verdict}."
        )
    return "\n".join(lines)


def write_csv(tables: Sequence[Table], path: Path) -> None:
    """Every table's rows in one CSV: suite, task, condition, rank, controller, kind, counts, metrics."""
    keys = list(dict.fromkeys(metric.key for table in tables for metric in table.suite.metrics))
    with Path(path).open("w", newline="") as handle:
        writer = csv.writer(handle)
        writer.writerow(["suite", "task", "condition", "rank", "controller", "kind", "episodes", "completed", *keys])
        for table in tables:
            suite = table.suite
            for s in table.standings:
                values = [repr(s.values[key]) if key in s.values else "" for key in keys]
                row = [suite.name, suite.task, suite.condition.name, s.rank, s.entrant, s.kind, s.episodes, s.completed]
                writer.writerow([*row, *values])


def write_episodes_csv(results: Sequence[EpisodeResult], path: Path) -> None:
    """Every episode: suite, controller, kind, episode, seed, finished, its metrics."""
    keys = list(dict.fromkeys(key for result in results for key in result.metrics))
    with Path(path).open("w", newline="") as handle:
        writer = csv.writer(handle)
        writer.writerow(["suite", "controller", "kind", "episode", "seed", "finished", *keys])
        for r in results:
            values = [repr(r.metrics[key]) if key in r.metrics else "" for key in keys]
            writer.writerow([r.suite, r.entrant, r.kind, r.episode, r.seed, r.finished, *values])
