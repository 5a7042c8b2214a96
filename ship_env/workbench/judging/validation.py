"""Cross-validation: the error that matters is on runs the fit did not see.

The model is fitted to all runs; then each run in turn -- or each *group* of runs (a manoeuvre
type, a folder, the segments cut from one run) -- is left out, the model refitted to the others,
and the runs left out replayed from their measured initial states -- no per-run refitting. The
pooled errors of these replays are the *held-out* errors the workbench ranks models by; the spread
of the fold estimates gives jackknife standard errors.

A fold's fit starts from the all-run fit, which already is nearly its optimum: by default
(``FitOptions.fold_method = "linearised"``) it is one Gauss-Newton step from the all-run fit with
the left-out rows removed from its Jacobian, the classic one-step approximation of leave-one-out
(no replay needed); ``"refit"`` runs a full least-squares fit per fold instead. Where the one step
moves a term by more than ``FOLD_STEP_LIMIT`` of its scale (a term the other runs hardly determine:
the linearisation no longer holds) or past a term's bound (a bound the step would meet makes the
step of the bounded fit another one), that fold is refitted in full. The held-out replays of every
fold run in one compiled batch.

Runs of another kind (``validate_on``: fit on zig-zags, score on turning runs) are replayed by the
all-run fit: they are *validation runs*, never fitted. The cross-validation records the ranges the
fitted runs covered (:mod:`.coverage`), against which the validation runs' extrapolation is checked.
"""

from __future__ import annotations

import math
from collections.abc import Iterator, Mapping, Sequence
from concurrent.futures import FIRST_COMPLETED, Future, wait
from dataclasses import dataclass

import numpy as np

from ship_env.manoeuvres.uncertainty import jackknife_error
from ship_env.model import ShipModel
from ship_env.workbench.fitting.errors import ErrorScales, RunErrors, pooled, run_errors
from ship_env.workbench.fitting.fit import FitError, FitOptions, FitResult, Problem, fit_setup
from ship_env.workbench.fitting.parallel import pool
from ship_env.workbench.fitting.replay import ReplayModel, Simulated, simulate
from ship_env.workbench.fitting.terms import with_values
from ship_env.workbench.fitting.threads import one_thread
from ship_env.workbench.judging.coverage import Coverage, CoverageCheck, check_coverage, coverage_of
from ship_env.workbench.logs.logs import Log


@dataclass(frozen=True)
class Fold:
    """The fit with some runs left out.

    Attributes:
        left_out: the names of the runs left out.
        setup: the model fitted to the other runs.
        values: its fitted terms, SI units.
    """

    left_out: tuple[str, ...]
    setup: ReplayModel
    values: Mapping[str, float]


