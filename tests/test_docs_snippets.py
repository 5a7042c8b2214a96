"""Every snippet of the README and the documentation runs as written after the README's set-up.

The pages: README.md and docs/**/*.md but the results pages (docs/results/, which state what long runs
wrote). Each fenced ``python`` block runs in a fresh interpreter (nothing imported before it: an
environment id works without ``import ship_env``) and prints only labelled output (no bare arrays,
no ``np.float64(...)``). Each shell command runs from the repository after the set-up, without an
activated environment, so it starts with ``.venv/bin/``; every ``ship-env`` command, in a block or
in the text, is one the parser accepts; the quick ones run here, the long ones (the main job, the
workbench's walk-through, the RL quickstart's training) under the slow marker, the RL quickstart in
the default run with fewer steps. The set-up itself is tests/test_readme.py's and CI's.
"""

from __future__ import annotations

import os
import re
import shlex
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from ship_env.command_line import build_parser

ROOT = Path(__file__).resolve().parents[1]
PAGES = [ROOT / "README.md", *sorted(p for p in (ROOT / "docs").rglob("*.md") if "results" not in p.parts)]
#: ``_build`` holds the built pages' sources copied; never a page of its own.
PAGES = [page for page in PAGES if "_build" not in page.parts]
#: The README's set-up and its test run, run by CI and compared with it by tests/test_readme.py.
SET_UP = ("python3 -m venv .venv", ".venv/bin/python -m pytest", ".venv/bin/sphinx-build")
#: The subcommands whose documented commands run in the default test run, in their page's order (the
#: others under the slow marker; ``train`` only as far as the parser).
QUICK_COMMANDS = ("demo-logs", "diagnose", "manoeuvre", "scale")
#: The RL quickstart's training, and the fewer steps the default run trains it for.
FULL_TRAINING, SHORT_TRAINING = "total_timesteps=20_000", "total_timesteps=256"


def _blocks(language: str) -> list[tuple[str, str]]:
    """(where, text) of every fenced block in ``language`` on the pages."""
    found = []
    for page in PAGES:
        text = page.read_text()
        for match in re.finditer(rf"^```{language}\n(.*?)^```$", text, flags=re.S | re.M):
            line = text[: match.start()].count("\n") + 1
            found.append((f"{page.relative_to(ROOT)}:{line}", match[1]))
    return found


def _shell_commands() -> list[tuple[str, str]]:
    """(where, command) of every line of the pages' shell blocks, continuations joined, comments dropped."""
    commands = []
    for where, block in _blocks("(?:bash|sh|console)"):
        for line in block.replace("\\\n", " ").splitlines():
            command = line.split("  #")[0].split(" # ")[0].strip()
            if command:
                commands.append((where, command))
    return commands


def _inline_spans(start: str) -> list[tuple[str, str]]:
    """(page, span) of every inline code span of the pages that begins with ``start``."""
    spans = []
    for page in PAGES:
        text = re.sub(r"^```.*?^```$", "", page.read_text(), flags=re.S | re.M).replace("\n", " ")
        spans += [
            (str(page.relative_to(ROOT)), span) for span in re.findall(r"`([^`]+)`", text) if span.startswith(start)
        ]
    return spans


PYTHON_BLOCKS = _blocks("python")
SHELL_COMMANDS = _shell_commands()
#: ``ship-env`` command lines: the shell blocks' (as run) and the text's (named in a sentence).
SHIP_ENV_COMMANDS = [
    (where, command.removeprefix(".venv/bin/"))
    for where, command in SHELL_COMMANDS
    if command.startswith(".venv/bin/ship-env ")
] + [(where, span.removeprefix(".venv/bin/")) for where, span in _inline_spans(".venv/bin/ship-env ")]
#: The text's whole command lines; not a template (``fit|improve ...``, ``--ship FILE``, ``LOGS``), a
#: command named alone nor one of its options.
SHIP_ENV_COMMANDS += [
    (where, span)
    for where, span in _inline_spans("ship-env ")
    if len(span.split()) > 2
    and not re.fullmatch(r"ship-env [\w-]+ --[\w-]+", span)  # an option named: ``fit --preset``
    and not re.search(r"\.\.\.|\||/improve|\b[A-Z]{2,}\b", span)
]


def _run_python(code: str, cwd: Path, timeout: float = 600.0) -> str:
    environment = {**os.environ, "PYTHONPATH": str(ROOT)}
    done = subprocess.run(
        [sys.executable, "-c", code], cwd=cwd, env=environment, capture_output=True, text=True, timeout=timeout
    )
    assert done.returncode == 0, done.stderr[-3000:]
    return done.stdout


def _check_labelled(stdout: str) -> None:
    """Printed output says what it is: a word on every line, no numpy reprs."""
    assert "np.float64(" not in stdout and "array(" not in stdout, stdout
    for line in stdout.splitlines():
        assert re.search(r"[A-Za-z]{2,}", line), f"an unlabelled line: {line!r}"


