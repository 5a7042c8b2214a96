"""The identification comparison: every estimator on the same logs, a table, convergence plots, and stelling 5.

For each scenario of :mod:`ship_env.baselines.online_estimators.scenarios` the trial is sailed once and every
estimator runs on the same log; the table gives per estimator the final relative error of each
parameter, the time after which each stays within 10 % (:mod:`~ship_env.baselines.online_estimators.criteria`),
J_p over the run (thesis 6.1) and the cost per sample in microseconds (wall time of its run over the
log divided by the samples). An estimator that diverges is listed with the reason. The adaptation
section runs :func:`~ship_env.baselines.online_estimators.adaptation_comparison.compare_adaptation` for the
least-squares and the EKF pair at two drift densities. Plots are drawn on matplotlib's Agg canvas
(no display needed, the user's pyplot backend left alone).
"""

from __future__ import annotations

import math
import time
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure as Drawing

from ship_env.baselines.filter_health import FilterDivergenceError
from ship_env.baselines.online_estimators.adaptation_comparison import (
    AdaptationComparison,
    compare_adaptation,
)
from ship_env.baselines.online_estimators.criteria import (
    TOLERANCE,
    final_errors,
    parameter_criterion,
    settling_times,
)
from ship_env.baselines.online_estimators.estimator import Estimator
from ship_env.baselines.online_estimators.excitation import Trial
from ship_env.baselines.online_estimators.history import ParameterHistory
from ship_env.baselines.online_estimators.scenarios import (
    SCENARIOS,
    adaptation_trials,
    forgetting_ekf,
    forgetting_least_squares,
    random_walk_ekf,
    random_walk_least_squares,
)
from ship_env.text_table import Table

#: The relative drift densities (1/s) of the random walks in the adaptation comparison: slow and fast adaptation.
ADAPTATION_DRIFTS = (1e-5, 1e-4)


@dataclass(frozen=True, eq=False)
class EstimatorRun:
    """One estimator on one scenario's log.

    Attributes:
        scenario, estimator: names.
        history: its estimates (None if it diverged).
        microseconds_per_step: wall time of the run over the log per sample.
        final: |relative error| per parameter at the end.
        settling: per parameter, when it came within 10 % for good (None: never).
        criterion: J_p over the run, s.
        failure: why it stopped (divergence), else None.
    """

    scenario: str
    estimator: str
    history: ParameterHistory | None
    microseconds_per_step: float
    final: dict[str, float] | None = None
    settling: dict[str, float | None] | None = None
    criterion: float | None = None
    failure: str | None = None


def run_estimator(scenario: str, estimator: Estimator, trial: Trial) -> EstimatorRun:
    """Run ``estimator`` over ``trial``'s log and judge it against its truth."""
    start = time.perf_counter()
    try:
        history = estimator.run(trial.log)
    except FilterDivergenceError as error:
        cost = (time.perf_counter() - start) / trial.log.samples * 1e6
        return EstimatorRun(scenario, estimator.name, None, cost, failure=str(error))
    cost = (time.perf_counter() - start) / trial.log.samples * 1e6
    return EstimatorRun(
        scenario,
        estimator.name,
        history,
        cost,
        final_errors(history, trial.truth),
        settling_times(history, trial.truth),
        parameter_criterion(history, trial.truth),
    )


def run_scenario(name: str, seed: int = 0, scale: float = 1.0) -> tuple[Trial, list[EstimatorRun]]:
    """Sail scenario ``name`` (durations times ``scale``) and run its estimators on it."""
    scenario = SCENARIOS[name]
    trial = scenario.make_trial(seed, scale)
    return trial, [run_estimator(name, estimator, trial) for estimator in scenario.make_estimators(trial)]


@dataclass(frozen=True, eq=False)
class AdaptationRow:
    """One stelling-5 comparison: the estimator pair and the random walk's drift density."""

    pair: str
    drift: float
    comparison: AdaptationComparison


def run_adaptation(
    seed: int = 0, scale: float = 1.0, drifts: Sequence[float] = ADAPTATION_DRIFTS
) -> list[AdaptationRow]:
    """Stelling 5 for the least-squares pair and the EKF pair at each drift density."""
    calibration, change = adaptation_trials(seed, scale)
    length = change.ship_length
    rows = []
    for drift in drifts:
        pairs = (
            ("least squares", random_walk_least_squares(length, drift), forgetting_least_squares(length)),
            ("EKF", random_walk_ekf(length, drift), forgetting_ekf(length)),
        )
        for pair, random_walk, make_forgetting in pairs:
            comparison = compare_adaptation(random_walk, make_forgetting, calibration, change, 600.0 * scale)
            rows.append(AdaptationRow(pair, drift, comparison))
    return rows


def _seconds(value: float | None) -> str:
    return "never" if value is None else f"{value:.0f}"


