"""The adaptive track predictor (thesis ch. 3, 5.6, 6.3.4)."""

from __future__ import annotations

import math

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
import pytest

from ship_env.baselines.adaptive_autopilot import IndirectAdaptiveAutopilot
from ship_env.baselines.instruments import SimulatedInstruments
from ship_env.baselines.measurement import Measurement
from ship_env.baselines.nomoto import NomotoParameters
from ship_env.baselines.online_estimators.zigzag_trial import identify_by_zigzag
from ship_env.baselines.pd_autopilot import PDAutopilot, PDDesign
from ship_env.baselines.position_filter import PositionFilter
from ship_env.baselines.track_plot import plot_track_prediction
from ship_env.baselines.track_predictor import PredictedTrack, ShipSituation, TrackPredictor
from ship_env.baselines.track_scaling import TrackScalingEstimator
from ship_env.baselines.yaw_filter import YawFilter
from ship_env.model import Conditions, ShipModel, Simulator

KNOT = 1852.0 / 3600.0
SHIP = NomotoParameters(gain=1.6, time_constant=1.7)
LENGTH = 225.87
RUDDER_RATE = math.radians(2.5)
DESIGN = PDDesign(0.05, 1.0, math.radians(20.0), 9.5, "distance")  # scheduled as the predictor assumes (3.52)


def polyline_distance(points: np.ndarray, line: np.ndarray) -> np.ndarray:
    """Distance of each point to the nearest point of a polyline, m."""
    start, end = line[:-1], line[1:]
    segment = end - start
    squared = np.maximum(np.sum(segment**2, axis=1), 1e-12)
    along = np.clip(np.einsum("ijk,jk->ij", points[:, None, :] - start[None], segment) / squared, 0.0, 1.0)
    nearest = start[None] + along[..., None] * segment[None]
    return np.min(np.linalg.norm(points[:, None, :] - nearest, axis=2), axis=1)


def test_prediction_is_exact_for_a_nomoto_ship_with_the_same_autopilot():
    """The model of Fig. 3.14 against the simulator's linear Nomoto ship with Van Leeuwen sway (gamma = gamma1* L)."""
    model = ShipModel("container_226m", ("yaw", "sway", "kinematics", "steering_machine"))
    simulator = Simulator(model, dt=1.0)
    simulator.reset(seed=0)
    autopilot = PDAutopilot(DESIGN, SHIP, LENGTH)
    predictor = TrackPredictor(SHIP, LENGTH, DESIGN, model.parameter("sway.linear") * LENGTH, RUDDER_RATE)
    start = ShipSituation(0.0, 0.0, 0.0, 0.0, 0.0, model.service_speed)
    prediction = predictor.predict(start, math.radians(120.0), DESIGN.rudder_limit, 400.0)
    positions = [simulator.position[0].copy()]
    for _ in range(400):
        reading = Measurement(simulator.heading[0], simulator.rate_of_turn[0], simulator.rudder[0], simulator.speed[0])
        simulator.step(autopilot.order(math.radians(120.0), reading))
        positions.append(simulator.position[0].copy())
    deviation = np.max(np.linalg.norm(np.asarray(positions) - prediction.positions, axis=1))
    print(f"largest distance between the predicted and the simulated position: {deviation:.2f} m")
    assert deviation < 2.0


def test_track_is_the_same_at_any_predicted_speed_with_scheduled_gains():
    """(3.55, 3.56): with K_d = K_d* L/U the closed loop, and so the track, does not depend on U_p."""
    fast_rudder = math.radians(1000.0)  # the steering machine's rate is a time, not a distance: leave it out
    full = TrackPredictor(SHIP, LENGTH, DESIGN, 50.0, fast_rudder, sample_time=1.0)
    half = TrackPredictor(SHIP, LENGTH, DESIGN, 50.0, fast_rudder, sample_time=2.0)
    at_full = full.predict(ShipSituation(0.0, 0.0, 0.0, 0.0, 0.0, 9.5), math.radians(90.0), DESIGN.rudder_limit, 300.0)
    at_half = half.predict(ShipSituation(0.0, 0.0, 0.0, 0.0, 0.0, 4.75), math.radians(90.0), DESIGN.rudder_limit, 600.0)
    np.testing.assert_allclose(at_half.positions, at_full.positions, atol=1e-6)
    np.testing.assert_allclose(at_half.heading, at_full.heading, atol=1e-9)


def circle_track(radius: float = 1000.0, speed: float = 10.0, duration: float = 300.0) -> PredictedTrack:
    """A steady starboard turn from the origin on 000."""
    time = np.arange(0.0, duration + 1.0)
    heading = speed / radius * time
    return PredictedTrack(
        time,
        radius * np.sin(heading),
        radius * (1.0 - np.cos(heading)),
        heading,
        np.full_like(time, speed / radius),
        np.zeros_like(time),
        speed,
        LENGTH,
    )


def test_adaptation_scales_about_the_start_adds_the_current_and_translates_by_heading():
    track = circle_track()
    adapted = track.adapted(2.0, (1.0, -0.5))
    # A turn twice as fast in the distance domain is the same turn at half the radius (5.102, 5.103);
    # the current sets it by u_c i T_s (6.3.4).
    np.testing.assert_allclose(adapted.north - track.time * 1.0, 500.0 * np.sin(track.heading), atol=1e-9)
    np.testing.assert_allclose(adapted.east + track.time * 0.5, 500.0 * (1.0 - np.cos(track.heading)), atol=1e-9)
    moved = track.translated(math.radians(45.0), 100.0, 200.0)
    assert (moved.north[0], moved.east[0]) == (100.0, 200.0)
    assert moved.heading[0] == pytest.approx(math.radians(45.0), abs=track.rate_of_turn[0])
    assert track.normalised_rate_at(math.radians(30.0)) == pytest.approx(LENGTH / 1000.0)


