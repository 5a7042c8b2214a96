"""CleanRL's single-file PPO, as ``benchmarks/cleanrl_ppo_continuous.py`` writes it, trains on the id alone."""

from __future__ import annotations

from pathlib import Path

import pytest

SCRIPT = Path(__file__).resolve().parents[1] / "benchmarks" / "cleanrl_ppo_continuous.py"
pytest.importorskip("torch")


def test_the_script_trains_through_the_standard_wrappers_and_sees_the_time_limit(load_script):
    script = load_script(SCRIPT, "cleanrl_ppo_continuous")
    # Two sub-environments, one rollout of 650 steps each: each finishes one 600-step episode (the
    # registration's time limit, seen through RecordEpisodeStatistics), then one update.
    result = script.main(
        ["--total-timesteps", "1300", "--num-envs", "2", "--num-steps", "650", "--num-minibatches", "2"]
        + ["--update-epochs", "1", "--quiet"]
    )
    assert result["steps"] == 1300
    assert [length for _, _, length in result["episodes"]] == [600, 600]
    # The rewards are negative (heading error and rudder travel) and the returns unnormalised.
    assert all(episode_return < 0.0 for _, episode_return, _ in result["episodes"])


@pytest.mark.slow
def test_record_video_writes_the_first_episode(load_script, tmp_path):
    pytest.importorskip("moviepy")
    script = load_script(SCRIPT, "cleanrl_ppo_continuous")
    result = script.main(
        ["--total-timesteps", "1300", "--num-envs", "2", "--num-steps", "650", "--num-minibatches", "2"]
        + ["--update-epochs", "1", "--quiet", "--capture-video", "--video-folder", str(tmp_path)]
    )
    assert [video.name for video in result["videos"]] == ["rl-video-episode-0.mp4"]
    assert result["videos"][0].stat().st_size > 10_000
