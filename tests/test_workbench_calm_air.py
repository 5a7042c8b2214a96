"""Calm air: a log whose true wind does not stand out of its anemometer's noise gives no wind effect to fit.

A calm basin logged through a noisy anemometer reads a clipped noise of a few hundredths of a metre per second; a
wind effect fitted there takes the ship's own motion through still air (an apparent wind from the drift angle) for a
wind, and a ladder once added ``wind_moment`` on such logs."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from ship_env.model import ShipModel
from ship_env.workbench.fitting.fit import fit_setup
from ship_env.workbench.fitting.replay import ReplayModel
from ship_env.workbench.fitting.terms import WIND_EFFECTS, effect_terms, not_identified, why_not_fitted
from ship_env.workbench.logs.logs import Log
from ship_env.workbench.synthetic.synthetic import (
    NO_NOISE,
    SEA_TRIAL_NOISE,
    LogSettings,
    SensorNoise,
    model_test_programme,
    sail_all,
)

SHIP = "esso_osaka_model"


def logs_in(wind_speed: float, noise: SensorNoise) -> list[Log]:
    """The 3 m model's test programme (zig-zags and turns) in a mean true wind of ``wind_speed``, m/s."""
    manoeuvres = [replace(m, wind_speed=wind_speed) for m in model_test_programme(duration=40.0)]
    return sail_all(ReplayModel(ShipModel(SHIP)), manoeuvres, seed=3, settings=LogSettings(noise=noise))


@pytest.mark.parametrize(
    ("noise", "wind_speed"),
    [(SensorNoise(), 1.8), (SEA_TRIAL_NOISE, 5.0), (NO_NOISE, 1.8)],
    ids=["basin", "sea_trial", "noise_free"],
)
def test_a_calm_runs_anemometer_noise_is_calm_air_and_a_wind_blows(noise, wind_speed):
    """The basin's anemometer (0.1 m/s of noise) and a ship's (0.5 m/s) read a clipped noise in calm air; a wind
    (the programme's 1.8 m/s, a breeze of 5 m/s at sea) with gusts of 30 % blows through either; a noise-free log of
    calm air is calm."""
    calm, windy = logs_in(0.0, noise), logs_in(wind_speed, noise)
    assert not any(log.has_wind_beyond_noise for log in calm)
    assert all(log.has_wind_beyond_noise for log in windy)


def test_the_noise_is_read_from_the_changes_so_a_light_steady_wind_blows():
    """A steady 0.2 m/s read through noise of 0.02 m/s stands ten deviations out; through 0.1 m/s it does not."""
    rng = np.random.default_rng(0)
    time = np.arange(500) * 0.2
    for deviation, blows in ((0.02, True), (0.1, False)):
        wind = np.maximum(0.2 + deviation * rng.standard_normal(time.size), 0.0)
        log = Log("light", time, np.zeros_like(time), np.zeros_like(time), wind_speed=wind, wind_direction=wind * 0.0)
        assert log.has_wind_beyond_noise is blows


@pytest.mark.parametrize("effect", WIND_EFFECTS)
def test_a_wind_effect_is_no_candidate_in_calm_air_and_is_one_in_a_wind(effect):
    model = ShipModel(SHIP)
    reason = why_not_fitted(effect, model, logs_in(0.0, SensorNoise()))
    assert reason is not None and reason.startswith("calm air") and "anemometer" in reason
    assert why_not_fitted(effect, model, logs_in(1.8, SensorNoise())) is None


def test_one_windy_run_among_calm_ones_makes_the_wind_effects_candidates():
    calm, windy = logs_in(0.0, SensorNoise()), logs_in(1.8, SensorNoise())
    assert why_not_fitted("wind_moment", ShipModel(SHIP), [*calm[1:], windy[0]]) is None


def test_a_fit_in_calm_air_holds_the_wind_effects_of_its_starting_model_and_says_so():
    """A model that starts with the wind effects on (a preset's weather) fits their terms in a wind and holds them at
    the preset's values in calm air, where they would be fitted on the ship's own motion through still air."""
    model = ShipModel(SHIP).with_effects(*WIND_EFFECTS)
    wind_terms = {key for name in WIND_EFFECTS for key in effect_terms(name)}
    calm, windy = logs_in(0.0, SensorNoise()), logs_in(1.8, SensorNoise())
    assert wind_terms <= set(fit_setup(model, windy, None, None).keys)
    assert not wind_terms & set(fit_setup(model, calm, None, None).keys)
    words = not_identified(model, calm)
    assert any(line.startswith("wind_moment, wind_drift: calm air") for line in words)
    assert not any("calm air" in line for line in not_identified(model, windy))
