"""The leaderboard's fitted-uncertainty suites: on fitted presets only, other ships for dev and test, the same each
time, and a board that ranks on them."""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path

import pytest
import yaml
from fitted_presets import fitted_preset

from ship_env.cli import main
from ship_env.envs.variation import ShipFactors
from ship_env.leaderboard.board import run_leaderboard
from ship_env.leaderboard.entrants import Entrant
from ship_env.leaderboard.sailing import ship_task, suite_envs
from ship_env.leaderboard.suites import (
    CONDITIONS,
    COURSE_CHANGE,
    FITTED_UNCERTAINTY,
    NOMINAL,
    SUITE_SPECS,
    Suite,
    SuiteSpec,
    sails_condition,
)
from ship_env.model import ShipModel

#: One 30-deg course change each way in calm water.
TINY = SuiteSpec(course_changes_deg=(30.0,), tracks=(), conditions=(NOMINAL,), course_change_disturbances=("calm",))


@pytest.fixture
def ship_file(tmp_path: Path) -> Path:
    """kvlcc2 with K* +- 15 %, tau* +- 20 % (about its values 1.9 and 2.4)."""
    return fitted_preset(tmp_path, {"yaw.gain": 0.3, "yaw.time_constant": 0.5})


def _fitted_suite(spec_name: str, ship: Path) -> Suite:
    spec = dataclasses.replace(SUITE_SPECS[spec_name], ship=str(ship), tracks=(), course_change_disturbances=("calm",))
    (suite,) = [suite for suite in spec.suites() if suite.condition == FITTED_UNCERTAINTY]
    return suite


def _ships(suite: Suite) -> list[ShipFactors]:
    """The ship each episode of ``suite`` sails, as the leaderboard makes and resets its environment."""
    env, _ = suite_envs(suite, Entrant("PD, fixed gains", COURSE_CHANGE))
    ships = []
    for episode in suite.episodes:
        _, info = env.reset(seed=episode.seed, options=dict(episode.options))
        ships.append(info["scenario"].ship)
        assert info["scenario"].conditions.yaw_gain_factor == ships[-1].yaw_gain
    assert ship_task(env).variation is not None
    env.close()
    return ships


def test_the_suite_exists_on_fitted_presets_only(ship_file):
    assert FITTED_UNCERTAINTY in CONDITIONS
    plain = [suite.condition for suite in SUITE_SPECS["dev"].suites()]
    assert FITTED_UNCERTAINTY not in plain and len(plain) == 4 * (len(CONDITIONS) - 1)
    fitted = [suite for suite in dataclasses.replace(SUITE_SPECS["dev"], ship=str(ship_file)).suites()]
    assert len(fitted) == 4 * len(CONDITIONS)
    assert sorted(s.task for s in fitted if s.condition == FITTED_UNCERTAINTY) == [
        "CourseChange calm",
        "CourseChange wind_current",
        "CourseChange wind_current_waves",
        "TrackFollow",
    ]


def test_dev_and_test_sail_other_ships_the_same_ones_every_time(ship_file):
    dev = _ships(_fitted_suite("dev", ship_file))
    test = _ships(_fitted_suite("test", ship_file))
    assert len(dev) == 10 and len(test) == 12
    assert not set(dev) & set(test)
    assert len(set(dev)) == len(dev)  # a ship per episode
    assert _ships(_fitted_suite("dev", ship_file)) == dev
    # Ships around the fitted one: K* within 4 standard errors (the draws are the fit's, not x0.5-x2).
    gains = [ship.yaw_gain for ship in dev + test]
    spread = 0.3 / ShipModel(ship_file).parameter("yaw.gain")
    assert max(abs(g - 1.0) for g in gains) < 4 * spread and min(gains) != max(gains)
    assert {ship.speed for ship in dev + test} == {1.0}


def test_a_quick_board_ranks_on_the_fitted_ships(ship_file):
    spec = dataclasses.replace(TINY, ship=str(ship_file), conditions=(NOMINAL, FITTED_UNCERTAINTY))
    board = run_leaderboard(spec, shipped=False, progress=False)
    table = board.table("CourseChange calm | fitted uncertainty")
    nominal = board.table("CourseChange calm | nominal")
    assert len(table.standings) == len(nominal.standings) >= 3
    assert "### CourseChange calm | fitted uncertainty on fitted" in board.markdown()
    # Other ships than the nominal one: the episodes' figures differ.
    assert all(row.values != nominal.standing(row.entrant).values for row in table.standings)


def test_the_command_refuses_the_condition_on_a_ship_without_standard_errors(tmp_path, capsys):
    with pytest.raises(SystemExit):
        main(["leaderboard", "--conditions", "fitted-uncertainty", "--no-plots", "--out", str(tmp_path / "out")])
    error = capsys.readouterr().err
    assert "argument --conditions: fitted-uncertainty" in error and "container_226m gives none" in error


def test_train_on_the_fitted_ships_records_the_option_and_refuses_a_ship_without_errors(ship_file, tmp_path, capsys):
    config = tmp_path / "ppo.yaml"
    entry = {"n_envs": 2, "n_steps": 64, "batch_size": 64, "n_epochs": 1, "policy_kwargs": {"net_arch": [8]}}
    config.write_text(yaml.safe_dump({COURSE_CHANGE: {**entry, "env_kwargs": {"ship_variation": True}}}))
    out = tmp_path / "run"
    argv = ["train", "--algo", "ppo", "--steps", "256", "--config", str(config), "--no-progress"]
    assert main([*argv, "--ship", str(ship_file), "--ship-variation", "fitted", "--out", str(out)]) == 0
    metadata = json.loads((out / "metadata.json").read_text())
    assert metadata["env_kwargs"]["ship_variation"] == "fitted"
    assert "--ship-variation fitted" in metadata["command"]
    with pytest.raises(SystemExit):
        main([*argv, "--ship-variation", "fitted", "--out", str(tmp_path / "refused")])
    error = capsys.readouterr().err
    assert "argument --ship-variation: fitted" in error and "(the environment's own, container_226m)" in error


def test_the_command_refuses_the_condition_where_the_fit_does_not_determine_a_term(tmp_path, capsys):
    """tau* +- 1.4 times its value (as the Esso zig-zag ladder's preset has it): the draws would include ships
    without yaw inertia, on which every controller leaves the model's validity; asked for, the condition is
    refused naming the term, and it is not among a fitted preset's suites."""
    loose = fitted_preset(tmp_path, {"yaw.gain": 0.3, "yaw.time_constant": 1.4 * 2.582})
    assert not sails_condition(FITTED_UNCERTAINTY, str(loose))
    with pytest.raises(SystemExit):
        main(["leaderboard", "--ship", str(loose), "--conditions", "fitted-uncertainty", "--no-plots",
              "--out", str(tmp_path / "out")])  # fmt: skip
    error = capsys.readouterr().err
    assert "argument --conditions: fitted-uncertainty" in error
    assert "does not determine yaw.time_constant 2.582 +- 3.6" in error
