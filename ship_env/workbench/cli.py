"""What the workbench's commands (``fit``, ``compare``, ``diagnose``, ``improve``: one module each,
``cli_fit`` and so on) share: their arguments and examples, the model, runs and fit options each
starts from, and the tables more than one of them prints.

Only what the parsers read is imported here (the model's effects and ships, the workbench's
:mod:`~ship_env.workbench.defaults`); the steps import the workbench's fitting and tables when a
command runs, so that ``--help`` and a bad argument answer before pandas, matplotlib and scipy's
optimisers load.
"""

from __future__ import annotations

import argparse
import math
import shlex
import sys
import textwrap
import warnings
from collections.abc import Callable, Sequence
from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING

from ship_env.command_line import UsageError, positive_number, whole_number
from ship_env.model import EFFECTS, REQUIRED_EFFECTS, ShipModel, list_ships
from ship_env.model.arguments import EFFECT_SETS, effect_names, effect_set, ship_name
from ship_env.text_table import WIDTH
from ship_env.workbench.defaults import MIN_GAIN, MIN_SEGMENT, NUISANCE, ON_REQUEST, PAIR_WIDTH
from ship_env.workbench.fitting.parallel import usable_cores
from ship_env.workbench.outputs import claim_file, claim_folder

if TYPE_CHECKING:
    from ship_env.workbench import CrossValidation, ErrorScales, FitOptions, Log, ReplayModel
    from ship_env.workbench.deciding.rivals import FormSpread
    from ship_env.workbench.fitting.inverse_dynamics import Identification
    from ship_env.workbench.fitting.replay import Simulated
    from ship_env.workbench.fitting.runs import WorkbenchRuns

#: The ship the workbench's commands assume without ``--ship`` (and without ``--parameters``).
WORKBENCH_SHIP = "esso_osaka_model"
#: ``--model`` also takes "base": the required effects only, the speed-scheduled Nomoto ship (2.54).
WORKBENCH_MODELS: dict[str, Callable[[str], ShipModel]] = {
    "base": lambda ship: ShipModel(ship, REQUIRED_EFFECTS),
    **EFFECT_SETS,
}


def _workbench_model(text: str) -> str:
    """Check a workbench model name (base, minimal, default, full) or a comma-separated effect list."""
    return text if text in WORKBENCH_MODELS else effect_set(text)


def _names(text: str) -> list[str]:
    """Read a comma-separated list of names (terms, nuisance terms)."""
    return [name.strip() for name in text.split(",") if name.strip()]


_whole_number = whole_number(1)
_count = whole_number(0)


def _workbench_setup(args: argparse.Namespace) -> ReplayModel:
    """The model to start from: ``--model`` on ``--ship``, or a fit's document (``--parameters``) on its hull;
    plus ``--add``."""
    from ship_env.workbench.reporting.documents import DocumentError, read_fitted_model
    from ship_env.workbench.reporting.presets import preset_replay_model

    added = tuple(name for names in args.add for name in names)
    if args.parameters is not None:
        try:
            fitted = read_fitted_model(args.parameters, args.ship, added)
        except DocumentError as error:
            raise UsageError("--parameters", str(error)) from None
        if fitted.note:
            print(f"ship-env {args.command}: warning: {fitted.note}", file=sys.stderr)
        return fitted.setup
    ship = args.ship or WORKBENCH_SHIP
    try:
        if args.model in WORKBENCH_MODELS:
            model = WORKBENCH_MODELS[args.model](ship)
        else:
            model = ShipModel(ship, args.model.split(","))
        return preset_replay_model(model.with_effects(*added) if added else model)
    except (ValueError, TypeError) as error:
        raise UsageError("--add" if args.add else "--model", str(error)) from None


def _workbench_options(args: argparse.Namespace, setup: ReplayModel, logs: Sequence[Log]) -> FitOptions:
    """The fit options: scale-free error scales for the runs, each channel given in degrees or metres overriding."""
    from ship_env.workbench import ErrorScales, FitOptions

    nuisance = tuple(getattr(args, "nuisance", ()))
    unknown = [name for name in nuisance if name not in NUISANCE]
    if unknown:
        raise UsageError("--nuisance", f"unknown nuisance terms {unknown}; known: {', '.join(NUISANCE)}")
    scales = ErrorScales.for_runs(setup.model, logs)
    given = {
        "heading": None if args.heading_scale is None else math.radians(args.heading_scale),
        "rate_of_turn": None if args.rate_scale is None else math.radians(args.rate_scale),
        "position": args.position_scale,
        "speed_error": args.speed_scale,
    }
    scales = replace(scales, **{name: value for name, value in given.items() if value is not None})
    return FitOptions(scales=scales, nuisance=nuisance, initial_window=args.window, workers=getattr(args, "workers", 1))


