"""Nguyen (2008): recursive least squares with a forgetting factor, and the Nomoto K, T from it.

Model (Nguyen 21), the sampled yaw motion as a multi-output ARX (MARX) model:

    x(k) = A x(k-1) + B delta(k),   x = (r, psi),   A = [[a11, a12], [a21, a22]],   B = (b11, b21)

written per output as y(k) = Theta^T phi(k) + e(k) (Nguyen 4), with the regressor
phi(k) = (r(k-1), psi(k-1), delta(k)) and Theta (3 x 2) = [[a11, a21], [a12, a22], [b11, b21]].
delta(k) is the rudder over the interval (t(k-1), t(k)], the mean of its two readings. For a
first-order Nomoto ship a12 = 0 and (a11, b11) = (a, b) of the held-rudder model
(:mod:`ship_env.baselines.online_estimators.discrete_nomoto`), from which K, T and K*, tau* follow at the
measured speed. ``include_heading=False`` leaves psi out (y = r, phi = (r(k-1), delta(k))): the
thesis's first-order regression (5.3), the equation-error / series-parallel identifier (4.62).

Algorithm (Nguyen's Algorithm 2, (18)-(20); thesis 4.57-4.60, 4.64), with noise variance R
(Nguyen: R = 1):

    P(k|k-1) = P(k-1) / lambda                      (forgetting; or + Q_theta: random walk, 4.108)
    e(k)     = y(k) - Theta(k-1)^T phi(k)                                                   (18)
    L(k)     = P(k|k-1) phi(k) / (R + phi(k)^T P(k|k-1) phi(k))
    Theta(k) = Theta(k-1) + L(k) e(k)^T                                                     (20)
    P(k)     = P(k|k-1) - L(k) phi(k)^T P(k|k-1)                                            (19)

with P(0) = alpha I, alpha = 1e3..1e4, lambda = 0.95..0.998 (Nguyen's ranges).

Divergence: with a forgetting factor and no excitation P grows as lambda^-k ("wind-up"); when
its trace exceeds ``covariance_limit`` times its initial trace, or Theta leaves finite values,
:class:`~ship_env.baselines.filter_health.FilterDivergenceError` is raised.

Nguyen's recursive prediction-error variant (his Algorithm 1) is left out: for this model the
predicted output is linear in Theta, its gradient is phi, and with the step 1/t and a fixed
weighting it reduces to this recursion; it adds nothing here.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ship_env.baselines.filter_health import FilterDivergenceError
from ship_env.baselines.nomoto import NomotoParameters
from ship_env.baselines.online_estimators.adaptation import Adaptation, ForgettingFactor
from ship_env.baselines.online_estimators.discrete_nomoto import discrete_pair, nomoto_from_discrete
from ship_env.baselines.online_estimators.history import NOMOTO, HistoryRecorder, ParameterHistory
from ship_env.baselines.online_estimators.log import ExcitationLog

#: Nguyen's defaults: lambda in 0.95..0.998 (here 0.995, a memory of 200 samples), P(0) = 1e3 I.
NGUYEN_FORGETTING = ForgettingFactor(0.995)
NGUYEN_INITIAL_COVARIANCE = 1e3


class RecursiveLeastSquares:
    """Theta (parameters x outputs) estimated from y = Theta^T phi + e; see the module docstring.

    Args:
        initial: Theta(0), shape (parameters, outputs).
        initial_covariance: alpha of P(0) = alpha I.
        adaptation: forgetting factor or random walk.
        noise_variance: R (1 in Nguyen's form, where P is relative to R).
        covariance_limit: P's trace may grow to this times its initial trace before the
            estimator counts as diverged.
        name: for the divergence message.
    """

    def __init__(
        self,
        initial: np.ndarray,
        initial_covariance: float,
        adaptation: Adaptation,
        noise_variance: float = 1.0,
        covariance_limit: float = 1e6,
        name: str = "recursive least squares",
    ) -> None:
        self.theta = np.array(initial, dtype=float)
        if self.theta.ndim == 1:
            self.theta = self.theta[:, None]
        self.covariance = initial_covariance * np.eye(len(self.theta))
        self.adaptation = adaptation
        self.noise_variance = noise_variance
        self.name = name
        self._trace_limit = covariance_limit * float(np.trace(self.covariance))

    def update(self, regressor: np.ndarray, output: np.ndarray | float) -> np.ndarray:
        """One step (18)-(20) with phi(k) = ``regressor`` and y(k) = ``output``; returns the prediction error e(k)."""
        prior = self.adaptation.predict(self.covariance)
        error = np.atleast_1d(output) - self.theta.T @ regressor
        spread = prior @ regressor
        gain = spread / (self.noise_variance + regressor @ spread)
        self.theta = self.theta + np.outer(gain, error)
        self.covariance = prior - np.outer(gain, spread)
        trace = float(np.trace(self.covariance))
        if not (np.all(np.isfinite(self.theta)) and trace <= self._trace_limit):
            raise FilterDivergenceError(
                f"{self.name}: covariance trace {trace:.3g} beyond {self._trace_limit:.3g} (wind-up: the data "
                f"stopped informing the parameters under {self.adaptation.name}), or parameters not finite: "
                f"{np.array2string(self.theta.ravel(), precision=4)}"
            )
        return error


@dataclass(frozen=True, eq=False)
class NguyenRLS:
    """Nguyen's RLS on a log, reporting K*, tau*; see the module docstring.

    Args:
        length: the ship's length L, m.
        initial: the K*, tau* that give Theta(0) (a12 = 0, and the kinematic row psi(k) =
            psi(k-1) + T_s r(k-1) for the heading output).
        adaptation: Nguyen's forgetting factor, or a random walk (in P's units, relative to R).
        initial_covariance: alpha of P(0) = alpha I.
        include_heading: regress Nguyen's two outputs (r, psi) on (r, psi, delta); False: r on (r, delta).
        noise_variance: R.
    """

    parameter_names = NOMOTO

    length: float
    initial: NomotoParameters
    adaptation: Adaptation = NGUYEN_FORGETTING
    initial_covariance: float = NGUYEN_INITIAL_COVARIANCE
    include_heading: bool = True
    noise_variance: float = 1.0

    @property
    def name(self) -> str:
        method = "Nguyen RLS" if self.include_heading else "least squares"
        return f"{method} ({self.adaptation.name})"

    def run(self, log: ExcitationLog) -> ParameterHistory:
        """K*, tau* after each sample of ``log`` (uniformly sampled, with speed)."""
        sample_time = log.sample_time()
        speed = log.speed_or_error(self.name)
        a, b = discrete_pair(self.initial, sample_time, speed[0], self.length)
        if self.include_heading:
            initial = np.array([[a, sample_time], [0.0, 1.0], [b, 0.0]])
        else:
            initial = np.array([[a], [b]])
        estimator = RecursiveLeastSquares(
            initial, self.initial_covariance, self.adaptation, self.noise_variance, name=self.name
        )
        rudder = log.interval_rudder()
        recorder = HistoryRecorder(NOMOTO, log.time, (self.initial.gain, self.initial.time_constant))
        recorder.record(0, (self.initial.gain, self.initial.time_constant))
        for k in range(1, log.samples):
            if self.include_heading:
                regressor = np.array([log.rate_of_turn[k - 1], log.heading[k - 1], rudder[k - 1]])
                output = np.array([log.rate_of_turn[k], log.heading[k]])
            else:
                regressor = np.array([log.rate_of_turn[k - 1], rudder[k - 1]])
                output = log.rate_of_turn[k]
            estimator.update(regressor, output)
            a, b = estimator.theta[0, 0], estimator.theta[-1, 0]
            estimate = nomoto_from_discrete(a, b, sample_time, 0.5 * (speed[k - 1] + speed[k]), self.length)
            recorder.record(k, None if estimate is None else (estimate.gain, estimate.time_constant))
        return recorder.history()
