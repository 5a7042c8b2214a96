"""The built wheel, installed in a fresh virtual environment beside another package named ``baselines``.

OpenAI's ``baselines`` is still installed in many RL environments; ship-env must install and import
beside it (its classic baselines are ``ship_env.baselines``). The fresh environment borrows this
interpreter's installed dependencies through a ``.pth`` line (their plain import path, without the
editable install of ship_env), so pip needs no index: ``--no-index --no-deps``. Building the two wheels
and the environment takes longer than the default run allows: the whole module is in the slow set.
"""

from __future__ import annotations

import json
import math
import os
import shutil
import subprocess
import sys
import sysconfig
import zipfile
from pathlib import Path

import pytest

import ship_env
from ship_env.manoeuvres.turning_circle import turning_circle
from ship_env.model import ShipModel

pytestmark = pytest.mark.slow
ROOT = Path(__file__).resolve().parents[1]
STUB_NAME = "the stub baselines"


def run(*command: str | Path, cwd: Path) -> str:
    """Run a command with no PYTHONPATH (nothing from the source tree); its output, or a failure naming it."""
    env = {key: value for key, value in os.environ.items() if key != "PYTHONPATH"}
    result = subprocess.run([str(part) for part in command], cwd=cwd, env=env, capture_output=True, text=True)
    assert result.returncode == 0, f"{' '.join(map(str, command))} failed:\n{result.stdout}\n{result.stderr}"
    return result.stdout


def build_wheel(source: Path, out: Path) -> Path:
    """The wheel of the project in ``source``, built into the empty folder ``out``."""
    out.mkdir()
    run(
        sys.executable,
        "-m",
        "pip",
        "wheel",
        "--no-deps",
        "--no-build-isolation",
        "--no-index",
        "-q",
        "-w",
        out,
        source,
        cwd=out,
    )
    (wheel,) = out.glob("*.whl")
    return wheel


@pytest.fixture(scope="module")
def installed(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A fresh venv with the stub ``baselines`` and the ship-env wheel installed; its bin folder."""
    work = tmp_path_factory.mktemp("wheel")
    stub = work / "stub_baselines"
    (stub / "baselines").mkdir(parents=True)
    (stub / "baselines" / "__init__.py").write_text(f"NAME = {STUB_NAME!r}\n")
    (stub / "pyproject.toml").write_text(
        '[build-system]\nrequires = ["setuptools"]\nbuild-backend = "setuptools.build_meta"\n'
        '[project]\nname = "baselines"\nversion = "0.1.6"\n'
    )
    source = work / "source"  # a copy, so the build leaves nothing in the repository
    shutil.copytree(ROOT / "ship_env", source / "ship_env", ignore=shutil.ignore_patterns("__pycache__"))
    for name in ("pyproject.toml", "README.md"):
        shutil.copy(ROOT / name, source / name)
    ours = build_wheel(source, work / "ours")
    theirs = build_wheel(stub, work / "theirs")
    with zipfile.ZipFile(ours) as archive:
        top_level = {name.split("/", 1)[0] for name in archive.namelist()}
    assert "baselines" not in top_level, f"the wheel installs a top-level baselines: {sorted(top_level)}"

    venv = work / "venv"
    run(sys.executable, "-m", "venv", "--without-pip", venv, cwd=work)
    python = venv / "bin" / "python"
    site = run(python, "-c", "import sysconfig; print(sysconfig.get_paths()['purelib'])", cwd=work).strip()
    (Path(site) / "borrowed_dependencies.pth").write_text(sysconfig.get_paths()["purelib"] + "\n")
    pip = (sys.executable, "-m", "pip", "--python", python, "install", "--no-index", "--no-deps", "-q")
    run(*pip, theirs, cwd=work)  # the other package first: ours must not replace it
    run(*pip, ours, cwd=work)
    return venv / "bin"


def test_both_packages_import_from_the_fresh_environment(installed: Path):
    probe = (
        "import baselines, ship_env, ship_env.baselines.presys\n"
        "print(baselines.NAME)\n"
        "print(ship_env.__version__)\n"
        "print(ship_env.__file__)\n"
    )
    name, version, location = run(installed / "python", "-c", probe, cwd=installed).splitlines()
    assert name == STUB_NAME
    assert version == ship_env.__version__
    assert Path(location).is_relative_to(installed.parent), f"ship_env imported from {location}, not the wheel"
    typed = run(
        installed / "python",
        "-c",
        "import ship_env, pathlib; print((pathlib.Path(ship_env.__file__).parent / 'py.typed').is_file())",
        cwd=installed,
    )
    assert typed.strip() == "True"


def test_the_command_line_starts_from_the_wheel(installed: Path, tmp_path: Path):
    assert "manoeuvre" in run(installed / "ship-env", "--help", cwd=tmp_path)


def test_the_command_line_sails_from_the_wheel_with_the_numbers_of_the_source_tree(installed: Path, tmp_path: Path):
    """The installed package compiles its kernels afresh (numba's cache lies beside the sources): a minute."""
    figures = tmp_path / "figures.json"
    run(
        installed / "ship-env",
        "manoeuvre",
        "--effects",
        "minimal",
        "--turn-angle",
        "35",
        "--zigzag",
        "10/10",
        "--json",
        figures,
        cwd=tmp_path,
    )
    circle = json.loads(figures.read_text())["manoeuvres"][0]
    assert circle["manoeuvre"] == "turning circle"
    here = turning_circle(ShipModel.minimal("container_226m"), math.radians(35.0))
    assert circle["figures"]["advance"]["value"] == pytest.approx(here.advance, rel=1e-9)


@pytest.mark.parametrize("example", sorted((ROOT / "examples").glob("*.py")), ids=lambda path: path.name)
def test_the_examples_run_from_the_wheel(installed: Path, example: Path, tmp_path: Path):
    run(installed / "python", example, cwd=tmp_path)
