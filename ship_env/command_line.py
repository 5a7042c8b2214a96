"""The ``ship-env`` command line (:func:`main`) and what its subcommands share: their declaration
and parser, argument types that name the bad value, and the options several commands take: the
output options checked before any work and the progress bar (``--ray-address`` is in
:mod:`ship_env.ray_cluster`).

Each subcommand's module declares it as a :class:`Command`, listed in :data:`SUBCOMMANDS`, and
reads its values with the types here; an argument type raises ``argparse.ArgumentTypeError``,
which argparse reports with the argument's name and exit status 2, and a handler raises
:class:`UsageError` for a value that is well formed but does not fit (:func:`main` reports it the
same way). :func:`main` imports only the chosen subcommand's module before it parses, so that
``ship-env --help`` and a mistyped option answer without loading the simulator, torch or the
workbench.
"""

from __future__ import annotations

import argparse
import importlib
import math
import sys
from collections.abc import Callable, Collection, Sequence
from dataclasses import dataclass
from pathlib import Path

#: Every subcommand in the order ``ship-env --help`` lists them: its line there, and where its
#: :class:`Command` is declared (``module:attribute``), imported only when it is chosen.
SUBCOMMANDS: dict[str, tuple[str, str]] = {
    "manoeuvre": ("sail the standard manoeuvres and print their IMO figures", "ship_env.manoeuvres.cli:COMMAND"),
    "fit": ("fit the model to measured logs and validate it leaving one run out", "ship_env.workbench.cli_fit:COMMAND"),
    "fit-mmg": (
        "fit the MMG standard's 3-DOF forces to measured logs by inverse dynamics, and sail the fit free",
        "ship_env.workbench.cli_fit_mmg:COMMAND",
    ),
    "compare": ("replay logs with a model and print its RMS errors", "ship_env.workbench.cli_compare:COMMAND"),
    "diagnose": ("rank the physical effects the model lacks", "ship_env.workbench.cli_diagnose:COMMAND"),
    "improve": (
        "add effects while the held-out error falls: the error ladder",
        "ship_env.workbench.cli_improve:COMMAND",
    ),
    "demo-logs": (
        "write simulated model-test logs, optionally with hidden effects, to try the workbench on",
        "ship_env.workbench.synthetic.demo_logs:COMMAND",
    ),
    "scale": (
        "Froude-scale a ship preset to another length (a model-scale fit to full scale, or back)",
        "ship_env.model.froude:COMMAND",
    ),
    "train": (
        "train a PPO, recurrent PPO (ppo_lstm) or SAC policy on an environment",
        "ship_env.rl.cli_train:COMMAND",
    ),
    "leaderboard": (
        "rank the classic autopilots and learned policies on fixed, seeded suites",
        "ship_env.leaderboard.cli:COMMAND",
    ),
    "identify-bench": (
        "compare the on-line identification methods (Perera, Nguyen, Song, Passenier) on the same logs",
        "ship_env.baselines.online_estimators.cli:COMMAND",
    ),
}


class UsageError(Exception):
    """A command-line value that is well formed but does not fit (the chosen ship, the file system)."""

    def __init__(self, argument: str, message: str) -> None:
        super().__init__(message)
        self.argument = argument


def add_command(
    subcommands: argparse._SubParsersAction,
    name: str,
    *,
    help: str,
    description: str,
    examples: Sequence[str],
    handler: Callable[[argparse.Namespace], int],
    examples_title: str = "examples",
) -> argparse.ArgumentParser:
    """Register subcommand ``name``: its description as written, its examples as the epilog; ``handler``
    runs it with the parsed arguments (``args.command_parser`` is this parser, for its errors)."""
    parser = subcommands.add_parser(
        name,
        help=help,
        description=description,
        epilog=f"{examples_title}:\n" + "\n".join(f"  {example}" for example in examples),
        formatter_class=argparse.RawDescriptionHelpFormatter,
        allow_abbrev=False,  # --suit is not --suite
    )
    parser.set_defaults(handler=handler, command_parser=parser)
    return parser


