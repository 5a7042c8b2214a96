"""``ship-env improve``: effects added while the held-out error falls; the error ladder printed and, as
asked, a report, the final model's JSON and a fitted preset.

Declared as :data:`COMMAND`, with the arguments and steps the workbench's commands share
(:mod:`ship_env.workbench.cli`); the workbench's fitting is imported only when the command runs.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from ship_env.command_line import Command, add_json_argument, number, whole_number
from ship_env.workbench.cli import (
    WORKBENCH_EXAMPLES,
    WORKBENCH_EXAMPLES_TITLE,
    add_candidate_arguments,
    add_preset_argument,
    add_workbench_arguments,
    fitted_terms,
    model_line,
    start_command,
    write_fitted_preset,
)
from ship_env.workbench.defaults import MIN_GAIN

#: ``--min-gain``: a fraction of the held-out score.
_fraction = number("a number between 0 and 1", minimum=0.0, below=1.0)


def run_improve(args: argparse.Namespace) -> int:
    """``ship-env improve``: add effects while the held-out error falls; the error ladder, and with
    ``--report`` a report."""
    from ship_env.workbench import improve, write_report
    from ship_env.workbench.deciding.rivals import form_spread
    from ship_env.workbench.reporting.documents import ladder_document, write_document
    from ship_env.workbench.reporting.tables import estimate_table, ladder_table, validation_coverage_text

    setup, options, runs = start_command(args)
    logs = runs.logs
    print(model_line(setup, logs))
    terms = fitted_terms(args, setup, logs) if args.fix or args.free else None
    ladder = improve(
        setup,
        logs,
        options,
        args.candidates,
        args.min_gain,
        args.max_steps,
        args.refit,
        progress=lambda text: print(text, file=sys.stderr),
        pair_width=args.pairs,
        groups=runs.groups,
        validate_on=runs.validation,
        require_validation=args.require_validation,
        allow_worse_validation=args.allow_worse_validation,
        validate_by=args.validate_by,
        terms=terms,
    )
    print("\nerror ladder (held out: leave one run out)")
    print(ladder_table(ladder).text())
    print(f"stopped: {ladder.stopped}")
    if ladder.final.validation:
        print(validation_coverage_text(ladder.final, options.error_scales))
    print("\nfinal model, fitted to all runs")
    print(estimate_table(ladder.final).text())
    if args.report is not None:
        report = write_report(ladder, logs, args.report, workers=options.workers)
        print(f"\nreport written to {report}")
    if args.json is not None:
        write_document(ladder_document(ladder, runs.checks, logs), args.json)
        print(f"final model and ladder written to {args.json}")
    write_fitted_preset(args, ladder.final, runs, lambda: form_spread(ladder, logs, options, args.min_gain))
    return 0


def _improve_arguments(parser: argparse.ArgumentParser) -> None:
    add_workbench_arguments(parser)
    add_candidate_arguments(parser)
    parser.add_argument(
        "--min-gain",
        type=_fraction,
        default=MIN_GAIN,
        metavar="F",
        help="smallest relative fall of the held-out score to add an effect (default: %(default)s)",
    )
    parser.add_argument("--max-steps", type=whole_number(1), default=None, metavar="N", help="add at most N effects")
    parser.add_argument(
        "--require-validation",
        action="store_true",
        help="add an effect only if it also lowers the --validate-on runs' score by --min-gain",
    )
    parser.add_argument(
        "--validate-by",
        choices=("replay", "figures"),
        default="replay",
        help="score the --validate-on runs by their replay (held-out errors) or by their manoeuvres sailed free "
        "(advance, tactical diameter, steady rate and speed loss, overshoots against the measured, each over its "
        "bound) in the rules that use them (default: %(default)s)",
    )
    parser.add_argument(
        "--allow-worse-validation",
        action="store_true",
        help="add an effect even if it raises the --validate-on runs' score by more than --min-gain "
        "(by default it is not added)",
    )
    parser.add_argument(
        "--report",
        type=Path,
        default=None,
        metavar="DIR",
        help="write report.md with its figures into DIR (default: no report)",
    )
    add_json_argument(parser, "the final model (as 'fit --json' does) and the ladder")
    add_preset_argument(parser, "the final model")


COMMAND = Command(
    "improve",
    description=(
        "Start from the model, add the missing effect with the lowest held-out error while it lowers the\n"
        "held-out score by at least --min-gain; print the error ladder and, with --report DIR, write a\n"
        "Markdown report with its figures."
    ),
    handler=run_improve,
    arguments=_improve_arguments,
    examples=WORKBENCH_EXAMPLES,
    examples_title=WORKBENCH_EXAMPLES_TITLE,
)
