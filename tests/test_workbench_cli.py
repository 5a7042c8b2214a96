"""The workbench's commands: fit, compare, diagnose, improve, their outputs and their errors."""

from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from ship_env.cli import main
from ship_env.workbench import write_log
from ship_env.workbench.synthetic.synthetic import hidden_effect_logs, model_test_programme

SHIP = "esso_osaka_model"


@pytest.fixture(scope="module")
def log_folder(tmp_path_factory) -> Path:
    """Short synthetic runs in the standard CSV format, sailed with a rudder offset."""
    folder = tmp_path_factory.mktemp("logs")
    _, logs = hidden_effect_logs(["rudder_offset"], SHIP, manoeuvres=model_test_programme(duration=40.0)[::2])
    for log in logs:
        write_log(log, folder / f"{log.name}.csv")
    return folder


def held_out_score(out: str) -> float:
    return float(re.search(r"^held out .* (\S+)$", out, flags=re.MULTILINE).group(1))


def test_fit_prints_terms_and_errors_and_writes_json_and_plots(log_folder, tmp_path, capsys):
    fit_file = tmp_path / "fit.json"
    status = main(["fit", str(log_folder), "--ship", SHIP, "--json", str(fit_file), "--plot", str(tmp_path / "plots")])
    assert status == 0
    out = capsys.readouterr().out
    for text in (
        "effects: yaw, speed_loss, kinematics",  # the logs measure the speed: the model predicts it
        "yaw.gain",
        "std. error (jackknife)",
        "in-sample RMS errors",
        "held-out RMS errors",
        "heading [deg]",
        "speed [m/s]",
        "track [m]",
    ):
        assert text in out, text
    document = json.loads(fit_file.read_text())
    assert document["effects"] == ["yaw", "speed_loss", "kinematics"]
    assert set(document["values"]) == {"yaw.gain", "yaw.time_constant", "speed_loss.gain", "speed_loss.time_constant"}
    assert document["not_identified"] == [] and "speed" in document["error_scales"]
    assert len(list((tmp_path / "plots").glob("*.png"))) == 3
    base = held_out_score(out)
    assert (
        main(
            [
                "fit",
                str(log_folder),
                "--ship",
                SHIP,
                "--add",
                "rudder_offset",
                "--free",
                "yaw.linear",
                "--fix",
                "yaw.linear",
            ]
        )
        == 0
    )
    assert held_out_score(capsys.readouterr().out) < 0.5 * base


def test_compare_replays_a_fitted_model(log_folder, tmp_path, capsys):
    fit_file = tmp_path / "fit.json"
    main(["fit", str(log_folder), "--ship", SHIP, "--add", "rudder_offset", "--json", str(fit_file)])
    capsys.readouterr()
    assert (
        main(
            [
                "compare",
                str(log_folder),
                "--ship",
                SHIP,
                "--parameters",
                str(fit_file),
                "--plot",
                str(tmp_path / "plots"),
            ]
        )
        == 0
    )
    out = capsys.readouterr().out
    assert "effects: yaw, speed_loss, rudder_offset, kinematics" in out and "pooled" in out
    pooled = next(line for line in out.splitlines() if line.startswith("pooled")).split()
    assert float(pooled[1]) < 1.0  # deg: the fitted offset model replays the runs closely


def test_diagnose_names_the_missing_effect_and_draws_the_signals(log_folder, tmp_path, capsys):
    plot = tmp_path / "signals.png"
    assert main(["diagnose", str(log_folder), "--ship", SHIP, "--refit", "2", "--plot", str(plot)]) == 0
    out = capsys.readouterr().out
    table = out.split("missing effects, best first")[1]
    lines = table.splitlines()
    first = next(i for i, line in enumerate(lines) if line.startswith("1 "))
    assert "rudder_offset" in lines[first] and "rudder offset (neutral rudder angle" in lines[first + 1]
    assert max(map(len, table.split("\n\n")[0].splitlines())) <= 100  # the effect under its row (was 250 wide)
    assert "effects: yaw, speed_loss, kinematics" in table  # the logs measure the speed: the speed loss is fitted
    assert "the missing yaw acceleration against " in out and str(plot) in out
    assert plot.read_bytes().startswith(b"\x89PNG")
    # A file that exists is the user's: refused before any work, left as it was.
    plot.write_bytes(b"mine")
    assert main(["diagnose", str(log_folder), "--ship", SHIP, "--plot", str(plot)]) == 1
    assert "--plot: " in capsys.readouterr().err and plot.read_bytes() == b"mine"


