"""Free-running validation: each measured manoeuvre sailed free by the model, figure against figure.

A replay scores a model sample by sample; a naval architect judges it by the figures of its
manoeuvres (MSC.137(76)): advance, tactical diameter, the steady rate of turn and speed, the zig-zag
overshoots. Here each measured run is read as the manoeuvre it is, its figures are read off the log,
and the model sails the same manoeuvre free:

Each sails from the measured state at its first execute (heading, rate of turn, rudder, speed, propeller
rate, wind, the fit's current):

- a **turning run** -- the rudder held to one side (at least half its angle) while the heading turns
  through at least half a circle -- with the turn's rudder ordered at the execute and held to the
  measured turn's end;
- a **zig-zag run** -- the rudder reversed at least twice between the same angles a, each time the
  heading has passed b off the heading at the first execute -- closed loop on the heading: a helmsman
  puts the rudder over to a and reverses it whenever the heading passes b, with a and b read from the run.

Measured and predicted figures are read by the same code (:func:`manoeuvre_figures`), all towards the
side of the turn, from the first execute:

- turning: **advance** and **transfer** at 90 deg of heading change, **tactical diameter** at 180 deg
  (along and across the heading at the execute; MSC.137(76) 4.2.3-4.2.4); over the steady part -- the
  measured run's last full circle, or its last half circle where it turned less than one and a half,
  and the same seconds of the prediction, which sails the same rudder -- the **steady rate of turn** r,
  the **steady speed** u (where the log measures it) and the **steady radius** U/r with U the speed
  over the ground; the **speed loss** 1 - u / u_e against the speed at the execute u_e, where the ship
  approached at least as fast as it turns (a run that starts its turn from rest has no approach speed);
- zig-zag: the **first** and **second overshoot** angles, the largest heading deviation beyond b
  between the second and third and after the third execute (4.2.7-4.2.8); the **initial turning time**
  from the first execute to the heading change b.

A run of neither kind has no figures; a figure its run does not reach is NaN ("n/a").
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from functools import partial
from typing import TYPE_CHECKING

import numpy as np

from ship_env.manoeuvres.results import Figure, metre_digits
from ship_env.manoeuvres.series import first_crossing, value_at, velocity_over_ground
from ship_env.manoeuvres.settings import TrialSettings
from ship_env.manoeuvres.trial import run_trial
from ship_env.manoeuvres.uncertainty import figure_errors
from ship_env.manoeuvres.zigzag import ZigZagHelmsman
from ship_env.model import Conditions
from ship_env.model.external import NATIVE
from ship_env.text_table import Table
from ship_env.workbench.fitting.errors import ErrorScales, RunErrors, pooled
from ship_env.workbench.fitting.replay import ReplayModel, service_speed
from ship_env.workbench.fitting.terms import sailing_model
from ship_env.workbench.judging.validation import CrossValidation
from ship_env.workbench.logs.logs import Log

if TYPE_CHECKING:
    from ship_env.model.external import DynamicsSource
    from ship_env.workbench.fitting.inverse_dynamics import Identification

#: The rudder is "over" where it is at least this fraction of the manoeuvre's angle.
OVER = 0.5
#: The rudder is "at" the manoeuvre's angle from this fraction of it on (a steering machine's last degrees are slow).
AT_ANGLE = 0.9
#: Quantile of |rudder| over a run taken as the manoeuvre's rudder angle (robust to spikes).
RUDDER_QUANTILE = 0.95
#: The largest ratio of a zig-zag's heading deviations at its reversals (the same b, as a helmsman reads it).
ZIGZAG_SPREAD = 2.0
#: A zig-zag is sailed until this many executes, or twice the measured one's duration.
ZIGZAG_EXECUTES = 4


@dataclass(frozen=True)
class Series:
    """One run's motion, measured or predicted (SI units, rad): what its figures are read from.

    ``speed`` is the forward speed through the water (None where not measured or predicted).
    """

    time: np.ndarray
    north: np.ndarray
    east: np.ndarray
    heading: np.ndarray
    rate_of_turn: np.ndarray
    rudder: np.ndarray
    speed: np.ndarray | None = None

    @classmethod
    def of_log(cls, log: Log) -> Series | None:
        """The measured series, or None for a log without a track (north and east)."""
        if log.north is None or log.east is None:
            return None
        return cls(log.time, log.north, log.east, log.heading, log.rate_of_turn_or_smoothed, log.rudder, log.speed)


@dataclass(frozen=True)
class Manoeuvre:
    """What a run is, read from its rudder and heading.

    Attributes:
        kind: ``"turning"``, ``"zig-zag"`` or ``"other"``.
        side: +1 where the first (or only) rudder is to starboard, -1 to port.
        rudder_angle: a, the manoeuvre's rudder angle, rad, positive.
        heading_change: b, the zig-zag's switching heading deviation, rad (NaN for a turn).
        executes: the times the rudder was put over (the first execute, then each reversal), s.
        end: the time the turn's rudder was taken off (the run's end for a zig-zag), s.
        steady: the turn's steady part, (start, end) s; NaNs where it turned less than a full circle.
    """

    kind: str
    side: float
    rudder_angle: float
    heading_change: float
    executes: tuple[float, ...]
    end: float
    steady: tuple[float, float] = (math.nan, math.nan)


def _stretches(sides: np.ndarray) -> list[tuple[int, int, float]]:
    """(first, last + 1, side) of each run of consecutive samples on one side (+1 or -1; 0 is neither)."""
    changes = np.flatnonzero(np.diff(sides)) + 1
    bounds = np.concatenate(([0], changes, [len(sides)]))
    return [(int(a), int(b), float(sides[a])) for a, b in zip(bounds[:-1], bounds[1:], strict=True) if sides[a] != 0.0]


def _order_given(rudder: np.ndarray, over: int, side: float) -> int:
    """The sample at which the rudder, over to ``side`` at sample ``over``, started to move there: the
    order's time, as a log of the actual rudder shows it (the steering machine moves it at its rate)."""
    while over > 0 and side * rudder[over - 1] < side * rudder[over]:
        over -= 1
    return over


