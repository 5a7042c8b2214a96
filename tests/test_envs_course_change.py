"""CourseChange-v0: Gymnasium's contract, reproducibility, the vector env, physics through the env."""

from __future__ import annotations

import math

import gymnasium as gym
import numba
import numpy as np
import pytest
from env_contract import (
    DIVERGING_SHIP,
    NO_WIND_EFFECTS,
    assert_a_diverging_ship_ends_alone,
    assert_same_steps,
    assert_vector_equals_singles,
    sail,
)

import ship_env  # noqa: F401  (registers the environments)
from ship_env.envs.course_change import CourseChangeEnv
from ship_env.envs.course_change_task import DEFAULT_RUDDER_TRAVEL_WEIGHT, OBS_RATE_OF_TURN
from ship_env.envs.course_change_vector import CourseChangeVectorEnv
from ship_env.envs.metrics import course_change_metrics
from ship_env.envs.sensors import wrap
from ship_env.envs.weather import DISTURBANCES, RANDOM_DISTURBANCE
from ship_env.model import Conditions, ShipModel, simulator
from ship_env.model import state as S
from ship_env.model.simulator import PARALLEL_SHIPS, batch_loop

ENV_ID = "ship_env/CourseChange-v0"


def test_vector_env_equals_single_envs_seeded_s_plus_i_across_resets():
    """Sub-env i of a batch seeded s is a single env seeded s + i, through autoresets and reset_mask."""
    num_envs, seed = 3, 21
    vector = CourseChangeVectorEnv(num_envs=num_envs, max_episode_steps=7, disturbance=RANDOM_DISTURBANCE)
    singles = [CourseChangeEnv(disturbance=RANDOM_DISTURBANCE) for _ in range(num_envs)]
    rng = np.random.default_rng(1)

    def beyond_the_limits(observations: np.ndarray) -> np.ndarray:  # clipped to +-1 alike
        return rng.uniform(-1.3, 1.3, size=(num_envs, 1))

    episodes, elapsed = assert_vector_equals_singles(vector, singles, beyond_the_limits, 30, seed, partial_reset_at=10)
    assert episodes.min() >= 2 and elapsed.min() < elapsed.max()


def test_a_batch_updated_on_all_cores_equals_single_envs():
    num_envs, seed = PARALLEL_SHIPS, 5
    vector = CourseChangeVectorEnv(num_envs=num_envs, disturbance="wind_current_waves")
    actions = np.random.default_rng(2).uniform(-1.0, 1.0, size=(20, num_envs, 1))
    observations = [vector.reset(seed=seed)[0]]
    observations.extend(vector.step(action)[0] for action in actions)
    for i in (0, num_envs - 1):
        single = sail(CourseChangeEnv(disturbance="wind_current_waves"), actions[:, i], seed=seed + i)
        np.testing.assert_array_equal(np.array(observations)[:, i], np.array([step[0] for step in single]))


@pytest.mark.parametrize("slow_way", ["serial", "parallel"])
def test_a_large_batch_runs_its_loops_the_faster_way(monkeypatch, slow_way):
    """The loops are timed on a clock the test advances, not the machine's: the choice cannot depend on its load."""
    monkeypatch.setattr(numba, "get_num_threads", lambda: 2)
    clock = [0.0]
    monkeypatch.setattr(simulator.time, "perf_counter", lambda: clock[0])
    calls = {"serial": 0, "parallel": 0}

    def loop(name):
        def run(value):
            calls[name] += 1
            clock[0] += 0.02 if name == slow_way else 0.001
            return value

        return run

    serial, parallel = loop("serial"), loop("parallel")
    assert batch_loop(PARALLEL_SHIPS - 1, serial, parallel) is serial
    cores = batch_loop(PARALLEL_SHIPS, serial, parallel)
    assert [cores(k) for k in range(30)] == list(range(30))
    assert calls[slow_way] == 3  # each way twice (the first call untimed), the faster one, the slower at call 16


