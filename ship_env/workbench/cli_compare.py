"""``ship-env compare``: measured runs replayed by a model as it is (no fitting), with its RMS errors
and, for a fit's model, how far the runs lie from the data it was fitted to.

Declared as :data:`COMMAND`, with the arguments and steps the workbench's commands share
(:mod:`ship_env.workbench.cli`); the replay is imported only when the command runs.
"""

from __future__ import annotations

import argparse

from ship_env.command_line import Command, add_plot_argument
from ship_env.workbench.cli import (
    WORKBENCH_EXAMPLES,
    WORKBENCH_EXAMPLES_TITLE,
    add_workbench_arguments,
    model_line,
    print_inside_outside,
    start_command,
)


def run_compare(args: argparse.Namespace) -> int:
    """``ship-env compare``: replay the logs with a model as it is (no fitting)."""
    from ship_env.workbench import compare, plot_comparison
    from ship_env.workbench.judging.coverage import check_coverage, fitted_coverage
    from ship_env.workbench.reporting.tables import coverage_sections, error_table, sections_text

    setup, options, runs = start_command(args, fitting=False)
    logs = [*runs.logs, *runs.validation]
    print(model_line(setup, logs))
    comparison = compare(setup, logs, options.initial_window)
    print(error_table(comparison.errors, options.error_scales, comparison.pooled).text())
    print_inside_outside("RMS errors", logs, comparison.simulated, runs, options.error_scales)
    coverage = fitted_coverage(args.parameters) if args.parameters is not None else None
    if coverage is not None:
        checks = [check_coverage(log, coverage, setup.model) for log in logs]
        sections = coverage_sections("runs", coverage, checks, logs, comparison.simulated, options.error_scales)
        print(sections_text(sections))
    if args.plot is not None:
        plot_comparison(comparison, args.plot, f"{setup.model.ship.name}: {', '.join(setup.model.effects)}")
        print(f"\nplots written to {args.plot}/")
    return 0


def _compare_arguments(parser: argparse.ArgumentParser) -> None:
    add_workbench_arguments(parser, fitting=False)
    add_plot_argument(parser, "a PNG per run")


COMMAND = Command(
    "compare",
    description=(
        "Replay each run with the model as it is (preset values, or a fit's JSON), from its measured\n"
        "initial state, and print RMS heading, rate-of-turn, position and track errors per run and pooled."
    ),
    handler=run_compare,
    arguments=_compare_arguments,
    examples=WORKBENCH_EXAMPLES,
    examples_title=WORKBENCH_EXAMPLES_TITLE,
)
