"""The workbench's Markdown report: the runs, the error ladder, the diagnoses and the figures.

``write_report`` writes ``report.md`` and its PNG figures into one folder: the ladder as a table
and a plot, the fitted terms of the final model, each rung's diagnosis (why the next effect was
chosen), and per run the held-out comparison of the starting and the final model.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from pathlib import Path

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure as Drawing
from matplotlib.ticker import FormatStrFormatter

from ship_env.workbench.deciding.diagnose import Diagnosis
from ship_env.workbench.deciding.improve import Ladder
from ship_env.workbench.fitting.errors import ErrorScales
from ship_env.workbench.fitting.parallel import run_each
from ship_env.workbench.fitting.terms import not_identified, replay_inputs
from ship_env.workbench.judging.compare import held_out_comparison, plot_run, run_drawings
from ship_env.workbench.judging.coverage import beyond_in_words
from ship_env.workbench.judging.free_running import (
    RunFigures,
    Series,
    disagreements,
    free_running_table,
    held_out_free_running,
)
from ship_env.workbench.judging.validation import CrossValidation
from ship_env.workbench.logs.logs import Log
from ship_env.workbench.outputs import save_drawing
from ship_env.workbench.reporting.tables import (
    coverage_sections,
    diagnosis_table,
    estimate_table,
    ladder_table,
    log_table,
)


def plot_ladder(ladder: Ladder, path: Path) -> Path:
    """The held-out errors after each added effect: heading and track, and the score."""
    labels = [rung.label for rung in ladder.rungs]
    held_out = [rung.validation.pooled for rung in ladder.rungs]
    steps = np.arange(len(labels))
    drawing = Drawing(figsize=(max(6.0, 1.6 * len(labels) + 2.0), 6.5))
    FigureCanvasAgg(drawing)
    errors_axes, score_axes = drawing.subplots(2, 1, sharex=True)
    errors_axes.plot(steps, [math.degrees(e.heading) for e in held_out], "o-", color="tab:red", label="heading")
    errors_axes.set_ylabel("held-out RMS heading [deg]", color="tab:red")
    errors_axes.set_ylim(bottom=0.0)
    track = [e.track for e in held_out]
    if all(math.isfinite(value) for value in track):
        track_axes = errors_axes.twinx()
        track_axes.plot(steps, track, "s--", color="tab:blue", label="track")
        track_axes.set_ylabel("held-out RMS track [m]", color="tab:blue")
        track_axes.set_ylim(bottom=0.0)
    score_axes.semilogy(steps, [e.score(ladder.scales) for e in held_out], "o-", color="black")
    score_axes.yaxis.set_major_formatter(FormatStrFormatter("%g"))
    score_axes.yaxis.set_minor_formatter(FormatStrFormatter("%g"))
    score_axes.set_ylabel("held-out score (log scale)")
    score_axes.set_xticks(steps, labels, rotation=20, ha="right")
    score_axes.grid(True, which="both", alpha=0.3)
    errors_axes.set_title("Error ladder: held-out error (leave one run out) after each added effect")
    return save_drawing(drawing, path, dpi=90)


def plot_free_running(results: Sequence[RunFigures], logs: Sequence[Log], length: float, path: Path) -> Path:
    """Each run's track from its first execute, measured against sailed free, in ship lengths, into a PNG."""
    by_name = {log.name: log for log in logs}
    columns = min(4, len(results))
    rows = math.ceil(len(results) / columns)
    drawing = Drawing(figsize=(3.4 * columns, 3.2 * rows + 0.6))
    FigureCanvasAgg(drawing)
    axes = np.atleast_1d(drawing.subplots(rows, columns, squeeze=False)).ravel()
    for panel, result in zip(axes, results, strict=False):
        log, predicted = by_name[result.run], result.predicted_series
        start = result.manoeuvre.executes[0]
        measured = Series.of_log(log)
        assert measured is not None  # a run without a track has no figures
        sailed: list[tuple[Series, str, str]] = [(measured, "black", "measured")]
        if predicted is not None:  # None: the model cannot sail it
            sailed.append((predicted, "tab:red", "sailed free"))
        for series, colour, label in sailed:
            inside = (series.time >= start) & (series.time <= log.time[-1])  # over the measured run
            north0, east0 = (float(np.interp(start, series.time, v)) for v in (series.north, series.east))
            panel.plot(
                (series.east[inside] - east0) / length,
                (series.north[inside] - north0) / length,
                color=colour,
                label=label,
            )
        panel.set_aspect("equal", adjustable="datalim")
        stuck = "; the model cannot sail it" if result.cannot_sail else ""
        panel.set_title(f"{result.run} ({result.manoeuvre.kind}{stuck})", fontsize=9)
        panel.tick_params(labelsize=8)
    for panel in axes[len(results) :]:
        panel.set_visible(False)
    axes[0].legend(fontsize=8)
    drawing.supxlabel("east from the first execute [L]")
    drawing.supylabel("north [L]")
    return save_drawing(drawing, path, dpi=80)


