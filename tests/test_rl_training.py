"""``ship-env train``: agent configs, a short run writing model and metadata, clear errors."""

from __future__ import annotations

import json
import shlex
from pathlib import Path

import pytest
import yaml
from stable_baselines3 import PPO

import ship_env
from ship_env.cli import main
from ship_env.rl.agents import ALGORITHMS, load_agent_config
from ship_env.rl.metadata import machine_description
from ship_env.rl.policy_file import read_policy_file

COURSE_CHANGE = "ship_env/CourseChange-v0"
TRACK_FOLLOW = "ship_env/TrackFollow-v0"


@pytest.mark.parametrize(
    "algo, env_id", [("ppo", COURSE_CHANGE), ("sac", COURSE_CHANGE), ("ppo", TRACK_FOLLOW), ("ppo_lstm", COURSE_CHANGE)]
)
def test_shipped_agent_configs_have_an_entry_per_shipped_task(algo, env_id):
    config = load_agent_config(algo, env_id)
    assert config.env_id == env_id and config.n_envs >= 1 and config.n_timesteps > 0
    assert config.algorithm.__name__ == ALGORITHMS[algo]


def test_config_errors_name_the_file_and_the_problem(tmp_path):
    path = tmp_path / "ppo.yaml"
    path.write_text(yaml.safe_dump({COURSE_CHANGE: {"n_envs": 2, "n_stepz": 64}}))
    with pytest.raises(ValueError, match=r"ppo\.yaml: ship_env/CourseChange-v0: PPO takes no keyword 'n_stepz'"):
        load_agent_config("ppo", COURSE_CHANGE, path)
    with pytest.raises(
        ValueError, match=r"ppo\.yaml: no entry for 'ship_env/TrackFollow-v0'; entries: ship_env/CourseChange-v0"
    ):
        load_agent_config("ppo", "ship_env/TrackFollow-v0", path)
    path.write_text(yaml.safe_dump({COURSE_CHANGE: {"n_envs": 0}}))
    with pytest.raises(ValueError, match=r"n_envs: expected a whole number >= 1, got 0"):
        load_agent_config("ppo", COURSE_CHANGE, path)


@pytest.mark.parametrize(
    "entry, message",
    [
        ({"frame_stack": 4}, r"CourseChange-v0: rl-zoo3's key 'frame_stack' is not supported by ship-env train"),
        ({"normalize": True}, r"normalize: observation normalisation \(norm_obs\) is not supported"),
        ({"normalize": "{'norm_obs': False"}, r"normalize: cannot evaluate \"\{'norm_obs': False\""),
        ({"policy_kwargs": "dict(net_arch=os.system)"}, r"policy_kwargs: cannot evaluate .*name 'os' is not defined"),
        ({"learning_rate": "exp_0.001"}, r"learning_rate: expected a number or a linear schedule .* got 'exp_0.001'"),
        ({"env_wrapper": "gymnasium.wrappers.NoSuchWrapper"}, r"env_wrapper: expected a class .*NoSuchWrapper"),
        ({"policy": "ship_env.rl.features.NoSuchPolicy"}, r"policy: expected a class .*NoSuchPolicy"),
    ],
)
def test_rl_zoo3_keys_we_do_not_support_or_cannot_parse_are_named(tmp_path, entry, message):
    path = tmp_path / "ppo.yaml"
    path.write_text(yaml.safe_dump({COURSE_CHANGE: {"n_envs": 2, **entry}}))
    with pytest.raises(ValueError, match=message):
        load_agent_config("ppo", COURSE_CHANGE, path)


