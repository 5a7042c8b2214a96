"""TrackFollow-v0: the thesis's tracks, the cross-track geometry, the score, Gymnasium's contract."""

from __future__ import annotations

import math

import gymnasium as gym
import numpy as np
import pytest
from env_contract import (
    NO_WIND_EFFECTS,
    assert_a_diverging_ship_ends_alone,
    assert_all_core_vector_truncates_like_a_single_env,
    assert_vector_equals_singles,
)

import ship_env  # noqa: F401  (registers the environments)
from ship_env.envs.metrics import THESIS_NAVIGATOR_RMS, track_metrics
from ship_env.envs.track_follow import TrackFollowEnv
from ship_env.envs.track_follow_task import (
    OBS_CROSS_TRACK,
    OBS_HEADING_ERROR,
    OBS_NEXT_CHANGE,
    OBS_RATE_OF_TURN,
    OBS_WAYPOINT_DISTANCE,
    THESIS_CONDITIONS,
)
from ship_env.envs.track_follow_vector import TrackFollowVectorEnv
from ship_env.envs.tracks import (
    NAUTICAL_MILE,
    TRACK_IDS,
    build_track,
    cross_track_error,
    reference_track,
    steady_turn_radius,
)
from ship_env.model import Conditions, ShipModel, Simulator
from ship_env.model import state as S

ENV_ID = "ship_env/TrackFollow-v0"
#: The thesis's Tables 6.1.a (the course changes) and 6.1.b (each track's changes in order) as it prints them.
THESIS_TABLE_6_1_A = "C1: 15 degrees, C2: 30 degrees, C3: 45 degrees, C4: 75 degrees, C5: 105 degrees"
THESIS_TABLE_6_1_B = """
T1: C4 C3 C2 C5 C1
T2: C1 C4 C5 C2 C3
T3: C3 C1 C5 C4 C2
T4: C5 C2 C4 C1 C3
T5: C2 C1 C3 C4 C5
T6: C3 C5 C1 C2 C4
"""
CHANGE_DEG = {
    name: float(text.split()[0]) for name, text in (item.split(": ") for item in THESIS_TABLE_6_1_A.split(", "))
}
THESIS_TRACK_CHANGES_DEG = {
    track_id: [CHANGE_DEG[name] for name in changes.split()]
    for track_id, changes in (line.split(": ") for line in THESIS_TABLE_6_1_B.strip().splitlines())
}


class TrackPD:
    """A naive fixed-gain track follower on the observation alone (a sanity check, not a baseline).

    PD on the heading error, delta = Kp (psi_d - psi) - Kd r, the desired heading the leg's course
    corrected towards the track, psi_d = course - atan((e + Ki int e dt) / lookahead) (the integral
    takes out the current's crab angle); the next leg's course is ordered once the next waypoint is
    nearer than its arc's tangent length R tan(|change| / 2) plus ``lead``.
    """

    def __init__(self, task, kp=1.5, kd=40.0, lookahead=500.0, ki=0.01, lead=300.0) -> None:
        self.task, self.kp, self.kd, self.lookahead, self.ki, self.lead = task, kp, kd, lookahead, ki, lead
        self.length = task.model.length
        self.rate_scale = task.full_rudder_rate_per_speed * task.model.service_speed
        self.radius = float(task.tracks["T1"].turn_radii[0])
        self.integral = 0.0

    def __call__(self, observation: np.ndarray) -> np.ndarray:
        cross_track = observation[OBS_CROSS_TRACK] * self.length
        heading_error = observation[OBS_HEADING_ERROR] * math.pi
        change = observation[OBS_NEXT_CHANGE] * math.pi
        if (
            change
            and observation[OBS_WAYPOINT_DISTANCE] * NAUTICAL_MILE
            < self.radius * math.tan(0.5 * abs(change)) + self.lead
        ):
            heading_error += change
        else:
            self.integral += cross_track * self.task.dt
        correction = -math.atan((cross_track + self.ki * self.integral) / self.lookahead)
        rudder = self.kp * (heading_error + correction) - self.kd * observation[OBS_RATE_OF_TURN] * self.rate_scale
        return np.array([np.clip(rudder / self.task.rudder_limit, -1.0, 1.0)], dtype=np.float32)


# -- the reference tracks -----------------------------------------------------------------------


