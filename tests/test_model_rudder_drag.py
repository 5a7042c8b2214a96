"""The rudder's drag in the speed loss (``effects/rudder_drag.py``) against its closed forms.

Its null (C_R* = 0) is the thesis's speed loss (2.55) bit for bit; the steady turn's surge balance
u* + beta3 u*^3 = K_u* r*^2 + C_R* sin^2(delta) (1 - u*) holds in a simulated turning circle (no slipstream:
u_R^2 = u^2); a ship that barely turns (K* tiny) with its rudder held loses C_R* sin^2(delta) / (1 + C_R*
sin^2(delta)); port and starboard lose alike; the propeller's slipstream keeps the drag up, to the closed form
with u_R^2 = u^2 + c_s (n D)^2; the term is a candidate only where a log measures the speed; and the hidden-effect
check: logs sailed with the drag, the model fitted with it added, C_R* recovered.
"""

from __future__ import annotations

import math
from dataclasses import replace

import pytest
from speed_loss_checks import HARD_OVER, assert_same_hard_over_turn, recovered, steady_turn

from ship_env.model import Conditions, ShipModel, Simulator
from ship_env.model import state as S
from ship_env.workbench.fitting.replay import ReplayModel
from ship_env.workbench.fitting.terms import effect_terms, make_term, why_not_fitted
from ship_env.workbench.synthetic.synthetic import model_test_programme, sail_all

SHIP = "kvlcc2"
TURNING = ("yaw", "norrbin", "speed_loss", "steering_machine", "kinematics")


def with_drag(model: ShipModel, coefficient: float) -> ShipModel:
    return model.with_effects("rudder_drag").with_parameters({"rudder_drag.drag_coefficient": coefficient})


def test_its_null_is_the_thesis_speed_loss_bit_for_bit():
    thesis = ShipModel(SHIP, TURNING)
    assert_same_hard_over_turn(thesis, with_drag(thesis, 0.0))


@pytest.mark.parametrize("coefficient", [0.5, 2.0])
def test_the_steady_turn_holds_the_surge_balance(coefficient):
    """u* + beta3 u*^3 = K_u* r*^2 + C_R* sin^2(delta) (1 - u*) (2.55, 2.39 with this effect's forcing, u_R = u)."""
    model = with_drag(ShipModel(SHIP, TURNING), coefficient)
    rate, loss = steady_turn(model)
    gain, cubic = model.parameter("speed_loss.gain"), model.parameter("speed_loss.cubic")
    forcing = gain * rate**2 + coefficient * math.sin(HARD_OVER) ** 2 * (1.0 - loss)
    assert loss + cubic * loss**3 == pytest.approx(forcing, rel=1e-3)
    assert loss > steady_turn(with_drag(model, 0.0))[1]  # the drag adds to the turn's loss


def held_rudder_loss(model: ShipModel, rudder: float, propeller_rate: float, seconds: float = 30000.0) -> float:
    """u* after ``seconds`` with the rudder ordered to ``rudder`` from a straight start at the service speed."""
    simulator = Simulator(model, dt=1.0)
    simulator.reset(conditions=Conditions(propeller_rate=propeller_rate))
    for _ in range(int(seconds)):
        simulator.step(rudder)
    return float(simulator.state[0, S.SPEED_LOSS])


def test_a_held_rudder_without_a_turn_loses_the_drag_alone():
    """Yaw so weak that the ship barely turns (K* tiny): u* = C_R* s^2 (1 - u*), s = sin(delta), so
    u* = C_R* s^2 / (1 + C_R* s^2) with H_u = u*; the thesis's speed loss alone keeps the speed."""
    plain = ShipModel(SHIP, TURNING).with_parameters({"yaw.gain": 1e-6, "speed_loss.cubic": 0.0})
    coefficient, rudder = 3.0, math.radians(20.0)
    forcing = coefficient * math.sin(rudder) ** 2
    assert held_rudder_loss(with_drag(plain, coefficient), rudder, 0.0) == pytest.approx(
        forcing / (1.0 + forcing), rel=1e-3
    )
    assert held_rudder_loss(plain, rudder, 0.0) == pytest.approx(0.0, abs=1e-6)


def test_port_and_starboard_lose_alike():
    model = with_drag(ShipModel(SHIP, TURNING).with_parameters({"norrbin.odd_quadratic": 0.0}), 1.0)
    (rate_stbd, loss_stbd), (rate_port, loss_port) = (steady_turn(model, a) for a in (HARD_OVER, -HARD_OVER))
    assert loss_port == pytest.approx(loss_stbd, rel=1e-9) and rate_port == pytest.approx(rate_stbd, rel=1e-9)


def test_the_propellers_slipstream_keeps_the_drag_up():
    """u_R^2 = u^2 + c_s (n D)^2 > u^2: with the ship barely turning (K* tiny), the same C_R* slows it more with
    the slipstream on, and to the closed form's C_R* s^2 u_R^2 / (u U0) = u* (H_u = u*)."""
    values = {"yaw.gain": 1e-6, "speed_loss.cubic": 0.0, "propeller_slipstream.coefficient": 0.3}
    plain = with_drag(ShipModel(SHIP, TURNING).with_parameters(values), 3.0)
    slipstream = plain.with_effects("propeller_slipstream")
    rudder, rate = math.radians(20.0), 1.0
    losses = [held_rudder_loss(model, rudder, rate) for model in (plain, slipstream)]
    assert losses[1] > losses[0] * 1.05
    speed = slipstream.service_speed * (1.0 - losses[1])
    induced = rate * slipstream.parameter("propeller_slipstream.propeller_diameter")
    inflow = speed**2 + 0.3 * induced**2
    forcing = 3.0 * math.sin(rudder) ** 2 * inflow / (speed * slipstream.service_speed)
    assert losses[1] == pytest.approx(forcing, rel=1e-3)


def test_a_candidate_with_one_term_from_its_null_fitted_only_where_a_log_measures_the_speed():
    assert effect_terms("rudder_drag") == ("rudder_drag.drag_coefficient",)
    term = make_term("rudder_drag.drag_coefficient", ReplayModel(ShipModel(SHIP).with_effects("rudder_drag")))
    assert (term.null, term.lower, term.upper, term.material) == (0.0, 0.0, 20.0, 0.1)
    logs = sail_all(ReplayModel(ShipModel(SHIP, TURNING)), model_test_programme(ship=SHIP)[:1], seed=1)
    assert why_not_fitted("rudder_drag", ShipModel(SHIP), logs) is None
    speedless = [replace(log, speed=None) for log in logs]
    assert "measures the speed" in (why_not_fitted("rudder_drag", ShipModel(SHIP), speedless) or "")


def test_hidden_rudder_drag_is_recovered_by_a_fit_that_adds_it():
    """Logs sailed with the speed loss (K_u* 2, tau_u* 1) and C_R* = 1.5 on the 3 m model's test programme (zig-zags
    and hard-over turns) with a basin's sensors and the speed measured: the model with the term added recovers C_R*
    within 20 %."""
    key, truth_value = "rudder_drag.drag_coefficient", 1.5
    values = {"speed_loss.gain": 2.0, "speed_loss.time_constant": 1.0, key: truth_value}
    assert recovered("rudder_drag", values, key).value == pytest.approx(truth_value, rel=0.2)
