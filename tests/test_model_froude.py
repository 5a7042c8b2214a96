"""Froude scaling (``ship_env.model.froude``): a scaled preset moves as the original, in ship lengths.

With lambda = L_new / L_old, the scaled ship sailed in the scaled conditions with a time step
scaled by lambda^1/2 meets, at every step, the same equations in the same non-dimensional variables
(r* = L r / u, s* = u t / L): its positions are the original's times lambda, its times times
lambda^1/2, its angles the same. Only rounding differs: float64 rounds each operation by at most
2^-53 = 1.1e-16 relatively; a step's hundred-odd operations in four stages over a few thousand steps
make some 1e5 roundings, which, added in the worst case and not amplified by a stable turn, bound
the relative difference by about 1e-11. The tolerance, 1e-9, lies above that bound and a billionth
of any physical difference (measured: 2.8e-15 at most, kvlcc2 at 320 m and 7 m).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
import yaml

from ship_env.cli import main
from ship_env.manoeuvres import TrialSettings, turning_circle, zigzag
from ship_env.model import Conditions, ShipModel, Simulator, load_ship
from ship_env.model import state as S
from ship_env.model.froude import (
    CONDITION_UNITS,
    COVERAGE_UNITS,
    ScalingError,
    scale_document,
    scaled_conditions,
    unit_exponent,
)
from ship_env.model.registry import EFFECTS, register_effect
from ship_env.workbench.judging.coverage import QUANTITIES

TOLERANCE = 1e-9  # relative: rounding only (module docstring)
MODEL_LENGTH = 7.0  # the SIMMAN KVLCC2 model, m
SCALE = MODEL_LENGTH / 320.0


@pytest.fixture(scope="module")
def ships() -> tuple[ShipModel, ShipModel]:
    full = ShipModel("kvlcc2")
    return full, full.scaled(length=MODEL_LENGTH)


def test_every_unit_is_scaled_by_its_dimensions():
    """lambda^(a + b/2 + 3c) for m^a s^b kg^c; display units as the SI unit they convert to."""
    expected = {
        "-": 0.0,
        "rad": 0.0,
        "deg": 0.0,
        "m": 1.0,
        "s": 0.5,
        "m/s": 0.5,
        "kn": 0.5,
        "rad/s": -0.5,
        "deg/s": -0.5,
        "rps": -0.5,
        "rpm": -0.5,
        "rad/s^2": -1.0,
        "rad/m^2": -2.0,
        "1/m^2": -2.0,
        "m^2": 2.0,
        "kg": 3.0,
        "kg*m^2": 5.0,
        "U0": 0.0,  # the ship's own speed and length: the same fraction of them at every scale
        "U0/L": 0.0,
        "L": 0.0,
        "L/U0": 0.0,
    }
    assert {unit: unit_exponent(unit, "test") for unit in expected} == expected


def test_every_declared_parameter_has_a_known_scaling():
    """Each built-in effect's parameters, the principal particulars and the conditions have a unit the rule reads."""
    for name in EFFECTS:
        for parameter in EFFECTS[name].parameters:
            unit_exponent(parameter.unit, f"{name}.{parameter.name}")
    assert set(CONDITION_UNITS) >= {field.name for field in dataclasses.fields(Conditions)}
    assert set(CONDITION_UNITS) >= set(S.CONDITION_NAMES)
    assert set(COVERAGE_UNITS) == set(QUANTITIES)


