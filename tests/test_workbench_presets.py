"""Fitted presets: a fit written as a ship YAML that ShipModel, the simulators and the environments sail.

Synthetic zig-zags sailed by a known ship (the Esso Osaka model's Nomoto ship with a rudder offset;
``ship_env.workbench.synthetic.synthetic``, a model basin's sensor noise) are fitted, written as a preset and
read back: the values bit for bit, the replays to 1e-9, the truth within four standard errors.
"""

from __future__ import annotations

import hashlib
import json
import math
from pathlib import Path

import gymnasium as gym
import numpy as np
import pytest
import yaml
from scipy.optimize import brentq

from ship_env.cli import main
from ship_env.leaderboard.board import run_leaderboard
from ship_env.leaderboard.suites import NOMINAL, SuiteSpec
from ship_env.manoeuvres.uncertainty import fold_models, jackknife_error
from ship_env.model import Conditions, ShipModel, Simulator, load_ship
from ship_env.model.operating_point import CoverageWarning
from ship_env.workbench import FitOptions, ReplayModel, compare, cross_validate, load_logs, simulate, write_log
from ship_env.workbench.fitting.errors import ErrorScales
from ship_env.workbench.reporting.presets import (
    DataLimit,
    envelope_section,
    preset_document,
    standard_errors,
    write_preset,
)
from ship_env.workbench.reporting.tables import error_table
from ship_env.workbench.synthetic.synthetic import Manoeuvre, hidden_effect_logs

SHIP = "esso_osaka_model"
HIDDEN = ("rudder_offset",)
#: Standard errors the fitted values must recover the truth within: four (a 6e-5 chance each for a normal error).
SIGMAS = 4.0


@pytest.fixture(scope="module")
def sailed(tmp_path_factory):
    """Three 40 s zig-zags sailed by the known ship, written as CSV files: (truth, logs read back from the files)."""
    manoeuvres = [
        Manoeuvre(f"zigzag_{i}", "zigzag", math.radians(sign * 20.0), 40.0, approach=5.0, propeller_rate=rate)
        for i, (sign, rate) in enumerate([(1, 12.0), (-1, 10.0), (1, 14.0)])
    ]
    truth, logs = hidden_effect_logs(HIDDEN, SHIP, seed=3, manoeuvres=manoeuvres)
    folder = tmp_path_factory.mktemp("logs")
    for log in logs:
        write_log(log, folder / f"{log.name}.csv")
    return truth, folder, load_logs([folder])


@pytest.fixture(scope="module")
def fitted(sailed, tmp_path_factory):
    """The fit to the logs and the preset written from it: (validation, preset path)."""
    truth, _, logs = sailed
    setup = ReplayModel(ShipModel(SHIP, ["yaw", "kinematics", *HIDDEN]))
    options = FitOptions(scales=ErrorScales.for_runs(setup.model, logs), workers=1)
    keys = ["yaw.gain", "yaw.time_constant", "rudder_offset.angle"]
    validation = cross_validate(setup, logs, keys, options)
    path = tmp_path_factory.mktemp("preset") / "fitted_ship.yaml"
    write_preset(preset_document(validation, logs, "ship-env fit (test)", path.stem), path)
    return validation, path


def test_the_preset_records_its_fold_fits_and_the_manoeuvres_sail_them_for_each_figures_error(fitted, tmp_path):
    """The preset's fitted.jackknife holds each fold's terms bit for bit; ``ship-env manoeuvre`` sails every fold and
    gives each figure its jackknife standard error. For this Nomoto ship sailed free, each fold's steady turn has the
    closed form r* = K* (delta + delta_0) (2.26), u* + beta3 u*^3 = K_u* r*^2 (2.55, 2.39), r = r* U0 (1 - u*) / L
    (2.40, 2.53): the figure's error is the jackknife of those rates."""
    validation, path = fitted
    model = ShipModel(path)
    folds = fold_models(model)
    assert len(folds) == len(validation.folds) == 3
    for ship, fold in zip(folds, validation.folds, strict=True):
        assert {key: ship.parameter(key) for key in fold.values} == dict(fold.values)
        assert ship.effects == model.effects
    for key, error in validation.jackknife_errors().items():
        assert jackknife_error([ship.parameter(key) for ship in folds]) == pytest.approx(error, rel=1e-12), key
    figures = tmp_path / "figures.json"
    assert main(["manoeuvre", "--ship", str(path), "--turn-angle", "20", "--json", str(figures)]) == 0
    steady = json.loads(figures.read_text())["manoeuvres"][0]["figures"]["steady_rate_of_turn"]

    def steady_rate(ship: ShipModel) -> float:
        normalised = ship.parameter("yaw.gain") * (math.radians(20.0) + ship.parameter("rudder_offset.angle"))
        gain, cubic = ship.parameter("speed_loss.gain"), ship.parameter("speed_loss.cubic")
        loss = brentq(lambda u: u + cubic * u**3 - gain * normalised**2, 0.0, 1.0)
        return math.degrees(normalised * ship.service_speed * (1.0 - loss) / ship.length)

    assert steady["value"] == pytest.approx(steady_rate(model), rel=1e-6)
    assert steady["std_error"] == pytest.approx(jackknife_error([steady_rate(ship) for ship in folds]), rel=1e-5)
    assert steady["std_error"] > 0.0


