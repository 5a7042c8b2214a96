"""``ship-env leaderboard``: every controller on the fixed, seeded suites; tables and plots.

Declared as :data:`COMMAND`; the evaluation (torch, stable-baselines3, the baselines) is
imported only when the command runs.
"""

from __future__ import annotations

import argparse
import dataclasses
import sys
import textwrap
from pathlib import Path
from typing import Any

from ship_env.command_line import Command, add_progress_argument, number, ship_preset, whole_number
from ship_env.envs.tracks import TRACK_IDS, TrackError
from ship_env.extras import require
from ship_env.leaderboard.evaluation import BACKENDS
from ship_env.leaderboard.suites import (
    CONDITIONS,
    COURSE_CHANGE_DISTURBANCES,
    DEFAULT_SHIP,
    FITTED_UNCERTAINTY,
    SUITE_SPECS,
    SuiteSpec,
    sails_condition,
)
from ship_env.ray_cluster import add_backend_arguments

_CONDITIONS_BY_SLUG = {condition.slug: condition for condition in CONDITIONS}


def chosen_spec(args: argparse.Namespace) -> SuiteSpec:
    """``--suite``'s spec with the subsets the other options choose."""
    choices = {
        "course_changes_deg": args.course_changes,
        "tracks": [] if args.no_tracks else args.tracks,
        "conditions": None if args.conditions is None else [_CONDITIONS_BY_SLUG[s] for s in args.conditions],
        "course_change_disturbances": args.disturbances,
        "repetitions": args.repetitions,
        "ship": args.ship,
    }
    changes: dict[str, Any] = {
        name: tuple(value) if isinstance(value, list) else value for name, value in choices.items() if value is not None
    }
    return dataclasses.replace(SUITE_SPECS[args.suite], **changes)


#: Where ``--out`` defaults to: a folder per run, named after it (``default_out``).
OUT_ROOT = Path("out/leaderboard")


def default_out(suite: str, ship: str | None) -> Path:
    """The folder a run writes without ``--out``: ``out/leaderboard/SUITE``, or ``SUITE-SHIP`` on
    another ship than the default (a ship YAML by its file's stem)."""
    if ship is None:
        return OUT_ROOT / suite
    name = Path(ship).stem if ship.endswith((".yaml", ".yml")) else ship
    return OUT_ROOT / f"{suite}-{name}"