@pytest.mark.parametrize("track_id", TRACK_IDS)
def test_reference_tracks_have_the_thesis_course_changes_in_order_and_legs_of_2_to_2_5_nm(track_id):
    track = reference_track(track_id)
    legs = np.diff(track.waypoints, axis=0)
    courses = np.arctan2(legs[:, 1], legs[:, 0])
    changes = np.degrees((np.diff(courses) + math.pi) % (2.0 * math.pi) - math.pi)
    np.testing.assert_allclose(np.abs(changes), THESIS_TRACK_CHANGES_DEG[track_id], atol=1e-9)
    np.testing.assert_array_equal(np.sign(changes), [1, -1, 1, -1, 1])  # alternating, starboard first
    lengths_nm = np.hypot(legs[:, 0], legs[:, 1]) / NAUTICAL_MILE
    assert lengths_nm.shape == (6,) and np.all((lengths_nm >= 2.0 - 1e-12) & (lengths_nm <= 2.5 + 1e-12))
    np.testing.assert_allclose(track.waypoints[0], [0.0, 0.0])
    # The arcs join the legs: the outline runs along the waypoints' polyline except at the corners.
    assert np.abs(cross_track_error(track.outline(), track)).max() < 1e-9


def test_the_arcs_are_the_ships_own_steady_turn_which_it_follows_exactly():
    """A ship in its steady 10-deg turn, put on an arc's start, stays on the arc (no wind, no current)."""
    model = ShipModel("container_226m", parameters={"rudder_limit": math.radians(10.0)})
    linear_radius = model.length / (model.parameter("yaw.gain") * math.radians(10.0))  # L / (K* delta), 6.4.4.2
    for rudder in (math.radians(10.0), -math.radians(10.0)):
        radius = steady_turn_radius(model, rudder)
        assert 1.0 < radius / linear_radius < 1.15  # the Norrbin term widens the linear turn a little
        simulator = Simulator(model, dt=1.0)
        simulator.reset(seed=0)
        for _ in range(3000):
            simulator.step(rudder)
        before = simulator.position[0].copy()
        simulator.step(rudder)
        chord = simulator.position[0] - before  # parallel to the track at the step's middle
        drift = simulator.heading[0] - 0.5 * simulator.rate_of_turn[0] - math.atan2(chord[1], chord[0])
        track = build_track("corner", [math.copysign(0.5 * math.pi, rudder)], [3000.0, 3000.0], radius, radius)
        simulator.state[0, [S.TIME, S.NORTH, S.EAST, S.HEADING]] = [0.0, 3000.0 - radius, 0.0, drift]
        positions = [simulator.position[0].copy()]
        for _ in range(120):  # 90 deg at about 0.6 deg/s
            simulator.step(rudder)
            positions.append(simulator.position[0].copy())
        assert np.abs(cross_track_error(np.array(positions), track)).max() < 1e-3


def test_cross_track_error_of_known_points_against_a_hand_made_track():
    """North 1000 m, a 90-deg turn to starboard on a 200-m arc, east 1000 m."""
    track = build_track("hand-made", [math.radians(90.0)], [1000.0, 1000.0], 200.0, 300.0)
    centre = np.array([800.0, 200.0])  # the arc runs from (800, 0) to (1000, 200)
    np.testing.assert_allclose(track.arc_centres, [centre])
    diagonal = np.array([math.sqrt(0.5), -math.sqrt(0.5)])  # from the centre to the arc's middle
    points = np.array(
        [
            [400.0, 30.0],  # starboard of the first leg
            [400.0, -50.0],  # port of it
            centre + 200.0 * diagonal,  # on the arc
            centre + 150.0 * diagonal,  # inside the turn: starboard
            centre + 260.0 * diagonal,  # outside it: port
            [1000.0, 0.0],  # the waypoint itself: outside the arc
            [1050.0, 600.0],  # port of the second leg (north of an eastward leg)
            [950.0, 1000.0],  # starboard of its end
            [-30.0, 40.0],  # behind the start: the distance to the first waypoint
        ]
    )
    expected = [30.0, -50.0, 0.0, 50.0, -60.0, 200.0 - math.hypot(200.0, 200.0), -50.0, 50.0, 50.0]
    np.testing.assert_allclose(cross_track_error(points, track), expected, atol=1e-9)
    assert cross_track_error(points.reshape(3, 3, 2), track).shape == (3, 3)
    with pytest.raises(ValueError, match="position"):
        cross_track_error(np.zeros(3), track)