def read_manoeuvre(series: Series) -> Manoeuvre:
    """Read what manoeuvre a series sails (see the module docstring)."""
    rudder, heading, time = series.rudder, series.heading, series.time
    angle = float(np.quantile(np.abs(rudder), RUDDER_QUANTILE))
    other = Manoeuvre("other", 1.0, angle, math.nan, (), float(time[-1]))
    if angle <= 0.0:
        return other
    sides = np.sign(rudder) * (np.abs(rudder) >= OVER * angle)
    # Neighbouring stretches on the same side (the rudder dipping under half its angle) are one.
    merged: list[tuple[int, int, float]] = []
    for first, last, side in _stretches(sides):
        if merged and merged[-1][2] == side:
            merged[-1] = (merged[-1][0], last, side)
        else:
            merged.append((first, last, side))
    if not merged:
        return other
    turned = [abs(heading[last - 1] - heading[first]) for first, last, _ in merged]
    longest = int(np.argmax(turned))
    if turned[longest] >= math.pi:
        over, last, side = merged[longest]
        first = _order_given(rudder, over, side)
        change = side * (heading[first:last] - heading[first])
        circles = change[-1] / (2.0 * math.pi)
        span = 2.0 * math.pi if circles >= 1.5 else math.pi if circles >= 1.0 else math.nan
        steady = (math.nan, math.nan)
        if math.isfinite(span):
            start = first + int(np.searchsorted(change, change[-1] - span))
            steady = (float(time[start]), float(time[last - 1]))
        rudder_angle = float(np.median(np.abs(rudder[first:last])))
        return Manoeuvre("turning", side, rudder_angle, math.nan, (float(time[first]),), float(time[last - 1]), steady)
    # A zig-zag: from the first execute on, every reversal at a heading deviation +-b of one size (within
    # a factor ZIGZAG_SPREAD), alternating, at least twice; the rudder's corrections before it are no execute.
    for j in range(len(merged) - 2):
        start, stop, side = merged[j]
        magnitude = np.abs(rudder[start:])
        zigzag_angle = float(np.median(magnitude[magnitude >= OVER * angle]))
        # The first execute: the order that put the rudder at its angle (the corrections before it are none).
        at_angle = start + int(np.argmax(np.abs(rudder[start:stop]) >= AT_ANGLE * zigzag_angle))
        first = _order_given(rudder, at_angle, side)
        reversals = [_order_given(rudder, over, reversed_to) for over, _, reversed_to in merged[j + 1 :]]
        switched = [(-1.0) ** k * side * (heading[at] - heading[first]) for k, at in enumerate(reversals)]
        if min(switched) > 0.0 and max(switched) <= ZIGZAG_SPREAD * min(switched):
            return Manoeuvre(
                "zig-zag",
                side,
                zigzag_angle,
                switched[0],  # b: where the helmsman first reversed the rudder (MSC.137(76) 4.2.5)
                (float(time[first]), *(float(time[at]) for at in reversals)),
                float(time[-1]),
            )
    return other


