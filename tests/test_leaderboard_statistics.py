"""The leaderboard's statistics on synthetic scores: rliable's IQM and probability of improvement,
intervals that repeat to the last digit, "beats" only when the interval excludes parity, no made-up interval."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from rliable import metrics

from ship_env.leaderboard.sailing import EpisodeResult
from ship_env.leaderboard.statistics import PARITY
from ship_env.leaderboard.suites import COURSE_CHANGE, NOMINAL, Suite, course_change_episodes
from ship_env.leaderboard.tables import comparisons, first_place_markdown, markdown, rank, score_matrix

REFERENCE = "PD, fixed gains"
#: Ten course changes (15..105 deg both ways) in calm water.
SUITE = Suite(
    "CourseChange calm",
    COURSE_CHANGE,
    {"disturbance": "calm"},
    NOMINAL,
    course_change_episodes((15, 30, 45, 75, 105), 1),
)
#: The classic autopilot's integrated heading error per episode: it grows with the change.
CLASSIC_SCORES = np.array([300.0, 310.0, 700.0, 690.0, 1100.0, 1120.0, 2000.0, 1950.0, 2900.0, 3000.0])


def _results(name, kind, scores, training_seeds=(None,), travel=400.0):
    """Episode results of one entrant: ``scores`` (training seeds x episodes)."""
    scores = np.atleast_2d(scores)
    return [
        EpisodeResult(
            SUITE.name,
            name,
            kind,
            training_seed,
            episode.label,
            episode.seed,
            {
                "integrated_heading_error": float(score),
                "overshoot": 0.0,
                "settling_time": 60.0,
                "rudder_travel": travel,
            },
            True,
        )
        for training_seed, row in zip(training_seeds, scores, strict=True)
        for episode, score in zip(SUITE.episodes, row, strict=True)
    ]


def _learned(name, factor, noise, seeds=5):
    """A learned entrant ``factor`` times the classic autopilot's score, with a relative spread ``noise``."""
    spread = np.random.default_rng(len(name)).normal(0.0, noise, (seeds, len(SUITE.episodes)))
    return _results(name, "learned", CLASSIC_SCORES * factor * (1.0 + spread), tuple(range(seeds)), travel=200.0)


def _board(*learned):
    return rank(SUITE, _results(REFERENCE, "classic", CLASSIC_SCORES) + [r for results in learned for r in results])


def test_iqm_and_probability_of_improvement_are_rliables():
    results = _learned("PPO (a)", 0.97, 0.05)
    table = _board(results)
    scores = score_matrix(SUITE, results)
    assert scores.shape == (5, 10)
    standing = table.standing("PPO (a)")
    assert standing.score.value == pytest.approx(metrics.aggregate_iqm(scores), rel=1e-12)
    assert standing.normalised.value == pytest.approx(metrics.aggregate_iqm(scores / CLASSIC_SCORES), rel=1e-12)
    improvement = metrics.probability_of_improvement(-scores, -CLASSIC_SCORES[None, :])  # rliable: higher is better
    assert standing.improvement.value == pytest.approx(improvement, rel=1e-12)
    assert standing.score.low < standing.score.value < standing.score.high
    assert standing.sample == "5 seeds x 10 episodes"


def test_the_same_scores_give_the_same_table_and_intervals_to_the_last_digit():
    """Whatever numpy's global generator held before, and it holds the same after."""
    np.random.seed(1)
    state = np.random.get_state()
    first = _board(_learned("PPO (a)", 0.97, 0.05))
    assert np.array_equal(np.random.get_state()[1], state[1])
    np.random.rand(17)
    second = _board(_learned("PPO (a)", 0.97, 0.05))
    assert markdown(first) == markdown(second)
    assert first.standings == second.standings


def test_beats_only_when_the_interval_excludes_parity():
    """1 % better with a 5 % spread: no winner. 30 % better with the same spread: a winner."""
    table = _board(_learned("PPO (close)", 0.99, 0.05), _learned("PPO (clear)", 0.70, 0.05))
    verdicts = {c.learned: c for c in comparisons(table)}
    close, clear = verdicts["PPO (close)"], verdicts["PPO (clear)"]
    assert close.score_ratio < 1.0  # better on the IQM...
    assert close.improvement.low <= PARITY <= close.improvement.high  # ...by less than the noise
    assert not close.beats
    assert clear.improvement.low > PARITY and clear.beats
    text = markdown(table)
    assert "PPO (close) against the best classic autopilot, PD, fixed gains" in text
    assert text.count("beats it (the interval lies above parity, 0.5)") == 1
    assert "does not beat it (the interval includes parity, 0.5)" in text


def test_a_clearly_worse_entrant_is_said_to_be_worse():
    (comparison,) = comparisons(table := _board(_learned("PPO (worse)", 1.3, 0.05)))
    assert comparison.improvement.high < PARITY and not comparison.beats
    assert "does not beat it (the interval lies below parity, 0.5: it is worse)" in markdown(table)


