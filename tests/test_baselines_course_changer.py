"""The predictor-based course changer on TrackFollow-v0 (thesis 6.4.4.2, Table 6.4)."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest

import ship_env  # noqa: F401  (registers the environments)
from ship_env.baselines.presys import track_follow_controller
from ship_env.envs.tracks import TRACK_IDS

#: Table 6.4: the navigators' mean RMS track error with the track predictor, m.
THESIS_TRACK_PREDICTOR_RMS = 33.0


def sail(track: str, seed: int) -> dict:
    env = gym.make("ship_env/TrackFollow-v0", track=track)
    controller = track_follow_controller(env.unwrapped.task)
    observation, info = env.reset(seed=seed)
    controller.reset(observation, info)
    terminated = truncated = False
    while not (terminated or truncated):
        observation, _, terminated, truncated, info = env.step(controller.act(observation, info))
    assert terminated, f"{track}: the ship did not reach the last waypoint"
    return info["score"] | {"max_cross_track_error": info["metrics"]["max_cross_track_error"]}


@pytest.fixture(scope="module")
def scores() -> dict[str, dict]:
    return {track: sail(track, seed=0) for track in TRACK_IDS}


def test_predictor_based_course_changer_sails_t2_nearer_than_the_thesis_navigators_with_the_predictor():
    """Each track's RMS error lies below the navigators' mean (the six tracks: the slow test below)."""
    assert float(sail("T2", seed=0)["rms_cross_track_error"]) < THESIS_TRACK_PREDICTOR_RMS


@pytest.mark.slow
def test_predictor_based_course_changer_beats_the_thesis_navigators_with_the_predictor(scores):
    """Table 6.2 disturbances (2.5 kn current towards SW, 7 m/s wind from NW, gusts), rudder limit 10 deg."""
    rms = {track: float(score["rms_cross_track_error"]) for track, score in scores.items()}
    print(
        "RMS track error (m):",
        ", ".join(
            f"{track} {value:.1f} (max {scores[track]['max_cross_track_error']:.0f})" for track, value in rms.items()
        ),
        f"| mean {np.mean(list(rms.values())):.1f} against the thesis's {THESIS_TRACK_PREDICTOR_RMS:.0f}",
    )
    assert np.mean(list(rms.values())) < THESIS_TRACK_PREDICTOR_RMS
    assert max(rms.values()) < THESIS_TRACK_PREDICTOR_RMS


@pytest.mark.slow
@pytest.mark.parametrize("seed", [1, 2, 3])
def test_course_changer_holds_up_in_other_gusts_and_instrument_noise(seed):
    rms = [float(sail(track, seed)["rms_cross_track_error"]) for track in TRACK_IDS]
    print(f"seed {seed}: " + ", ".join(f"{value:.1f}" for value in rms) + f" | mean {np.mean(rms):.1f}")
    assert np.mean(rms) < THESIS_TRACK_PREDICTOR_RMS


@pytest.mark.parametrize(("track", "seed"), [("T4", 1), ("T1", 4)])
def test_course_changer_starts_on_the_leg_a_before_turn_episode_starts_on(track, seed):
    """``start="before_turn"`` (the leaderboard's test suite) puts the ship on a later leg (T4 seed 1:
    the fifth, T1 seed 4: the third); the course changer keeps to that leg and turns onto the next,
    inside the thesis navigators' RMS as from the first waypoint (not steering for the first leg's course)."""
    env = gym.make("ship_env/TrackFollow-v0", track=track, start="before_turn")
    controller = track_follow_controller(env.unwrapped.task)
    observation, info = env.reset(seed=seed)
    assert info["leg"] > 0
    controller.reset(observation, info)
    terminated = truncated = False
    while not (terminated or truncated):
        observation, _, terminated, truncated, info = env.step(controller.act(observation, info))
    assert terminated
    assert info["score"]["rms_cross_track_error"] < THESIS_TRACK_PREDICTOR_RMS
