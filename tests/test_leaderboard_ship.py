"""The leaderboard and training on any ship: ``--ship`` with a preset file, the autopilots designed from its
values, the ship named in every table, learned entrants trained on another ship labelled, bad input refused."""

from __future__ import annotations

import csv
import dataclasses
import json
import shlex
from pathlib import Path

import gymnasium as gym
import numpy as np
import pytest
import yaml

from ship_env.baselines.nomoto import NomotoParameters
from ship_env.baselines.pd_autopilot import PDAutopilot, pd_gains
from ship_env.baselines.presys import NATURAL_FREQUENCY
from ship_env.cli import main
from ship_env.envs.variation import FITTED
from ship_env.leaderboard.board import CSV_FILE, EPISODES_FILE, run_leaderboard, write_leaderboard
from ship_env.leaderboard.entrants import DesignedTask, Entrant, policy_entrants
from ship_env.leaderboard.sailing import ship_task, suite_envs
from ship_env.leaderboard.suites import COURSE_CHANGE, DEFAULT_SHIP, HALF_SPEED, NOMINAL, SuiteSpec
from ship_env.model import ShipModel
from ship_env.paths import config_dir
from ship_env.rl.policy_file import read_policy_file

#: One 30-deg course change each way in calm water on the nominal ship.
TINY = SuiteSpec(course_changes_deg=(30.0,), tracks=(), conditions=(NOMINAL,), course_change_disturbances=("calm",))
SHIP_NAME = "tanker_from_file"


@pytest.fixture
def ship_file(tmp_path: Path) -> Path:
    """A ship YAML outside the presets: the kvlcc2 preset under another name."""
    document = yaml.safe_load((config_dir() / "ships" / "kvlcc2.yaml").read_text())
    document["name"] = SHIP_NAME
    path = tmp_path / "tanker.yaml"
    path.write_text(yaml.safe_dump(document, sort_keys=False))
    return path


def _fixed_pd(ship: str | None) -> PDAutopilot:
    """The fixed-gain PD the leaderboard designs for TINY's suite on ``ship``."""
    (suite,) = dataclasses.replace(TINY, ship=ship).suites()
    entrant = Entrant("PD, fixed gains", COURSE_CHANGE)
    env, design_model = suite_envs(suite, entrant)
    autopilot = entrant.build(DesignedTask(ship_task(env), design_model)).autopilot
    env.close()
    assert isinstance(autopilot, PDAutopilot)
    return autopilot


def test_the_autopilots_are_designed_from_the_given_ships_values(ship_file):
    """K_p = omega_n^2 (tau*/K*) (L/u)^2 (5.79) with the file's K*, tau*, L and u, not the container ship's."""
    sailed, container = _fixed_pd(str(ship_file)), _fixed_pd(None)
    tanker = ShipModel(ship_file)
    assert sailed.ship == NomotoParameters(tanker.parameter("yaw.gain"), tanker.parameter("yaw.time_constant"))
    assert (
        (sailed.length, sailed.design.design_speed)
        == (tanker.length, tanker.service_speed)
        == (320.0, pytest.approx(15.5 * 1852 / 3600))
    )
    gains, container_gains = (
        pd_gains(NATURAL_FREQUENCY, 1.0, autopilot.ship, autopilot.length, autopilot.design.design_speed)
        for autopilot in (sailed, container)
    )
    ratio = (
        tanker.parameter("yaw.time_constant") / tanker.parameter("yaw.gain") * (320.0 / tanker.service_speed) ** 2
    ) / (container.ship.time_constant / container.ship.gain * (container.length / container.design.design_speed) ** 2)
    assert gains.proportional / container_gains.proportional == pytest.approx(ratio, rel=1e-12)
    assert ratio > 2.0  # a longer, slower ship: its gains are not the container ship's


def test_half_speed_is_half_the_given_ships_speed(ship_file):
    """The robustness conditions scale the given ship: at half speed the file's ship sails at half its
    own service speed (15.5 kn), its autopilots designed for the full one."""
    (suite,) = dataclasses.replace(TINY, ship=str(ship_file), conditions=(HALF_SPEED,)).suites()
    env, design_model = suite_envs(suite, Entrant("PD, fixed gains", COURSE_CHANGE))
    env.reset(seed=0, options={"course_change_deg": 30.0})
    for _ in range(100):
        _, _, _, _, info = env.step(np.zeros(1, dtype=np.float32))
    env.close()
    service_speed = 15.5 * 1852 / 3600
    assert design_model.service_speed == pytest.approx(service_speed)
    assert info["measurement"]["speed"] == pytest.approx(0.5 * service_speed, rel=0.05)


