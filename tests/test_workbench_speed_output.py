"""A fit is a free-running ship: with a speed channel the replay predicts the speed, the fit fits the speed loss.

The measured speed sets only each run's service speed U0 and its initial speed (``replay`` module
docstring); the model's own speed U0 (1 - u*) (thesis 2.53, 2.55) is integrated, scored and tabled.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from ship_env.model import REQUIRED_EFFECTS, ShipModel
from ship_env.workbench import FitOptions, ReplayModel, cross_validate, fit, simulate
from ship_env.workbench.fitting.errors import ErrorScales, pooled, run_errors
from ship_env.workbench.fitting.terms import default_terms
from ship_env.workbench.reporting.documents import fit_document
from ship_env.workbench.reporting.presets import preset_document
from ship_env.workbench.reporting.tables import error_table
from ship_env.workbench.synthetic.synthetic import NO_NOISE, LogSettings, Manoeuvre, SensorNoise, noise_scales, sail_all

SHIP = "esso_osaka_model"
#: The true speed loss: K_u* 3 and tau_u* 3 ship lengths (a third of the speed lost in the 35 deg turn).
TRUE_SPEED_LOSS = {"speed_loss.gain": 3.0, "speed_loss.time_constant": 3.0}


def truth() -> ReplayModel:
    return ReplayModel(ShipModel(SHIP, [*REQUIRED_EFFECTS, "speed_loss"], TRUE_SPEED_LOSS))


def manoeuvres() -> list[Manoeuvre]:
    """Turns and zig-zags from the approach speed, and one zig-zag accelerating from 0.15 m/s."""
    return [
        Manoeuvre("turn_35", "turn", math.radians(35.0), 120.0, start_speed=0.35, final_speed=0.35),
        Manoeuvre("turn_m25", "turn", math.radians(-25.0), 120.0, start_speed=0.3, final_speed=0.3),
        Manoeuvre("zigzag_20", "zigzag", math.radians(20.0), 120.0, start_speed=0.4, final_speed=0.4),
        Manoeuvre("zigzag_m15", "zigzag", math.radians(-15.0), 120.0, start_speed=0.15, final_speed=0.35),
    ]


def test_a_replay_predicts_the_speed_instead_of_following_the_measured_one():
    """The free replay sails at the model's own speed: a measured speed that differs after the start (here
    halved) changes neither the replayed speed nor the heading; the true model's replay is the log's speed."""
    model = truth()
    log = sail_all(model, manoeuvres()[:1], seed=5, settings=LogSettings(noise=NO_NOISE))[0]
    replayed = simulate(model, [log], window=0.0)[0]
    later = log.time > 5.0
    halved = dataclasses.replace(log, speed=np.where(later, 0.5 * log.speed, log.speed))  # U0: the log's own
    other = simulate(model, [halved], window=0.0)[0]
    np.testing.assert_array_equal(other.heading, replayed.heading)
    np.testing.assert_array_equal(other.speed, replayed.speed)
    np.testing.assert_allclose(replayed.speed, log.speed, rtol=0.0, atol=1e-9)
    assert replayed.speed[-1] < 0.8 * replayed.speed[0]  # the 35 deg turn's speed loss, predicted
    # The track replay imposes the measured speed, as it does the heading.
    np.testing.assert_allclose(other.track_speed, halved.speed, rtol=0.0, atol=1e-12)


def test_the_fit_recovers_a_true_speed_loss_from_the_speed_channel():
    """Logs of a ship losing speed in its turns: a fit of the speed-scheduled Nomoto ship turns the speed loss on
    and finds K_u* and tau_u*, with each run's service speed given (U0 exact) and estimated from the speed."""
    noise = SensorNoise()
    logs = sail_all(truth(), manoeuvres(), seed=11, settings=LogSettings(noise=noise))
    start = ShipModel(SHIP, REQUIRED_EFFECTS, {"speed_loss.gain": 1.0, "speed_loss.time_constant": 8.0})
    options = FitOptions(scales=noise_scales(noise))
    # Estimated, U0 is that of the runs that start at their approach speed (a run still accelerating at its end
    # never shows it).
    estimated = [dataclasses.replace(log, service_speed=None) for log in logs[:3]]
    for tolerance, runs in ((0.05, logs), (0.1, estimated)):
        result = fit(start, runs, options=options)
        assert result.setup.model.has("speed_loss")
        values = result.values()
        for key in ("speed_loss.gain", "speed_loss.time_constant"):
            assert values[key] == pytest.approx(TRUE_SPEED_LOSS[key], rel=tolerance), (key, values)
        assert result.pooled.speed < 3.0 * noise.speed


def test_the_speed_error_is_in_the_score_and_the_tables():
    model = truth()
    logs = sail_all(model, manoeuvres()[:2], seed=3, settings=LogSettings(noise=SensorNoise()))
    constant_speed = ReplayModel(model.model.without_effects("speed_loss"))
    errors = [run_errors(log, replayed) for log, replayed in zip(logs, simulate(constant_speed, logs), strict=True)]
    for log, error, replayed in zip(logs, errors, simulate(constant_speed, logs), strict=True):
        assert error.speed == pytest.approx(float(np.sqrt(np.mean((replayed.speed - log.speed) ** 2))))
        assert error.speed > 0.02  # a ship held at its service speed misses the turn's speed loss
    scales = ErrorScales.for_ship(3.0, 0.3)
    assert scales.speed_error == pytest.approx(0.3 * math.radians(1.0))
    without_speed = dataclasses.replace(errors[0], speed=math.nan)
    assert errors[0].score(scales) ** 2 == pytest.approx(
        (3.0 * without_speed.score(scales) ** 2 + (errors[0].speed / scales.speed_error) ** 2) / 4.0
    )
    table = error_table(errors, scales, pooled(errors)).text()
    assert "speed [m/s]" in table
    assert f"{pooled(errors).speed:.2g}" in table.splitlines()[-1]


def test_without_a_speed_channel_the_fit_says_the_speed_loss_is_not_identified():
    """No speed: the speed-loss terms are not fitted (the preset's values kept), and the fit's document and
    preset say so and name what the fit took from the logs."""
    logs = sail_all(truth(), manoeuvres()[:3], seed=2, settings=LogSettings(measure_speed=False))
    assert default_terms(truth().model.effects, logs) == ["yaw.gain", "yaw.time_constant"]
    validation = cross_validate(truth(), logs)
    assert [e.term.key for e in validation.fit.estimates] == ["yaw.gain", "yaw.time_constant"]
    assert validation.fit.setup.model.parameter("speed_loss.gain") == TRUE_SPEED_LOSS["speed_loss.gain"]
    document = fit_document(validation, ErrorScales.for_runs(truth().model, logs), logs=logs)
    assert document["not_identified"] and "does not identify the speed loss" in document["not_identified"][0]
    assert "starting preset's values" in document["not_identified"][0]
    assert document["inputs"][:3] == ["rudder", "propeller_rate", "wind_speed"]
    assert document["inputs"][-1].startswith("service speed")
    preset = preset_document(validation, logs, "test", "no_speed")
    assert preset["fitted"]["not_identified"] == document["not_identified"]
    assert preset["fitted"]["inputs"] == document["inputs"]
    with_speed = sail_all(truth(), manoeuvres()[:3], seed=2)
    validation = cross_validate(truth(), with_speed)
    document = fit_document(validation, ErrorScales.for_runs(truth().model, with_speed), logs=with_speed)
    assert document["not_identified"] == []
    assert "speed_loss.gain" in document["values"]
    assert document["inputs"][-1].startswith("speed: each run's service speed U0 and initial speed only")