def test_a_figures_jackknife_error_is_the_spread_of_the_folds():
    assert jackknife_error([1.0, 2.0, 3.0, 4.0]) == pytest.approx(math.sqrt(3 / 4 * 5.0))
    assert math.isnan(jackknife_error([1.0, math.nan, 3.0]))  # a fold that did not reach the figure
    assert math.isnan(jackknife_error([1.0]))
    assert fold_models(ShipModel("kvlcc2")) == []  # a built-in preset records no fold fits


def test_a_fold_that_cannot_sail_a_manoeuvre_leaves_that_manoeuvre_without_an_error_and_says_so(
    fitted, tmp_path, capsys
):
    """One fold's K* made ten times the fit's: it stops dead in the turning circle (its speed loss past the ship's
    speed), so the turn's figures get no error and the printout says which manoeuvre and how many folds."""
    _, path = fitted
    document = yaml.safe_load(path.read_text())
    record = document["fitted"]["jackknife"]
    record["values"][0][record["terms"].index("yaw.gain")] *= 10.0
    changed = tmp_path / "changed.yaml"
    changed.write_text(yaml.safe_dump(document, sort_keys=False))
    figures = tmp_path / "figures.json"
    assert main(["manoeuvre", "--ship", str(changed), "--zigzag", "10/10", "--json", str(figures)]) == 0
    printed = capsys.readouterr().out
    assert "none where fold fits cannot sail the manoeuvre: turning circle 35 (1 of 3)" in printed, printed
    turn, zigzag_10 = json.loads(figures.read_text())["manoeuvres"][:2]
    assert all("std_error" not in figure for figure in turn["figures"].values())
    assert zigzag_10["figures"]["first_overshoot"]["std_error"] > 0.0


def test_a_malformed_fold_record_is_refused_naming_the_field(fitted, tmp_path):
    _, path = fitted
    document = yaml.safe_load(path.read_text())
    document["fitted"]["jackknife"]["values"][1].pop()
    broken = tmp_path / "broken.yaml"
    broken.write_text(yaml.safe_dump(document, sort_keys=False))
    with pytest.raises(ValueError, match="fitted.jackknife needs 'terms' and per fold as many 'values'"):
        fold_models(ShipModel(broken))


def test_the_preset_holds_the_fitted_values_bit_for_bit_and_recovers_the_truth(sailed, fitted):
    truth, _, _ = sailed
    validation, path = fitted
    model = ShipModel(path)
    assert model.effects == validation.fit.setup.model.effects
    errors = standard_errors(validation)
    jackknife = validation.jackknife_errors()
    for estimate in validation.fit.estimates:
        key = estimate.term.key
        assert model.parameter(key) == estimate.value, key  # exact: written at repr precision
        assert model.ship.std_errors[key] == errors[key] == max(estimate.std_error, jackknife[key]), key
        assert abs(estimate.value - truth.model.parameter(key)) < SIGMAS * errors[key], key
    # The particulars and the numbers not fitted are the starting preset's, with their sources.
    start = load_ship(SHIP)
    assert model.ship.principal == start.principal
    assert model.parameter("yaw.linear") == start.values["yaw"]["linear"]
    assert model.ship.sources["yaw.linear"] == start.sources["yaw.linear"]


def test_a_resail_with_the_preset_reproduces_the_fits_replay(sailed, fitted):
    _, _, logs = sailed
    validation, path = fitted
    replays = simulate(ReplayModel(ShipModel(path)), logs)
    for ours, fits in zip(replays, simulate(validation.fit.setup, logs), strict=True):
        assert np.max(np.abs(ours.heading - fits.heading)) <= 1e-9
        assert np.max(np.abs(ours.rate_of_turn - fits.rate_of_turn)) <= 1e-9
        assert np.max(np.abs(np.hypot(ours.north - fits.north, ours.east - fits.east))) <= 1e-9


