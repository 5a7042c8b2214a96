"""Stelling 5 put to the test: random-walk parameters against a forgetting factor tuned to the same steady-state noise.

The thesis's claim (stelling 5; 4.5.3): additive system noise on the parameters (a random walk,
4.108) is the better-founded way to keep an estimator adapting than a multiplicative forgetting
factor (4.64). Either one trades noise for tracking speed, so the comparison is made at equal noise:

1. on a calibration run of a ship that does not change, the random-walk estimator's steady-state
   noise is measured: sum over the parameters of the variance of theta^_i / theta_i over the
   samples from ``steady_from`` on (the spread of the estimates, not their bias, which belongs to
   the estimator's model, not to its adaptation);
2. the forgetting factor lambda that gives the forgetting estimator the same steady-state noise on
   the same run is found by bisection on log(1 - lambda) (where no lambda gives it, because the
   forgetting estimator's noise jumps as its covariance winds up, the comparison says so);
3. both then run on a ship that changes (the same programme, a loading or speed change at
   ``change_time``), and their J_p (thesis 6.1) from the change to the end, and the time they need
   to come back within 10 %, are compared: lower J_p tracks better.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ship_env.baselines.filter_health import FilterDivergenceError
from ship_env.baselines.online_estimators.criteria import parameter_criterion, settling_times
from ship_env.baselines.online_estimators.estimator import Estimator
from ship_env.baselines.online_estimators.excitation import Trial
from ship_env.baselines.online_estimators.history import ParameterHistory

#: The bisection's bracket for lambda and its number of halvings.
FORGETTING_BRACKET = (0.9, 0.999999)
BISECTION_STEPS = 24
#: Steady-state noises within this ratio of each other count as matched.
MATCH_TOLERANCE = 1.25


def steady_state_noise(estimate: ParameterHistory, truth: ParameterHistory, start: float) -> float:
    """Sum over the parameters of var(theta^_i / theta_i) over the samples at or after ``start``."""
    late = estimate.time >= start
    return float(np.sum(np.var(estimate.values[late] / truth.values[late], axis=0)))


def match_forgetting(
    make_forgetting: Callable[[float], Estimator], calibration: Trial, steady_from: float, target_noise: float
) -> float:
    """The lambda whose estimator has ``target_noise`` on ``calibration`` (noise falls as lambda rises).

    A lambda at which the estimator diverges counts as infinitely noisy.
    """

    def noise(factor: float) -> float:
        try:
            history = make_forgetting(factor).run(calibration.log)
        except FilterDivergenceError:
            return math.inf
        return steady_state_noise(history, calibration.truth, steady_from)

    low, high = (
        math.log(1.0 - factor) for factor in reversed(FORGETTING_BRACKET)
    )  # log(1 - lambda), low = long memory
    for _ in range(BISECTION_STEPS):
        middle = 0.5 * (low + high)
        if noise(1.0 - math.exp(middle)) > target_noise:
            high = middle
        else:
            low = middle
    return 1.0 - math.exp(0.5 * (low + high))


@dataclass(frozen=True, eq=False)
class AdaptationResult:
    """One estimator in the comparison.

    Attributes:
        name: the estimator's.
        steady_noise: its steady-state noise on the calibration run.
        tracking_criterion: J_p (6.1) on the changing run from the change to the end, s.
        recovery_time: s after the change until it stays within 10 %; None if it does not.
        history: its estimates on the changing run.
    """

    name: str
    steady_noise: float
    tracking_criterion: float
    recovery_time: float | None
    history: ParameterHistory


@dataclass(frozen=True, eq=False)
class AdaptationComparison:
    """The random-walk and the matched forgetting estimator, and the matched lambda."""

    random_walk: AdaptationResult
    forgetting: AdaptationResult
    forgetting_factor: float

    @property
    def random_walk_tracks_better(self) -> bool:
        return self.random_walk.tracking_criterion < self.forgetting.tracking_criterion

    @property
    def noise_matched(self) -> bool:
        """Whether the bisection found a lambda with the random walk's steady-state noise (within
        :data:`MATCH_TOLERANCE`); it does not where the forgetting estimator's noise jumps from
        below to far above the target between two neighbouring lambda (its covariance winds up)."""
        ratio = self.forgetting.steady_noise / self.random_walk.steady_noise
        return 1.0 / MATCH_TOLERANCE <= ratio <= MATCH_TOLERANCE


def compare_adaptation(
    random_walk: Estimator,
    make_forgetting: Callable[[float], Estimator],
    calibration: Trial,
    change: Trial,
    steady_from: float,
) -> AdaptationComparison:
    """Match the forgetting factor to ``random_walk``'s steady-state noise on ``calibration``, then
    compare both on ``change`` (whose first change time starts the tracking window)."""
    change_time = change.change_times[0]
    target = steady_state_noise(random_walk.run(calibration.log), calibration.truth, steady_from)
    factor = match_forgetting(make_forgetting, calibration, steady_from, target)
    forgetting = make_forgetting(factor)
    results = []
    for estimator in (random_walk, forgetting):
        noise = steady_state_noise(estimator.run(calibration.log), calibration.truth, steady_from)
        history = estimator.run(change.log)
        settled = settling_times(history, change.truth)
        settled_at = [t for t in settled.values() if t is not None]
        recovery = max(settled_at) - change_time if len(settled_at) == len(settled) else None
        results.append(
            AdaptationResult(
                estimator.name,
                noise,
                parameter_criterion(history, change.truth, start=change_time),
                recovery if recovery is None else max(recovery, 0.0),
                history,
            )
        )
    return AdaptationComparison(results[0], results[1], factor)
