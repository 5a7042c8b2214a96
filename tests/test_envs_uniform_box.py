"""The continuous action space: Box's samples, bit for bit, by a shorter way; a Box everywhere else."""

from __future__ import annotations

import copy
import pickle

import gymnasium as gym
import numpy as np
import pytest
from gymnasium import spaces
from gymnasium.vector.utils import batch_space

import ship_env  # noqa: F401  (registers the environments)
from ship_env.envs.uniform_box import UniformBox

# Bounds a float32 cannot hold exactly (0.1, 0.7) as well as the action's -1 and 1; several shapes.
CASES = [(-1.0, 1.0, (1,), np.float32), (0.1, 0.7, (2, 3), np.float32), (-2.5, 0.3, (4,), np.float64)]


@pytest.mark.parametrize(("low", "high", "shape", "dtype"), CASES)
def test_the_samples_are_box_samples_bit_for_bit(low, high, shape, dtype):
    ours, theirs = UniformBox(low, high, shape, dtype, seed=7), spaces.Box(low, high, shape, dtype, seed=7)
    for _ in range(2000):
        sample, expected = ours.sample(), theirs.sample()
        assert sample.dtype == expected.dtype and sample.shape == expected.shape
        assert np.array_equal(sample, expected)
        assert ours.contains(sample)


def test_it_is_a_box_to_gymnasium():
    ours, theirs = UniformBox(-1.0, 1.0, (1,)), spaces.Box(-1.0, 1.0, (1,), np.float32)
    assert ours == theirs and theirs == ours
    assert repr(ours) == repr(theirs)
    assert spaces.flatten_space(ours) == spaces.flatten_space(theirs)
    assert batch_space(ours, 4) == batch_space(theirs, 4)
    with pytest.raises(gym.error.Error, match="Box.sample cannot be provided a mask"):
        ours.sample(mask=np.ones(1))


def test_a_batch_of_them_is_one_and_samples_as_gymnasiums_batch():
    single = UniformBox(0.1, 0.7, (2,), seed=5)
    ours, theirs = batch_space(single, 8), batch_space(spaces.Box(0.1, 0.7, (2,), np.float32, seed=5), 8)
    assert type(ours) is UniformBox and ours.shape == (8, 2)
    for _ in range(200):
        assert np.array_equal(ours.sample(), theirs.sample())


def test_copies_and_pickles_go_on_with_the_same_numbers():
    space = UniformBox(-1.0, 1.0, (2,), seed=3)
    space.sample()
    copies = (copy.deepcopy(space), pickle.loads(pickle.dumps(space)))
    expected = space.sample()
    for copied in copies:
        assert type(copied) is UniformBox
        assert np.array_equal(copied.sample(), expected)


@pytest.mark.parametrize(
    ("arguments", "message"),
    [
        ((-1.0, 1.0, (1,), np.int64), "dtype: expected a floating dtype, got int64"),
        ((1.0, 1.0, (1,)), "low < high, got low=1.0, high=1.0"),
        ((-np.inf, 1.0, (1,)), "finite bounds"),
    ],
)
def test_bounds_it_cannot_sample_uniformly_are_refused(arguments, message):
    with pytest.raises(ValueError, match=message):
        UniformBox(*arguments)


def test_the_environments_continuous_actions_are_uniform_boxes():
    env = gym.make("ship_env/CourseChange-v0")
    assert type(env.action_space) is UniformBox
    env.action_space.seed(11)
    reference = spaces.Box(-1.0, 1.0, (1,), np.float32, seed=11)
    assert np.array_equal(env.action_space.sample(), reference.sample())
    env.close()
    vector = gym.make_vec("ship_env/CourseChange-v0", num_envs=3, vectorization_mode="vector_entry_point")
    assert type(vector.action_space) is UniformBox and vector.action_space.shape == (3, 1)
    vector.close()
