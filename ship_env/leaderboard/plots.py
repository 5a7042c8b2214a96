"""The leaderboard's drawings, written as PNGs: the scores with their intervals, the headline, and
every controller on one scenario.

Drawn with matplotlib's object interface on the Agg canvas (no display, the user's pyplot backend
left alone), as :mod:`ship_env.manoeuvres.plotting` does, except the headline, drawn by rliable's
own ``plot_interval_estimates`` (a pyplot figure, closed once saved). Score axes start at 0.
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
from ship_env.leaderboard.tables import Table
from ship_env.model import state as S

#: Bar colours by the entrant's kind.
KIND_COLOURS = {"classic": "tab:blue", "learned": "tab:orange", "human": "0.6"}


def plot_scores(tables: Sequence[Table], path: Path) -> Path:
    """Each suite's normalised scores (IQM, 1 = the reference autopilot, lower is better) as points
    with their 95 % intervals, one panel per suite (conditions in rows), on an axis from 0; an
    entrant without an interval is drawn hollow, under a title naming the ship sailed. Returns ``path``."""
    tasks = list(dict.fromkeys(table.suite.task for table in tables))
    conditions = list(dict.fromkeys(table.suite.condition.name for table in tables))
    drawing = Drawing(figsize=(5.2 * len(tasks), 2.8 * len(conditions)), layout="constrained")
    FigureCanvasAgg(drawing)
    panels = drawing.subplots(len(conditions), len(tasks), squeeze=False)
    drawing.suptitle(f"normalised scores on {tables[0].suite.ship_name}")
    for row in panels:
        for axes in row:
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
        highs = [s.normalised.bounds[1] for s in standings]
        axes.set_xlim(0.0, 1.1 * max([1.0, *highs]))
        axes.axvline(1.0, color="0.5", linestyle="--", linewidth=1.0)
        axes.set_title(table.suite.name, fontsize="medium")
        axes.set_xlabel(f"normalised IQM [95 % CI] (1 = {REFERENCES[table.suite.env_id]})", fontsize="small")
        axes.tick_params(labelsize="small")
        axes.grid(True, axis="x", alpha=0.3)
    drawing.savefig(path, dpi=90)
    return path


def plot_aggregate(
    estimates: Mapping[str, Sequence[Estimate]], metric_names: Sequence[str], xlabel: str, title: str, path: Path
) -> Path:
    """rliable's interval-estimates figure (a bar per entrant spanning its 95 % interval, a tick at
    the point estimate) under ``title``, one panel per metric, each axis from 0; returns ``path``."""
    import matplotlib.pyplot as pyplot
    from rliable import plot_utils

    names = list(estimates)
    points = {name: np.array([e.value for e in estimates[name]]) for name in names}
    intervals = {name: np.array([e.bounds for e in estimates[name]]).T for name in names}
    figure, panels = plot_utils.plot_interval_estimates(
        points, intervals, metric_names, algorithms=names, xlabel=xlabel, subfigure_width=4.5, row_height=0.5
    )
    for k, axes in enumerate(np.atleast_1d(panels)):
        axes.set_xlim(0.0, 1.05 * max(float(intervals[name][1, k]) for name in names))
        axes.axvline(1.0, color="0.5", linestyle="--", linewidth=1.0)
    figure.suptitle(title)
    figure.savefig(path, dpi=90, bbox_inches="tight")
    pyplot.close(figure)
    return path


def plot_course_changes(runs: Mapping[str, np.ndarray], title: str, course_change_deg: float, path: Path) -> Path:
    """Heading change and rudder against time of each controller's run (states from
    :func:`~ship_env.leaderboard.sailing.sail_recorded`); returns ``path``."""
    drawing = Drawing(figsize=(11, 7), layout="constrained")
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
    drawing.savefig(path, dpi=90)
    return path


def plot_tracks(runs: Mapping[str, np.ndarray], task: TrackFollowTask, track: str, title: str, path: Path) -> Path:
    """Each controller's track over the ground beside the reference track ``track`` (north up,
    equal axes); returns ``path``."""
    drawing = Drawing(figsize=(8, 9), layout="constrained")
    FigureCanvasAgg(drawing)
    axes = drawing.subplots()
    outline = task.tracks[track].outline()
    axes.plot(outline[:, 1], outline[:, 0], color="0.5", linestyle="--", linewidth=1.5, label=f"reference {track}")
    for name, states in runs.items():
        axes.plot(states[:, S.EAST], states[:, S.NORTH], label=name, linewidth=1.0)
    axes.set(title=title, xlabel="east [m]", ylabel="north [m]", aspect="equal")
    axes.grid(True, alpha=0.3)
    axes.legend(fontsize="small")
    drawing.savefig(path, dpi=90)
    return path
