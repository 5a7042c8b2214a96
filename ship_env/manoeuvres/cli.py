"""``ship-env manoeuvre``: the standard manoeuvres of IMO MSC.137(76) sailed from a steady straight
approach in calm water, their figures and criteria printed (and drawn, and written as JSON).

Declared as :data:`COMMAND`; the manoeuvres (the simulator) and their plotting are imported only
when the command runs. Invalid arguments end with a message naming the argument and exit status 2;
a manoeuvre that leaves the model's validity ends with status 1.
"""

from __future__ import annotations

import argparse
import json
import math
import re
import sys
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, replace
from functools import partial
from pathlib import Path
from typing import TYPE_CHECKING, Any

from tqdm import tqdm

from ship_env.command_line import (
    Command,
    UsageError,
    add_json_argument,
    add_plot_argument,
    positive_number,
    prepare_outputs,
)
from ship_env.model import EFFECTS, ShipModel, list_ships
from ship_env.model.arguments import EFFECT_SETS, effect_set, ship_name

if TYPE_CHECKING:
    from ship_env.manoeuvres import CriterionCheck, ManoeuvreResult, TrialSettings
    from ship_env.model.mmg_fitted import MmgRecord
    from ship_env.model.operating_point import FittedRanges

#: Rudder of the steady turns before the pull-out, deg (or the rudder limit, if smaller).
PULL_OUT_RUDDER_DEG = 20.0


# -- argument types: each raises ArgumentTypeError, which argparse reports with the argument --------
def _turn_angle(text: str) -> float:
    """Read a non-zero rudder angle in deg."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a rudder angle in deg, got {text!r}") from None
    if not math.isfinite(value) or value == 0.0:
        raise argparse.ArgumentTypeError(f"expected a non-zero rudder angle in deg, got {text!r}")
    return value


_ZIGZAG = re.compile(r"^\s*([+-]?\d+(?:\.\d*)?)\s*/\s*([+-]?\d+(?:\.\d*)?)\s*$")


def _zigzag(text: str) -> tuple[float, float]:
    """Read a zig-zag spec "A/B" (deg) as (rudder angle, heading change); a negative A starts to port."""
    match = _ZIGZAG.match(text)
    if match is None:
        raise argparse.ArgumentTypeError(f"expected RUDDER/HEADING in deg such as 10/10 or -20/-20, got {text!r}")
    rudder, heading = float(match[1]), float(match[2])
    if rudder == 0.0 or heading == 0.0:
        raise argparse.ArgumentTypeError(f"rudder and heading change must not be zero, got {text!r}")
    if heading < 0.0 < rudder:
        raise argparse.ArgumentTypeError(f"a port heading change needs port rudder (-A/-B), got {text!r}")
    return rudder, abs(heading)


# -- the command ---------------------------------------------------------------------------------
def _build_model(ship: str, effects: str) -> ShipModel:
    """The ship model, or a UsageError naming --effects when an effect lacks its parameters."""
    try:
        if effects in EFFECT_SETS:
            return EFFECT_SETS[effects](ship)
        return ShipModel(ship, effects.split(","))
    except (ValueError, TypeError) as error:
        raise UsageError("--effects", str(error)) from None


def _check_rudder(model: ShipModel, argument: str, degrees: float, shown: str) -> None:
    """A UsageError naming ``argument`` when a rudder angle in deg exceeds the ship's limit."""
    limit = math.degrees(model.rudder_limit)
    if abs(degrees) > limit + 1e-9:
        raise UsageError(argument, f"{shown} exceeds the rudder limit of {limit:g} deg of {model.ship.name}")


#: A manoeuvre to sail: its name, and how a ship (its model and trial settings) sails it.
Task = tuple[str, "Callable[[ShipModel, TrialSettings], ManoeuvreResult]"]


