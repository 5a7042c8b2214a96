"""``ship-env fit-mmg``: the MMG standard's 3-DOF forces fitted to measured runs by inverse dynamics, and the
fitted ship sailed free through the hard-over turning circles and the 10/10 zig-zag it was not fitted to, and
through the runs' own manoeuvres (``--validate-on``: runs it was not fitted to), measured against predicted.

Declared as :data:`COMMAND`; the smoothing, the fit (:mod:`ship_env.workbench.fitting.inverse_dynamics`) and the
manoeuvres are imported only when the command runs.
"""

from __future__ import annotations

import argparse
import math
import shlex
import sys
import warnings
from pathlib import Path
from typing import TYPE_CHECKING

from ship_env.command_line import Command, UsageError, number
from ship_env.model import list_ships
from ship_env.model.arguments import ship_name
from ship_env.text_table import Table
from ship_env.workbench.cli import add_log_arguments, add_validation_argument
from ship_env.workbench.outputs import claim_file

if TYPE_CHECKING:
    from ship_env.model import ShipModel
    from ship_env.workbench.fitting.inverse_dynamics import Identification
    from ship_env.workbench.logs.logs import Log

#: The preset the command starts from without ``--ship``.
FIT_MMG_SHIP = "esso_osaka_model"
#: The share of each force the form should explain (R^2) where the runs hold no other forces.
EXPLAINED = 0.9
#: The standard's zig-zag sailed besides the hard-over turns: rudder and heading change, deg.
ZIGZAG = (10.0, 10.0)


