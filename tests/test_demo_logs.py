"""``ship-env demo-logs``: simulated logs the workbench's examples run on, with a known hidden truth."""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest

from ship_env.cli import main
from ship_env.model import REQUIRED_EFFECTS, ShipModel
from ship_env.workbench import load_logs
from ship_env.workbench.fitting.replay import ReplayModel
from ship_env.workbench.fitting.terms import make_term
from ship_env.workbench.synthetic.demo_logs import hidden_values
from ship_env.workbench.synthetic.synthetic import NULL_PRESET_VALUES

#: Short runs (s), so that the fits take seconds.
DURATION = "40"
KEY = "rudder_offset.angle"
#: Fits this small run in one process: starting worker processes would take longer than the fits.
ONE_WORKER = ("--workers", "1")


@pytest.fixture(scope="module")
def demo(tmp_path_factory) -> Path:
    folder = tmp_path_factory.mktemp("demo") / "logs"
    assert main(["demo-logs", str(folder), "--hidden", "rudder_offset", "--duration", DURATION]) == 0
    return folder


def test_demo_logs_hold_zigzags_turns_and_the_truth(demo, capsys):
    assert sorted(path.name for path in (demo / "zigzag").glob("*.csv")) == [
        "zigzag_10_n10.csv",
        "zigzag_20_n12.csv",
        "zigzag_m20_n16.csv",
    ]
    assert len(list((demo / "turning").glob("*.csv"))) == 3
    truth = json.loads((demo / "truth.json").read_text())
    assert truth["hidden"] == ["rudder_offset"] and truth["ship"] == "esso_osaka_model"
    assert truth["values"] == {"rudder_offset.angle": pytest.approx(math.radians(3.0))}  # the preset's offset
    assert "rudder_offset.angle = 0.0523599 rad (3 deg)" in (demo / "README.txt").read_text()


def test_the_workbench_fits_the_demo_logs_and_finds_the_hidden_offset(demo, tmp_path, capsys):
    fit_file = tmp_path / "fit.json"
    assert main(["fit", str(demo / "zigzag"), "--add", "rudder_offset", "--json", str(fit_file), *ONE_WORKER]) == 0
    fitted = json.loads(fit_file.read_text())
    truth = json.loads((demo / "truth.json").read_text())["values"][KEY]
    # The fitted offset misses the truth by less than the smallest offset that matters for this ship.
    term = make_term(KEY, ReplayModel(ShipModel("esso_osaka_model", [*REQUIRED_EFFECTS, "rudder_offset"])))
    assert abs(fitted["values"][KEY] - truth) < term.material
    capsys.readouterr()
    assert (
        main(["diagnose", str(demo / "zigzag"), "--validate-on", str(demo / "turning"), "--refit", "2", *ONE_WORKER])
        == 0
    )
    assert first_missing_effect(capsys.readouterr().out) == "rudder_offset"


def test_demo_logs_never_overwrite_without_force(demo, capsys):
    truth = (demo / "truth.json").read_text()
    assert main(["demo-logs", str(demo), "--duration", DURATION]) == 1
    assert "exists; choose another folder or pass --force" in capsys.readouterr().err
    assert (demo / "truth.json").read_text() == truth
    assert main(["demo-logs", str(demo), "--hidden", "rudder_offset", "--duration", DURATION, "--force"]) == 0
    assert (demo / "truth.json").read_text() == truth  # same seed, same truth


def test_an_unknown_hidden_effect_is_a_usage_error_naming_it(tmp_path, capsys):
    with pytest.raises(SystemExit) as exit_status:
        main(["demo-logs", str(tmp_path / "logs"), "--hidden", "rudder_offset,rudder_ofset"])
    assert exit_status.value.code == 2
    assert "argument --hidden: unknown effect 'rudder_ofset'; known: " in capsys.readouterr().err
    assert not (tmp_path / "logs").exists()


def test_an_effect_the_csv_cannot_carry_is_refused_with_the_reason(tmp_path, capsys):
    # The ordered rudder that hides a steering machine would be read back as the actual rudder.
    with pytest.raises(SystemExit) as exit_status:
        main(["demo-logs", str(tmp_path / "logs"), "--hidden", "steering_machine"])
    assert exit_status.value.code == 2
    assert "argument --hidden: steering_machine cannot be hidden in CSV logs: its logs record the ordered" in (
        capsys.readouterr().err
    )
    assert not (tmp_path / "logs").exists()


def test_a_ship_with_an_aligned_rudder_hides_the_stated_offset():
    # The container ship's preset has no rudder offset: hidden, it takes the stated one, not zero.
    assert (
        hidden_values("container_226m", ["rudder_offset"])["rudder_offset.angle"]
        == (NULL_PRESET_VALUES["rudder_offset.angle"])
    )


def first_missing_effect(out: str) -> str:
    """The effect ranked first by ``ship-env diagnose``'s output."""
    table = out.split("missing effects, best first")[1]
    return next(line for line in table.splitlines() if line.startswith("1 ")).split()[1]


def test_full_scale_sea_trial_logs_read_back_and_their_readme_command_finds_the_offset(tmp_path, capsys):
    # Gusts swing the 280 deg wind of a 5-minute run past north: the anemometer reads 0..360 deg.
    folder = tmp_path / "logs"
    demo = ["demo-logs", str(folder), "--ship", "container_226m", "--sensors", "sea-trial", "--hidden", "rudder_offset"]
    assert main(demo) == 0
    logs = load_logs([folder / "zigzag", folder / "turning"])
    assert len(logs) == 6
    for log in logs:
        assert log.wind_direction is not None
        assert 0.0 <= log.wind_direction.min() and log.wind_direction.max() < 2.0 * math.pi
    # README.txt's diagnose command, on the scale-free default error scales (track L/30 = 7.5 m, not an
    # absolute 0.1 m that 3 m of GPS noise swamps), finds the 1 deg offset.
    readme = (folder / "README.txt").read_text()
    command = next(line.split() for line in readme.splitlines() if line.strip().startswith("ship-env diagnose"))
    capsys.readouterr()
    assert main([*command[1:], "--refit", "2", *ONE_WORKER]) == 0
    assert first_missing_effect(capsys.readouterr().out) == "rudder_offset"