def test_the_preset_names_its_logs_by_hash_and_takes_the_datas_range_as_envelope(sailed, fitted):
    _, folder, logs = sailed
    validation, path = fitted
    document = yaml.safe_load(path.read_text())
    hashes = {file.name: hashlib.sha256(file.read_bytes()).hexdigest()[:12] for file in folder.glob("*.csv")}
    assert {entry["file"]: entry["sha256"] for entry in document["fitted"]["logs"]} == hashes
    for name, digest in hashes.items():
        assert f"{name} (sha256 {digest})" in document["effects"]["yaw"]["gain"]["source"]
    held_out = validation.pooled.in_display_units()
    assert document["fitted"]["held_out"]["heading"] == held_out["heading"]
    envelope = load_ship(path).envelope
    ranges = validation.coverage.ranges
    # The preset's minimum speed (0.1 m/s) and maximum drift (40 deg) are wider than the runs': the data's hold.
    assert envelope.minimum_speed == ranges["speed"].low
    assert envelope.maximum_drift == pytest.approx(ranges["drift"].high, rel=1e-12)
    assert envelope.maximum_rate == pytest.approx(ranges["rate"].high * ranges["speed"].high / 3.0, rel=1e-12)
    assert envelope.propeller_ahead_only is True
    assert "the fitted data's range" in document["envelope"]["maximum_rate"]["source"]


def test_a_narrower_preset_limit_is_kept_and_says_so():
    preset = {"maximum_rate": {"value": 2.0, "unit": "deg/s", "source": "model tests"}}
    limits = {
        "maximum_rate": DataLimit(3.0, "deg/s", "the fitted data's range"),
        "maximum_drift": DataLimit(12.0, "deg", "the fitted data's range"),
    }
    section = envelope_section({"envelope": preset}, limits)
    assert section["maximum_rate"]["value"] == 2.0
    assert section["maximum_rate"]["source"] == "model tests (kept: narrower than the fitted data's range, 3 deg/s)"
    assert section["maximum_drift"] == {"value": 12.0, "unit": "deg", "source": "the fitted data's range"}
    wider = envelope_section({"envelope": {**preset, "maximum_rate": {**preset["maximum_rate"], "value": 5.0}}}, limits)
    assert wider["maximum_rate"]["value"] == 3.0
    # Logs that reverse the propeller widen nothing the preset restricts to ahead: its limit is kept and says so.
    ahead = {"propeller_ahead_only": {"value": True, "source": "no astern model"}}
    astern = {"propeller_ahead_only": DataLimit(False, None, "the fitted data's range: astern in run_3")}
    kept = envelope_section({"envelope": ahead}, astern)["propeller_ahead_only"]
    assert kept == {
        "value": True,
        "source": "no astern model (kept: narrower than the fitted data's range, ahead and astern)",
    }


def test_the_simulator_and_the_environments_sail_the_preset(fitted):
    _, path = fitted
    simulator = Simulator(ShipModel(path), dt=0.2)
    simulator.reset(seed=0, conditions=Conditions(service_speed=0.35, propeller_rate=12.0))
    for _ in range(50):
        simulator.step(math.radians(10.0))
    assert np.all(np.isfinite(simulator.heading)) and simulator.heading[0] > 0.0
    env = gym.make("ship_env/CourseChange-v0", ship=str(path))
    observation, _ = env.reset(seed=0)
    observation, *_ = env.step(env.action_space.sample())
    assert np.all(np.isfinite(observation))
    assert env.unwrapped.task.model.parameter("yaw.gain") == ShipModel(path).parameter("yaw.gain")
    vector = gym.make_vec("ship_env/CourseChange-v0", num_envs=2, vectorization_mode="vector_entry_point", ship=path)
    observations, _ = vector.reset(seed=0)
    assert observations.shape[0] == 2 and np.all(np.isfinite(observations))


def _edited(path: Path, tmp_path: Path, edit) -> Path:
    document = yaml.safe_load(path.read_text())
    edit(document)
    edited = tmp_path / "edited.yaml"
    edited.write_text(yaml.safe_dump(document, sort_keys=False))
    return edited