def test_scaled_preset_values(ships):
    """Lengths x lambda, speeds x lambda^1/2, the rudder rate x lambda^-1/2, coefficients kept; sources say so."""
    full, model = ships
    assert model.length == pytest.approx(7.0, rel=1e-15)
    assert model.service_speed == pytest.approx(full.service_speed * math.sqrt(SCALE), rel=1e-15)
    # SIMMAN 2020 case 1.2: 1.18 m/s and 15.68 deg/s at model scale
    assert model.service_speed == pytest.approx(1.18, abs=0.005)
    assert math.degrees(model.parameter("steering_machine.rudder_rate")) == pytest.approx(15.68, abs=0.01)
    for key in ("yaw.gain", "yaw.time_constant", "norrbin.cubic", "sway.linear", "wind_drift.force_ratio"):
        assert model.parameter(key) == full.parameter(key)
    diameter = model.parameter("propeller_slipstream.propeller_diameter")
    assert diameter == pytest.approx(full.parameter("propeller_slipstream.propeller_diameter") * SCALE, rel=1e-14)
    assert diameter == pytest.approx(0.216, abs=1e-3)  # Yasukawa & Yoshimura 2015, Table 1: the 7 m model's D_P
    assert model.parameter("wind_moment.yaw_coefficient") == pytest.approx(2.4e-8 / SCALE**2, rel=1e-15)
    assert model.parameter("gusts.time_constant") == pytest.approx(10.0 * math.sqrt(SCALE), rel=1e-15)
    assert model.envelope.maximum_rate == pytest.approx(full.envelope.maximum_rate / math.sqrt(SCALE), rel=1e-15)
    assert model.ship.sources["yaw.gain"].startswith("Froude-scaled from kvlcc2.yaml by lambda = 0.021875 (kept")
    assert "lambda^0.5" in model.ship.sources["principal.service_speed"]
    (step,) = model.ship.scaled
    assert (step["from_preset"], step["factor"], step["from_length"], step["to_length"]) == (
        "kvlcc2.yaml",
        SCALE,
        320.0,
        7.0,
    )


def _figures_in_lengths(model: ShipModel, dt: float) -> dict[str, float]:
    """IMO figures made non-dimensional: distances / L, times u / L, rates L / u; angles as they are."""
    settings = TrialSettings(dt=dt)
    length, speed = model.length, model.service_speed
    circle = turning_circle(model, math.radians(35.0), settings)
    zig = zigzag(model, math.radians(10.0), math.radians(10.0), settings)
    return {
        "advance": circle.advance / length,
        "tactical_diameter": circle.tactical_diameter / length,
        "time_to_90": circle.time_to_90 * speed / length,
        "steady_rate": circle.steady_rate_of_turn * length / speed,
        "speed_loss": circle.speed_loss,
        "drift_angle": circle.drift_angle,
        "first_overshoot": zig.first_overshoot,
        "second_overshoot": zig.second_overshoot,
        "initial_turning_time": zig.initial_turning_time * speed / length,
        "time_to_check_yaw": zig.time_to_check_yaw * speed / length,
    }


def test_scaled_ship_sails_the_same_manoeuvres_in_ship_lengths(ships):
    """Turning circle and 10/10 zig-zag: advance and tactical diameter in L, overshoots equal; times x lambda^1/2."""
    full, model = ships
    original = _figures_in_lengths(full, 0.5)
    scaled = _figures_in_lengths(model, 0.5 * math.sqrt(SCALE))
    assert all(math.isfinite(value) for value in original.values()), original
    assert original["tactical_diameter"] == pytest.approx(2.91, abs=0.05)  # the preset's own figure (a real turn)
    assert scaled == pytest.approx(original, rel=TOLERANCE)


def test_scaled_ship_in_scaled_conditions_follows_the_same_track(ships):
    """Propeller slipstream at 105 rpm, a current and a wind (its moment and drift), the rudder at 10 deg then -10:
    the track scales by lambda, the time by lambda^1/2, heading and drift angle kept."""
    full, model = ships
    parameters = {"propeller_slipstream.coefficient": 0.25}
    full = full.with_effects("propeller_slipstream").with_parameters(parameters)
    model = model.with_effects("propeller_slipstream").with_parameters(parameters)
    conditions = Conditions(
        propeller_rate=105.2 / 60.0, current_speed=0.4, current_direction=0.7, wind_speed=14.0, wind_direction=1.1
    )
    histories = []
    for ship, dt, sailed in ((full, 1.0, conditions), (model, math.sqrt(SCALE), scaled_conditions(conditions, SCALE))):
        simulator = Simulator(ship, dt=dt)
        simulator.reset(seed=3, conditions=sailed)
        rows = [simulator.state[0].copy()]
        for step in range(600):
            simulator.step(math.radians(10.0 if step < 300 else -10.0))
            rows.append(simulator.state[0].copy())
        histories.append(np.array(rows))
    original, scaled = histories
    lengths = np.array([0.5, 1.0, 1.0, 0.0, -0.5, 0.0, 0.0])  # time, north, east, heading, rate, u*, rudder
    factors = SCALE ** lengths[: S.MOTION_SIZE]
    assert np.abs(original[:, S.HEADING]).max() > 2.0  # it turned
    np.testing.assert_allclose(
        scaled[:, : S.MOTION_SIZE], original[:, : S.MOTION_SIZE] * factors, rtol=TOLERANCE, atol=1e-9
    )


