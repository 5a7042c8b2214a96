"""``ship-env train --seeds``: a run per seed, each repeated by its own command, the same on Ray, none overwritten;
``--trained-agent``: a run that continues a saved agent."""

from __future__ import annotations

import hashlib
import json
import re
import shlex

import numpy as np
import pytest
import torch
import yaml
from stable_baselines3.common.save_util import load_from_zip_file

from ship_env.cli import main
from ship_env.rl.features import MirroredObservationPolicy, ScaledObservationPolicy
from ship_env.rl.policy_file import read_policy_file
from ship_env.rl.seeds import parse_seeds

COURSE_CHANGE = "ship_env/CourseChange-v0"
#: A config small enough for a run of two 128-step rollouts in about a second.
TINY_ENTRY = {"n_envs": 2, "n_steps": 64, "batch_size": 64, "n_epochs": 1, "policy_kwargs": "dict(net_arch=[16])"}


@pytest.fixture
def tiny_config(tmp_path):
    path = tmp_path / "ppo.yaml"
    path.write_text(yaml.safe_dump({COURSE_CHANGE: TINY_ENTRY}))
    return path


def _train(config, out, *more):
    argv = ["train", "--algo", "ppo", "--steps", "256", "--config", str(config), "--out", str(out), *more]
    return main([*argv, "--no-progress"])


def _weights(folder):
    _, parameters, _ = load_from_zip_file(folder / "model.zip", device="cpu", load_data=False)
    return parameters["policy"]


def _same_weights(one, other):
    first, second = _weights(one), _weights(other)
    return first.keys() == second.keys() and all(torch.equal(first[key], second[key]) for key in first)


@pytest.mark.parametrize(
    "text, seeds", [("0-4", (0, 1, 2, 3, 4)), ("0,2,5", (0, 2, 5)), ("0-2,7", (0, 1, 2, 7)), ("3", (3,))]
)
def test_seed_lists_and_ranges(text, seeds):
    assert parse_seeds(text) == seeds


@pytest.mark.parametrize(
    "text, message",
    [
        ("4-0", "expected an ascending seed range such as 0-4, got '4-0'"),
        ("0-x", "got '0-x'"),
        ("-1", "got '-1'"),
        ("0,1,1", "seed 1 is listed twice in '0,1,1'"),
        ("", "got ''"),
    ],
)
def test_a_seed_list_that_does_not_parse_is_named(text, message, capsys):
    with pytest.raises(ValueError, match=message):
        parse_seeds(text)
    with pytest.raises(SystemExit) as raised:
        main(["train", "--algo", "ppo", "--seeds", text])
    assert raised.value.code == 2
    err = capsys.readouterr().err
    assert "argument --seeds: " in err and message in err


def test_each_seed_gets_a_folder_and_the_command_that_repeats_it(tmp_path, tiny_config, capsys):
    """Seeds trained one after another in one process are the runs their own commands make alone."""
    assert _train(tiny_config, tmp_path / "runs", "--seeds", "1,3") == 0
    assert "2 seeds in" in capsys.readouterr().out
    assert sorted(path.name for path in (tmp_path / "runs").iterdir()) == ["seed1", "seed3"]
    metadata = json.loads((tmp_path / "runs" / "seed3" / "metadata.json").read_text())
    assert metadata["seed"] == 3
    words = shlex.split(metadata["command"])
    assert words[words.index("--seed") + 1] == "3" and words[words.index("--out") + 1] == str(tmp_path / "runs/seed3")
    words[words.index("--out") + 1] = str(tmp_path / "again")
    assert main([*words[1:], "--no-progress"]) == 0
    assert _same_weights(tmp_path / "runs" / "seed3", tmp_path / "again")
    assert not _same_weights(tmp_path / "runs" / "seed3", tmp_path / "runs" / "seed1")


def test_nothing_trained_is_overwritten_without_force(tmp_path, tiny_config, capsys):
    assert _train(tiny_config, tmp_path / "run", "--seed", "1") == 0
    before = (tmp_path / "run" / "model.zip").read_bytes()
    with pytest.raises(SystemExit) as raised:
        _train(tiny_config, tmp_path / "run", "--seed", "2")
    assert raised.value.code == 2
    assert f"not overwritten without --force: {tmp_path / 'run'}" in capsys.readouterr().err
    assert (tmp_path / "run" / "model.zip").read_bytes() == before
    assert json.loads((tmp_path / "run" / "metadata.json").read_text())["seed"] == 1
    assert _train(tiny_config, tmp_path / "run", "--seed", "2", "--force") == 0
    assert json.loads((tmp_path / "run" / "metadata.json").read_text())["seed"] == 2


