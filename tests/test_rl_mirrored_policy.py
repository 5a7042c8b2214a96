"""The mirror-symmetric policy: a course change to port steered as the mirror image of one to starboard."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest
import torch
import yaml
from gymnasium import spaces

from ship_env.cli import main
from ship_env.rl.features import MirroredObservationPolicy, ScaledObservationPolicy
from ship_env.rl.policy_file import read_policy_file

COURSE_CHANGE = "ship_env/CourseChange-v0"
#: CourseChange with a history of 2: heading error, rate, rudder, speed, turn direction, 2 x (e, r, rudder).
SCALES = [50, 5, 1, 1, 1, 50, 5, 1, 50, 5, 1]
MIRRORED = [0, 1, 2, 4, 5, 6, 7, 8, 9, 10]
OBSERVATION_SPACE = spaces.Box(-4.0, 4.0, (11,), np.float32)
ACTION_SPACE = spaces.Box(-1.0, 1.0, (1,), np.float32)


def _policy(policy_class=MirroredObservationPolicy, **kwargs):
    torch.manual_seed(0)
    if policy_class is MirroredObservationPolicy:
        kwargs = {"mirror_sign": 4, "mirrored": MIRRORED, **kwargs}
    return policy_class(
        OBSERVATION_SPACE,
        ACTION_SPACE,
        lambda _: 3e-4,
        net_arch=[16, 16],
        features_extractor_kwargs={"scales": SCALES},
        **kwargs,
    )


def _observations_and_mirror_images() -> tuple[torch.Tensor, torch.Tensor]:
    rng = np.random.default_rng(3)
    observations = rng.uniform(-0.3, 0.3, (64, 11)).astype(np.float32)
    observations[:, 3] = rng.uniform(0.5, 1.0, 64)  # speed: the same in the mirror image
    observations[:, 4] = rng.choice([-1.0, 1.0], 64)  # half to port, half to starboard
    mirror_images = observations.copy()
    mirror_images[:, MIRRORED] *= -1.0
    return torch.as_tensor(observations), torch.as_tensor(mirror_images)


def test_the_mirror_image_of_an_observation_gets_the_mirrored_action_and_the_same_value():
    policy = _policy()
    observations, mirror_images = _observations_and_mirror_images()
    with torch.no_grad():
        actions = policy._predict(observations, deterministic=True)
        assert torch.all(actions != 0.0)
        torch.testing.assert_close(policy._predict(mirror_images, deterministic=True), -actions, rtol=0, atol=0)
        torch.testing.assert_close(policy.predict_values(mirror_images), policy.predict_values(observations))
        sampled, values, log_prob = policy(observations)
        values_seen, log_prob_seen, _ = policy.evaluate_actions(observations, sampled)
        values_mirrored, log_prob_mirrored, entropy = policy.evaluate_actions(mirror_images, -sampled)
        assert entropy is not None
    torch.testing.assert_close(values_seen, values)
    torch.testing.assert_close(log_prob_seen, log_prob)  # the rollout's log-probabilities are the update's
    torch.testing.assert_close(log_prob_mirrored, log_prob)
    torch.testing.assert_close(values_mirrored, values)
    # The same network without the mirror is not symmetric: the check above could fail.
    plain = _policy(ScaledObservationPolicy)
    with torch.no_grad():
        assert not torch.allclose(
            plain._predict(mirror_images, deterministic=True), -plain._predict(observations, True)
        )


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"mirror_sign": 3}, r"mirror_sign: expected one of the mirrored elements \[0, 1, 2, 4, .*\], got 3"),
        ({"mirrored": [0, 4, 11]}, r"mirrored: expected elements of an observation of size 11, got \[0, 4, 11\]"),
    ],
)
def test_a_mirror_outside_the_observation_is_refused_with_the_field_named(kwargs, message):
    with pytest.raises(ValueError, match=message):
        _policy(**kwargs)


def test_a_discrete_action_is_refused():
    with pytest.raises(ValueError, match=r"action_space: expected a Box \(a continuous action\), got Discrete\(7\)"):
        MirroredObservationPolicy(
            OBSERVATION_SPACE,
            spaces.Discrete(7),
            lambda _: 3e-4,
            features_extractor_kwargs={"scales": SCALES},
            mirror_sign=4,
            mirrored=MIRRORED,
        )


def test_a_trained_mirrored_policy_file_steers_port_and_starboard_as_mirror_images(tmp_path):
    """``ship-env train`` with the policy named in the agent config; the policy file rebuilds it, and on
    a noise-free calm sea the same course change to port and to starboard are sailed as mirror images."""
    config = tmp_path / "ppo.yaml"
    entry = {
        "n_envs": 2,
        "policy": "ship_env.rl.features.MirroredObservationPolicy",
        "env_kwargs": {"observation_history": 2},
        "n_steps": 32,
        "batch_size": 32,
        "n_epochs": 1,
        "policy_kwargs": {
            "net_arch": [8],
            "features_extractor_kwargs": {"scales": SCALES},
            "mirror_sign": 4,
            "mirrored": MIRRORED,
        },
    }
    config.write_text(yaml.safe_dump({COURSE_CHANGE: entry}))
    out = tmp_path / "mirrored"
    argv = ["train", "--algo", "ppo", "--steps", "64", "--config", str(config), "--out", str(out)]
    assert main([*argv, "--no-progress"]) == 0
    policy = read_policy_file(out).policy()
    assert isinstance(policy, MirroredObservationPolicy)
    env = gym.make(COURSE_CHANGE, observation_history=2, sensor_noise_scale=0.0)
    rudders = []
    for change in (30.0, -30.0):
        observation, _ = env.reset(seed=5, options={"course_change_deg": change, "initial_heading_deg": 90.0})
        orders = []
        for _ in range(40):
            action, _ = policy.predict(observation, deterministic=True)
            orders.append(float(action[0]))
            observation, *_ = env.step(action)
        rudders.append(np.array(orders))
    assert np.any(rudders[0] != 0.0)
    np.testing.assert_allclose(rudders[1], -rudders[0], rtol=0.0, atol=1e-5)