def manoeuvre_figures(series: Series, manoeuvre: Manoeuvre, length: float) -> tuple[Figure, ...]:
    """The figures of ``manoeuvre`` read off ``series`` (measured or predicted; module docstring)."""
    time = series.time
    if manoeuvre.kind == "turning":
        return _turning_figures(series, manoeuvre, length)
    if manoeuvre.kind == "zig-zag":
        executes = manoeuvre.executes
        start = executes[0]
        deviation = manoeuvre.side * (series.heading - np.interp(start, time, series.heading))
        b = manoeuvre.heading_change

        def overshoot(k: int) -> float:
            """The largest deviation beyond b, to the side of swing k, between execute k and k + 1."""
            if len(executes) <= k:
                return math.nan
            until = executes[k + 1] if len(executes) > k + 1 else time[-1]
            inside = (time >= executes[k]) & (time <= until)
            return float(np.max((-1.0) ** (k - 1) * deviation[inside])) - b

        return (
            Figure("rudder_angle", "rudder angle a", math.degrees(manoeuvre.rudder_angle), "deg", 1),
            Figure("heading_change", "heading change b", math.degrees(b), "deg", 1),
            Figure("first_overshoot", "first overshoot", math.degrees(overshoot(1)), "deg", 1),
            Figure("second_overshoot", "second overshoot", math.degrees(overshoot(2)), "deg", 1),
            Figure(
                "initial_turning_time",
                "initial turning time",
                first_crossing(time, deviation, b, start) - start,
                "s",
                1,
            ),
        )
    return ()


def _turning_figures(series: Series, manoeuvre: Manoeuvre, length: float) -> tuple[Figure, ...]:
    time, side, start = series.time, manoeuvre.side, manoeuvre.executes[0]
    turn = (time >= start) & (time <= manoeuvre.end)
    heading0 = float(np.interp(start, time, series.heading))
    north = series.north - np.interp(start, time, series.north)
    east = series.east - np.interp(start, time, series.east)
    along = north * math.cos(heading0) + east * math.sin(heading0)
    across = side * (-north * math.sin(heading0) + east * math.cos(heading0))
    change = np.where(turn, side * (series.heading - heading0), -math.inf)
    at_90 = first_crossing(time, change, 0.5 * math.pi, start)
    at_180 = first_crossing(time, change, math.pi, start)
    steady = (time >= manoeuvre.steady[0]) & (time <= manoeuvre.steady[1])
    rate = speed = ground_speed = math.nan
    if np.any(steady):
        north_rate, east_rate = velocity_over_ground(time, series.north, series.east)
        rate = float(np.mean(side * series.rate_of_turn[steady]))
        ground_speed = float(np.mean(np.hypot(north_rate, east_rate)[steady]))
        if series.speed is not None:
            speed = float(np.mean(series.speed[steady]))
    approach = math.nan if series.speed is None else float(np.interp(start, time, series.speed))
    speed_loss = 1.0 - speed / approach if approach >= speed else math.nan  # NaN compares False
    digits = metre_digits(length)
    return (
        Figure("rudder_angle", "rudder angle", math.degrees(manoeuvre.rudder_angle), "deg", 1),
        Figure("advance_lengths", "advance", value_at(time, along, at_90) / length, "L", 2),
        Figure("transfer_lengths", "transfer", value_at(time, across, at_90) / length, "L", 2),
        Figure("tactical_diameter_lengths", "tactical diameter", value_at(time, across, at_180) / length, "L", 2),
        Figure("steady_rate_of_turn", "steady rate of turn", math.degrees(rate), "deg/s", 3),
        Figure("steady_speed", "steady speed", speed, "m/s", max(2, digits)),
        Figure("steady_radius", "steady radius U/r", ground_speed / rate, "m", digits),
        Figure("speed_loss", "speed loss in steady turn", 100.0 * speed_loss, "%", 1),
    )


