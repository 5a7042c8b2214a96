"""Checks of the Gymnasium contract every ship environment keeps: seeding, and vector = N singles."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import gymnasium as gym
import numpy as np
import pytest

from ship_env.model import Conditions, ShipModel
from ship_env.model import state as S
from ship_env.model.simulator import PARALLEL_SHIPS

#: Keys of a single env's info that the vector env reports in its own way.
EPISODE_KEYS = ("scenario", "score")
#: A speed-loss gain of 50 (the container ship's: 0.8): hard over, the turn slows the ship past a
#: standstill (u* > 1) within minutes; a gentle rudder keeps it valid.
DIVERGING_SHIP = {"ship_parameters": {"speed_loss.gain": 50.0}}
#: The container ship's effects less the wind's: even in still air the model feels the apparent wind of the
#: ship's own motion over the ground (2.74), which the tests' closed forms leave out.
NO_WIND_EFFECTS = [
    name for name in ShipModel("container_226m").effects if name not in ("wind_moment", "wind_drift", "gusts")
]


def sail(env: gym.Env, actions: np.ndarray, seed: int, options: dict | None = None) -> list:
    """Reset with ``seed`` and step through ``actions``; every returned item, in order."""
    steps = [env.reset(seed=seed, options=options)]
    steps.extend(env.step(action) for action in actions)
    return steps


def assert_same_steps(first: list, second: list) -> None:
    """Two runs returned the same observations, rewards, flags and information."""
    for one, other in zip(first, second, strict=True):
        np.testing.assert_array_equal(one[0], other[0])
        np.testing.assert_array_equal(one[-1]["state"], other[-1]["state"])
        assert one[-1]["measurement"] == other[-1]["measurement"]
        assert one[-1]["metrics"] == other[-1]["metrics"]
        assert one[1:-1] == other[1:-1]


def _assert_info_row(info: dict[str, Any], i: int, single_info: dict[str, Any]) -> None:
    """Sub-environment ``i`` of a vector info holds what the single env's info holds."""
    for key, value in single_info.items():
        if key in EPISODE_KEYS:
            continue
        if isinstance(value, dict):
            assert {name: info[key][name][i] for name in value} == value, key
        else:
            np.testing.assert_array_equal(info[key][i], value, err_msg=key)


