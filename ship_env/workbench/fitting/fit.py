"""Output-error fitting of a model's parameters to measured runs, with leave-one-run-out validation.

The measured rudder, propeller rate and wind drive the model (:mod:`.replay`, ``INPUTS``); the fit
chooses the terms (:mod:`.terms`) that minimise the weighted squared differences between measured
and simulated

- heading, rate of turn and speed (free simulation from the run's initial state: the speed is the
  model's, a measured speed sets only the run's service speed and initial speed), and
- track (north, east) replayed with the measured heading (and speed),

each divided by its error scale (:class:`~ship_env.workbench.fitting.errors.ErrorScales`), with
``scipy.optimize.least_squares`` (trust-region reflective, within the terms' ranges). The Jacobian
is taken by forward differences, every perturbed parameter set and run replayed in one compiled
batch. Optional per-run nuisance terms (an offset of the initial heading and of the initial rate of
turn) absorb a poor start of a run in the fit; runs the fit did not see always start from their
measured state.

Uncertainty: cov = s^2 (J^T J)^-1 with s^2 = |residual|^2 / (m - n), the Gauss-Newton estimate at
the optimum; a term the data do not determine (in the Jacobian's null space) gets an infinite
standard error (:func:`~.uncertainty.unknown_variances`). Output-error residuals are correlated in time, so these
standard errors are optimistic; the spread of the leave-one-run-out estimates (:mod:`.validation`) is the honest check.
"""

from __future__ import annotations

import contextlib
import math
import warnings
from collections import Counter
from collections.abc import Iterator, Mapping, Sequence
from dataclasses import dataclass, field, replace

import numpy as np
from scipy.optimize import least_squares

from ship_env.model import ShipModel
from ship_env.model import state as S
from ship_env.workbench.defaults import NUISANCE
from ship_env.workbench.fitting.errors import ErrorScales, RunErrors, pooled, run_errors
from ship_env.workbench.fitting.replay import (
    EAST,
    HEADING,
    NORTH,
    RATE,
    SPEED,
    ReplayModel,
    Simulated,
    Tasks,
    free_and_track_tasks,
    moved_replays,
    pack_runs,
    replay,
    unpack,
)
from ship_env.workbench.fitting.runs import screen_runs
from ship_env.workbench.fitting.terms import (
    Term,
    acts_on,
    default_terms,
    make_term,
    value_of,
    with_speed_output,
    with_values,
    write_record,
)
from ship_env.workbench.fitting.threads import one_thread
from ship_env.workbench.fitting.uncertainty import unknown_covariance, unknown_variances
from ship_env.workbench.logs.logs import Log

#: How cross-validation fits a fold (see :mod:`.validation`).
FOLD_METHODS = ("linearised", "refit")
#: Forward-difference step, in units of each term's scale.
DIFFERENCE_STEP = 1e-4


#: A replay of a batch: (point, run, track replay?).
Request = tuple[int, int, bool]


class FitError(ValueError):
    """A fit that cannot be set up (unknown term, an effect not in the model, too few runs)."""