@dataclass(frozen=True)
class CrossValidation:
    """A fit on all runs and the errors on each run of a fit that did not see it.

    Attributes:
        fit: the fit on all runs.
        folds: per group of runs left out, the fit on the others.
        held_out: per run, its errors under the fold that left it out (from its measured state).
        replays: per run, that held-out replay (for errors over parts of a run, drawings).
        validation: per validation run (never fitted), its errors under the all-run fit.
        validation_replays: those replays.
        groups: per run, the group it was left out with.
        validation_logs: the validation runs.
        coverage: the ranges the fitted runs covered (None: not recorded).
        window: seconds at a run's start from which its replays' initial state was estimated (None: each run's
            :func:`~.replay.initial_window`).
    """

    fit: FitResult
    folds: tuple[Fold, ...]
    held_out: tuple[RunErrors, ...]
    replays: tuple[Simulated, ...] = ()
    validation: tuple[RunErrors, ...] = ()
    validation_replays: tuple[Simulated, ...] = ()
    groups: tuple[str, ...] = ()
    validation_logs: tuple[Log, ...] = ()
    coverage: Coverage | None = None
    window: float | None = None

    @property
    def pooled(self) -> RunErrors:
        """The held-out errors pooled over all runs."""
        return pooled(self.held_out, "held out")

    @property
    def pooled_validation(self) -> RunErrors | None:
        """The validation runs' errors pooled, or None without validation runs."""
        return pooled(self.validation, "validation") if self.validation else None

    def score(self, scales: ErrorScales) -> float:
        return self.pooled.score(scales)

    def validation_checks(self) -> list[CoverageCheck]:
        """Each validation run against the fitted runs' coverage (none without a coverage)."""
        if self.coverage is None:
            return []
        model = self.fit.setup.model
        return [check_coverage(log, self.coverage, model) for log in self.validation_logs]

    def score_jackknife(self, scales: ErrorScales, other: CrossValidation | None = None) -> float:
        """Jackknife standard error, over the groups of runs, of the held-out score (or its difference to ``other``'s).

        The pooled score is recomputed with each group left out in turn; the standard error is
        sqrt((n - 1) / n * sum_i (S_i - mean S)^2) over the n groups. With ``other`` (a model on
        the same runs) it is that of the difference of the two scores: the runs that are hard for
        one model are hard for the other, so the difference is known better than either score.
        """
        labels = self.groups or tuple(e.name for e in self.held_out)
        names = sorted(set(labels))
        if len(names) < 2:
            return math.nan

        def without(errors: Sequence[RunErrors], name: str) -> float:
            return pooled([e for e, label in zip(errors, labels, strict=True) if label != name]).score(scales)

        values = np.array(
            [
                without(self.held_out, name) - (without(other.held_out, name) if other is not None else 0.0)
                for name in names
            ]
        )
        return jackknife_error(values)

    def jackknife_errors(self) -> dict[str, float]:
        """Standard errors of the fitted terms from the spread of the leave-one-group-out fits.

        The jackknife estimate sqrt((n - 1) / n * sum_i (theta_i - mean theta)^2) over the n folds:
        unlike the Jacobian's, it holds what differs from run to run (correlated residuals, noisy
        inputs, effects the model lacks).
        """
        keys = [estimate.term.key for estimate in self.fit.estimates]
        spread = np.sqrt(np.diag(self.jackknife_covariance(keys)))
        return {key: float(value) for key, value in zip(keys, spread, strict=True)}

    def jackknife_covariance(self, keys: Sequence[str]) -> np.ndarray:
        """The jackknife covariance of the named terms over the n folds, SI units:
        (n - 1) / n * sum_i (theta_i - mean theta) (theta_i - mean theta)^T (its diagonal: :meth:`jackknife_errors`)."""
        values = np.array([[fold.values[key] for key in keys] for fold in self.folds])
        count = len(self.folds)
        deviations = values - values.mean(axis=0)
        return (count - 1) / count * deviations.T @ deviations


def fold_groups(logs: Sequence[Log], groups: Sequence[str] | None) -> list[list[int]]:
    """The runs of each fold: one per run, or one per distinct group label (in order of first appearance)."""
    if groups is None:
        return [[i] for i in range(len(logs))]
    if len(groups) != len(logs):
        raise FitError(f"cross-validation: {len(groups)} group labels for {len(logs)} runs")
    order = list(dict.fromkeys(groups))
    return [[i for i, label in enumerate(groups) if label == name] for name in order]


#: Largest step of a linearised fold, in units of the terms' scales, beyond which the fold is refitted.
FOLD_STEP_LIMIT = 0.5


def _linearised_fold(problem: Problem, fitted: FitResult, left_out: Sequence[int]) -> np.ndarray | None:
    """One Gauss-Newton step from the all-run fit with the left-out runs' rows removed (in scale units).

    None where the step moves a term by more than ``FOLD_STEP_LIMIT`` scales, or past its bounds (the
    unconstrained step, clipped, is not the bounded fit's step): refit that fold instead.
    """
    lengths = [problem.residual_length(run) for run in range(len(problem.logs))]
    edges = np.concatenate([[0], np.cumsum(lengths)])
    keep = np.ones(len(fitted.residual), dtype=bool)
    for run in left_out:
        keep[edges[run] : edges[run + 1]] = False
    jacobian, residual = fitted.jacobian[keep], fitted.residual[keep]
    step = np.linalg.lstsq(jacobian, -residual, rcond=None)[0] if jacobian.shape[1] else np.zeros(0)
    if np.any(np.abs(step[: len(problem.terms)]) > FOLD_STEP_LIMIT):
        return None
    lower, upper = problem.bounds()
    point = fitted.solution + step
    if np.any(point < lower) or np.any(point > upper):
        return None
    return point


@dataclass(frozen=True)
class ValidationJob:
    """A cross-validation to run (the arguments of :func:`cross_validate`, the terms named).

    ``scored_on`` holds the same runs with more samples (a fit on every n-th sample, scored on every
    sample, :func:`~.diagnose.screening_runs`): the held-out replays are measured there. Empty: on ``logs``.
    """

    setup: ReplayModel
    logs: Sequence[Log]
    keys: Sequence[str]
    options: FitOptions
    starts: Sequence[Mapping[str, float]] = ()
    groups: Sequence[str] | None = None
    validate_on: Sequence[Log] = ()
    scored_on: Sequence[Log] = ()