@pytest.mark.parametrize(
    ("edit", "message"),
    [
        (
            lambda d: d["effects"].update(bow_thruster={"enabled": True}),
            "edited.yaml: effects: unknown effect 'bow_thruster'",
        ),
        (
            lambda d: d["effects"]["yaw"]["gain"].update(value=-0.5),
            "edited.yaml:yaw.gain: value -0.5 - is outside [0.0, inf]",
        ),
        (
            lambda d: d["effects"]["yaw"]["gain"].update(std_error=-1.0),
            "edited.yaml:yaw.gain.std_error: value -1.0 - is outside [0.0, inf]",
        ),
        (lambda d: d["principal"].pop("service_speed"), "edited.yaml: principal: missing service_speed"),
        (
            lambda d: d["effects"]["rudder_offset"].pop("angle"),
            "edited.yaml: effect 'rudder_offset' is on but has no value for 'angle'",
        ),
        (lambda d: d.update(fitted=["logs"]), "edited.yaml: fitted: expected a mapping"),
    ],
)
def test_a_bad_preset_names_the_file_and_the_field(fitted, tmp_path, edit, message):
    _, path = fitted
    with pytest.raises((ValueError, TypeError)) as error:
        ShipModel(_edited(path, tmp_path, edit))
    assert message in str(error.value)


def test_fit_writes_a_preset_that_compare_sails_and_never_overwrites_without_force(sailed, tmp_path, capsys):
    _, folder, _ = sailed
    preset = tmp_path / "ship.yaml"
    fit = ["fit", str(folder), "--ship", SHIP, "--add", "rudder_offset", "--workers", "1", "--preset", str(preset)]
    assert main(fit) == 0
    document = yaml.safe_load(preset.read_text())
    assert document["fitted"]["command"] == "ship-env " + " ".join(fit)
    rudder_covered = math.degrees(document["fitted"]["coverage"]["ranges"]["rudder"]["high"])
    assert (
        "its hard-over turning circle sails beyond the fitted runs: r* up to "  # fitted on 20/20 zig-zags
        in (printed := capsys.readouterr().out)
    ), printed
    assert f"rudder up to 35 deg (|rudder| <= {rudder_covered:.3g} deg)" in printed
    assert "fit-mmg" not in printed  # the runs' 20 deg rudder is not the hard-over turn's: no form is fitted there
    with pytest.warns(CoverageWarning, match="sailed at rudder 35 deg"):  # left for the user's own sailing
        Simulator(ShipModel(preset)).step(math.radians(35.0))
    assert document["effects"]["rudder_offset"]["enabled"] is True
    capsys.readouterr()
    assert main(["compare", str(folder), "--ship", str(preset), "--model", "default"]) == 0
    assert "yaw, speed_loss, rudder_offset, kinematics" in capsys.readouterr().out
    written = preset.read_text()
    assert main(fit) == 1
    output = capsys.readouterr()
    assert f"--preset: {str(preset)!r} exists; choose another name or pass --force" in output.err
    assert "fitted terms" not in output.out  # refused before any fitting
    assert preset.read_text() == written
    assert main([*fit, "--force"]) == 0


def test_a_preset_whose_hard_over_turn_diverges_is_written_and_says_so(sailed, tmp_path, capsys, monkeypatch):
    _, folder, _ = sailed
    preset = tmp_path / "ship.yaml"

    def diverging(model: ShipModel) -> list[str]:
        raise FloatingPointError("ship 0 left the model's validity at t = 47.5 s: speed_loss u* = 1.010 > 1")

    monkeypatch.setattr("ship_env.manoeuvres.extrapolation.hard_over_turn_beyond", diverging)
    assert main(["fit", str(folder), "--ship", SHIP, "--workers", "1", "--preset", str(preset)]) == 0
    printed = capsys.readouterr().out
    assert "its hard-over turning circle leaves the model's validity: ship 0 left the model's validity" in printed
    assert ShipModel(preset).has("yaw")


@pytest.mark.slow
def test_improve_writes_its_final_model_as_a_preset(sailed, tmp_path):
    _, folder, _ = sailed
    preset = tmp_path / "improved.yaml"
    improve = [
        "improve",
        str(folder),
        "--ship",
        SHIP,
        "--candidates",
        "rudder_offset",
        "--pairs",
        "0",
        "--workers",
        "1",
    ]
    assert main([*improve, "--report", str(tmp_path / "report"), "--preset", str(preset)]) == 0
    model = ShipModel(preset)
    assert model.has("rudder_offset")  # the ladder adds the hidden offset
    assert model.ship.std_errors["rudder_offset.angle"] > 0.0
    assert "rudder_offset.angle" in yaml.safe_load(preset.read_text())["fitted"]["terms"]


