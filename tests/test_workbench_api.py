"""One workbench for Python and the command line: scale-free error scales, the same screening of the runs,
and the fit's JSON document (improve --json; the hull it records and refuses to change)."""

from __future__ import annotations

import json
import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from ship_env.cli import main
from ship_env.model import REQUIRED_EFFECTS, ShipModel
from ship_env.workbench import (
    ErrorScales,
    FitOptions,
    LogWarning,
    cross_validate,
    fit,
    fit_each_run,
    improve,
    load_logs,
    write_log,
)
from ship_env.workbench.fitting.errors import mean_speed
from ship_env.workbench.fitting.replay import ReplayModel
from ship_env.workbench.reporting.documents import DocumentError, read_fitted_model
from ship_env.workbench.synthetic.synthetic import (
    LogSettings,
    Manoeuvre,
    SensorNoise,
    hidden_effect_logs,
    model_test_programme,
    sail_all,
)

SHIP = "esso_osaka_model"


# -- scale-free error scales ------------------------------------------------------------------------
def test_the_scale_free_scales_are_one_degree_one_degree_per_ship_length_and_a_thirtieth_of_it():
    model = ErrorScales.for_ship(3.0, 0.3)
    assert model.heading == pytest.approx(math.radians(1.0))
    assert model.rate_of_turn == pytest.approx(math.radians(0.1))  # 1 deg per 3 m sailed at 0.3 m/s
    assert model.position == pytest.approx(0.1)
    tanker = ErrorScales.for_ship(320.0, 8.0)
    assert tanker.heading == model.heading
    assert tanker.rate_of_turn == pytest.approx(math.radians(1.0) * 8.0 / 320.0)
    assert tanker.position == pytest.approx(320.0 / 30.0)
    assert tanker.describe() == (
        "heading 1 deg, rate of turn 0.025 deg/s (1 deg per ship length at 8 m/s), speed 0.14 m/s (1.7 % of 8 m/s), "
        "track 10.7 m (L/30, L = 320 m)"
    )
    assert tanker.speed_error == pytest.approx(math.radians(1.0) * 8.0)
    # A channel set absolutely is said without its derivation.
    assert replace(tanker, position=0.1).describe().endswith("track 0.1 m")
    with pytest.raises(ValueError, match="mean speed"):
        ErrorScales.for_ship(320.0, 0.0)


def test_the_mean_speed_weighs_samples_and_takes_the_service_speed_where_a_log_has_no_speed():
    model = ShipModel(SHIP, REQUIRED_EFFECTS)
    _, logs = hidden_effect_logs([], SHIP, manoeuvres=model_test_programme(duration=20.0)[2:4])
    measured, unmeasured = logs[0], replace(logs[1], speed=None, service_speed=0.5)
    expected = (np.sum(measured.speed) + 0.5 * unmeasured.samples) / (measured.samples + unmeasured.samples)
    assert mean_speed(model, [measured, unmeasured]) == pytest.approx(expected)
    assert mean_speed(model, [replace(unmeasured, service_speed=None)]) == pytest.approx(model.service_speed)
    # Going astern, a ship sails its lengths as well.
    astern = replace(measured, speed=-measured.speed)
    assert mean_speed(model, [astern]) == pytest.approx(float(np.mean(measured.speed)))
    options = FitOptions().for_runs(model, [measured, unmeasured])
    assert options.scales == ErrorScales.for_ship(model.length, expected)


#: A full-scale sea trial: the kvlcc2 tanker (L = 320 m) with a rudder offset of 1 deg and a current
#: of 0.36 m/s; GPS 3 m, compass 0.5 deg, rudder indicator 0.2 deg.
SEA_TRIAL = SensorNoise(
    heading=math.radians(0.5), rate_of_turn=math.radians(0.05), position=3.0, rudder=math.radians(0.2), speed=0.05
)


def sea_trial_logs() -> list:
    model = ShipModel(
        "kvlcc2", [*REQUIRED_EFFECTS, "rudder_offset", "current"], {"rudder_offset.angle": math.radians(1.0)}
    )
    truth = ReplayModel(model, 0.3, -0.2)
    speed = model.service_speed
    zigzags = [
        Manoeuvre(
            f"zigzag_{angle}",
            "zigzag",
            math.radians(angle),
            600.0,
            approach=30.0,
            zigzag_angle=math.radians(abs(angle)),
            start_speed=speed,
            final_speed=speed,
            propeller_rate=1.0,
            wind_speed=0.0,
        )
        for angle in (10, -10, 20, -20)
    ]
    # No speed channel: the claim is about the heading and the track's scales (a speed channel would add its own).
    return sail_all(truth, zigzags, seed=3, settings=LogSettings(dt=1.0, noise=SEA_TRIAL, measure_speed=False))


