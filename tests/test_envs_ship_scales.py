"""The tasks take their scales from the ship (ship_env.envs.ship_scales) and report leaving its envelope."""

from __future__ import annotations

import math

import gymnasium as gym
import numpy as np
import pytest

import ship_env  # noqa: F401  (registers the environments)
from ship_env.envs.course_change_vector import CourseChangeVectorEnv
from ship_env.envs.ship_scales import REFERENCE_SHIP, ship_scales
from ship_env.envs.tracks import NAUTICAL_MILE
from ship_env.leaderboard.entrants import CLASSIC_BUILDERS
from ship_env.leaderboard.sailing import sail
from ship_env.leaderboard.suites import COURSE_CHANGE, TRACK_FOLLOW, Episode
from ship_env.model import ShipModel

#: A 3 m model tank ship at 0.35 m/s (L/U 8.6 s) and a 320 m tanker at 15.5 kn (L/U 40 s).
SMALL_AND_LARGE = ("esso_osaka_model", "kvlcc2")


def _sailed(env_id: str, steps: int, seed: int, **env_kwargs: object) -> tuple[np.ndarray, dict, np.ndarray]:
    """The rewards, last metrics and last observation of ``steps`` steps of a seeded random rudder."""
    env = gym.make(env_id, **env_kwargs).unwrapped
    env.reset(seed=seed)
    actions = np.random.default_rng(seed).uniform(-1.0, 1.0, (steps, 1)).astype(np.float32)
    rewards = []
    for action in actions:
        observation, reward, terminated, _, info = env.step(action)
        rewards.append(reward)
        if terminated:
            break
    return np.asarray(rewards), info["metrics"], observation


def test_the_reference_ship_derives_todays_constants_and_sails_its_episodes_bit_for_bit():
    model = ShipModel(REFERENCE_SHIP)
    scales = ship_scales(model)
    assert (scales.length, scales.speed, scales.time, scales.dt) == (1.0, 1.0, 1.0, 1.0)
    derived = gym.make(TRACK_FOLLOW, start="before_turn").unwrapped.task
    assert (derived.dt, derived.track_scale, float(derived.sensors[0]["fix_interval"])) == (1.0, 1.0, 2.0)
    explicit_settings = {
        COURSE_CHANGE: {"dt": 1.0, "fix_interval": 0.0},
        TRACK_FOLLOW: {"dt": 1.0, "fix_interval": 2.0, "track_scale": 1.0},
    }
    options = {COURSE_CHANGE: {"disturbance": "wind_current_waves"}, TRACK_FOLLOW: {"start": "before_turn"}}
    for env_id, explicit in explicit_settings.items():
        rewards, metrics, observation = _sailed(env_id, 400, 3, **options[env_id])
        explicit_rewards, explicit_metrics, explicit_observation = _sailed(
            env_id, 400, 3, **options[env_id], **explicit
        )
        np.testing.assert_array_equal(rewards, explicit_rewards)
        np.testing.assert_array_equal(observation, explicit_observation)
        assert {name: float(value) for name, value in metrics.items()} == {
            name: float(value) for name, value in explicit_metrics.items()
        }


@pytest.mark.parametrize("ship", SMALL_AND_LARGE)
def test_a_ships_step_and_tracks_follow_its_length_and_speed(ship):
    task = gym.make(TRACK_FOLLOW, ship=ship).unwrapped.task
    reference = gym.make(TRACK_FOLLOW).unwrapped.task
    model = task.model
    time_unit = model.length / model.service_speed
    reference_time_unit = reference.model.length / reference.model.service_speed
    assert task.dt == pytest.approx(time_unit / reference_time_unit)  # 1 s of the reference ship in L / U
    assert float(task.sensors[0]["fix_interval"]) == pytest.approx(2.0 * task.dt)
    for track_id, track in task.tracks.items():  # the legs as long in ship lengths as the reference's
        legs = track.leg_lengths / model.length
        np.testing.assert_allclose(legs, reference.tracks[track_id].leg_lengths / reference.model.length)
        # so a leg lasts as many steps: its length over U, in steps of dt
        steps = track.leg_lengths / model.service_speed / task.dt
        reference_steps = reference.tracks[track_id].leg_lengths / reference.model.service_speed / reference.dt
        np.testing.assert_allclose(steps, reference_steps)
    assert float(task.parameters[0]["waypoint_distance_unit"]) == pytest.approx(
        NAUTICAL_MILE * model.length / reference.model.length
    )


