"""The ``ship-env`` command line: default run, outputs, and clear errors for bad arguments."""

from __future__ import annotations

import json
import math
import subprocess
import sys

import pytest

from ship_env.cli import main


def test_manoeuvre_defaults_print_the_imo_figures(capsys):
    assert main(["manoeuvre", "--dt", "1"]) == 0
    out, err = capsys.readouterr()
    assert "container_226m: L = 225.9 m" in out
    for text in (
        "Turning circle",
        "35 deg stbd",
        "advance [L]",
        "tactical diameter [m]",
        "tactical diameter [L]",
        "steady radius U/r [m]",
        "drift angle in steady turn [deg]",
        "10/10",
        "20/20",
        "first overshoot angle [deg]",
        "time to check yaw [s]",
        "Pull-out",
        "residual rate of turn, stbd [deg/s]",
        "Reversed spiral",
        "hard over",
        "IMO MSC.137(76) 5.3 criteria",
        "5.3.3.3 first overshoot, zig-zag 20/20 [deg]",
    ):
        assert text in out, text
    assert out.count("pass") == 6 and "FAIL" not in out
    assert "manoeuvres" in err  # the progress bar goes to stderr


@pytest.mark.slow
def test_manoeuvre_options_choose_runs_and_write_plots_and_json(tmp_path, capsys):
    json_file = tmp_path / "figures.json"
    status = main(
        [
            "manoeuvre",
            "--effects",
            "minimal",
            "--speed",
            "15",
            "--dt",
            "1",
            "--turn-angle",
            "-35",
            "20",
            "--zigzag",
            "10/10",
            "-10/-10",
            "--plot",
            str(tmp_path / "plots"),
            "--json",
            str(json_file),
        ]
    )
    assert status == 0
    out = capsys.readouterr().out
    assert "V = 15.0 kn" in out and "effects: yaw, steering_machine, kinematics" in out
    assert "35 deg port" in out and "20 deg stbd" in out and "-10/-10" in out
    report = json.loads(json_file.read_text())
    assert [m["manoeuvre"] for m in report["manoeuvres"]] == [
        "turning circle",
        "turning circle",
        "zig-zag",
        "zig-zag",
        "pull-out",
        "reversed spiral",
    ]
    circle = report["manoeuvres"][0]["figures"]
    assert circle["tactical_diameter_lengths"]["unit"] == "L"
    # Nomoto ship: steady radius u/r = L / (K* delta) (2.61), whatever the speed.
    assert circle["steady_radius"]["value"] == pytest.approx(225.87 / (1.6 * math.radians(35.0)), rel=0.01)
    assert {c["clause"] for c in report["criteria"]} == {"5.3.1", "5.3.2", "5.3.3.1", "5.3.3.2"}
    assert len(report["manoeuvres"][-1]["table"]) == 13
    plots = sorted(p.name for p in (tmp_path / "plots").iterdir())
    assert plots == [
        "pull-out_20_deg.png",
        "reversed_spiral.png",
        "turning_circle_20_deg_stbd.png",
        "turning_circle_35_deg_port.png",
        "zig-zag_-10_-10.png",
        "zig-zag_10_10.png",
    ]


@pytest.mark.parametrize(
    ("arguments", "named"),
    [
        (["--ship", "titanic"], ["--ship", "'titanic'"]),
        (["--effects", "yaw,warp_drive"], ["--effects", "'warp_drive'"]),
        (["--zigzag", "10x10"], ["--zigzag", "'10x10'"]),
        (["--zigzag", "10/-10"], ["--zigzag", "'10/-10'"]),
        (["--dt", "0"], ["--dt", "'0'"]),
        (["--dt", "-0.5"], ["--dt", "'-0.5'"]),
        (["--speed", "fast"], ["--speed", "'fast'"]),
        (["--turn-angle", "0"], ["--turn-angle", "'0'"]),
        (["--turn-angle", "40"], ["--turn-angle", "40 deg", "rudder limit of 35 deg"]),
        (["--zigzag", "45/10"], ["--zigzag", "45/10", "rudder limit"]),
    ],
)
def test_bad_arguments_exit_2_naming_the_argument(arguments, named, capsys):
    with pytest.raises(SystemExit) as exit_info:
        main(["manoeuvre", *arguments])
    assert exit_info.value.code == 2
    err = capsys.readouterr().err
    assert "error: argument" in err
    for text in named:
        assert text in err


@pytest.mark.slow
def test_bad_arguments_give_no_traceback_from_the_installed_command():
    done = subprocess.run(
        [sys.executable, "-m", "ship_env.cli", "manoeuvre", "--effects", "nope"],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert done.returncode == 2
    assert "argument --effects: unknown effect 'nope'" in done.stderr
    assert "Traceback" not in done.stderr


def test_help_names_the_subcommands_and_options(capsys):
    with pytest.raises(SystemExit) as exit_info:
        main(["--help"])
    assert exit_info.value.code == 0
    assert "manoeuvre" in capsys.readouterr().out
    with pytest.raises(SystemExit):
        main(["manoeuvre", "--help"])
    out = capsys.readouterr().out
    options = ("--ship NAME", "--effects SET", "--speed KN", "--dt S", "--turn-angle DEG", "--zigzag A/B", "--plot DIR")
    for option in (*options, "--json FILE"):
        assert option in out
    with pytest.raises(SystemExit) as exit_info:
        main([])
    assert exit_info.value.code == 2