def sail_free(setup: ReplayModel, log: Log, manoeuvre: Manoeuvre, dynamics: DynamicsSource | None = None) -> Series:
    """The model's manoeuvre, sailed free (:func:`~ship_env.manoeuvres.trial.run_trial`) from the measured state
    at the first execute: the heading, rate of turn, rudder and speed there (the run's service speed U0 as the
    replay takes it, :func:`~.replay.service_speed`, the speed loss from there by the model's own equation),
    the propeller rate and wind there, the fit's current; the starting preset's steering machine where the log
    records the actual rudder (:func:`~.terms.sailing_model`, as the fitted preset sails); a turn holds its rudder
    ordered to the measured turn's end,
    a zig-zag reverses it closed loop on the heading (:class:`~ship_env.manoeuvres.zigzag.ZigZagHelmsman`)
    until its fifth execute or twice the measured run's time.

    ``dynamics``, where given, sails the ship instead of ``setup``'s model (an external model, as
    :class:`~ship_env.manoeuvres.settings.TrialSettings` takes it: a fitted MMG model of ``ship-env fit-mmg``),
    ``setup`` then giving the preset's particulars and rudder limit; without it ``setup``'s own effects sail, whatever
    model the preset's ``dynamics:`` block names. Such a model starts at the speed it is given
    as its service speed (the measured speed there, where the log has one); it sails in the log's wind, so a log
    without wind channels sails a model that has no wind forces."""
    start = manoeuvre.executes[0]

    def at(values: np.ndarray | None, default: float = 0.0) -> float:
        return default if values is None else float(np.interp(start, log.time, values))

    current_north, current_east = setup.current
    conditions = Conditions(
        propeller_rate=None if log.propeller_rate is None else at(log.propeller_rate),  # None: the ship's own
        wind_speed=max(at(log.wind_speed), 0.0),
        wind_direction=at(log.wind_direction),
        current_speed=math.hypot(current_north, current_east),
        current_direction=math.atan2(current_east, current_north),
    )
    measured_speed = at(log.speed) if log.speed is not None and at(log.speed) > 0.0 else None
    speed = service_speed(log, setup.model)
    if dynamics is not None and measured_speed is not None:  # an external model starts at its "service" speed
        speed, measured_speed = measured_speed, None
    settings = TrialSettings(
        speed=speed, dt=float(np.median(np.diff(log.time))), dynamics=NATIVE if dynamics is None else dynamics
    )
    heading0 = at(log.heading)
    order = manoeuvre.side * manoeuvre.rudder_angle
    helmsman = ZigZagHelmsman(order, manoeuvre.heading_change, heading0)
    zigzag = manoeuvre.kind == "zig-zag"
    frame = run_trial(
        sailing_model(setup.model, [log]),  # with the preset's steering machine where the log holds the actual rudder
        settings,
        helmsman if zigzag else lambda simulator: order,
        [log.name],
        2.0 * (log.time[-1] - start) if zigzag else manoeuvre.end - start,
        (lambda simulator: helmsman.executes > ZIGZAG_EXECUTES) if zigzag else None,
        initial_rate_of_turn=np.array([at(log.rate_of_turn_or_smoothed)]),
        initial_rudder=at(log.rudder),
        conditions=conditions,
        initial_heading=heading0,
        initial_speed=measured_speed,  # None: at the settings' speed
    )
    columns = ("north", "east", "heading", "rate_of_turn", "rudder", "speed")
    return Series(frame["time"].to_numpy() + start, *(frame[name].to_numpy() for name in columns))