def test_rl_zoo3_keys_are_read_as_rl_zoo3_reads_them(tmp_path):
    """Strings evaluated with torch.nn in scope, reward-only normalisation with the entry's gamma,
    rl-zoo3's linear schedule, wrappers and callbacks with their keyword arguments."""
    from gymnasium.wrappers import ClipReward
    from torch import nn

    from ship_env.rl.training import make_training_env

    path = tmp_path / "ppo.yaml"
    entry = {
        "n_envs": 2,
        "n_steps": 64,
        "batch_size": 64,
        "n_epochs": 1,
        "gamma": 0.98,
        "normalize": "{'norm_obs': False, 'norm_reward': True}",
        "learning_rate": "lin_0.001",
        "policy_kwargs": "dict(net_arch=[8], activation_fn=nn.ReLU)",
        "env_wrapper": [{"gymnasium.wrappers.ClipReward": {"min_reward": -0.5, "max_reward": 0.5}}],
        "callback": [
            {
                "stable_baselines3.common.callbacks.CheckpointCallback": {
                    "save_freq": 32,
                    "save_path": str(tmp_path / "saved"),
                }
            }
        ],
    }
    path.write_text(yaml.safe_dump({COURSE_CHANGE: entry}))
    config = load_agent_config("ppo", COURSE_CHANGE, path)
    assert config.hyperparameters["policy_kwargs"] == {"net_arch": [8], "activation_fn": nn.ReLU}
    assert config.normalize == {"norm_obs": False, "norm_reward": True, "gamma": 0.98}
    assert config.hyperparameters["learning_rate"](0.5) == pytest.approx(0.0005)
    env = make_training_env(config)
    assert env.norm_reward and not env.norm_obs and env.gamma == 0.98
    assert all(isinstance(sub_env, ClipReward) for sub_env in env.venv.venv.vector_env.envs)
    env.close()
    argv = ["train", "--algo", "ppo", "--steps", "128", "--config", str(path), "--out", str(tmp_path / "run")]
    assert main([*argv, "--no-progress"]) == 0
    assert sorted(path.name for path in (tmp_path / "saved").iterdir()) == [
        "rl_model_128_steps.zip",
        "rl_model_64_steps.zip",
    ]


def test_train_command_writes_model_and_metadata(tmp_path, capsys):
    config = tmp_path / "ppo.yaml"
    entry = {
        "n_envs": 4,
        "n_timesteps": 10_000,
        "env_kwargs": {"disturbance": "wind_current", "rudder_travel_weight": 0.5},
        "n_steps": 64,
        "batch_size": 128,
        "n_epochs": 1,
        "policy_kwargs": {"net_arch": [16, 16]},
    }
    config.write_text(yaml.safe_dump({COURSE_CHANGE: entry}))
    out = tmp_path / "run"
    argv = ["train", "--algo", "ppo", "--steps", "300", "--seed", "3", "--config", str(config), "--out", str(out)]
    assert main([*argv, "--no-progress"]) == 0
    printed = capsys.readouterr().out
    assert "ppo on ship_env/CourseChange-v0, seed 3: 512 steps" in printed  # two rollouts of 4 x 64
    metadata = json.loads((out / "metadata.json").read_text())
    assert metadata["env_id"] == COURSE_CHANGE and metadata["algo"] == "ppo"
    assert metadata["env_kwargs"] == entry["env_kwargs"]
    assert metadata["config"]["n_steps"] == 64 and metadata["config"]["n_envs"] == 4
    assert (metadata["seed"], metadata["steps"], metadata["timesteps"], metadata["torch_threads"]) == (3, 300, 512, 1)
    assert (
        isinstance(metadata["wall_time_s"], float) and metadata["wall_time_s"] >= 0.0
    )  # measured, not asserted on: a fast machine may round it to 0
    assert metadata["versions"]["ship-env"] == ship_env.__version__
    assert {"stable-baselines3", "torch", "numpy", "gymnasium", "python"} <= set(metadata["versions"])
    assert metadata["machine"] == machine_description() and metadata["machine"]["torch_cpu_capability"]
    assert shlex.split(metadata["command"]) == [
        "ship-env",
        "train",
        "--algo",
        "ppo",
        "--env",
        COURSE_CHANGE,
        "--seed",
        "3",
        "--steps",
        "300",
        "--config",
        str(config),
        "--out",
        str(out),
    ]
    model = PPO.load(out / "model.zip", device="cpu")
    assert model.n_envs == 4 and model.num_timesteps == 512
    assert read_policy_file(out).env_id == COURSE_CHANGE


def test_sac_trains_with_its_config(tmp_path):
    config = tmp_path / "sac.yaml"
    entry = {"n_envs": 2, "learning_starts": 50, "batch_size": 32, "policy_kwargs": {"net_arch": [16, 16]}}
    config.write_text(yaml.safe_dump({COURSE_CHANGE: entry}))
    argv = ["train", "--algo", "sac", "--steps", "100", "--config", str(config), "--out", str(tmp_path / "sac")]
    assert main([*argv, "--no-progress"]) == 0
    assert read_policy_file(tmp_path / "sac").algo == "SAC"


def test_train_command_rejects_an_environment_without_a_config_entry(tmp_path, capsys):
    with pytest.raises(SystemExit) as raised:
        main(["train", "--algo", "ppo", "--env", "ship_env/CourseKeeping-v0", "--out", str(tmp_path)])
    assert raised.value.code == 2
    err = capsys.readouterr().err
    assert "no entry for 'ship_env/CourseKeeping-v0'" in err and "ppo.yaml" in err


