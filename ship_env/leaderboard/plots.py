"""The leaderboard's drawings, written as PNGs: the scores with their intervals, the headline, and
every controller on one scenario.

Drawn with matplotlib's object interface on the Agg canvas (no display, the user's pyplot backend
left alone), as :mod:`ship_env.manoeuvres.plotting` does, except the headline, drawn by rliable's
own ``plot_interval_estimates`` (a pyplot figure, closed once saved). Score axes start at 0.

The drawings are as wide as the documentation's page column (:data:`PAGE_WIDTH_PX` at :data:`DPI`),
where the pages show them, so a browser shows them at the size they were drawn; the headline keeps
rliable's size and large type, which a browser scales to the column.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure as Drawing

from ship_env.envs.track_follow_task import TrackFollowTask
from ship_env.leaderboard.statistics import REFERENCES, Estimate
from ship_env.leaderboard.tables import SuiteRanking
from ship_env.model import state as S

#: Bar colours by the entrant's kind.
KIND_COLOURS = {"classic": "tab:blue", "learned": "tab:orange", "human": "0.6"}
#: The resolution the drawings are written at, dots per inch.
DPI = 90
#: The width of the documentation's page column, in CSS pixels (furo's article at a 1280-pixel window: 46 em
#: of 16 pixels between the sidebars), which the drawings are drawn for.
PAGE_WIDTH_PX = 736
#: The drawings' width, inches: the page column at :data:`DPI`.
PAGE_WIDTH_IN = PAGE_WIDTH_PX / DPI
#: Panels side by side in the scores' drawing (two fit the page column with their entrants' names).
SCORE_COLUMNS = 2
#: Height of a scores panel, inches: per entrant drawn, and for its title and axis below.
SCORE_ROW_IN, SCORE_PANEL_FRAME_IN = 0.3, 1.1


def draw_scores(tables: Sequence[SuiteRanking]) -> Drawing:
    """Each suite's normalised scores (IQM, 1 = the reference autopilot, lower is better) as points
    with their 95 % intervals, one panel per suite, on an axis from 0; an entrant without an interval is
    drawn hollow, under a title naming the ship sailed. Each condition's panels lie under its name,
    :data:`SCORE_COLUMNS` to a row, so the drawing is as wide as the page column."""
    tasks = list(dict.fromkeys(table.suite.task for table in tables))
    conditions = list(dict.fromkeys(table.suite.condition.name for table in tables))
    columns = min(SCORE_COLUMNS, len(tasks))
    rows = math.ceil(len(tasks) / columns)
    panel_height = SCORE_PANEL_FRAME_IN + SCORE_ROW_IN * max(len(table.standings) for table in tables)
    drawing = Drawing(figsize=(PAGE_WIDTH_IN, panel_height * rows * len(conditions)), dpi=DPI, layout="constrained")
    FigureCanvasAgg(drawing)
    ship = tables[0].suite.ship_name
    drawing.suptitle(f"normalised scores on {ship}: IQM, 95 % intervals, lower is better")
    layout = drawing.add_gridspec(len(conditions), 1)
    groups = [drawing.add_subfigure(layout[k, 0]) for k in range(len(conditions))]
    panels = []
    for group, condition in zip(groups, conditions, strict=True):
        group.suptitle(condition, fontsize="medium", fontweight="bold")
        panels.append(group.subplots(rows, columns, squeeze=False).ravel())
        for axes in panels[-1]:
            axes.set_axis_off()
    for table in tables:
        axes = panels[conditions.index(table.suite.condition.name)][tasks.index(table.suite.task)]
        axes.set_axis_on()
        standings = [s for s in table.standings[::-1] if math.isfinite(s.normalised.value)]  # the best on top
        for y, standing in enumerate(standings):
            estimate, colour = standing.normalised, KIND_COLOURS[standing.kind]
            if estimate.has_interval:
                low, high = estimate.bounds
                whiskers = [[estimate.value - low], [high - estimate.value]]
                axes.errorbar(estimate.value, y, xerr=whiskers, fmt="o", color=colour, capsize=3)
            else:
                axes.plot(estimate.value, y, "o", markerfacecolor="none", color=colour)
        axes.set_yticks(range(len(standings)), [standing.entrant for standing in standings])
        axes.set_ylim(-0.5, len(standings) - 0.5)
        highs = [s.normalised.bounds[1] for s in standings]
        axes.set_xlim(0.0, 1.1 * max([1.0, *highs]))
        axes.axvline(1.0, color="0.5", linestyle="--", linewidth=1.0)
        axes.set_title(table.suite.task, fontsize="medium")
        axes.set_xlabel(f"1 = {REFERENCES[table.suite.env_id]}", fontsize="small")
        axes.tick_params(labelsize="small")
        axes.grid(True, axis="x", alpha=0.3)
    return drawing


def plot_scores(tables: Sequence[SuiteRanking], path: Path) -> Path:
    """:func:`draw_scores` written to ``path``; returns ``path``."""
    draw_scores(tables).savefig(path, dpi=DPI)
    return path


def draw_aggregate(
    estimates: Mapping[str, Sequence[Estimate]], metric_names: Sequence[str], xlabel: str, title: str
) -> Drawing:
    """rliable's interval-estimates figure (a bar per entrant spanning its 95 % interval, a tick at
    the point estimate) under ``title``, one panel per metric, each axis from 0; the title stands
    above the panels' titles. A pyplot figure: close it once saved."""
    from rliable import plot_utils

    names = list(estimates)
    points = {name: np.array([e.value for e in estimates[name]]) for name in names}
    intervals = {name: np.array([e.bounds for e in estimates[name]]).T for name in names}
    figure, panels = plot_utils.plot_interval_estimates(
        points, intervals, metric_names, algorithms=names, xlabel="", subfigure_width=4.5, row_height=0.5
    )
    panels = np.atleast_1d(panels)
    for k, axes in enumerate(panels):
        axes.set_xlim(0.0, 1.05 * max(float(intervals[name][1, k]) for name in names))
        axes.axvline(1.0, color="0.5", linestyle="--", linewidth=1.0)
    # rliable sets its axis label and a figure title at fixed heights, where the tick labels and the
    # panels' titles may reach: set both beyond what the panels draw instead.
    figure.draw_without_rendering()
    renderer = figure.canvas.get_renderer()  # Agg's, as pyplot made it
    drawn = [axes.get_tightbbox(renderer) for axes in panels]
    middle = (min(box.x0 for box in drawn) + max(box.x1 for box in drawn)) / 2 / figure.bbox.width
    bottom = min(box.y0 for box in drawn) / figure.bbox.height
    figure.text(middle, bottom, xlabel, ha="center", va="top", fontsize="xx-large")
    top = max(box.y1 for box in drawn) / figure.bbox.height
    figure.suptitle(title, x=middle, y=top, va="bottom", fontsize="x-large")
    return figure


