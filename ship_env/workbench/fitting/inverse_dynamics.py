"""Identify the MMG standard's 3-DOF forces from measured runs by inverse dynamics (equation error).

The output-error fits of :mod:`.fit` replay the runs through the De Keizer / Van Leeuwen model, whose sway is
algebraic (2.47) and whose hull damping H(r*) is a function of r* alone. Zig-zags then fit a damping shaped to
their own rates of turn, which the hard-over turn, at r* and drift well beyond them, does not follow
(``docs/results/free_running.md``). The MMG standard writes the hull's forces in v' and r' to the third order,
the rudder's with its inflow and the hull's flow straightening, and its equations of motion have the sway as a
state (:mod:`ship_env.model.mmg_form`). Its coefficients are linear in the forces, which is how
identification pipelines fit them: the runs' states and accelerations smoothed (:mod:`.smoothing`), the forces
that moved the ship computed from the mass matrix, and the force coefficients regressed on the form's columns.

1. Each run is smoothed (:func:`~.smoothing.smooth_run`) into u, v, r and du/dt, dv/dt, dr/dt; the samples
   within half a ship length of its ends are left out.
2. The forces X, Y, N that moved the ship are :meth:`~ship_env.model.mmg_form.RigidBody.inertial_forces`,
   non-dimensionalised by 1/2 rho L d (N by 1/2 rho L^2 d).
3. For given inflow parameters (b_un, c_nn, gamma_R+, gamma_R-, l_R, c_w) the coefficients are the linear
   least-squares solution of each force on its columns (:func:`~ship_env.model.mmg_form.force_regressors`);
   the inflow parameters minimise the three equations' residuals, each weighted by its force's standard
   deviation (variable projection: ``scipy.optimize.least_squares`` over the six, the coefficients solved
   inside).
4. Each run is left out in turn and the fit repeated from the all-run fit's inflow: the jackknife's spread is
   each coefficient's standard error, and each fold's model sails the manoeuvres too (the spread of a
   predicted figure, :mod:`ship_env.manoeuvres.uncertainty`'s way).

The masses are not identified (:class:`~ship_env.model.mmg_form.RigidBody`: displacement from C_B, added masses
from Clarke et al. 1983); the fitted coefficients absorb most of an error in them (``docs/results/free_running.md``:
C_B 0.6 to 0.9 move the basin's predicted figures by less than 0.2 %).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from scipy.optimize import least_squares

from ship_env.model import ShipModel
from ship_env.model.mmg_fitted import MmgRecord
from ship_env.model.mmg_form import (
    INFLOW_TERMS,
    RHO,
    SURGE_TERMS,
    SWAY_TERMS,
    YAW_TERMS,
    MmgForm,
    RigidBody,
    force_regressors,
)
from ship_env.workbench.fitting.smoothing import SmoothedRun, smooth_run
from ship_env.workbench.logs.logs import Log

#: The inflow parameters' start and bounds (b_un, c_nn, gamma_R+, gamma_R-, l_R, c_w), the propeller rate times the
#: draught as nT (the MMG standard's KVLCC2: u_R^2 about 0.4 u^2 + 0.4 u nT + 0.8 (nT)^2 at its service point,
#: gamma_R 0.4-0.6, l_R -0.7, c_w = C_2 - 1 0.1-0.6); c_w starts at no change of the wake with the drift.
INFLOW_START = np.array([0.5, 0.1, 0.5, 0.5, -0.7, 0.0])
INFLOW_LOWER = np.array([-20.0, 0.0, 0.05, 0.05, -3.0, -0.5])
INFLOW_UPPER = np.array([20.0, 20.0, 5.0, 5.0, 0.5, 3.0])
#: The block coefficient assumed where none is given (its range 0.55 to 0.85 moves the predicted figures by
#: less than 0.2 %: the coefficients absorb the mass).
BLOCK_COEFFICIENT = 0.75


class IdentificationError(ValueError):
    """Runs from which the 3-DOF forces cannot be identified (naming why)."""


@dataclass(frozen=True)
class Samples:
    """The smoothed samples of the runs kept, stacked: states, rudder, propeller rate and the forces
    (non-dimensionalised) that moved the ship."""

    surge: np.ndarray
    sway: np.ndarray
    rate_of_turn: np.ndarray
    rudder: np.ndarray
    propeller_rate: np.ndarray
    forces: tuple[np.ndarray, np.ndarray, np.ndarray]

    @classmethod
    def of(cls, runs: Sequence[SmoothedRun], body: RigidBody) -> Samples:
        def stacked(name: str) -> np.ndarray:
            return np.concatenate([getattr(run, name)[run.kept] for run in runs])

        u, v, r = stacked("surge"), stacked("sway"), stacked("rate_of_turn")
        x, y, n = body.inertial_forces(
            u, v, r, stacked("surge_rate"), stacked("sway_rate"), stacked("yaw_acceleration")
        )
        scale = 0.5 * RHO * body.length * body.draught
        return cls(
            u, v, r, stacked("rudder"), stacked("propeller_rate"), (x / scale, y / scale, n / (scale * body.length))
        )


@dataclass(frozen=True)
class FormFit:
    """A fit of the form: the model, its three equations' coefficients of determination and its cost."""

    form: MmgForm
    determination: tuple[float, float, float]
    cost: float


