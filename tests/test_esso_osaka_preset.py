"""The shipped ``esso_osaka_model`` preset: identified from the Esso Osaka runs, sailed by the tasks.

Without data: the preset loads, every identified number carries its standard error and a source naming
the runs it was fitted to (file names and SHA-256), and the fixed PD autopilot designed from its K*,
tau* completes a 45 deg course change at a 0.37 s step. With the runs at ``../shared/data/esso_osaka``
(slow): the preset replays the runs of another kind (the berthing runs inside its envelope) with the
errors its ``fitted.validation`` states, and its effects refitted leaving one run out keep the
held-out errors of ``fitted.held_out``, each within twice the jackknife standard error of the pooled
RMS over the runs (what one run more or less moves it by).
"""

from __future__ import annotations

import math
import shlex
import warnings
from collections.abc import Sequence
from pathlib import Path

import gymnasium as gym
import numpy as np
import pytest

import ship_env  # noqa: F401  (registers the environments)
from ship_env.baselines.presys import pd_controller
from ship_env.leaderboard.sailing import sail
from ship_env.leaderboard.suites import Episode
from ship_env.model import ShipModel, load_ship
from ship_env.workbench import FitOptions, LogWarning, compare, cross_validate, load_logs
from ship_env.workbench.fitting.errors import ErrorScales, RunErrors, pooled
from ship_env.workbench.fitting.runs import prepare_runs
from ship_env.workbench.fitting.terms import CURRENT_TERMS
from ship_env.workbench.logs.logs import every_nth
from ship_env.workbench.reporting.presets import log_file, preset_replay_model

SHIP = "esso_osaka_model"
ROOT = Path(__file__).resolve().parents[1]
DATA = ROOT.parent / "shared" / "data" / "esso_osaka"
NEEDS_DATA = pytest.mark.skipif(
    not DATA.is_dir(), reason=f"the Esso Osaka data is not at {DATA} (../shared/data/esso_osaka beside the repository)"
)
#: The step the tasks take on a 3 m model at 0.35 m/s (about L / U / 23), s.
MODEL_STEP = 0.37
#: Jackknife standard errors a recomputed pooled error may lie above the figure the preset states.
SIGMAS = 2.0


def test_every_identified_value_carries_its_standard_error_and_the_runs_it_was_fitted_to():
    ship = load_ship(SHIP)
    assert ship.fitted is not None, "the shipped preset records what it was fitted to"
    runs = {entry["file"]: entry["sha256"] for entry in ship.fitted["logs"]}
    assert runs and all(len(digest) == 12 for digest in runs.values())
    parameters = [key for key in ship.fitted["terms"] if key not in CURRENT_TERMS]
    assert parameters
    for key in parameters:
        effect = key.partition(".")[0]
        assert effect in ship.enabled, key
        std_error = ship.std_errors[key]
        assert std_error is not None and math.isfinite(std_error) and std_error > 0.0, key
        for name, digest in runs.items():
            assert f"{name} (sha256 {digest})" in ship.sources[key], key
    assert not [key for key, source in ship.sources.items() if "placeholder" in source]
    model = ShipModel(SHIP)
    assert model.effects == tuple(ship.fitted["effects"]) or set(ship.fitted["effects"]) <= set(model.effects)


def test_the_fixed_pd_autopilot_completes_a_45_deg_course_change_on_the_identified_ship():
    for change in (45.0, -45.0):
        env = gym.make("ship_env/CourseChange-v0", ship=SHIP, dt=MODEL_STEP, max_episode_steps=600)
        task = env.unwrapped.task
        metrics, terminated = sail(
            env,
            pd_controller(task, schedule="fixed"),
            Episode(0, {"course_change_deg": change, "disturbance": "calm"}, f"{change:+.0f}"),
        )
        assert not terminated, f"{change:+.0f} deg: the ship left the model's validity"
        # Settled: within the 2 deg band from settling_time to the episode's end (inf: never settled).
        assert metrics["settling_time"] < 600 * MODEL_STEP, f"{change:+.0f} deg: {metrics}"


