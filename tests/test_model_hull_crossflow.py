"""The hull's cross-flow drag in yaw (``effects/hull_crossflow.py``) against its closed forms.

The strip integral's closed form against numerical quadrature, its drift factor g(gamma), the
steady turn r* + c g r*|r*| = K* delta solved for r* against the simulator, port-starboard
symmetry, and the hidden-effect check: logs sailed with the term, the model fitted with it added,
its coefficient recovered.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from conftest import CONTAINER, run
from scipy.integrate import quad

from ship_env.model import REQUIRED_EFFECTS, ShipModel, load_ship
from ship_env.model import state as S
from ship_env.model.effects.hull_crossflow import crossflow_integral
from ship_env.model.ship import ship_from_document
from ship_env.workbench import FitOptions, ReplayModel
from ship_env.workbench.fitting.fit import fit
from ship_env.workbench.fitting.terms import effect_terms, make_term, why_not_fitted
from ship_env.workbench.synthetic.synthetic import HIDDEN_VALUES, SensorNoise, hidden_effect_logs, noise_scales

CROSSFLOW = ["yaw", "kinematics", "hull_crossflow"]
COEFFICIENT = 0.8


def strip_integral(drift: float, rate: float) -> float:
    """integral of xi |v* + xi r*| (v* + xi r*) over the hull, by quadrature split at the pivot point."""
    pivot = -drift / rate if rate else math.inf
    points = [pivot] if -0.5 < pivot < 0.5 else None
    value, _ = quad(lambda xi: xi * abs(drift + xi * rate) * (drift + xi * rate), -0.5, 0.5, points=points)
    return value


@pytest.mark.parametrize(
    ("drift", "rate"),
    [(0.0, 0.4), (0.0, -1.1), (-0.1, 0.4), (0.1, 0.4), (-0.3, 0.4), (0.25, -0.5), (0.05, 0.0), (-0.2, -0.9)],
)
def test_closed_form_is_the_strip_integral(drift, rate):
    """Both branches (pivot point on the hull or off it), both signs, no rate: quad to 1e-12."""
    assert crossflow_integral(drift, rate) == pytest.approx(strip_integral(drift, rate), rel=1e-10, abs=1e-15)


@pytest.mark.parametrize("gamma", [0.0, 0.1, 0.25, 0.4683, 0.5, 0.7])
def test_drift_factor_of_the_linear_sway(gamma):
    """v* = -gamma r*: 32 I = g(gamma) r*|r*| with g = 1 + 8 g^2 - 16 g^4 / 3 (|g| <= 1/2), 16 |g| / 3 beyond."""
    factor = 1.0 + 8.0 * gamma**2 - 16.0 * gamma**4 / 3.0 if gamma <= 0.5 else 16.0 * gamma / 3.0
    rate = 0.6
    assert 32.0 * strip_integral(-gamma * rate, rate) == pytest.approx(factor * rate * rate, rel=1e-10)


def steady_rate(model: ShipModel, rudder: float, drift_factor: float = 1.0) -> float:
    """r (rad/s) solving r* + c g r*|r*| = K* delta (2.26 with the cross-flow part of H)."""
    gain, curvature = model.parameter("yaw.gain"), model.parameter("hull_crossflow.coefficient") * drift_factor
    demand = gain * abs(rudder)
    normalised = (-1.0 + math.sqrt(1.0 + 4.0 * curvature * demand)) / (2.0 * curvature)
    return math.copysign(normalised, rudder) * model.service_speed / model.length


@pytest.mark.parametrize("rudder_deg", [5.0, 20.0, -35.0])
def test_steady_turn_is_the_quadratic_root(rudder_deg):
    """Without drift: r* + c r*|r*| = K* delta; the simulator's steady rate to 1e-6."""
    model = ShipModel(CONTAINER, CROSSFLOW, {"hull_crossflow.coefficient": COEFFICIENT})
    history = run(model, math.radians(rudder_deg), duration=1500.0, dt=1.0)
    expected = steady_rate(model, math.radians(rudder_deg))
    assert history[-1, S.RATE_OF_TURN] == pytest.approx(expected, rel=1e-6)
    linear = model.parameter("yaw.gain") * math.radians(rudder_deg) * model.service_speed / model.length
    assert abs(expected) < 0.95 * abs(linear)  # the term matters at these rudders


def test_steady_turn_with_drift_uses_the_pivot_point():
    """With the sway effect (gamma1* = 0.25 of the container ship): the drift factor g(0.25) = 1.479."""
    model = ShipModel(CONTAINER, [*CROSSFLOW, "sway"], {"hull_crossflow.coefficient": COEFFICIENT})
    gamma = model.parameter("sway.linear")
    factor = 1.0 + 8.0 * gamma**2 - 16.0 * gamma**4 / 3.0
    history = run(model, math.radians(25.0), duration=1500.0, dt=1.0)
    assert history[-1, S.RATE_OF_TURN] == pytest.approx(steady_rate(model, math.radians(25.0), factor), rel=1e-6)
    assert steady_rate(model, math.radians(25.0), factor) < 0.95 * steady_rate(model, math.radians(25.0))