@dataclass(frozen=True)
class Command:
    """A ``ship-env`` subcommand, declared beside the code that runs it.

    Attributes:
        name: the word that picks it (``ship-env NAME``); its line in ``ship-env --help`` is in
            :data:`SUBCOMMANDS`.
        description: its ``--help`` text, as written (line breaks kept).
        examples: command lines shown at the end of its ``--help``.
        handler: runs it with the parsed arguments; returns the exit status.
        arguments: adds its arguments to its parser.
        examples_title: the heading of the examples.
    """

    name: str
    description: str
    examples: Sequence[str]
    handler: Callable[[argparse.Namespace], int]
    arguments: Callable[[argparse.ArgumentParser], None]
    examples_title: str = "examples"

    def register(self, subcommands: argparse._SubParsersAction) -> argparse.ArgumentParser:
        """Add the subcommand with its arguments to ``subcommands`` (:func:`add_command`)."""
        parser = add_command(
            subcommands,
            self.name,
            help=SUBCOMMANDS[self.name][0],
            description=self.description,
            examples=self.examples,
            handler=self.handler,
            examples_title=self.examples_title,
        )
        self.arguments(parser)
        return parser


def declared_command(name: str) -> Command:
    """The :class:`Command` of subcommand ``name``, its module imported."""
    module, attribute = SUBCOMMANDS[name][1].split(":")
    command: Command = getattr(importlib.import_module(module), attribute)
    return command


