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
from collections.abc import Callable
from typing import TYPE_CHECKING

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
    from ship_env.manoeuvres import ManoeuvreResult

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


def run_manoeuvres(args: argparse.Namespace) -> int:
    """``ship-env manoeuvre``: sail the standard manoeuvres, print the figures and IMO criteria."""
    from ship_env.manoeuvres import (
        TrialSettings,
        check_criteria,
        format_report,
        plot_manoeuvre,
        pull_out,
        report_dict,
        reversed_spiral,
        ship_line,
        turning_circle,
        zigzag,
    )
    from ship_env.manoeuvres.results import KNOT
    from ship_env.manoeuvres.uncertainty import fold_models

    model = _build_model(args.ship, args.effects)
    for angle in args.turn_angle:
        _check_rudder(model, "--turn-angle", angle, f"{angle:g} deg")
    for rudder, heading in args.zigzag:
        _check_rudder(model, "--zigzag", rudder, f"{rudder:g}/{heading:g}")
    prepare_outputs(args.plot, args.json)
    settings = TrialSettings(speed=None if args.speed is None else args.speed * KNOT, dt=args.dt)
    pull_out_rudder = min(math.radians(PULL_OUT_RUDDER_DEG), model.rudder_limit)
    tasks: list[tuple[str, Callable[[ShipModel], ManoeuvreResult]]] = [
        *(
            (f"turning circle {a:g}", lambda ship, a=a: turning_circle(ship, math.radians(a), settings))
            for a in args.turn_angle
        ),
        *(
            (
                f"zig-zag {a:g}/{b:g}",
                lambda ship, a=a, b=b: zigzag(ship, math.radians(a), math.radians(b), settings),
            )
            for a, b in args.zigzag
        ),
        ("pull-out", lambda ship: pull_out(ship, pull_out_rudder, settings)),
        ("reversed spiral", lambda ship: reversed_spiral(ship, settings=settings)),
    ]
    folds = fold_models(model)
    results = []
    fold_results: list[list[ManoeuvreResult | None]] = []
    with tqdm(tasks, desc="manoeuvres", unit="manoeuvre", file=sys.stderr, leave=False) as progress:
        for name, task in progress:
            progress.set_postfix_str(name)
            try:
                results.append(task(model))
            except FloatingPointError as error:
                print(f"ship-env manoeuvre: {name} failed: {error}", file=sys.stderr)
                return 1
            fold_results.append([_sailed_or_none(task, fold) for fold in folds])
    checks = check_criteria(results)
    errors = [_figure_errors(sailed) for sailed in fold_results] if folds else None
    print(format_report(ship_line(model, settings.approach_speed(model)), results, checks, errors))
    if folds:
        print(_uncertainty_line(len(folds), [name for name, _ in tasks], fold_results))
    beyond = _extrapolation_block(model, results)
    if beyond:
        print(beyond)
    if args.plot is not None:
        for result in results:
            plot_manoeuvre(result, args.plot / f"{result.slug}.png")
        print(f"\nplots written to {args.plot}/")
    if args.json is not None:
        args.json.write_text(json.dumps(report_dict(model, results, checks, errors), indent=2) + "\n")
        print(f"figures written to {args.json}")
    return 0


def _sailed_or_none(task: Callable[[ShipModel], ManoeuvreResult], ship: ShipModel) -> ManoeuvreResult | None:
    """The manoeuvre sailed by ``ship``, or None where it leaves the model's validity."""
    try:
        return task(ship)
    except FloatingPointError:
        return None


def _figure_errors(sailed: list[ManoeuvreResult | None]) -> dict[str, float]:
    """Per numeric figure, its jackknife standard error over the fold fits (none where one could not sail)."""
    from ship_env.manoeuvres.uncertainty import figure_errors

    results = [result for result in sailed if result is not None]
    return figure_errors([result.figures() for result in results]) if len(results) == len(sailed) else {}


def _extrapolation_block(model: ShipModel, results: list[ManoeuvreResult]) -> str:
    """How far each manoeuvre sailed beyond the fitted runs (nothing for a preset without a coverage)."""
    from ship_env.manoeuvres.extrapolation import beyond_coverage

    beyond = [(result.title, words) for result in results if (words := beyond_coverage(result, model))]
    if not beyond:
        return ""
    lines = ["", "beyond the fitted runs (the preset's fitted.coverage: a figure there rests on the model's form):"]
    lines += [f"  {title}: {'; '.join(words)}" for title, words in beyond]
    return "\n".join(lines)


def _uncertainty_line(count: int, names: list[str], fold_results: list[list[ManoeuvreResult | None]]) -> str:
    """What +- means, and which manoeuvres some fold fits could not sail."""
    line = (
        f"\n+- the fit's jackknife standard error: each figure sailed by the {count} ships fitted with one run (group) "
        "left out (the preset's fitted.jackknife)"
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
    ),
    handler=run_manoeuvres,
    arguments=_manoeuvre_arguments,
)