def run_fit_mmg(args: argparse.Namespace) -> int:
    """``ship-env fit-mmg``: fit the form to the logs, print it with its errors, sail it free, write it."""
    import numpy as np

    from ship_env.manoeuvres import TrialSettings, ship_line, turning_circle, zigzag
    from ship_env.manoeuvres.cli import Sailing, Task, sail_report
    from ship_env.model import ShipModel
    from ship_env.model.mmg_form import INFLOW_TERMS, SURGE_TERMS, SWAY_TERMS, YAW_TERMS
    from ship_env.workbench import LogWarning, load_logs
    from ship_env.workbench.fitting.inverse_dynamics import identify, rigid_body
    from ship_env.workbench.reporting.presets import fitted_mmg_document, mmg_preset_document, write_preset

    model = ShipModel(args.ship)
    output = None if args.output is None else claim_file(args.output, args.force, "--output")
    preset = None if args.preset is None else claim_file(args.preset, args.force, "--preset")
    plot = None if args.plot is None else claim_file(args.plot, args.force, "--plot")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", LogWarning)
        logs = load_logs(args.logs, args.format)
        validation = load_logs(args.validate_on, args.format) if args.validate_on else []
    for warning in caught:
        print(f"ship-env fit-mmg: warning: {warning.message}", file=sys.stderr)
    try:
        body = rigid_body(model, args.block_coefficient, args.centre_of_gravity * model.length)
    except ValueError as error:
        raise UsageError("--ship", str(error)) from None
    identified = identify(logs, model, body, jackknife=not args.no_jackknife, propeller_rate=args.propeller_rate)
    record = identified.record
    print(
        f"{len(logs)} runs of {model.ship.name} (L {model.length:g} m): the MMG standard's 3-DOF forces fitted by "
        f"inverse dynamics; rigid body from C_B {body.block_coefficient:g} and x_G {body.centre_of_gravity:g} m "
        "(assumed)"
    )
    surge, sway, yaw = identified.fitted.determination
    print(f"equation error: R^2 surge {surge:.3f}, sway {sway:.3f}, yaw {yaw:.3f}")
    windy = [log.name for log in logs if log.has_wind_beyond_noise]
    if windy:
        print(
            f"warning: {len(windy)} of {len(logs)} runs sail in wind ({', '.join(windy[:3])}"
            f"{', ...' if len(windy) > 3 else ''}): the form has no wind forces, so the fit takes them for the "
            "hull's and the rudder's"
        )
    if min(surge, sway, yaw) < EXPLAINED:
        print(
            f"warning: the form explains less than {EXPLAINED:.0%} of a force the runs show (R^2 above): the "
            "coefficients and what the model predicts rest on what it leaves out"
        )
    errors = identified.standard_errors
    arrays = (record.form.inflow, record.form.surge, record.form.sway, record.form.yaw)
    rows = tuple(
        (name, f"{value:.4g}", f"{errors[name]:.2g}" if name in errors else "-")
        for names, values in zip((INFLOW_TERMS, SURGE_TERMS, SWAY_TERMS, YAW_TERMS), arrays, strict=True)
        for name, value in zip(names, values, strict=True)
    )
    print(Table(("term", "value", "std. error (jackknife)"), rows).text())
    if not identified.folds:
        print("no jackknife (--no-jackknife, or fewer than three runs): the figures below have no error")
    dt = float(np.median(np.concatenate([np.diff(log.time) for log in logs])))  # the logs' sample interval
    settings = TrialSettings(dt=dt)
    hard_over = math.degrees(model.rudder_limit)
    tasks: list[Task] = [
        *(
            (f"turning circle {angle:g}", lambda ship, how, a=angle: turning_circle(ship, math.radians(a), how))
            for angle in (hard_over, -hard_over)
        ),
        (
            f"zig-zag {ZIGZAG[0]:g}/{ZIGZAG[1]:g}",
            lambda ship, how: zigzag(ship, math.radians(ZIGZAG[0]), math.radians(ZIGZAG[1]), how),
        ),
    ]
    title = ship_line(model, settings.approach_speed(model), "the fitted MMG model")
    print(f"\nsailed free at the runs' propeller rate {record.propeller_rate:.4g} rps")
    try:
        print(sail_report(Sailing.fitted(model, settings, record), tasks, title).text)
    except FloatingPointError as error:
        print(f"ship-env fit-mmg: {error}", file=sys.stderr)
    _print_runs_sailed_free(model, identified, logs, validation, plot)
    command = "ship-env " + shlex.join(getattr(args, "argv", []))
    if output is not None:
        write_preset(fitted_mmg_document(identified, command, str(model.ship.path or model.ship.name)), output)
        print(
            f"\nfitted MMG model written to {output}; sail it with: ship-env manoeuvre --ship {args.ship} "
            f"--dynamics {output}"
        )
    if preset is not None:
        write_preset(mmg_preset_document(model, identified, command, preset.stem), preset)
        print(
            f"\npreset sailed by the fitted MMG model written to {preset} (gym.make(..., ship={str(preset)!r}), "
            f"ship-env manoeuvre --ship {preset}, ship-env leaderboard --ship {preset})"
        )
    return 0


def _print_runs_sailed_free(
    model: ShipModel, identified: Identification, logs: list[Log], validation: list[Log], plot: Path | None
) -> None:
    """The runs' manoeuvres sailed free, each by a fit that did not see it, measured against predicted
    (:mod:`ship_env.workbench.judging.free_running`): a fitted run by the fold that left it out (with the
    jackknife), a ``--validate-on`` run by the fit to all runs, +- the folds' spread; their tracks into ``plot``."""
    from ship_env.workbench import ReplayModel
    from ship_env.workbench.judging.free_running import disagreements, free_running_table, held_out_mmg_sailing

    results = held_out_mmg_sailing(ReplayModel(model), identified, logs, validation)
    folds = identified.record.folds
    if not results:
        if validation or folds:
            print("\nno run reads as a turning circle or a zig-zag: none sailed free against its measurement")
        return
    whose = "a fitted run by the fold that left it out, " if folds else ""
    print(
        f"\nthe runs' manoeuvres sailed free from their first execute, each by a fit that did not see it ({whose}a "
        "--validate-on run by the fit to all runs, +- the folds' spread; in calm water: the form has no wind forces)"
    )
    print(free_running_table(results).text())
    for line in disagreements(results, None):
        print(f"disagrees: {line}")
    if plot is not None:
        from ship_env.workbench.reporting.report import plot_free_running

        plot_free_running(results, [*logs, *validation], model.length, plot)
        print(f"tracks, measured against sailed free, written to {plot}")