@dataclass(frozen=True)
class Sailing:
    """Who sails the manoeuvres: the ship, the jackknife's ships (each a model and its settings: a fitted preset's
    folds, or a fitted MMG model's) and the ranges the fit's runs covered (None: not a fit)."""

    model: ShipModel
    settings: TrialSettings
    folds: list[tuple[ShipModel, TrialSettings]]
    ranges: FittedRanges | None

    @classmethod
    def of(cls, model: ShipModel, settings: TrialSettings) -> Sailing:
        """``model`` sailed with ``settings``: its preset's folds and coverage, or, where ``settings.dynamics`` (or,
        without it, the preset's ``dynamics:`` block) is a fitted MMG model, that model's (:meth:`fitted`)."""
        from ship_env.manoeuvres.uncertainty import fold_models
        from ship_env.model.external import preset_dynamics
        from ship_env.model.mmg_fitted import read_mmg
        from ship_env.model.mmg_record import MmgRecord

        dynamics = preset_dynamics(model, settings.dynamics)
        if isinstance(dynamics, (str, Path)) and str(dynamics).endswith((".yaml", ".yml")):
            dynamics = read_mmg(dynamics)
        if isinstance(dynamics, MmgRecord):
            return cls.fitted(model, settings, dynamics)
        if dynamics is not None:
            return cls(model, settings, [], None)
        return cls(model, settings, [(fold, settings) for fold in fold_models(model)], model.fitted_ranges)

    @classmethod
    def fitted(cls, model: ShipModel, settings: TrialSettings, record: MmgRecord) -> Sailing:
        """The fitted MMG model ``record`` sailed with ``settings`` (its dynamics replaced), its folds and its
        runs' coverage; ``model`` the preset of its particulars."""
        from ship_env.model.mmg_fitted import MmgFitted

        folds = [(model, replace(settings, dynamics=partial(MmgFitted, fold))) for fold in record.fold_records()]
        return cls(model, replace(settings, dynamics=partial(MmgFitted, record)), folds, record.fitted_ranges())


@dataclass(frozen=True)
class SailedReport:
    """The manoeuvres sailed: their results, the criteria, the figures' jackknife errors (None without folds) and
    the report's text."""

    results: list[ManoeuvreResult]
    checks: list[CriterionCheck]
    errors: list[dict[str, float]] | None
    text: str


def sail_report(sailing: Sailing, tasks: Sequence[Task], title: str) -> SailedReport:
    """Sail ``tasks`` with the ship and each of its folds; the report (``title`` its first line), the jackknife's
    line and how far each manoeuvre went beyond the fit's runs.

    Raises:
        FloatingPointError: the ship left its model's validity in a manoeuvre (named).
    """
    from ship_env.manoeuvres import check_criteria, format_report

    results = []
    fold_results: list[list[ManoeuvreResult | None]] = []
    with tqdm(tasks, desc="manoeuvres", unit="manoeuvre", file=sys.stderr, leave=False) as progress:
        for name, task in progress:
            progress.set_postfix_str(name)
            try:
                results.append(task(sailing.model, sailing.settings))
            except FloatingPointError as error:
                raise FloatingPointError(f"{name} failed: {error}") from None
            fold_results.append([_sailed_or_none(task, *fold) for fold in sailing.folds])
    checks = check_criteria(results)
    errors = [_figure_errors(sailed) for sailed in fold_results] if sailing.folds else None
    lines = [format_report(title, results, checks, errors)]
    if sailing.folds:
        lines.append(_uncertainty_line(len(sailing.folds), [name for name, _ in tasks], fold_results))
    if beyond := _extrapolation_block(sailing, results):
        lines.append(beyond)
    if forms := _rival_forms_block(sailing):
        lines.append(forms)
    return SailedReport(results, checks, errors, "\n".join(lines))


def run_manoeuvres(args: argparse.Namespace) -> int:
    """``ship-env manoeuvre``: sail the standard manoeuvres, print the figures and IMO criteria."""
    from ship_env.manoeuvres import (
        TrialSettings,
        plot_manoeuvre,
        pull_out,
        report_dict,
        reversed_spiral,
        ship_line,
        turning_circle,
        zigzag,
    )
    from ship_env.manoeuvres.results import KNOT

    model = _build_model(args.ship, args.effects)
    for angle in args.turn_angle:
        _check_rudder(model, "--turn-angle", angle, f"{angle:g} deg")
    for rudder, heading in args.zigzag:
        _check_rudder(model, "--zigzag", rudder, f"{rudder:g}/{heading:g}")
    dynamics = _dynamics(args.dynamics, model)
    prepare_outputs(args.plot, args.json)
    settings = TrialSettings(speed=None if args.speed is None else args.speed * KNOT, dt=args.dt, dynamics=dynamics)
    pull_out_rudder = min(math.radians(PULL_OUT_RUDDER_DEG), model.rudder_limit)
    tasks: list[Task] = [
        *(
            (f"turning circle {a:g}", lambda ship, how, a=a: turning_circle(ship, math.radians(a), how))
            for a in args.turn_angle
        ),
        *(
            (f"zig-zag {a:g}/{b:g}", lambda ship, how, a=a, b=b: zigzag(ship, math.radians(a), math.radians(b), how))
            for a, b in args.zigzag
        ),
        ("pull-out", lambda ship, how: pull_out(ship, pull_out_rudder, how)),
        ("reversed spiral", lambda ship, how: reversed_spiral(ship, settings=how)),
    ]
    sailing = Sailing.of(model, settings)
    try:
        report = sail_report(sailing, tasks, ship_line(model, settings.approach_speed(model), args.dynamics))
    except FloatingPointError as error:
        print(f"ship-env manoeuvre: {error}", file=sys.stderr)
        return 1
    print(report.text)
    if args.plot is not None:
        for result in report.results:
            plot_manoeuvre(result, args.plot / f"{result.slug}.png")
        print(f"\nplots written to {args.plot}/")
    if args.json is not None:
        document = report_dict(model, report.results, report.checks, report.errors)
        args.json.write_text(json.dumps(document, indent=2) + "\n")
        print(f"figures written to {args.json}")
    return 0