def run_leaderboard_command(args: argparse.Namespace) -> int:
    """Evaluate, print a summary within 100 columns and the wall time, write the tables and plots into
    ``--out`` (a folder named after the run by default)."""
    require("leaderboard", "the leaderboard", "torch", "stable_baselines3", "rliable")
    from ship_env.leaderboard.board import run_leaderboard, write_leaderboard
    from ship_env.ray_cluster import check_backend
    from ship_env.rl.policy_file import PolicyFileError

    check_backend(args.backend, args.ray_address)
    if args.ship is not None:
        from ship_env.leaderboard.entrants import check_design_ship

        if args.suite == "unseen":
            args.command_parser.error("argument --ship: the unseen suite sails its own ship, the MMG KVLCC2")
        try:
            check_design_ship(args.ship)
        except ValueError as error:
            args.command_parser.error(f"argument --ship: {error}")
    from ship_env.envs.variation import undetermined_terms
    from ship_env.model import load_ship

    ship = args.ship or DEFAULT_SHIP
    preset = load_ship(ship)
    # A ship sailed by its preset's fitted MMG model draws its uncertainty from that model's jackknife (the suites).
    undetermined = [] if preset.dynamics is not None else undetermined_terms(preset)
    why = (
        f"the fit of {ship} does not determine {', '.join(undetermined)} (a standard error over half the value)"
        if undetermined
        else f"the ship {ship} gives none (sail --ship FILE written by ship-env fit --preset or improve --preset)"
    )
    asked = FITTED_UNCERTAINTY in chosen_spec(args).conditions
    if args.conditions and FITTED_UNCERTAINTY.slug in args.conditions and not sails_condition(FITTED_UNCERTAINTY, ship):
        args.command_parser.error(
            f"argument --conditions: {FITTED_UNCERTAINTY.slug} draws ships from a fitted preset's standard errors; "
            f"{why}"
        )
    if asked and undetermined:
        print(f"ship-env leaderboard: left out the {FITTED_UNCERTAINTY.slug} condition: {why}", file=sys.stderr)
    try:
        board = run_leaderboard(
            chosen_spec(args),
            args.policies,
            not args.no_shipped,
            args.backend,
            progress=not args.no_progress,
            ray_address=args.ray_address,
            trust_policy_code=args.trust_policy_code,
        )
    except PolicyFileError as error:
        args.command_parser.error(f"argument --policies: {error}")
    except TrackError as error:  # the only task asked for cannot be sailed on this ship
        print(f"ship-env leaderboard: nothing to sail: {error}", file=sys.stderr)
        return 1
    for line in board.left_out:
        print(f"ship-env leaderboard: left out {line}", file=sys.stderr)
    print(board.summary())
    print(
        f"\n{len(board.results)} episodes, {len(board.entrants)} controllers, {len(board.suites)} suites on "
        f"{board.ship_name}: {board.wall_time_s:.1f} s on the {args.backend} backend"
    )
    out = default_out(args.suite, args.ship) if args.out is None else args.out
    written = write_leaderboard(board, out, plots=not args.no_plots)
    print(f"every suite's ranked table: {written[0]}")
    print(textwrap.fill(f"written to {out}/: {', '.join(path.name for path in written)}", 100, subsequent_indent="  "))
    return 0


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """The arguments of ``ship-env leaderboard``."""
    parser.add_argument(
        "--suite",
        choices=list(SUITE_SPECS),
        default="dev",
        help="dev (alias quick), for screening and tuning: the thesis's course changes and tracks once in every "
        "condition (nominal, K*, tau* x0.5 and x2, half speed, and on a fitted preset ships drawn from its "
        "standard errors, fitted-uncertainty); full: the dev episodes three times; test, to "
        "report: course changes, seeds and track starts no screen sailed; unseen: the dev episodes on "
        "shipmmg's MMG KVLCC2 (calm, wind and current, tracks scaled to 320 m; needs shipmmg) "
        "(default: %(default)s)",
    )
    parser.add_argument(
        "--ship",
        type=ship_preset,
        default=None,
        metavar="FILE",
        help="the ship sailed: a preset name or a ship YAML (say one written by ship-env fit ... --preset); the "
        "classic autopilots are designed from its values, the conditions scale its K*, tau* and speed (on a "
        "fitted preset fitted-uncertainty draws them from its standard errors, other ships for dev and test), and the "
        "learned entrants sail it, named as trained on another ship where they were (default: container_226m; "
        "not with --suite unseen)",
    )
    parser.add_argument(
        "--policies",
        type=Path,
        nargs="+",
        default=[],
        metavar="PATH",
        help="SB3 policies to rank beside the others, one entrant each: a model.zip, a training run's folder, "
        "or a folder of one run per training seed (seed<S>/, as ship-env train --seeds writes them)",
    )
    parser.add_argument(
        "--trust-policy-code",
        action="store_true",
        help="read the --policies files with stable-baselines3's unpickling, which RUNS ANY CODE THEY CARRY: only for "
        "files you trust that the default reading (no code run: spaces, allowed policy classes, tensors) refuses",
    )
    parser.add_argument("--no-shipped", action="store_true", help="leave out the policies shipped with ship_env")
    parser.add_argument(
        "--out",
        type=Path,
        default=None,
        metavar="DIR",
        help=f"folder for the tables and plots, whose former ones are replaced (default: {OUT_ROOT}/SUITE, or "
        f"{OUT_ROOT}/SUITE-SHIP with --ship: a folder per run)",
    )
    add_backend_arguments(
        parser, BACKENDS, "local: in this process; ray: one Ray task per controller, training seed and suite"
    )
    parser.add_argument(
        "--course-changes",
        type=number("a course change in (0, 180] deg", above=0.0, maximum=180.0),
        nargs="+",
        default=None,
        metavar="DEG",
        help="sail only these CourseChange magnitudes, each to both sides (default: the suite's; dev and full: "
        "15 30 45 75 105)",
    )
    parser.add_argument(
        "--disturbances",
        choices=COURSE_CHANGE_DISTURBANCES,
        nargs="+",
        default=None,
        metavar="LEVEL",
        help=f"sail only these CourseChange levels ({', '.join(COURSE_CHANGE_DISTURBANCES)})",
    )
    tracks = parser.add_mutually_exclusive_group()
    tracks.add_argument(
        "--tracks",
        choices=TRACK_IDS,
        nargs="+",
        default=None,
        metavar="ID",
        help=f"sail only these TrackFollow tracks ({', '.join(TRACK_IDS)}; default: the suite's, all six)",
    )
    tracks.add_argument(
        "--no-tracks",
        action="store_true",
        help="sail no TrackFollow suites: CourseChange only",
    )
    parser.add_argument(
        "--conditions",
        choices=list(_CONDITIONS_BY_SLUG),
        nargs="+",
        default=None,
        metavar="NAME",
        help=f"sail only in these ship conditions ({', '.join(_CONDITIONS_BY_SLUG)})",
    )
    parser.add_argument(
        "--repetitions",
        type=whole_number(1),
        default=None,
        metavar="N",
        help="sail each episode N times with other seeds (default: the suite's)",
    )
    parser.add_argument("--no-plots", action="store_true", help="write the tables only")
    add_progress_argument(parser)