def test_the_leaderboard_on_a_ship_file_names_it_everywhere(ship_file, tmp_path):
    board = run_leaderboard(dataclasses.replace(TINY, ship=str(ship_file)), shipped=False, progress=False)
    assert board.ship_name == SHIP_NAME
    assert {suite.env_kwargs["ship"] for suite in board.suites} == {str(ship_file)}
    text = board.markdown()
    assert f"### Headline: CourseChange, nominal ship, all seas together ({SHIP_NAME})" in text
    assert f"### CourseChange calm | nominal on {SHIP_NAME}" in text
    write_leaderboard(board, tmp_path / "out", plots=False)
    for name in (CSV_FILE, EPISODES_FILE):
        with (tmp_path / "out" / name).open() as handle:
            assert {row["ship"] for row in csv.DictReader(handle)} == {SHIP_NAME}


def test_the_shipped_policy_sailing_another_ship_is_named_as_trained_on_its_own(ship_file):
    env = gym.make(COURSE_CHANGE)
    spaces = {COURSE_CHANGE: (env.observation_space, env.action_space)}
    env.close()
    (on_the_container_ship,) = policy_entrants([], spaces)
    (on_the_file,) = policy_entrants([], spaces, ship=str(ship_file))
    assert on_the_container_ship.name == "PPO (shipped)"
    assert on_the_file.name == f"PPO (shipped, trained on {DEFAULT_SHIP})"


def test_a_policy_shipped_for_one_ship_sails_that_ships_board_only(ship_file):
    """The PPO shipped for the identified Esso Osaka model, trained on ships drawn from its fit, sails
    its board beside the container ship's (zero-shot), once; on the container ship's board and on a
    third ship's it is left out."""
    env = gym.make(COURSE_CHANGE)
    spaces = {COURSE_CHANGE: (env.observation_space, env.action_space)}
    env.close()
    on_esso = policy_entrants([], spaces, ship="esso_osaka_model")
    assert sorted(entrant.name for entrant in on_esso) == ["PPO (shipped)", f"PPO (shipped, trained on {DEFAULT_SHIP})"]
    trained_on_esso = next(entrant for entrant in on_esso if entrant.name == "PPO (shipped)")
    assert all("ppo_esso_osaka_model" in str(path) for path in trained_on_esso.policies)
    for path in trained_on_esso.policies:
        metadata = read_policy_file(path).metadata
        assert metadata is not None, path
        assert (metadata.env_kwargs["ship"], metadata.env_kwargs["ship_variation"]) == ("esso_osaka_model", FITTED)
    for board_ship in (DEFAULT_SHIP, str(ship_file)):
        assert all(
            "ppo_esso_osaka_model" not in str(path)
            for e in policy_entrants([], spaces, ship=board_ship)
            for path in e.policies
        )


@pytest.mark.parametrize(
    ("arguments", "message"),
    [
        (["--ship", "nowhere.yaml"], "nowhere.yaml: no such ship file"),
        (["--ship", "no_such_preset"], "unknown preset 'no_such_preset'"),
        (["--ship", "kvlcc2", "--suite", "unseen"], "the unseen suite sails its own ship"),
    ],
)
def test_bad_ships_are_refused_by_name(tmp_path, capsys, arguments, message):
    with pytest.raises(SystemExit) as raised:
        main(["leaderboard", *arguments, "--no-plots", "--out", str(tmp_path / "out")])
    assert raised.value.code == 2
    assert message in capsys.readouterr().err
    assert not (tmp_path / "out").exists()


def test_a_ship_without_a_design_value_is_refused_naming_the_file_and_field(ship_file, tmp_path, capsys):
    document = yaml.safe_load(ship_file.read_text())
    del document["effects"]["yaw"]["gain"]
    lacking = tmp_path / "lacking.yaml"
    lacking.write_text(yaml.safe_dump(document))
    with pytest.raises(SystemExit):
        main(["leaderboard", "--ship", str(lacking), "--no-plots", "--out", str(tmp_path / "out")])
    error = capsys.readouterr().err
    assert "argument --ship" in error and "lacking.yaml" in error and "'gain'" in error


def test_train_on_a_ship_file_records_it_and_the_leaderboard_labels_the_policy(ship_file, tmp_path):
    config = tmp_path / "ppo.yaml"
    entry = {"n_envs": 2, "n_steps": 32, "batch_size": 64, "n_epochs": 1, "policy_kwargs": {"net_arch": [8]}}
    config.write_text(yaml.safe_dump({COURSE_CHANGE: entry}))
    out = tmp_path / "run"
    argv = ["train", "--algo", "ppo", "--steps", "64", "--config", str(config), "--ship", str(ship_file)]
    assert main([*argv, "--out", str(out), "--no-progress"]) == 0
    metadata = json.loads((out / "metadata.json").read_text())
    assert metadata["env_kwargs"]["ship"] == str(ship_file)
    assert shlex.split(metadata["command"])[8:10] == ["--ship", str(ship_file)]

    env = gym.make(COURSE_CHANGE)
    spaces = {COURSE_CHANGE: (env.observation_space, env.action_space)}
    env.close()
    (on_its_ship,) = policy_entrants([out], spaces, shipped=False, ship=str(ship_file))
    (elsewhere,) = policy_entrants([out], spaces, shipped=False)
    assert on_its_ship.name == f"PPO ({out})"
    assert elsewhere.name == f"PPO ({out}, trained on {SHIP_NAME})"