@dataclass(frozen=True)
class RunFigures:
    """One run's manoeuvre, its measured figures and the model's (same names, same order).

    Where the model cannot sail the manoeuvre (it leaves its validity on the way: a speed loss past the ship's
    speed, a rate of turn that runs away), ``cannot_sail`` says why, its figures are NaN ("n/a") and it has no
    predicted series. ``spread``, where given, holds each predicted figure's jackknife standard error over the
    fit's folds (:func:`held_out_free_running`; NaN where a fold does not reach the figure).
    """

    run: str
    manoeuvre: Manoeuvre
    measured: tuple[Figure, ...]
    predicted: tuple[Figure, ...]
    predicted_series: Series | None
    cannot_sail: str = ""
    spread: tuple[float, ...] = ()


def compare_free_running(
    setup: ReplayModel, logs: Sequence[Log], dynamics: DynamicsSource | None = None
) -> tuple[RunFigures, ...]:
    """Each run's manoeuvre figures, measured and sailed free by ``setup`` (or by ``dynamics``, as
    :func:`sail_free` takes them; runs of neither kind left out)."""
    results = []
    for log in logs:
        measured_series = Series.of_log(log)
        if measured_series is None:
            continue
        manoeuvre = read_manoeuvre(measured_series)
        if manoeuvre.kind == "other":
            continue
        measured = manoeuvre_figures(measured_series, manoeuvre, setup.model.length)
        try:
            predicted_series = sail_free(setup, log, manoeuvre, dynamics)
        except FloatingPointError as error:  # the model left its validity: no figures, and why
            unreached = tuple(replace(figure, value=math.nan) for figure in measured)
            results.append(RunFigures(log.name, manoeuvre, measured, unreached, None, str(error)))
            continue
        predicted_manoeuvre = manoeuvre  # a turn: the same rudder over the same seconds
        if manoeuvre.kind == "zig-zag":  # its own executes, where its heading passed b
            predicted_manoeuvre = read_manoeuvre(predicted_series)
            if predicted_manoeuvre.kind != "zig-zag":  # the model never reached b: no reversal
                predicted_manoeuvre = replace(manoeuvre, executes=manoeuvre.executes[:1])
        results.append(
            RunFigures(
                log.name,
                manoeuvre,
                measured,
                manoeuvre_figures(predicted_series, predicted_manoeuvre, setup.model.length),
                predicted_series,
            )
        )
    return tuple(results)


def free_running_table(results: Sequence[RunFigures]) -> Table:
    """Run, manoeuvre, figure, measured, predicted (+- its jackknife standard error, where the result has one) and
    their difference, one row per figure."""
    rows = []
    for result in results:
        spread = result.spread or (math.nan,) * len(result.predicted)
        for measured, predicted, error in zip(result.measured, result.predicted, spread, strict=True):
            difference = float(predicted.value) - float(measured.value)
            rows.append(
                (
                    result.run,
                    result.manoeuvre.kind,
                    f"{measured.label}, {measured.unit}",
                    measured.text,
                    predicted.text_with_error(error),
                    Figure(measured.key, "", difference, measured.unit, measured.digits).text,
                )
            )
    return Table(("run", "manoeuvre", "figure", "measured", "predicted", "predicted - measured"), tuple(rows), words=3)


#: A fitted model's free sailing of some runs: :func:`compare_free_running` bound to the model.
Sail = Callable[[Sequence[Log]], tuple[RunFigures, ...]]


def held_out_free_running(
    validation: CrossValidation, logs: Sequence[Log], validation_logs: Sequence[Log] | None = None
) -> tuple[RunFigures, ...]:
    """Every run of a cross-validated fit sailed free by a fit that did not see it (:func:`held_out_sailing`), and
    ``validation_logs`` (None: the validation's own) by the fit to all runs."""
    return held_out_sailing(
        partial(compare_free_running, validation.fit.setup),
        [(fold.left_out, partial(compare_free_running, fold.setup)) for fold in validation.folds],
        logs,
        validation.validation_logs if validation_logs is None else validation_logs,
    )