def _dynamics(text: str | None, model: ShipModel) -> str | None:
    """``--dynamics``, checked now (a fitted MMG model's file read, an import path imported); a UsageError
    naming the option where it cannot be sailed, or where a fitted model's length is not ``model``'s (``--ship``
    gives the particulars and the approach speed the manoeuvres are read with)."""
    from ship_env.model.external import NATIVE, dynamics_factory
    from ship_env.model.mmg_fitted import read_mmg

    if text is None or text == NATIVE:
        return text
    try:
        dynamics_factory(text)
        fitted_length = read_mmg(text).form.body.length if text.endswith((".yaml", ".yml")) else model.length
    except (ValueError, TypeError) as error:
        raise UsageError("--dynamics", str(error)) from None
    if not math.isclose(fitted_length, model.length, rel_tol=1e-9):
        raise UsageError(
            "--dynamics",
            f"{text} was fitted to a ship of length {fitted_length:g} m; --ship {model.ship.name} is {model.length:g} "
            "m long: give the preset it was fitted with",
        )
    return text


def _sailed_or_none(
    task: Callable[[ShipModel, TrialSettings], ManoeuvreResult], ship: ShipModel, settings: TrialSettings
) -> ManoeuvreResult | None:
    """The manoeuvre sailed by ``ship``, or None where it leaves the model's validity."""
    try:
        return task(ship, settings)
    except FloatingPointError:
        return None


def _figure_errors(sailed: list[ManoeuvreResult | None]) -> dict[str, float]:
    """Per numeric figure, its jackknife standard error over the fold fits (none where one could not sail)."""
    from ship_env.manoeuvres.uncertainty import figure_errors

    results = [result for result in sailed if result is not None]
    return figure_errors([result.figures() for result in results]) if len(results) == len(sailed) else {}


def _extrapolation_block(sailing: Sailing, results: list[ManoeuvreResult]) -> str:
    """How far each manoeuvre sailed beyond the fitted runs (nothing for a ship without a coverage)."""
    from ship_env.manoeuvres.extrapolation import beyond_coverage

    if sailing.ranges is None:
        return ""
    beyond = [
        (result.title, words) for result in results if (words := beyond_coverage(result, sailing.model, sailing.ranges))
    ]
    if not beyond:
        return ""
    lines = ["", "beyond the fitted runs (the fit's coverage: a figure there rests on the model's form):"]
    lines += [f"  {title}: {'; '.join(words)}" for title, words in beyond]
    return "\n".join(lines)


def _rival_forms_block(sailing: Sailing) -> str:
    """The forms its fit could not rule out and what they sail, as a fitted preset records them (``fitted.rival_forms``,
    written by ``improve --preset``), where the preset's effects sail it."""
    from ship_env.model.external import preset_dynamics

    recorded = (sailing.model.ship.fitted or {}).get("rival_forms")
    if not recorded or not recorded.get("rivals") or preset_dynamics(sailing.model, sailing.settings.dynamics):
        return ""

    def figures(entry: Mapping[str, Any]) -> str:
        return ", ".join(f"{name} {number['value']:.4g}" for name, number in entry["figures"].items())

    final = recorded["final_model"]
    lines = ["", f"rival forms of the fit ({recorded['why']}; the jackknife's +- carry none of them):"]
    lines.append(f"  as fitted (in-sample score {final['in_sample_score']:.3g}): {figures(final)}")
    lines += [f"  {rival['form']} ({rival['in_sample_score']:.3g}): {figures(rival)}" for rival in recorded["rivals"]]
    return "\n".join(lines)


