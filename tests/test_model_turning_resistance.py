"""The turning resistance at the speed through the water (``effects/turning_resistance.py``) against its closed forms.

Its null (q = 0) is the thesis's speed loss (2.55) bit for bit; the steady turn's surge balance
u* + beta3 u*^3 = K_u* r*^2 (1 - u*)^q holds in a simulated turning circle; with H_u = u* and q = 1 the steady loss
is K_u* r*^2 / (1 + K_u* r*^2), below the speed, where the thesis's stops the ship; port and starboard lose alike;
and the hidden-effect check: logs sailed with the term, the model fitted with it added, q recovered.
"""

from __future__ import annotations

import math

import pytest
from speed_loss_checks import assert_same_hard_over_turn, recovered, steady_turn

from ship_env.manoeuvres import turning_circle
from ship_env.model import ShipModel
from ship_env.workbench.fitting.replay import ReplayModel
from ship_env.workbench.fitting.terms import effect_terms, make_term

SHIP = "kvlcc2"
TURNING = ("yaw", "norrbin", "speed_loss", "steering_machine", "kinematics")


def with_exponent(model: ShipModel, exponent: float, **values: float) -> ShipModel:
    return model.with_effects("turning_resistance").with_parameters(
        {"turning_resistance.speed_exponent": exponent, **values}
    )


def test_its_null_is_the_thesis_speed_loss_bit_for_bit():
    thesis = ShipModel(SHIP, TURNING)
    assert_same_hard_over_turn(thesis, with_exponent(thesis, 0.0))


@pytest.mark.parametrize("exponent", [1.0, 2.0])
def test_the_steady_turn_holds_the_surge_balance(exponent):
    """u* + beta3 u*^3 = K_u* r*^2 (1 - u*)^q (2.55, 2.39 with the forcing of this effect) in the steady turn."""
    model = with_exponent(ShipModel(SHIP, TURNING), exponent)
    rate, loss = steady_turn(model)
    gain, cubic = model.parameter("speed_loss.gain"), model.parameter("speed_loss.cubic")
    assert loss + cubic * loss**3 == pytest.approx(gain * rate**2 * (1.0 - loss) ** exponent, rel=1e-3)
    assert loss < steady_turn(with_exponent(model, 0.0))[1]  # the forcing falls as the ship slows


def test_a_linear_restoring_with_q_1_saturates_below_the_speed_where_the_thesis_stops_the_ship():
    """H_u = u* (beta3 = 0) and K_u* = 10: the thesis's steady loss K_u* r*^2 passes 1 in a hard-over turn (the ship
    cannot sail it); with q = 1 it is K_u* r*^2 / (1 + K_u* r*^2)."""
    values = {"speed_loss.cubic": 0.0, "speed_loss.gain": 10.0}
    thesis = ShipModel(SHIP, TURNING).with_parameters(values)
    with pytest.raises(FloatingPointError, match="speed_loss u"):
        turning_circle(thesis)
    rate, loss = steady_turn(with_exponent(thesis, 1.0))
    forcing = 10.0 * rate**2
    # at 83 % loss the surge settles over many ship lengths: the last circle's means are steady to a few 0.1 %
    assert forcing > 1.0 and loss == pytest.approx(forcing / (1.0 + forcing), rel=1e-2)


def test_port_and_starboard_lose_alike():
    model = with_exponent(ShipModel(SHIP, TURNING).with_parameters({"norrbin.odd_quadratic": 0.0}), 1.5)
    (rate_stbd, loss_stbd), (rate_port, loss_port) = (
        steady_turn(model, a) for a in (math.radians(35.0), -math.radians(35.0))
    )
    assert loss_port == pytest.approx(loss_stbd, rel=1e-9) and rate_port == pytest.approx(rate_stbd, rel=1e-9)


def test_a_candidate_with_one_term_from_its_null():
    assert effect_terms("turning_resistance") == ("turning_resistance.speed_exponent",)
    term = make_term(
        "turning_resistance.speed_exponent", ReplayModel(ShipModel(SHIP).with_effects("turning_resistance"))
    )
    assert (term.null, term.lower, term.upper, term.material) == (0.0, 0.0, 4.0, 0.1)


def test_hidden_turning_resistance_is_recovered_by_a_fit_that_adds_it():
    """Logs sailed with the speed loss (K_u* 2, tau_u* 1) and q = 1.5 on the 3 m model's test programme (its
    hard-over turns included) with a basin's sensors and the speed measured: the model with the term added
    recovers q within 20 %."""
    key, truth_value = "turning_resistance.speed_exponent", 1.5
    values = {"speed_loss.gain": 2.0, "speed_loss.time_constant": 1.0, key: truth_value}
    assert recovered("turning_resistance", values, key).value == pytest.approx(truth_value, rel=0.2)
