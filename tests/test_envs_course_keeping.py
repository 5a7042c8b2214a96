"""CourseKeeping-v0: the criterion, the waves on the compass, Gymnasium's contract."""

from __future__ import annotations

import math

import gymnasium as gym
import numpy as np
import pytest
from env_contract import (
    DIVERGING_SHIP,
    NO_WIND_EFFECTS,
    assert_a_diverging_ship_ends_alone,
    assert_all_core_vector_truncates_like_a_single_env,
    assert_vector_equals_singles,
)

import ship_env  # noqa: F401  (registers the environments)
from ship_env.envs.course_keeping import CourseKeepingEnv
from ship_env.envs.course_keeping_task import HEADING_SCALE, OBS_HEADING_ERROR, OBS_RATE_OF_TURN
from ship_env.envs.course_keeping_vector import CourseKeepingVectorEnv
from ship_env.envs.metrics import course_keeping_metrics
from ship_env.envs.weather import RANDOM_DISTURBANCE
from ship_env.model import Conditions
from ship_env.model import state as S

ENV_ID = "ship_env/CourseKeeping-v0"


def heading_pd(task, kp: float = 1.0, kd: float = 30.0):
    """A fixed-gain PD autopilot on the observation: delta = Kp e - Kd r (rad, s)."""
    rate_scale = task.full_rudder_rate_per_speed * task.model.service_speed

    def policy(observations: np.ndarray) -> np.ndarray:
        observations = np.atleast_2d(observations)
        rudder = (
            kp * observations[:, OBS_HEADING_ERROR] * HEADING_SCALE
            - kd * observations[:, OBS_RATE_OF_TURN] * rate_scale
        )
        return np.clip(rudder / task.rudder_limit, -1.0, 1.0).astype(np.float32)[:, None]

    return policy


def test_vector_env_equals_single_envs_seeded_s_plus_i_across_resets():
    num_envs, seed = 3, 21
    vector = CourseKeepingVectorEnv(num_envs=num_envs, max_episode_steps=7, disturbance=RANDOM_DISTURBANCE)
    singles = [CourseKeepingEnv(disturbance=RANDOM_DISTURBANCE) for _ in range(num_envs)]
    episodes, elapsed = assert_vector_equals_singles(
        vector, singles, heading_pd(vector.task), 30, seed, partial_reset_at=10
    )
    assert episodes.min() >= 2 and elapsed.min() < elapsed.max()


@pytest.mark.slow
def test_make_vec_uses_the_vector_entry_point_on_all_cores_like_single_envs():
    assert_all_core_vector_truncates_like_a_single_env(ENV_ID, CourseKeepingVectorEnv, CourseKeepingEnv(), 4)


@pytest.mark.parametrize(("decision_interval", "history"), [(1, 0), (1, 2), (3, 2)])
def test_a_diverging_ship_ends_only_its_own_episode(decision_interval, history):
    options = {"disturbance": "calm", "decision_interval": decision_interval, "observation_history": history}
    single = CourseKeepingEnv(**DIVERGING_SHIP, **options)
    assert_a_diverging_ship_ends_alone(CourseKeepingVectorEnv, single, seed=5, **options)


def test_still_water_with_the_rudder_amidships_costs_nothing():
    env = CourseKeepingEnv(disturbance="calm", effects=NO_WIND_EFFECTS, sensor_noise_scale=0.0)
    _, info = env.reset(seed=0, options={"course_deg": 200.0})
    for _ in range(100):
        observation, reward, _, _, info = env.step(np.zeros(1, dtype=np.float32))
        assert reward == 0.0 and observation[OBS_HEADING_ERROR] == 0.0
    assert info["state"][S.HEADING] == math.radians(200.0) == info["course"]
    assert info["metrics"] == {
        "cost": 0.0,
        "mean_squared_heading_error": 0.0,
        "mean_squared_rudder": 0.0,
        "rudder_travel": 0.0,
        "samples": 100,
    }


def test_an_episode_truncates_at_the_spec_length_and_its_mean_reward_is_the_criterion():
    """600 steps; info's metrics equal ``course_keeping_metrics`` of the run; mean reward = -J / delta_max^2."""
    env = gym.make(ENV_ID)
    observation, info = env.reset(seed=5)
    policy = heading_pd(env.unwrapped.task)
    states, rewards, truncated = [info["state"]], [], False
    while not truncated:
        observation, reward, terminated, truncated, info = env.step(policy(observation)[0])
        assert not terminated
        states.append(info["state"])
        rewards.append(reward)
    states = np.array(states)
    assert len(rewards) == 600
    expected = course_keeping_metrics(states[:, S.HEADING], states[:, S.RUDDER], info["course"])
    assert info["metrics"] == pytest.approx(expected, rel=1e-12)
    rudder_limit_deg = 10.0
    assert np.mean(rewards) == pytest.approx(-expected["cost"] / rudder_limit_deg**2, rel=1e-9)
    assert 0.0 < expected["mean_squared_heading_error"] < 4.0 and expected["rudder_travel"] > 0.0


def test_course_keeping_metrics_on_a_hand_made_run():
    course = math.radians(10.0)
    heading = np.radians([10.0, 12.0, 9.0, 370.0 - 2.0])  # the last wraps through north
    rudder = np.radians([0.0, -2.0, 1.0, 3.0])
    metrics = course_keeping_metrics(heading, rudder, course, rudder_weight=0.5)
    squared_errors, squared_rudder = (4.0 + 1.0 + 4.0) / 3.0, (4.0 + 1.0 + 9.0) / 3.0
    assert metrics == pytest.approx(
        {
            "cost": squared_errors + 0.5 * squared_rudder,
            "mean_squared_heading_error": squared_errors,
            "mean_squared_rudder": squared_rudder,
            "rudder_travel": 7.0,
            "samples": 3,
        }
    )


def test_the_compass_sees_the_waves_yaw_that_the_criterion_ignores():
    conditions = Conditions(wave_height=4.0, wave_period=8.0, wave_direction=0.0)
    env = CourseKeepingEnv(sensor_noise_scale=0.0)
    _, info = env.reset(seed=2, options={"conditions": conditions, "course_deg": 0.0})
    assert info["scenario"].disturbance == "custom"
    wave_yaw = []
    for _ in range(200):
        observation, reward, _, _, info = env.step(np.zeros(1, dtype=np.float32))
        state = info["state"]
        true_error = -state[S.HEADING]
        assert observation[OBS_HEADING_ERROR] == pytest.approx(
            (true_error - state[S.WAVE_HEADING]) / HEADING_SCALE, abs=1e-6
        )
        assert reward == pytest.approx(-((true_error / math.radians(10.0)) ** 2))
        wave_yaw.append(state[S.WAVE_HEADING])
    assert np.std(wave_yaw) > math.radians(0.05)
