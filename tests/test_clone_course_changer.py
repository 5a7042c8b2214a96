"""benchmarks/clone_course_changer.py: DART demonstrations and the cloned policy, on a known steering law."""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import gymnasium as gym
import numpy as np
import pytest

import ship_env  # noqa: F401  (registers the environments)
from ship_env.envs.track_follow_task import OBS_CROSS_TRACK, OBS_LINE_OF_SIGHT
from ship_env.rl.agents import load_agent_config
from ship_env.rl.policy_file import read_policy_file

SCRIPT = Path(__file__).resolve().parents[1] / "benchmarks" / "clone_course_changer.py"
#: Steps per demonstration episode (truncated): enough for the law's rudder to move, a second's run.
EPISODE_STEPS = 60


def law(observation: np.ndarray) -> np.ndarray:
    """A fixed steering law of the observation: line of sight and cross-track error, as a fraction of delta_max."""
    rudder = 10.0 * observation[OBS_LINE_OF_SIGHT] - 0.5 * observation[OBS_CROSS_TRACK]
    return np.array([np.clip(rudder, -1.0, 1.0)], dtype=np.float32)


class LawController:
    """The expert of these tests: :func:`law`, no state."""

    def reset(self, observation: np.ndarray, info: Mapping[str, Any]) -> None:
        pass

    def act(self, observation: np.ndarray, info: Mapping[str, Any]) -> np.ndarray:
        return law(observation)


def test_demonstrations_record_the_experts_orders_while_every_other_episode_sails_them_perturbed(load_script):
    clone = load_script(SCRIPT, "clone_course_changer")
    env = gym.make(
        "ship_env/TrackFollow-v0",
        track_preview=True,
        decision_interval=1,
        start="before_turn",
        max_episode_steps=EPISODE_STEPS,
    )
    observations, actions = clone.demonstrations(env, LawController(), [5, 5], 0.3, 5.0, np.random.default_rng(0))
    assert observations.shape == (2 * EPISODE_STEPS, env.observation_space.shape[0])
    np.testing.assert_array_equal(actions, np.array([law(o) for o in observations]))
    clean, perturbed = observations[:EPISODE_STEPS], observations[EPISODE_STEPS:]
    np.testing.assert_array_equal(clean[0], perturbed[0])  # the same episode seed: the same start
    assert not np.allclose(clean, perturbed)  # the second sails the orders plus the DART offset


@pytest.mark.slow
def test_the_cloned_policy_steers_by_the_law_and_loads_as_a_policy_file(tmp_path, load_script):
    """A network fitted to a smooth law of its own observation reproduces it over its demonstrations
    (R^2 > 0.9; unfitted, below 0), saved as a policy file the leaderboard reads without running code."""
    clone = load_script(SCRIPT, "clone_course_changer")
    config = load_agent_config("ppo", clone.ENV_ID, clone.CONFIG)
    # One sub-environment: its rollout (n_steps) is one mini-batch, which PPO would otherwise truncate.
    config = dataclasses.replace(
        config,
        n_envs=1,
        env_kwargs={**config.env_kwargs, "max_episode_steps": EPISODE_STEPS},
        hyperparameters={**config.hyperparameters, "batch_size": config.hyperparameters["n_steps"]},
    )
    clone.clone(
        config,
        tmp_path,
        "test",
        seed=0,
        episodes=2,
        noise=0.3,
        correlation_time=5.0,
        epochs=300,
        expert=lambda task: LawController(),
    )
    policy_file = read_policy_file(tmp_path / "model.zip")
    assert policy_file.metadata is not None and policy_file.metadata.env_kwargs["decision_interval"] == 1
    policy = policy_file.policy()
    env = gym.make(clone.ENV_ID, **config.env_kwargs)
    # The demonstrations the clone was fitted to: its episode seeds and noise generator for seed 0.
    observations, orders = clone.demonstrations(env, LawController(), [1000, 1001], 0.3, 5.0, np.random.default_rng(0))
    predicted = np.array([policy.predict(o, deterministic=True)[0] for o in observations]).reshape(orders.shape)
    explained = 1.0 - np.mean((predicted - orders) ** 2) / np.var(orders)
    assert explained > 0.9