def _fit_mmg_arguments(parser: argparse.ArgumentParser) -> None:
    add_log_arguments(parser)
    parser.add_argument(
        "--ship",
        type=ship_name,
        default=FIT_MMG_SHIP,
        metavar="NAME",
        help=f"ship preset ({', '.join(list_ships())}) or a YAML file: its length, breadth, draught, rudder "
        "limit and steering machine (default: %(default)s)",
    )
    parser.add_argument(
        "--block-coefficient",
        type=number("a block coefficient", minimum=0.3, maximum=1.0),
        default=0.75,
        metavar="CB",
        help="C_B, for the displacement and the added masses (default: %(default)s; the coefficients absorb most "
        "of an error in it)",
    )
    parser.add_argument(
        "--centre-of-gravity",
        type=number("x_G / L", minimum=-0.1, maximum=0.1),
        default=0.0,
        metavar="XG",
        help="x_G / L, forward of midships (default: %(default)s)",
    )
    parser.add_argument(
        "--propeller-rate",
        type=number("a propeller rate in rps", above=0.0),
        default=None,
        metavar="RPS",
        help="the propeller rate of logs without a propeller channel (default: such a log is refused)",
    )
    add_validation_argument(parser, "sailed free by the fit through their own manoeuvres, measured against predicted,")
    parser.add_argument(
        "--plot", type=Path, default=None, metavar="PNG", help="write the runs' tracks, measured against sailed free"
    )
    parser.add_argument("--no-jackknife", action="store_true", help="fit once, without leaving each run out")
    parser.add_argument("-o", "--output", type=Path, default=None, metavar="FILE", help="write the fitted model")
    parser.add_argument(
        "--preset",
        type=Path,
        default=None,
        metavar="FILE",
        help="write --ship's preset sailed by the fitted model (its dynamics block), at the runs' speed and propeller "
        "rate: the environments, manoeuvre and the leaderboard sail it by default",
    )
    parser.add_argument("--force", action="store_true", help="overwrite --output, --preset and --plot")


COMMAND = Command(
    "fit-mmg",
    description=(
        "Fit the MMG standard's 3-DOF hull, propeller and rudder forces (Yasukawa & Yoshimura 2015)\n"
        "to measured runs by inverse dynamics: the runs' states and accelerations smoothed (Kalman\n"
        "filter and RTS smoother, the noise from the logs), the forces from the mass matrix, the\n"
        "coefficients by least squares; each run left out in turn for their errors. Then sail the\n"
        "fitted ship free through the hard-over turning circles and the 10/10 zig-zag, and say how\n"
        "far they go beyond the runs; and through the runs' own manoeuvres, each by a fit that did not\n"
        "see it (--validate-on: turning runs, say), measured against predicted. Needs position, heading\n"
        "and speed channels, and the propeller rate\n"
        "(a channel, or --propeller-rate where it was constant); rudder orders are followed at the\n"
        "preset's steering-machine rate."
    ),
    handler=run_fit_mmg,
    arguments=_fit_mmg_arguments,
    examples=(
        "ship-env scale kvlcc2 --length 7 -o kvlcc2_model.yaml",
        "ship-env fit-mmg basin/zigzag --ship kvlcc2_model.yaml -o hull.yaml",
        "ship-env fit-mmg basin/zigzag --ship kvlcc2_model.yaml --preset fitted.yaml",
        "ship-env fit-mmg basin/zigzag --ship kvlcc2_model.yaml --validate-on basin/turning --plot sailed.png",
        "ship-env manoeuvre --ship kvlcc2_model.yaml --dynamics hull.yaml --turn-angle 35 -35 --zigzag 10/10",
        "ship-env manoeuvre --ship fitted.yaml --turn-angle 35 -35 --zigzag 10/10",
    ),
)
