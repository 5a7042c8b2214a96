"""The Nomoto estimators on the container ship: Nguyen, Passenier (MRAS, EKF), Song; divergence is flagged."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from ship_env.baselines.filter_health import FilterDivergenceError
from ship_env.baselines.instruments import InstrumentNoise
from ship_env.baselines.online_estimators.adaptation import ForgettingFactor
from ship_env.baselines.online_estimators.criteria import final_errors, settling_times
from ship_env.baselines.online_estimators.excitation import Turning, ZigZag, sail
from ship_env.baselines.online_estimators.least_squares import NguyenRLS
from ship_env.baselines.online_estimators.mras import CombinedMRAS
from ship_env.baselines.online_estimators.passenier_ekf import PassenierEKF
from ship_env.baselines.online_estimators.perera_ekf import PereraFilter
from ship_env.baselines.online_estimators.perera_model import VIOLENT_RUDDER, simulate
from ship_env.baselines.online_estimators.scenarios import (
    GUESS,
    PERERA_GUESS,
    SAMPLE_TIME,
    container,
    gyro_variance,
)
from ship_env.baselines.online_estimators.song_ekf import SongFilter

ZIGZAG = ZigZag(math.radians(20.0), math.radians(20.0))
EXACT = InstrumentNoise(heading=0.0, rate_of_turn=0.0, speed=0.0, position=0.0)


@pytest.fixture(scope="module")
def zigzag_trials():
    """Nguyen's 20/20 zig-zag, 1200 s, on the first-order Nomoto ship, with the environments' instruments."""
    return {seed: sail(container(), ZIGZAG, 1200.0, SAMPLE_TIME, seed=seed) for seed in (0, 1)}


def nomoto_errors(estimator, trial) -> dict[str, float]:
    """|relative error| of K and T at the end (of K*, tau*: the same at constant speed)."""
    return final_errors(estimator.run(trial.log), trial.truth)


@pytest.mark.parametrize("seed", [0, 1])
def test_nguyen_finds_K_and_T_within_5_percent_on_a_20_20_zigzag(zigzag_trials, seed):
    """Nguyen's RLS (lambda 0.995, P(0) = 1e3 I): his two-output model on exact instruments, and the
    r-row alone on the environments' instruments (the heading regressor amplifies the noise bias, below)."""
    model = container()
    exact = sail(model, ZIGZAG, 1200.0, SAMPLE_TIME, noise=EXACT, seed=seed)
    two_outputs = nomoto_errors(NguyenRLS(model.length, GUESS), exact)
    rate_only = nomoto_errors(NguyenRLS(model.length, GUESS, include_heading=False), zigzag_trials[seed])
    print(f"seed {seed}: (r, psi) exact instruments {two_outputs}; r only, instruments' noise {rate_only}")
    assert max(two_outputs.values()) < 0.05
    assert max(rate_only.values()) < 0.05


def test_gyro_noise_biases_nguyens_time_constant_and_the_heading_regressor_amplifies_it(zigzag_trials):
    """Equation error (series-parallel) with a noisy r(k-1) regressor: T comes out short (thesis 4.4.3).
    With psi(k-1) in the regression as well the bias passes 5 %."""
    trial = zigzag_trials[0]
    two_outputs = nomoto_errors(NguyenRLS(trial.length, GUESS, ForgettingFactor(1.0)), trial)
    rate_only = nomoto_errors(NguyenRLS(trial.length, GUESS, ForgettingFactor(1.0), include_heading=False), trial)
    print(f"(r, psi): {two_outputs}; r only: {rate_only}")
    assert two_outputs["tau*"] > 0.05 > rate_only["tau*"] > 0.01


def test_mras_combined_is_fast_like_series_parallel_and_unbiased_like_parallel(zigzag_trials):
    """Thesis 4.4.3-4.4.4: Series-Parallel converges fastest but is biased by the noise, Parallel rejects
    the noise but converges slowly, the combined identifier has the speed of the one and the accuracy of the other."""
    results = {}
    for seed, trial in zigzag_trials.items():
        for observation in ("series-parallel", "combined", "parallel"):
            mras = CombinedMRAS(trial.length, GUESS, ForgettingFactor(1.0), gyro_variance(), observation=observation)
            history = mras.run(trial.log)
            results[seed, observation] = (
                max(settling_times(history, trial.truth).values()),
                final_errors(history, trial.truth)["tau*"],
            )
    print(results)
    for seed in zigzag_trials:
        series, combined, parallel = (results[seed, name] for name in ("series-parallel", "combined", "parallel"))
        assert series[0] < combined[0] < parallel[0]
        assert series[1] > 1.5 * combined[1]
        assert combined[0] < 150.0 and combined[1] < 0.02


def test_song_and_passenier_ekfs_identify_the_ship(zigzag_trials):
    for trial in zigzag_trials.values():
        for estimator, deadline in (
            (SongFilter(trial.length, GUESS), 120.0),
            (PassenierEKF(trial.length, GUESS), 300.0),
        ):
            history = estimator.run(trial.log)
            settled = settling_times(history, trial.truth)
            print(estimator.name, settled, history.final())
            assert max(settled.values()) < deadline
            assert max(final_errors(history, trial.truth).values()) < 0.03


def test_songs_guard_as_printed_wrecks_the_filter(zigzag_trials):
    """gamma = 1 in (22): the guard acts on a third of the samples of a consistent filter and inflates the
    parameters' covariance each time: tau* ends far off or is no ship at all (the default gamma = 25
    leaves a consistent filter alone)."""
    for seed, trial in zigzag_trials.items():
        try:
            errors = nomoto_errors(SongFilter(trial.length, GUESS, reserve=1.0), trial)
        except FilterDivergenceError as error:
            print(f"seed {seed}: {error}")
            assert "no ship" in str(error)
        else:
            print(f"seed {seed}: final errors {errors}")
            assert errors["tau*"] > 0.5


def test_every_estimator_flags_divergence_instead_of_returning_nan(zigzag_trials):
    trial = zigzag_trials[0]
    length = trial.length
    compass_three_times = dataclasses.replace(trial.log, heading=3.0 * trial.log.heading)
    straight = sail(container(), Turning(0.0), 600.0, SAMPLE_TIME).log
    perera = simulate(VIOLENT_RUDDER, 200.0).log
    compass_jump = dataclasses.replace(
        perera, heading=perera.heading + np.where(perera.time > 100.0, math.radians(30.0), 0.0)
    )
    cases = [
        (NguyenRLS(length, GUESS, ForgettingFactor(0.95)), trial.log, "wind-up"),
        (CombinedMRAS(length, GUESS, ForgettingFactor(0.98), gyro_variance()), straight, "F's trace"),
        (SongFilter(length, GUESS), compass_three_times, "no ship"),
        (PassenierEKF(length, GUESS), compass_three_times, "innovations in a row outside the gate"),
        (PereraFilter(PERERA_GUESS), compass_jump, "innovations in a row outside the gate"),
    ]
    for estimator, log, reason in cases:
        with pytest.raises(FilterDivergenceError, match=reason):
            estimator.run(log)
    for estimator in (NguyenRLS(length, GUESS), CombinedMRAS(length, GUESS, ForgettingFactor(1.0), gyro_variance())):
        history = estimator.run(straight)
        assert np.all(np.isfinite(history.values))
