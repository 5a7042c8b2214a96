"""The leaderboard's drawings, written as PNGs: the scores, and every controller on one scenario.

Drawn with matplotlib's object interface on the Agg canvas (no display, the user's pyplot backend
left alone), as :mod:`ship_env.manoeuvres.plotting` does.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure as Drawing

from ship_env.envs.task import ShipTask
from ship_env.leaderboard.tables import Table
from ship_env.model import state as S

#: Bar colours by the entrant's kind.
KIND_COLOURS = {"classic": "tab:blue", "learned": "tab:orange", "human": "0.6"}


def plot_scores(tables: Sequence[Table], path: Path) -> Path:
    """Bars of each suite's ranking metric, one panel per suite (conditions in rows); returns ``path``."""
    tasks = list(dict.fromkeys(table.suite.task for table in tables))
    conditions = list(dict.fromkeys(table.suite.condition.name for table in tables))
    drawing = Drawing(figsize=(4.8 * len(tasks), 2.8 * len(conditions)), layout="constrained")
    FigureCanvasAgg(drawing)
    panels = drawing.subplots(len(conditions), len(tasks), squeeze=False)
    for row in panels:
        for axes in row:
            axes.set_axis_off()
    for table in tables:
        axes = panels[conditions.index(table.suite.condition.name)][tasks.index(table.suite.task)]
        axes.set_axis_on()
        metric = table.suite.metrics[0]
        standings = table.standings[::-1]  # the best on top
        values = [standing.values[metric.key] for standing in standings]
        axes.barh(
            [standing.entrant for standing in standings],
            values,
            color=[KIND_COLOURS[standing.kind] for standing in standings],
        )
        finite = [value for value in values if math.isfinite(value)]
        if finite and max(finite) < 1.5 * min(finite):  # a few per cent apart: start near the smallest bar
            axes.set_xlim(0.9 * min(finite), 1.02 * max(finite))
        axes.set_title(table.suite.name, fontsize="medium")
        axes.set_xlabel(metric.heading, fontsize="small")
        axes.tick_params(labelsize="small")
        axes.grid(True, axis="x", alpha=0.3)
    drawing.savefig(path, dpi=90)
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


def plot_tracks(runs: Mapping[str, np.ndarray], task: ShipTask, track: str, title: str, path: Path) -> Path:
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
