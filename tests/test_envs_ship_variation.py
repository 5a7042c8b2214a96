"""Ship variation (``ship_variation``): seeded, within its ranges, reported, and sailed as drawn."""

from __future__ import annotations

import math

import gymnasium as gym
import numpy as np
import pytest

import ship_env  # noqa: F401  (registers the environments)
from ship_env.envs.course_change_task import CourseChangeTask
from ship_env.envs.track_follow_task import TrackFollowTask
from ship_env.envs.variation import DEFAULT_SHIP_VARIATION
from ship_env.model import Conditions, ShipModel, Simulator, load_ship


def test_same_seed_same_ships_and_the_task_episode_of_the_nominal_ship():
    task = CourseChangeTask(disturbance="random", ship_variation=True)
    first = [task.draw_scenario(np.random.default_rng(7)) for _ in range(2)]
    assert first[0] == first[1]
    rng = np.random.default_rng(8)
    ships = {task.draw_scenario(rng).ship for _ in range(5)}
    assert len(ships) == 5  # another draw, another ship
    nominal = CourseChangeTask(disturbance="random").draw_scenario(np.random.default_rng(7))
    assert nominal.ship is None
    assert (nominal.course_change, nominal.initial_heading, nominal.seed) == (
        first[0].course_change,
        first[0].initial_heading,
        first[0].seed,
    )


def test_ranges_respected_and_the_conditions_carry_the_drawn_ship():
    ranges = {"yaw_gain": [0.5, 2.0], "yaw_time_constant": [0.8, 1.25], "speed": [0.5, 1.0], "disturbance": [0, 2]}
    task = CourseChangeTask(disturbance="wind_current_waves", ship_variation=ranges)
    nominal_task = CourseChangeTask(disturbance="wind_current_waves")
    service_speed = task.model.service_speed
    factors = []
    for seed in range(300):
        scenario = task.draw_scenario(np.random.default_rng(seed))
        weather = nominal_task.draw_scenario(np.random.default_rng(seed)).conditions
        ship, conditions = scenario.ship, scenario.conditions
        factors.append([ship.yaw_gain, ship.yaw_time_constant, ship.speed, ship.disturbance])
        assert conditions.yaw_gain_factor == ship.yaw_gain
        assert conditions.yaw_time_constant_factor == ship.yaw_time_constant
        assert conditions.service_speed == pytest.approx(service_speed * ship.speed, rel=1e-15)
        assert conditions.wind_speed == pytest.approx(weather.wind_speed * ship.disturbance, rel=1e-15)
        assert conditions.wave_height == pytest.approx(weather.wave_height * ship.disturbance, rel=1e-15)
    factors = np.array(factors)
    low = np.array([value[0] for value in ranges.values()])
    high = np.array([value[1] for value in ranges.values()])
    assert np.all(factors >= low) and np.all(factors <= high)
    # They fill their ranges: K*, tau* log-uniform (median at the geometric mean), the others uniform.
    assert np.median(factors[:, 0]) == pytest.approx(1.0, abs=0.15)
    assert factors[:, 0].min() < 0.55 and factors[:, 0].max() > 1.8
    assert np.median(factors[:, 2]) == pytest.approx(0.75, abs=0.05)


def test_keys_left_out_stay_nominal_and_true_takes_the_defaults():
    ship = CourseChangeTask(ship_variation={"speed": [0.5, 0.6]}).draw_scenario(np.random.default_rng(1)).ship
    assert (ship.yaw_gain, ship.yaw_time_constant, ship.disturbance) == (1.0, 1.0, 1.0)
    assert 0.5 <= ship.speed <= 0.6
    assert CourseChangeTask(ship_variation=True).variation.ranges == DEFAULT_SHIP_VARIATION