def fit_form(samples: Samples, body: RigidBody, start: np.ndarray = INFLOW_START) -> FormFit:
    """The form fitted to ``samples`` by variable projection (the module docstring, step 3)."""
    targets = samples.forces
    weights = [1.0 / max(float(np.std(target)), 1e-12) for target in targets]
    states = (samples.surge, samples.sway, samples.rate_of_turn, samples.rudder, samples.propeller_rate)

    def solved(inflow: np.ndarray) -> tuple[tuple[np.ndarray, ...], list[np.ndarray]]:
        columns = force_regressors(*states, inflow, body)
        return columns, [np.linalg.lstsq(c, t, rcond=None)[0] for c, t in zip(columns, targets, strict=True)]

    def residuals(inflow: np.ndarray) -> np.ndarray:
        columns, coefficients = solved(inflow)
        return np.concatenate(
            [w * (c @ k - t) for w, c, k, t in zip(weights, columns, coefficients, targets, strict=True)]
        )

    inside = np.clip(start, INFLOW_LOWER + 1e-9, INFLOW_UPPER - 1e-9)
    solution = least_squares(residuals, inside, bounds=(INFLOW_LOWER, INFLOW_UPPER), x_scale="jac")
    columns, coefficients = solved(solution.x)
    determination = tuple(
        1.0 - float(np.var(c @ k - t) / np.var(t)) for c, k, t in zip(columns, coefficients, targets, strict=True)
    )
    form = MmgForm(body, solution.x, *coefficients)
    return FormFit(form, determination, float(solution.cost))  # type: ignore[arg-type]


@dataclass(frozen=True)
class Identification:
    """The identified model and how sure of it the runs make us.

    Attributes:
        record: the model with what sails it (the preset's steering machine, the runs' propeller rate and speed),
            its folds and the runs' coverage.
        fitted: the all-run fit.
        folds: the fits with each run left out, in the runs' order (empty with fewer than three runs).
        runs: the runs' names.
    """

    record: MmgRecord
    fitted: FormFit
    folds: tuple[FormFit, ...]
    runs: tuple[str, ...]

    @property
    def standard_errors(self) -> dict[str, float]:
        """Each coefficient's jackknife standard error over the runs left out (none without folds)."""
        if not self.folds:
            return {}
        names = (*INFLOW_TERMS, *SURGE_TERMS, *SWAY_TERMS, *YAW_TERMS)
        values = np.array([np.concatenate((f.form.inflow, f.form.surge, f.form.sway, f.form.yaw)) for f in self.folds])
        count = len(values)
        spread = np.sqrt((count - 1) / count * np.sum((values - values.mean(axis=0)) ** 2, axis=0))
        return dict(zip(names, (float(value) for value in spread), strict=True))