def test_make_vec_uses_the_vector_entry_point_with_next_step_autoreset():
    envs = gym.make_vec(ENV_ID, num_envs=4, vectorization_mode="vector_entry_point", max_episode_steps=2)
    assert isinstance(envs.unwrapped, CourseChangeVectorEnv)
    assert envs.metadata["autoreset_mode"] == gym.vector.AutoresetMode.NEXT_STEP
    assert envs.observation_space.shape == (4, 5) and envs.action_space.shape == (4, 1)
    envs.reset(seed=0)
    hard_over = np.ones((4, 1), dtype=np.float32)
    for _ in range(2):
        _, _, _, truncated, _ = envs.step(hard_over)
    assert truncated.all()
    observations, rewards, _, truncated, info = envs.step(hard_over)
    assert not truncated.any() and (rewards == 0.0).all() and info["_scenario"].all()
    np.testing.assert_array_equal(observations[:, 2], 0.0)  # a new episode: rudder amidships


def test_a_diverging_ship_ends_only_its_own_episode():
    single = CourseChangeEnv(**DIVERGING_SHIP, disturbance="calm")
    assert_a_diverging_ship_ends_alone(CourseChangeVectorEnv, single, seed=8, disturbance="calm")


def test_zero_rudder_in_calm_water_with_a_current_drifts_with_the_current():
    env = CourseChangeEnv(sensor_noise_scale=0.0, effects=NO_WIND_EFFECTS)
    heading, current_speed, current_direction = math.radians(30.0), 1.2, math.radians(135.0)
    conditions = Conditions(current_speed=current_speed, current_direction=current_direction)
    _, info = env.reset(seed=3, options={"conditions": conditions, "initial_heading_deg": 30.0})
    assert info["scenario"].disturbance == "custom"
    speed = env.task.model.service_speed
    for _ in range(200):
        _, _, _, _, info = env.step(np.zeros(1, dtype=np.float32))
    state = info["state"]
    time = state[S.TIME]
    assert time == pytest.approx(200.0)
    assert state[S.HEADING] == heading and state[S.RATE_OF_TURN] == 0.0
    north = (speed * math.cos(heading) + current_speed * math.cos(current_direction)) * time
    east = (speed * math.sin(heading) + current_speed * math.sin(current_direction)) * time
    assert state[S.NORTH] == pytest.approx(north, rel=1e-12)
    assert state[S.EAST] == pytest.approx(east, rel=1e-12)
    assert (info["measurement"]["north"], info["measurement"]["east"]) == (state[S.NORTH], state[S.EAST])


def closed_form_steady_rate(model: ShipModel, rudder: float) -> float:
    """Steady r of the model in calm water: H(r*) = K* delta (2.26, 2.27), u* from (2.55), r = u r* / L."""
    cubic = model.parameter("norrbin.cubic") if model.has("norrbin") else 0.0
    quadratic, constant = (
        (model.parameter("asymmetry.quadratic"), model.parameter("asymmetry.constant"))
        if model.has("asymmetry")
        else (0.0, 0.0)
    )
    odd_quadratic = model.parameter("norrbin.odd_quadratic") if model.has("norrbin") else 0.0
    quadratic += math.copysign(odd_quadratic, rudder)  # |r*| r* = sign(r*) r*^2, r* turning with the rudder
    coefficients = [cubic, quadratic, model.parameter("yaw.linear"), constant - model.parameter("yaw.gain") * rudder]
    roots = np.roots(coefficients)
    normalised_rate = float(roots[np.abs(roots.imag) < 1e-12].real[0])
    speed_loss = 0.0
    if model.has("speed_loss"):
        loss_roots = np.roots(
            [model.parameter("speed_loss.cubic"), 0.0, 1.0, -model.parameter("speed_loss.gain") * normalised_rate**2]
        )
        speed_loss = float(loss_roots[np.abs(loss_roots.imag) < 1e-12].real[0])
    return model.service_speed * (1.0 - speed_loss) * normalised_rate / model.length


def test_constant_full_rudder_reaches_the_closed_form_steady_rate_of_turn():
    env = CourseChangeEnv(sensor_noise_scale=0.0, rudder_limit_deg=20.0, effects=NO_WIND_EFFECTS)
    env.reset(seed=5)
    for _ in range(1500):
        observation, _, _, _, info = env.step(np.ones(1, dtype=np.float32))
    model = env.task.model
    expected = closed_form_steady_rate(model, math.radians(20.0))
    assert info["state"][S.RUDDER] == pytest.approx(math.radians(20.0))
    assert info["state"][S.RATE_OF_TURN] == pytest.approx(expected, rel=1e-4)
    linear_full_rudder_rate = model.parameter("yaw.gain") * model.service_speed / model.length * math.radians(20.0)
    assert observation[OBS_RATE_OF_TURN] == pytest.approx(expected / linear_full_rudder_rate, rel=1e-5)