def test_the_pages_hold_the_snippets_this_test_runs():
    assert len(PYTHON_BLOCKS) >= 8, PYTHON_BLOCKS
    assert len(SHELL_COMMANDS) >= 10, SHELL_COMMANDS
    assert sum(FULL_TRAINING in block for _, block in PYTHON_BLOCKS) == 1


@pytest.mark.parametrize(("where", "command"), SHELL_COMMANDS, ids=[w for w, _ in SHELL_COMMANDS])
def test_every_shell_command_runs_after_the_set_up_without_an_activated_environment(where, command):
    program = shlex.split(command)[0]
    assert command.startswith(SET_UP) or program.startswith(".venv/bin/"), (
        f"{where}: {command!r} is not found after the README's set-up (no activated environment): "
        "write .venv/bin/" + program
    )


@pytest.fixture(scope="module")
def working_folder(tmp_path_factory) -> Path:
    """A folder holding what the documented commands name: ``fitted.yaml`` (a fitted preset)."""
    folder = tmp_path_factory.mktemp("commands")
    shutil.copy(ROOT / "ship_env" / "configs" / "ships" / "esso_osaka_model.yaml", folder / "fitted.yaml")
    return folder


@pytest.mark.parametrize(("where", "command"), SHIP_ENV_COMMANDS, ids=[c for _, c in SHIP_ENV_COMMANDS])
def test_every_documented_ship_env_command_is_one_the_parser_accepts(where, command, working_folder, monkeypatch):
    monkeypatch.chdir(working_folder)
    words = shlex.split(command.replace("[", "").replace("]", ""))[1:]  # "[--plot DIR]": an option shown optional
    try:
        build_parser(only=words[:1]).parse_args(words)
    except SystemExit as error:
        pytest.fail(f"{where}: ship-env refuses {command!r} (exit {error.code})")


def _shell_runs(quick: bool) -> dict[str, list[tuple[str, str]]]:
    """Each page's ``ship-env`` commands, in order: the quick ones or the others (not ``train``, nor a
    leaderboard of the policies it trains)."""
    runs: dict[str, list[tuple[str, str]]] = {}
    for where, command in SHELL_COMMANDS:
        subcommand = shlex.split(command)[1] if command.startswith(".venv/bin/ship-env ") else "train"
        after_training = subcommand == "train" or "--policies" in command  # a policy the page trained
        if not after_training and (subcommand in QUICK_COMMANDS) == quick:
            runs.setdefault(where.split(":")[0], []).append((where, command))
    return runs


def _run_commands(commands: list[tuple[str, str]], cwd: Path) -> None:
    """Run the commands in order in ``cwd`` (so that a walk-through's later commands read its first's
    output), ``.venv/bin/ship-env`` as this interpreter's, with ``fitted.yaml`` a fitted preset."""
    shutil.copy(ROOT / "ship_env" / "configs" / "ships" / "esso_osaka_model.yaml", cwd / "fitted.yaml")
    environment = {**os.environ, "PYTHONPATH": str(ROOT)}
    for where, command in commands:
        words = [sys.executable, "-m", "ship_env.cli", *shlex.split(command)[1:]]
        done = subprocess.run(words, cwd=cwd, env=environment, capture_output=True, text=True, timeout=3600)
        assert done.returncode == 0, f"{where}: {command}\n{done.stderr[-3000:]}"


@pytest.mark.parametrize("page", sorted(_shell_runs(quick=True)))
def test_the_quick_shell_commands_run_in_their_pages_order(page, tmp_path):
    _run_commands(_shell_runs(quick=True)[page], tmp_path)


@pytest.mark.slow
@pytest.mark.parametrize("page", sorted(_shell_runs(quick=False)))
def test_the_long_shell_commands_run_in_their_pages_order(page, tmp_path):
    """The main job and the walk-throughs' long steps, after their page's quick ones."""
    _run_commands([*_shell_runs(quick=True).get(page, []), *_shell_runs(quick=False)[page]], tmp_path)


def _quick_blocks() -> list[tuple[str, str]]:
    return [(where, block.replace(FULL_TRAINING, SHORT_TRAINING)) for where, block in PYTHON_BLOCKS]


@pytest.mark.parametrize(("where", "code"), _quick_blocks(), ids=[w for w, _ in PYTHON_BLOCKS])
def test_every_python_snippet_runs_in_a_fresh_interpreter_and_labels_its_output(where, code, tmp_path):
    _check_labelled(_run_python(code, tmp_path))


@pytest.mark.slow
def test_the_rl_quickstart_trains_its_20000_steps(tmp_path):
    (code,) = [block for _, block in PYTHON_BLOCKS if FULL_TRAINING in block]
    _check_labelled(_run_python(code, tmp_path, timeout=1800))


@pytest.mark.parametrize(
    ("where", "span"),
    [(w, s) for w, s in _inline_spans("gym") if "make" in s and "..." not in s],
    ids=[s for w, s in _inline_spans("gym") if "make" in s and "..." not in s],
)
def test_every_environment_made_in_the_text_is_made_without_importing_ship_env(where, span, tmp_path):
    _run_python(f"import gymnasium\nimport gymnasium as gym\n{span}", tmp_path)