def _runs_named(entries: Sequence[dict], every: int) -> list:
    """The runs a preset names (``fitted.logs``), read from the data folder, each file's hash checked."""
    files = {path.name: path for path in DATA.rglob("*.csv")}
    paths = [files[entry["file"]] for entry in entries]
    for path, entry in zip(paths, entries, strict=True):
        assert log_file_digest(path) == entry["sha256"], f"{path} is not the run the preset was fitted to"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", LogWarning)
        return [every_nth(log, every) for log in load_logs(paths)]


def log_file_digest(path: Path) -> str | None:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", LogWarning)
        return log_file(load_logs([path])[0]).sha256


def _option(words: list[str], name: str, default: str) -> str:
    return words[words.index(name) + 1] if name in words else default


def _jackknife_bound(errors: Sequence[RunErrors], groups: Sequence[str], stated: dict) -> dict[str, float]:
    """Per channel (deg, deg/s, m): the stated pooled RMS plus SIGMAS jackknife standard errors over the runs."""
    names = list(dict.fromkeys(groups))
    bounds = {}
    for channel in ("heading", "rate_of_turn", "track"):
        left_out = np.array(
            [
                pooled([e for e, g in zip(errors, groups, strict=True) if g != name]).in_display_units()[channel]
                for name in names
            ]
        )
        spread = math.sqrt((len(names) - 1) / len(names) * np.sum((left_out - left_out.mean()) ** 2))
        bounds[channel] = stated[channel] + SIGMAS * spread
    return bounds


@pytest.fixture(scope="module")
def preset_runs():
    """The preset, and its runs prepared as its command prepared them: (ship, setup, prepared runs, options)."""
    ship = load_ship(SHIP)
    words = shlex.split(ship.fitted["command"])
    every = int(_option(words, "--every", "1"))
    setup = preset_replay_model(ShipModel(SHIP))
    logs = _runs_named(ship.fitted["logs"], every)
    validation = _runs_named(ship.fitted.get("validation_logs", []), every)
    runs = prepare_runs(logs, setup.model, "--inside" in words, validate_on=validation)
    options = FitOptions(scales=ErrorScales.for_runs(setup.model, runs.logs), workers=1)
    return ship, setup, runs, options


def _run_of(log_name: str) -> str:
    """The run a segment was cut from (``--inside`` names a segment ``RUN@START-ENDs``)."""
    return log_name.split("@")[0]


@NEEDS_DATA
@pytest.mark.slow
def test_the_preset_replays_the_runs_of_another_kind_with_the_errors_it_states(preset_runs):
    ship, setup, runs, options = preset_runs
    assert runs.validation, "the preset was validated on runs of another kind"
    replayed = compare(setup, runs.validation, options.initial_window).errors
    errors = pooled(replayed).in_display_units()
    bounds = _jackknife_bound(replayed, [_run_of(e.name) for e in replayed], ship.fitted["validation"])
    for channel, bound in bounds.items():
        assert errors[channel] <= bound, (channel, errors[channel], ship.fitted["validation"][channel])


@NEEDS_DATA
@pytest.mark.slow
def test_the_presets_effects_refitted_leaving_one_run_out_keep_the_held_out_errors_it_states(preset_runs):
    ship, setup, runs, options = preset_runs
    validation = cross_validate(setup, runs.logs, list(ship.fitted["terms"]), options, groups=runs.groups)
    held_out = validation.pooled.in_display_units()
    groups = runs.groups or [log.name for log in runs.logs]
    bounds = _jackknife_bound(validation.held_out, groups, ship.fitted["held_out"])
    for channel, bound in bounds.items():
        assert held_out[channel] <= bound, (channel, held_out[channel], ship.fitted["held_out"][channel])
