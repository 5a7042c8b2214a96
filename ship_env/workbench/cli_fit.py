"""``ship-env fit``: the model fitted to measured runs, validated leaving one run out; its terms, errors
and, as asked, plots, the fit's JSON and a fitted preset.

Declared as :data:`COMMAND`, with the arguments and steps the workbench's commands share
(:mod:`ship_env.workbench.cli`); the workbench's fitting is imported only when the command runs.
"""

from __future__ import annotations

import argparse

from ship_env.command_line import Command, add_json_argument, add_plot_argument
from ship_env.workbench.cli import (
    WORKBENCH_EXAMPLES,
    WORKBENCH_EXAMPLES_TITLE,
    add_preset_argument,
    add_workbench_arguments,
    fitted_terms,
    model_line,
    print_inside_outside,
    print_validation,
    print_validation_runs,
    start_command,
    write_fitted_preset,
)


def run_fit(args: argparse.Namespace) -> int:
    """``ship-env fit``: fit the model to the logs, validate it leaving one run out."""
    from ship_env.workbench import cross_validate, fit_each_run, held_out_comparison, plot_comparison
    from ship_env.workbench.reporting.documents import fit_document, write_document
    from ship_env.workbench.reporting.tables import error_table

    setup, options, runs = start_command(args)
    logs = runs.logs
    keys = fitted_terms(args, setup, logs)
    print(model_line(setup, logs) + f"; fitted terms: {', '.join(keys)}")
    validation = cross_validate(setup, logs, keys, options, groups=runs.groups, validate_on=runs.validation)
    print_validation(validation, options.error_scales)
    print_inside_outside("held-out RMS errors", logs, validation.replays, runs, options.error_scales)
    print_validation_runs(validation, runs, options.error_scales)
    if args.per_run:
        fits = fit_each_run(validation.fit.setup, logs, keys, options)
        print("\neach run fitted on its own (in-sample)")
        print(error_table([f.errors[0] for f in fits], options.error_scales).text())
    if args.plot is not None:
        plot_comparison(held_out_comparison(validation, logs), args.plot, "cross-validated fit", options.workers)
        print(f"\nplots written to {args.plot}/")
    if args.json is not None:
        write_document(fit_document(validation, options.error_scales, runs.checks, logs), args.json)
        print(f"fit written to {args.json}")
    write_fitted_preset(args, validation, runs)
    return 0


def _fit_arguments(parser: argparse.ArgumentParser) -> None:
    add_workbench_arguments(parser)
    parser.add_argument("--per-run", action="store_true", help="also fit each run on its own (in-sample)")
    add_plot_argument(parser, "a held-out PNG per run")
    add_json_argument(parser, "the fit")
    add_preset_argument(parser, "the fitted model")


COMMAND = Command(
    "fit",
    description=(
        "Fit the model's parameters to measured runs by output-error simulation (the measured\n"
        "rudder, propeller rate and wind in; heading, rate of turn, speed and track out), print\n"
        "them with standard errors, the in-sample errors and the held-out errors of\n"
        "leave-one-run-out cross-validation."
    ),
    handler=run_fit,
    arguments=_fit_arguments,
    examples=WORKBENCH_EXAMPLES,
    examples_title=WORKBENCH_EXAMPLES_TITLE,
)