def _workbench_logs(args: argparse.Namespace, paths: Sequence[Path] | None = None) -> list[Log]:
    """The logs (``args.logs`` or ``paths``), each loader warning printed as one line on stderr."""
    from ship_env.workbench import LogWarning, load_logs
    from ship_env.workbench.logs.logs import every_nth

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", LogWarning)
        logs = load_logs(args.logs if paths is None else paths, args.format, args.service_speed)
    for warning in caught:
        print(f"ship-env {args.command}: warning: {warning.message}", file=sys.stderr)
    return [every_nth(log, args.every or 1) for log in logs]


def _workbench_runs(args: argparse.Namespace, setup: ReplayModel) -> WorkbenchRuns:
    """Load the logs, check them against the model's envelope, cut or group them as asked; print what was done."""
    from ship_env.workbench.fitting.runs import GroupingError, prepare_runs
    from ship_env.workbench.reporting.tables import envelope_line, envelope_table

    logs = _workbench_logs(args)
    validation = _workbench_logs(args, args.validate_on) if args.validate_on else []
    model = setup.model
    try:
        runs = prepare_runs(logs, model, args.inside, args.min_segment, args.group_by, validation)
    except GroupingError as error:
        raise UsageError("--group-by", str(error)) from None
    print(f"envelope of {model.ship.name} with {', '.join(model.effects)}: {envelope_line(model.envelope)}")
    print(envelope_table(list(runs.checks.values())).text())
    for message in runs.messages:
        print(message)
    return runs


def print_inside_outside(
    title: str, logs: Sequence[Log], replays: Sequence[Simulated], runs: WorkbenchRuns, scales: ErrorScales
) -> None:
    """RMS errors over the samples inside and outside the envelope, where a run has both."""
    from ship_env.workbench.fitting.errors import pooled
    from ship_env.workbench.fitting.runs import inside_outside_errors
    from ship_env.workbench.reporting.tables import error_table

    for where, errors in inside_outside_errors(logs, replays, runs.checks).items():
        print(f"\n{title}, over the samples {where} the envelope")
        print(error_table(errors, scales, pooled(errors)).text())


def fitted_terms(args: argparse.Namespace, setup: ReplayModel, logs: Sequence[Log]) -> list[str]:
    """The model's default terms for the logs, plus ``--free``, less ``--fix``."""
    from ship_env.workbench.fitting.terms import default_terms

    defaults = default_terms(setup.model.effects, logs)
    keys = defaults + [key for key in args.free if key not in defaults]
    unknown = [key for key in args.fix if key not in keys]
    if unknown:
        raise UsageError("--fix", f"{', '.join(unknown)} not among the fitted terms {', '.join(keys)}")
    return [key for key in keys if key not in args.fix]


def _claim_outputs(args: argparse.Namespace) -> None:
    """Check every output before any work: no user's file overwritten, no foreign folder written into."""
    if getattr(args, "json", None) is not None:
        claim_file(args.json, args.force, "--json")
    if getattr(args, "preset", None) is not None:
        claim_file(args.preset, args.force, "--preset")
    for option in ("plot", "report"):
        if getattr(args, option, None) is not None:
            claim_folder(getattr(args, option), args.force, f"--{option}")


def print_validation(validation: CrossValidation, scales: ErrorScales) -> None:
    from ship_env.workbench.reporting.tables import error_table, estimate_table

    fitted = validation.fit
    print(f"\nfitted terms ({fitted.evaluations} evaluations; {fitted.message})")
    if fitted.warnings:
        print(f"fit: {fitted.warnings_line()}")
    print(estimate_table(validation).text())
    print("\nin-sample RMS errors (fitted to all runs)")
    print(error_table(fitted.errors, scales, fitted.pooled).text())
    print("\nheld-out RMS errors (each run replayed by the fit to the other runs, from its measured start)")
    print(error_table(validation.held_out, scales, validation.pooled).text())


def model_line(setup: ReplayModel, logs: Sequence[Log]) -> str:
    model = setup.model
    return f"{model.ship.name}: {len(logs)} runs; effects: {', '.join(model.effects)}"