def test_build_track_rejects_turns_that_do_not_fit_their_legs():
    with pytest.raises(ValueError, match="leg 0"):
        build_track("tight", [math.radians(105.0)], [500.0, 3000.0], 860.0, 860.0)


def test_track_metrics_sample_every_two_seconds_from_the_start():
    track = build_track("straight", [math.radians(30.0)], [5000.0, 5000.0], 500.0, 500.0)
    time = np.arange(7.0)
    offsets = np.array([0.0, 100.0, 10.0, 100.0, -20.0, 100.0, 20.0])  # only the even seconds count
    metrics = track_metrics(time, 10.0 * time, offsets, np.radians([0, 1, 2, 2, 1, 0, 0]), track)
    assert metrics["rms_cross_track_error"] == pytest.approx(math.sqrt((0.0 + 100.0 + 400.0 + 400.0) / 4.0))
    assert metrics["max_cross_track_error"] == pytest.approx(20.0)
    assert metrics["rudder_travel"] == pytest.approx(4.0) and metrics["samples"] == 4


# -- the environment ------------------------------------------------------------------------------


def test_reset_draws_every_thesis_track():
    tracks = {TrackFollowEnv().reset(seed=seed)[1]["scenario"].track for seed in range(30)}
    assert tracks == set(TRACK_IDS)


def test_the_first_observation_describes_the_first_leg_in_the_thesis_conditions():
    env = TrackFollowEnv(sensor_noise_scale=0.0)
    observation, info = env.reset(seed=0, options={"track": "T1"})
    scenario = info["scenario"]
    assert scenario.track == "T1" and scenario.disturbance == "thesis" and scenario.conditions == THESIS_CONDITIONS
    assert scenario.conditions.current_speed == pytest.approx(1.286, abs=1e-3)  # 2.5 kn
    assert math.degrees(scenario.conditions.current_direction) == pytest.approx(225.0)  # sets towards SW
    assert math.degrees(scenario.conditions.wind_direction) == pytest.approx(315.0)  # blows from NW
    assert observation[OBS_CROSS_TRACK] == 0.0 and observation[OBS_HEADING_ERROR] == 0.0
    assert observation[OBS_NEXT_CHANGE] == pytest.approx(75.0 / 180.0)
    assert observation[OBS_WAYPOINT_DISTANCE] == pytest.approx(2.0)
    assert info["leg"] == 0 and info["cross_track_error"] == 0.0 and info["metrics"]["samples"] == 1


def test_zero_rudder_on_a_straight_leg_in_still_water_keeps_zero_cross_track_error():
    env = TrackFollowEnv(disturbance="calm", effects=NO_WIND_EFFECTS, sensor_noise_scale=0.0)
    env.reset(seed=3, options={"track": "T2"})
    for _ in range(300):  # 2.8 km of the first 4.1-km leg, before its turn
        observation, reward, terminated, _, info = env.step(np.zeros(1, dtype=np.float32))
        assert info["cross_track_error"] == 0.0 and observation[OBS_CROSS_TRACK] == 0.0 and reward == 0.0
    assert not terminated and info["leg"] == 0 and info["metrics"]["rms_cross_track_error"] == 0.0
    assert info["state"][S.NORTH] == pytest.approx(300.0 * env.task.model.service_speed)


def test_a_pd_with_cross_track_correction_sails_every_track_to_its_end_and_is_scored():
    """The task is feasible: a naive PD finishes T1..T6 in the thesis's conditions, nearer than the
    navigators' 95 m; the score at the end equals ``track_metrics`` of the recorded run."""
    env = gym.make(ENV_ID)
    scores = {}
    for track_id in TRACK_IDS:
        observation, info = env.reset(seed=1, options={"track": track_id})
        controller = TrackPD(env.unwrapped.task)
        states, terminated, truncated = [info["state"]], False, False
        while not (terminated or truncated):
            observation, _, terminated, truncated, info = env.step(controller(observation))
            states.append(info["state"])
        assert terminated and info["leg"] == 5
        states = np.array(states)
        expected = track_metrics(
            states[:, S.TIME],
            states[:, S.NORTH],
            states[:, S.EAST],
            states[:, S.RUDDER],
            env.unwrapped.task.tracks[track_id],
        )
        assert info["metrics"] == pytest.approx(expected, rel=1e-12)
        score = info["score"]
        assert score["rms_cross_track_error"] == info["metrics"]["rms_cross_track_error"]
        assert {name: score[f"thesis_{name}"] for name in THESIS_NAVIGATOR_RMS} == THESIS_NAVIGATOR_RMS
        scores[track_id] = score["rms_cross_track_error"]
    assert max(scores.values()) < THESIS_NAVIGATOR_RMS["ground_speed_vector"], scores