def plot_aggregate(
    estimates: Mapping[str, Sequence[Estimate]], metric_names: Sequence[str], xlabel: str, title: str, path: Path
) -> Path:
    """:func:`draw_aggregate` written to ``path``, cropped to what it draws; returns ``path``."""
    import matplotlib.pyplot as pyplot

    figure = draw_aggregate(estimates, metric_names, xlabel, title)
    figure.savefig(path, dpi=DPI, bbox_inches="tight")
    pyplot.close(figure)
    return path


def plot_course_changes(runs: Mapping[str, np.ndarray], title: str, course_change_deg: float, path: Path) -> Path:
    """Heading change and rudder against time of each controller's run (states from
    :func:`~ship_env.leaderboard.sailing.sail_recorded`); returns ``path``."""
    drawing = Drawing(figsize=(PAGE_WIDTH_IN, 6.5), layout="constrained")
    FigureCanvasAgg(drawing)
    heading, rudder = drawing.subplots(2, 1, sharex=True)
    for name, states in runs.items():
        time = states[:, S.TIME]
        heading.plot(time, np.degrees(states[:, S.HEADING] - states[0, S.HEADING]), label=name)
        rudder.plot(time, np.degrees(states[:, S.RUDDER]), label=name, linewidth=1.0)
    heading.axhline(course_change_deg, color="0.5", linestyle="--", linewidth=1.0, label="ordered change")
    heading.set(title=title, ylabel="heading change [deg]")
    rudder.set(xlabel="time [s]", ylabel="actual rudder [deg]")
    for axes in (heading, rudder):
        axes.grid(True, alpha=0.3)
    heading.legend(fontsize="small")
    drawing.savefig(path, dpi=DPI)
    return path


def plot_tracks(runs: Mapping[str, np.ndarray], task: TrackFollowTask, track: str, title: str, path: Path) -> Path:
    """Each controller's track over the ground beside the reference track ``track`` (north up,
    equal axes); returns ``path``."""
    drawing = Drawing(figsize=(PAGE_WIDTH_IN, 9), layout="constrained")
    FigureCanvasAgg(drawing)
    axes = drawing.subplots()
    outline = task.tracks[track].outline()
    axes.plot(outline[:, 1], outline[:, 0], color="0.5", linestyle="--", linewidth=1.5, label=f"reference {track}")
    for name, states in runs.items():
        axes.plot(states[:, S.EAST], states[:, S.NORTH], label=name, linewidth=1.0)
    axes.set(title=title, xlabel="east [m]", ylabel="north [m]", aspect="equal")
    axes.grid(True, alpha=0.3)
    axes.legend(fontsize="small")
    drawing.savefig(path, dpi=DPI)
    return path