def print_validation_runs(validation: CrossValidation, runs: WorkbenchRuns, scales: ErrorScales) -> None:
    """The --validate-on runs' errors under the all-run fit, whole and inside/outside the envelope."""
    from ship_env.workbench.reporting.tables import error_table, validation_coverage_text

    if not validation.validation:
        return
    print("\nvalidation runs (another kind, never fitted), replayed by the fit to all runs")
    print(error_table(validation.validation, scales, validation.pooled_validation).text())
    print_inside_outside("validation runs", validation.validation_logs, validation.validation_replays, runs, scales)
    if validation.coverage is not None:
        print(validation_coverage_text(validation, scales))


def start_command(args: argparse.Namespace, fitting: bool = True) -> tuple[ReplayModel, FitOptions, WorkbenchRuns]:
    """A workbench command's model, runs and options (the error scales printed), its outputs claimed first.

    A command that fits (``fitting``) sails the model with the speed loss on where a log measures the
    speed (:func:`~.terms.with_speed_output`), and says what the logs leave it unable to know.
    """
    from ship_env.workbench.fitting.terms import not_identified, with_speed_output

    setup = _workbench_setup(args)
    _claim_outputs(args)
    runs = _workbench_runs(args, setup)
    options = _workbench_options(args, setup, runs.logs)
    print(textwrap.fill(f"error scales: {options.error_scales.describe()}", WIDTH, subsequent_indent="  "))
    if fitting:
        setup = with_speed_output(setup, runs.logs)
        for words in not_identified(setup.model, runs.logs):
            print(f"not identified: {words}")
        if args.every is None:
            _print_coarser_step(runs.logs, setup.model, screens=args.command in ("diagnose", "improve"))
    return setup, options, runs


def _print_coarser_step(logs: Sequence[Log], model: ShipModel, screens: bool) -> None:
    """Where the runs sample the ship's motion more densely than a fit needs, the ``--every`` that fits them faster
    (and, for a command that ``screens`` candidates, that it screens them at that step already)."""
    from ship_env.workbench.fitting.replay import SAMPLES_PER_LENGTH, coarser_step, samples_per_length

    step = coarser_step(logs, model)
    if step > 1:
        densities = [samples_per_length(log, model) for log in logs]
        print(
            textwrap.fill(
                f"sampling: the runs hold {min(densities):.0f} to {max(densities):.0f} samples per ship length sailed; "
                f"--every {step} keeps {SAMPLES_PER_LENGTH:.0f} or more (five or more in each of a zig-zag's rudder "
                f"moves) and fits in about 1/{step} of the time"
                + ("; the candidates are screened at that step, and confirmed on every sample" if screens else ""),
                WIDTH,
                subsequent_indent="  ",
            )
        )


def write_fitted_preset(
    args: argparse.Namespace,
    validation: CrossValidation,
    runs: WorkbenchRuns,
    form_spread: Callable[[], FormSpread | None] | None = None,
) -> None:
    """``--preset FILE``: the fitted model as a ship preset (claimed before any work), sailed by its effects or, where
    the runs reach the hard-over rudder and it predicts their manoeuvres better, by the MMG standard's forces fitted by
    inverse dynamics (:mod:`~ship_env.workbench.judging.dynamics_choice`). Where its effects sail it, ``form_spread``
    (``improve``'s: :func:`~ship_env.workbench.deciding.rivals.form_spread`) gives what the forms the runs could not
    rule out would sail, printed and kept in the preset (``fitted.rival_forms``)."""
    from ship_env.manoeuvres.extrapolation import hard_over_turn_beyond
    from ship_env.workbench.judging.dynamics_choice import choose_dynamics
    from ship_env.workbench.reporting.presets import preset_document, with_dynamics, write_preset

    if args.preset is None:
        return
    command = "ship-env " + shlex.join(args.argv)
    document = preset_document(validation, runs.logs, command, args.preset.stem, runs.validation)
    choice = choose_dynamics(validation, runs.logs, getattr(args, "min_gain", MIN_GAIN))  # improve's, or its default
    if choice is not None:
        print("\n" + "\n".join(choice.lines()))
        if choice.chosen and choice.identified is not None:
            document = with_dynamics(document, choice.identified, command, choice.summary())
            if runs.validation:
                _print_validation_sailed_by_mmg(validation, choice.identified, runs.validation)
        else:  # the evidence kept with the preset: why its effects sail it
            document["fitted"] = {**document["fitted"], "dynamics": choice.summary()}
    spread = form_spread() if form_spread is not None and (choice is None or not choice.chosen) else None
    if spread is not None:
        print(f"\n{spread.text()}")
        document["fitted"] = {**document["fitted"], "rival_forms": spread.summary()}
    write_preset(document, args.preset)
    print(f"fitted preset written to {args.preset} (sail it: ShipModel({str(args.preset)!r}), --ship {args.preset})")
    try:
        beyond = hard_over_turn_beyond(ShipModel(args.preset))
    except FloatingPointError as error:
        print(f"  its hard-over turning circle leaves the model's validity: {error}")
        return
    if beyond:
        print(
            f"  its hard-over turning circle sails beyond the fitted runs: {'; '.join(beyond)}; its figures rest on "
            f"the model's form there (ship-env manoeuvre --ship {args.preset})"
        )