@pytest.mark.parametrize(
    "more, message",
    [
        (
            ["--backend", "ray", "--ray-address", "127.0.0.1:1"],
            "Ray address '127.0.0.1:1': no Ray cluster answers there",
        ),
        (["--backend", "ray", "--ray-address", "headnode"], "Ray address 'headnode': expected host:port"),
        (["--ray-address", "127.0.0.1:6379"], "'127.0.0.1:6379' needs --backend ray"),
    ],
)
def test_a_ray_address_that_does_not_answer_is_named(tmp_path, tiny_config, capsys, more, message):
    pytest.importorskip("ray", reason="Ray (the dev extra) is not installed")
    with pytest.raises(SystemExit) as raised:
        _train(tiny_config, tmp_path / "runs", "--seeds", "0-1", *more)
    assert raised.value.code == 2
    assert f"argument --ray-address: {message}" in capsys.readouterr().err
    assert not (tmp_path / "runs").exists()


@pytest.mark.slow  # starting Ray takes half a minute
def test_seeds_trained_as_ray_tasks_are_the_seeds_trained_here(tmp_path, tiny_config, capsys):
    ray = pytest.importorskip("ray", reason="Ray (the dev extra) is not installed")
    ray.init(num_cpus=2, include_dashboard=False, log_to_driver=False)
    try:
        assert _train(tiny_config, tmp_path / "ray", "--seeds", "0-1", "--backend", "ray") == 0
    finally:
        ray.shutdown()
    assert "2 seeds in" in capsys.readouterr().out
    assert _train(tiny_config, tmp_path / "here", "--seeds", "0-1") == 0
    for seed in ("seed0", "seed1"):
        assert _same_weights(tmp_path / "ray" / seed, tmp_path / "here" / seed)
        on_ray = json.loads((tmp_path / "ray" / seed / "metadata.json").read_text())
        here = json.loads((tmp_path / "here" / seed / "metadata.json").read_text())
        assert on_ray["command"] == here["command"].replace(str(tmp_path / "here"), str(tmp_path / "ray"))


def _changed_config(tmp_path, name, **changed):
    path = tmp_path / f"{name}.yaml"
    path.write_text(yaml.safe_dump({COURSE_CHANGE: {**TINY_ENTRY, **changed}}))
    return path


def test_a_continued_run_starts_from_the_saved_weights_and_trains_with_the_configs_hyperparameters(
    tmp_path, tiny_config
):
    """``--trained-agent`` (rl-zoo3's option): with the config's learning rate 0 the continued agent
    keeps the saved weights exactly (a new agent of the same seed has others), with 3e-4 it moves
    them; the metadata names the file, its SHA-256 and its command, and the run's own command
    repeats it bit for bit."""
    _train(tiny_config, tmp_path / "start", "--seed", "1")
    frozen = _changed_config(tmp_path, "frozen", learning_rate=0.0)
    assert _train(frozen, tmp_path / "frozen", "--trained-agent", str(tmp_path / "start")) == 0
    assert _same_weights(tmp_path / "frozen", tmp_path / "start")
    assert _train(frozen, tmp_path / "new") == 0
    assert not _same_weights(tmp_path / "new", tmp_path / "start")
    assert _train(tiny_config, tmp_path / "moved", "-i", str(tmp_path / "start" / "model.zip")) == 0
    assert not _same_weights(tmp_path / "moved", tmp_path / "start")

    metadata = json.loads((tmp_path / "moved" / "metadata.json").read_text())
    start = json.loads((tmp_path / "start" / "metadata.json").read_text())
    assert start["trained_agent"] is None
    assert metadata["trained_agent"] == {
        "path": str(tmp_path / "start" / "model.zip"),
        "sha256": hashlib.sha256((tmp_path / "start" / "model.zip").read_bytes()).hexdigest(),
        "command": start["command"],
    }
    words = shlex.split(metadata["command"])
    assert words[words.index("--trained-agent") + 1] == str(tmp_path / "start" / "model.zip")
    words[words.index("--out") + 1] = str(tmp_path / "again")
    assert main([*words[1:], "--no-progress"]) == 0
    assert _same_weights(tmp_path / "moved", tmp_path / "again")


def test_with_seeds_each_seed_continues_its_own_run(tmp_path, tiny_config):
    _train(tiny_config, tmp_path / "start", "--seeds", "0-1")
    frozen = _changed_config(tmp_path, "frozen", learning_rate=0.0)
    assert _train(frozen, tmp_path / "on", "--seeds", "0-1", "--trained-agent", str(tmp_path / "start")) == 0
    for seed in (0, 1):
        assert _same_weights(tmp_path / "on" / f"seed{seed}", tmp_path / "start" / f"seed{seed}")
        metadata = json.loads((tmp_path / "on" / f"seed{seed}" / "metadata.json").read_text())
        assert metadata["trained_agent"]["path"] == str(tmp_path / "start" / f"seed{seed}" / "model.zip")


#: The tiny config's network as ScaledObservationPolicy, and behind the mirror (CourseChange's
#: observation: heading error, rate of turn, rudder, speed, turn direction; all but the speed mirrored).
SCALED = {
    "policy": "ship_env.rl.features.ScaledObservationPolicy",
    "policy_kwargs": "dict(net_arch=[16], features_extractor_kwargs=dict(scales=[50, 5, 1, 1, 1]))",
}
MIRROR = "mirror_sign=4, mirrored=[0, 1, 2, 4]"


