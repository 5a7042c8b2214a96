"""Leave-one-run-out cross-validation: the error that matters is on runs the fit did not see.

The model is fitted to all runs; then each run in turn is left out, the model refitted to the
others (starting from the all-run fit), and the run left out replayed from its measured initial
state -- no per-run refitting. The pooled errors of these replays are the *held-out* errors the
workbench ranks models by; the spread of the fold estimates gives jackknife standard errors.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from ship_env.model import ShipModel
from ship_env.workbench.errors import ErrorScales, RunErrors, pooled, run_errors
from ship_env.workbench.fit import FitError, FitOptions, FitResult, Problem, as_setup
from ship_env.workbench.logs import Log
from ship_env.workbench.replay import ReplayModel, simulate
from ship_env.workbench.terms import default_terms, with_values


@dataclass(frozen=True)
class CrossValidation:
    """A fit on all runs and the errors on each run of a fit that did not see it.

    Attributes:
        fit: the fit on all runs.
        folds: per run, the fit on the other runs.
        held_out: per run, its errors under the fold that left it out (from its measured state).
    """

    fit: FitResult
    folds: tuple[FitResult, ...]
    held_out: tuple[RunErrors, ...]

    @property
    def pooled(self) -> RunErrors:
        """The held-out errors pooled over all runs."""
        return pooled(self.held_out, "held out")

    def score(self, scales: ErrorScales) -> float:
        return self.pooled.score(scales)

    def jackknife_errors(self) -> dict[str, float]:
        """Standard errors of the fitted terms from the spread of the leave-one-run-out fits.

        The jackknife estimate sqrt((n - 1) / n * sum_i (theta_i - mean theta)^2) over the n folds:
        unlike the Jacobian's, it holds what differs from run to run (correlated residuals, noisy
        inputs, effects the model lacks).
        """
        values = np.array([[estimate.value for estimate in fold.estimates] for fold in self.folds])
        count = len(self.folds)
        spread = np.sqrt((count - 1) / count * np.sum((values - values.mean(axis=0)) ** 2, axis=0))
        return {estimate.term.key: float(value) for estimate, value in zip(self.fit.estimates, spread, strict=True)}


def cross_validate(
    model: ShipModel | ReplayModel,
    logs: Sequence[Log],
    terms: Sequence[str] | None = None,
    options: FitOptions | None = None,
    starts: Sequence[Mapping[str, float]] = (),
) -> CrossValidation:
    """Fit on all runs, then leave each run out in turn: fit on the rest, replay the one left out.

    Output-error fits have local minima, so the all-run fit may start from several points: the
    model's own values and each of ``starts`` (values for some terms); the fit with the lowest
    cost is kept, and every fold starts from it.
    """
    if len(logs) < 2:
        raise FitError("cross-validation: leaving one run out needs at least two runs")
    options = options or FitOptions()
    setup = as_setup(model)
    keys = default_terms(setup.model.effects) if terms is None else list(terms)
    candidates = [Problem(with_values(setup, start), logs, keys, options).solve() for start in ({}, *starts)]
    everything = min(candidates, key=lambda result: float(result.residual @ result.residual))
    folds = []
    held_out = []
    for left_out, log in enumerate(logs):
        others = [other for i, other in enumerate(logs) if i != left_out]
        fold = Problem(everything.setup, others, keys, options).solve()
        folds.append(fold)
        held_out.append(run_errors(log, simulate(fold.setup, [log], options.initial_window)[0]))
    return CrossValidation(fit=everything, folds=tuple(folds), held_out=tuple(held_out))