def test_a_classic_autopilots_interval_comes_from_its_episodes():
    """...and one better than the best on 8 of the 10 episodes improves on it with probability 0.8."""
    better = CLASSIC_SCORES * np.where(np.arange(10) < 8, 0.99, 1.01)
    table = rank(SUITE, _results(REFERENCE, "classic", CLASSIC_SCORES) + _results("MRAC", "classic", better))
    assert table.standing("MRAC").improvement is None  # the best classic autopilot now
    assert table.standing(REFERENCE).improvement.value == pytest.approx(0.2)
    assert table.standing(REFERENCE).improvement.low < PARITY
    standing = _board().standing(REFERENCE)
    assert standing.seeds == 1 and standing.sample == "10 episodes (deterministic)"
    assert standing.score.low < metrics.aggregate_iqm(CLASSIC_SCORES) < standing.score.high
    assert standing.normalised.value == standing.normalised.low == standing.normalised.high == 1.0


def test_one_seed_gets_an_interval_over_its_episodes_only():
    table = _board(_learned("PPO (one seed)", 0.97, 0.05, seeds=1))
    standing = table.standing("PPO (one seed)")
    assert standing.score.has_interval and standing.sample == "1 seed x 10 episodes (episodes only)"


def test_one_seed_and_one_episode_get_no_interval():
    suite = Suite(SUITE.task, SUITE.env_id, SUITE.env_kwargs, NOMINAL, SUITE.episodes[:1])
    results = [r for r in _results(REFERENCE, "classic", CLASSIC_SCORES) if r.episode == suite.episodes[0].label]
    results += [r for r in _learned("PPO (one)", 0.5, 0.0, seeds=1) if r.episode == suite.episodes[0].label]
    table = rank(suite, results)
    standing = table.standing("PPO (one)")
    assert not standing.score.has_interval and standing.score.low is None
    assert standing.sample == "1 x 1: no interval"
    (comparison,) = comparisons(table)
    assert comparison.improvement.value == 1.0 and not comparison.beats
    text = markdown(table)
    assert "150.0 (no interval)" in text and "no verdict (no interval: a single score)" in text


def _unsettled(results, training_seed, label):
    """``results`` with the episode ``label`` of ``training_seed`` never settled."""
    return [
        dataclasses.replace(r, metrics={**r.metrics, "settling_time": math.inf})
        if (r.training_seed, r.episode) == (training_seed, label)
        else r
        for r in results
    ]


def test_first_place_needs_the_rank_or_the_firsts_interval_the_travel_and_the_settling():
    """Against an adaptive autopilot 5 % better than the reference with a spread: 4 % better is
    inside its interval, 10 % worse is not; first with twice its rudder travel, or first with one
    seed that never settles a course change the autopilots settle, does not hold first place; the
    verdicts do not depend on the other learned entrants."""
    spread = np.random.default_rng(3).normal(0.0, 0.05, len(CLASSIC_SCORES))
    adaptive = _results("MRAC", "classic", CLASSIC_SCORES * 0.95 * (1.0 + spread), travel=150.0)
    learned = {
        "close": _learned("PPO (close)", 0.96, 0.002),
        "worse": _learned("PPO (worse)", 1.10, 0.002),
        "busy": _results("PPO (busy)", "learned", CLASSIC_SCORES * 0.5, (0,), travel=300.0),
        "unsettled": _unsettled(_learned("PPO (unsettled)", 0.5, 0.002), 3, "+45 deg"),
        "first": _learned("PPO (first)", 0.5, 0.002),
    }
    table = rank(SUITE, _results(REFERENCE, "classic", CLASSIC_SCORES) + adaptive + sum(learned.values(), []))
    verdicts = {c.learned.split("(")[1][:-1]: c for c in comparisons(table)}
    mrac = table.standing("MRAC").normalised
    assert mrac.low < table.standing("PPO (close)").normalised.value < mrac.high
    assert table.standing("PPO (close)").rank > table.standing("MRAC").rank
    assert {name for name, c in verdicts.items() if c.within_first} == {"close", "busy", "unsettled", "first"}
    assert verdicts["busy"].travel_ratio == 2.0 and verdicts["close"].travel_ratio == pytest.approx(200.0 / 150.0)
    assert not verdicts["unsettled"].settles and table.standing("PPO (unsettled)").completed == 49
    assert {name for name, c in verdicts.items() if c.holds_first} == {"close", "first"}
    text = first_place_markdown([table])
    assert "PPO (first) holds first place on 1 of the 1 ship_env/CourseChange-v0 suites." in text
    assert "PPO (worse) holds first place on 0 of the 1" in text
    alone = rank(SUITE, _results(REFERENCE, "classic", CLASSIC_SCORES) + adaptive + learned["close"])
    assert [c.holds_first for c in comparisons(alone)] == [True]