@pytest.mark.parametrize(
    ("ranges", "message"),
    [
        ({"yaw_gain": [-0.5, 2.0]}, r"ship_variation\['yaw_gain'\]\[0\].*-0.5"),
        ({"speed": [0.0, 1.0]}, r"ship_variation\['speed'\]\[0\].*0.0"),
        ({"yaw_time_constant": [2.0, 0.5]}, r"ship_variation\['yaw_time_constant'\]\[1\].*0.5"),
        ({"mass": [1.0, 2.0]}, r"unknown keys \['mass'\]"),
    ],
)
def test_bad_ranges_raise_naming_the_key_and_value(ranges, message):
    with pytest.raises(ValueError, match=message):
        gym.make("ship_env/CourseChange-v0", ship_variation=ranges)


def test_given_conditions_are_sailed_as_given():
    given = Conditions(wind_speed=3.0)
    scenario = CourseChangeTask(ship_variation=True).draw_scenario(np.random.default_rng(0), {"conditions": given})
    assert scenario.conditions == given and scenario.ship is None


def test_vector_env_sails_different_ships_as_single_envs_do():
    kwargs = {"disturbance": "random", "ship_variation": True}
    vector = gym.make_vec("ship_env/CourseChange-v0", num_envs=3, vectorization_mode="vector_entry_point", **kwargs)
    singles = [gym.make("ship_env/CourseChange-v0", **kwargs) for _ in range(3)]
    observations, info = vector.reset(seed=11)
    ships = [single.reset(seed=11 + i)[1]["scenario"].ship for i, single in enumerate(singles)]
    assert list(info["scenario"][k].ship for k in range(3)) == ships
    assert len({ship.yaw_gain for ship in ships}) == 3
    actions = np.array([[0.7], [-0.3], [1.0]], dtype=np.float32)
    for _ in range(40):
        observations, rewards, *_ = vector.step(actions)
        for i, single in enumerate(singles):
            observation, reward, *_ = single.step(actions[i])
            np.testing.assert_array_equal(observation, observations[i])
            assert reward == rewards[i]


def test_track_follow_varies_too():
    scenario = TrackFollowTask(ship_variation=True).draw_scenario(np.random.default_rng(3))
    assert scenario.conditions.current_speed == pytest.approx(
        TrackFollowTask().draw_scenario(np.random.default_rng(3)).conditions.current_speed * scenario.ship.disturbance
    )


@pytest.mark.parametrize("factor", [0.5, 2.0])
def test_per_ship_factors_sail_as_the_scaled_model(factor):
    """Conditions' K*, tau* factors = a model with K*, tau* scaled (2.54): the steady rate r = K* (U/L) delta."""
    preset = load_ship("container_226m")
    nominal = ShipModel(preset)
    scaled = ShipModel(
        preset,
        parameters={
            "yaw.gain": factor * nominal.parameter("yaw.gain"),
            "yaw.time_constant": factor * nominal.parameter("yaw.time_constant"),
        },
    )
    by_conditions = Simulator(nominal, num_ships=2)
    by_conditions.reset(conditions=[Conditions(), Conditions(yaw_gain_factor=factor, yaw_time_constant_factor=factor)])
    by_model = Simulator(scaled, num_ships=1)
    by_model.reset()
    rudder = math.radians(10.0)
    for _ in range(300):
        by_conditions.step(rudder)
        by_model.step(rudder)
    np.testing.assert_allclose(by_conditions.state[1], by_model.state[0], rtol=1e-12, atol=1e-12)
    assert abs(by_conditions.state[1, 4] - by_conditions.state[0, 4]) > 0.2 * abs(by_conditions.state[0, 4])


def test_bad_factors_in_conditions_raise():
    with pytest.raises(ValueError, match="yaw_time_constant_factor: must be positive, got 0.0"):
        Conditions(yaw_time_constant_factor=0.0)
    with pytest.raises(ValueError, match="yaw_gain_factor: must not be negative, got -1.0"):
        Conditions(yaw_gain_factor=-1.0)


