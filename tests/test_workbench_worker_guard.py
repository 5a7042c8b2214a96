"""A script that fits with worker processes but lacks the ``__main__`` guard gets a clear error, not a bare
BrokenProcessPool, and the process ends (no hang)."""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]

SCRIPT = textwrap.dedent(
    """
    from ship_env.model import REQUIRED_EFFECTS, ShipModel
    from ship_env.workbench import FitOptions, ReplayModel, improve
    from ship_env.workbench.synthetic.synthetic import LogSettings, model_test_programme, sail_all

    truth = ReplayModel(ShipModel("esso_osaka_model", [*REQUIRED_EFFECTS, "rudder_offset"]))
    logs = sail_all(truth, model_test_programme(duration=20.0)[:3], seed=5, settings=LogSettings())
    improve(ShipModel("esso_osaka_model", REQUIRED_EFFECTS), logs, FitOptions(workers=2), max_steps=1)
    """
)


@pytest.mark.slow
def test_a_script_without_the_main_guard_gets_an_error_naming_it_and_the_fix(tmp_path):
    script = tmp_path / "no_guard.py"
    script.write_text(SCRIPT)
    environment = {**os.environ, "PYTHONPATH": os.pathsep.join([str(ROOT), os.environ.get("PYTHONPATH", "")])}
    finished = subprocess.run(
        [sys.executable, str(script)], capture_output=True, text=True, timeout=300, env=environment, cwd=tmp_path
    )
    assert finished.returncode != 0
    last = finished.stderr.strip().splitlines()[-1]
    assert last.startswith(
        "ship_env.workbench.fitting.parallel.WorkerStartError: the worker processes stopped while starting"
    )
    assert str(script) in last and 'if __name__ == "__main__":' in last and "workers=1" in last
    assert "BrokenProcessPool" not in finished.stderr