def test_vector_env_equals_single_envs_through_terminations_and_autoresets():
    """Sub-env i of a batch seeded s is a single env seeded s + i: PD-steered ships finish their
    (random) tracks at different steps, restart, and one is reset alone."""
    num_envs, seed = 3, 4
    vector = TrackFollowVectorEnv(num_envs=num_envs)
    singles = [TrackFollowEnv() for _ in range(num_envs)]
    controllers = [TrackPD(vector.task) for _ in range(num_envs)]

    def policy(observations: np.ndarray) -> np.ndarray:
        return np.stack(
            [controller(observation) for controller, observation in zip(controllers, observations, strict=True)]
        )

    episodes, elapsed = assert_vector_equals_singles(vector, singles, policy, 3000, seed, partial_reset_at=100)
    assert episodes.tolist() == [1, 1, 1], "every ship should have finished its track once"
    assert len(set(elapsed)) == num_envs, "the ships should have finished at different steps"


def test_a_ship_with_twice_the_gain_diverges_and_ends_only_its_own_episode():
    """With a speed-loss gain of 5 (the preset's 0.8) the reference tracks' turns at the rudder limit stay
    valid; a ship of twice the K* (as ``ship_variation`` may draw) turns too tight for the model."""
    options = {"ship_parameters": {"speed_loss.gain": 5.0}, "disturbance": "calm"}
    assert_a_diverging_ship_ends_alone(
        TrackFollowVectorEnv, TrackFollowEnv(**options), seed=4, conditions=Conditions(yaw_gain_factor=2.0), **options
    )


@pytest.mark.slow
def test_vector_env_truncates_and_the_parallel_update_equals_the_serial_one():
    assert_all_core_vector_truncates_like_a_single_env(ENV_ID, TrackFollowVectorEnv, TrackFollowEnv(), 8)


def test_discrete_levels_order_rudder_angles_from_port_to_starboard_hard_over():
    env = TrackFollowEnv(action_type="discrete", rudder_levels=5, sensor_noise_scale=0.0)
    env.reset(seed=0)
    for _ in range(10):
        _, _, _, _, info = env.step(np.int64(3))
    assert info["state"][S.RUDDER] == pytest.approx(math.radians(5.0))
    vector = TrackFollowVectorEnv(num_envs=2, action_type="discrete", rudder_levels=5)
    vector.reset(seed=0)
    for _ in range(10):
        _, _, _, _, info = vector.step(np.array([0, 4]))
    np.testing.assert_allclose(info["state"][:, S.RUDDER], np.radians([-10.0, 10.0]))


def test_unknown_options_and_tracks_raise():
    with pytest.raises(ValueError, match="track"):
        TrackFollowEnv(track="T7")
    env = TrackFollowEnv()
    with pytest.raises(ValueError, match="unknown keys"):
        env.reset(seed=0, options={"course_change_deg": 10.0})
    with pytest.raises(ValueError, match="track"):
        env.reset(seed=0, options={"track": "t1"})


# -- training options: decision interval, starts before a turn, bounded reward --------------------


def test_a_decision_interval_holds_the_order_and_sums_the_rewards_through_the_terminal_step():
    """An env deciding every 5 steps sails exactly as the plain env given each order 5 times: the
    same states and observations, the rewards summed per decision, and at the terminal decision
    the record of the terminal step (score and metrics), not of the steps sailed after it."""
    interval, seed = 5, 7
    held = TrackFollowEnv(decision_interval=interval, start="before_turn")
    plain = TrackFollowEnv(start="before_turn")
    observation, info = held.reset(seed=seed)
    plain_observation, plain_info = plain.reset(seed=seed)
    assert info["scenario"] == plain_info["scenario"]
    controller = TrackPD(held.task)
    terminated = False
    decisions = 0
    while not terminated:
        action = controller(observation)
        observation, reward, terminated, _, info = held.step(action)
        decisions += 1
        summed = 0.0
        for _ in range(interval):
            plain_observation, plain_reward, plain_terminated, _, plain_info = plain.step(action)
            summed += plain_reward
            if plain_terminated:
                break
        assert terminated == plain_terminated
        assert reward == pytest.approx(summed, rel=1e-12, abs=1e-12)
        np.testing.assert_array_equal(observation, plain_observation)
        assert info["metrics"] == plain_info["metrics"] and info["leg"] == plain_info["leg"]
        assert decisions < 1000, "the PD should finish the track"
    assert info["score"] == plain_info["score"]
    assert info["state"][S.TIME] > plain_info["state"][S.TIME], "the ship ended within the interval"