def rigid_body(
    model: ShipModel, block_coefficient: float = BLOCK_COEFFICIENT, centre_of_gravity: float = 0.0
) -> RigidBody:
    """The rigid body of ``model``'s particulars (length, breadth, draught) with these assumptions; a preset
    without a breadth or draught is refused, naming them."""
    missing = [name for name in ("breadth", "draught") if not model.parameter(name) > 0.0]
    if missing:
        raise IdentificationError(
            f"{model.ship.name}: the preset states no {' or '.join(missing)}, from which the masses are estimated"
        )
    return RigidBody(
        model.length, model.parameter("breadth"), model.parameter("draught"), block_coefficient, centre_of_gravity
    )


def steering_rate(model: ShipModel) -> float:
    """The preset's steering machine's rudder rate, rad/s; ``IdentificationError`` where it states none."""
    try:
        return model.parameter("steering_machine.rudder_rate")
    except KeyError:
        raise IdentificationError(
            f"{model.ship.name}: the preset states no steering_machine.rudder_rate, at which the identified ship "
            "moves its rudder"
        ) from None


def identify(
    logs: Sequence[Log],
    model: ShipModel,
    body: RigidBody | None = None,
    jackknife: bool = True,
    propeller_rate: float | None = None,
) -> Identification:
    """The MMG-form model of the ship that sailed ``logs`` (the module docstring); ``model`` (the preset) gives
    the particulars, the steering machine's rate and the rudder limit; ``propeller_rate`` (rps) that of logs
    without a propeller channel.

    Raises:
        IdentificationError: fewer than two runs, or a run that cannot be smoothed
            (:class:`~.smoothing.SmoothingError`, naming the run and the channel).
    """
    if len(logs) < 2:
        raise IdentificationError(f"inverse dynamics: give at least two runs, got {len(logs)}")
    body = rigid_body(model) if body is None else body
    rudder_rate = steering_rate(model)
    runs = [smooth_run(log, model.length, rudder_rate, propeller_rate) for log in logs]
    samples = Samples.of(runs, body)
    fitted = fit_form(samples, body)
    folds: tuple[FormFit, ...] = ()
    if jackknife and len(runs) >= 3:
        folds = tuple(
            fit_form(Samples.of([run for j, run in enumerate(runs) if j != i], body), body, fitted.form.inflow)
            for i in range(len(runs))
        )
    straight = np.abs(samples.rate_of_turn) * model.length / np.hypot(samples.surge, samples.sway) < 0.01
    record = MmgRecord(
        fitted.form,
        rudder_rate,
        model.rudder_limit,
        float(np.median(samples.propeller_rate)),
        float(np.median(samples.surge[straight])) if np.any(straight) else float(np.max(samples.surge)),
        folds=tuple(fold.form for fold in folds),
        coverage=coverage_of(samples, model.length),
    )
    return Identification(record, fitted, folds, tuple(log.name for log in logs))


def coverage_of(samples: Samples, length: float) -> dict[str, tuple[float | None, float]]:
    """The ranges the samples cover, as a fitted preset's (``ship_env.model.operating_point``): the largest r* =
    L |r| / u, drift angle and rudder angle, the speed u's lowest and highest."""
    surge = samples.surge
    return {
        "rate": (None, float(np.max(length * np.abs(samples.rate_of_turn) / surge))),
        "drift": (None, float(np.max(np.abs(np.arctan2(-samples.sway, surge))))),
        "rudder": (None, float(np.max(np.abs(samples.rudder)))),
        "speed": (float(np.min(surge)), float(np.max(surge))),
    }


__all__ = [
    "BLOCK_COEFFICIENT",
    "FormFit",
    "Identification",
    "coverage_of",
    "IdentificationError",
    "Samples",
    "fit_form",
    "identify",
    "rigid_body",
]