def held_out_sailing(
    fit: Sail, folds: Sequence[tuple[Sequence[str], Sail]], logs: Sequence[Log], validation_logs: Sequence[Log]
) -> tuple[RunFigures, ...]:
    """Every run sailed free by a fit that did not see it: a fitted run (``logs``) by the fold that left it out
    (``folds``: the runs each left out and its sailing; ``fit``, the fit to all runs, where none did), a validation
    run by ``fit``, each of its figures with its jackknife standard error over the folds (every fold sails it too:
    how far the fitted runs would move the prediction)."""
    fold_of = {name: sail for left_out, sail in folds for name in left_out}
    fitted = [fold_of.get(log.name, fit)([log]) for log in logs]
    validated = fit(validation_logs)
    if len(folds) >= 2:
        by_fold = [sail(validation_logs) for _, sail in folds]
        validated = tuple(
            replace(result, spread=_spread(result, [results[i] for results in by_fold]))
            for i, result in enumerate(validated)
        )
    return (*(figures for run in fitted for figures in run), *validated)


def held_out_mmg_sailing(
    setup: ReplayModel, identified: Identification, logs: Sequence[Log], validation_logs: Sequence[Log]
) -> tuple[RunFigures, ...]:
    """Every run sailed free by a fitted MMG model (``ship-env fit-mmg``'s :class:`~.inverse_dynamics.Identification`)
    that did not see it (:func:`held_out_sailing`): a fitted run by the fold that left it out (the fit to all runs
    without a jackknife), a validation run by the fit to all runs; in calm water, the logs' wind left out (the form
    has no wind forces); ``setup`` gives the particulars and rudder limit."""
    from ship_env.model.mmg_fitted import MmgFitted, MmgRecord

    def sail(record: MmgRecord) -> Sail:
        return partial(compare_free_running, setup, dynamics=partial(MmgFitted, record))

    def calm(runs: Sequence[Log]) -> list[Log]:
        return [replace(log, wind_speed=None, wind_direction=None) for log in runs]

    record = identified.record
    folds = [((run,), sail(fold)) for run, fold in zip(identified.runs, record.fold_records(), strict=True)]
    return held_out_sailing(sail(record), folds, calm(logs) if folds else [], calm(validation_logs))


def _spread(result: RunFigures, by_fold: Sequence[RunFigures]) -> tuple[float, ...]:
    """Per figure of one run's ``result``, the jackknife standard error of the folds' predictions of it."""
    errors = figure_errors([fold.predicted for fold in by_fold])
    return tuple(errors.get(figure.key, math.nan) for figure in result.predicted)


#: The figures judged, with the bound beyond which prediction and measurement disagree (relative to the measured
#: figure, or in its unit where ``relative`` is False) and the library's effects that shape each (beyond the
#: yaw equation's gain and time constant, which every model fits): MSC.137(76)'s figures, the bounds a naval
#: architect asks of a prediction (advance and tactical diameter 5 %, steady rate and speed loss 10 %, the
#: first overshoot 2 deg).
JUDGED_FIGURES: dict[str, tuple[float, bool, tuple[str, ...]]] = {
    "advance_lengths": (0.05, True, ("steering_machine", "speed_loss", "hull_crossflow", "norrbin")),
    "tactical_diameter_lengths": (0.05, True, ("hull_crossflow", "norrbin", "sway", "speed_loss")),
    "steady_rate_of_turn": (0.10, True, ("hull_crossflow", "norrbin", "propeller_slipstream", "asymmetry")),
    "speed_loss": (0.10, True, ("speed_loss", "turning_resistance", "rudder_drag", "drift_resistance")),
    "first_overshoot": (2.0, False, ("steering_machine", "norrbin", "hull_crossflow")),
}


def judged_errors(results: Sequence[RunFigures]) -> dict[str, list[float]]:
    """Per judged figure (:data:`JUDGED_FIGURES`), predicted - measured over the runs that reach it in both,
    relative to the measured figure where its bound is relative."""
    errors: dict[str, list[float]] = {key: [] for key in JUDGED_FIGURES}
    for result in results:
        for measured, predicted in zip(result.measured, result.predicted, strict=True):
            if measured.key not in errors or isinstance(measured.value, str) or isinstance(predicted.value, str):
                continue
            if math.isfinite(measured.value) and math.isfinite(predicted.value) and measured.value != 0.0:
                error = predicted.value - measured.value
                errors[measured.key].append(error / abs(measured.value) if JUDGED_FIGURES[measured.key][1] else error)
    return errors


