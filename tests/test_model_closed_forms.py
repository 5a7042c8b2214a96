"""The model against closed forms and the thesis's own numbers (ch. 2, 6.4.4)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from conftest import CONTAINER, SPEED, run

from ship_env.model import Conditions, ShipModel, Simulator
from ship_env.model import state as S

NOMOTO = ["yaw", "kinematics"]  # minimal yaw without the steering machine: tau dr/dt + r = K delta


def test_thesis_nominal_rate_of_turn_at_10_degrees():
    """6.4.4.2: r = K* (U/L) delta_max = 1.6 * 9.5/226 * 10 deg * 60 ~ 40 deg/min."""
    model = ShipModel(CONTAINER, ["yaw", "kinematics", "steering_machine"])
    history = run(model, math.radians(10.0), duration=900.0, conditions=Conditions(service_speed=9.5))
    rate_deg_per_min = math.degrees(history[-1, S.RATE_OF_TURN]) * 60.0
    assert rate_deg_per_min == pytest.approx(40.0, rel=0.02)


@pytest.mark.parametrize("rudder_deg", [-20.0, 5.0, 15.0])
@pytest.mark.parametrize("speed", [4.0, 9.5])
def test_linear_steady_turn_is_k_delta(rudder_deg, speed):
    """(2.58, 2.61): steady r = K delta with K = K* u / L."""
    model = ShipModel(CONTAINER, NOMOTO)
    history = run(model, math.radians(rudder_deg), duration=2000.0, dt=1.0, conditions=Conditions(service_speed=speed))
    gain = model.parameter("yaw.gain") * speed / model.length
    assert history[-1, S.RATE_OF_TURN] == pytest.approx(gain * math.radians(rudder_deg), rel=1e-6)


def test_nomoto_step_response_matches_closed_form():
    """tau dr/dt + r = K delta from rest: r(t) = K delta (1 - exp(-t / tau)), tau = tau* L / u (2.61)."""
    model = ShipModel(CONTAINER, NOMOTO)
    speed, rudder = 9.5, math.radians(10.0)
    history = run(model, rudder, duration=200.0, dt=0.5, conditions=Conditions(service_speed=speed))
    time = history[:, S.TIME]
    gain = model.parameter("yaw.gain") * speed / model.length
    time_constant = model.parameter("yaw.time_constant") * model.length / speed
    expected = gain * rudder * (1.0 - np.exp(-time / time_constant))
    np.testing.assert_allclose(history[:, S.RATE_OF_TURN], expected, rtol=0, atol=1e-9)


def test_rk4_converges_at_fourth_order_and_euler_at_first():
    model = ShipModel(CONTAINER)  # non-linear: Norrbin, speed loss, sway

    def final_heading(dt: float, method: str) -> float:
        return run(model, math.radians(20.0), duration=120.0, dt=dt, method=method)[-1, S.HEADING]

    reference = final_heading(0.05, "rk4")
    rk4_ratio = (final_heading(2.0, "rk4") - reference) / (final_heading(1.0, "rk4") - reference)
    euler_ratio = (final_heading(1.0, "euler") - reference) / (final_heading(0.5, "euler") - reference)
    assert rk4_ratio == pytest.approx(16.0, rel=0.25)
    assert euler_ratio == pytest.approx(2.0, rel=0.1)


def test_turning_radius_is_u_over_r():
    """(2.69): the steady track is a circle of radius R = U / r (U the speed over the ground)."""
    model = ShipModel(CONTAINER)
    history = run(model, math.radians(35.0), duration=1500.0, dt=0.5)
    steady = history[-400:]
    north, east = steady[:, S.NORTH], steady[:, S.EAST]
    # Algebraic circle fit (Kasa): x^2 + y^2 = 2 a x + 2 b y + c.
    design = np.column_stack([2 * north, 2 * east, np.ones_like(north)])
    a, b, c = np.linalg.lstsq(design, north**2 + east**2, rcond=None)[0]
    radius = math.sqrt(c + a * a + b * b)
    speed = steady[-1, SPEED]
    normalised_rate = model.length * steady[-1, S.RATE_OF_TURN] / speed
    sway = -speed * model.parameter("sway.linear") * normalised_rate
    ground_speed = math.hypot(speed, sway)
    assert radius == pytest.approx(ground_speed / steady[-1, S.RATE_OF_TURN], rel=1e-3)


def test_norrbin_steady_turn_solves_h_of_r_equals_k_delta():
    """(2.26, 2.27): steady r* solves r* + alpha3 r*^3 = K* delta."""
    model = ShipModel(CONTAINER, ["yaw", "kinematics", "norrbin"])
    rudder = math.radians(30.0)
    history = run(model, rudder, duration=1500.0, dt=1.0)
    normalised_rate = model.length * history[-1, S.RATE_OF_TURN] / history[-1, SPEED]
    cubic = model.parameter("norrbin.cubic")
    assert normalised_rate + cubic * normalised_rate**3 == pytest.approx(model.parameter("yaw.gain") * rudder, rel=1e-6)
    linear_rate = model.parameter("yaw.gain") * rudder
    assert normalised_rate < 0.8 * linear_rate  # the cubic term does bend the spiral


def test_speed_loss_steady_value_and_rate_of_turn_overshoot():
    """(2.55): steady u* = K_u* r*^2 (beta3 = 0); the falling speed makes r overshoot (Fig. 2.7)."""
    with_loss = ShipModel(CONTAINER, ["yaw", "kinematics", "steering_machine", "speed_loss"])
    history = run(with_loss, math.radians(20.0), duration=1500.0, dt=0.5)
    rate, speed = history[:, S.RATE_OF_TURN], history[:, SPEED]
    normalised_rate = with_loss.length * rate[-1] / speed[-1]
    assert history[-1, S.SPEED_LOSS] == pytest.approx(
        with_loss.parameter("speed_loss.gain") * normalised_rate**2, rel=1e-5
    )
    assert rate.max() > 1.05 * rate[-1]  # overshoot of Fig. 2.7
    assert speed[-1] < 0.9 * speed[0]

    without_loss = with_loss.without_effects("speed_loss")
    rate = run(without_loss, math.radians(20.0), duration=1500.0, dt=0.5)[:, S.RATE_OF_TURN]
    assert rate.max() <= rate[-1] * (1 + 1e-9)  # monotonic rise: no overshoot


def test_van_leeuwen_sway_gives_drift_angle_inside_the_turn():
    """(2.52): v = -u (gamma1* r* + gamma3* r*^3); turning to starboard the ship drifts to port."""
    model = ShipModel(CONTAINER, ["yaw", "kinematics", "sway"])
    history = run(model, math.radians(20.0), duration=1200.0, dt=0.25)
    heading = history[-2, S.HEADING]
    # Central difference: the course at the middle sample.
    velocity = (history[-1, S.NORTH] - history[-3, S.NORTH], history[-1, S.EAST] - history[-3, S.EAST])
    course = math.atan2(velocity[1], velocity[0])
    drift_angle = math.atan2(math.sin(heading - course), math.cos(heading - course))
    normalised_rate = model.length * history[-2, S.RATE_OF_TURN] / history[-2, SPEED]
    expected = math.atan(model.parameter("sway.linear") * normalised_rate)  # bow inside: heading ahead of course
    assert drift_angle == pytest.approx(expected, rel=1e-3)


def test_steering_machine_takes_angle_over_rate_seconds_and_clips_the_order():
    model = ShipModel(CONTAINER, ["yaw", "kinematics", "steering_machine"])
    rate = model.parameter("steering_machine.rudder_rate")
    history = run(model, math.radians(50.0), duration=30.0, dt=0.5)  # ordered beyond the 35-deg limit
    rudder = history[:, S.RUDDER]
    limit = model.rudder_limit
    assert rudder.max() == pytest.approx(limit, abs=1e-12)
    reached = history[np.argmax(rudder >= limit - 1e-12), S.TIME]
    assert reached == pytest.approx(limit / rate, abs=0.5)  # 35 / 2.5 = 14 s, to within one step
    np.testing.assert_allclose(np.diff(rudder[: int(14.0 / 0.5)]), rate * 0.5, rtol=1e-12)


def test_rudder_offset_turns_the_ship_at_zero_rudder():
    model = ShipModel(CONTAINER, NOMOTO + ["rudder_offset"], {"rudder_offset.angle": math.radians(3.0)})
    history = run(model, 0.0, duration=2000.0, dt=1.0)
    expected = model.parameter("yaw.gain") * model.service_speed / model.length * math.radians(3.0)
    assert history[-1, S.RATE_OF_TURN] == pytest.approx(expected, rel=1e-6)


def test_propeller_slipstream_scales_rudder_effect_and_turns_a_ship_at_rest():
    """u_R^2 = u^2 + c_s (n D)^2 in the rudder term: steady r = K* u_R^2 delta / (L u) (linear H)."""
    base = ShipModel(CONTAINER, NOMOTO + ["propeller_slipstream"], {"propeller_slipstream.coefficient": 0.2})
    speed, propeller_rate, rudder = 5.0, 1.5, math.radians(10.0)
    conditions = Conditions(service_speed=speed, propeller_rate=propeller_rate)
    history = run(base, rudder, duration=3000.0, dt=1.0, conditions=conditions)
    diameter = base.parameter("propeller_slipstream.propeller_diameter")
    inflow_squared = speed**2 + 0.2 * (propeller_rate * diameter) ** 2
    expected = base.parameter("yaw.gain") * inflow_squared * rudder / (base.length * speed)
    assert history[-1, S.RATE_OF_TURN] == pytest.approx(expected, rel=1e-6)

    at_rest = run(base, rudder, duration=60.0, dt=1.0, conditions=Conditions(service_speed=0.0, propeller_rate=1.5))
    assert at_rest[-1, S.RATE_OF_TURN] > 0.0
    no_propeller = run(base, rudder, duration=60.0, dt=1.0, conditions=Conditions(service_speed=0.0))
    assert no_propeller[-1, S.RATE_OF_TURN] == 0.0


def test_course_unstable_ship_turns_away_at_zero_rudder():
    """(2.27): alpha1 < 0, alpha3 > 0 gives the unstable spiral; steady r* solves alpha1 r* + alpha3 r*^3 = 0."""
    model = ShipModel(CONTAINER, ["yaw", "kinematics", "norrbin"], {"yaw.linear": -0.5, "norrbin.cubic": 1.0})
    history = run(model, 0.0, duration=3000.0, dt=1.0)
    assert np.all(history[:, S.RATE_OF_TURN] == 0.0)  # balanced on the unstable equilibrium
    sim = Simulator(model, dt=1.0)
    sim.reset(seed=0, rate_of_turn=-1e-5)
    for _ in range(3000):
        sim.step(0.0)
    normalised_rate = model.length * sim.rate_of_turn[0] / sim.speed[0]
    assert normalised_rate == pytest.approx(-math.sqrt(0.5), rel=1e-6)
