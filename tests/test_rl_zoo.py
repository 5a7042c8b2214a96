"""The shipped agent configs as rl-zoo3 has them: it trains with them unchanged; ``ship-env train`` reads them alike."""

from __future__ import annotations

import sys

import gymnasium as gym
import pytest
import yaml
from stable_baselines3.common.save_util import load_from_zip_file

from ship_env.rl.agents import agents_file, load_agent_config
from ship_env.rl.policy_file import read_policy_file

COURSE_CHANGE = "ship_env/CourseChange-v0"
TRACK_FOLLOW = "ship_env/TrackFollow-v0"
#: Each shipped config entry, with rl-zoo3 ``--hyperparams`` overrides that make a run of a few hundred steps.
SHORT_RUNS = {
    ("ppo", COURSE_CHANGE): ["n_envs:2", "n_steps:64", "batch_size:64", "n_epochs:1"],
    ("ppo", TRACK_FOLLOW): ["n_envs:2", "n_steps:64", "batch_size:64", "n_epochs:1"],
    ("ppo_lstm", COURSE_CHANGE): ["n_envs:2", "n_steps:64", "batch_size:64", "n_epochs:1"],
    ("sac", COURSE_CHANGE): ["n_envs:1", "learning_starts:64", "batch_size:32", "train_freq:16", "gradient_steps:1"],
}


@pytest.mark.parametrize("algo, env_id", list(SHORT_RUNS))
def test_rl_zoo3_trains_with_the_shipped_config_unchanged(tmp_path, monkeypatch, algo, env_id):
    """``python -m rl_zoo3.train --algo A --env ID --gym-packages ship_env -conf configs/agents/A.yaml``,
    a few hundred steps: the same policy class, policy kwargs, reward normalisation and env kwargs as
    ``ship-env train`` reads from the file, and a model the leaderboard can sail."""
    pytest.importorskip("rl_zoo3", reason="rl-zoo3 (the dev extra) is not installed")
    from rl_zoo3.train import train

    argv = ["rl_zoo3.train", "--algo", algo, "--env", env_id, "--gym-packages", "ship_env"]
    argv += ["-conf", str(agents_file(algo)), "-n", "256", "--seed", "0", "--eval-freq", "-1", "--log-interval", "-1"]
    argv += ["-f", str(tmp_path), "--hyperparams", *SHORT_RUNS[algo, env_id]]
    monkeypatch.setattr(sys, "argv", argv)
    train()

    name = env_id.replace("/", "-")  # rl-zoo3's folder and file names
    run = tmp_path / algo / f"{name}_1"
    data, _, _ = load_from_zip_file(run / f"{name}.zip", device="cpu")
    ours = load_agent_config(algo, env_id)
    assert data["num_timesteps"] >= 256
    assert ours.hyperparameters["policy_kwargs"].items() <= data["policy_kwargs"].items()  # SAC adds use_sde
    if isinstance(ours.policy, type):  # a class path (ship_env.rl.features), not an SB3 alias
        assert data["policy_class"] is ours.policy
    saved = dict(yaml.unsafe_load((run / name / "config.yml").read_text()))
    assert saved.get("env_kwargs") == ours.entry.get("env_kwargs")
    assert (run / name / "vecnormalize.pkl").is_file() == (ours.normalize is not None)
    policy_file = read_policy_file(run / f"{name}.zip")
    env = gym.make(env_id, **ours.env_kwargs)
    assert policy_file.mismatch(env_id, env.observation_space, env.action_space) is None
    env.close()
