"""Policy files read without running their code: the shipped ones act as SB3's own load makes them
act; a file whose pickles carry code is refused unless its code is trusted, and then the code runs."""

from __future__ import annotations

import base64
import collections
import json
import pickle
import shutil
import zipfile
from collections.abc import Callable
from pathlib import Path

import gymnasium as gym
import numpy as np
import pytest
from stable_baselines3 import PPO
from torch import nn

import ship_env  # noqa: F401  (registers the environments)
from ship_env.cli import main
from ship_env.envs.task import observation_keywords
from ship_env.rl.metadata import METADATA_FILE, MODEL_FILE
from ship_env.rl.policy_file import PolicyFileError, read_policy_file
from ship_env.rl.shipped import POLICIES_DIR

COURSE_CHANGE_POLICY = POLICIES_DIR / "CourseChange-v0" / "ppo" / "seed0"
SHIPPED = [
    COURSE_CHANGE_POLICY,
    POLICIES_DIR / "CourseChange-v0" / "ppo" / "seed3",
    POLICIES_DIR / "TrackFollow-v0" / "ppo" / "seed0",
    POLICIES_DIR / "TrackFollow-v0" / "ppo" / "nominal_ship" / "seed1",
]


class TouchOnUnpickling:
    """Unpickles to ``Path(marker).touch()``: a file appears if the pickle is run."""

    def __init__(self, marker: Path) -> None:
        self.marker = marker

    def __reduce__(self):
        return (Path.touch, (self.marker,))


def copied_policy(folder: Path, edit_data: Callable[[dict], object], left_out: tuple[str, ...] = ()) -> Path:
    """A copy of the shipped CourseChange run (zip and metadata) with ``edit_data`` applied to its
    ``data`` document and the zip's files ``left_out`` left out."""
    folder.mkdir(parents=True)
    shutil.copy(COURSE_CHANGE_POLICY / METADATA_FILE, folder / METADATA_FILE)
    with (
        zipfile.ZipFile(COURSE_CHANGE_POLICY / MODEL_FILE) as original,
        zipfile.ZipFile(folder / MODEL_FILE, "w") as copy,
    ):
        for name in set(original.namelist()) - set(left_out):
            content = original.read(name)
            if name == "data":
                data = json.loads(content)
                edit_data(data)
                content = json.dumps(data).encode()
            copy.writestr(name, content)
    return folder / MODEL_FILE


def replacing_pickle(entry: str, pickled: bytes) -> Callable[[dict], None]:
    """An edit of ``data``: ``pickled`` in place of ``entry``'s pickle, its readable fields as they were."""

    def edit(data: dict) -> None:
        data[entry][":serialized:"] = base64.b64encode(pickled).decode()

    return edit


@pytest.mark.parametrize("run", SHIPPED, ids=lambda run: str(run.relative_to(POLICIES_DIR)))
def test_a_shipped_policy_read_without_its_code_acts_bit_for_bit_as_sb3_loads_it(run):
    safe, trusted = read_policy_file(run), read_policy_file(run, trust_policy_code=True)
    assert safe.policy_class is trusted.policy_class and safe.policy_kwargs == trusted.policy_kwargs
    for space, expected in (
        (safe.observation_space, trusted.observation_space),
        (safe.action_space, trusted.action_space),
    ):
        assert space.shape == expected.shape and space.dtype == expected.dtype
        np.testing.assert_array_equal(space.low, expected.low)
        np.testing.assert_array_equal(space.high, expected.high)
    env = gym.make(safe.env_id, **observation_keywords(safe.metadata.env_kwargs))
    env.action_space.seed(0)
    env.observation_space.seed(0)
    # episode starts, and random observations over the whole space (saturated actions included)
    observations = np.stack(
        [env.reset(seed=seed)[0] for seed in range(8)] + [env.observation_space.sample() for _ in range(8)]
    )
    safe_actions, _ = safe.policy().predict(observations, deterministic=True)
    trusted_actions, _ = trusted.policy().predict(observations, deterministic=True)
    assert np.array_equal(safe_actions, trusted_actions)
    assert len(np.unique(safe_actions)) > 2  # the observations ask for different rudders


@pytest.mark.parametrize("protocol, called", [(5, r"pathlib\.Path\.touch"), (0, r"__builtin__\.getattr")])
def test_a_pickled_payload_is_refused_and_never_run_unless_its_code_is_trusted(tmp_path, protocol, called):
    """Pickle protocol 5 (SB3's) refers to the method by its qualified name; protocol 0 fetches it with getattr."""
    marker = tmp_path / "payload-ran"
    payload = pickle.dumps(TouchOnUnpickling(marker), protocol=protocol)
    path = copied_policy(tmp_path / "payload", replacing_pickle("observation_space", payload))
    pattern = (
        rf"payload/model\.zip: cannot be read without running code.*observation_space: its pickle refers to {called}"
    )
    with pytest.raises(PolicyFileError, match=pattern) as refused:
        read_policy_file(path)
    assert "--trust-policy-code" in str(refused.value) and "runs any code" in str(refused.value)
    assert not marker.exists()

    with pytest.raises(PolicyFileError, match=r"its observation_space is None, not a gymnasium space"):
        read_policy_file(path, trust_policy_code=True)
    assert marker.exists()  # trusting the file ran its code, as the option says