COMMAND = Command(
    "leaderboard",
    description=(
        "Sail every controller - fixed and gain-scheduled PD, indirect adaptive PD, MRAC, the predictor\n"
        "course changer (TrackFollow), the shipped policies and the policy files given - on fixed,\n"
        "seeded suites: CourseChange (dev 15..105, test 10..120 deg both ways, calm / wind and current / waves) and\n"
        "TrackFollow (T1..T6), on the nominal ship, with its K*, tau* off by 2x from the controllers'\n"
        "design values, and at half speed. The ship is container_226m, or --ship's (a preset or a fitted\n"
        "preset's YAML), whose own values the classic autopilots are designed from. Writes a ranked\n"
        "table per suite as markdown and CSV with plots into a folder named after the run, and prints\n"
        "the headline and the learned entrants' verdicts. Learned policies sail every\n"
        "episode with each training seed; each table gives the IQM of its ranking metric and of the\n"
        "normalised score (1 = the fixed PD, or the predictor\n"
        "course changer on TrackFollow) with 95 % stratified-bootstrap intervals over training seeds\n"
        "and episodes (rliable), and each learned policy's probability of improvement over the best\n"
        "classic autopilot: better where that interval lies above parity (0.5), worse where below, tied\n"
        "otherwise. Screen and tune on --suite dev, report on --suite test (held-out course changes, seeds\n"
        "and track starts). The same seeds give the same tables and intervals to the last digit.\n"
        'Needs the leaderboard extra: pip install "ship-env[leaderboard]".'
    ),
    examples=(
        "ship-env leaderboard",
        "ship-env leaderboard --suite test",
        "ship-env leaderboard --suite full --backend ray --out leaderboard_full",
        "ship-env leaderboard --policies runs/CourseChange-v0/ppo --conditions nominal --no-tracks",
        "ship-env leaderboard --ship fitted.yaml --tracks T1 T2",
    ),
    handler=run_leaderboard_command,
    arguments=add_arguments,
)
