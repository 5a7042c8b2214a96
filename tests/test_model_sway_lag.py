"""Sway that lags the rate of turn (``effects/sway_lag.py``) against its closed forms.

The drift's step response behind a first-order Nomoto ship against its closed form, a steady turn that
is the model's without the effect whatever the coupling, and the hidden-effect check: logs sailed with
the lag and its coupling, the model fitted with the effect added, its terms recovered.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from conftest import CONTAINER, run

from ship_env.model import REQUIRED_EFFECTS, ShipModel
from ship_env.workbench import FitOptions
from ship_env.workbench.fitting.fit import fit
from ship_env.workbench.fitting.terms import effect_terms, why_not_fitted
from ship_env.workbench.synthetic.synthetic import HIDDEN_VALUES, SensorNoise, hidden_effect_logs, noise_scales

LAGGING = ["yaw", "kinematics", "sway", "sway_lag"]
RUDDER = math.radians(10.0)


def test_the_drift_follows_a_rudder_step_as_two_first_order_lags():
    """Constant speed (no speed loss), the rudder stepped at t = 0: r = K delta (1 - exp(-t/T)) (2.58) and
    tau_v dv*/dt = -gamma1 L r / u - v*, so v*(t) = -gamma1 (L/u) K delta [1 - (T e^(-t/T) - tau_v e^(-t/tau_v))
    / (T - tau_v)] with T = tau* L / u, tau_v = tau_v* L / u, K = K* u / L. RK4 at 0.1 s against time constants
    of tens of seconds: errors of order (dt / T)^4, far below 1e-6."""
    model = ShipModel(CONTAINER, LAGGING, {"sway_lag.time_constant": 0.8, "sway.cubic": 0.0})
    speed, length = model.service_speed, model.length
    lag, yaw_time = 0.8 * length / speed, model.parameter("yaw.time_constant") * length / speed
    steady_rate = model.parameter("yaw.gain") * speed / length * RUDDER
    history = run(model, RUDDER, 300.0, dt=0.1)
    time = np.arange(len(history)) * 0.1
    column = model.state_names.index("lagging_drift")
    shape = 1.0 - (yaw_time * np.exp(-time / yaw_time) - lag * np.exp(-time / lag)) / (yaw_time - lag)
    expected = -model.parameter("sway.linear") * length / speed * steady_rate * shape
    np.testing.assert_allclose(history[:, column], expected, rtol=1e-6, atol=1e-9 * abs(expected[-1]))
    assert abs(history[60, column]) < 0.5 * abs(expected[-1])  # 6 s in: the drift has not caught up


def test_a_steady_turn_is_the_model_s_without_it_whatever_the_coupling():
    """In a steady turn v* is (2.47)'s and the coupling vanishes: r and the drift of the quasi-static model."""
    values = {"sway.cubic": 0.3, "sway_lag.coupling": 2.0}
    lagging = ShipModel(CONTAINER, [*LAGGING, "norrbin", "speed_loss"], values)
    settled = ShipModel(CONTAINER, ["yaw", "kinematics", "sway", "norrbin", "speed_loss"], values)
    end = run(lagging, math.radians(25.0), 3000.0)[-1]
    reference = run(settled, math.radians(25.0), 3000.0)[-1]
    for name in ("rate_of_turn", "speed_loss"):
        assert end[lagging.state_names.index(name)] == pytest.approx(reference[settled.state_names.index(name)])
    speed = lagging.service_speed * (1.0 - end[lagging.state_names.index("speed_loss")])
    normalised = lagging.length * end[lagging.state_names.index("rate_of_turn")] / speed
    settled_drift = -(lagging.parameter("sway.linear") * normalised + 0.3 * normalised**3)
    assert end[lagging.state_names.index("lagging_drift")] == pytest.approx(settled_drift, rel=1e-9)


def test_the_ladder_can_propose_it_for_any_preset():
    model = ShipModel(CONTAINER)
    assert why_not_fitted("sway_lag", model, []) is None
    assert effect_terms("sway_lag") == ("sway_lag.time_constant", "sway_lag.coupling")


def test_hidden_sway_lag_is_recovered_by_a_fit_that_adds_it():
    """Logs sailed by the 3 m model with its drift lagging (tau_v* 0.6) and coupled (n_v 3), a basin's sensors:
    the model with the effect added recovers both within 15 %."""
    truth_values = {"sway_lag.time_constant": 0.6, "sway_lag.coupling": 3.0}
    ship = "esso_osaka_model"
    _, logs = hidden_effect_logs(["sway", "sway_lag"], ship, values={**HIDDEN_VALUES, **truth_values})
    model = ShipModel(ship, [*REQUIRED_EFFECTS, "sway", "sway_lag"])
    result = fit(model, logs, options=FitOptions(scales=noise_scales(SensorNoise())))
    found = {e.term.key: e for e in result.estimates}
    for key, value in truth_values.items():
        print(f"\n{key}: {found[key].value:.4f} +- {found[key].std_error:.4f} (truth {value})")
        assert found[key].value == pytest.approx(value, rel=0.15)
