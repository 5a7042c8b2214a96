"""Gymnasium's contract, the same for every ship environment: the checker, the discrete rudder,
seeded resets, bad actions, a fresh interpreter's gym.make and the rgb_array render."""

from __future__ import annotations

import math
import subprocess
import sys
import warnings

import gymnasium as gym
import numpy as np
import pytest
from env_contract import assert_same_steps, sail
from gymnasium.utils.env_checker import check_env

import ship_env  # noqa: F401  (registers the environments)
from ship_env.envs.batch import INFO_KEYS, ship_info_maker
from ship_env.envs.course_change import CourseChangeEnv
from ship_env.envs.course_keeping import CourseKeepingEnv
from ship_env.envs.sensors import MEASUREMENT_NAMES
from ship_env.envs.track_follow import TrackFollowEnv
from ship_env.envs.weather import DISTURBANCES, RANDOM_DISTURBANCE

ENVS = {
    "ship_env/CourseChange-v0": CourseChangeEnv,
    "ship_env/CourseKeeping-v0": CourseKeepingEnv,
    "ship_env/TrackFollow-v0": TrackFollowEnv,
}
EVERY_DISTURBANCE = [{"disturbance": level} for level in (*DISTURBANCES, RANDOM_DISTURBANCE)]

#: Each environment with the options that change what it observes, draws or accepts.
CHECKED = [
    *(("ship_env/CourseChange-v0", options) for options in EVERY_DISTURBANCE),
    *(("ship_env/CourseKeeping-v0", options) for options in EVERY_DISTURBANCE),
    ("ship_env/CourseKeeping-v0", {"action_type": "discrete"}),
    ("ship_env/TrackFollow-v0", {}),
    ("ship_env/TrackFollow-v0", {"track": "T4", "disturbance": "calm"}),
    ("ship_env/TrackFollow-v0", {"action_type": "discrete", "rudder_levels": 5}),
]
SEEDED = [
    *(("ship_env/CourseChange-v0", options) for options in EVERY_DISTURBANCE),
    ("ship_env/CourseKeeping-v0", {"disturbance": RANDOM_DISTURBANCE}),
    ("ship_env/TrackFollow-v0", {}),
]
COURSE_CHANGE, COURSE_KEEPING, TRACK_FOLLOW = ENVS
DISCRETE = {"action_type": "discrete"}
BAD_CONTINUOUS_ACTIONS = (
    np.array([np.nan]),
    np.array([np.inf]),
    np.array([-np.inf]),
    np.array([0.1, 0.2]),
    np.array([[0.1]]),
    0.5,
    "port",
    None,
)
BAD_ACTIONS = [
    *((env_id, {}, action) for env_id in ENVS for action in BAD_CONTINUOUS_ACTIONS),
    (COURSE_KEEPING, {"action_type": "discrete", "rudder_levels": 3}, 3),
    (COURSE_KEEPING, DISCRETE, True),
    *((TRACK_FOLLOW, DISCRETE, action) for action in (7, -1, 0.5, np.array([3]))),
]
BAD_VECTOR_ACTIONS = [np.full((3,), 0.1), np.array([[0.1], [np.nan], [0.2]]), np.zeros((3, 2))]
#: gym.make's keywords in a fresh interpreter, what it prints of the env and what that must read.
FRESH = [
    (
        COURSE_CHANGE,
        "rudder_limit_deg=10.0, disturbance='random'",
        "round(env.unwrapped.task.rudder_limit, 6), env.unwrapped.task.disturbance",
        ["600", str(round(math.radians(10.0), 6)), "random", "(5,)", "CourseChangeVectorEnv", "600"],
    ),
    (
        COURSE_KEEPING,
        "rudder_weight=0.5, action_type='discrete'",
        "env.unwrapped.task.rudder_weight, env.action_space",
        ["600", "0.5", "Discrete(7)", "(4,)", "CourseKeepingVectorEnv", "600"],
    ),
    (
        TRACK_FOLLOW,
        "track='T5', disturbance='calm'",
        "info['scenario'].track, info['scenario'].disturbance",
        ["3600", "T5", "calm", "(8,)", "TrackFollowVectorEnv", "3600"],
    ),
]
RENDERED = [
    ("ship_env/CourseChange-v0", {"disturbance": "wind_current_waves"}),
    ("ship_env/CourseKeeping-v0", {}),
    ("ship_env/TrackFollow-v0", {"track": "T1"}),
]


def _ids(cases: list[tuple[str, dict]]) -> list[str]:
    return [env_id.split("/")[1] + "".join(f"-{value}" for value in options.values()) for env_id, options in cases]


def _assert_checked_without_warnings(env: gym.Env) -> None:
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        check_env(env.unwrapped)
    assert [str(warning.message) for warning in caught] == []


@pytest.mark.parametrize(("env_id", "options"), CHECKED, ids=_ids(CHECKED))
def test_check_env_passes_without_warnings(env_id, options):
    _assert_checked_without_warnings(gym.make(env_id, **options))