def test_explicit_step_and_track_scale_win_over_the_ships():
    task = gym.make(TRACK_FOLLOW, ship="kvlcc2", dt=0.5, track_scale=2.0, fix_interval=1.0).unwrapped.task
    assert (task.dt, task.track_scale, float(task.sensors[0]["fix_interval"])) == (0.5, 2.0, 1.0)
    native = gym.make(TRACK_FOLLOW).unwrapped.task
    np.testing.assert_allclose(task.tracks["T1"].leg_lengths, 2.0 * native.tracks["T1"].leg_lengths)


@pytest.mark.parametrize("ship", SMALL_AND_LARGE)
@pytest.mark.parametrize("autopilot", ["PD, fixed gains", "PD, gain-scheduled"])
@pytest.mark.parametrize("change_deg", [45.0, -105.0])
def test_the_classic_autopilots_complete_a_course_change_on_a_small_and_a_large_ship(ship, autopilot, change_deg):
    env = gym.make(COURSE_CHANGE, ship=ship)
    controller = CLASSIC_BUILDERS[COURSE_CHANGE][autopilot](env.unwrapped.task)  # designed from the preset's K*, tau*
    metrics, _ = sail(env, controller, Episode(0, {"course_change_deg": change_deg}, ""))
    episode_duration = env.spec.max_episode_steps * env.unwrapped.task.dt
    # settled in the 2-deg band (and stays there) before the registered 600 steps end
    assert metrics["settling_time"] < episode_duration, f"{autopilot} did not settle on {ship}: {metrics}"


@pytest.mark.parametrize("ship", SMALL_AND_LARGE)
def test_the_predictor_course_changer_reaches_the_end_of_a_track_on_a_small_and_a_large_ship(ship):
    """In the thesis's wind and current in the ship's scales, from before a turn of T3 to its end."""
    env = gym.make(TRACK_FOLLOW, ship=ship, start="before_turn")
    controller = CLASSIC_BUILDERS[TRACK_FOLLOW]["predictor course changer"](env.unwrapped.task)
    metrics, terminated = sail(env, controller, Episode(0, {"track": "T3"}, ""))
    assert terminated, f"{ship}: the track's end not reached in {env.spec.max_episode_steps} steps"
    # within a ship length of the track (RMS), as on the reference ship
    assert metrics["rms_cross_track_error"] < env.unwrapped.task.model.length, metrics


def test_a_ship_pushed_out_of_its_envelope_says_where_and_why():
    """Full rudder for a minute on kvlcc2 with its rate limit lowered to 0.5 deg/s: inside at first
    (the rate grows from 0), then out on the rate, at the first step whose rate of turn crosses it."""
    env = gym.make(COURSE_CHANGE, ship="kvlcc2").unwrapped
    limit = math.radians(0.5)
    env.task.parameters[0]["maximum_rate"] = limit
    _, info = env.reset(seed=0)
    assert info["envelope"]["inside"] and info["envelope"]["quantity"] == ""
    rates = []
    for _ in range(60):
        _, _, _, _, info = env.step(np.array([1.0], dtype=np.float32))
        rates.append(abs(info["state"][4]))
    first = int(np.argmax(np.asarray(rates) > limit))
    assert rates[first] > limit >= max(rates[:first])
    envelope = info["envelope"]
    assert not envelope["inside"]
    assert envelope["quantity"] == "rate"
    assert envelope["step"] == first + 1  # simulator steps since the start (the reset is step 0)
    assert envelope["value"] == pytest.approx(rates[first]) and envelope["limit"] == limit
    assert envelope["time"] == pytest.approx((first + 1) * env.task.dt)
    env.reset(seed=1)  # a new episode starts inside
    assert env.batch.info(0)["envelope"]["inside"]


def test_the_vector_env_reports_each_ships_envelope():
    """Half the steady rate of turn at full rudder (K* U / L delta_max) as the rate limit: the ships at
    full rudder leave on the rate, the one amidships stays inside (calm water, no noise in the state)."""
    env = CourseChangeVectorEnv(num_envs=3, ship="esso_osaka_model", sensor_noise_scale=0.0)
    task = env.task
    env.task.parameters[0]["maximum_rate"] = 0.5 * task.full_rudder_rate_per_speed * task.model.service_speed
    env.reset(seed=0)
    orders = np.array([[1.0], [0.0], [-1.0]], dtype=np.float32)
    for _ in range(100):
        _, _, _, _, info = env.step(orders)
    envelope = info["envelope"]
    np.testing.assert_array_equal(envelope["inside"], [False, True, False])
    np.testing.assert_array_equal(envelope["quantity"], ["rate", "", "rate"])
    assert np.all(envelope["value"][[0, 2]] > envelope["limit"][[0, 2]])
    assert envelope["value"][1] == 0.0 and envelope["step"][1] == -1
    assert envelope["_inside"].all()
