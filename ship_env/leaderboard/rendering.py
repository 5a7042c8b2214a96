"""The leaderboard's tables written out: each suite's ranking, the learned entrants' verdicts and the
headline as markdown, every suite's rows and every episode as CSV.

Each markdown table is built as a header and rows of cells (:class:`~ship_env.text_table.Table`, its
columns of numbers and of estimates with their intervals right-aligned) under a heading and a
paragraph saying what it shows; the ranking and the verdicts themselves come from
:mod:`ship_env.leaderboard.tables`.
"""

from __future__ import annotations

import csv
import math
from collections.abc import Sequence
from pathlib import Path

from ship_env.leaderboard.sailing import EpisodeResult
from ship_env.leaderboard.statistics import REFERENCES, Estimate
from ship_env.leaderboard.suites import COMPLETION, COURSE_CHANGE
from ship_env.leaderboard.tables import (
    BETTER,
    HUMAN,
    TIED,
    TRAVEL_ALLOWANCE,
    VERDICTS,
    WORSE,
    Comparison,
    SuiteRanking,
    best_classic,
    comparisons,
)
from ship_env.text_table import Table


def _cell(value: float, digits: int) -> str:
    return "" if math.isnan(value) else f"{value:.{digits}f}"


def markdown(ranking: SuiteRanking) -> str:
    """The ranking in markdown, with a heading naming the suite and the ship, each learned entrant's verdict
    against the best classic autopilot in its row and, below, the comparisons in words."""
    suite = ranking.suite
    metric = suite.metrics[0]
    others = suite.metrics[1:]
    found = {c.learned: c for c in comparisons(ranking)}
    header = (
        "rank",
        "controller",
        "kind",
        f"IQM {metric.heading} [95 % CI]",
        "normalised IQM [95 % CI]",
        "P(improvement) [95 % CI]",
        "verdict",
        *(other.heading for other in others),
        COMPLETION[suite.env_id],
        "sample",
    )
    numbers = (True, False, False, True, True, True, False, *(True for _ in others), True, False)
    rows = []
    for s in ranking.standings:
        improvement = "" if s.improvement is None else s.improvement.text(2)
        score = _cell(s.score.value, metric.digits) if s.kind == HUMAN else s.score.text(metric.digits)
        verdict = found[s.entrant].verdict if s.entrant in found else ""
        values = (_cell(s.values[other.key], other.digits) for other in others)
        done = f"{s.completed}/{s.seeds * s.episodes}" if s.episodes else ""
        rows.append(
            (str(s.rank), s.entrant, s.kind, score, s.normalised.text(3), improvement, verdict, *values, done, s.sample)
        )
    lines = [
        f"### {suite.name} on {suite.ship_name}",
        "",
        f"{len(suite.episodes)} episode(s) per training seed; ranked by the IQM of {metric.heading}, lower is better; "
        "95 % stratified-bootstrap intervals (rliable) over seeds and episodes; "
        f"normalised: 1 = {REFERENCES.get(suite.env_id, '')}; "
        "P(improvement) and verdict: against the best classic autopilot. Other columns: means over all episodes.",
        "",
        Table(header, tuple(rows), numbers=numbers).markdown(),
    ]
    for c in found.values():
        lines.append(
            f"\n{c.learned} against the best classic autopilot, {c.classic}: P(improvement) {c.improvement.text(2)}, "
            f"IQM x{c.score_ratio:.3f}, rudder travel x{c.travel_ratio:.2f}: {c.verdict} ({c.reason})."
        )
    return "\n".join(lines)


def verdict_count(comparisons_made: Sequence[Comparison]) -> str:
    """``"better on 5, tied on 4, worse on 3 of 12"``."""
    counts = {verdict: sum(c.verdict == verdict for c in comparisons_made) for verdict in VERDICTS}
    return f"better on {counts[BETTER]}, tied on {counts[TIED]}, worse on {counts[WORSE]} of {len(comparisons_made)}"