def test_on_a_full_scale_ship_the_ladder_moves_the_heading_only_with_the_scale_free_scales():
    logs = sea_trial_logs()
    start = ShipModel("kvlcc2", REQUIRED_EFFECTS)
    climbs = {
        label: improve(start, logs, options, candidates=["current", "rudder_offset"], pair_width=0, max_steps=2)
        for label, options in (("absolute", FitOptions(scales=ErrorScales())), ("scale-free", FitOptions()))
    }
    headings = {label: [rung.validation.pooled.heading for rung in ladder.rungs] for label, ladder in climbs.items()}
    assert "rudder_offset" in climbs["scale-free"].added
    # The heading error the offset makes (several deg) falls to near the compass noise.
    assert headings["scale-free"][-1] < 0.5 * headings["scale-free"][0]
    # Scored against 0.1 m of track, 3 m of GPS noise outweighs it: the offset is not added, the heading stays.
    assert "rudder_offset" not in climbs["absolute"].added
    assert headings["absolute"][-1] > 0.8 * headings["absolute"][0]


# -- one answer from Python and from the command line ----------------------------------------------
@pytest.fixture(scope="module")
def folder_with_a_run_outside(tmp_path_factory) -> Path:
    """Three short runs with a rudder offset, and one at 0.05 m/s: wholly outside the envelope (below 0.1 m/s)."""
    folder = tmp_path_factory.mktemp("logs")
    _, logs = hidden_effect_logs(["rudder_offset"], SHIP, manoeuvres=model_test_programme(duration=40.0)[::2])
    alongside = replace(logs[0], name="alongside", speed=np.full(logs[0].samples, 0.05))
    for log in (*logs, alongside):
        write_log(log, folder / f"{log.name}.csv")
    return folder


def test_fit_and_fit_each_run_leave_out_a_run_outside_the_envelope_as_cross_validate_does(folder_with_a_run_outside):
    logs = load_logs([folder_with_a_run_outside])
    model = ShipModel(SHIP, REQUIRED_EFFECTS)
    with pytest.warns(LogWarning, match="alongside lies wholly outside the model's envelope"):
        result = fit(model, logs)
    assert [errors.name for errors in result.errors] == [log.name for log in logs if log.name != "alongside"]
    with pytest.warns(LogWarning, match="alongside lies wholly outside the model's envelope"):
        each = fit_each_run(model, logs)
    assert [f.errors[0].name for f in each] == [errors.name for errors in result.errors]


@pytest.mark.slow
def test_python_leaves_out_a_run_outside_the_envelope_and_gives_the_command_lines_held_out_errors(
    folder_with_a_run_outside, tmp_path, capsys
):
    logs = load_logs([folder_with_a_run_outside])
    model = ShipModel(SHIP, REQUIRED_EFFECTS)
    with pytest.warns(LogWarning, match="alongside lies wholly outside the model's envelope"):
        validation = cross_validate(model, logs)
    assert "alongside" not in [errors.name for errors in validation.held_out]
    fit_file = tmp_path / "fit.json"
    assert main(["fit", str(folder_with_a_run_outside), "--ship", SHIP, "--workers", "1", "--json", str(fit_file)]) == 0
    assert "alongside lies wholly outside" in capsys.readouterr().out
    held_out = json.loads(fit_file.read_text())["held_out"]["held out"]
    assert held_out["heading"] == pytest.approx(math.degrees(validation.pooled.heading), rel=1e-9)
    assert held_out["track"] == pytest.approx(validation.pooled.track, rel=1e-9)

    with pytest.warns(LogWarning, match="alongside"):
        ladder = improve(model, logs, candidates=["rudder_offset"], pair_width=0, max_steps=1)
    ladder_file = tmp_path / "ladder.json"
    arguments = ["improve", str(folder_with_a_run_outside), "--ship", SHIP, "--workers", "1", "--pairs", "0"]
    arguments += ["--candidates", "rudder_offset", "--max-steps", "1", "--report", str(tmp_path / "report")]
    assert main([*arguments, "--json", str(ladder_file)]) == 0
    document = json.loads(ladder_file.read_text())
    assert [rung["added"] for rung in document["ladder"]] == [list(rung.added) for rung in ladder.rungs]
    for rung, written in zip(ladder.rungs, document["ladder"], strict=True):
        assert written["held_out"]["heading"] == pytest.approx(math.degrees(rung.validation.pooled.heading), rel=1e-9)
        assert written["held_out"]["track"] == pytest.approx(rung.validation.pooled.track, rel=1e-9)
    assert document["stopped"] == ladder.stopped