@pytest.mark.parametrize(("outside", "limit"), [(3.0, 1.0), (-7.5, -1.0)])
def test_out_of_range_actions_are_clipped(outside, limit):
    actions = np.full((30, 1), outside, dtype=np.float32)
    clipped = sail(CourseChangeEnv(), actions, seed=4)
    assert_same_steps(clipped, sail(CourseChangeEnv(), np.full_like(actions, limit), seed=4))
    assert clipped[5][-1]["state"][S.RUDDER] == pytest.approx(limit * math.radians(2.5) * 5)
    assert clipped[-1][-1]["state"][S.RUDDER] == limit * math.radians(20.0)


def test_episode_truncates_at_the_spec_length_with_the_shared_metrics_in_its_last_info():
    env = gym.make(ENV_ID)
    _, info = env.reset(seed=8, options={"course_change_deg": -45.0})
    states = [info["state"]]
    truncated, steps = False, 0
    while not truncated:
        heading_error = info["new_heading"] - info["state"][S.HEADING]
        action = np.clip([2.0 * heading_error - 40.0 * info["state"][S.RATE_OF_TURN]], -1.0, 1.0).astype(np.float32)
        _, _, terminated, truncated, info = env.step(action)
        assert not terminated
        states.append(info["state"])
        steps += 1
    assert steps == 600
    states = np.array(states)
    expected = course_change_metrics(states[:, S.TIME], states[:, S.HEADING], states[:, S.RUDDER], math.radians(-45.0))
    assert info["metrics"] == pytest.approx(expected, rel=1e-12)
    assert 0.0 < expected["settling_time"] < 600.0 and expected["rudder_travel"] > 0.0


#: A weather setting: each disturbance level's rudder-travel weight, wind and current left out.
WEATHER_SETTING = {"calm": 0.1, "wind_current_waves": 0.9}


@pytest.mark.parametrize(
    ("options", "weight"),
    [
        ({"disturbance": "calm"}, 0.1),
        ({"disturbance": "wind_current_waves"}, 0.9),
        ({"disturbance": "wind_current"}, DEFAULT_RUDDER_TRAVEL_WEIGHT),  # left out: the default
        ({"conditions": Conditions(wind_speed=10.0)}, DEFAULT_RUDDER_TRAVEL_WEIGHT),  # "custom"
    ],
)
def test_each_steps_reward_weighs_the_rudder_travel_by_the_episodes_disturbance_level(options, weight):
    env = CourseChangeEnv(
        disturbance=RANDOM_DISTURBANCE, heading_error_weight=0.7, rudder_travel_weight=WEATHER_SETTING
    )
    actions = np.random.default_rng(6).uniform(-1.0, 1.0, size=(40, 1)).astype(np.float32)
    steps = sail(env, actions, seed=11, options={"course_change_deg": 45.0, **options})
    limit = math.radians(20.0)
    infos = [step[-1] for step in steps]  # the reset's, then each step's
    rudder_moves = []
    for info, (_, reward, _, _, next_info) in zip(infos[:-1], steps[1:], strict=True):
        assert info["rudder_travel_weight"] == weight
        state = next_info["state"]
        rudder_move = abs(state[S.RUDDER] - info["state"][S.RUDDER])
        heading_error = abs(wrap(next_info["new_heading"] - state[S.HEADING]))
        assert reward == pytest.approx(-(0.7 * heading_error / math.pi + weight * rudder_move / limit), rel=1e-12)
        rudder_moves.append(rudder_move)
    assert min(rudder_moves[1:]) > 0.0  # every step pays for rudder travel


def test_one_rudder_travel_weight_for_all_levels_is_the_same_as_a_mapping_giving_each_level_it():
    actions = np.random.default_rng(7).uniform(-1.0, 1.0, size=(30, 1)).astype(np.float32)
    every_level = dict.fromkeys((*DISTURBANCES, "custom"), 0.35)
    for seed in (1, 2, 3):  # random levels
        one = sail(CourseChangeEnv(disturbance=RANDOM_DISTURBANCE, rudder_travel_weight=0.35), actions, seed)
        assert_same_steps(
            one, sail(CourseChangeEnv(disturbance=RANDOM_DISTURBANCE, rudder_travel_weight=every_level), actions, seed)
        )
        assert one[0][-1]["rudder_travel_weight"] == 0.35