def test_improve_climbs_the_ladder_and_writes_the_report_with_every_figure(log_folder, tmp_path, capsys):
    report_folder = tmp_path / "report"
    assert (
        main(
            [
                "improve",
                str(log_folder),
                "--ship",
                SHIP,
                "--refit",
                "2",
                "--max-steps",
                "1",
                "--report",
                str(report_folder),
            ]
        )
        == 0
    )
    captured = capsys.readouterr()
    assert "+ rudder_offset" in captured.out and "error ladder" in captured.out
    assert "added rudder_offset" in captured.err
    report = (report_folder / "report.md").read_text()
    for heading in (
        "## Runs",
        "## Error ladder",
        "## Final model",
        "## Diagnoses",
        "### start model",
        "### final model",
    ):
        assert heading in report, heading
    figures = re.findall(r"!\[[^\]]*\]\(([^)]+)\)", report)
    assert len(figures) == 1 + 2 * 3  # the ladder, then each run for the start and the final model
    for figure in figures:
        data = (report_folder / figure).read_bytes()
        assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 10_000, figure


def test_improve_writes_no_report_unasked(log_folder, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    arguments = ["improve", str(log_folder), "--ship", SHIP, "--candidates", "rudder_offset", "--max-steps", "1"]
    assert main([*arguments, "--pairs", "0", "--workers", "1"]) == 0
    assert "error ladder" in capsys.readouterr().out
    assert list(tmp_path.iterdir()) == []  # was workbench_report/, with its figures


def test_a_bad_log_ends_with_a_clear_error(tmp_path, capsys):
    frame = pd.DataFrame({"time": np.arange(30.0), "heading": np.zeros(30), "rudder": np.zeros(30)})
    frame.loc[10, "heading"] = np.nan
    frame.to_csv(tmp_path / "gap.csv", index=False)
    assert main(["fit", str(tmp_path / "gap.csv")]) == 1
    err = capsys.readouterr().err
    assert "ship-env fit: error:" in err and "column 'heading' (heading) is NaN at rows 11..11" in err


@pytest.mark.parametrize(
    "arguments, message",
    [
        (["fit", "x.csv", "--add", "wake"], "argument --add: unknown effect 'wake'"),
        (["fit", "x.csv", "--model", "tiny"], "argument --model: unknown effect 'tiny'"),
        (["improve", "x.csv", "--min-gain", "2"], "argument --min-gain: expected a number between 0 and 1"),
        (["fit", "x.csv", "--every", "0"], "argument --every: expected a positive whole number"),
    ],
)
def test_bad_arguments_name_the_argument(arguments, message, capsys):
    with pytest.raises(SystemExit) as stop:
        main(arguments)
    assert stop.value.code == 2
    assert message in capsys.readouterr().err


@pytest.mark.parametrize("command", ["fit", "improve"])
def test_fixing_a_term_that_is_not_fitted_names_it(log_folder, capsys, command):
    with pytest.raises(SystemExit):
        main([command, str(log_folder), "--fix", "rudder_offset.angle"])
    assert "argument --fix: rudder_offset.angle not among the fitted terms" in capsys.readouterr().err


def test_improve_holds_a_fixed_term_on_every_rung(log_folder, capsys):
    """``improve --fix`` holds a starting model's term at the preset's value on every rung (it was accepted and the
    term fitted all the same); ``--free`` fits one the defaults leave out."""
    ladder = ["improve", str(log_folder), "--ship", SHIP, "--candidates", "rudder_offset", "--max-steps", "1"]
    arguments = [*ladder, "--pairs", "0", "--workers", "1", "--fix", "yaw.time_constant", "--free", "yaw.linear"]
    assert main(arguments) == 0
    captured = capsys.readouterr()
    assert "added rudder_offset" in captured.err
    final = captured.out.split("final model, fitted to all runs")[1]
    rows = {line.split()[0] for line in final.splitlines()[2:] if line.strip()}
    assert {"yaw.gain", "yaw.linear", "rudder_offset.angle"} <= rows and "yaw.time_constant" not in rows


def test_json_onto_an_existing_file_fails_without_force(log_folder, tmp_path, capsys):
    users_file = tmp_path / "fit.json"
    users_file.write_text("the user's notes\n")
    assert main(["fit", str(log_folder), "--ship", SHIP, "--json", str(users_file)]) == 1
    error = capsys.readouterr().err
    assert "--json" in error and "exists" in error and "--force" in error
    assert users_file.read_text() == "the user's notes\n"
    assert main(["fit", str(log_folder), "--ship", SHIP, "--json", str(users_file), "--force"]) == 0
    assert json.loads(users_file.read_text())["effects"] == ["yaw", "speed_loss", "kinematics"]


@pytest.mark.parametrize("command", ["compare", "improve"])
def test_a_folder_the_workbench_did_not_write_is_left_alone(log_folder, tmp_path, capsys, command):
    folder = tmp_path / "mine"
    folder.mkdir()
    (folder / "thesis.tex").write_text("chapter 1\n")
    option = "--plot" if command == "compare" else "--report"
    assert main([command, str(log_folder), "--ship", SHIP, option, str(folder)]) == 1
    error = capsys.readouterr().err
    assert option in error and "did not write" in error and "--force" in error
    assert sorted(p.name for p in folder.iterdir()) == ["thesis.tex"]


@pytest.mark.slow
def test_the_workbench_writes_again_into_its_own_folder(log_folder, tmp_path):
    folder = tmp_path / "plots"
    assert main(["compare", str(log_folder), "--ship", SHIP, "--plot", str(folder)]) == 0
    assert main(["compare", str(log_folder), "--ship", SHIP, "--plot", str(folder)]) == 0
    assert len(list(folder.glob("*.png"))) == 3


def test_a_fit_on_densely_sampled_runs_says_which_sample_step_keeps_what_it_needs(tmp_path, capsys):
    """Runs at 10 Hz of a 3 m model at 0.3 m/s hold 100 samples per ship length sailed (L / (U0 dt)): ``fit`` says
    ``--every 4`` keeps 25 or more; a 320 m tanker at 8 m/s logged at 1 Hz holds 40, and is offered none, nor is a fit
    given its own ``--every``."""
    from ship_env.model import ShipModel
    from ship_env.workbench import Log, load_logs
    from ship_env.workbench.fitting.replay import SAMPLES_PER_LENGTH, coarser_step, samples_per_length

    def run(duration: float, interval: float, speed: float) -> Log:
        time = np.arange(0.0, duration, interval)
        return Log("straight", time, np.zeros_like(time), np.zeros_like(time), speed=np.full_like(time, speed))

    model, tanker = ShipModel(SHIP), ShipModel("kvlcc2")
    assert samples_per_length(run(60.0, 0.1, 0.3), model) == pytest.approx(100.0)
    assert coarser_step([run(60.0, 0.1, 0.3)], model) == int(100.0 // SAMPLES_PER_LENGTH) == 4
    assert coarser_step([run(60.0, 0.1, 0.3), run(60.0, 0.1, 0.6)], model) == 2  # the faster run's 50 decides
    assert samples_per_length(run(600.0, 1.0, 8.0), tanker) == pytest.approx(40.0)
    assert coarser_step([run(600.0, 1.0, 8.0)], tanker) == 1
    folder = tmp_path / "logs"
    folder.mkdir()
    _, logs = hidden_effect_logs([], SHIP, manoeuvres=model_test_programme(duration=20.0)[:2], dt=0.05)
    for log in logs:  # logged at 20 Hz
        write_log(log, folder / f"{log.name}.csv")
    assert main(["fit", str(folder), "--ship", SHIP, "--model", "base"]) == 0
    step = coarser_step(load_logs([folder]), model)  # as read: the runs' service speeds estimated from their speed
    assert step >= 2 and f"--every {step} keeps 25 or more" in capsys.readouterr().out.replace("\n  ", " ")
    assert main(["fit", str(folder), "--ship", SHIP, "--model", "base", "--every", "1"]) == 0
    assert "sampling:" not in capsys.readouterr().out