def test_port_and_starboard_are_mirror_images():
    """delta -> -delta: rate, heading and the track across mirrored exactly, along the track unchanged."""
    model = ShipModel(CONTAINER, [*CROSSFLOW, "sway", "steering_machine"], {"hull_crossflow.coefficient": COEFFICIENT})
    starboard = run(model, math.radians(30.0), duration=600.0)
    port = run(model, math.radians(-30.0), duration=600.0)
    for column in (S.RATE_OF_TURN, S.HEADING, S.EAST, S.RUDDER):
        np.testing.assert_array_equal(port[:, column], -starboard[:, column])
    np.testing.assert_array_equal(port[:, S.NORTH], starboard[:, S.NORTH])


def test_quadratic_growth_extrapolates_more_gently_than_the_cubic():
    """Fitted to the same steady rate at a zig-zag's r* = 0.2, the cross-flow term predicts a hard-over
    turn's rate closer to linear than Norrbin's cubic: H grows as r*^2, not r*^3."""
    small, large = 0.2, 0.8
    # each term makes H(0.2) = 0.2 + 0.02: c 0.04 = 0.02, alpha3 0.008 = 0.02
    crossflow, cubic = 0.02 / small**2, 0.02 / small**3
    assert large + crossflow * large**2 < large + cubic * large**3
    crossflow_model = ShipModel(CONTAINER, CROSSFLOW, {"hull_crossflow.coefficient": crossflow})
    cubic_model = ShipModel(
        CONTAINER, ["yaw", "kinematics", "norrbin"], {"norrbin.cubic": cubic, "norrbin.odd_quadratic": 0.0}
    )
    rates = [
        run(m, math.radians(35.0), duration=1500.0, dt=1.0)[-1, S.RATE_OF_TURN] for m in (crossflow_model, cubic_model)
    ]
    demand = cubic_model.parameter("yaw.gain") * math.radians(35.0)
    cubic_root = next(root.real for root in np.roots([cubic, 0.0, 1.0, -demand]) if abs(root.imag) < 1e-12)
    to_rate = cubic_model.service_speed / cubic_model.length
    assert rates[0] == pytest.approx(steady_rate(crossflow_model, math.radians(35.0)), rel=1e-6)
    assert rates[1] == pytest.approx(cubic_root * to_rate, rel=1e-6)
    assert rates[0] > rates[1]


@pytest.mark.slow
def test_hidden_crossflow_is_recovered_by_a_fit_that_adds_it():
    """Logs sailed with sway and the cross-flow term (c = 0.5) on the 3 m model with a basin's sensors:
    the model with the term added recovers c within 15 %."""
    ship, truth_value = "esso_osaka_model", 0.5
    values = {**HIDDEN_VALUES, "hull_crossflow.coefficient": truth_value}
    truth, logs = hidden_effect_logs(["sway", "hull_crossflow"], ship, values=values)
    model = ShipModel(ship, [*REQUIRED_EFFECTS, "sway", "hull_crossflow"])
    result = fit(model, logs, options=FitOptions(scales=noise_scales(SensorNoise())))
    (estimate,) = [e for e in result.estimates if e.term.key == "hull_crossflow.coefficient"]
    print(f"\nhull_crossflow.coefficient: {estimate.value:.4f} +- {estimate.std_error:.4f} (truth {truth_value})")
    assert estimate.value == pytest.approx(truth_value, rel=0.15)


def test_the_ladder_can_propose_it_for_any_preset():
    """A candidate like the other effects: any preset can turn it on, one written before it existed too (its
    null is the declared default), one term fitted from 0 within [0, 100], material from 0.05."""
    document = load_ship("kvlcc2").document
    unaware = ship_from_document(  # a preset written before the effect existed
        {**document, "effects": {k: v for k, v in document["effects"].items() if k != "hull_crossflow"}}, "old"
    )
    for ship in ("kvlcc2", "container_226m", "esso_osaka_model", unaware):
        model = ShipModel(ship, REQUIRED_EFFECTS)
        assert why_not_fitted("hull_crossflow", model, []) is None
        assert model.with_effects("hull_crossflow").parameter("hull_crossflow.coefficient") == 0.0
    assert effect_terms("hull_crossflow") == ("hull_crossflow.coefficient",)
    term = make_term("hull_crossflow.coefficient", ReplayModel(ShipModel("kvlcc2").with_effects("hull_crossflow")))
    assert (term.null, term.lower, term.upper, term.material) == (0.0, 0.0, 100.0, 0.05)
