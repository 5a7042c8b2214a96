"""The whole leaderboard: entrants, suites, evaluation, tables and the files written.

::

    from ship_env.leaderboard import SUITE_SPECS
    from ship_env.leaderboard.board import run_leaderboard, write_leaderboard

    board = run_leaderboard(SUITE_SPECS["quick"])
    print(board.markdown())
    write_leaderboard(board, Path("leaderboard"))
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import gymnasium as gym
import numpy as np

from ship_env.envs.track_follow_task import TrackFollowTask
from ship_env.envs.tracks import TrackError
from ship_env.leaderboard.entrants import Entrant, classic_entrants, policy_entrants
from ship_env.leaderboard.evaluation import evaluate, jobs_for
from ship_env.leaderboard.plots import plot_aggregate, plot_course_changes, plot_scores, plot_tracks
from ship_env.leaderboard.rendering import (
    headline_markdown,
    markdown,
    verdict_count,
    verdicts_markdown,
    write_csv,
    write_episodes_csv,
)
from ship_env.leaderboard.sailing import EpisodeResult, sail_recorded
from ship_env.leaderboard.statistics import REFERENCES, Estimate, improvements
from ship_env.leaderboard.suites import COURSE_CHANGE, NOMINAL, TRACK_FOLLOW, Suite, SuiteSpec
from ship_env.leaderboard.tables import (
    Comparison,
    SuiteRanking,
    comparisons,
    grouped_estimates,
    learned_verdicts,
    rank,
    score_matrix,
)
from ship_env.text_table import Table

#: The scenario every CourseChange controller is drawn on: a 75-deg change in wind and current.
SAMPLE_COURSE_CHANGE = ("CourseChange wind_current", "+75 deg")
#: The files :func:`write_leaderboard` writes.
MARKDOWN_FILE = "leaderboard.md"
CSV_FILE = "leaderboard.csv"
EPISODES_FILE = "episodes.csv"
SCORES_PLOT = "scores.png"
HEADLINE_PLOT = "headline.png"
COURSE_CHANGE_PLOT = "course_change_sample.png"
TRACK_PLOT = "track_follow_sample.png"
#: The drawings among them, each written only where the run sails what it draws.
PLOTS = (SCORES_PLOT, HEADLINE_PLOT, COURSE_CHANGE_PLOT, TRACK_PLOT)


@dataclass(frozen=True)
class Leaderboard:
    """An evaluated leaderboard.

    Attributes:
        entrants: the controllers that sailed.
        suites: the suites sailed.
        results: every episode, job by job.
        tables: the ranked table of each suite.
        wall_time_s: the evaluation's wall-clock time, s.
        left_out: one line per task the ship cannot sail (its suites are not sailed) and per entrant whose
            controller failed on a suite (not ranked there), saying why.
    """

    entrants: tuple[Entrant, ...]
    suites: tuple[Suite, ...]
    results: tuple[EpisodeResult, ...]
    tables: tuple[SuiteRanking, ...]
    wall_time_s: float
    left_out: tuple[str, ...] = ()

    @property
    def ship_name(self) -> str:
        """The name of the ship sailed (every suite's; :attr:`Suite.ship_name`)."""
        return self.suites[0].ship_name

    def table(self, suite_name: str) -> SuiteRanking:
        """The table of the suite named ``suite_name`` (``"CourseChange calm | nominal"``)."""
        for table in self.tables:
            if table.suite.name == suite_name:
                return table
        raise KeyError(f"no suite {suite_name!r}; suites: {', '.join(t.suite.name for t in self.tables)}")

    def _nominal_course_changes(self) -> list[SuiteRanking]:
        """The nominal CourseChange suites' tables (none without episodes)."""
        tables = [t for t in self.tables if t.suite.env_id == COURSE_CHANGE and t.suite.condition == NOMINAL]
        return tables if tables and tables[0].suite.episodes else []

    def _headline_scores(self) -> dict[str, np.ndarray]:
        """Per CourseChange entrant, its normalised scores on every episode of the nominal CourseChange
        suites side by side, (training seeds x episodes); empty without those suites or the reference."""
        tables = self._nominal_course_changes()
        reference = REFERENCES[COURSE_CHANGE]
        names = [s.entrant for s in tables[0].standings] if tables else []
        if reference not in names:
            return {}
        matrices = {}
        for name in names:
            parts = []
            for table in tables:
                episodes = {
                    n: [r for r in self.results if r.suite == table.suite.name and r.entrant == n]
                    for n in (name, reference)
                }
                parts.append(score_matrix(table.suite, episodes[name]) / score_matrix(table.suite, episodes[reference]))
            matrices[name] = np.hstack(parts)
        return matrices

    def headline(self) -> dict[str, list[Estimate]]:
        """Per CourseChange entrant, the IQM and the mean of the normalised score over every episode
        of the nominal CourseChange suites, all seas together (rliable's aggregate over tasks), with
        95 % stratified-bootstrap intervals; empty without those suites."""
        matrices = self._headline_scores()
        return grouped_estimates({name: [matrix, matrix] for name, matrix in matrices.items()}, ["iqm", "mean"])

    def headline_verdicts(self) -> dict[str, Comparison]:
        """Per learned entrant, its verdict on the headline against the classic autopilot with the lowest
        headline IQM: the probability of improvement over every nominal CourseChange episode together,
        the rudder travel's mean over them, completing each episode a classic autopilot completes."""
        tables, matrices, headline = self._nominal_course_changes(), self._headline_scores(), self.headline()
        kinds = {s.entrant: s.kind for s in tables[0].standings} if matrices else {}
        classic = [name for name in matrices if kinds[name] == "classic"]
        learned = [name for name in matrices if kinds[name] == "learned"]
        if not classic or not learned:
            return {}
        best = min(classic, key=lambda name: (headline[name][0].value, name))
        chances = grouped_estimates({n: [improvements(matrices[n], matrices[best])] for n in learned}, ["mean"])

        def travel(name: str) -> float:  # every suite sails as many episodes: the mean of the suites' means
            return float(np.mean([t.standing(name).values["rudder_travel"] for t in tables]))

        return {
            name: Comparison(
                name,
                best,
                chances[name][0],
                headline[name][0].value / headline[best][0].value,
                travel(name) / travel(best),
                all(c.settles for c in learned_verdicts(tables, name).values()),
            )
            for name in learned
        }

    def summary(self) -> str:
        """What the terminal shows, within 100 columns: the headline's IQM with each learned entrant's
        verdict, and each learned entrant's verdicts counted per environment (every table is in
        :meth:`markdown`'s file)."""
        lines = []
        headline = self.headline()
        if headline:
            verdicts = self.headline_verdicts()
            rows = []
            for name, (iqm, _) in headline.items():
                c = verdicts.get(name)
                rows.append((name, iqm.text(3), *(("", "") if c is None else (c.improvement.text(2), c.verdict))))
            header = ("controller", "IQM [95 % CI]", "P(improvement) [95 % CI]", "verdict")
            lines += [
                f"CourseChange, nominal ship, all seas together ({self.ship_name}): normalised score",
                f"(1 = {REFERENCES[COURSE_CHANGE]}, lower is better)",
                "",
                Table(header, tuple(rows)).text(),
            ]
        made: dict[tuple[str, str], list[Comparison]] = {}
        for table in self.tables:
            for c in comparisons(table):
                made.setdefault((c.learned, table.suite.env_id), []).append(c)
        if made:
            lines += ["", "against the best classic autopilot on each suite:"]
            lines += [f"  {name} on {env_id}: {verdict_count(counted)}" for (name, env_id), counted in made.items()]
        return "\n".join(lines)

    def markdown(self) -> str:
        """The headline, the learned entrants' verdicts and every table in markdown."""
        sections = [
            "\n".join(f"Left out: {line}" for line in self.left_out),
            headline_markdown(self.headline(), self.headline_verdicts(), self.ship_name),
            verdicts_markdown(self.tables),
            *(markdown(t) for t in self.tables),
        ]
        return "\n\n".join(filter(None, sections))


def run_leaderboard(
    spec: SuiteSpec,
    policies: Sequence[Path] = (),
    shipped: bool = True,
    backend: str = "local",
    progress: bool = True,
    ray_address: str | None = None,
    trust_policy_code: bool = False,
) -> Leaderboard:
    """Sail ``spec``'s suites with the classic baselines, the shipped policies (if ``shipped``) and
    the policies at ``policies`` (each a file, a run's folder or a folder of seeds' runs), every
    learned entrant with each of its training seeds, on the ship ``spec`` sails (its ``ship``);
    ``PolicyFileError`` before anything sails if one does not fit or cannot be read without running
    its code. ``trust_policy_code`` reads the files at ``policies`` by unpickling them, which runs any
    code they carry. ``backend`` ``"ray"`` runs the jobs on Ray (at ``ray_address``).

    What the ship cannot sail (:meth:`~ship_env.leaderboard.suites.SuiteSpec.left_out`: on a ship sailed by its
    preset's fitted MMG model, the robustness conditions and the wind and waves) is left out with one line saying
    why, and so is a task whose environment cannot be made for the ship
    (``left_out``): TrackFollow where the ship turns too wide at the tracks' rudder for their legs
    (:class:`~ship_env.envs.tracks.TrackError`); that error where no task is left. So is an entrant
    whose controller fails on a suite (:func:`~ship_env.leaderboard.sailing.sail_suite`: its filter
    diverges, or it sails the ship out of the model's validity): its episodes there are not ranked;
    and a suite on which every entrant fails (the ship's model fails there, as a fitted preset's
    draws beyond its data can), in one line."""
    suites = spec.suites()
    env_kwargs = {suite.env_id: suite.env_kwargs for suite in suites}
    env_spaces = {}
    left_out = spec.left_out()
    for env_id, kwargs in env_kwargs.items():
        try:
            env = gym.make(env_id, **kwargs)
        except TrackError as error:
            left_out.append(f"{env_id.split('/')[-1]}: {error}")
            continue
        env_spaces[env_id] = (env.observation_space, env.action_space)
        env.close()
    suites = [suite for suite in suites if suite.env_id in env_spaces]
    if not suites:
        raise TrackError("; ".join(left_out))
    env_kwargs = {env_id: kwargs for env_id, kwargs in env_kwargs.items() if env_id in env_spaces}
    learned = policy_entrants(policies, env_spaces, shipped, trust_policy_code, suites[0].ship)
    entrants = classic_entrants(list(env_kwargs)) + learned
    start = time.perf_counter()
    results = evaluate(jobs_for(suites, entrants), backend, progress, ray_address)
    wall_time = time.perf_counter() - start
    failures = [r for r in results if r.failure]
    failed = {(r.entrant, r.suite) for r in failures}
    every = {s.name for s in suites if all((e.name, s.name) in failed for e in entrants)}  # the ship's fault
    left_out += [
        f"{r.suite}: every controller fails ({r.entrant}: {r.failure}, episode {r.episode}, seed {r.seed}); "
        "the suite is not ranked"
        for r in {r.suite: r for r in reversed(failures) if r.suite in every}.values()
    ]
    left_out += [
        f"{r.entrant} on {r.suite}: {r.failure} (episode {r.episode}, seed {r.seed}); not ranked on that suite"
        for r in failures
        if r.suite not in every
    ]
    suites = [suite for suite in suites if suite.name not in every]
    results = [result for result in results if (result.entrant, result.suite) not in failed]
    tables = tuple(rank(suite, results) for suite in suites)
    return Leaderboard(tuple(entrants), tuple(suites), tuple(results), tables, wall_time, tuple(left_out))


def _nominal_suite(board: Leaderboard, task: str) -> Suite | None:
    return next((s for s in board.suites if s.task == task and s.condition == NOMINAL and s.episodes), None)


def _ranked(board: Leaderboard, suite: Suite, env_id: str) -> list[Entrant]:
    """The entrants of ``env_id`` ranked on ``suite`` (not those whose controller failed there)."""
    ranked = {result.entrant for result in board.results if result.suite == suite.name}
    return [entrant for entrant in board.entrants if entrant.env_id == env_id and entrant.name in ranked]


def write_leaderboard(board: Leaderboard, out: Path, plots: bool = True) -> list[Path]:
    """Write the tables (markdown, CSV), the episodes (CSV) and, with ``plots``, the drawings
    into ``out``: the scores, and every controller on one course change and on one track. A drawing
    of an earlier run that this one does not draw is removed, so that the folder holds one run."""
    written = _write_leaderboard(board, Path(out), plots)
    for name in PLOTS:
        if Path(out, name) not in written:
            Path(out, name).unlink(missing_ok=True)
    return written


def _write_leaderboard(board: Leaderboard, out: Path, plots: bool) -> list[Path]:
    out.mkdir(parents=True, exist_ok=True)
    written = [out / MARKDOWN_FILE, out / CSV_FILE, out / EPISODES_FILE]
    written[0].write_text(board.markdown() + "\n")
    write_csv(board.tables, written[1])
    write_episodes_csv(board.results, written[2], board.ship_name)
    if not plots:
        return written
    written.append(plot_scores(board.tables, out / SCORES_PLOT))
    headline = board.headline()
    if headline:
        xlabel = f"normalised score (1 = {REFERENCES[COURSE_CHANGE]}), lower is better"
        title = f"CourseChange, nominal ship, all seas together ({board.ship_name})"
        written.append(plot_aggregate(headline, ["IQM", "Mean"], xlabel, title, out / HEADLINE_PLOT))
    task, label = SAMPLE_COURSE_CHANGE
    suite = _nominal_suite(board, task) or _nominal_suite(board, "CourseChange calm")
    if suite is not None:
        episode = next((e for e in suite.episodes if e.label == label), suite.episodes[0])
        runs = {e.name: sail_recorded(e, suite, episode)[0] for e in _ranked(board, suite, COURSE_CHANGE)}
        change = float(episode.options["course_change_deg"])
        title = f"{suite.name} on {suite.ship_name}: {episode.label} (seed {episode.seed})"
        written.append(plot_course_changes(runs, title, change, out / COURSE_CHANGE_PLOT))
    suite = _nominal_suite(board, "TrackFollow")
    if suite is not None:
        episode = suite.episodes[0]
        recorded = {e.name: sail_recorded(e, suite, episode) for e in _ranked(board, suite, TRACK_FOLLOW)}
        task_sailed = next(iter(recorded.values()))[1]
        assert isinstance(task_sailed, TrackFollowTask)  # the TrackFollow suite's
        runs = {name: states for name, (states, _) in recorded.items()}
        title = f"{suite.name} on {suite.ship_name}: {episode.label} (seed {episode.seed})"
        written.append(plot_tracks(runs, task_sailed, episode.options["track"], title, out / TRACK_PLOT))
    return written