def comparison_table(runs: Sequence[EstimatorRun]) -> str:
    """The comparison as text: one row per scenario and estimator, then why each diverged run failed."""
    rows = []
    for run in runs:
        if run.failure is not None:
            rows.append((run.scenario, run.estimator, "diverged", "", "", ""))
            continue
        assert run.final is not None and run.settling is not None  # a run that did not diverge has its figures
        final = " ".join(f"{name} {100.0 * error:.1f}" for name, error in run.final.items())
        settled = " ".join(f"{name} {_seconds(value)}" for name, value in run.settling.items())
        rows.append(
            (run.scenario, run.estimator, final, settled, f"{run.criterion:.3g}", f"{run.microseconds_per_step:.0f}")
        )
    header = ("scenario", "estimator", "final |error| %", "within 10 % after (s)", "J_p (s)", "us/step")
    failures = [f"{run.scenario}, {run.estimator} diverged: {run.failure}" for run in runs if run.failure is not None]
    return "\n".join([Table(header, tuple(rows), words=4).text(), *failures])


def adaptation_table(rows: Sequence[AdaptationRow]) -> str:
    """Stelling 5 as text: the matched lambda, both noises, both J_p after the change, both recoveries."""
    cells = []
    for row in rows:
        c = row.comparison
        better = ("random walk" if c.random_walk_tracks_better else "forgetting") + ("" if c.noise_matched else " *")
        cells.append(
            (
                row.pair,
                f"{row.drift:.0e}",
                f"{c.forgetting_factor:.5f}",
                f"{c.random_walk.steady_noise:.2e}",
                f"{c.forgetting.steady_noise:.2e}",
                f"{c.random_walk.tracking_criterion:.3g}",
                f"{c.forgetting.tracking_criterion:.3g}",
                _seconds(c.random_walk.recovery_time),
                _seconds(c.forgetting.recovery_time),
                better,
            )
        )
    header = (
        "pair",
        "drift 1/s",
        "lambda",
        "noise RW",
        "noise FF",
        "J_p RW",
        "J_p FF",
        "recover RW",
        "recover FF",
        "better (* noise not matched)",
    )
    return Table(header, tuple(cells)).text()


def plot_scenario(trial: Trial, runs: Sequence[EstimatorRun], path: Path) -> Path:
    """Each parameter's estimates against time, the truth dashed in a +-10 % band; one PNG."""
    names = trial.truth.names
    figure = Drawing(figsize=(9, 2.2 * len(names) + 0.8))
    FigureCanvasAgg(figure)
    axes = figure.subplots(len(names), 1, sharex=True, squeeze=False)
    for i, (name, axis) in enumerate(zip(names, axes[:, 0], strict=True)):
        truth = trial.truth.values[:, i]
        axis.fill_between(trial.truth.time, truth * (1 - TOLERANCE), truth * (1 + TOLERANCE), color="0.88", lw=0)
        axis.plot(trial.truth.time, truth, "k--", lw=1.2, label="truth")
        for run in runs:
            if run.history is not None:
                axis.plot(run.history.time, run.history.values[:, i], lw=1.0, label=run.estimator)
        low, high = sorted((truth.min() * 0.5, truth.max() * 1.5))
        axis.set_ylim(low - 0.05 * abs(high), high + 0.05 * abs(high))
        axis.set_ylabel(name)
        axis.grid(alpha=0.3)
    axes[0, 0].set_title(trial.log.name)
    axes[-1, 0].set_xlabel("time (s)")
    axes[0, 0].legend(fontsize=7, loc="upper right")
    figure.tight_layout()
    figure.savefig(path, dpi=110)
    return path


def plot_adaptation(rows: Sequence[AdaptationRow], truth: ParameterHistory, path: Path) -> Path:
    """The adaptation comparison: each pair's K*, tau* on the loading change, random walk against forgetting."""
    figure = Drawing(figsize=(3.6 * len(rows), 5.2))
    FigureCanvasAgg(figure)
    axes = figure.subplots(len(truth.names), len(rows), sharex=True, squeeze=False)
    for j, row in enumerate(rows):
        c = row.comparison
        for i, name in enumerate(truth.names):
            axis = axes[i, j]
            axis.plot(truth.time, truth.values[:, i], "k--", lw=1.2, label="truth")
            axis.plot(c.random_walk.history.time, c.random_walk.history.values[:, i], lw=1.0, label="random walk")
            axis.plot(
                c.forgetting.history.time,
                c.forgetting.history.values[:, i],
                lw=1.0,
                label=f"forgetting {c.forgetting_factor:.4f}",
            )
            axis.set_ylim(0.5 * truth.values[:, i].min(), 1.5 * truth.values[:, i].max())
            axis.set_ylabel(name)
            axis.grid(alpha=0.3)
        axes[0, j].set_title(f"{row.pair}, drift {row.drift:.0e}/s", fontsize=9)
        axes[0, j].legend(fontsize=6)
        axes[-1, j].set_xlabel("time (s)")
    figure.tight_layout()
    figure.savefig(path, dpi=110)
    return path


def scale_label(scale: float) -> str:
    return "" if math.isclose(scale, 1.0) else f" (durations x{scale:g})"