def test_compare_sails_a_preset_in_the_current_its_fit_found(tmp_path, capsys):
    """The fitted current is a condition of the runs (``fitted.conditions``): compare --ship replays in it."""
    manoeuvres = [Manoeuvre(f"zigzag_{i}", "zigzag", math.radians(sign * 20.0), 40.0) for i, sign in enumerate((1, -1))]
    _, logs = hidden_effect_logs(("current",), SHIP, seed=5, manoeuvres=manoeuvres)
    for log in logs:
        write_log(log, tmp_path / f"{log.name}.csv")
    logs = load_logs([tmp_path])
    setup = ReplayModel(ShipModel(SHIP, ["yaw", "kinematics", "current"]))
    options = FitOptions(scales=ErrorScales.for_runs(setup.model, logs), workers=1)
    validation = cross_validate(setup, logs, ["current.north", "current.east"], options)
    path = tmp_path / "in_current.yaml"
    write_preset(preset_document(validation, logs, "ship-env fit (test)", path.stem), path)
    assert set(yaml.safe_load(path.read_text())["fitted"]["conditions"]) == {"current.north", "current.east"}
    fits = compare(validation.fit.setup, logs, options.initial_window)
    expected = error_table(fits.errors, options.scales, fits.pooled).text()
    still = compare(ReplayModel(validation.fit.setup.model), logs, options.initial_window)
    assert error_table(still.errors, options.scales, still.pooled).text() != expected  # the current shows
    capsys.readouterr()
    assert main(["compare", str(tmp_path), "--ship", str(path), "--model", "default"]) == 0
    assert expected in capsys.readouterr().out


def test_the_leaderboard_sails_the_preset_with_autopilots_designed_from_it(fitted):
    """A preset written from a fit is a leaderboard's ship: named in its tables, the four classic
    course-changing autopilots (designed from its fitted K*, tau*) settle a 30 deg change each way."""
    _, path = fitted
    spec = SuiteSpec(
        course_changes_deg=(30.0,),
        tracks=(),
        conditions=(NOMINAL,),
        course_change_disturbances=("calm",),
        ship=str(path),
    )
    board = run_leaderboard(spec, shipped=False, progress=False)
    assert board.ship_name == path.stem
    rows = [line for line in board.markdown().splitlines() if "| classic |" in line]
    assert len(rows) == 4 and all("| 2/2 |" in row for row in rows), rows


def test_a_ship_that_leaves_its_models_validity_leaves_the_suite_out_in_one_line(fitted, tmp_path):
    """A preset whose speed loss stops the ship in a course change (K_u* = 20, u* > 1) cannot be sailed by any
    controller: the leaderboard says so in one line for the suite, naming the first failure, and ranks nothing
    there, where it raised the simulator's FloatingPointError through its whole stack."""
    _, path = fitted
    stopping = _edited(
        path,
        tmp_path,
        lambda document: document["effects"]["speed_loss"].update(
            enabled=True, gain={"value": 20.0, "source": "test"}, time_constant={"value": 0.5, "source": "test"}
        ),
    )
    spec = SuiteSpec(
        course_changes_deg=(90.0,),
        tracks=(),
        conditions=(NOMINAL,),
        course_change_disturbances=("calm",),
        ship=str(stopping),
    )
    board = run_leaderboard(spec, shipped=False, progress=False)
    (line,) = board.left_out
    assert "every controller fails" in line and "left the model's validity" in line and "not ranked" in line
    assert board.suites == () and board.results == ()


def test_the_manoeuvres_say_how_far_they_sail_beyond_the_fitted_runs(fitted, tmp_path, capsys):
    """Fitted on 20 deg zig-zags, the preset's 35 deg turn sails beyond its runs' rudder and r*; the printout and
    the JSON say how far, each against the runs' range. The turn's largest r* is its steady one, K* (delta +
    delta_0) for this Nomoto ship (2.26): r* rises to it without overshoot (thesis Fig. 2.7)."""
    _, path = fitted
    model = ShipModel(path)
    ranges = yaml.safe_load(path.read_text())["fitted"]["coverage"]["ranges"]
    figures = tmp_path / "figures.json"
    assert main(["manoeuvre", "--ship", str(path), "--zigzag", "10/10", "--json", str(figures)]) == 0
    printed = capsys.readouterr().out
    steady = model.parameter("yaw.gain") * (math.radians(35.0) + model.parameter("rudder_offset.angle"))
    rudder = f"rudder up to 35 deg (|rudder| <= {math.degrees(ranges['rudder']['high']):.3g} deg)"
    rate = f"r* up to {steady:.3g} (|r*| <= {ranges['rate']['high']:.3g})"
    assert f"  turning circle 35 deg stbd: {rate}; {rudder}" in printed, printed
    turn, zigzag_10 = json.loads(figures.read_text())["manoeuvres"][:2]
    assert turn["beyond_coverage"] == [rate, rudder]
    assert zigzag_10["beyond_coverage"] == []  # a 10/10 zig-zag stays inside the 20/20 runs