def test_round_trip_gives_the_original_values(ships):
    """lambda then 1/lambda: every number the original's, to the rounding of the products and powers (a
    few 1e-16 relative: 1e-15 is about 9 roundings); Froude-invariant numbers exactly."""
    full, model = ships
    back = model.scaled(1.0 / SCALE).ship
    original = full.ship
    assert back.principal == pytest.approx(original.principal, rel=1e-15)
    for effect, values in original.values.items():
        assert back.values[effect] == pytest.approx(values, rel=1e-15), effect
    assert back.values["yaw"] == original.values["yaw"]
    for name, value in vars(original.envelope).items():
        kept = getattr(back.envelope, name)
        assert kept == (pytest.approx(value, rel=1e-15) if isinstance(value, float) else value), name
    assert [step["from_preset"] for step in back.scaled] == ["kvlcc2.yaml", "kvlcc2_scaled"]
    document = {**full.ship.document, "fitted": FITTED_RECORD}
    there = scale_document(document, SCALE, "fitted.yaml")
    again = scale_document(there, 1.0 / SCALE, "fitted_scaled")["fitted"]
    assert again["coverage"]["ranges"]["propeller"]["high"] == pytest.approx(1.8, rel=1e-15)
    assert again["held_out"] == pytest.approx(FITTED_RECORD["held_out"], rel=1e-15)
    assert again["conditions"]["current.north"]["std_error"] == pytest.approx(0.01, rel=1e-15)


FITTED_RECORD = {
    "from_preset": "kvlcc2.yaml",
    "error_units": {"heading": "deg", "rate_of_turn": "deg/s", "position": "m", "track": "m"},
    "held_out": {"heading": 3.0, "rate_of_turn": 0.2, "position": 40.0, "track": 10.0},
    "conditions": {"current.north": {"value": 0.2, "unit": "m/s", "std_error": 0.01, "source": "fitted"}},
    "operating_point": {"propeller_rate": {"value": 1.75, "unit": "rps", "source": "the fitted runs' rate"}},
    "service_conditions": {"propeller_rate": 1.75},
    "coverage": {
        "percentile": 99.0,
        "runs": ["z1"],
        "ranges": {
            "speed": {"low": 6.0, "high": 8.0},
            "rate": {"low": None, "high": 0.5},
            "propeller": {"low": 1.7, "high": 1.8},
        },
    },
}


def test_fitted_record_scales_by_its_units():
    """A fitted preset's current, operating point, coverage and held-out errors scale as their units say."""
    document = {**load_ship("kvlcc2").document, "fitted": FITTED_RECORD}
    scaled = scale_document(document, 0.25, "fitted.yaml")["fitted"]
    assert scaled["held_out"] == {"heading": 3.0, "rate_of_turn": 0.4, "position": 10.0, "track": 2.5}
    current = scaled["conditions"]["current.north"]
    assert (current["value"], current["std_error"]) == (0.1, 0.005)
    assert current["source"].startswith("Froude-scaled from fitted.yaml by lambda = 0.25 (x lambda^0.5): fitted")
    assert scaled["operating_point"]["propeller_rate"]["value"] == 3.5
    assert scaled["service_conditions"]["propeller_rate"] == 3.5
    assert scaled["coverage"]["ranges"] == {
        "speed": {"low": 3.0, "high": 4.0},
        "rate": {"low": None, "high": 0.5},
        "propeller": {"low": 3.4, "high": 3.6},
    }
    assert scaled["coverage"]["percentile"] == 99.0


def test_a_fitted_preset_s_jackknife_scales_each_term_by_its_unit():
    """The fold fits' values (``fitted.jackknife``, written by ``fit``/``improve --preset``) scale as their terms:
    the steering machine's rate in rad/s by lambda^-1/2, K* (non-dimensional) kept; a term that names no parameter
    is refused by name."""
    terms = ["steering_machine.rudder_rate", "yaw.gain"]
    jackknife = {"terms": terms, "values": [[0.04, 1.5], [0.06, 1.4]], "left_out": []}
    document = {**load_ship("kvlcc2").document, "fitted": {"jackknife": jackknife}}
    scaled = scale_document(document, 4.0, "fitted.yaml")["fitted"]["jackknife"]
    assert scaled["values"] == [[0.02, 1.5], [0.03, 1.4]] and scaled["terms"] == terms
    document["fitted"] = {"jackknife": {**jackknife, "terms": ["yaw.mystery", "yaw.gain"]}}
    with pytest.raises(ScalingError, match=r"fitted\.jackknife\.terms: 'yaw\.mystery'"):
        scale_document(document, 4.0, "fitted.yaml")