# -- the fit's document: improve --json, and the hull -----------------------------------------------
@pytest.fixture(scope="module")
def ladder_file(folder_with_a_run_outside, tmp_path_factory) -> Path:
    folder = tmp_path_factory.mktemp("ladder")
    path = folder / "ladder.json"
    arguments = ["improve", str(folder_with_a_run_outside), "--ship", SHIP, "--workers", "1", "--pairs", "0"]
    arguments += ["--candidates", "rudder_offset", "--report", str(folder / "report"), "--json", str(path)]
    assert main(arguments) == 0
    return path


def test_improve_json_holds_the_final_model_the_ladder_and_the_hull_and_compare_reads_it(
    ladder_file, folder_with_a_run_outside, capsys
):
    document = json.loads(ladder_file.read_text())
    assert set(document["effects"]) == {"yaw", "speed_loss", "kinematics", "rudder_offset"}
    assert [rung["added"] for rung in document["ladder"]] == [[], ["rudder_offset"]]
    assert document["ladder"][1]["held_out"]["score"] < document["ladder"][0]["held_out"]["score"]
    assert document["stopped"]
    model = ShipModel(SHIP)
    assert document["hull"]["preset"] == SHIP
    assert document["hull"]["principal"]["length"] == model.length == 3.0
    assert document["hull"]["principal"]["service_speed"] == model.service_speed
    capsys.readouterr()
    # Without --ship the document's own hull is used.
    assert main(["compare", str(folder_with_a_run_outside), "--parameters", str(ladder_file)]) == 0
    out = capsys.readouterr().out
    assert f"{SHIP}: 3 runs; effects: {', '.join(document['effects'])}" in out
    # fit starts from it: the fitted terms are those of its effects.
    assert main(["fit", str(folder_with_a_run_outside), "--parameters", str(ladder_file), "--workers", "1"]) == 0
    assert "rudder_offset.angle" in capsys.readouterr().out


def test_improve_json_does_not_overwrite_a_file_without_force(folder_with_a_run_outside, tmp_path, capsys):
    existing = tmp_path / "mine.json"
    existing.write_text("{}")
    arguments = ["improve", str(folder_with_a_run_outside), "--ship", SHIP, "--json", str(existing)]
    assert main(arguments) == 1
    assert "exists; choose another name or pass --force" in capsys.readouterr().err
    assert existing.read_text() == "{}"


def test_a_fit_is_refused_on_another_hull_naming_the_file_the_hulls_and_the_particular(
    ladder_file, folder_with_a_run_outside, capsys
):
    with pytest.raises(SystemExit) as stopped:
        main(["compare", str(folder_with_a_run_outside), "--parameters", str(ladder_file), "--ship", "kvlcc2"])
    assert stopped.value.code == 2
    err = capsys.readouterr().err
    assert str(ladder_file) in err and "'esso_osaka_model'" in err and "kvlcc2" in err
    assert "length differs (3 against 320)" in err
    # The same hull under another name (a YAML copy of the preset) is accepted.
    assert read_fitted_model(ladder_file, "esso_osaka_model").setup.model.ship.name == "esso_osaka_model"


def test_a_fit_whose_hull_is_not_found_says_so(ladder_file, tmp_path):
    document = json.loads(ladder_file.read_text())
    document["hull"] = {**document["hull"], "preset": None, "yaml": str(tmp_path / "gone.yaml"), "name": "gone"}
    moved = tmp_path / "moved.json"
    moved.write_text(json.dumps(document))
    with pytest.raises(DocumentError, match=r"fitted on 'gone' \(the YAML file .*gone.yaml'\), which is not found"):
        read_fitted_model(moved)


def test_a_document_from_an_older_version_loads_onto_its_preset_with_a_note(
    ladder_file, folder_with_a_run_outside, tmp_path, capsys
):
    document = json.loads(ladder_file.read_text())
    del document["hull"]
    old = tmp_path / "old.json"
    old.write_text(json.dumps(document))
    fitted = read_fitted_model(old)
    assert fitted.setup.model.ship.name == SHIP and "records no hull" in fitted.note
    assert fitted.setup.model.parameter("rudder_offset.angle") == document["values"]["rudder_offset.angle"]
    capsys.readouterr()
    assert main(["compare", str(folder_with_a_run_outside), "--parameters", str(old)]) == 0
    assert "records no hull (written by an older version): loaded onto esso_osaka_model" in capsys.readouterr().err