def assert_vector_equals_singles(
    vector: gym.vector.VectorEnv,
    singles: list[gym.Env],
    policy: Callable[[np.ndarray], np.ndarray],
    steps: int,
    seed: int,
    partial_reset_at: int | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """Step ``vector`` and ``singles`` (seeded ``seed + i``) with the same ``policy`` actions and
    compare everything, through NEXT_STEP autoresets and, at ``partial_reset_at``, a reset of
    sub-environment 1 alone. Returns how many episodes each sub-environment ended, and the steps
    each one's current episode has run."""
    num_envs = len(singles)
    max_steps = vector.max_episode_steps
    observations, info = vector.reset(seed=seed)
    single = [env.reset(seed=seed + i) for i, env in enumerate(singles)]  # (observation, info) per env
    elapsed = np.zeros(num_envs, dtype=int)
    ended = np.zeros(num_envs, dtype=bool)
    episodes = np.zeros(num_envs, dtype=int)
    for k in range(steps):
        for i, (observation, single_info) in enumerate(single):
            np.testing.assert_array_equal(observations[i], observation)
            _assert_info_row(info, i, single_info)
        if k == partial_reset_at:
            mask = np.arange(num_envs) == 1
            observations, info = vector.reset(options={"reset_mask": mask})
            np.testing.assert_array_equal(info["_state"], mask)
            single[1] = singles[1].reset()
            elapsed[1], ended[1] = 0, False
            continue
        actions = policy(observations)
        observations, rewards, terminated, truncated, info = vector.step(actions)
        for i, env in enumerate(singles):
            if ended[i]:
                single[i] = env.reset()
                elapsed[i], reward, single_terminated = 0, 0.0, False
                assert info["_scenario"][i] and info["scenario"][i] == single[i][1]["scenario"]
            else:
                observation, reward, single_terminated, _, single_info = env.step(actions[i])
                single[i] = (observation, single_info)
                elapsed[i] += 1
                if single_terminated:
                    assert info["_score"][i]
                    assert {name: info["score"][name][i] for name in single_info["score"]} == single_info["score"]
            assert rewards[i] == reward
            assert terminated[i] == single_terminated
            assert truncated[i] == (elapsed[i] >= max_steps)
            ended[i] = terminated[i] or truncated[i]
            episodes[i] += ended[i]
    return episodes, elapsed


def assert_all_core_vector_truncates_like_a_single_env(
    env_id: str, vector_class: type, single: gym.Env, observation_size: int
) -> None:
    """``make_vec`` with ``PARALLEL_SHIPS`` envs (the all-core update) truncates every ship after 3
    steps with NEXT_STEP autoreset, and its last ship's observations equal a single env's."""
    vector = gym.make_vec(env_id, num_envs=PARALLEL_SHIPS, vectorization_mode="vector_entry_point", max_episode_steps=3)
    assert isinstance(vector.unwrapped, vector_class)
    assert vector.metadata["autoreset_mode"] == gym.vector.AutoresetMode.NEXT_STEP
    assert vector.observation_space.shape == (PARALLEL_SHIPS, observation_size)
    assert vector.action_space.shape == (PARALLEL_SHIPS, 1)
    actions = np.random.default_rng(2).uniform(-1.0, 1.0, size=(4, PARALLEL_SHIPS, 1)).astype(np.float32)
    observations = [vector.reset(seed=9)[0]]
    for k in range(4):
        observation, rewards, terminated, truncated, info = vector.step(actions[k])
        observations.append(observation)
        assert truncated.all() == (k == 2) and not terminated.any()
    assert (rewards == 0.0).all() and info["_scenario"].all()
    steps = sail(single, actions[:3, -1], seed=9 + PARALLEL_SHIPS - 1)
    np.testing.assert_array_equal(np.array(observations)[:4, -1], [step[0] for step in steps])


def assert_a_diverging_ship_ends_alone(
    vector_class: type, single: gym.Env, seed: int, conditions: Conditions | None = None, **options: Any
) -> None:
    """Ship 1 of three, hard over in a ``DIVERGING_SHIP`` (sailing ``conditions`` if given, such as a
    larger K*), leaves the model's validity: only its episode ends (truncated, ``info["diverged"]``, a
    finite observation and reward) and restarts at the next step, while ships 0 and 2 sail bit for bit
    as in a batch whose ship 1 steers a gentle course; the ``single`` environment (made with the same
    options) raises instead."""
    options = {**DIVERGING_SHIP, **options}
    diverging, gentle = vector_class(num_envs=3, **options), vector_class(num_envs=3, **options)
    hard_over = np.array([[0.2], [1.0], [-0.2]], dtype=np.float32)
    steady = np.array([[0.2], [0.1], [-0.2]], dtype=np.float32)
    others = [0, 2]
    observations, _ = diverging.reset(seed=seed)
    gentle.reset(seed=seed)
    single.reset(seed=seed + 1)
    if conditions is not None:  # ship 1 starts again in these conditions
        restart = {"reset_mask": np.array([False, True, False]), "conditions": conditions}
        observations, _ = diverging.reset(options=restart)
        gentle.reset(options=restart)
        single.reset(options={"conditions": conditions})
    diverged_at = None
    for k in range(600):
        previous = observations
        observations, rewards, terminated, truncated, info = diverging.step(hard_over)
        expected = gentle.step(steady)
        for item, other in zip((observations, rewards, terminated, truncated), expected[:4], strict=True):
            np.testing.assert_array_equal(item[others], other[others])
        np.testing.assert_array_equal(info["state"][others], expected[4]["state"][others])
        assert "diverged" not in expected[4]
        if diverged_at is not None:  # the step after: ship 1 starts a new episode
            assert info["_scenario"][1] and rewards[1] == 0.0 and not truncated[1] and "diverged" not in info
            assert np.isfinite(observations[1]).all() and np.isfinite(info["state"][1]).all()
            break
        if "diverged" in info:
            diverged_at = k
            np.testing.assert_array_equal(info["diverged"], [False, True, False])
            np.testing.assert_array_equal(info["_diverged"], [False, True, False])
            assert truncated[1] and not terminated[1]
            assert np.isfinite(observations[1]).all() and np.isfinite(rewards[1])
            state = info["state"][1]
            assert not np.isfinite(state).all() or state[S.SPEED_LOSS] > 1.0, state
            if diverging.task.decision_interval == 1:  # the observation of the step before, reward 0
                np.testing.assert_array_equal(observations[1], previous[1])
                assert rewards[1] == 0.0
        else:
            assert not truncated[1]
    assert diverged_at is not None, "ship 1 did not diverge"
    with pytest.raises(FloatingPointError, match="left the model's validity"):
        for _ in range(diverged_at + 1):
            single.step(hard_over[1])