def test_a_number_of_unknown_scaling_is_refused():
    """A record's number with no unit, and a parameter in a unit the rule cannot read, are refused by name."""
    document = {**load_ship("kvlcc2").document, "fitted": {"mystery": 3.0}}
    with pytest.raises(ScalingError, match=r"fitted\.mystery: the Froude scaling of 3\.0 is not known"):
        scale_document(document, 2.0, "kvlcc2.yaml")
    with pytest.raises(ScalingError, match=r"heat\.temperature .*unit 'K'.*'K' is not known"):
        unit_exponent("K", "heat.temperature (water temperature)")


def test_a_parameter_in_an_unknown_unit_is_refused(tmp_path):
    """An effect from outside ship_env whose parameter is in kelvin: ``scale`` names the parameter."""
    from ship_env.model import Contribution, Effect, Parameter

    effect = Effect(
        "warm_water",
        "viscosity change with the water's temperature",
        "none",
        Parameter(
            "temperature", "K", "water temperature", minimum=250.0, maximum=320.0, default=288.0, source="assumed: 15 C"
        ),
    )
    register_effect(effect, [Contribution("side_moment", lambda temperature: 0.0 * temperature)])
    try:
        document = load_ship("kvlcc2").document
        document = {
            **document,
            "effects": {
                **document["effects"],
                "warm_water": {"enabled": True, "temperature": {"value": 290.0, "source": "test"}},
            },
        }
        with pytest.raises(ScalingError, match=r"effects\.warm_water\.temperature .*'K' is not known"):
            scale_document(document, 2.0, "kvlcc2.yaml")
    finally:
        EFFECTS.unregister("warm_water")


def test_scale_command_writes_a_preset_that_records_its_origin(tmp_path, capsys):
    """``ship-env scale kvlcc2 --length 7 -o OUT``: OUT loads, at 7 m, its record naming kvlcc2.yaml and lambda."""
    output = tmp_path / "kvlcc2_model.yaml"
    assert main(["scale", "kvlcc2", "--length", "7", "-o", str(output)]) == 0
    assert "lambda = 0.021875" in capsys.readouterr().out
    model = ShipModel(output)
    assert model.length == 7.0 and model.ship.name == "kvlcc2_model"
    assert yaml.safe_load(output.read_text())["scaled"][0]["factor"] == SCALE
    with pytest.raises(SystemExit):
        main(["scale", "kvlcc2", "--length", "7", "--factor", "2", "-o", str(tmp_path / "other.yaml")])


def test_scale_command_refuses_a_number_of_unknown_scaling(tmp_path, capsys):
    """A preset whose record holds a number without a unit: exit status 2, the message naming it, no OUT."""
    preset = tmp_path / "odd.yaml"
    preset.write_text(yaml.safe_dump({**load_ship("kvlcc2").document, "fitted": {"mystery": 3.0}}))
    output = tmp_path / "scaled.yaml"
    with pytest.raises(SystemExit) as stopped:
        main(["scale", str(preset), "--factor", "2", "-o", str(output)])
    assert stopped.value.code == 2
    assert "argument IN: fitted.mystery: the Froude scaling of 3.0 is not known" in capsys.readouterr().err
    assert not output.exists()


def test_a_preset_s_operating_point_scales_with_it(tmp_path):
    """The fitted preset's service propeller rate (``service_conditions``) turns lambda^-1/2 as fast."""
    document = {**load_ship("kvlcc2").document}
    document["service_conditions"] = {"propeller_rate": {"value": 12.0, "unit": "rps", "source": "fitted runs"}}
    path = tmp_path / "fitted.yaml"
    path.write_text(yaml.safe_dump(document))
    model = ShipModel(str(path))
    assert model.service_propeller_rate == 12.0
    assert model.scaled(factor=4.0).service_propeller_rate == pytest.approx(6.0, rel=1e-15)
