"""Parsing the ``ship-env`` command line: no abbreviated options, each subcommand's usage for its own
errors, and the leaderboard's ``--tracks`` / ``--no-tracks``."""

from __future__ import annotations

import argparse
import subprocess
import sys

import pytest

from ship_env.cli import main
from ship_env.command_line import build_parser
from ship_env.envs.tracks import TRACK_IDS
from ship_env.leaderboard.cli import chosen_spec


def _subcommand_parsers(parser: argparse.ArgumentParser) -> dict[str, argparse.ArgumentParser]:
    (subcommands,) = (action for action in parser._actions if isinstance(action, argparse._SubParsersAction))
    return dict(subcommands.choices)


def _error(argv: list[str], capsys: pytest.CaptureFixture[str]) -> str:
    with pytest.raises(SystemExit) as exit_info:
        main(argv)
    assert exit_info.value.code == 2
    return capsys.readouterr().err


def test_no_parser_takes_an_abbreviated_option():
    parser = build_parser()
    parsers = _subcommand_parsers(parser)
    assert {"manoeuvre", "fit", "compare", "diagnose", "improve", "demo-logs", "train", "leaderboard"} <= set(parsers)
    for name, subparser in {"ship-env": parser, **parsers}.items():
        assert subparser.allow_abbrev is False, name


@pytest.mark.parametrize(
    ("argv", "usage"),
    [
        (["leaderboard", "--suit", "quick"], "usage: ship-env leaderboard"),  # was taken as --suite
        (["leaderboard", "--sute", "quick"], "usage: ship-env leaderboard"),  # printed ship-env's usage
        (["manoeuvre", "--zig", "10/10"], "usage: ship-env manoeuvre"),
        (["fit", "logs", "--form", "f.yaml"], "usage: ship-env fit"),
    ],
)
def test_an_unknown_option_ends_with_its_subcommands_usage(argv, usage, capsys):
    err = _error(argv, capsys)
    assert err.startswith(usage)
    assert f"error: unrecognized arguments: {' '.join(argv[-2:])}" in err


def _leaderboard_spec(*options: str):
    return chosen_spec(build_parser().parse_args(["leaderboard", "--suite", "test", *options]))


def test_the_test_suite_sails_every_track_unless_no_tracks_says_otherwise():
    assert _leaderboard_spec().tracks == TRACK_IDS
    assert _leaderboard_spec("--tracks", "T2", "T5").tracks == ("T2", "T5")
    assert _leaderboard_spec("--no-tracks").tracks == ()


@pytest.mark.parametrize(
    ("options", "named"),
    [
        (["--tracks"], "argument --tracks: expected at least one argument"),  # dropped TrackFollow
        (["--tracks", "T1", "--no-tracks"], "argument --no-tracks: not allowed with argument --tracks"),
        (["--tracks", "T9"], "argument --tracks: invalid choice: 'T9'"),
    ],
)
def test_tracks_options_that_do_not_fit_are_refused_by_name(options, named, capsys):
    err = _error(["leaderboard", *options], capsys)
    assert err.startswith("usage: ship-env leaderboard")
    assert named in err


#: What a subprocess reports after ``ship-env ARGV``: its exit status and the heavy modules it imported.
_IMPORTED = """
import sys
from ship_env.command_line import main
try:
    main(sys.argv[1:])
except SystemExit as exit:
    heavy = (
        "numba", "scipy", "torch", "matplotlib", "pandas", "ship_env.model", "ship_env.manoeuvres",
        "ship_env.manoeuvres.trial", "ship_env.workbench", "ship_env.workbench.fitting.fit", "ship_env.rl",
    )
    print(exit.code, *[name for name in heavy if name in sys.modules], file=sys.stderr)
"""

#: The model (its effect registry, which ``--help`` lists and ``--effects`` checks), with numba and scipy.
_MODEL = {"numba", "scipy", "ship_env.model"}
#: The model and the light part of the workbench (``ship_env.workbench.defaults``, ``.outputs``, ``.parallel``).
_WORKBENCH_ARGUMENTS = {*_MODEL, "ship_env.workbench"}
#: The model and the manoeuvres' package (``ship_env.manoeuvres.cli``), none of its manoeuvres.
_MANOEUVRE_ARGUMENTS = {*_MODEL, "ship_env.manoeuvres"}