@pytest.mark.parametrize("env_id", list(ENVS))
def test_every_env_offers_the_discrete_rudder(env_id):
    env = gym.make(env_id, action_type="discrete", rudder_levels=3)
    assert env.action_space == gym.spaces.Discrete(3)
    _assert_checked_without_warnings(env)


@pytest.mark.parametrize(("env_id", "options"), SEEDED, ids=_ids(SEEDED))
def test_seeded_reset_repeats_the_trajectory_and_other_seeds_differ(env_id, options):
    actions = np.random.default_rng(0).uniform(-1.0, 1.0, size=(40, 1)).astype(np.float32)
    env = ENVS[env_id](**options)
    first = sail(env, actions, seed=11)
    assert_same_steps(first, sail(env, actions, seed=11))
    assert_same_steps(first, sail(ENVS[env_id](**options), actions, seed=11))
    other = sail(env, actions, seed=12)
    assert not np.array_equal(first[-1][-1]["state"], other[-1][-1]["state"])


@pytest.mark.parametrize(("env_id", "options", "action"), BAD_ACTIONS)
def test_bad_actions_raise_value_error_naming_the_action(env_id, options, action):
    env = ENVS[env_id](**options)
    env.reset(seed=0)
    with pytest.raises(ValueError, match="action") as raised:
        env.step(action)
    assert repr(action) in str(raised.value) or str(action) in str(raised.value)


@pytest.mark.parametrize("env_id", list(ENVS))
@pytest.mark.parametrize("action", BAD_VECTOR_ACTIONS, ids=["flat", "nan", "two-columns"])
def test_bad_vector_actions_raise_value_error(env_id, action):
    envs = gym.make_vec(env_id, num_envs=3, vectorization_mode="vector_entry_point")
    envs.reset(seed=0)
    with pytest.raises(ValueError, match="action"):
        envs.step(action)