@pytest.mark.slow
@pytest.mark.parametrize(
    ("env_id", "entrant"), [(COURSE_CHANGE, "ppo"), (TRACK_FOLLOW, "ppo"), (COURSE_CHANGE, "ppo_esso_osaka_model")]
)
def test_the_shipped_policys_command_reproduces_it(tmp_path, monkeypatch, env_id, entrant):
    """Same command, seed, thread count, package versions and kind of machine: the same weights, bit
    for bit (the shipped entrant's last training seed). A run recorded on another machine is skipped,
    naming both, and so is a run that does not name its machine: its weights depend on the machine, so
    none can be expected to give them. The shipped TrackFollow seed and the Esso Osaka model's
    CourseChange seed (trained on its fitted draws) name the machine kind that gave their weights; the
    container ship's CourseChange seeds were recorded before runs named their machine (their weights
    came back on one machine kind and not on another). The command is run where it was, from the repository's
    root (its paths are the repository's), wherever the tests are run from."""
    import torch
    from stable_baselines3.common.save_util import load_from_zip_file

    from ship_env.rl.metadata import PolicyMetadata
    from ship_env.rl.policy_file import seed_models
    from ship_env.rl.shipped import shipped_folder

    model = seed_models(shipped_folder(env_id, entrant))[-1]
    metadata = PolicyMetadata.read(model.parent / "metadata.json")
    here = machine_description()
    if metadata.machine is None:
        pytest.skip(f"{model.parent}/metadata.json does not name the machine it was trained on")
    if metadata.machine != here:
        pytest.skip(f"trained on {metadata.machine}; this machine is {here}")
    words = shlex.split(metadata.command)
    out_index = words.index("--out") + 1
    words[out_index] = str(tmp_path / "run")
    monkeypatch.chdir(Path(__file__).parents[1])
    assert main([*words[1:], "--no-progress"]) == 0
    _, shipped, _ = load_from_zip_file(model, device="cpu", load_data=False)
    _, again, _ = load_from_zip_file(tmp_path / "run" / "model.zip", device="cpu", load_data=False)
    assert shipped["policy"].keys() == again["policy"].keys()
    assert all(torch.equal(shipped["policy"][key], again["policy"][key]) for key in shipped["policy"])


def test_recurrent_ppo_trains_and_its_policy_steers_with_its_memory(tmp_path):
    """``--algo ppo_lstm`` (sb3-contrib's RecurrentPPO, rl-zoo3's name) trains with an agent config,
    and the policy file rebuilds the LSTM policy the leaderboard's controller steers with, carrying
    its hidden state from step to step and restarting it with each episode."""
    import gymnasium as gym
    import numpy as np

    from ship_env.baselines.controller import SB3Controller
    from ship_env.rl.features import ScaledObservationLstmPolicy

    config = tmp_path / "ppo_lstm.yaml"
    entry = {
        "n_envs": 2,
        "policy": "ship_env.rl.features.ScaledObservationLstmPolicy",
        "env_kwargs": {"ship_variation": True},
        "n_steps": 32,
        "batch_size": 32,
        "n_epochs": 1,
        "policy_kwargs": {
            "lstm_hidden_size": 8,
            "net_arch": [8],
            "features_extractor_kwargs": {"scales": [50, 5, 1, 1, 1]},
        },
    }
    config.write_text(yaml.safe_dump({COURSE_CHANGE: entry}))
    out = tmp_path / "lstm"
    argv = ["train", "--algo", "ppo_lstm", "--steps", "64", "--config", str(config), "--out", str(out)]
    assert main([*argv, "--no-progress"]) == 0
    policy_file = read_policy_file(out)
    assert policy_file.algo == "PPO_LSTM" and policy_file.metadata.env_kwargs == {"ship_variation": True}
    policy = policy_file.policy()
    assert isinstance(policy, ScaledObservationLstmPolicy)
    controller = SB3Controller(policy)
    env = gym.make(COURSE_CHANGE)
    actions = []
    for _ in range(2):
        observation, info = env.reset(seed=4)
        controller.reset(observation, info)
        episode = []
        for _ in range(5):
            action = controller.act(observation, info)
            episode.append(action)
            observation, _, _, _, info = env.step(action)
        actions.append(np.concatenate(episode))
    np.testing.assert_array_equal(actions[0], actions[1])  # the memory restarts with the episode
    hidden, _ = controller._hidden_state  # the policy LSTM's (hidden, cell) after the last step
    assert hidden.shape == (1, 1, 8) and np.any(hidden != 0.0)