def test_the_leaderboard_refuses_a_payload_without_running_it_unless_trusted(tmp_path, capsys):
    marker, out = tmp_path / "payload-ran", tmp_path / "out"
    path = copied_policy(
        tmp_path / "payload", replacing_pickle("observation_space", pickle.dumps(TouchOnUnpickling(marker)))
    )
    with pytest.raises(SystemExit) as raised:
        main(["leaderboard", "--policies", str(path.parent), "--no-tracks", "--out", str(out)])
    assert raised.value.code == 2
    err = capsys.readouterr().err
    assert "argument --policies: policy file" in err and "pathlib.Path.touch" in err and "--trust-policy-code" in err
    assert not marker.exists() and not out.exists()

    with pytest.raises(SystemExit):
        main(["leaderboard", "--policies", str(path.parent), "--trust-policy-code", "--no-tracks", "--out", str(out)])
    assert marker.exists() and "its observation_space is None" in capsys.readouterr().err


def test_the_trust_option_is_documented_as_running_the_files_code(capsys):
    with pytest.raises(SystemExit):
        main(["leaderboard", "--help"])
    help_text = " ".join(capsys.readouterr().out.split())
    assert (
        "--trust-policy-code read the --policies files with stable-baselines3's unpickling, which RUNS ANY CODE"
        in help_text
    )


def test_a_policy_class_outside_the_allow_list_is_named(tmp_path):
    path = copied_policy(
        tmp_path / "other_class", replacing_pickle("policy_class", pickle.dumps(collections.OrderedDict))
    )
    with pytest.raises(
        PolicyFileError, match=r"policy_class: the class collections\.OrderedDict is not among the allowed"
    ):
        read_policy_file(path)


def test_a_policy_class_pickled_with_a_call_is_refused(tmp_path):
    marker = tmp_path / "payload-ran"
    path = copied_policy(tmp_path / "call", replacing_pickle("policy_class", pickle.dumps(TouchOnUnpickling(marker))))
    with pytest.raises(PolicyFileError, match=r"policy_class: its pickle is not one reference to a class .*REDUCE"):
        read_policy_file(path)
    assert not marker.exists()


def test_a_class_in_the_policy_keywords_is_read_from_its_printed_name(tmp_path):
    folder = tmp_path / "relu"
    folder.mkdir()
    env = gym.make("ship_env/CourseChange-v0")
    PPO("MlpPolicy", env, n_steps=64, device="cpu", policy_kwargs={"net_arch": [8], "activation_fn": nn.ReLU}).save(
        folder / MODEL_FILE
    )
    safe, trusted = read_policy_file(folder), read_policy_file(folder, trust_policy_code=True)
    assert safe.policy_kwargs == {"net_arch": [8], "activation_fn": nn.ReLU} == trusted.policy_kwargs
    observations = np.stack([env.observation_space.sample() for _ in range(8)])
    safe_actions, _ = safe.policy().predict(observations, deterministic=True)
    assert np.array_equal(safe_actions, trusted.policy().predict(observations, deterministic=True)[0])


def test_a_keyword_class_outside_the_allow_list_is_named(tmp_path):
    folder = tmp_path / "hardtanh"
    folder.mkdir()
    PPO(
        "MlpPolicy",
        gym.make("ship_env/CourseChange-v0"),
        n_steps=64,
        device="cpu",
        policy_kwargs={"activation_fn": nn.Hardtanh},
    ).save(folder / MODEL_FILE)
    with pytest.raises(
        PolicyFileError, match=r"policy_kwargs: its pickle refers to torch\.nn\.modules\.activation\.Hardtanh"
    ):
        read_policy_file(folder)
    assert read_policy_file(folder, trust_policy_code=True).policy_kwargs == {"activation_fn": nn.Hardtanh}


@pytest.mark.parametrize(
    "edit_data, left_out, named",
    [
        (lambda data: data["observation_space"].pop("low"), (), r"observation_space: no readable 'low' field.*--trust"),
        (
            lambda data: data["action_space"].update({":type:": "<class 'gymnasium.spaces.dict.Dict'>"}),
            (),
            r"action_space: a <class 'gymnasium\.spaces\.dict\.Dict'> is not read without its code.*--trust",
        ),
        (lambda data: data.pop("policy_class"), (), r"data: no policy_class.*--trust"),
        (lambda data: None, ("policy.pth",), r"not a stable-baselines3 model: no policy\.pth"),
    ],
    ids=["field", "space", "entry", "weights"],
)
def test_what_the_safe_reading_lacks_is_named(tmp_path, edit_data, left_out, named):
    path = copied_policy(tmp_path / "lacking", edit_data, left_out)
    with pytest.raises(PolicyFileError, match=rf"lacking/model\.zip: .*{named}"):
        read_policy_file(path)