def test_make_from_a_fresh_interpreter_with_only_the_id_and_kwargs_passing_through(tmp_path):
    """One fresh interpreter, which has not imported ship_env, makes each environment by its id alone
    and sails it without importing matplotlib or scipy.stats (an environment never drawn does not
    wait for them)."""
    code = "import sys, gymnasium as gym\nassert 'ship_env' not in sys.modules\n"
    for env_id, keywords, printed, _ in FRESH:
        code += (
            f"env = gym.make('ship_env:{env_id}', {keywords})\n"
            "observation, info = env.reset(seed=1)\n"
            "env.step(env.action_space.sample())\n"
            f"envs = gym.make_vec('ship_env:{env_id}', num_envs=2, vectorization_mode='vector_entry_point')\n"
            f"print('{env_id}', env.spec.max_episode_steps, {printed}, observation.shape,"
            " type(envs.unwrapped).__name__, envs.unwrapped.max_episode_steps)\n"
        )
    code += "print('imported', 'matplotlib' in sys.modules, 'scipy.stats' in sys.modules)\n"
    result = subprocess.run([sys.executable, "-c", code], cwd=tmp_path, capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stderr
    printed_lines = {line.split()[0]: line.split()[1:] for line in result.stdout.splitlines()}
    for env_id, _, _, expected in FRESH:
        assert printed_lines[env_id] == expected, env_id
    assert printed_lines["imported"] == ["False", "False"]


@pytest.mark.parametrize(("env_id", "options"), RENDERED, ids=_ids(RENDERED))
def test_rgb_array_render_returns_an_rgb_frame(env_id, options):
    env = gym.make(env_id, render_mode="rgb_array", **options)
    env.reset(seed=2)
    for _ in range(20):
        env.step(np.full(1, 0.5, dtype=np.float32))
    frame = env.render()
    assert frame.dtype == np.uint8 and frame.ndim == 3 and frame.shape[2] == 3 and frame.shape[0] > 100
    assert len(np.unique(frame.reshape(-1, 3), axis=0)) > 10
    env.close()


def test_rgb_array_frames_drawn_over_the_kept_picture_equal_what_matplotlib_draws_of_the_whole_figure():
    """The renderer keeps the still picture (axes, ticks, legend, the sea's arrows) and draws the moving
    artists over a copy of it. The view holds while the track stays a ship length inside it and is
    framed afresh once it does not (160 steps on a straight course); a new episode in another sea keeps
    the view and redraws the arrows; and then a frame equals matplotlib's drawing of the whole figure
    with nothing left out (outside the legend, which the renderer puts over the lines opaque)."""
    env = gym.make("ship_env/CourseChange-v0", render_mode="rgb_array", disturbance="random")
    axes_limits = []
    for seed, steps in ((3, 160), (4, 3)):
        env.reset(seed=seed)
        for step in range(steps):
            env.step(np.zeros(1, dtype=np.float32))
            if step in (0, steps - 2, steps - 1):
                kept = env.render()
                figure = env.unwrapped._renderer.figure
                axes_limits.append((figure.axes[0].get_xlim(), figure.axes[0].get_ylim()))
    assert axes_limits[0] != axes_limits[1] == axes_limits[2] == axes_limits[3] == axes_limits[-1]
    for artist in figure.axes[0].get_children():
        artist.set_animated(False)
    figure.canvas.draw()
    whole = np.asarray(figure.canvas.buffer_rgba())[:, :, :3]
    legend = figure.axes[0].get_legend().get_window_extent()
    outside = np.ones(kept.shape[:2], dtype=bool)
    height = kept.shape[0]
    outside[
        height - math.ceil(legend.y1) : height - math.floor(legend.y0), math.floor(legend.x0) : math.ceil(legend.x1)
    ] = False
    assert np.array_equal(kept[outside], whole[outside])
    env.close()


@pytest.mark.parametrize("env_id", list(ENVS))
def test_info_keys_build_the_chosen_keys_alone_and_sail_the_same_episodes(env_id):
    full = gym.make(env_id)
    _, reset_info = full.reset(seed=5)
    _, _, _, _, step_info = full.step(full.action_space.sample())
    # The documented keys, in order: every task's, then its own (those ``task_info_keys`` declares).
    own = full.unwrapped.batch.task_info_keys
    assert list(step_info) == [*INFO_KEYS, *own] and list(reset_info) == [*INFO_KEYS, *own, "scenario"]
    for keys in ((), ("metrics",), ("state", own[0])):
        full, lean = gym.make(env_id), gym.make(env_id, info_keys=keys)
        (first, full_info), (lean_first, lean_info) = full.reset(seed=5), lean.reset(seed=5)
        assert np.array_equal(first, lean_first) and set(lean_info) == {*keys, "scenario"}
        full.action_space.seed(1)
        for _ in range(20):
            action = full.action_space.sample()
            *outcome, full_info = full.step(action)
            *lean_outcome, lean_info = lean.step(action)
            assert np.array_equal(outcome[0], lean_outcome[0]) and outcome[1:] == lean_outcome[1:]
            assert list(lean_info) == list(keys)
            assert all(np.array_equal(lean_info[key], full_info[key]) for key in keys if key != "metrics")
            assert lean_info.get("metrics", full_info["metrics"]) == full_info["metrics"]

    vector = gym.make_vec(env_id, num_envs=3, vectorization_mode="vector_entry_point", info_keys=("metrics",))
    _, info = vector.reset(seed=5)
    assert set(info) == {"metrics", "_metrics", "scenario", "_scenario"}
    _, _, _, _, info = vector.step(vector.action_space.sample())
    first_metric = next(iter(info["metrics"]))
    assert set(info) == {"metrics", "_metrics"} and info["metrics"][first_metric].shape == (3,)


@pytest.mark.parametrize("env_id", list(ENVS))
def test_one_ships_measurements_and_metrics_are_python_numbers_of_the_records_in_field_order(env_id):
    env = gym.make(env_id)
    env.reset(seed=2)
    info = env.step(env.action_space.sample())[-1]
    batch = env.unwrapped.batch
    metrics = batch.metrics[0]
    assert list(info["metrics"]) == list(batch.metrics_dtype.names)
    for name, value in info["metrics"].items():
        assert type(value) is type(metrics[name].item()) and value == metrics[name], name
    measured = batch.episodes["measurement"][0]
    assert [type(value) for value in info["measurement"].values()] == [float] * len(measured)
    assert list(info["measurement"].values()) == measured.tolist()


def test_the_info_literal_builds_what_a_dict_of_zip_builds_and_refuses_a_key_not_a_string():
    keys = ("a", "b'", 'c"\\')
    measurement = [0.0] * len(MEASUREMENT_NAMES)
    made = ship_info_maker(keys, ())(measurement, None, [1, 2.0, "x", "not a value: no key"], None, {}, 0)["metrics"]
    assert made == dict(zip(keys, [1, 2.0, "x"], strict=True)) and list(made) == list(keys)
    with pytest.raises(TypeError, match="dict_literal: expected string keys, got 1"):
        ship_info_maker(["a", 1], ())


@pytest.mark.parametrize(
    ("info_keys", "message"),
    [
        (("metric",), r"info_keys: unknown keys \['metric'\] in \('metric',\); known: measurement, state"),
        ("metrics", "info_keys: expected a sequence of key names or None, got 'metrics'"),
    ],
)
def test_info_keys_refuse_an_unknown_key_naming_it_and_the_known_ones(info_keys, message):
    with pytest.raises(ValueError, match=message):
        gym.make("ship_env/CourseChange-v0", info_keys=info_keys)


def test_info_keys_may_be_any_iterable_of_names():
    env = gym.make("ship_env/CourseChange-v0", info_keys=(key for key in ("metrics", "state")))
    env.reset(seed=0)
    assert list(env.step(np.array([0.5], dtype=np.float32))[-1]) == ["state", "metrics"]
