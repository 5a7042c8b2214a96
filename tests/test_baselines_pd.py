"""The PD course-changing autopilot (3.45, 3.52, 5.79, 5.80) and the one controller interface."""

from __future__ import annotations

import math

import gymnasium as gym
import numpy as np
import pytest

import ship_env  # noqa: F401  (registers the environments)
from baselines.controller import Controller, SB3Controller
from baselines.nomoto import NomotoParameters
from baselines.pd_autopilot import PDDesign, pd_gains
from baselines.presys import indirect_adaptive_controller, mrac_controller, pd_controller
from ship_env.model import Conditions

SHIP = NomotoParameters(gain=1.6, time_constant=1.7)
LENGTH = 225.87
DESIGN_SPEED = 9.5


@pytest.mark.parametrize("speed", [4.75, 9.5, 12.0])
def test_gains_place_the_closed_loop_at_the_design_frequency_and_damping(speed):
    natural_frequency, damping = 0.05, 0.8
    gains = pd_gains(natural_frequency, damping, SHIP, LENGTH, speed)
    gain = SHIP.gain * speed / LENGTH  # K (2.61)
    time_constant = SHIP.time_constant * LENGTH / speed  # tau
    # tau psi'' + (1 + K K_d) psi' + K K_p psi = K K_p psi_r
    assert math.sqrt(gain * gains.proportional / time_constant) == pytest.approx(natural_frequency)
    assert (1.0 + gain * gains.derivative) / time_constant == pytest.approx(2.0 * damping * natural_frequency)


def test_scheduled_gains_are_those_of_3_52_and_fixed_gains_do_not_move():
    scheduled = PDDesign(0.05, 0.8, math.radians(20.0), DESIGN_SPEED)
    fixed = PDDesign(0.05, 0.8, math.radians(20.0), DESIGN_SPEED, scheduled=False)
    at_design = scheduled.gains(SHIP, LENGTH, DESIGN_SPEED)
    at_half = scheduled.gains(SHIP, LENGTH, DESIGN_SPEED / 2.0)
    assert at_half.proportional == pytest.approx(at_design.proportional)  # K_p fixed
    assert at_half.derivative == pytest.approx(2.0 * at_design.derivative)  # K_d = K_d* L/u
    assert fixed.gains(SHIP, LENGTH, DESIGN_SPEED / 2.0) == at_design


def course_change(builder, speed: float, change_deg: float, **builder_options) -> dict:
    env = gym.make("ship_env/CourseChange-v0", max_episode_steps=900)
    controller = builder(env.unwrapped.task, **builder_options)
    observation, info = env.reset(
        seed=0, options={"conditions": Conditions(service_speed=speed), "course_change_deg": change_deg}
    )
    controller.reset(observation, info)
    done = False
    while not done:
        observation, _, terminated, truncated, info = env.step(controller.act(observation, info))
        done = terminated or truncated
    return info["metrics"]


@pytest.mark.parametrize("change_deg", [45.0, 105.0])
def test_gain_scheduling_keeps_the_overshoot_small_at_half_the_design_speed(change_deg):
    scheduled = course_change(pd_controller, DESIGN_SPEED / 2.0, change_deg)
    fixed = course_change(pd_controller, DESIGN_SPEED / 2.0, change_deg, scheduled=False)
    at_design = course_change(pd_controller, DESIGN_SPEED, change_deg)
    assert scheduled["overshoot"] < fixed["overshoot"]
    print(
        f"{change_deg:.0f} deg at half speed: overshoot scheduled {scheduled['overshoot']:.2f} deg, fixed "
        f"{fixed['overshoot']:.2f} deg (at the design speed {at_design['overshoot']:.2f} deg)"
    )


class ConstantPolicy:
    """Stands in for a stable-baselines3 model: ``predict`` with SB3's signature."""

    def __init__(self) -> None:
        self.calls: list[tuple] = []

    def predict(self, observation, state=None, episode_start=None, deterministic=False):
        self.calls.append((state, bool(episode_start[0]), deterministic))
        return np.array([0.5], dtype=np.float32), ("hidden",)


def test_every_controller_steers_through_one_interface():
    env = gym.make("ship_env/CourseChange-v0", disturbance="wind_current_waves", max_episode_steps=30)
    policy = ConstantPolicy()
    controllers = [
        pd_controller(env.unwrapped.task),
        indirect_adaptive_controller(env.unwrapped.task),
        mrac_controller(env.unwrapped.task),
        SB3Controller(policy),
    ]
    for controller in controllers:
        assert isinstance(controller, Controller)
        for seed in (0, 1):
            observation, info = env.reset(seed=seed)
            controller.reset(observation, info)
            done = False
            while not done:
                action = controller.act(observation, info)
                assert action.shape == (1,) and action.dtype == np.float32 and env.action_space.contains(action)
                observation, _, terminated, truncated, info = env.step(action)
                done = terminated or truncated
    # The policy acted deterministically, its hidden state carried along and restarted each episode.
    assert policy.calls[0] == (None, True, True) and policy.calls[1] == (("hidden",), False, True)
    assert policy.calls[30] == (None, True, True)


def test_sb3_controller_runs_a_stable_baselines3_model():
    from stable_baselines3 import PPO

    env = gym.make("ship_env/CourseChange-v0", max_episode_steps=5)
    controller = SB3Controller(PPO("MlpPolicy", env, n_steps=8, batch_size=8, seed=0, device="cpu"))
    observation, info = env.reset(seed=0)
    controller.reset(observation, info)
    action = controller.act(observation, info)
    assert action.shape == (1,) and env.action_space.contains(action)
