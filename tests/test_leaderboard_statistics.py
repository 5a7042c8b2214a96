"""The leaderboard's statistics on synthetic scores: rliable's IQM and probability of improvement,
intervals that repeat to the last digit, better / tied / worse from the interval against parity, no made-up interval."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from rliable import metrics

from ship_env.leaderboard.rendering import markdown, verdicts_markdown
from ship_env.leaderboard.sailing import EpisodeResult
from ship_env.leaderboard.statistics import PARITY
from ship_env.leaderboard.suites import COURSE_CHANGE, NOMINAL, Suite, course_change_episodes
from ship_env.leaderboard.tables import BETTER, TIED, WORSE, comparisons, rank, score_matrix

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


def test_better_only_when_the_interval_lies_above_parity():
    """1 % better with a 5 % spread: tied. 30 % better with the same spread: better."""
    table = _board(_learned("PPO (close)", 0.99, 0.05), _learned("PPO (clear)", 0.70, 0.05))
    verdicts = {c.learned: c for c in comparisons(table)}
    close, clear = verdicts["PPO (close)"], verdicts["PPO (clear)"]
    assert close.score_ratio < 1.0  # better on the IQM...
    assert close.improvement.low <= PARITY <= close.improvement.high  # ...by less than the noise
    assert close.verdict == TIED
    assert clear.improvement.low > PARITY and clear.verdict == BETTER
    text = markdown(table)
    assert "PPO (close) against the best classic autopilot, PD, fixed gains" in text
    assert text.count("better (the interval lies above parity, 0.5)") == 1
    assert "tied (the interval includes parity, 0.5)" in text
    rows = {line.split(" | ")[1]: line for line in text.splitlines() if line.startswith("| ")}
    assert "| tied |" in rows["PPO (close)"] and "| better |" in rows["PPO (clear)"]
    assert "| tied |" not in rows[REFERENCE] and "| better |" not in rows[REFERENCE]  # no verdict on a classic row


def test_a_clearly_worse_entrant_is_said_to_be_worse():
    (comparison,) = comparisons(table := _board(_learned("PPO (worse)", 1.3, 0.05)))
    assert comparison.improvement.high < PARITY and comparison.verdict == WORSE
    assert "worse (the interval lies below parity, 0.5)" in markdown(table)


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
    assert comparison.improvement.value == 1.0 and comparison.verdict == TIED
    text = markdown(table)
    assert "150.0 (no interval)" in text and "tied (no interval: a single score)" in text


def _unsettled(results, training_seed, label):
    """``results`` with the episode ``label`` of ``training_seed`` never settled."""
    return [
        dataclasses.replace(r, metrics={**r.metrics, "settling_time": math.inf})
        if (r.training_seed, r.episode) == (training_seed, label)
        else r
        for r in results
    ]


def _adaptive():
    """An adaptive autopilot 5 % better than the reference, with a 5 % spread over the episodes."""
    spread = np.random.default_rng(3).normal(0.0, 0.05, len(CLASSIC_SCORES))
    return CLASSIC_SCORES * 0.95 * (1.0 + spread)


def test_worse_on_every_episode_is_worse_even_inside_the_best_classics_interval():
    """2 % worse than the best classic autopilot on every episode, with five seeds: its normalised IQM
    lies inside the autopilot's wide interval (where a rule on the IQM's interval, which fewer episodes
    widen, would call it first), but it is worse on every episode: P(improvement) 0, worse."""
    adaptive = _adaptive()
    seeds = np.tile(adaptive * 1.02, (5, 1))
    table = rank(
        SUITE,
        _results(REFERENCE, "classic", CLASSIC_SCORES)
        + _results("MRAC", "classic", adaptive, travel=150.0)
        + _results("PPO (close)", "learned", seeds, tuple(range(5)), travel=150.0),
    )
    mrac, learned = table.standing("MRAC").normalised, table.standing("PPO (close)").normalised
    assert mrac.low < learned.value < mrac.high
    (comparison,) = comparisons(table)
    assert comparison.improvement.value == comparison.improvement.high == 0.0
    assert comparison.verdict == WORSE


def test_better_needs_the_interval_the_travel_and_the_settling_and_ties_are_counted_apart():
    """Against the adaptive autopilot: better on half the episodes and worse on the other half is
    tied (P(improvement) 0.5); half its score with twice its rudder travel, or with one seed that never
    settles a course change the autopilots settle, is tied; half its score within the allowance is
    better; 10 % worse than the reference everywhere is worse. Other learned entrants do not change
    the verdict."""
    adaptive = _adaptive()
    halves = np.where(np.arange(len(CLASSIC_SCORES)) % 2 == 0, 0.99, 1.01)
    learned = {
        "even": _results("PPO (even)", "learned", np.tile(adaptive * halves, (5, 1)), tuple(range(5)), travel=150.0),
        "worse": _learned("PPO (worse)", 1.10, 0.002),
        "busy": _results("PPO (busy)", "learned", CLASSIC_SCORES * 0.5, (0,), travel=300.0),
        "unsettled": _unsettled(_learned("PPO (unsettled)", 0.5, 0.002), 3, "+45 deg"),
        "first": _learned("PPO (first)", 0.5, 0.002),
    }
    mrac = _results("MRAC", "classic", adaptive, travel=150.0)
    table = rank(SUITE, _results(REFERENCE, "classic", CLASSIC_SCORES) + mrac + sum(learned.values(), []))
    verdicts = {c.learned.split("(")[1][:-1]: c for c in comparisons(table)}
    assert {c.classic for c in verdicts.values()} == {"MRAC"}
    assert verdicts["even"].improvement.value == 0.5
    assert verdicts["busy"].travel_ratio == 2.0 and verdicts["busy"].improvement.value == 1.0
    assert not verdicts["unsettled"].settles and table.standing("PPO (unsettled)").completed == 49
    assert {name: c.verdict for name, c in verdicts.items()} == {
        "even": TIED,
        "worse": WORSE,
        "busy": TIED,
        "unsettled": TIED,
        "first": BETTER,
    }
    assert "with more than x1.5 the rudder travel" in verdicts["busy"].reason
    assert "missing an episode a classic autopilot completes" in verdicts["unsettled"].reason
    text = verdicts_markdown([table, table])
    assert "PPO (first) on the ship_env/CourseChange-v0 suites: better on 2, tied on 0, worse on 0 of 2." in text
    assert "PPO (even) on the ship_env/CourseChange-v0 suites: better on 0, tied on 2, worse on 0 of 2." in text
    alone = rank(SUITE, _results(REFERENCE, "classic", CLASSIC_SCORES) + mrac + learned["first"])
    assert [c.verdict for c in comparisons(alone)] == [BETTER]