def _print_validation_sailed_by_mmg(
    validation: CrossValidation, identified: Identification, validation_logs: Sequence[Log]
) -> None:
    """The ``--validate-on`` runs sailed free by the MMG model the preset sails (the tables above sail its effects),
    measured against predicted, +- the jackknife's spread, and where they disagree."""
    from ship_env.workbench.judging.free_running import disagreements, free_running_table, held_out_mmg_sailing

    results = held_out_mmg_sailing(validation.fit.setup, identified, [], validation_logs)
    if not results:
        return
    print("  the --validate-on runs sailed free by the MMG model the preset sails (+- its jackknife's spread):")
    print(free_running_table(results).text())
    for line in disagreements(results, None):
        print(f"  disagrees: {line}")


# -- the arguments and examples ---------------------------------------------------------------
def add_log_arguments(parser: argparse.ArgumentParser) -> None:
    """The logs and their ``--format``."""
    parser.add_argument("logs", nargs="+", type=Path, metavar="LOG", help="CSV or Parquet logs, or folders of them")
    parser.add_argument(
        "--format",
        default=None,
        metavar="NAME",
        help="log format: esso_osaka, standard, or a YAML file (default: the built-in one the columns fit)",
    )


def add_validation_argument(parser: argparse.ArgumentParser, scored: str) -> None:
    """``--validate-on``: runs never fitted, ``scored`` as the command says."""
    parser.add_argument(
        "--validate-on",
        nargs="+",
        type=Path,
        default=None,
        metavar="LOG",
        help=f"runs of another kind {scored} and never fitted, e.g. fit on zig-zags, validate on turning runs",
    )


