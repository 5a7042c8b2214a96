"""Every ``reset`` option of every environment acts as documented or is refused: a test per option.

An option may pin a part of the episode (``disturbance``, ``conditions``, ``course_change_deg``,
``initial_heading_deg``, ``course_deg``, ``track``, the vector env's ``reset_mask``); one that would
bring weather the model has no effect to sail (waves on an environment made calm, whose model has no
wave effects) is refused, naming the option and the constructor argument that sails it."""

from __future__ import annotations

import math

import numpy as np
import pytest
from env_contract import NO_WIND_EFFECTS

import ship_env  # noqa: F401  (registers the environments)
from ship_env.envs.course_change import CourseChangeEnv
from ship_env.envs.course_change_vector import CourseChangeVectorEnv
from ship_env.envs.course_keeping import CourseKeepingEnv
from ship_env.envs.track_follow import TrackFollowEnv
from ship_env.envs.weather import CALM, DISTURBANCES, WAVE_EFFECTS
from ship_env.model import Conditions, ShipModel
from ship_env.model import state as S

WEATHER_ENVS = [CourseChangeEnv, CourseKeepingEnv]
DEFAULT_EFFECTS = ShipModel("container_226m").effects
WAVES = Conditions(wind_speed=8.0, current_speed=1.0, wave_height=3.2, wave_period=8.0, wave_direction=1.0)


def _max_wave_heading(env, options: dict, steps: int = 120) -> float:
    """The largest HF wave heading (the wave filter's state) over an episode's first ``steps``."""
    _, info = env.reset(seed=2, options=options)
    largest = abs(info["state"][S.WAVE_HEADING])
    for _ in range(steps):
        info = env.step(np.zeros(env.action_space.shape, dtype=env.action_space.dtype))[-1]
        largest = max(largest, abs(info["state"][S.WAVE_HEADING]))
    return largest


# -- disturbance ---------------------------------------------------------------------------------------
@pytest.mark.parametrize("env_class", WEATHER_ENVS)
@pytest.mark.parametrize("level", DISTURBANCES)
def test_the_disturbance_option_sails_its_level(env_class, level):
    env = env_class(disturbance="random")
    _, info = env.reset(seed=4, options={"disturbance": level})
    scenario = info["scenario"]
    assert scenario.disturbance == level
    conditions = scenario.conditions
    assert (conditions == CALM) == (level == "calm")
    assert (conditions.wave_height > 0.0) == (level == "wind_current_waves")
    wave_heading = _max_wave_heading(env, {"disturbance": level})
    if level == "wind_current_waves":  # the sea moves the compass's wave yaw
        assert wave_heading > 1e-3


def _sail(env, seed: int | None, options: dict, steps: int = 80) -> list:
    """An episode's reset and ``steps`` steps at a rudder sine (every returned item)."""
    shape, dtype = env.action_space.shape, env.action_space.dtype
    items = [env.reset(seed=seed, options=options)]
    items.extend(env.step(np.full(shape, 0.5 * math.sin(k / 9.0), dtype=dtype)) for k in range(steps))
    return items


def _assert_same_episodes(one: list, other: list) -> None:
    for a, b in zip(one, other, strict=True):
        np.testing.assert_array_equal(a[0], b[0])
        np.testing.assert_array_equal(a[-1]["state"], b[-1]["state"])
        assert a[-1]["measurement"] == b[-1]["measurement"] and a[1:-1] == b[1:-1]


@pytest.mark.parametrize("env_class", WEATHER_ENVS)
@pytest.mark.parametrize(
    "options",
    [{"disturbance": "wind_current_waves"}, {"disturbance": "random"}, {"conditions": WAVES}],
    ids=["wind_current_waves", "random", "conditions"],
)
def test_waves_an_option_brings_sail_as_in_an_env_made_with_waves(env_class, options):
    """Made with ``"wind_current"`` (no wave effects), the option's episode, and a later one without
    it, sail bit for bit as in an environment made with ``"random"`` (the wave effects on)."""
    made_without, made_with = env_class(disturbance="wind_current"), env_class(disturbance="random")
    for seed in (5, 6, 7):
        _assert_same_episodes(_sail(made_without, seed, options), _sail(made_with, seed, options))
    assert any(made_without.task.model.has(effect) for effect in WAVE_EFFECTS)
    _assert_same_episodes(_sail(made_without, 8, {"disturbance": "calm"}), _sail(made_with, 8, {"disturbance": "calm"}))
    if "random" not in options.values():
        assert _max_wave_heading(made_without, options) > 1e-3  # the sea moves the compass's wave yaw