def verdicts_markdown(rankings: Sequence[SuiteRanking]) -> str:
    """Per learned entrant, its verdict on each suite (:attr:`Comparison.verdict`) as a markdown table,
    counted per environment; empty without a learned entrant."""
    rows: dict[str, list[tuple[str, ...]]] = {}
    by_environment: dict[tuple[str, str], list[Comparison]] = {}
    for ranking in rankings:
        best = best_classic(ranking)
        for c in comparisons(ranking):
            assert best is not None  # comparisons are made against it
            learned = ranking.standing(c.learned)
            rows.setdefault(c.learned, []).append(
                (
                    ranking.suite.task,
                    ranking.suite.condition.name,
                    learned.normalised.text(3),
                    f"{best.entrant} {best.normalised.text(3)}",
                    c.improvement.text(2),
                    f"x{c.travel_ratio:.2f}",
                    f"{learned.completed}/{learned.seeds * learned.episodes}",
                    "yes" if c.settles else "no",
                    f"**{c.verdict}**",
                )
            )
            by_environment.setdefault((c.learned, ranking.suite.env_id), []).append(c)
    if not rows:
        return ""
    lines = [
        "### Learned entrants against the best classic autopilot: better, tied or worse "
        f"({rankings[0].suite.ship_name})",
        "",
        "Normalised IQM [95 % CI] (1 = the reference autopilot, lower is better). Verdict from the 95 % interval "
        "of the probability of improvement over the best classic autopilot (the lowest IQM): better where it lies "
        f"above parity (0.5), with at most x{TRAVEL_ALLOWANCE:g} that autopilot's rudder travel, completing with "
        "every training seed each episode a classic autopilot completes; worse where it lies below parity; tied "
        "otherwise. More episodes can resolve a tie; they do not make a better worse.",
    ]
    numbers = (False, False, True, False, True, True, True, False, False)
    for entrant, entrant_rows in rows.items():
        header = (
            f"{entrant}: task",
            "condition",
            "normalised IQM",
            "best classic",
            "P(improvement) [95 % CI]",
            "rudder travel / best classic's",
            "completed",
            "where a classic does",
            "verdict",
        )
        lines += ["", Table(header, tuple(entrant_rows), numbers=numbers).markdown()]
        for (name, env_id), made in by_environment.items():
            if name == entrant:
                lines.append(f"\n{entrant} on the {env_id} suites: {verdict_count(made)}.")
    return "\n".join(lines)


def headline_markdown(headline: dict[str, list[Estimate]], verdicts: dict[str, Comparison], ship_name: str) -> str:
    """The headline (per CourseChange entrant, the IQM and the mean of its normalised score over the
    nominal CourseChange suites) with each learned entrant's verdict as a markdown table; empty
    without a headline."""
    if not headline:
        return ""
    best = next(iter(verdicts.values())).classic if verdicts else ""
    rows = []
    for name, (iqm, mean) in headline.items():
        c = verdicts.get(name)
        rows.append((name, iqm.text(3), mean.text(3), *(("", "") if c is None else (c.improvement.text(2), c.verdict))))
    header = ("controller", "IQM [95 % CI]", "mean [95 % CI]", "P(improvement) [95 % CI]", "verdict")
    return "\n".join(
        [
            f"### Headline: CourseChange, nominal ship, all seas together ({ship_name})",
            "",
            f"Normalised score: each episode's integrated heading error divided by that of {REFERENCES[COURSE_CHANGE]} "
            "(1 = the reference, lower is better); 95 % stratified-bootstrap intervals (rliable) over training "
            f"seeds and episodes. Verdict: against the best classic autopilot here ({best}), from the interval of "
            "the probability of improvement over it (as on each suite).",
            "",
            Table(header, tuple(rows), numbers=(False, True, True, True, False)).markdown(),
        ]
    )


def _estimate_cells(estimate: Estimate | None) -> list[str]:
    if estimate is None:
        return ["", "", ""]
    return [repr(estimate.value), *("" if bound is None else repr(bound) for bound in (estimate.low, estimate.high))]


def write_csv(rankings: Sequence[SuiteRanking], path: Path) -> None:
    """Every ranking's rows in one CSV: suite, ship, task, condition, rank, controller, kind, counts, the
    estimates with their interval bounds (empty: no interval), a learned entrant's verdict, the
    metrics' aggregates."""
    keys = list(dict.fromkeys(metric.key for ranking in rankings for metric in ranking.suite.metrics))
    estimates = [f"{name}{part}" for name in ("iqm", "normalised_iqm", "improvement") for part in ("", "_low", "_high")]
    estimates.append("verdict")
    with Path(path).open("w", newline="") as handle:
        writer = csv.writer(handle)
        head = ["suite", "ship", "task", "condition", "rank", "controller", "kind", "seeds", "episodes", "completed"]
        writer.writerow([*head, *estimates, *keys])
        for ranking in rankings:
            suite = ranking.suite
            verdicts = {c.learned: c.verdict for c in comparisons(ranking)}
            for s in ranking.standings:
                row = [suite.name, suite.ship_name, suite.task, suite.condition.name, s.rank, s.entrant, s.kind]
                row += [s.seeds, s.episodes]
                cells = [*_estimate_cells(s.score), *_estimate_cells(s.normalised), *_estimate_cells(s.improvement)]
                cells.append(verdicts.get(s.entrant, ""))
                values = [repr(s.values[key]) if key in s.values else "" for key in keys]
                writer.writerow([*row, s.completed, *cells, *values])


def write_episodes_csv(results: Sequence[EpisodeResult], path: Path, ship: str) -> None:
    """Every episode: suite, ``ship`` (the name of the ship sailed), controller, kind, training seed,
    episode, seed, finished, its metrics."""
    keys = list(dict.fromkeys(key for result in results for key in result.metrics))
    with Path(path).open("w", newline="") as handle:
        writer = csv.writer(handle)
        head = ["suite", "ship", "controller", "kind", "training_seed", "episode", "seed", "finished"]
        writer.writerow([*head, *keys])
        for r in results:
            values = [repr(r.metrics[key]) if key in r.metrics else "" for key in keys]
            training_seed = "" if r.training_seed is None else r.training_seed
            writer.writerow([r.suite, ship, r.entrant, r.kind, training_seed, r.episode, r.seed, r.finished, *values])