def add_workbench_arguments(parser: argparse.ArgumentParser, fitting: bool = True) -> None:
    """The arguments the workbench's commands share: logs, format, ship, model, error scales."""
    add_log_arguments(parser)
    parser.add_argument(
        "--ship",
        type=ship_name,
        default=None,
        metavar="NAME",
        help=f"ship preset ({', '.join(list_ships())}) or a YAML file (default: {WORKBENCH_SHIP}; with "
        "--parameters, the hull the fit was made on; another hull is refused)",
    )
    parser.add_argument(
        "--parameters",
        type=Path,
        default=None,
        metavar="FILE",
        help="start from the fitted model of 'ship-env fit --json FILE' or 'improve --json FILE' (replaces "
        "--model; --add adds to it)",
    )
    parser.add_argument(
        "--model",
        type=_workbench_model,
        default="base",
        metavar="SET",
        help=(
            f"starting effects: {', '.join(WORKBENCH_MODELS)} (base: the speed-scheduled Nomoto ship, "
            f"{' + '.join(REQUIRED_EFFECTS)}), or a comma-separated list of effects (default: %(default)s)"
        ),
    )
    parser.add_argument(
        "--add",
        type=effect_names,
        action="append",
        default=[],
        metavar="EFFECT[,EFFECT]",
        help=f"effects to add to the model: {', '.join(EFFECTS)}",
    )
    if fitting:
        parser.add_argument(
            "--free",
            type=_names,
            default=[],
            metavar="TERM[,TERM]",
            help="more terms to fit besides the effects' defaults, e.g. yaw.linear",
        )
        parser.add_argument("--fix", type=_names, default=[], metavar="TERM[,TERM]", help="default terms to hold")
        parser.add_argument(
            "--nuisance",
            type=_names,
            default=[],
            metavar="NAME[,NAME]",
            help=f"per-run nuisance terms fitted with the model: {', '.join(NUISANCE)} (initial-state offsets)",
        )
        parser.add_argument(
            "--workers",
            type=_whole_number,
            default=usable_cores(),
            metavar="N",
            help="processes that run independent fits side by side; 1: one after another, same results "
            "(default: the CPU cores this process may run on)",
        )
    parser.add_argument(
        "--service-speed",
        type=positive_number,
        default=None,
        metavar="M/S",
        help="service speed for logs without a speed channel (default: the ship's)",
    )
    parser.add_argument(
        "--every",
        type=_whole_number,
        default=None,
        metavar="N",
        help="use every N-th sample (default: every sample; a fit says which N keeps what it needs where the runs are "
        "sampled more densely)",
    )
    parser.add_argument(
        "--inside",
        action="store_true",
        help="fit and score only the stretches of each run inside the model's envelope, each replayed from its "
        "measured state",
    )
    parser.add_argument(
        "--min-segment",
        type=positive_number,
        default=MIN_SEGMENT,
        metavar="S",
        help="with --inside, the shortest stretch kept, s (default: %(default)s)",
    )
    add_validation_argument(parser, "(or a named set) scored by the fit to LOGS")
    parser.add_argument(
        "--group-by",
        default=None,
        metavar="folder|REGEX",
        help="leave out groups of runs instead of single runs: by folder, or by the part of the run's name "
        "a regular expression matches (its first group if it has one)",
    )
    parser.add_argument(
        "--force",
        action="store_true",
        help="overwrite an existing --json or --preset file, or write into a --plot/--report folder the workbench "
        "did not write",
    )
    parser.add_argument(
        "--window",
        type=positive_number,
        default=None,
        metavar="S",
        help="seconds at a run's start from which its initial state is estimated (default: the time the ship "
        "takes to sail half its length at the run's service speed, at least 2 s and at most half the run)",
    )
    parser.add_argument(
        "--heading-scale",
        type=positive_number,
        default=None,
        metavar="DEG",
        help="heading error worth one score unit (default: 1 deg)",
    )
    parser.add_argument(
        "--rate-scale",
        type=positive_number,
        default=None,
        metavar="DEG/S",
        help="rate-of-turn error worth one score unit (default: 1 deg per ship length sailed, (1 deg) x U / L, "
        "U the runs' mean speed through the water, L the ship's length)",
    )
    parser.add_argument(
        "--position-scale",
        type=positive_number,
        default=None,
        metavar="M",
        help="track error worth one score unit (default: L / 30, a thirtieth of the ship's length)",
    )
    parser.add_argument(
        "--speed-scale",
        type=positive_number,
        default=None,
        metavar="M/S",
        help="speed error worth one score unit (default: 1.7 %% of the mean speed, the heading's 1 deg across the "
        "velocity)",
    )


def add_candidate_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "--candidates",
        type=effect_names,
        default=None,
        metavar="EFFECT[,EFFECT]",
        help="effects that may be added (default: every effect the logs can show, less those tried only where "
        f"named here: {', '.join(ON_REQUEST)})",
    )
    parser.add_argument(
        "--refit",
        type=_whole_number,
        default=None,
        metavar="K",
        help="refit only the K candidates with the most residual evidence (default: all)",
    )
    parser.add_argument(
        "--pairs",
        type=_count,
        default=PAIR_WIDTH,
        metavar="K",
        help=f"where no single effect pays, try pairs of the K candidates with most evidence "
        f"(0: never; default: {PAIR_WIDTH})",
    )


#: The workbench commands' examples: on simulated logs with hidden effects (``ship-env demo-logs``),
#: then on measured ones, the Esso Osaka model tests in their built-in format.
WORKBENCH_EXAMPLES = (
    "ship-env demo-logs demo --hidden propeller_slipstream,rudder_offset   # what is hidden: demo/README.txt",
    "ship-env fit demo/zigzag --validate-on demo/turning",
    "ship-env diagnose demo/zigzag",
    "ship-env fit demo/zigzag --add propeller_slipstream,rudder_offset --json fit.json",
    "ship-env compare demo/turning --parameters fit.json --plot plots/",
    "ship-env improve demo/zigzag --validate-on demo/turning --report report/",
    "ship-env improve ../shared/data/esso_osaka/zigzag --report esso_report/   # measured runs, where they are",
)


def add_preset_argument(parser: argparse.ArgumentParser, content: str) -> None:
    parser.add_argument(
        "--preset",
        type=Path,
        default=None,
        metavar="FILE",
        help=f"write {content} to FILE as a ship preset (YAML) the simulators and environments sail "
        "(--ship FILE), with standard errors, the logs' hashes and the data's range as validity envelope",
    )


#: The heading of the workbench's examples in its four commands' ``--help``.
WORKBENCH_EXAMPLES_TITLE = "examples, on demo logs (the last on measured ones)"