def disagreements(results: Sequence[RunFigures], effects: Sequence[str] | None) -> list[str]:
    """Where the free-running figures disagree, in words, a line per judged figure (:data:`JUDGED_FIGURES`) that
    some run misses by more than its bound: how many runs, the median error, and the library's effects that
    shape the figure which the model (``effects``) lacks -- the physics to try next (``--add``), or, where it has
    them all, its terms fitted on runs that do not reach these manoeuvres' rates of turn (``effects`` None: a
    model not made of the library's effects, such as a fitted MMG form; no effects named)."""
    lines = []
    for key, errors in judged_errors(results).items():
        bound, relative, shaping = JUDGED_FIGURES[key]
        missed = [error for error in errors if abs(error) > bound]
        if not missed:
            continue
        median = float(np.median(errors))
        shown = f"{100.0 * median:+.0f} %" if relative else f"{median:+.1f} deg"
        limit = f"{100.0 * bound:g} %" if relative else f"{bound:g} deg"
        label = next(m.label for r in results for m in r.measured if m.key == key)
        line = f"{label}: {len(missed)} of {len(errors)} runs beyond {limit} (median {shown})"
        if effects is not None:
            lacking = [name for name in shaping if name not in effects]
            line += (
                f"; effects that shape it, not in the model: {', '.join(lacking)}"
                if lacking
                else "; the model has every effect the library knows to shape it: their terms extrapolate"
            )
        lines.append(line)
    stuck = [result for result in results if result.cannot_sail]
    if stuck:
        names = ", ".join(result.run for result in stuck)
        lines.append(f"{len(stuck)} of {len(results)} runs cannot be sailed ({names}): {stuck[0].cannot_sail}")
    return lines


def sailed_score(results: Sequence[RunFigures], logs: Sequence[Log], scales: ErrorScales) -> float:
    """The runs sailed free against their measurement, sample by sample, as one number: the workbench's score
    (:meth:`~ship_env.workbench.fitting.errors.RunErrors.score`, ``sqrt(mean_c (RMS_c / scale_c)^2)``) over heading,
    rate of turn and speed (where logged), each RMS pooled over the runs' samples from the first execute to the
    predicted run's end (the predicted series interpolated at the log's times); infinite where the model cannot
    sail one of the runs, NaN where none was sailed. Every sample counts where :func:`figure_score` reads one
    figure per zig-zag: the speed a ship loses in its swings, the timing of its reversals."""
    if any(result.cannot_sail for result in results):
        return math.inf
    by_name = {log.name: log for log in logs}
    errors = [_sailed_errors(result, by_name[result.run]) for result in results if result.predicted_series is not None]
    errors = [e for e in errors if e.samples]
    return pooled(errors).score(scales) if errors else math.nan


def _sailed_errors(result: RunFigures, log: Log) -> RunErrors:
    """One run sailed free against its log: the RMS of heading, rate of turn and speed (NaN where not logged) over the
    log's samples from the first execute to the predicted run's end, the prediction interpolated at their times."""
    series = result.predicted_series
    assert series is not None
    inside = (log.time >= result.manoeuvre.executes[0]) & (log.time <= series.time[-1])
    time = log.time[inside]

    def rms(predicted: np.ndarray | None, measured: np.ndarray | None) -> float:
        if predicted is None or measured is None or not time.size:
            return math.nan
        return float(np.sqrt(np.mean((np.interp(time, series.time, predicted) - measured[inside]) ** 2)))

    heading = rms(series.heading, log.heading)
    rate = rms(series.rate_of_turn, log.rate_of_turn_or_smoothed)
    return RunErrors(result.run, time.size, heading, rate, math.nan, math.nan, rms(series.speed, log.speed))


def figure_score(results: Sequence[RunFigures]) -> float:
    """The runs' manoeuvre figures against the measured, as one number: the mean over every judged figure
    (:data:`JUDGED_FIGURES`) that both reach of |predicted - measured| / bound (relative to the measured figure
    where the bound is), so 1 is a prediction at the bounds; infinite where the model cannot sail one of the runs,
    NaN where no run has a judged figure."""
    if any(result.cannot_sail for result in results):
        return math.inf
    ratios = [abs(error) / JUDGED_FIGURES[key][0] for key, errors in judged_errors(results).items() for error in errors]
    return float(np.mean(ratios)) if ratios else math.nan
