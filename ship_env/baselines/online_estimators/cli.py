"""``ship-env identify-bench``: every on-line estimator on the same logs, a table, plots, and stelling 5.

:data:`COMMAND` declares the subcommand for the ``ship-env`` parser; the comparison and
matplotlib are imported only when it runs.
"""

from __future__ import annotations

import argparse
import json
import sys

from ship_env.baselines.online_estimators.scenarios import SCENARIOS, adaptation_trials
from ship_env.command_line import Command, add_json_argument, add_plot_argument, name_list, number, prepare_outputs


def run_identify_bench(args: argparse.Namespace) -> int:
    """Sail the scenarios, run the estimators, print the tables, write the plots and the JSON."""
    from ship_env.baselines.online_estimators.bench import (
        adaptation_table,
        comparison_table,
        plot_adaptation,
        plot_scenario,
        run_adaptation,
        run_scenario,
        scale_label,
    )

    prepare_outputs(args.plot, args.json)
    runs = []
    for name in args.scenarios:
        print(f"sailing {name}{scale_label(args.scale)} ...", file=sys.stderr)
        trial, scenario_runs = run_scenario(name, args.seed, args.scale)
        runs.extend(scenario_runs)
        if args.plot is not None:
            plot_scenario(trial, scenario_runs, args.plot / f"{name}.png")
    print(f"identification comparison, seed {args.seed}{scale_label(args.scale)}")
    print(comparison_table(runs))
    rows = []
    if not args.no_adaptation:
        print("comparing random walk and forgetting factor (stelling 5) ...", file=sys.stderr)
        rows = run_adaptation(args.seed, args.scale)
        print("\nstelling 5: random walk (RW) against a forgetting factor (FF) matched to its steady-state noise,")
        print("loading change at the middle of a 20/20 zig-zag; J_p (6.1) and recovery from the change")
        print(adaptation_table(rows))
        if args.plot is not None:
            plot_adaptation(rows, adaptation_trials(args.seed, args.scale)[1].truth, args.plot / "adaptation.png")
    if args.plot is not None:
        print(f"\nplots written to {args.plot}/")
    if args.json is not None:
        document = {
            "seed": args.seed,
            "scale": args.scale,
            "runs": [
                {
                    "scenario": run.scenario,
                    "estimator": run.estimator,
                    "final_relative_error": run.final,
                    "within_10_percent_after_s": run.settling,
                    "J_p_s": run.criterion,
                    "microseconds_per_step": run.microseconds_per_step,
                    "failure": run.failure,
                }
                for run in runs
            ],
            "adaptation": [
                {
                    "pair": row.pair,
                    "drift_per_s": row.drift,
                    "forgetting_factor": row.comparison.forgetting_factor,
                    "noise_matched": row.comparison.noise_matched,
                    **{
                        f"{key}_{field}": getattr(getattr(row.comparison, key), field)
                        for key in ("random_walk", "forgetting")
                        for field in ("steady_noise", "tracking_criterion", "recovery_time")
                    },
                }
                for row in rows
            ],
        }
        args.json.write_text(json.dumps(document, indent=2) + "\n")
        print(f"results written to {args.json}")
    return 0


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """The arguments of ``ship-env identify-bench``."""
    parser.add_argument(
        "--scenarios",
        type=name_list("scenario", SCENARIOS),
        default=list(SCENARIOS),
        metavar="NAME[,NAME]",
        help=f"scenarios to run (default: all): {', '.join(SCENARIOS)}",
    )
    parser.add_argument("--seed", type=int, default=0, metavar="N", help="noise and rudder seed (default: %(default)s)")
    parser.add_argument(
        "--scale",
        type=number("a factor between 0.05 and 10", minimum=0.05, maximum=10.0),
        default=1.0,
        metavar="F",
        help="multiply every run's duration (and change time) by F, e.g. 0.25 for a quick look (default: %(default)s)",
    )
    parser.add_argument("--no-adaptation", action="store_true", help="leave out the stelling-5 comparison")
    add_plot_argument(parser, "convergence plots (PNG)")
    add_json_argument(parser, "the results")


COMMAND = Command(
    "identify-bench",
    description=(
        "Sail excitation runs (zig-zag, PRBS, white-noise rudder, turning, a loading change, a speed\n"
        "change) on the container ship and on Perera et al.'s model, run every on-line estimator on the\n"
        "same logs (Nguyen's RLS, Passenier's combined MRAS and random-walk EKF, Song's EKF, Perera's\n"
        "EKF) and print per estimator the final parameter error, the time to within 10 %, J_p (thesis\n"
        "6.1) and the cost per sample; then test stelling 5 (random walk against a forgetting factor\n"
        "matched to the same steady-state noise)."
    ),
    examples=(
        "ship-env identify-bench --plot identification/",
        "ship-env identify-bench --scenarios zigzag,loading-change --no-adaptation",
        "ship-env identify-bench --scale 0.25 --json bench.json",
    ),
    handler=run_identify_bench,
    arguments=add_arguments,
)