def _free_running_lines(ladder: Ladder, logs: Sequence[Log], folder: Path, workers: int = 1) -> list[str]:
    """The section on the runs' manoeuvres sailed free by the starting and the final model (none: no lines),
    the two sailed on ``workers`` processes."""
    first, last = ladder.rungs[0], ladder.rungs[-1]
    shown = (("start", first), ("final", last)) if len(ladder.rungs) > 1 else (("final", last),)
    figures = run_each(held_out_free_running, [(rung.validation, logs) for _, rung in shown], workers)
    sailed = [(label, rung, results) for (label, rung), results in zip(shown, figures, strict=True)]
    if not sailed[-1][2]:
        return []
    lines = [
        "## Manoeuvres sailed free: measured against predicted",
        "",
        (
            "Each turning and zig-zag run (validation runs included) read as its manoeuvre and sailed free by a "
            "model that did not see it, from the measured state at its first execute: a turn holds its rudder, a "
            "zig-zag reverses the rudder on the heading, as a helmsman does "
            "(`ship_env.workbench.judging.free_running`). Figures in ship lengths L, degrees and seconds."
        ),
        "",
    ]
    everything = [*logs, *last.validation.validation_logs]
    length = last.validation.fit.setup.model.length
    for label, rung, results in sailed:
        path = plot_free_running(
            results,
            everything,
            length,
            folder / f"free_running_{label}.png",
        )
        lines += [
            f"### {label} model: {', '.join(rung.effects)}",
            "",
            free_running_table(results).markdown(),
            "",
            *_figure_links([path], folder),
            "",
        ]
    missed = disagreements(sailed[-1][2], last.validation.fit.setup.model.effects)
    if missed:
        beyond = beyond_in_words(last.validation.validation_checks())
        lines += [
            "Where the final model's figures disagree with the measured ones:",
            "",
            *(f"- {line}" for line in missed),
            *([f"- the validation runs lie {beyond}"] if beyond else []),
            "",
        ]
    return lines


def _coverage_lines(validation: CrossValidation, scales: ErrorScales) -> list[str]:
    """The validation runs against the fitted runs' coverage, as Markdown (none without validation runs)."""
    if validation.coverage is None or not validation.validation:
        return []
    checks, logs = validation.validation_checks(), validation.validation_logs
    sections = coverage_sections(
        "Validation runs", validation.coverage, checks, logs, validation.validation_replays, scales
    )
    lines = ["## Validation runs and the fitted runs' coverage (final model)", ""]
    for heading, table in sections:
        lines += [heading[:1].upper() + heading[1:] + ("." if table is None else ":"), ""]
        if table is not None:
            lines += [table.markdown(), ""]
    return lines


def _figure_links(paths: Sequence[Path], folder: Path) -> list[str]:
    return [f"![{path.stem}]({path.relative_to(folder).as_posix()})" for path in paths]


def write_report(
    ladder: Ladder, logs: Sequence[Log], folder: Path, title: str = "Measurement workbench", workers: int = 1
) -> Path:
    """Write ``report.md`` with its figures (drawn on ``workers`` processes) into ``folder``; returns its path."""
    folder.mkdir(parents=True, exist_ok=True)
    scales = ladder.scales
    first, last = ladder.rungs[0], ladder.rungs[-1]
    ladder_plot = plot_ladder(ladder, folder / "error_ladder.png")
    lines = [
        f"# {title}",
        "",
        (
            f"Ship preset `{last.validation.fit.setup.model.ship.name}`; {len(logs)} runs. Errors are RMS over "
            "each run's samples, *held out*: each run is replayed from its measured initial state by the model "
            "fitted to the other runs. *Track* is the track replayed with the measured heading (the error of the "
            "track effects alone), *position* the freely simulated track; both are distances between measured "
            "and simulated positions; *speed* is the model's own speed, predicted from each run's service and "
            "initial speed. The score is sqrt(mean((RMS / scale)^2)) over heading, rate of turn, speed and "
            f"track with the error scales {scales.describe()}."
        ),
        "",
        f"Inputs taken from the logs: {'; '.join(replay_inputs(logs))}.",
        "",
        *(
            line
            for words in not_identified(last.validation.fit.setup.model, logs)
            for line in (f"Not identified: {words}.", "")
        ),
        "## Runs",
        "",
        log_table(logs).markdown(),
        "",
        "## Error ladder",
        "",
        ladder_table(ladder).markdown(),
        "",
        f"Stopped: {ladder.stopped}.",
        "",
        *_figure_links([ladder_plot], folder),
        "",
        *_coverage_lines(last.validation, scales),
        "## Final model",
        "",
        f"Effects: {', '.join(last.effects)}. Fitted to all runs:",
        "",
        estimate_table(last.validation).markdown(),
        "",
        (
            "Standard errors from the Jacobian, scaled by the residual variance (optimistic: output-error "
            "residuals are correlated in time), and from the spread of the leave-one-run-out fits (jackknife)."
        ),
        "",
        "## Diagnoses",
        "",
    ]
    for rung in ladder.rungs:
        if rung.diagnosis is None:
            continue
        name = "start" if not rung.added else f"after adding {' + '.join(rung.added)}"
        lines += [f"### {name}", "", diagnosis_table(rung.diagnosis).markdown(), ""]
        if rung.pairs:
            together = Diagnosis(rung.diagnosis.baseline, rung.pairs, ladder.scales)
            lines += [
                "Added two at a time (no single effect paid enough):",
                "",
                diagnosis_table(together).markdown(),
                "",
            ]
    lines += _free_running_lines(ladder, logs, folder, workers)
    lines += ["## Runs, held out: measured against simulated", ""]
    shown = (("start", first), ("final", last)) if len(ladder.rungs) > 1 else (("final", last),)
    drawings = [
        run_drawings(
            held_out_comparison(rung.validation, logs),
            folder / label,
            f"{label} model: {', '.join(rung.effects)}",
        )
        for label, rung in shown
    ]
    # Every model's runs drawn in one go: the workers share them out evenly.
    paths = iter(run_each(plot_run, [drawing for runs in drawings for drawing in runs], workers))
    for (label, _), runs in zip(shown, drawings, strict=True):
        lines += [f"### {label} model", "", *_figure_links([next(paths) for _ in runs], folder), ""]
    path = folder / "report.md"
    path.write_text("\n".join(lines))
    return path
