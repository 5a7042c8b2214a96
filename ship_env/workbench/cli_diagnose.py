"""``ship-env diagnose``: the model fitted and validated, then the effects it lacks ranked by the
evidence in its residuals and the held-out error after adding each.

Declared as :data:`COMMAND`, with the arguments and steps the workbench's commands share
(:mod:`ship_env.workbench.cli`); the workbench's fitting is imported only when the command runs.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from ship_env.command_line import Command
from ship_env.workbench.cli import (
    WORKBENCH_EXAMPLES,
    WORKBENCH_EXAMPLES_TITLE,
    add_candidate_arguments,
    add_workbench_arguments,
    fitted_terms,
    model_line,
    print_validation,
    print_validation_runs,
    start_command,
)
from ship_env.workbench.outputs import claim_file


def run_diagnose(args: argparse.Namespace) -> int:
    """``ship-env diagnose``: rank the effects the model lacks."""
    from ship_env.workbench import cross_validate, diagnose
    from ship_env.workbench.deciding.diagnose import past_the_library
    from ship_env.workbench.deciding.signals import plot_signals
    from ship_env.workbench.reporting.tables import diagnosis_table

    if args.signals_plot is not None:
        claim_file(args.signals_plot, args.force, "--plot")
    setup, options, runs = start_command(args)
    logs = runs.logs
    print(model_line(setup, logs))
    validation = cross_validate(
        setup, logs, fitted_terms(args, setup, logs), options, groups=runs.groups, validate_on=runs.validation
    )
    print_validation(validation, options.error_scales)
    print_validation_runs(validation, runs, options.error_scales)
    diagnosis = diagnose(validation, logs, options, args.candidates, args.refit)
    print(
        "\nmissing effects, best first (corr, var. expl.: residual evidence;\n"
        "score: held out after adding and refitting, (screened): after a brief refit only)"
    )
    print(diagnosis_table(diagnosis).text())
    beyond = past_the_library(diagnosis)
    if beyond:
        print(f"\n{beyond}")
    if args.signals_plot is not None and diagnosis.signals is not None:
        plot_signals(diagnosis.signals, args.signals_plot)
        words = diagnosis.signals.strongest.signal.words
        print(f"\nthe missing yaw acceleration against {words}: {args.signals_plot}")
    return 0


def _diagnose_arguments(parser: argparse.ArgumentParser) -> None:
    add_workbench_arguments(parser)
    add_candidate_arguments(parser)
    parser.add_argument(
        "--plot",
        dest="signals_plot",  # a file, not the folder the other commands' --plot names
        type=Path,
        default=None,
        metavar="FILE",
        help="draw the missing yaw acceleration against the signal it follows most into FILE (PNG); "
        "an existing FILE only with --force",
    )


COMMAND = Command(
    "diagnose",
    description=(
        "Fit and validate the model, then for each effect it lacks: the evidence in the residuals\n"
        "(correlation with the effect's regressors, variance explained) and the held-out error after\n"
        "adding it and refitting; best first."
    ),
    handler=run_diagnose,
    arguments=_diagnose_arguments,
    examples=WORKBENCH_EXAMPLES,
    examples_title=WORKBENCH_EXAMPLES_TITLE,
)
