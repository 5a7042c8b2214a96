"""The core install: everything but training, the leaderboard, Ray and the benchmark runs without the extras.

A fresh interpreter in which every extra's package fails to import (a ``sys.meta_path`` finder
raises ImportError for them, as an install without them would) imports ship_env, steps an
environment and imports every module of the core's packages; ``ship-env train`` and ``ship-env
leaderboard`` end with a message naming the extra that installs what they lack. The slow set also
writes demo logs and fits them there.
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

tomllib = pytest.importorskip("tomllib", reason="reads pyproject.toml with tomllib (Python 3.11 on)")
ROOT = Path(__file__).resolve().parents[1]
PROJECT = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]


def module_name(requirement: str) -> str:
    """The import name of a requirement such as ``stable-baselines3>=2.3``: ``stable_baselines3``."""
    match = re.match(r"[A-Za-z0-9_.-]+", requirement)
    assert match is not None, requirement
    return match.group(0).lower().replace("-", "_")


#: The packages of the extras (their import names), and those of the core.
EXTRA_MODULES = {
    module_name(requirement)
    for extra in ("rl", "leaderboard", "ray", "bench", "video")
    for requirement in PROJECT["optional-dependencies"][extra]
} - {"ship_env"}
CORE_MODULES = {module_name(requirement) for requirement in PROJECT["dependencies"]}

BLOCKER = f"""
import importlib.abc, sys

class Absent(importlib.abc.MetaPathFinder):
    def find_spec(self, name, path=None, target=None):
        if name.partition(".")[0] in {sorted(EXTRA_MODULES)!r}:
            raise ModuleNotFoundError(f"No module named {{name!r}}", name=name)
        return None

sys.meta_path.insert(0, Absent())
"""

PROBE = """
import importlib
import pkgutil
import sys
import gymnasium as gym
import numpy as np

import ship_env
from ship_env.cli import main
from ship_env.extras import MissingExtra

env = gym.make("ship_env:ship_env/CourseChange-v0")
observation, _ = env.reset(seed=0)
for _ in range(5):
    observation, *_ = env.step(env.action_space.sample())
assert np.all(np.isfinite(observation))
print("environment: stepped")

folder = sys.argv[1]
for package in ("model", "envs", "baselines", "manoeuvres", "workbench"):
    found = pkgutil.walk_packages(importlib.import_module("ship_env." + package).__path__, f"ship_env.{package}.")
    for module in found:
        if module.name != "ship_env.envs.sb3_adapter":  # the rl extra's, tried below
            importlib.import_module(module.name)
print("core: imported")
for command in ("manoeuvre", "train", "leaderboard"):
    try:
        main([command, "--help"])
    except SystemExit as exit_status:
        assert exit_status.code == 0, command
print("help: shown")
assert main(["train", "--algo", "ppo", "--steps", "64", "--out", folder + "/run"]) == 1
assert main(["leaderboard", "--out", folder + "/board"]) == 1
try:
    import ship_env.envs.sb3_adapter
except MissingExtra as error:
    print(f"adapter: {error}")
"""

#: The workbench from the core alone (the slow set: the fit compiles the replay in a fresh interpreter).
WORKBENCH_PROBE = """
import sys
from ship_env.cli import main

folder = sys.argv[1]
assert main(["demo-logs", folder, "--hidden", "rudder_offset", "--duration", "20"]) == 0
assert main(["fit", folder + "/zigzag", "--workers", "1"]) == 0
print("workbench: fitted")
"""


def run_without_the_extras(probe: str, folder: Path) -> subprocess.CompletedProcess[str]:
    """Run ``probe`` in a fresh interpreter in which every extra's package fails to import."""
    return subprocess.run(
        [sys.executable, "-c", BLOCKER + probe, str(folder)],
        cwd=folder.parent,
        env={**os.environ, "PYTHONPATH": str(ROOT)},
        capture_output=True,
        text=True,
    )


def test_the_core_dependencies_hold_no_extra():
    assert {"torch", "stable_baselines3", "rliable"} <= EXTRA_MODULES
    assert not CORE_MODULES & EXTRA_MODULES, CORE_MODULES & EXTRA_MODULES


def test_the_core_runs_without_the_extras_and_names_the_extra_a_command_needs(tmp_path):
    result = run_without_the_extras(PROBE, tmp_path / "demo")
    assert result.returncode == 0, result.stdout + result.stderr
    for line in ("environment: stepped", "core: imported", "help: shown"):
        assert line in result.stdout
    assert 'Needs the rl extra: pip install "ship-env[rl]".' in result.stdout
    assert 'Needs the leaderboard extra: pip install "ship-env[leaderboard]".' in result.stdout
    assert "ship-env train: error: training needs torch" in result.stderr
    assert 'install it with pip install "ship-env[rl]"' in result.stderr
    assert "ship-env leaderboard: error: the leaderboard needs torch" in result.stderr
    assert 'pip install "ship-env[leaderboard]"' in result.stderr
    assert "adapter: ship_env.envs.sb3_adapter needs stable_baselines3" in result.stdout
    assert not (tmp_path / "demo" / "run").exists() and not (tmp_path / "demo" / "board").exists()


@pytest.mark.slow
def test_the_workbench_writes_and_fits_demo_logs_without_the_extras(tmp_path):
    result = run_without_the_extras(WORKBENCH_PROBE, tmp_path / "demo")
    assert result.returncode == 0, result.stdout + result.stderr
    assert "workbench: fitted" in result.stdout
    assert (tmp_path / "demo" / "zigzag").is_dir()