@pytest.mark.parametrize("env_class", WEATHER_ENVS)
def test_a_waves_option_on_an_env_given_effects_without_wave_effects_is_refused(env_class):
    env = env_class(disturbance="wind_current", effects=DEFAULT_EFFECTS)
    for options in ({"disturbance": "wind_current_waves"}, {"disturbance": "random"}, {"conditions": WAVES}):
        with pytest.raises(ValueError, match=r"options\['(disturbance|conditions)'\].*wave_height.*effects including"):
            env.reset(seed=0, options=options)
    env.reset(seed=0, options={"disturbance": "calm"})  # the levels it sails stay open


def test_a_disturbance_option_bringing_wind_to_a_model_without_wind_effects_is_refused():
    env = CourseChangeEnv(effects=NO_WIND_EFFECTS)
    with pytest.raises(ValueError, match=r"options\['disturbance'\] = 'wind_current'.*wind_speed.*effects including"):
        env.reset(seed=0, options={"disturbance": "wind_current"})


# -- conditions ----------------------------------------------------------------------------------------
@pytest.mark.parametrize("env_class", [*WEATHER_ENVS, TrackFollowEnv])
def test_the_conditions_option_sails_its_waves_where_the_model_has_wave_effects(env_class):
    env = env_class(effects=[*DEFAULT_EFFECTS, *WAVE_EFFECTS])
    _, info = env.reset(seed=1, options={"conditions": WAVES})
    assert info["scenario"].disturbance == "custom" and info["scenario"].conditions == WAVES
    assert _max_wave_heading(env, {"conditions": WAVES}) > 1e-3


def test_the_conditions_option_brings_its_waves_to_the_track_as_to_an_env_made_with_wave_effects():
    made_without, made_with = TrackFollowEnv(), TrackFollowEnv(effects=[*DEFAULT_EFFECTS, *WAVE_EFFECTS])
    _assert_same_episodes(_sail(made_without, 3, {"conditions": WAVES}), _sail(made_with, 3, {"conditions": WAVES}))
    with pytest.raises(ValueError, match=r"options\['conditions'\]\.wave_height = 3\.2: .*effects including"):
        TrackFollowEnv(effects=DEFAULT_EFFECTS).reset(seed=0, options={"conditions": WAVES})
    calm_sea = Conditions(wind_speed=8.0, current_speed=1.0)
    _, info = TrackFollowEnv(effects=DEFAULT_EFFECTS).reset(seed=0, options={"conditions": calm_sea})
    assert info["scenario"].conditions == calm_sea


def test_the_disturbance_and_conditions_options_together_are_refused():
    env = CourseChangeEnv(disturbance="random")
    with pytest.raises(ValueError, match="'disturbance' and 'conditions' together"):
        env.reset(seed=0, options={"disturbance": "calm", "conditions": WAVES})


def test_the_conditions_option_sails_its_current():
    # Without the wind's effects: the relative wind of a ship set by the current would turn it.
    env = CourseKeepingEnv(disturbance="calm", sensor_noise_scale=0.0, effects=NO_WIND_EFFECTS)
    current = Conditions(current_speed=1.5, current_direction=math.radians(90.0))
    runs = {}
    for name, conditions in (("calm", CALM), ("current", current)):
        env.reset(seed=3, options={"conditions": conditions, "course_deg": 0.0})
        for _ in range(100):
            info = env.step(np.zeros(1, dtype=np.float32))[-1]
        runs[name] = info["state"]
    set_east = runs["current"][S.EAST] - runs["calm"][S.EAST]
    assert set_east == pytest.approx(1.5 * runs["calm"][S.TIME], rel=1e-12)  # 1.5 m/s towards east