def test_track_scaling_factor_comes_from_the_filtered_rate():
    track = circle_track()
    estimator = TrackScalingEstimator()
    for heading in np.linspace(0.0, 2.5, 200):
        estimator.update(0.9 * track.rate_of_turn[0], heading, track.speed, track)
    assert estimator.value == pytest.approx(0.9, abs=0.01)


def sail_predicted_course_change(seed: int, identify: bool, change_deg: float = 120.0) -> dict:
    """3.5 / 6.3.4: a 120-deg change under wind and current, the prediction made at wheel-over.

    The full container ship with HF waves, current 3 kn towards 315, wind 7 m/s from 045; the
    ship's K*, tau* identified by a 15/15 zig-zag first (6.4.4.1) or taken from the preset
    (``identify=False``: the linear values, which the Norrbin term makes about 5% too fast at
    20 deg); gamma from the zig-zag; 10 min on 000 for the position filter, then the wheel goes
    over with the rudder limited to 20 deg. The autopilot: the PD on the yaw filter's signals with
    the same K*, tau* (no compensation, as in 6.3.4).
    """
    model = ShipModel("container_226m").with_effects("wave_filter")
    trial = identify_by_zigzag(model, SHIP)
    parameters = trial.parameters if identify else SHIP
    sample_time = 0.5
    simulator = Simulator(model, dt=sample_time)
    simulator.reset(
        seed=seed,
        conditions=Conditions(
            current_speed=3.0 * KNOT,
            current_direction=math.radians(315.0),
            wind_speed=7.0,
            wind_direction=math.radians(45.0),
        ),
    )
    instruments = SimulatedInstruments(simulator, seed=seed)
    yaw_filter = YawFilter(model.length, sample_time, parameters)
    yaw_filter.adapting = False
    autopilot = IndirectAdaptiveAutopilot(DESIGN, yaw_filter)
    position_filter = PositionFilter(sample_time, sway_constant=trial.sway_constant)
    scaling = TrackScalingEstimator()
    reading = instruments.read()
    autopilot.reset(reading)
    position_filter.reset(reading, yaw_filter.rate_of_turn, yaw_filter.heading)
    setpoint, prediction, sailed, first = 0.0, None, [], True
    while simulator.time[0] < 1200.0:
        if prediction is None and simulator.time[0] >= 600.0:
            start = ShipSituation(
                *position_filter.position,
                yaw_filter.heading,
                yaw_filter.rate_of_turn,
                reading.rudder,
                position_filter.speed,
            )
            predictor = TrackPredictor(parameters, LENGTH, DESIGN, position_filter.sway_constant, RUDDER_RATE)
            setpoint = math.radians(change_deg)
            prediction = predictor.predict(start, setpoint, DESIGN.rudder_limit, 600.0)
            current = position_filter.current
        simulator.step(autopilot.order(setpoint, reading))
        reading = instruments.read()
        if not first:
            position_filter.step(reading, yaw_filter.rate_of_turn, yaw_filter.heading)
        first = False
        if prediction is not None:
            scaling.update(yaw_filter.rate_of_turn, yaw_filter.heading, position_filter.speed, prediction)
            sailed.append((*simulator.position[0], simulator.heading[0]))
    sailed = np.asarray(sailed)
    settled = np.flatnonzero(np.abs(sailed[:, 2] - setpoint) > math.radians(1.0))[-1] + 1
    manoeuvre = sailed[: settled + int(60.0 / sample_time), :2]  # wheel-over to a minute after the heading settled
    return {
        "manoeuvre": manoeuvre,
        "unadapted": prediction,
        "current_only": prediction.adapted(1.0, current),
        "adapted": prediction.adapted(scaling.value, current),
        "scaling": scaling.value,
        "current_error": math.dist(
            current, (3.0 * KNOT * math.cos(math.radians(315.0)), 3.0 * KNOT * math.sin(math.radians(315.0)))
        ),
    }


@pytest.mark.parametrize("identify", [True, False], ids=["identified", "preset"])
@pytest.mark.parametrize("seed", [0, pytest.param(1, marks=pytest.mark.slow)])
def test_adapted_prediction_made_at_wheel_over_follows_the_sailed_track(seed, identify):
    result = sail_predicted_course_change(seed, identify)
    errors = {
        name: float(np.sqrt(np.mean(polyline_distance(result["manoeuvre"], result[name].positions) ** 2)))
        for name in ("unadapted", "current_only", "adapted")
    }
    assert errors["adapted"] < 0.1 * LENGTH
    assert errors["adapted"] < errors["unadapted"]
    print(
        f"seed {seed}, {'identified' if identify else 'preset'} K*, tau*: RMS distance over the manoeuvre: "
        f"adapted {errors['adapted']:.1f} m ({errors['adapted'] / LENGTH:.3f} L), "
        f"current only {errors['current_only']:.1f} m, unadapted {errors['unadapted']:.1f} m; "
        f"K_rho {result['scaling']:.3f}, current error {result['current_error'] / KNOT:.2f} kn"
    )
    figure, axes = plt.subplots()
    plot_track_prediction(
        axes, result["manoeuvre"], {"x_0 initial": result["unadapted"], "x_p adapted": result["adapted"]}
    )
    assert len(axes.get_lines()) == 3 and axes.get_legend() is not None
    plt.close(figure)