@pytest.mark.parametrize(
    ("weight", "error", "message"),
    [
        ({"storm": 1.0}, ValueError, "rudder_travel_weight's level: expected one of calm, .*, got 'storm'"),
        ({"random": 1.0}, ValueError, "got 'random'"),
        ({"calm": -0.1}, ValueError, r"rudder_travel_weight\['calm'\]: .*got -0.1"),
        ({"wind_current": math.nan}, ValueError, r"rudder_travel_weight\['wind_current'\]: .*got nan"),
        ({"calm": "low"}, TypeError, r"rudder_travel_weight\['calm'\]: expected a number, got 'low'"),
        (-1.0, ValueError, "rudder_travel_weight: .*got -1.0"),
        ([0.1, 0.5], TypeError, r"rudder_travel_weight: expected a number, got \[0.1, 0.5\]"),
    ],
)
def test_a_bad_rudder_travel_weight_is_refused_naming_the_field_and_value(weight, error, message):
    with pytest.raises(error, match=message):
        CourseChangeEnv(rudder_travel_weight=weight)


def test_course_change_metrics_on_a_hand_made_run():
    time = [0.0, 1.0, 2.0, 3.0, 4.0]
    errors_deg = np.array([10.0, 5.0, -1.0, 0.5, -0.5])  # to starboard: overshoot 1 deg at t = 2
    rudder = np.radians([0.0, 10.0, 5.0, 5.0, 0.0])
    for sign in (1.0, -1.0):
        heading = np.radians(355.0 + sign * (10.0 - errors_deg)) % (2.0 * math.pi)  # wraps through north
        metrics = course_change_metrics(time, heading, sign * rudder, math.radians(sign * 10.0))
        assert metrics == pytest.approx(
            {"integrated_heading_error": 7.0, "overshoot": 1.0, "settling_time": 2.0, "rudder_travel": 20.0}
        )
    unsettled = course_change_metrics(time, np.zeros(5), np.zeros(5), math.radians(10.0))
    assert unsettled["settling_time"] == math.inf and unsettled["overshoot"] == 0.0


def test_ppo_trains_on_the_vector_env_through_the_sb3_adapter():
    torch = pytest.importorskip("torch")
    from stable_baselines3 import PPO
    from stable_baselines3.common.vec_env import VecMonitor

    from ship_env.envs.sb3_adapter import SB3VecEnvAdapter

    torch.set_num_threads(1)
    vector_env = gym.make_vec(ENV_ID, num_envs=4, vectorization_mode="vector_entry_point", max_episode_steps=16)
    adapter = SB3VecEnvAdapter(vector_env)
    adapter.seed(3)
    adapter.reset()
    for _ in range(16):
        _, rewards, dones, infos = adapter.step(np.zeros((4, 1), dtype=np.float32))
    assert dones.all() and rewards.dtype == np.float32
    assert all(info["TimeLimit.truncated"] and info["terminal_observation"].shape == (5,) for info in infos)
    assert set(infos[0]["metrics"]) == {"integrated_heading_error", "overshoot", "settling_time", "rudder_travel"}
    model = PPO("MlpPolicy", VecMonitor(adapter), n_steps=32, batch_size=64, n_epochs=1, seed=0)
    model.learn(256)
    assert model.num_timesteps == 256 and len(model.ep_info_buffer) > 0


def test_the_sb3_adapter_restarts_a_diverged_ship_alone_and_says_so():
    pytest.importorskip("stable_baselines3")
    from stable_baselines3.common.vec_env import VecMonitor

    from ship_env.envs.sb3_adapter import SB3VecEnvAdapter

    adapter = VecMonitor(
        SB3VecEnvAdapter(CourseChangeVectorEnv(num_envs=3, disturbance="calm", **DIVERGING_SHIP)),
        info_keywords=("diverged",),
    )
    adapter.seed(8)
    adapter.reset()
    hard_over = np.array([[0.2], [1.0], [-0.2]], dtype=np.float32)
    for _ in range(600):
        observations, rewards, dones, infos = adapter.step(hard_over)
        if dones.any():
            break
    np.testing.assert_array_equal(dones, [False, True, False])
    assert infos[1]["diverged"] and infos[1]["TimeLimit.truncated"] and infos[1]["episode"]["diverged"]
    assert np.isfinite(infos[1]["terminal_observation"]).all() and np.isfinite(rewards).all()
    assert np.isfinite(observations).all() and observations[1, 2] == 0.0  # a new episode: rudder amidships
    assert infos[0] == {} and infos[2] == {}
