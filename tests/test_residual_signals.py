"""Diagnosis past the library: the missing yaw acceleration follows the signal of the effect that made it."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from ship_env.model import REQUIRED_EFFECTS, ShipModel
from ship_env.workbench import fit
from ship_env.workbench.deciding.signals import plot_signals, residual_signals
from ship_env.workbench.fitting.replay import ReplayModel
from ship_env.workbench.synthetic.synthetic import model_test_programme, sail_all

#: The Esso Osaka hull with the nominal coefficients these checks were designed on (not the identified preset).
SHIP = str(Path(__file__).parent / "data" / "esso_osaka_nominal.yaml")
SHORT_RUNS = model_test_programme(duration=60.0)


def _signals(truth: ReplayModel, logs):
    fitted = fit(ShipModel(SHIP, REQUIRED_EFFECTS), logs)
    return residual_signals(fitted.setup, logs)


@pytest.mark.parametrize(
    ("hidden", "parameters", "expected"),
    [
        ((), {}, None),
        (("norrbin",), {"norrbin.cubic": 2.0, "norrbin.odd_quadratic": 0.0}, {"rate_cubed", "rate_squared_signed"}),
        (("rudder_offset",), {"rudder_offset.angle": math.radians(2.0)}, {"speed_squared"}),
        (("propeller_slipstream",), {}, {"rudder_propeller"}),
        (("wind_moment",), {}, {"wind_bow"}),
    ],
)
def test_the_missing_yaw_acceleration_follows_the_hidden_effects_signal(hidden, parameters, expected):
    truth = ReplayModel(ShipModel(SHIP, [*REQUIRED_EFFECTS, *hidden], parameters))
    logs = sail_all(truth, SHORT_RUNS, seed=2)
    signals = _signals(truth, logs)
    strongest = signals.strongest
    if expected is None:
        # The fitted model is the truth: nothing but noise is left, no signal stands out.
        assert abs(strongest.correlation) < 0.3, signals.text()
    else:
        assert strongest.signal.name in expected, signals.text()
        assert abs(strongest.correlation) > 0.6, signals.text()


@pytest.mark.slow
def test_a_stalling_rudder_points_to_the_rudder_and_is_drawn(tmp_path):
    import effect_plugin

    from ship_env.model import EFFECTS, register_effect

    register_effect(effect_plugin.EFFECT, effect_plugin.CONTRIBUTIONS)
    try:
        truth = ReplayModel(ShipModel(SHIP, [*REQUIRED_EFFECTS, "rudder_lift_loss"], {"rudder_lift_loss.loss": 0.8}))
        logs = sail_all(truth, SHORT_RUNS, seed=2)
    finally:
        EFFECTS.unregister("rudder_lift_loss")
    signals = _signals(truth, logs)
    assert signals.strongest.signal.name in {"rudder_squared", "rudder_cubed"}, signals.text()
    assert signals.strongest.correlation < -0.6  # the ship turns less than the linear model at large rudder
    assert "look for a rudder force" in signals.text()
    path = plot_signals(signals, tmp_path / "signals.png")
    assert path.stat().st_size > 10_000
