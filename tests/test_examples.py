"""The worked example: an effect the library lacks, written outside the package, found and added."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from ship_env.model import EFFECTS

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "rudder_stall.py"


@pytest.mark.slow
def test_the_rudder_stall_example_finds_the_missing_effect_and_the_error_falls(tmp_path, capsys, load_script):
    """About a minute on 2 cores: six runs, the library's candidates, improve and the command line."""
    try:
        example = load_script(EXAMPLE, "rudder_stall_example")  # registers rudder_stall
        assert example.main(["--out", str(tmp_path)]) == 0
    finally:
        EFFECTS.unregister("rudder_stall")
    output = capsys.readouterr().out
    floor = float(re.search(r"held-out score ([\d.]+)\n", output).group(1))
    base = float(re.search(r"base model \(yaw, kinematics\): held-out score ([\d.]+)", output).group(1))
    added = float(re.search(r"\+ rudder_stall +[\d.]+ +[\d.]+ +[\d.]+ +[\d.]+ +([\d.]+)", output).group(1))
    assert "no effect of the library lowers the held-out score by 50%" in output
    assert re.search(r"1\. the rudder angle (squared|cubed)", output), output
    assert added <= 0.2 * base and added <= 1.5 * floor, output
    assert (tmp_path / "missing_yaw_acceleration.png").stat().st_size > 10_000
