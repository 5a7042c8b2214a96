"""A policy trained with an observation option sails the leaderboard's environments with it."""

from __future__ import annotations

import gymnasium as gym

from ship_env.leaderboard.board import run_leaderboard
from ship_env.leaderboard.suites import NOMINAL, SuiteSpec
from ship_env.paths import config_dir
from ship_env.rl.agents import load_agent_config
from ship_env.rl.training import train


def test_a_policy_with_observation_history_is_sailed_with_it(tmp_path):
    path = tmp_path / "ppo.yaml"
    path.write_text(
        "ship_env/CourseChange-v0:\n  n_envs: 2\n  n_steps: 32\n  batch_size: 64\n  n_epochs: 1\n"
        "  env_kwargs: {observation_history: 2, ship_variation: true}\n"
    )
    config = load_agent_config("ppo", "ship_env/CourseChange-v0", path)
    train(config, tmp_path / "run", "test", steps=64, progress_bar=False)
    spec = SuiteSpec(course_changes_deg=(30.0,), tracks=(), conditions=(NOMINAL,), course_change_disturbances=("calm",))
    board = run_leaderboard(spec, policies=[tmp_path / "run"], shipped=False, progress=False)
    learned = [entrant for entrant in board.entrants if entrant.kind == "learned"]
    assert [entrant.observation_kwargs for entrant in learned] == [(("observation_history", 2),)]
    assert len([result for result in board.results if result.kind == "learned"]) == 2  # +-30 deg, sailed


def test_the_robust_course_change_config_loads_and_fits_its_environment():
    config = load_agent_config("ppo", "ship_env/CourseChange-v0", config_dir() / "agents" / "ppo_robust.yaml")
    env = gym.make(config.env_id, **config.env_kwargs)
    scales = config.hyperparameters["policy_kwargs"]["features_extractor_kwargs"]["scales"]
    assert len(scales) == env.observation_space.shape[0] == 5 + 3 * config.env_kwargs["observation_history"]
    assert env.reset(seed=0)[1]["scenario"].ship is not None