# -- the tasks' own options ------------------------------------------------------------------------------
@pytest.mark.parametrize("change_deg", [35.0, -105.0])
def test_the_course_change_and_initial_heading_options_set_the_ordered_and_initial_headings(change_deg):
    env = CourseChangeEnv()
    _, info = env.reset(seed=0, options={"course_change_deg": change_deg, "initial_heading_deg": 200.0})
    scenario = info["scenario"]
    assert scenario.course_change == pytest.approx(math.radians(change_deg), abs=1e-15)
    assert info["state"][S.HEADING] == pytest.approx(math.radians(200.0), abs=1e-15)
    assert info["new_heading"] == pytest.approx(math.radians(200.0 + change_deg), abs=1e-15)


def test_the_course_option_sets_the_course_kept_and_the_initial_heading():
    env = CourseKeepingEnv(disturbance="calm", sensor_noise_scale=0.0)
    observation, info = env.reset(seed=0, options={"course_deg": 250.0})
    assert info["state"][S.HEADING] == pytest.approx(math.radians(250.0), abs=1e-15)
    assert observation[0] == 0.0  # on the ordered course


@pytest.mark.parametrize("track", ["T2", "T5"])
def test_the_track_option_sails_that_track_from_its_first_waypoint(track):
    env = TrackFollowEnv(track="random")
    _, info = env.reset(seed=0, options={"track": track})
    assert info["scenario"].track == track
    assert info["state"][S.HEADING] == env.task.tracks[track].courses[0]


# -- the vector env's --------------------------------------------------------------------------------------
def test_the_reset_mask_option_restarts_only_the_masked_ships():
    envs = CourseChangeVectorEnv(num_envs=3, disturbance="wind_current")
    envs.reset(seed=0)
    for _ in range(5):
        envs.step(np.full((3, 1), 0.5, dtype=np.float32))
    before = envs.batch.simulator.state.copy()
    mask = np.array([False, True, False])
    _, info = envs.reset(options={"reset_mask": mask})
    after = envs.batch.simulator.state
    np.testing.assert_array_equal(after[~mask], before[~mask])
    assert after[1, S.TIME] == 0.0 and info["_scenario"].tolist() == mask.tolist()


def test_waves_one_sub_env_is_restarted_into_sail_there_as_in_a_single_env_and_leave_the_others_be():
    """Ship 1 restarted with waves sails as a single env made with them (its generator's second
    episode); ships 0 and 2 observe and earn as in a batch whose ship 1 restarted without waves."""
    switched, twin = (CourseChangeVectorEnv(num_envs=3, disturbance="wind_current") for _ in range(2))
    single = CourseChangeEnv(disturbance="random")
    actions = [np.full((3, 1), 0.5 * math.sin(k / 9.0), dtype=np.float32) for k in range(60)]
    for envs in (switched, twin):
        envs.reset(seed=0)
        for action in actions[:5]:
            envs.step(action)
    mask = np.array([False, True, False])
    observations, _ = switched.reset(options={"reset_mask": mask, "disturbance": "wind_current_waves"})
    twin.reset(options={"reset_mask": mask, "disturbance": "wind_current"})
    single.reset(seed=1)
    observation, _ = single.reset(options={"disturbance": "wind_current_waves"})
    np.testing.assert_array_equal(observations[1], observation)
    for action in actions[5:]:
        observations, rewards, _, _, info = switched.step(action)
        twin_observations, twin_rewards, *_ = twin.step(action)
        observation, reward, _, _, single_info = single.step(action[1])
        np.testing.assert_array_equal(observations[[0, 2]], twin_observations[[0, 2]])
        np.testing.assert_array_equal(rewards[[0, 2]], twin_rewards[[0, 2]])
        np.testing.assert_array_equal(observations[1], observation)
        np.testing.assert_array_equal(info["state"][1], single_info["state"])
        assert rewards[1] == reward
    assert abs(single_info["state"][S.WAVE_HEADING]) > 0.0