@pytest.mark.parametrize(
    "env_id", ["ship_env/CourseChange-v0", pytest.param("ship_env/TrackFollow-v0", marks=pytest.mark.slow)]
)
def test_observation_history_remembers_the_previous_steps(env_id):
    plain = gym.make(env_id)
    remembering = gym.make(env_id, observation_history=2)
    task = remembering.unwrapped.task
    remembered = list(task.history_observations)
    size = plain.observation_space.shape[0]
    assert remembering.observation_space.shape == (size + 2 * len(remembered),)
    first, _ = remembering.reset(seed=4)
    np.testing.assert_array_equal(first[:size], plain.reset(seed=4)[0])
    np.testing.assert_array_equal(first[size:], np.tile(first[remembered], 2))  # a steady ship's past
    seen = [first]
    for action in (1.0, -0.5, 0.25):
        observation, *_ = remembering.step(np.array([action], dtype=np.float32))
        np.testing.assert_array_equal(observation[:size], plain.step(np.array([action], dtype=np.float32))[0])
        seen.append(observation)
    np.testing.assert_array_equal(seen[3][size : size + 3], seen[2][remembered])
    np.testing.assert_array_equal(seen[3][size + 3 :], seen[1][remembered])
    assert remembering.observation_space.contains(seen[3])


def test_track_preview_reads_the_arc_ahead_and_on_it():
    env = gym.make("ship_env/TrackFollow-v0", track_preview=True, disturbance="calm", sensor_noise_scale=0.0)
    observation, info = env.reset(seed=0, options={"track": "T1"})
    task = env.unwrapped.task
    legs = task.tracks["T1"].legs
    first_arc = np.hypot(*legs[0, 8:10])  # the first leg's straight ends at the first arc's start
    speed = task.model.service_speed
    assert observation[10] == pytest.approx(min(first_arc / speed / 60.0, 5.0), rel=1e-6)
    # The arcs are the ship's turns at the rudder limit: about K* delta_max / L of curvature.
    assert observation[11] == pytest.approx(np.sign(legs[0, 13]) * 0.94, abs=0.03)
    assert observation[9] == 0.0 and observation[8] == pytest.approx(observation[1], abs=1e-6)
    while observation[10] > 0.0 or observation[9] == 0.0:  # hold the rudder hard over from the arc's start
        action = [0.0] if observation[10] > 0.0 else [np.sign(observation[11])]
        observation, _, terminated, _, info = env.step(np.array(action, dtype=np.float32))
    assert observation[9] == observation[11] and info["leg"] == 0
    with pytest.raises(TypeError, match="track_preview: expected true or false, got 'yes'"):
        gym.make("ship_env/TrackFollow-v0", track_preview="yes")


def test_the_yaw_factor_scales_k_and_tau_together():
    task = CourseChangeTask(ship_variation={"yaw": [0.5, 2.0]})
    rng = np.random.default_rng(5)
    ships = [task.draw_scenario(rng).ship for _ in range(50)]
    assert all(ship.yaw_gain == ship.yaw_time_constant for ship in ships)
    assert min(ship.yaw_gain for ship in ships) < 0.6 and max(ship.yaw_gain for ship in ships) > 1.7


@pytest.mark.parametrize(("env_id", "speed"), [("ship_env/CourseChange-v0", 3), ("ship_env/TrackFollow-v0", 4)])
def test_observe_design_speed_shows_a_slower_ship_in_the_speed_observation(env_id, speed):
    """At half the service speed the log speed over the ship's own service speed reads 1, over the
    design ship's 1/2; the other observations are the same numbers."""
    observations = {}
    for design in (False, True):
        env = gym.make(env_id, ship_variation={"speed": (0.5, 0.5)}, observe_design_speed=design)
        env.reset(seed=3)
        observations[design] = env.step(np.zeros(1, dtype=np.float32))[0]
    own, design = observations[False], observations[True]
    assert own[speed] == pytest.approx(1.0, abs=0.02) and design[speed] == pytest.approx(0.5 * own[speed], rel=1e-6)
    np.testing.assert_array_equal(np.delete(own, speed), np.delete(design, speed))
    with pytest.raises(TypeError, match="observe_design_speed: expected true or false, got 'yes'"):
        gym.make(env_id, observe_design_speed="yes")
