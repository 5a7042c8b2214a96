"""Compare a model with measurements: RMS errors per run and pooled, and drawings of each run.

Each run is replayed from its measured initial state (no per-run fitting). The drawing of a run
(:func:`plot_run`) shows the measured and simulated heading, rate of turn, speed and rudder against time,
the tracks (measured, simulated freely, and replayed with the measured heading) and the residuals;
after a cross-validation, shaded around the simulated heading, rate of turn and track, the
jackknife band of the fold models' replays (:mod:`.bands`): how sure the model is where it predicts.
Drawn with matplotlib's object interface on the Agg canvas: no display needed, and the user's
pyplot backend is left alone.
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from matplotlib.axes import Axes
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure as Drawing

from ship_env.workbench.fitting.errors import RunErrors, pooled, run_errors
from ship_env.workbench.fitting.parallel import run_each
from ship_env.workbench.fitting.replay import (
    EAST,
    HEADING,
    NORTH,
    RATE,
    SPEED,
    ReplayModel,
    Simulated,
    simulate,
)
from ship_env.workbench.fitting.runs import screen_runs
from ship_env.workbench.judging.bands import BAND_LABEL, Band, jackknife_bands
from ship_env.workbench.judging.validation import CrossValidation
from ship_env.workbench.logs.logs import Log
from ship_env.workbench.outputs import save_drawing

MEASURED_STYLE: dict[str, Any] = {"color": "black", "linewidth": 1.0, "label": "measured"}
SIMULATED_STYLE: dict[str, Any] = {"color": "tab:red", "linewidth": 1.0, "label": "simulated"}
BAND_STYLE: dict[str, Any] = {"color": "tab:red", "alpha": 0.2, "linewidth": 0.0}
TRACK_STYLE: dict[str, Any] = {
    "color": "tab:blue",
    "linewidth": 1.0,
    "linestyle": "--",
    "label": "track with measured heading",
}


@dataclass(frozen=True)
class Comparison:
    """A model replayed on runs: the simulated series and the errors per run and pooled.

    Attributes:
        bands: per run, the jackknife band of its replay (empty: none, as for a model not cross-validated).
        roles: per run, what its replay is where runs differ (e.g. a validation run; empty: all alike).
    """

    setup: ReplayModel
    logs: tuple[Log, ...]
    simulated: tuple[Simulated, ...]
    errors: tuple[RunErrors, ...]
    bands: tuple[Band, ...] = ()
    roles: tuple[str, ...] = ()

    @property
    def pooled(self) -> RunErrors:
        return pooled(self.errors)


def compare(setup: ReplayModel, logs: Sequence[Log], window: float | None = None) -> Comparison:
    """Replay every log with the model and measure the errors; a run wholly outside the model's envelope is
    left out with a :class:`~.logs.LogWarning` (:func:`~.runs.screen_runs`)."""
    logs, _, _ = screen_runs(setup.model, logs)
    simulated = simulate(setup, logs, window)
    return Comparison(
        setup,
        tuple(logs),
        tuple(simulated),
        tuple(run_errors(log, sim) for log, sim in zip(logs, simulated, strict=True)),
    )


def held_out_comparison(validation: CrossValidation, logs: Sequence[Log]) -> Comparison:
    """Each run replayed by the fit that left it out (what the held-out errors measure), then each validation
    run replayed by the fit to all runs; each with its jackknife band (every fold's model, one batch)."""
    every = (*logs, *validation.validation_logs)
    return Comparison(
        validation.fit.setup,
        every,
        (*validation.replays, *validation.validation_replays),
        (*validation.held_out, *validation.validation),
        tuple(jackknife_bands(validation.folds, every, validation.window)),
        ("held out: replayed by the fit that left it out",) * len(logs)
        + ("validation run: replayed by the fit to all runs",) * len(validation.validation),
    )


def file_name(run: str) -> str:
    """A file-system-safe name for a run."""
    return re.sub(r"[^A-Za-z0-9_.-]+", "_", run)


def _band_label(band: Band) -> str:
    return f"{BAND_LABEL} (+-1 s.d., {band.replays} fold fits)"


def _track_band(axes: Axes, band: Band) -> None:
    """Shade the band around the fold replays' mean track: +-its position s.d. across the track's direction."""
    north, east = band.centre[:, NORTH], band.centre[:, EAST]
    heading = np.arctan2(np.gradient(east), np.gradient(north))
    across_north, across_east = -np.sin(heading) * band.radius, np.cos(heading) * band.radius
    outline_east = np.concatenate([east + across_east, (east - across_east)[::-1]])
    outline_north = np.concatenate([north + across_north, (north - across_north)[::-1]])
    axes.fill(outline_east, outline_north, label=_band_label(band), **BAND_STYLE)


def plot_run(
    log: Log, simulated: Simulated, errors: RunErrors, title: str, path: Path, band: Band | None = None
) -> Path:
    """Draw one run, measured against simulated (with its jackknife ``band`` where given), into a PNG file."""
    drawing = Drawing(figsize=(13, 10.5))
    FigureCanvasAgg(drawing)
    grid = drawing.add_gridspec(4, 2, width_ratios=(1.6, 1.0))
    time = log.time - log.time[0]
    band = band if band is not None and band.replays > 1 else None  # one replay has no spread to show
    heading_axes = drawing.add_subplot(grid[0, 0])
    if band is not None:
        low, high = np.degrees(band.low(HEADING)), np.degrees(band.high(HEADING))
        heading_axes.fill_between(time, low, high, label=_band_label(band), **BAND_STYLE)
    heading_axes.plot(time, np.degrees(log.heading), **MEASURED_STYLE)
    heading_axes.plot(time, np.degrees(simulated.heading), **SIMULATED_STYLE)
    heading_axes.set_ylabel("heading [deg]")
    heading_axes.legend(loc="best", fontsize=8)
    rate_axes = drawing.add_subplot(grid[1, 0], sharex=heading_axes)
    if band is not None:
        rate_axes.fill_between(time, np.degrees(band.low(RATE)), np.degrees(band.high(RATE)), **BAND_STYLE)
    if log.rate_of_turn is not None:
        rate_axes.plot(time, np.degrees(log.rate_of_turn), **MEASURED_STYLE)
    rate_axes.plot(time, np.degrees(simulated.rate_of_turn), **SIMULATED_STYLE)
    rate_axes.set_ylabel("rate of turn [deg/s]")
    rudder_axes = rate_axes.twinx()
    rudder_axes.plot(time, np.degrees(log.rudder), color="tab:green", linewidth=0.6, alpha=0.7)
    rudder_axes.set_ylabel(f"{log.rudder_kind} rudder [deg]", color="tab:green")
    speed_axes = drawing.add_subplot(grid[2, 0], sharex=heading_axes)
    if band is not None:
        speed_axes.fill_between(time, band.low(SPEED), band.high(SPEED), **BAND_STYLE)
    if log.speed is not None:
        speed_axes.plot(time, log.speed, **MEASURED_STYLE)
    speed_axes.plot(time, simulated.speed, **SIMULATED_STYLE)
    speed_axes.set_ylabel("speed u [m/s]" if log.speed is not None else "speed u [m/s] (not measured)")
    residual_axes = drawing.add_subplot(grid[3, 0], sharex=heading_axes)
    residual_axes.plot(
        time, np.degrees(simulated.heading - log.heading), color="tab:red", linewidth=0.8, label="heading [deg]"
    )
    if log.has_position:
        residual_axes.plot(
            time,
            np.hypot(simulated.track_north - log.north, simulated.track_east - log.east),
            color="tab:blue",
            linewidth=0.8,
            label="track distance [m]",
        )
    residual_axes.axhline(0.0, color="grey", linewidth=0.5)
    residual_axes.set_xlabel("time [s]")
    residual_axes.set_ylabel("simulated - measured")
    residual_axes.legend(loc="best", fontsize=8)
    track_axes = drawing.add_subplot(grid[:, 1])
    if log.north is not None and log.east is not None:
        if band is not None:
            _track_band(track_axes, band)
        track_axes.plot(log.east, log.north, **MEASURED_STYLE)
        track_axes.plot(simulated.east, simulated.north, **SIMULATED_STYLE)
        track_axes.plot(simulated.track_east, simulated.track_north, **TRACK_STYLE)
        track_axes.plot(log.east[0], log.north[0], "ko", markersize=4)
        track_axes.set_aspect("equal", adjustable="datalim")
        track_axes.legend(loc="best", fontsize=8)
    else:
        track_axes.text(0.5, 0.5, "no position in this log", ha="center", va="center", transform=track_axes.transAxes)
    track_axes.set_xlabel("east [m]")
    track_axes.set_ylabel("north [m]")
    shown = errors.in_display_units()
    drawing.suptitle(
        f"{title}\n{log.name}: RMS heading {shown['heading']:.2f} deg, rate {shown['rate_of_turn']:.3f} deg/s, "
        f"speed {shown['speed']:.3g} m/s, position {shown['position']:.2f} m, track {shown['track']:.2f} m",
        fontsize=10,
    )
    return save_drawing(drawing, path, dpi=90)


def run_drawings(
    comparison: Comparison, folder: Path, title: str
) -> list[tuple[Log, Simulated, RunErrors, str, Path, Band | None]]:
    """The arguments of :func:`plot_run` for each run: one PNG per run in ``folder``, named after the run (the
    title followed by the run's role where runs differ)."""
    count = len(comparison.logs)
    bands: Sequence[Band | None] = comparison.bands or (None,) * count
    roles = comparison.roles or ("",) * count
    return [
        (log, simulated, errors, f"{title}; {role}" if role else title, folder / f"{file_name(log.name)}.png", band)
        for log, simulated, errors, band, role in zip(
            comparison.logs, comparison.simulated, comparison.errors, bands, roles, strict=True
        )
    ]


def plot_comparison(comparison: Comparison, folder: Path, title: str, workers: int = 1) -> list[Path]:
    """One PNG per run in ``folder`` (named after the runs), drawn on ``workers`` processes."""
    return run_each(plot_run, run_drawings(comparison, folder, title), workers)