def build_parser(only: Collection[str] | None = None) -> argparse.ArgumentParser:
    """The ``ship-env`` parser: every subcommand with its arguments, or only those in ``only`` (the
    others by name and help line, their modules not imported)."""
    parser = argparse.ArgumentParser(
        prog="ship-env",
        allow_abbrev=False,
        description=(
            "Ship steering simulator (Passenier 1989; De Keizer / Van Leeuwen model): standard manoeuvres, "
            "and the measurement workbench (fit, compare, diagnose, improve)."
        ),
    )
    subcommands = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    for name, (line, _) in SUBCOMMANDS.items():
        if only is None or name in only:
            declared_command(name).register(subcommands)
        else:
            subcommands.add_parser(name, help=line, add_help=False)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Run ``ship-env`` with ``argv`` (default: the process's arguments); returns the exit status.

    The command line is parsed with only the chosen subcommand's module imported; the errors its
    handler may end with are imported after."""
    arguments = list(sys.argv[1:] if argv is None else argv)
    chosen = next((word for word in arguments if not word.startswith("-")), None)
    args = parse_command_line(build_parser(only=[chosen] if chosen in SUBCOMMANDS else []), arguments)
    args.argv = arguments  # the command line a written preset records
    from ship_env.extras import MissingExtra
    from ship_env.ray_cluster import RayUnavailable
    from ship_env.workbench import FitError, FormatError, LogError
    from ship_env.workbench.outputs import OutputError

    command_parser: argparse.ArgumentParser = args.command_parser
    try:
        handler: Callable[[argparse.Namespace], int] = args.handler
        return handler(args)
    except UsageError as error:
        command_parser.error(f"argument {error.argument}: {error}")
    except RayUnavailable as error:  # --backend ray: an address that does not answer, or one without Ray
        command_parser.error(f"argument --ray-address: {error}")
    except (LogError, FormatError, FitError, OutputError, MissingExtra) as error:
        print(f"ship-env {args.command}: error: {error}", file=sys.stderr)
        return 1


def parse_command_line(parser: argparse.ArgumentParser, argv: Sequence[str] | None) -> argparse.Namespace:
    """``argv`` parsed by ``parser``, whose subcommands :func:`add_command` registered; an argument no
    parser knows ends with the subcommand's usage (argparse's own ends with the top-level usage)."""
    args, unknown = parser.parse_known_args(argv)
    if unknown:
        command_parser: argparse.ArgumentParser = args.command_parser
        command_parser.error(f"unrecognized arguments: {' '.join(unknown)}")
    return args


# -- argument types -------------------------------------------------------------------------------
def number(
    what: str,
    *,
    minimum: float = -math.inf,
    maximum: float = math.inf,
    above: float | None = None,
    below: float | None = None,
) -> Callable[[str], float]:
    """An argument type: a finite number in [``minimum``, ``maximum``], and greater than ``above`` and
    less than ``below`` where given; otherwise "expected ``what``, got '...'"."""

    def parse(text: str) -> float:
        try:
            value = float(text)
        except ValueError:
            value = math.nan
        inside = math.isfinite(value) and minimum <= value <= maximum
        if not inside or (above is not None and value <= above) or (below is not None and value >= below):
            raise argparse.ArgumentTypeError(f"expected {what}, got {text!r}")
        return value

    return parse


#: An argument type: a finite number greater than zero.
positive_number = number("a positive number", above=0.0)


def whole_number(minimum: int) -> Callable[[str], int]:
    """An argument type: a whole number of at least ``minimum``."""
    kind = {0: "a non-negative whole number", 1: "a positive whole number"}.get(minimum, f"a whole number >= {minimum}")

    def parse(text: str) -> int:
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected {kind}, got {text!r}") from None
        if value < minimum:
            raise argparse.ArgumentTypeError(f"expected {kind}, got {text!r}")
        return value

    return parse


def ship_preset(text: str) -> str:
    """An argument type: a ship preset's name or a ship YAML file whose model builds; otherwise the
    reason, naming the file (and the field) that is missing or wrong."""
    from ship_env.model import ShipModel

    if text.endswith((".yaml", ".yml")) and not Path(text).is_file():
        raise argparse.ArgumentTypeError(f"{text}: no such ship file")
    try:
        ShipModel(text)
    except (OSError, TypeError, ValueError) as error:
        raise argparse.ArgumentTypeError(str(error)) from None
    return text


def name_list(kind: str, known: Collection[str]) -> Callable[[str], list[str]]:
    """An argument type: comma-separated names, each one of ``known`` (read when parsing, so a live
    registry may grow); otherwise "unknown ``kind`` '...'; known: ..."."""

    def parse(text: str) -> list[str]:
        names = [name.strip() for name in text.split(",") if name.strip()]
        unknown = [name for name in names if name not in known]
        if unknown or not names:
            raise argparse.ArgumentTypeError(
                f"unknown {kind} {', '.join(map(repr, unknown)) or repr(text)}; known: {', '.join(known)}"
            )
        return names

    return parse


# -- options several commands take ---------------------------------------------------------------
def add_plot_argument(parser: argparse.ArgumentParser, plots: str) -> None:
    """``--plot DIR``: write ``plots`` into DIR (checked before any work, e.g. by :func:`prepare_outputs`)."""
    parser.add_argument("--plot", type=Path, default=None, metavar="DIR", help=f"write {plots} into DIR")


def add_json_argument(parser: argparse.ArgumentParser, content: str) -> None:
    """``--json FILE``: write ``content`` to FILE as JSON (checked before any work, e.g. by :func:`prepare_outputs`)."""
    parser.add_argument("--json", type=Path, default=None, metavar="FILE", help=f"write {content} to FILE as JSON")


def add_progress_argument(parser: argparse.ArgumentParser) -> None:
    """``--no-progress``: no progress bar."""
    parser.add_argument("--no-progress", action="store_true", help="do not show the progress bar")


def prepare_outputs(plot: Path | None, json_file: Path | None) -> None:
    """Create the ``--plot`` folder and check the ``--json`` file's folder before any work is done."""
    if plot is not None:
        try:
            plot.mkdir(parents=True, exist_ok=True)
        except OSError as error:
            raise UsageError("--plot", f"cannot create folder {str(plot)!r}: {error.strerror}") from None
    if json_file is not None and not json_file.parent.is_dir():
        raise UsageError("--json", f"folder {str(json_file.parent)!r} does not exist")