#: A fit to run: the model (its values are the start), the runs, the terms, the options.
FitTask = tuple[ReplayModel, Sequence[Log], Sequence[str], FitOptions]


def _fitted(setup: ReplayModel, logs: Sequence[Log], keys: Sequence[str], options: FitOptions) -> FitResult | Exception:
    """The fit from the setup's values, or the error that stopped it (returned, to be raised for its job alone)."""
    try:
        return Problem(setup, logs, keys, options).solve()
    except (ValueError, FloatingPointError) as error:
        return error


def _fitted_values(
    setup: ReplayModel, logs: Sequence[Log], keys: Sequence[str], options: FitOptions
) -> dict[str, float] | Exception:
    """The fitted terms (SI units), or the error that stopped the fit."""
    try:
        problem = Problem(setup, logs, keys, options)
        return problem.values_at(problem.optimum()[0])
    except (ValueError, FloatingPointError) as error:
        return error


@one_thread
def cross_validate(
    model: ShipModel | ReplayModel,
    logs: Sequence[Log],
    terms: Sequence[str] | None = None,
    options: FitOptions | None = None,
    starts: Sequence[Mapping[str, float]] = (),
    groups: Sequence[str] | None = None,
    validate_on: Sequence[Log] = (),
) -> CrossValidation:
    """Fit on all runs, then leave each run (or group of runs) out in turn and replay what was left out.

    Output-error fits have local minima, so the all-run fit may start from several points: the
    model's own values and each of ``starts`` (values for some terms); the fit with the lowest
    cost is kept, and every fold starts from it.

    A run wholly outside the model's envelope is left out, with a :class:`~.logs.LogWarning`
    (:func:`~.runs.screen_runs`); the error scales default to the scale-free ones for the runs kept.

    Args:
        groups: per run, a label; the runs with one label are left out together (default: each run alone).
        validate_on: runs replayed by the all-run fit and never fitted (another manoeuvre type).
    """
    prepared = fit_setup(model, logs, terms, options, groups, validate_on)
    job = ValidationJob(
        prepared.setup,
        prepared.logs,
        prepared.keys,
        prepared.options,
        starts,
        prepared.groups,
        prepared.validate_on,
    )
    outcome = cross_validate_each([job], prepared.options.workers)[0]
    if isinstance(outcome, Exception):
        raise outcome
    return outcome


def cross_validate_each(jobs: Sequence[ValidationJob], workers: int = 1) -> list[CrossValidation | Exception]:
    """Each job's :func:`cross_validate`, or the error that stopped it; the fits on ``workers`` processes.

    Every job's all-run fits (every start) are handed to the workers at once, the jobs' last starts
    first (a refit's fresh start from the preset takes longest); as soon as a job's starts are
    done, the folds it must refit in full follow. The linearised folds and the held-out replays
    are computed here.
    """
    plans: list[_Plan | Exception] = []
    for job in jobs:
        try:
            plans.append(_Plan(job))
        except (ValueError, FloatingPointError) as error:
            plans.append(error)
    planned = [plan for plan in plans if isinstance(plan, _Plan)]
    # One fit alone (a single start of a single job) runs here, with its folds: a pool would cost more.
    workers_ = pool(workers, sum(len(plan.starts) for plan in planned))
    starts: list[list[Future[FitResult | Exception]]] = [[] for _ in planned]
    for k in reversed(range(max((len(plan.starts) for plan in planned), default=0))):
        for plan, futures in zip(planned, starts, strict=True):
            if k < len(plan.starts):
                futures.insert(0, workers_.submit(_fitted, *plan.start_tasks()[k]))
    folds: dict[int, list[Future[dict[str, float] | Exception]]] = {}
    while len(folds) < len(planned):
        for index, (plan, futures) in enumerate(zip(planned, starts, strict=True)):
            if index not in folds and all(future.done() for future in futures):
                plan.choose([future.result() for future in futures])
                folds[index] = [workers_.submit(_fitted_values, *task) for task in plan.fold_tasks()]
        running = [
            future
            for index, futures in enumerate(starts)
            if index not in folds
            for future in futures
            if not future.done()
        ]
        if running:
            wait(running, return_when=FIRST_COMPLETED)
    finished = iter(plan.finish([future.result() for future in folds[index]]) for index, plan in enumerate(planned))
    return [plan if isinstance(plan, Exception) else next(finished) for plan in plans]