def _mirrored_config(tmp_path, name, policy_kwargs=SCALED["policy_kwargs"], **changed):
    mirrored = {
        "policy": "ship_env.rl.features.MirroredObservationPolicy",
        "policy_kwargs": policy_kwargs[:-1] + f", {MIRROR})",
    }
    return _changed_config(tmp_path, name, **mirrored, **changed)


def test_a_continued_run_builds_the_configs_policy_with_the_saved_weights(tmp_path):
    """A config naming another policy class than the saved agent's (the same network behind the
    mirror) continues the agent's weights in it: with learning rate 0 the mirrored policy acts as
    the plain one on turns to starboard and as its mirror image on turns to port."""
    _train(_changed_config(tmp_path, "plain", **SCALED), tmp_path / "start", "--seed", "1")
    frozen = _mirrored_config(tmp_path, "frozen", learning_rate=0.0)
    assert _train(frozen, tmp_path / "mirrored", "--trained-agent", str(tmp_path / "start")) == 0
    plain, mirrored = read_policy_file(tmp_path / "start").policy(), read_policy_file(tmp_path / "mirrored").policy()
    assert type(plain) is ScaledObservationPolicy
    assert isinstance(mirrored, MirroredObservationPolicy)
    metadata = json.loads((tmp_path / "mirrored" / "metadata.json").read_text())
    assert metadata["trained_agent"]["path"] == str(tmp_path / "start" / "model.zip")

    rng = np.random.default_rng(2)
    starboard = rng.uniform(-0.1, 0.1, (32, 5)).astype(np.float32)
    starboard[:, 3], starboard[:, 4] = rng.uniform(0.5, 1.0, 32), 1.0
    port = starboard * np.array([-1, -1, -1, 1, -1], np.float32)  # the mirror images
    actions = plain.predict(starboard, deterministic=True)[0]
    assert np.all(actions != 0.0)
    np.testing.assert_array_equal(mirrored.predict(starboard, deterministic=True)[0], actions)
    np.testing.assert_array_equal(mirrored.predict(port, deterministic=True)[0], -actions)
    assert not np.allclose(plain.predict(port, deterministic=True)[0], -actions)  # the plain one is not symmetric


@pytest.mark.parametrize(
    "policy_kwargs, message",
    [
        (
            "dict(net_arch=[32], features_extractor_kwargs=dict(scales=[50, 5, 1, 1, 1]))",
            r"its ScaledObservationPolicy's weights do not fit the config's MirroredObservationPolicy: "
            r"mlp_extractor\.policy_net\.0\.weight has shape \(16, 5\), not \(32, 5\)",
        ),
        (
            "dict(net_arch=[16], features_extractor_kwargs=dict(scales=[1, 1, 1, 1, 1]))",
            r"its ScaledObservationPolicy's weights do not fit the config's MirroredObservationPolicy: "
            r"features_extractor\.scales \(fixed by policy_kwargs\) holds other values",
        ),
    ],
)
def test_weights_that_do_not_fit_the_configs_policy_are_refused_by_name(tmp_path, capsys, policy_kwargs, message):
    _train(_changed_config(tmp_path, "plain", **SCALED), tmp_path / "start")
    with pytest.raises(SystemExit) as raised:
        _train(_mirrored_config(tmp_path, "other", policy_kwargs), tmp_path / "run", "-i", str(tmp_path / "start"))
    assert raised.value.code == 2
    assert re.search(
        r"argument -i/--trained-agent: policy file .*start/model\.zip: " + message, capsys.readouterr().err
    )
    assert not (tmp_path / "run" / "model.zip").exists()


@pytest.mark.parametrize(
    "start, message",
    [
        ("missing", r"argument -i/--trained-agent: policy file .*missing: no such file"),
        ("sac", r"argument -i/--trained-agent: policy file .*sac/model\.zip: trained with sac, not ppo"),
        ("other_spaces", r"argument -i/--trained-agent: policy file .*other_spaces/model\.zip: its observation space"),
    ],
)
def test_an_agent_that_cannot_continue_is_named_and_nothing_is_written(tmp_path, tiny_config, capsys, start, message):
    if start == "sac":
        sac = tmp_path / "sac.yaml"
        sac.write_text(yaml.safe_dump({COURSE_CHANGE: {"n_envs": 2, "learning_starts": 10, "batch_size": 16}}))
        argv = ["train", "--algo", "sac", "--steps", "20", "--config", str(sac), "--out", str(tmp_path / "sac")]
        main([*argv, "--no-progress"])
    if start == "other_spaces":
        history = _changed_config(tmp_path, "history", env_kwargs={"observation_history": 2})
        _train(history, tmp_path / "other_spaces")
    with pytest.raises(SystemExit) as raised:
        _train(tiny_config, tmp_path / "run", "--trained-agent", str(tmp_path / start))
    assert raised.value.code == 2
    assert re.search(message, capsys.readouterr().err)
    assert not (tmp_path / "run" / "model.zip").exists()
