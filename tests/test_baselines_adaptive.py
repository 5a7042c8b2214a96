"""The adaptive autopilots (thesis 5.5): MRAC from a reference model at K*/4, tau*/4; the indirect adaptive PD."""

from __future__ import annotations

import math

import gymnasium as gym
import numpy as np
import pytest

import ship_env  # noqa: F401  (registers the environments)
from ship_env.baselines.instruments import SimulatedInstruments
from ship_env.baselines.mrac import ModelReferenceAutopilot
from ship_env.baselines.nomoto import NomotoParameters
from ship_env.baselines.pd_autopilot import PDDesign
from ship_env.baselines.presys import indirect_adaptive_controller, pd_controller
from ship_env.baselines.yaw_filter import YawFilter
from ship_env.leaderboard.sailing import sail
from ship_env.leaderboard.suites import Episode
from ship_env.model import Conditions, ShipModel, Simulator

SHIP = NomotoParameters(gain=1.6, time_constant=1.7)
NOMOTO_WITH_WAVES = ("yaw", "kinematics", "steering_machine", "wave_filter")
SAMPLE_TIME = 0.5
#: Course changes of 40 deg, to and fro, 5 min each.
SETPOINTS_DEG = (40.0, 0.0, 40.0, 0.0, 40.0, 0.0, 40.0, 0.0)
CHANGE_DURATION = 300.0


def sail_course_changes(
    autopilot: ModelReferenceAutopilot, model: ShipModel, seed: int = 0, conditions: Conditions | None = None
) -> dict:
    """The setpoint series; per sample the change's index, r, r_R and the compensation."""
    simulator = Simulator(model, dt=SAMPLE_TIME)
    simulator.reset(seed=seed, conditions=conditions)
    instruments = SimulatedInstruments(simulator, seed=seed)
    autopilot.reset(instruments.read())
    log = {name: [] for name in ("change", "rate", "reference_rate", "compensation")}
    for change, setpoint in enumerate(SETPOINTS_DEG):
        for _ in range(int(round(CHANGE_DURATION / SAMPLE_TIME))):
            order = autopilot.order(math.radians(setpoint), instruments.read())
            log["change"].append(change)
            log["rate"].append(simulator.rate_of_turn[0])
            log["reference_rate"].append(autopilot.reference_rate)
            log["compensation"].append(autopilot.compensation)
            simulator.step(order)
    return {name: np.asarray(values) for name, values in log.items()}


def mrac(model: ShipModel, reference_gain: float) -> ModelReferenceAutopilot:
    """MRAC with filter and reference model started at K*/4, tau*/4 (Figs. 6.4, 6.5)."""
    yaw_filter = YawFilter(model.length, SAMPLE_TIME, SHIP.scaled(0.25))
    design = PDDesign(0.05, 1.0, math.radians(20.0), model.service_speed)
    return ModelReferenceAutopilot(design, yaw_filter, SHIP.scaled(0.25), reference_gain)


def rms(values: np.ndarray) -> float:
    return float(np.sqrt(np.mean(values**2)))


def test_mrac_compensation_fades_as_the_reference_model_learns_the_ship():
    model = ShipModel("container_226m", NOMOTO_WITH_WAVES)
    autopilot = mrac(model, reference_gain=0.002)
    log = sail_course_changes(autopilot, model)
    compensation = [rms(log["compensation"][log["change"] == change]) for change in range(len(SETPOINTS_DEG))]
    assert compensation[-1] <= 0.2 * compensation[0]
    late = log["change"] >= len(SETPOINTS_DEG) // 2
    tracking = rms(log["rate"][late] - log["reference_rate"][late]) / rms(log["rate"][late])
    assert tracking < 0.1
    assert abs(autopilot.reference.gain / SHIP.gain - 1.0) < 0.1
    assert abs(autopilot.reference.time_constant / SHIP.time_constant - 1.0) < 0.1
    print(
        "RMS compensation per change (deg):",
        " ".join(f"{math.degrees(value):.2f}" for value in compensation),
        f"| RMS(r - r_R) / RMS(r) over the last four: {tracking:.3f} | reference K* {autopilot.reference.gain:.3f}, "
        f"tau* {autopilot.reference.time_constant:.3f}",
    )


@pytest.mark.slow
def test_mrac_on_the_full_model_in_wind_keeps_only_the_wind_and_non_linear_share():
    """Fig. 6.5's setting: the full preset (Norrbin term, speed loss, sway, wind) in 7 m/s from NW.
    The compensation keeps what no Nomoto reference can hold: the wind's offset and the Norrbin term."""
    model = ShipModel("container_226m").with_effects("wave_filter")
    autopilot = mrac(model, reference_gain=0.002)
    log = sail_course_changes(
        autopilot, model, conditions=Conditions(wind_speed=7.0, wind_direction=math.radians(315.0))
    )
    compensation = [rms(log["compensation"][log["change"] == change]) for change in range(len(SETPOINTS_DEG))]
    late = log["change"] >= len(SETPOINTS_DEG) // 2
    tracking = rms(log["rate"][late] - log["reference_rate"][late]) / rms(log["rate"][late])
    print(
        "full model in wind, RMS compensation per change (deg):",
        " ".join(f"{math.degrees(value):.2f}" for value in compensation),
        f"| RMS(r - r_R) / RMS(r) over the last four: {tracking:.3f} | reference K* {autopilot.reference.gain:.3f}, "
        f"tau* {autopilot.reference.time_constant:.3f}",
    )
    assert compensation[-1] <= 0.25 * compensation[0]
    assert tracking < 0.1


def test_a_held_reference_model_keeps_compensating():
    """K_R = 0 (5.92): the reference stays at K*/4, tau*/4; the ship is made to follow it throughout."""
    model = ShipModel("container_226m", NOMOTO_WITH_WAVES)
    autopilot = mrac(model, reference_gain=0.0)
    log = sail_course_changes(autopilot, model)
    assert autopilot.reference == SHIP.scaled(0.25)
    late = log["change"] >= len(SETPOINTS_DEG) // 2
    assert rms(log["compensation"][late]) > math.radians(2.0)
    assert rms(log["rate"][late] - log["reference_rate"][late]) < 0.1 * rms(log["rate"][late])


def course_change_metrics(builder, seed: int) -> dict:
    env = gym.make("ship_env/CourseChange-v0", disturbance="wind_current_waves")
    controller = builder(env.unwrapped.task)
    return sail(env, controller, Episode(seed, {"course_change_deg": 45.0}, "+45 deg"))[0]


@pytest.mark.parametrize("seed", [0, 1])
def test_filtered_adaptive_autopilot_works_the_rudder_less_in_waves(seed):
    """5.5.1: on the yaw filter's signals the rudder no longer answers the waves."""
    plain = course_change_metrics(pd_controller, seed)
    adaptive = course_change_metrics(indirect_adaptive_controller, seed)
    assert adaptive["rudder_travel"] < 0.3 * plain["rudder_travel"]
    assert adaptive["overshoot"] < 2.0
    assert adaptive["integrated_heading_error"] < 1.1 * plain["integrated_heading_error"]
    print(
        f"seed {seed}: rudder travel PD {plain['rudder_travel']:.0f} deg, "
        f"indirect adaptive {adaptive['rudder_travel']:.0f} deg"
    )
