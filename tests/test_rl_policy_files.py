"""Policy files: the shipped ones load and steer; bad ones are refused with the file and the mismatch named."""

from __future__ import annotations

import json

import gymnasium as gym
import numpy as np
import pytest
from packaging.version import Version
from stable_baselines3 import PPO

import ship_env  # noqa: F401  (registers the environments)
from ship_env.cli import main
from ship_env.envs.task import observation_keywords
from ship_env.leaderboard.entrants import policy_entrants
from ship_env.rl.metadata import METADATA_FILE, PolicyMetadata, package_versions
from ship_env.rl.policy_file import PolicyFileError, read_policy_file
from ship_env.rl.shipped import shipped_policies

COURSE_CHANGE = "ship_env/CourseChange-v0"
TRACK_FOLLOW = "ship_env/TrackFollow-v0"


def spaces_of(*env_ids: str) -> dict:
    envs = {env_id: gym.make(env_id) for env_id in env_ids}
    return {env_id: (env.observation_space, env.action_space) for env_id, env in envs.items()}


def untrained_policy(env_id: str, folder, metadata_env_id: str | None = None):
    """An untrained PPO saved as ``folder/model.zip``, with metadata naming ``metadata_env_id`` if given."""
    folder.mkdir(parents=True, exist_ok=True)
    PPO("MlpPolicy", gym.make(env_id), n_steps=64, device="cpu").save(folder / "model.zip")
    if metadata_env_id is not None:
        PolicyMetadata(
            env_id=metadata_env_id,
            env_kwargs={},
            algo="ppo",
            config={},
            config_file="ppo.yaml",
            seed=0,
            steps=0,
            timesteps=0,
            wall_time_s=0.0,
            torch_threads=1,
            versions=package_versions(),
            command="(untrained)",
        ).write(folder)
    return folder / "model.zip"


def test_shipped_policies_load_with_their_metadata_and_steer():
    paths = shipped_policies()
    assert {read_policy_file(path).env_id for path in paths} == {COURSE_CHANGE, TRACK_FOLLOW}
    for path in paths:
        policy_file = read_policy_file(path)
        assert policy_file.metadata is not None and policy_file.metadata.command.startswith("ship-env train ")
        Version(policy_file.metadata.versions["ship-env"])  # the package version that trained it
        env = gym.make(policy_file.env_id, **observation_keywords(policy_file.metadata.env_kwargs))
        policy_file.check(policy_file.env_id, env.observation_space, env.action_space)
        observation, _ = env.reset(seed=0)
        action, _ = policy_file.policy().predict(observation, deterministic=True)
        assert env.action_space.contains(np.asarray(action, dtype=np.float32))


def test_a_run_records_the_version_of_the_ship_env_code_that_trained_it():
    assert package_versions()["ship-env"] == ship_env.__version__


def test_a_file_that_is_not_a_model_names_the_file(tmp_path):
    path = tmp_path / "notes.zip"
    path.write_text("not a zip")
    with pytest.raises(PolicyFileError, match=r"policy file .*notes\.zip: not a stable-baselines3 model"):
        read_policy_file(path)
    with pytest.raises(PolicyFileError, match=r"policy file .*missing\.zip: no such file"):
        read_policy_file(tmp_path / "missing.zip")


def test_a_policy_for_another_environment_is_refused(tmp_path):
    path = untrained_policy("Pendulum-v1", tmp_path / "pendulum", metadata_env_id="Pendulum-v1")
    with pytest.raises(
        PolicyFileError, match=r"pendulum/model\.zip: it was trained on Pendulum-v1; the leaderboard sails"
    ):
        policy_entrants([path], spaces_of(COURSE_CHANGE), shipped=False)


def test_metadata_naming_an_environment_whose_spaces_differ_is_refused(tmp_path):
    path = untrained_policy(COURSE_CHANGE, tmp_path / "mislabelled", metadata_env_id=TRACK_FOLLOW)
    pattern = r"mislabelled/model\.zip: its observation space Box\(.*\(5,\).* differs from ship_env/TrackFollow-v0's"
    with pytest.raises(PolicyFileError, match=pattern):
        policy_entrants([path], spaces_of(COURSE_CHANGE, TRACK_FOLLOW), shipped=False)


def test_without_metadata_the_spaces_choose_the_environment(tmp_path):
    path = untrained_policy(TRACK_FOLLOW, tmp_path / "bare")
    (entrant,) = policy_entrants([path], spaces_of(COURSE_CHANGE, TRACK_FOLLOW), shipped=False)
    assert entrant.env_id == TRACK_FOLLOW and entrant.kind == "learned"
    with pytest.raises(
        PolicyFileError, match=r"bare/model\.zip: its observation space .* differs from ship_env/CourseChange-v0's"
    ):
        policy_entrants([path], spaces_of(COURSE_CHANGE), shipped=False)


def test_discrete_actions_do_not_fit_the_continuous_environment(tmp_path):
    folder = tmp_path / "discrete"
    folder.mkdir()
    env = gym.make(COURSE_CHANGE, action_type="discrete")
    PPO("MlpPolicy", env, n_steps=64, device="cpu").save(folder / "model.zip")
    with pytest.raises(
        PolicyFileError, match=r"its action space Discrete\(7\) differs from ship_env/CourseChange-v0's Box"
    ):
        policy_entrants([folder], spaces_of(COURSE_CHANGE), shipped=False)


def test_leaderboard_command_reports_a_bad_policy_file(tmp_path, capsys):
    path = untrained_policy("Pendulum-v1", tmp_path / "pendulum")
    with pytest.raises(SystemExit) as raised:
        main(["leaderboard", "--policies", str(path), "--no-tracks", "--out", str(tmp_path / "out")])
    assert raised.value.code == 2
    err = capsys.readouterr().err
    assert "argument --policies: policy file" in err and "pendulum/model.zip" in err
    assert "observation space" in err
    assert not (tmp_path / "out").exists()


def test_unreadable_metadata_names_the_file(tmp_path):
    path = untrained_policy(COURSE_CHANGE, tmp_path / "run")
    (tmp_path / "run" / METADATA_FILE).write_text(json.dumps({"env_id": COURSE_CHANGE}))
    with pytest.raises(PolicyFileError, match=r"run/metadata\.json: not a training run's metadata, missing"):
        read_policy_file(path)