class _Plan:
    """One cross-validation in its stages: the all-run fits from each start, the folds, the held-out replays.

    A stage's fits are handed out as tasks (:data:`FitTask`) and their results handed back, so that
    the fits of many cross-validations run side by side (:func:`cross_validate_each`).
    """

    def __init__(self, job: ValidationJob) -> None:
        self.job = job
        self.folds_runs = fold_groups(job.logs, job.groups)
        if len(self.folds_runs) < 2:
            raise FitError("cross-validation: leaving one run out needs at least two runs (or two groups)")
        self.starts = [with_values(job.setup, start) for start in ({}, *job.starts)]
        self.error: Exception | None = None
        self.points: list[np.ndarray | None] = []
        self._fold_tasks: list[FitTask] = []

    def start_tasks(self) -> list[FitTask]:
        return [(start, self.job.logs, self.job.keys, self.job.options) for start in self.starts]

    def choose(self, fits: Sequence[FitResult | Exception]) -> None:
        """Keep the all-run fit with the lowest cost; find each fold's fit by one step, or ask for a refit."""
        try:
            self._choose(fits)
        except (ValueError, FloatingPointError) as error:
            self.error = error
            self._fold_tasks = []

    def _choose(self, fits: Sequence[FitResult | Exception]) -> None:
        done = [fitted for fitted in fits if not isinstance(fitted, Exception)]
        if len(done) < len(fits):
            raise next(fitted for fitted in fits if isinstance(fitted, Exception))
        best = min(range(len(done)), key=lambda i: float(done[i].residual @ done[i].residual))
        job = self.job
        self.problem = Problem(self.starts[best], job.logs, job.keys, job.options)
        self.everything = done[best]
        for left_out in self.folds_runs:
            linearised = job.options.fold_method == "linearised"
            point = _linearised_fold(self.problem, self.everything, left_out) if linearised else None
            self.points.append(None if point is None else self.problem.padded(point[: len(job.keys)]))
            if point is None:
                others = [log for i, log in enumerate(job.logs) if i not in left_out]
                self._fold_tasks.append((self.everything.setup, others, job.keys, job.options))

    def fold_tasks(self) -> list[FitTask]:
        return self._fold_tasks

    def finish(self, refits: Sequence[dict[str, float] | Exception]) -> CrossValidation | Exception:
        """The cross-validation from the folds refitted in full (in the order of :meth:`fold_tasks`)."""
        values = [fold for fold in refits if not isinstance(fold, Exception)]
        if self.error is not None:
            return self.error
        if len(values) < len(refits):
            return next(fold for fold in refits if isinstance(fold, Exception))
        try:
            return self._assemble(iter(values))
        except (ValueError, FloatingPointError) as error:
            return error

    def _assemble(self, refits: Iterator[dict[str, float]]) -> CrossValidation:
        job, problem = self.job, self.problem
        points = [problem.point_of(next(refits)) if point is None else point for point in self.points]
        # Every fold's runs left out, replayed from their measured states, in one batch; each point holds the
        # terms only (the runs start as measured), so it replays the runs as scored as well as those fitted.
        logs = job.scored_on or job.logs
        scoring = Problem(problem.setup, logs, job.keys, job.options) if job.scored_on else problem
        owner = {run: f for f, left_out in enumerate(self.folds_runs) for run in left_out}
        replays = scoring.replay_each(points, [owner[run] for run in range(len(logs))])
        folds = tuple(
            Fold(
                left_out=tuple(logs[run].name for run in left_out),
                setup=problem.setup_at(point),
                values=problem.values_at(point),
            )
            for left_out, point in zip(self.folds_runs, points, strict=True)
        )
        validation_replays: list[Simulated] = []
        if job.validate_on:
            validation_replays = simulate(self.everything.setup, job.validate_on, job.options.initial_window)
        labels = job.groups if job.groups is not None else [log.name for log in logs]
        return CrossValidation(
            fit=self.everything,
            folds=folds,
            held_out=tuple(run_errors(log, sim) for log, sim in zip(logs, replays, strict=True)),
            replays=tuple(replays),
            validation=tuple(
                run_errors(log, sim) for log, sim in zip(job.validate_on, validation_replays, strict=True)
            ),
            validation_replays=tuple(validation_replays),
            groups=tuple(labels),
            validation_logs=tuple(job.validate_on),
            coverage=coverage_of(logs, self.everything.setup.model),
            window=job.options.initial_window,
        )


__all__ = ["CrossValidation", "Fold", "ValidationJob", "cross_validate", "cross_validate_each", "fold_groups"]
