"""How well an estimator did: final error, time to within a tolerance, and the thesis's J_p (6.1).

With e_i(t) = (theta_i(t) - theta^_i(t)) / theta_i(t) the relative error of parameter i against
the truth theta_i(t) (which may change during the run):

- final error: e_i at the last sample;
- settling time: the first time after which |e_i| stays within the tolerance (10 %) to the end;
- J_p = integral of sum_i e_i(t)^2 dt  (thesis 6.1, there for K* and tau*; here for whichever
  parameters the estimator reports), by the rectangle rule on the sample intervals, optionally
  over a window [start, end).

A sample where the estimator had no usable estimate counts as a 100 % error of every parameter.
"""

from __future__ import annotations

import numpy as np

from ship_env.baselines.online_estimators.history import ParameterHistory

#: The relative error within which an estimate counts as found (the issue's and Perera's 10 %).
TOLERANCE = 0.10


def relative_errors(estimate: ParameterHistory, truth: ParameterHistory) -> np.ndarray:
    """e_i(k) = (theta_i - theta^_i) / theta_i, shape (samples, parameters); 1 where the estimate is invalid."""
    _check_same_run(estimate, truth)
    errors = (truth.values - estimate.values) / truth.values
    errors[~estimate.valid] = 1.0
    return errors


def final_errors(estimate: ParameterHistory, truth: ParameterHistory) -> dict[str, float]:
    """|e_i| at the last sample, per parameter."""
    return dict(zip(truth.names, map(float, np.abs(relative_errors(estimate, truth)[-1])), strict=True))


def settling_times(
    estimate: ParameterHistory, truth: ParameterHistory, tolerance: float = TOLERANCE
) -> dict[str, float | None]:
    """Per parameter, the first time after which |e_i| <= ``tolerance`` to the end of the run; None if never."""
    outside = np.abs(relative_errors(estimate, truth)) > tolerance
    times: dict[str, float | None] = {}
    for i, name in enumerate(truth.names):
        late = np.flatnonzero(outside[:, i])
        if len(late) == 0:
            times[name] = float(truth.time[0])
        elif late[-1] == len(truth.time) - 1:
            times[name] = None
        else:
            times[name] = float(truth.time[late[-1] + 1])
    return times


def parameter_criterion(
    estimate: ParameterHistory, truth: ParameterHistory, start: float | None = None, end: float | None = None
) -> float:
    """J_p (thesis 6.1) over [start, end) (default the whole run), s."""
    errors = relative_errors(estimate, truth)
    squared = np.sum(errors[:-1] ** 2, axis=1)
    time = truth.time
    window = np.ones(len(time) - 1, dtype=bool)
    if start is not None:
        window &= time[:-1] >= start
    if end is not None:
        window &= time[:-1] < end
    return float(np.sum(squared[window] * np.diff(time)[window]))


def _check_same_run(estimate: ParameterHistory, truth: ParameterHistory) -> None:
    if estimate.names != truth.names:
        raise ValueError(f"estimate of {estimate.names} cannot be judged against the truth of {truth.names}")
    if estimate.time.shape != truth.time.shape or not np.array_equal(estimate.time, truth.time):
        raise ValueError("estimate and truth must be sampled at the same times (the log's)")
