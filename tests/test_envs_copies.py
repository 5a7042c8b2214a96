"""Copies and pickles sail the same ship: ``copy.deepcopy`` and a pickle round trip taken mid-episode
continue bit for bit as the original does (states, observations, rewards, information), for the
simulator, every environment, the native vector environment, and environments sent to spawned workers."""

from __future__ import annotations

import copy
import dataclasses
import math
import pickle
from collections.abc import Callable
from typing import Any

import gymnasium as gym
import numpy as np
import pytest

import ship_env  # noqa: F401  (registers the environments)
from ship_env.model import Conditions, ShipModel, Simulator

#: Each environment in weather that uses every array the simulator steps (the sea's draws included).
ENVS = [
    ("ship_env/CourseChange-v0", {"disturbance": "wind_current_waves"}),
    ("ship_env/CourseKeeping-v0", {"disturbance": "wind_current_waves"}),
    ("ship_env/TrackFollow-v0", {}),
    ("ship_env/CourseKeeping-v0", {"action_type": "discrete", "decision_interval": 3}),
]
COPIES: dict[str, Callable[[Any], Any]] = {
    "deepcopy": copy.deepcopy,
    "pickle": lambda thing: pickle.loads(pickle.dumps(thing)),
}
BEFORE, AFTER = 15, 25


def assert_identical(one: Any, other: Any, where: str = "") -> None:
    """The same values bit for bit, through dicts, sequences, arrays and dataclasses."""
    if isinstance(one, dict):
        assert one.keys() == other.keys(), where
        for key in one:
            assert_identical(one[key], other[key], f"{where}[{key!r}]")
    elif isinstance(one, (list, tuple)):
        assert len(one) == len(other), where
        for k, (a, b) in enumerate(zip(one, other, strict=True)):
            assert_identical(a, b, f"{where}[{k}]")
    elif isinstance(one, np.ndarray):
        assert one.dtype == other.dtype and one.shape == other.shape, where
        if one.dtype == object:
            assert_identical(list(one), list(other), where)
        else:
            if one.dtype.names is None:
                np.testing.assert_array_equal(one, other, err_msg=where)
            assert one.tobytes() == other.tobytes(), where
    elif dataclasses.is_dataclass(one):
        assert type(one) is type(other), where
        assert_identical(dataclasses.asdict(one), dataclasses.asdict(other), where)
    elif isinstance(one, float) and math.isnan(one):
        assert isinstance(other, float) and math.isnan(other), where
    else:
        assert one == other, where


def _actions(space: gym.Space, count: int) -> list[Any]:
    space.seed(7)
    return [space.sample() for _ in range(count)]


def _copied_and_checked(env: Any, how: str) -> tuple[Any, list[Any]]:
    """A copy of ``env`` (single or vector) made ``BEFORE`` steps into its episode, checked to sail on and to reset
    as the original; the copy and the actions sailed."""
    actions = _actions(env.action_space, BEFORE + AFTER)
    env.reset(seed=3)
    for action in actions[:BEFORE]:
        env.step(action)
    copied = COPIES[how](env)
    assert_identical([copied.step(a) for a in actions[BEFORE:]], [env.step(a) for a in actions[BEFORE:]])
    assert_identical(copied.reset(seed=4), env.reset(seed=4))
    return copied, actions


@pytest.mark.parametrize("how", list(COPIES))
@pytest.mark.parametrize("num_ships", [1, 3])
def test_a_copied_simulator_sails_on_as_the_original(how, num_ships):
    sim = Simulator(ShipModel("container_226m", [*ShipModel("container_226m").effects, "wave_spectrum"]), num_ships)
    sim.reset(seed=5, conditions=Conditions(wind_speed=8.0, wave_height=3.0, current_speed=1.0))
    orders = np.radians(20.0) * np.sin(np.arange(BEFORE + AFTER) / 5.0)
    for order in orders[:BEFORE]:
        sim.step(order)
    copied = COPIES[how](sim)
    for order in orders[BEFORE:]:
        sim.step(order)
        copied.step(order)
        assert_identical(copied.state, sim.state)
    assert sim.state[0, 0] > 0.0
    assert_identical(copied.conditions, sim.conditions)
    assert_identical(copied.step_index, sim.step_index)
    sim.reset(seed=6)
    copied.reset(seed=6)
    sim.step(0.1)
    copied.step(0.1)
    assert_identical(copied.state, sim.state)


@pytest.mark.parametrize("how", list(COPIES))
@pytest.mark.parametrize(("env_id", "options"), ENVS, ids=[f"{e}-{o}" for e, o in ENVS])
def test_a_copied_env_sails_on_as_the_original(env_id, options, how):
    env = gym.make(env_id, **options)
    copied, actions = _copied_and_checked(env, how)
    assert_identical([copied.step(a) for a in actions[:5]], [env.step(a) for a in actions[:5]])


@pytest.mark.parametrize("how", list(COPIES))
@pytest.mark.parametrize("num_envs", [1, 2])
@pytest.mark.parametrize(("env_id", "options"), ENVS[:3], ids=[e for e, _ in ENVS[:3]])
def test_a_copied_vector_env_sails_on_as_the_original(env_id, options, num_envs, how):
    vector = gym.make_vec(env_id, num_envs=num_envs, vectorization_mode="vector_entry_point", **options)
    copied, actions = _copied_and_checked(vector, how)
    copied_info = copied.step(actions[0])[-1]
    assert_identical(copied_info, vector.step(actions[0])[-1])
    with pytest.raises(ValueError, match="read-only"):  # the masks every info shares stay read-only
        copied_info["_state"][0] = False


def test_envs_sent_to_spawned_workers_sail_on_as_the_originals():
    """``AsyncVectorEnv`` with env instances pickles them into spawned processes mid-episode."""
    env_id, options = ENVS[0]
    envs = [gym.make(env_id, **options) for _ in range(2)]
    twins = [gym.make(env_id, **options) for _ in range(2)]
    actions = np.array(_actions(envs[0].action_space, BEFORE + AFTER))
    for k, (env, twin) in enumerate(zip(envs, twins, strict=True)):
        env.reset(seed=10 + k)
        twin.reset(seed=10 + k)
        for action in actions[:BEFORE]:
            env.step(action)
            twin.step(action)
    spawned = gym.vector.AsyncVectorEnv([lambda env=env: env for env in envs], context="spawn")
    try:
        for action in actions[BEFORE:]:
            observations, rewards, terminated, truncated, infos = spawned.step(np.stack([action, -action]))
            for k, twin in enumerate(twins):
                observation, reward, _, _, info = twin.step(action if k == 0 else -action)
                assert_identical(observations[k], observation)
                assert_identical(rewards[k], reward)
                assert_identical(infos["state"][k], info["state"])
    finally:
        spawned.close()