@dataclass(frozen=True)
class FitOptions:
    """How to fit.

    Attributes:
        scales: the error per channel that weighs one unit in the cost; None (the default): scale-free,
            ``ErrorScales.for_runs`` for the model's ship and the runs, set by each entry point
            (:meth:`for_runs`) and the same for all the fits it makes.
        nuisance: per-run nuisance terms to fit, from ``NUISANCE`` (``heading``, ``rate_of_turn``).
        initial_window: seconds at a run's start from which its initial state is estimated; None (the default):
            each run's :func:`~.replay.initial_window` (half a ship length's time at its service speed, at least 2 s).
        max_evaluations: most cost evaluations per fit (each is a batch of replays).
        tolerance: relative change of cost and terms at which the fit stops.
        fold_method: how cross-validation fits a fold from the all-run fit: ``"linearised"``
            (one Gauss-Newton step with the left-out rows removed) or ``"refit"`` (a full fit).
        workers: processes that run independent fits (starts, folds, candidates) side by side
            (:mod:`.parallel`); 1 runs them one after another, with the same results. A script that
            sets more needs the ``if __name__ == "__main__":`` guard (the workers are spawned).
    """

    scales: ErrorScales | None = None
    nuisance: tuple[str, ...] = ()
    initial_window: float | None = None
    max_evaluations: int = 100
    tolerance: float = 1e-6
    fold_method: str = "linearised"
    workers: int = 1

    def __post_init__(self) -> None:
        if self.workers < 1:
            raise FitError(f"fit: workers must be at least 1, got {self.workers}")
        if self.fold_method not in FOLD_METHODS:
            raise FitError(f"fit: unknown fold_method {self.fold_method!r}; known: {', '.join(FOLD_METHODS)}")
        unknown = [name for name in self.nuisance if name not in NUISANCE]
        if unknown:
            raise FitError(f"fit: unknown nuisance terms {unknown}; known: {', '.join(NUISANCE)}")

    def for_runs(self, model: ShipModel, logs: Sequence[Log]) -> FitOptions:
        """These options with their error scales chosen: those given, or the scale-free ones for the runs."""
        return self if self.scales is not None else replace(self, scales=ErrorScales.for_runs(model, logs))

    @property
    def error_scales(self) -> ErrorScales:
        """The error scales (set by :meth:`for_runs`)."""
        if self.scales is None:
            raise FitError("fit: the error scales are not chosen yet; call FitOptions.for_runs(model, logs)")
        return self.scales


@dataclass(frozen=True)
class Estimate:
    """A fitted term: value and standard error in SI units, and whether it ended on its range's edge."""

    term: Term
    value: float
    std_error: float
    at_bound: bool


@dataclass(frozen=True)
class FitResult:
    """A fitted model and how well it fits the runs it saw.

    Attributes:
        setup: the fitted model (with the fitted current).
        estimates: the fitted terms.
        nuisance: per run, the fitted nuisance terms (offsets of the initial state, SI units).
        errors: per-run RMS errors with the fitted model (in-sample).
        solution: the fitted values in units of their scales, then the nuisance terms run by run.
        residual: the weighted residual vector at the optimum (for diagnosis).
        jacobian: its derivative by ``solution``.
        evaluations: cost evaluations used.
        message: the optimiser's verdict.
        warnings: the numerical warnings the fit met (overflow, invalid values): each message and how
            often it came; they are not shown while fitting (see :meth:`Problem.counting_warnings`).
    """

    setup: ReplayModel
    estimates: tuple[Estimate, ...]
    nuisance: Mapping[str, Mapping[str, float]]
    errors: tuple[RunErrors, ...]
    solution: np.ndarray
    residual: np.ndarray
    jacobian: np.ndarray
    evaluations: int
    message: str
    warnings: tuple[tuple[str, int], ...] = ()

    @property
    def pooled(self) -> RunErrors:
        return pooled(self.errors)

    def covariance(self, keys: Sequence[str]) -> np.ndarray:
        """The Jacobian's covariance of the named terms, SI units: s^2 (J^T J)^-1 scaled by the terms' scales
        (their standard errors are the square roots of its diagonal, :func:`~.uncertainty.unknown_covariance`)."""
        degrees_of_freedom = max(len(self.residual) - len(self.solution), 1)
        variance = float(self.residual @ self.residual) / degrees_of_freedom
        index = {estimate.term.key: j for j, estimate in enumerate(self.estimates)}
        rows = [index[key] for key in keys]
        scales = np.array([self.estimates[j].term.scale for j in rows])
        covariance = unknown_covariance(self.jacobian)[np.ix_(rows, rows)]
        return variance * covariance * np.outer(scales, scales)

    def warnings_line(self) -> str:
        """The numerical warnings in one line ('' if none): how many, and which."""
        if not self.warnings:
            return ""
        total = sum(count for _, count in self.warnings)
        which = "; ".join(f"{count} x {message}" for message, count in self.warnings)
        return f"{total} numerical warnings while fitting ({which})"

    def values(self) -> dict[str, float]:
        return {estimate.term.key: estimate.value for estimate in self.estimates}


