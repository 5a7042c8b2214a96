"""Perera et al. (2015) reproduced: their EKF on their model (13) with their parameters.

Published: with a white-noise ("violent") rudder the estimates reach the actual values, a1, b1, b2
in under 1500 s and a2, a3 by about 3500 s; with zig-zag or turning manoeuvres they do not. Here:
the violent rudder does it (faster than published); the zig-zag sailed with a steering machine's
5 deg/s does not, but neither does the violent rudder with that steering machine, while the zig-zag
with the violent rudder's fast actuator does: the rudder rate decides, not the programme.
"""

from __future__ import annotations

import dataclasses
import math

import pytest

from ship_env.baselines.online_estimators.criteria import final_errors, settling_times
from ship_env.baselines.online_estimators.excitation import ZigZag
from ship_env.baselines.online_estimators.perera_ekf import PereraFilter, PereraFilterNoise
from ship_env.baselines.online_estimators.perera_model import (
    PUBLISHED,
    STEERING_MACHINE_RATE,
    VIOLENT_RUDDER,
    PereraSetting,
    simulate,
)

#: Perera's conclusion: a1, b1, b2 converged in less than 1500 s, a2, a3 around 3500 s.
PUBLISHED_TIMES = {"a1": 1500.0, "b1": 1500.0, "b2": 1500.0, "a2": 3500.0, "a3": 3500.0}
DURATION = 3500.0
FAST = PereraSetting()
STEERING_MACHINE = PereraSetting(rudder_rate_limit=STEERING_MACHINE_RATE)
ZIGZAG = ZigZag(math.radians(20.0), math.radians(20.0))


def identify(programme, setting: PereraSetting, seed: int = 0, duration: float = DURATION, **options):
    trial = simulate(programme, duration, setting=setting, seed=seed)
    history = PereraFilter(PUBLISHED.scaled(0.5), PereraFilterNoise.matched(setting), **options).run(trial.log)
    return trial, history


def within_published_times(settling: dict[str, float | None]) -> bool:
    return all(settling[name] is not None and settling[name] <= limit for name, limit in PUBLISHED_TIMES.items())


def violent(seed: int):
    return dataclasses.replace(VIOLENT_RUDDER, seed=seed)


@pytest.mark.slow
@pytest.mark.parametrize("seed", [0, 1, 2])
def test_violent_rudder_finds_the_published_parameters_in_the_published_times(seed):
    trial, history = identify(violent(seed), FAST, seed)
    settling = settling_times(history, trial.truth)
    print(f"seed {seed}: within 10 % after {settling}; final {history.final()}")
    assert within_published_times(settling)
    assert max(final_errors(history, trial.truth).values()) < 0.10


@pytest.mark.slow
def test_zigzag_with_a_steering_machine_does_not():
    """The paper's second conclusion holds for a zig-zag sailed with a ship's steering machine (5 deg/s)."""
    trial, history = identify(ZIGZAG, STEERING_MACHINE)
    settling = settling_times(history, trial.truth)
    errors = final_errors(history, trial.truth)
    print(f"within 10 % after {settling}; final errors {errors}")
    assert not within_published_times(settling)
    assert min(errors[name] for name in ("a2", "a3", "b1")) > 0.10


@pytest.mark.slow
def test_the_rudder_rate_decides_not_the_programme():
    """With the violent rudder's fast actuator (40 deg/s) the zig-zag finds a2, a3, b1 within the hour too;
    with the steering machine the violent rudder does not."""
    trial, history = identify(ZIGZAG, FAST)
    settling = settling_times(history, trial.truth)
    print(f"zig-zag, fast actuator: {settling}")
    assert all(settling[name] is not None for name in ("a2", "a3", "b1"))
    trial, history = identify(violent(0), STEERING_MACHINE)
    settling = settling_times(history, trial.truth)
    print(f"violent rudder, steering machine: {settling}")
    assert settling["a2"] is None and settling["a3"] is None


def test_the_printed_rudder_model_biases_b2_by_half_a_sample():
    """(16) holds delta constant over the sample; the rudder moves, and b2 absorbs most of b1 T_s / 2
    (+14 %; the filter spreads the rest of the model error over the other parameters)."""
    _, printed = identify(violent(0), FAST, duration=300.0, rudder_integrates_rate=False)
    trial, improved = identify(violent(0), FAST, duration=300.0)
    expected = (PUBLISHED.b2 + PUBLISHED.b1 * FAST.sample_time / 2.0) / PUBLISHED.b2 - 1.0
    printed_bias = printed.final()["b2"] / PUBLISHED.b2 - 1.0
    print(
        f"b2 bias as printed {printed_bias:+.3f} (b1 T_s / 2 predicts {expected:+.3f}); "
        f"improved {improved.final()['b2']:.4f}"
    )
    assert 0.5 * expected < printed_bias < 1.2 * expected
    assert final_errors(improved, trial.truth)["b2"] < 0.02