def _uncertainty_line(count: int, names: list[str], fold_results: list[list[ManoeuvreResult | None]]) -> str:
    """What +- means, and which manoeuvres some fold fits could not sail."""
    line = (
        f"\n+- the fit's jackknife standard error: each figure sailed by the {count} ships fitted with one run (group) "
        "left out (the fit's jackknife)"
    )
    failed = [
        f"{name} ({missing} of {count})"
        for name, sailed in zip(names, fold_results, strict=True)
        if (missing := sum(result is None for result in sailed))
    ]
    if failed:
        line += f"; none where fold fits cannot sail the manoeuvre: {', '.join(failed)}"
    return line


def _manoeuvre_arguments(parser: argparse.ArgumentParser) -> None:
    """The arguments of ``ship-env manoeuvre``."""
    # Read "-10/-10" (the mirrored zig-zag) as a value, not an option, as argparse does from
    # Python 3.13 on; before that only plain negative numbers such as "-35" were.
    parser._negative_number_matcher = re.compile(r"^-\.?\d")
    parser.add_argument(
        "--ship",
        type=ship_name,
        default="container_226m",
        metavar="NAME",
        help=f"ship preset ({', '.join(list_ships())}) or a YAML file (default: %(default)s)",
    )
    parser.add_argument(
        "--effects",
        type=effect_set,
        default="default",
        metavar="SET",
        help=(
            f"model effects: {', '.join(EFFECT_SETS)} (the preset's own set), or a comma-separated list "
            f"of: {', '.join(EFFECTS)} (default: %(default)s)"
        ),
    )
    parser.add_argument(
        "--speed",
        type=positive_number,
        default=None,
        metavar="KN",
        help="approach speed in knots (default: the ship's service speed)",
    )
    parser.add_argument(
        "--dt",
        type=positive_number,
        default=0.5,
        metavar="S",
        help="integration step in seconds (default: %(default)s)",
    )
    parser.add_argument(
        "--turn-angle",
        type=_turn_angle,
        nargs="+",
        default=[35.0],
        metavar="DEG",
        help="rudder angles of the turning circles in deg, negative to port (default: 35)",
    )
    parser.add_argument(
        "--zigzag",
        type=_zigzag,
        nargs="+",
        default=[(10.0, 10.0), (20.0, 20.0)],
        metavar="A/B",
        help="zig-zag tests as rudder/heading change in deg, -A/-B starts to port (default: 10/10 20/20)",
    )
    parser.add_argument(
        "--dynamics",
        default=None,
        metavar="SOURCE",
        help="sail a ship simulated elsewhere: a fitted MMG model written by 'ship-env fit-mmg' (a .yaml file; its "
        "jackknife gives the figures' errors) or the 'module:attribute' path of a ship-dynamics adapter "
        "(ship_env.model.external); --ship then gives the particulars, rudder limit and approach speed "
        "(default: the preset's own: its dynamics block where it has one, else its effects; 'native': its effects)",
    )
    add_plot_argument(parser, "a PNG per manoeuvre")
    add_json_argument(parser, "the figures and criteria")


COMMAND = Command(
    "manoeuvre",
    description=(
        "Sail the standard manoeuvres of IMO MSC.137(76) from a steady straight approach in calm\n"
        "water: turning circles, zig-zag tests, a pull-out test to both sides and a reversed\n"
        "spiral (Bech). Prints advance, transfer, tactical diameter, overshoot angles, the spiral\n"
        "characteristic and the MSC.137(76) 5.3 criteria with pass or fail."
    ),
    examples=(
        "ship-env manoeuvre",
        "ship-env manoeuvre --effects minimal --turn-angle 35 -35 20 --zigzag 10/10 -10/-10",
        "ship-env manoeuvre --speed 15 --plot plots/ --json figures.json",
        "ship-env manoeuvre --ship kvlcc2_model.yaml --dynamics hull.yaml --turn-angle 35 -35 --zigzag 10/10",
    ),
    handler=run_manoeuvres,
    arguments=_manoeuvre_arguments,
)