class Problem:
    """The output-error problem for one model, a set of terms and a set of runs.

    The unknowns ``x`` are the terms divided by their scales, then the nuisance terms run by run.
    """

    def __init__(self, setup: ReplayModel, logs: Sequence[Log], keys: Sequence[str], options: FitOptions) -> None:
        if not logs:
            raise FitError("fit: no logs")
        for key in keys:
            effect = key.partition(".")[0]
            if "." in key and effect not in setup.model.effects:
                raise FitError(f"fit: term {key!r} belongs to the effect {effect!r}, which is not in the model; add it")
        if len(set(keys)) != len(keys):
            raise FitError(f"fit: terms repeat in {list(keys)}")
        self.setup = setup
        self.logs = list(logs)
        self.options = options.for_runs(setup.model, self.logs)
        self.terms = [make_term(key, setup) for key in keys]
        self.runs = pack_runs(self.logs, setup.model, options.initial_window)
        self._has_position = [log.has_position for log in self.logs]
        self._nuisance = [NUISANCE[name] for name in options.nuisance]
        self._cache: tuple[np.ndarray, np.ndarray] | None = None
        self._edges = np.concatenate([[0], np.cumsum([self.residual_length(run) for run in range(len(self.logs))])])
        # Per term, whether it can move the free and the track replay: from the equations, and nothing where
        # its effect cannot act on these logs. It holds at every point (numbers would not: a term may move
        # a replay only once another term has grown from zero).
        self._can_move = [
            moved_replays(setup.model, key, all(log.speed is not None for log in self.logs))
            if acts_on(key.partition(".")[0], self.logs)
            else (False, False)
            for key in keys
        ]
        self.evaluations = 0
        self.warnings: Counter[str] = Counter()

    @contextlib.contextmanager
    def counting_warnings(self) -> Iterator[None]:
        """Count the numerical warnings (``RuntimeWarning``: overflow, invalid values) raised inside, by message,
        instead of showing them: a diverging fit raises dozens, which the fit's summary line replaces. Other
        warnings are shown as usual."""
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", RuntimeWarning)
            yield
        for record in caught:
            if issubclass(record.category, RuntimeWarning):
                self.warnings[str(record.message)] += 1
            else:
                warnings.warn_explicit(record.message, record.category, record.filename, record.lineno)

    # -- the unknowns ----------------------------------------------------------------------------
    @property
    def size(self) -> int:
        return len(self.terms) + len(self._nuisance) * len(self.logs)

    def start(self) -> np.ndarray:
        """The model's current values (in scale units), nuisance zero."""
        x = np.zeros(self.size)
        for j, term in enumerate(self.terms):
            x[j] = np.clip(value_of(self.setup, term.key), term.lower, term.upper) / term.scale
        return x

    def bounds(self) -> tuple[np.ndarray, np.ndarray]:
        lower = [term.lower / term.scale for term in self.terms]
        upper = [term.upper / term.scale for term in self.terms]
        for _ in self.logs:
            for _, scale, bound in self._nuisance:
                lower.append(-bound / scale)
                upper.append(bound / scale)
        return np.array(lower), np.array(upper)

    def _term_values(self, x: np.ndarray) -> np.ndarray:
        return x[: len(self.terms)] * np.array([term.scale for term in self.terms])

    def _initial_offset(self, x: np.ndarray, run: int) -> np.ndarray:
        offset = np.zeros(S.MOTION_SIZE)
        first = len(self.terms) + run * len(self._nuisance)
        for k, (index, scale, _) in enumerate(self._nuisance):
            offset[index] = x[first + k] * scale
        return offset

    def _current(self, x: np.ndarray) -> tuple[float, float]:
        values = dict(zip((term.key for term in self.terms), self._term_values(x), strict=True))
        north = values.get("current.north", self.setup.current_north)
        east = values.get("current.east", self.setup.current_east)
        return (north, east) if self.setup.model.has("current") else (0.0, 0.0)

    # -- replays ---------------------------------------------------------------------------------
    def _outputs(
        self, points: Sequence[np.ndarray], requests: Sequence[tuple[int, int, bool]]
    ) -> tuple[np.ndarray, np.ndarray]:
        """Replay ``requests`` (point, run, track?) in one batch."""
        records = np.repeat(self.setup.model.record, len(points))
        currents = [self._current(x) for x in points]
        for p, x in enumerate(points):
            write_record(records[p : p + 1], self.terms, self._term_values(x))
        offsets = np.stack(
            [np.zeros(S.MOTION_SIZE) if track else self._initial_offset(points[p], run) for p, run, track in requests]
        )
        tasks = Tasks.build(
            record=[p for p, _, _ in requests],
            run=[run for _, run, _ in requests],
            track=[track for _, _, track in requests],
            initial_offset=offsets,
            current=np.array([currents[p] for p, _, _ in requests]),
        )
        self.evaluations += 1
        return replay(self.runs, records, tasks)

    def _free_part(self, run: int, free: np.ndarray) -> np.ndarray:
        """The weighted heading, rate-of-turn and speed residual of a free replay (or of a stack of them)."""
        log = self.logs[run]
        scales = self.options.error_scales
        parts = [(free[..., : log.samples, HEADING] - log.heading) / scales.heading]
        if log.rate_of_turn is not None:
            parts.append((free[..., : log.samples, RATE] - log.rate_of_turn) / scales.rate_of_turn)
        if log.speed is not None:
            parts.append((free[..., : log.samples, SPEED] - np.maximum(log.speed, 0.0)) / scales.speed_error)
        return np.concatenate(parts, axis=-1)

    def _track_part(self, run: int, track: np.ndarray) -> np.ndarray:
        """The weighted north and east residual of a track replay (or of a stack of them)."""
        log = self.logs[run]
        position = self.options.error_scales.position
        north = (track[..., : log.samples, NORTH] - log.north) / position
        return np.concatenate([north, (track[..., : log.samples, EAST] - log.east) / position], axis=-1)

    def _requests(self, point: int, runs: Sequence[int], free: bool = True, track: bool = True) -> list[Request]:
        requests = [(point, run, False) for run in runs] if free else []
        if track:
            requests += [(point, run, True) for run in runs if self._has_position[run]]
        return requests

    def residual(self, x: np.ndarray) -> np.ndarray:
        """The weighted residual vector of all runs at ``x``."""
        if self._cache is not None and np.array_equal(self._cache[0], x):
            return self._cache[1]
        requests = self._requests(0, range(len(self.logs)))
        outputs, _ = self._outputs([x], requests)
        vector = np.empty(self._edges[-1])
        for i, (_, run, track) in enumerate(requests):
            vector[self._rows(run, track)] = (
                self._track_part(run, outputs[i]) if track else self._free_part(run, outputs[i])
            )
        self._cache = (x.copy(), vector)
        return vector

    def _rows(self, run: int, track: bool) -> slice:
        """The rows of a run's free (heading, rate, speed) or track (north, east) residual."""
        first, stop = self._edges[run], self._edges[run + 1]
        split = stop - 2 * self.logs[run].samples if self._has_position[run] else stop
        return slice(split, stop) if track else slice(first, split)

    def jacobian(self, x: np.ndarray) -> np.ndarray:
        """Forward differences, all perturbations in one batch; a nuisance term moves only its run's free replay.

        A term that leaves the free replay (heading, rate of turn) or the track replay alone -- a
        current moves only the track, a yaw gain only the heading, the track being replayed on the
        measured heading -- leaves its part of the Jacobian exactly zero: those replays are not run
        where the model's equations show it (:func:`~.replay.moved_replays`) or the logs (an effect
        that acts only with the propeller astern, :func:`~.terms.acts_on`). Every other replay is run
        at every point: a term that moves nothing at one point (a time constant whose gain is at zero,
        a current while the wind moment that couples it to the heading is zero) may move it at the next.
        """
        base = self.residual(x)
        _, upper = self.bounds()
        steps = np.where(x + DIFFERENCE_STEP <= upper, DIFFERENCE_STEP, -DIFFERENCE_STEP)
        points = []
        requests: list[Request] = []
        all_runs = range(len(self.logs))
        per_run = len(self._nuisance)
        for j in range(self.size):
            shifted = x.copy()
            shifted[j] += steps[j]
            points.append(shifted)
            if j < len(self.terms):
                requests += self._requests(j, all_runs, *self._can_move[j])
            else:
                requests += self._requests(j, [(j - len(self.terms)) // per_run], track=False)
        outputs, _ = self._outputs(points, requests)
        matrix = np.zeros((len(base), self.size))
        replays_of: dict[tuple[int, bool], list[int]] = {}  # (run, track?) -> its requests
        for i, (_, run, track) in enumerate(requests):
            replays_of.setdefault((run, track), []).append(i)
        for (run, track), indices in replays_of.items():
            rows = self._rows(run, track)
            columns = [requests[i][0] for i in indices]
            replays = outputs[indices, : self.logs[run].samples]
            parts = self._track_part(run, replays) if track else self._free_part(run, replays)
            differences = (parts - base[rows]) / steps[columns, np.newaxis]
            matrix[rows, columns] = differences.T
        return matrix

    def residual_length(self, run: int) -> int:
        log = self.logs[run]
        return (1 + (log.rate_of_turn is not None) + (log.speed is not None) + 2 * log.has_position) * log.samples

    def padded(self, term_values: np.ndarray) -> np.ndarray:
        """A point with these terms (scale units) and every nuisance term zero (runs start as measured)."""
        x = np.zeros(self.size)
        x[: len(self.terms)] = term_values
        return x

    def point_of(self, values: Mapping[str, float]) -> np.ndarray:
        """The point (scale units, nuisance zero) with the terms at ``values``, SI units."""
        return self.padded(np.array([values[term.key] / term.scale for term in self.terms]))

    def values_at(self, x: np.ndarray) -> dict[str, float]:
        """The terms at ``x``, SI units."""
        return {term.key: float(value) for term, value in zip(self.terms, self._term_values(x), strict=True)}

    def setup_at(self, x: np.ndarray) -> ReplayModel:
        """The replay model with the terms at ``x``."""
        return with_values(self.setup, self.values_at(x))

    def replay_each(self, points: Sequence[np.ndarray], point_of_run: Sequence[int]) -> list[Simulated]:
        """Each run replayed (free and track) at its own point ``points[point_of_run[run]]``, in one batch."""
        runs = range(len(self.logs))
        requests = [(point_of_run[run], run, False) for run in runs] + [(point_of_run[run], run, True) for run in runs]
        outputs, valid_samples = self._outputs(points, requests)
        return unpack(self.logs, outputs, valid_samples)

    def simulated(self, x: np.ndarray) -> list[Simulated]:
        """Each run replayed at ``x`` (with its nuisance terms)."""
        tasks = free_and_track_tasks(len(self.logs))
        requests = list(zip(tasks.record, tasks.run, tasks.track, strict=True))
        outputs, valid_samples = self._outputs([x], requests)
        return unpack(self.logs, outputs, valid_samples)

    # -- the fit ---------------------------------------------------------------------------------
    def solve(self, x0: np.ndarray | None = None) -> FitResult:
        """Least squares from ``x0`` (default: the model's values); the fitted model and its errors."""
        with self.counting_warnings():
            return self._result(*self.optimum(x0))

    def optimum(self, x0: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray, str]:
        """Least squares from ``x0`` (default: the model's values): the solution, its residual and Jacobian, the
        optimiser's verdict."""
        lower, upper = self.bounds()
        if x0 is not None and len(x0) < self.size:
            x0 = self.padded(x0[: len(self.terms)])
        start = np.clip(self.start() if x0 is None else x0, lower, upper)
        if self.size == 0:
            return start, self.residual(start), np.zeros((len(self.residual(start)), 0)), "nothing to fit"
        with self.counting_warnings():
            solution = least_squares(
                self.residual,
                start,
                jac=self.jacobian,
                bounds=(lower, upper),
                method="trf",
                x_scale=1.0,
                ftol=self.options.tolerance,
                xtol=self.options.tolerance,
                gtol=self.options.tolerance,
                max_nfev=self.options.max_evaluations,
            )
        return solution.x, solution.fun, solution.jac, str(solution.message)

    def _result(self, x: np.ndarray, residual: np.ndarray, jacobian: np.ndarray, message: str) -> FitResult:
        lower, upper = self.bounds()
        degrees_of_freedom = max(len(residual) - self.size, 1)
        variance = float(residual @ residual) / degrees_of_freedom
        variances = variance * unknown_variances(jacobian)
        values = self._term_values(x)
        estimates = tuple(
            Estimate(
                term=term,
                value=float(value),
                std_error=float(math.sqrt(variances[j]) * term.scale),
                at_bound=bool(np.isclose(x[j], lower[j]) or np.isclose(x[j], upper[j])),
            )
            for j, (term, value) in enumerate(zip(self.terms, values, strict=True))
        )
        nuisance = {
            log.name: {
                name: float(x[len(self.terms) + run * len(self._nuisance) + k] * NUISANCE[name][1])
                for k, name in enumerate(self.options.nuisance)
            }
            for run, log in enumerate(self.logs)
        }
        simulated = self.simulated(x)
        return FitResult(
            setup=with_values(self.setup, {e.term.key: e.value for e in estimates}),
            estimates=estimates,
            nuisance=nuisance,
            errors=tuple(run_errors(log, sim) for log, sim in zip(self.logs, simulated, strict=True)),
            solution=x,
            residual=residual,
            jacobian=jacobian,
            evaluations=self.evaluations,
            message=str(message),
            warnings=tuple(self.warnings.items()),
        )


def as_setup(model: ShipModel | ReplayModel) -> ReplayModel:
    return model if isinstance(model, ReplayModel) else ReplayModel(model)


@dataclass(frozen=True)
class FitSetup:
    """What a fit sails, fits and weighs (:func:`fit_setup`): the model, the runs kept and their groups, the
    validation runs kept, the terms and the options."""

    setup: ReplayModel
    logs: list[Log]
    keys: list[str]
    options: FitOptions
    groups: list[str] | None = None
    validate_on: list[Log] = field(default_factory=list)


def fit_setup(
    model: ShipModel | ReplayModel,
    logs: Sequence[Log],
    terms: Sequence[str] | None,
    options: FitOptions | None,
    groups: Sequence[str] | None = None,
    validate_on: Sequence[Log] = (),
) -> FitSetup:
    """What a fit to ``logs`` sails, fits and weighs: the runs (and their ``groups``, and the ``validate_on``
    runs) less those wholly outside the model's envelope, each left out with a :class:`~.logs.LogWarning`
    (:func:`~.runs.screen_runs`); the model (the speed loss on where a log measures the speed,
    :func:`~.terms.with_speed_output`); the terms (``terms``, or the default ones for the logs; where the speed
    loss was turned on here, its default terms are added to those given) and the options with their error
    scales chosen for the runs kept (:meth:`FitOptions.for_runs`)."""
    setup = as_setup(model)
    kept, kept_groups, kept_validation = screen_runs(setup.model, logs, groups, validate_on)
    sailed = with_speed_output(setup, kept)
    if terms is None:
        keys = default_terms(sailed.model.effects, kept)
    else:
        keys = list(terms)
        if sailed is not setup:
            keys += [key for key in default_terms(("speed_loss",)) if key not in keys]
    options = (options or FitOptions()).for_runs(sailed.model, kept)
    return FitSetup(sailed, kept, keys, options, kept_groups, kept_validation)


@one_thread
def fit(
    model: ShipModel | ReplayModel,
    logs: Sequence[Log],
    terms: Sequence[str] | None = None,
    options: FitOptions | None = None,
) -> FitResult:
    """Fit ``terms`` (default: those of the model's effects, ``terms.DEFAULT_TERMS``) to the logs.

    Where a log measures the speed, the model sails with the speed loss on and its speed is fitted
    (:func:`~.terms.with_speed_output`; the speed loss's default terms join ``terms`` where it was off).
    A run wholly outside the model's envelope is left out, with a :class:`~.logs.LogWarning`, as
    :func:`~.validation.cross_validate` and :func:`~.improve.improve` leave it out (:func:`~.runs.screen_runs`).

    Example::

        model = ShipModel("esso_osaka_model", ["yaw", "kinematics", "rudder_offset"])
        result = fit(model, load_logs(["../shared/data/esso_osaka/zigzag"]))
        result.estimates, result.pooled.heading
    """
    prepared = fit_setup(model, logs, terms, options)
    return Problem(prepared.setup, prepared.logs, prepared.keys, prepared.options).solve()


@one_thread
def fit_each_run(
    model: ShipModel | ReplayModel,
    logs: Sequence[Log],
    terms: Sequence[str] | None = None,
    options: FitOptions | None = None,
) -> list[FitResult]:
    """One fit per run (in-sample): how well the model can fit each run on its own; a run wholly outside the
    model's envelope is left out, as :func:`fit` leaves it out."""
    prepared = fit_setup(model, logs, terms, options)
    return [Problem(prepared.setup, [log], prepared.keys, prepared.options).solve() for log in prepared.logs]
