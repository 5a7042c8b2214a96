"""Drawings of a manoeuvre: track, heading, rate of turn, speed and rudder, written as a PNG.

Drawn with matplotlib's object interface on the Agg canvas, so it needs no display and leaves the
user's pyplot backend alone.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from matplotlib.axes import Axes
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure as Drawing

from ship_env.manoeuvres.results import KNOT, ManoeuvreResult
from ship_env.manoeuvres.spiral import SpiralTest

#: Runs of a batch beyond which the legend is left out (the spiral's many ships).
MAX_LEGEND_RUNS = 4


def _footer(result: ManoeuvreResult, width: int = 180) -> str:
    """The result's figures, separated by bars, in lines of at most ``width`` characters."""
    lines = [""]
    for figure in result.figures():
        part = f"{figure.label} {figure.text}{' ' + figure.unit if figure.unit else ''}"
        joined = f"{lines[-1]}  |  {part}" if lines[-1] else part
        if len(joined) > width and lines[-1]:
            lines.append(part)
        else:
            lines[-1] = joined
    return "\n".join(lines)


def _draw_spiral(axes: Axes, spiral: SpiralTest) -> None:
    """The spiral characteristic: steady rate of turn against rudder."""
    table = spiral.table
    held, hard_over = table[~table["hard_over"]], table[table["hard_over"]]
    axes.plot(np.degrees(held["rudder"]), np.degrees(held["rate_of_turn"]), "o-", label="held rate (autopilot)")
    axes.plot(np.degrees(hard_over["rudder"]), np.degrees(hard_over["rate_of_turn"]), "s", label="rudder hard over")
    axes.axhline(0.0, color="0.7", linewidth=0.8)
    axes.axvline(0.0, color="0.7", linewidth=0.8)
    axes.set(title="spiral characteristic", xlabel="rudder [deg]", ylabel="steady rate of turn [deg/s]")
    axes.legend(fontsize="small")
    axes.grid(True, alpha=0.3)


def plot_manoeuvre(result: ManoeuvreResult, path: str | Path) -> Path:
    """Write a PNG of ``result``: track (north up, equal axes) and time histories; returns the path."""
    path = Path(path)
    spiral = isinstance(result, SpiralTest)
    drawing = Drawing(figsize=(20 if spiral else 16, 9), layout="constrained")
    FigureCanvasAgg(drawing)
    grid = drawing.add_gridspec(2, 4 if spiral else 3)
    track = drawing.add_subplot(grid[:, 0])
    heading, rate_of_turn = drawing.add_subplot(grid[0, 1]), drawing.add_subplot(grid[0, 2])
    speed, rudder = drawing.add_subplot(grid[1, 1], sharex=heading), drawing.add_subplot(grid[1, 2], sharex=heading)
    rate_of_turn.sharex(heading)

    runs = list(dict.fromkeys(result.time_series["run"]))
    for run in runs:
        series = result.time_series[result.time_series["run"] == run]
        time = series["time"]
        (line,) = track.plot(series["east"], series["north"], label=run)
        colour = line.get_color()
        track.plot(series["east"].iloc[0], series["north"].iloc[0], "o", color=colour)
        heading.plot(time, np.degrees(series["heading"]), color=colour, label=run)
        rate_of_turn.plot(time, np.degrees(series["rate_of_turn"]), color=colour)
        speed.plot(time, series["speed"] / KNOT, color=colour)
        rudder.plot(time, np.degrees(series["rudder"]), color=colour)
        rudder.plot(time, np.degrees(series["ordered_rudder"]), color=colour, linestyle="--", linewidth=0.8)

    track.set(title="track", xlabel="east [m]", ylabel="north [m]", aspect="equal", adjustable="datalim")
    heading.set(title="heading", ylabel="heading [deg]")
    rate_of_turn.set(title="rate of turn", ylabel="rate of turn [deg/s]")
    speed.set(title="forward speed", xlabel="time [s]", ylabel="speed [kn]")
    rudder.set(title="rudder (dashed: ordered)", xlabel="time [s]", ylabel="rudder [deg]")
    for axes in (track, heading, rate_of_turn, speed, rudder):
        axes.grid(True, alpha=0.3)
    if len(runs) <= MAX_LEGEND_RUNS:
        heading.legend(fontsize="small")
    if isinstance(result, SpiralTest):
        _draw_spiral(drawing.add_subplot(grid[:, 3]), result)

    speed_kn = result.approach_speed / KNOT
    drawing.suptitle(f"{result.title.capitalize()}: {result.ship}, L = {result.length:.1f} m, V = {speed_kn:.1f} kn")
    drawing.text(0.5, 0.0, _footer(result), ha="center", va="top", fontsize="small")
    path.parent.mkdir(parents=True, exist_ok=True)
    drawing.savefig(path, dpi=100, bbox_inches="tight")
    return path