@pytest.mark.parametrize(
    ("argv", "status", "imported"),
    [
        (["--help"], "0", set()),  # the subcommands by their help lines: nothing of theirs imported
        (["nope"], "2", set()),
        (["leaderboard", "--bad"], "2", _MODEL),  # its suites, not torch nor the plots
        (["leaderboard", "--help"], "0", _MODEL),
        # neither pandas nor matplotlib nor the fitting (once about 2 s on an idle machine, all the workbench)
        (["manoeuvre", "--help"], "0", _MANOEUVRE_ARGUMENTS),
        (["manoeuvre", "--bad"], "2", _MANOEUVRE_ARGUMENTS),
        (["manoeuvre", "--zigzag", "0/10"], "2", _MANOEUVRE_ARGUMENTS),
        *(([command, "--help"], "0", _WORKBENCH_ARGUMENTS) for command in ("fit", "compare", "diagnose", "improve")),
        *(
            ([command, "x", "--bad"], "2", _WORKBENCH_ARGUMENTS)
            for command in ("fit", "compare", "diagnose", "improve")
        ),
        (["improve", "x", "--add", "nope"], "2", _WORKBENCH_ARGUMENTS),
    ],
)
def test_the_command_line_is_parsed_before_the_heavy_imports(argv, status, imported):
    done = subprocess.run([sys.executable, "-c", _IMPORTED, *argv], capture_output=True, text=True, timeout=120)
    code, *modules = done.stderr.splitlines()[-1].split()
    assert code == status, done.stderr
    assert set(modules) <= imported, done.stderr


def test_import_ship_env_registers_the_environments_and_loads_the_model_when_asked():
    code = (
        "import sys, gymnasium, ship_env\n"
        "assert 'ship_env.model' not in sys.modules and 'ship_env/CourseChange-v0' in gymnasium.registry\n"
        "assert ship_env.ShipModel is ship_env.model.ShipModel is sys.modules['ship_env.model'].ShipModel\n"
        "from ship_env import Conditions, Simulator\n"
        "print(Simulator.__name__, Conditions.__name__)\n"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert done.stdout.split() == ["Simulator", "Conditions"], done.stderr


def test_import_ship_env_workbench_loads_a_module_when_one_of_its_names_is_asked_for():
    code = (
        "import pathlib, sys, ship_env.workbench as workbench\n"
        "assert not {'ship_env.model', 'scipy', 'pandas', 'matplotlib'} & set(sys.modules)\n"
        "import ship_env.workbench.deciding.improve  # imports fitting.fit and deciding.diagnose\n"
        "from ship_env.workbench import FitError, compare, diagnose, fit, improve, reporting\n"
        "modules = {'compare': 'judging.compare', 'diagnose': 'deciding.diagnose', 'fit': 'fitting.fit',\n"
        "           'improve': 'deciding.improve'}\n"
        "for name, module in modules.items():\n"
        "    assert getattr(workbench, name) is sys.modules['ship_env.workbench.' + module].__dict__[name]\n"
        "assert FitError is sys.modules['ship_env.workbench.fitting.fit'].FitError\n"
        "assert reporting.__name__ == 'ship_env.workbench.reporting'\n"
        "here = {path.stem for path in pathlib.Path(workbench.__file__).parent.iterdir()}\n"
        "assert not here & set(workbench.__all__), here & set(workbench.__all__)  # no name shadows a module\n"
        "try:\n"
        "    import ship_env.workbench.tables  # the flat workbench's path\n"
        "except ModuleNotFoundError:\n"
        "    pass\n"
        "else:\n"
        "    raise AssertionError('ship_env.workbench.tables')\n"
        "names = [getattr(workbench, name) for name in workbench.__all__]  # none of them a module\n"
        "print(len(names), sum(not isinstance(value, type(sys)) for value in names))\n"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    count, not_modules = done.stdout.split()
    assert int(count) > 30 and not_modules == count, done.stderr