@pytest.mark.slow
def test_vector_env_with_a_decision_interval_and_starts_before_turns_equals_single_envs():
    num_envs, seed = 3, 2
    options = {"decision_interval": 4, "start": "before_turn"}
    vector = TrackFollowVectorEnv(num_envs=num_envs, **options)
    singles = [TrackFollowEnv(**options) for _ in range(num_envs)]
    controllers = [TrackPD(vector.task) for _ in range(num_envs)]

    def policy(observations: np.ndarray) -> np.ndarray:
        return np.stack(
            [controller(observation) for controller, observation in zip(controllers, observations, strict=True)]
        )

    episodes, _ = assert_vector_equals_singles(vector, singles, policy, 700, seed, partial_reset_at=50)
    assert episodes.min() >= 1, "every ship should have finished its track"


def test_starts_before_a_turn_are_seeded_and_lie_1_to_1_6_nm_before_a_legs_end_on_its_course():
    env = TrackFollowEnv(start="before_turn", sensor_noise_scale=0.0)
    legs = set()
    for seed in range(40):
        observation, info = env.reset(seed=seed)
        scenario = info["scenario"]
        assert env.reset(seed=seed)[1]["scenario"] == scenario
        track = env.task.tracks[scenario.track]
        leg = info["leg"]
        legs.add(leg)
        assert leg < 5 and scenario.initial_heading == pytest.approx(track.courses[leg])
        state = info["state"]
        assert (state[S.NORTH], state[S.EAST]) == (scenario.initial_north, scenario.initial_east)
        to_end = track.waypoints[leg + 1] - np.array([state[S.NORTH], state[S.EAST]])
        along = to_end @ [math.cos(track.courses[leg]), math.sin(track.courses[leg])]
        assert 1.0 <= along / NAUTICAL_MILE <= 1.6 and np.linalg.norm(to_end) == pytest.approx(along)
        assert observation[OBS_WAYPOINT_DISTANCE] == pytest.approx(along / NAUTICAL_MILE, abs=1e-6)
        assert observation[OBS_HEADING_ERROR] == 0.0 and abs(info["cross_track_error"]) < 1e-6
    assert legs == {0, 1, 2, 3, 4}
    first = TrackFollowEnv().reset(seed=0)[1]
    assert first["scenario"].initial_north == 0.0 and first["leg"] == 0, "the default start stays the origin"


def test_the_cross_track_reward_bound_caps_a_lost_ships_cost():
    bounded, plain = TrackFollowEnv(cross_track_reward_bound=1.0), TrackFollowEnv()
    bounded.reset(seed=5, options={"track": "T3"})
    plain.reset(seed=5, options={"track": "T3"})
    length = bounded.task.model.length
    lost = False
    for _ in range(400):  # hard to starboard: the ship circles off the first leg
        _, reward, _, _, info = bounded.step(np.ones(1, dtype=np.float32))
        _, plain_reward, _, _, _ = plain.step(np.ones(1, dtype=np.float32))
        relative = abs(info["cross_track_error"]) / length
        travel = plain_reward + relative**2  # the rudder travel's share, the same in both
        assert reward == pytest.approx(travel - min(relative, 1.0) ** 2, abs=1e-9)
        lost |= relative > 1.5
    assert lost


@pytest.mark.parametrize(
    ("options", "message"),
    [
        ({"decision_interval": 0}, "decision_interval: .* got 0"),
        ({"decision_interval": 2.5}, "decision_interval: .* got 2.5"),
        ({"start": "middle"}, "start: .* got 'middle'"),
        ({"cross_track_reward_bound": -1.0}, r"cross_track_reward_bound: .* got -1.0"),
    ],
)
def test_bad_training_options_raise_naming_the_key_and_value(options, message):
    with pytest.raises(ValueError, match=message):
        TrackFollowEnv(**options)
