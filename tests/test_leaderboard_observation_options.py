"""A policy trained with an observation option sails the leaderboard's environments with it, and
every condition's ship on the design ship's observation scales."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest

from ship_env.leaderboard.board import run_leaderboard
from ship_env.leaderboard.entrants import Entrant
from ship_env.leaderboard.sailing import ship_task, suite_envs
from ship_env.leaderboard.suites import COURSE_CHANGE, HALF_SPEED, K_TAU_DOUBLE, NOMINAL, Suite, SuiteSpec
from ship_env.model import state as S
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


def test_the_course_change_config_loads_and_fits_its_environment():
    """The shipped CourseChange policy's entry: varied ships and a history of the observations."""
    config = load_agent_config("ppo", "ship_env/CourseChange-v0", config_dir() / "agents" / "ppo.yaml")
    env = gym.make(config.env_id, **config.env_kwargs)
    scales = config.hyperparameters["policy_kwargs"]["features_extractor_kwargs"]["scales"]
    assert len(scales) == env.observation_space.shape[0] == 5 + 3 * config.env_kwargs["observation_history"]
    assert env.reset(seed=0)[1]["scenario"].ship is not None


@pytest.mark.parametrize("condition", [K_TAU_DOUBLE, HALF_SPEED])
def test_a_condition_sails_its_ship_observed_on_the_design_ships_scales(condition):
    """K*, tau* doubled: the ship turns faster than the design ship at a held rudder (less than
    twice: Norrbin's term and the speed lost), and its observed rate of turn is larger by as much
    (a policy is not told the changed K*, as no autopilot is); half speed: the ship sails, and is
    observed, as ``ship_variation`` draws it."""
    suite = Suite("CourseChange calm", COURSE_CHANGE, {"disturbance": "calm"}, condition, ())
    sailed, design_model = suite_envs(suite, Entrant("PD, fixed gains", COURSE_CHANGE))
    nominal = gym.make(COURSE_CHANGE, disturbance="calm")
    assert design_model.parameter("yaw.gain") == ship_task(nominal).model.parameter("yaw.gain")
    ship = sailed.reset(seed=4, options={"initial_heading_deg": 0.0})[1]["scenario"].ship
    nominal.reset(seed=4, options={"initial_heading_deg": 0.0})
    scales = condition.scales
    assert (ship.yaw_gain, ship.yaw_time_constant, ship.speed) == (
        scales.get("yaw.gain", 1.0),
        scales.get("yaw.time_constant", 1.0),
        scales.get("service_speed", 1.0),
    )
    for _ in range(600):
        observed, _, _, _, info = sailed.step(np.array([0.5], dtype=np.float32))
        expected, _, _, _, nominal_info = nominal.step(np.array([0.5], dtype=np.float32))
    rate = info["state"][S.RATE_OF_TURN] / nominal_info["state"][S.RATE_OF_TURN]
    speed = info["measurement"]["speed"] / nominal_info["measurement"]["speed"]
    if condition is K_TAU_DOUBLE:
        assert rate > 1.4 and observed[1] / expected[1] == pytest.approx(rate, rel=0.02)
    else:
        assert speed == pytest.approx(0.5, rel=0.05) and observed[3] == pytest.approx(expected[3], rel=0.05)
