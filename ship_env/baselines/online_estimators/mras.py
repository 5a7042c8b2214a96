"""Passenier's combined Series-Parallel / Parallel MRAS identifier (thesis 4.4.4, 4.83-4.94; 4.126-4.132).

Model (first order, the thesis's (5.3) without offset; y = r the rate of turn, u = delta):

    y(k) = Psi^T(k) theta,   Psi^T(k) = (y(k-1), u(k)),   theta = (theta_y, theta_u) = (a, b)

Measurement y~(k) = y(k) + v(k), v ~ N(0, R). The identifier estimates theta and, beside it, the
output y itself, which it puts into the observation vector instead of the noisy measurement:

    Psi^^T(k) = (y^(k-1), u(k))                                                       (4.83)
    y-(k)     = Psi^^T(k) theta-(k),   theta-(k) = theta^(k-1)                          (4.84)
    M_y(k)    = Psi^^T(k) F(k|k-1) Psi^(k) + theta-_y(k)^2 P_y(k-1)                     (4.94, 4.126)
    K_y(k)    = M_y(k) / (M_y(k) + R)                                                   (4.86, 4.129)
    y^(k)     = y-(k) + K_y(k) (y~(k) - y-(k))                                          (4.85)
    P_y(k)    = (1 - K_y(k)) M_y(k)                                                     (4.87, 4.131)
    theta^(k) = theta-(k) + F(k|k-1) Psi^(k) (y~(k) - y-(k)) / (M_y(k) + R)             (4.130)
    F(k)      = F(k|k-1) - F(k|k-1) Psi^ Psi^T F(k|k-1) / (M_y(k) + R)                  (4.132)

F(k|k-1) is F(k-1) after adaptation (a random walk, 4.108, or a forgetting factor, 4.64; see
:mod:`ship_env.baselines.online_estimators.adaptation`). With high F(0) and P_y(0) the identifier starts as
Series-Parallel (K_y = 1: the measurement in the observation vector, fast convergence) and, as the
uncertainty falls, becomes Parallel (K_y -> 0: the model's own output, no noise bias; 4.4.3).
``observation`` fixes K_y instead: "series-parallel" (K_sp = 1) or "parallel" (K_sp = 0), with
P_y = 0 (4.134-4.139: the Minimum-Variance estimator and the Parallel MRAS).

theta = (a, b) is the held-rudder pair of :mod:`ship_env.baselines.online_estimators.discrete_nomoto`
(u(k) the rudder over the interval), so K*, tau* follow at the measured speed; the identifier
itself is not speed-scheduled.

Divergence: F or theta^ leaving finite values, or F's trace growing beyond ``covariance_limit``
times its initial trace (wind-up), raises :class:`~ship_env.baselines.filter_health.FilterDivergenceError`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ship_env.baselines.filter_health import FilterDivergenceError
from ship_env.baselines.nomoto import NomotoParameters
from ship_env.baselines.online_estimators.adaptation import Adaptation
from ship_env.baselines.online_estimators.discrete_nomoto import discrete_pair, nomoto_from_discrete
from ship_env.baselines.online_estimators.history import NOMOTO, HistoryRecorder, ParameterHistory
from ship_env.baselines.online_estimators.log import ExcitationLog

OBSERVATIONS = ("combined", "series-parallel", "parallel")


@dataclass(frozen=True, eq=False)
class CombinedMRAS:
    """The combined identifier on a log, reporting K*, tau*; see the module docstring.

    Args:
        length: the ship's length L, m.
        initial: the K*, tau* that give theta(0) (the thesis starts at K*/4, tau*/4).
        adaptation: random walk (in (a, b) units per sample) or forgetting factor.
        noise_variance: R, the variance of the rate gyro's noise, (rad/s)^2.
        parameter_uncertainty: F(0) = diag((u (1 - a0))^2, (u b0)^2) with u this factor (1: no prior knowledge).
        output_uncertainty: sqrt(P_y(0)), rad/s.
        observation: "combined" (4.86), "series-parallel" (K_y = 1) or "parallel" (K_y = 0).
        covariance_limit: F's trace may grow to this times its initial trace.
    """

    parameter_names = NOMOTO

    length: float
    initial: NomotoParameters
    adaptation: Adaptation
    noise_variance: float
    parameter_uncertainty: float = 1.0
    output_uncertainty: float = 0.01
    observation: str = "combined"
    covariance_limit: float = 1e6

    def __post_init__(self) -> None:
        if self.observation not in OBSERVATIONS:
            raise ValueError(f"observation must be one of {OBSERVATIONS}, got {self.observation!r}")

    @property
    def name(self) -> str:
        return f"MRAS {self.observation} ({self.adaptation.name})"

    def run(self, log: ExcitationLog) -> ParameterHistory:
        """K*, tau* after each sample of ``log`` (uniformly sampled, with speed)."""
        sample_time = log.sample_time()
        speed = log.speed_or_error(self.name)
        theta = np.array(discrete_pair(self.initial, sample_time, speed[0], self.length))
        gain_matrix = np.diag((self.parameter_uncertainty * np.array([1.0 - theta[0], theta[1]])) ** 2)  # F
        trace_limit = self.covariance_limit * float(np.trace(gain_matrix))
        output = log.rate_of_turn[0]  # y^
        output_variance = self.output_uncertainty**2 if self.observation == "combined" else 0.0  # P_y
        noise_variance = self.noise_variance
        rudder = log.interval_rudder()
        recorder = HistoryRecorder(NOMOTO, log.time, (self.initial.gain, self.initial.time_constant))
        recorder.record(0, (self.initial.gain, self.initial.time_constant))
        for k in range(1, log.samples):
            prior = self.adaptation.predict(gain_matrix)
            observation = np.array([output, rudder[k - 1]])  # Psi^(k), 4.83
            predicted = observation @ theta  # y-(k), 4.84
            spread = prior @ observation
            output_prior = observation @ spread + theta[0] ** 2 * output_variance  # M_y, 4.94
            innovation = log.rate_of_turn[k] - predicted
            denominator = output_prior + noise_variance
            theta = theta + spread * (innovation / denominator)  # 4.130
            gain_matrix = prior - np.outer(spread, spread) / denominator  # 4.132
            if self.observation == "combined":
                output_gain = output_prior / denominator  # K_y, 4.86
                output_variance = (1.0 - output_gain) * output_prior  # 4.87
            else:
                output_gain = 1.0 if self.observation == "series-parallel" else 0.0  # K_sp
            output = predicted + output_gain * innovation  # 4.85
            trace = float(np.trace(gain_matrix))
            if not (np.all(np.isfinite(theta)) and np.isfinite(output) and trace <= trace_limit):
                raise FilterDivergenceError(
                    f"{self.name}: at t = {log.time[k]:.1f} s F's trace is {trace:.3g} (limit {trace_limit:.3g}), "
                    f"theta^ = {theta}, y^ = {output!r}"
                )
            estimate = nomoto_from_discrete(
                theta[0], theta[1], sample_time, 0.5 * (speed[k - 1] + speed[k]), self.length
            )
            recorder.record(k, None if estimate is None else (estimate.gain, estimate.time_constant))
        return recorder.history()
