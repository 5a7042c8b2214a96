"""Passenier's EKF with the parameters as random walks (thesis 4.5.2, 4.106-4.108; 5.3) on a log.

This runs :class:`ship_env.baselines.yaw_filter.YawFilter` (the thesis's 7-state yaw filter: a_s, b_s,
N_w, r, v_f, psi, psi_v; see that module for the model, noise and guard) over an
:class:`~ship_env.baselines.online_estimators.log.ExcitationLog` and records its K*, tau* (5.27, 5.28) after
each sample. Its parameters adapt by additive system noise on a_s, b_s (the random walks of
5.18, 5.19, densities ``inverse_time_constant_walk`` and ``gain_ratio_walk`` of
:class:`~ship_env.baselines.yaw_filter.YawFilterNoise`), not by a forgetting factor (stelling 5).
"""

from __future__ import annotations

from ship_env.baselines.measurement import Measurement
from ship_env.baselines.nomoto import NomotoParameters
from ship_env.baselines.online_estimators.history import NOMOTO, HistoryRecorder, ParameterHistory
from ship_env.baselines.online_estimators.log import ExcitationLog
from ship_env.baselines.yaw_filter import YawFilter, YawFilterNoise


class PassenierEKF:
    """The thesis's yaw filter on a log, reporting K*, tau*.

    Args:
        length: the ship's length L, m.
        initial: the K*, tau* to start from (the thesis: K*/4, tau*/4 of a guess).
        noise: the yaw filter's calibration (default: :class:`~ship_env.baselines.yaw_filter.YawFilterNoise`'s).
    """

    parameter_names = NOMOTO

    def __init__(self, length: float, initial: NomotoParameters, noise: YawFilterNoise | None = None) -> None:
        self.length = length
        self.initial = initial
        self.noise = noise or YawFilterNoise()
        self.name = "Passenier EKF (random walk)"

    def run(self, log: ExcitationLog) -> ParameterHistory:
        """K*, tau* after each sample of ``log`` (uniformly sampled, with speed); where the filter
        holds no stable ship (``YawFilter.parameters`` is None) the sample is invalid."""
        speed = log.speed_or_error(self.name)
        yaw_filter = YawFilter(self.length, log.sample_time(), self.initial, self.noise)
        recorder = HistoryRecorder(NOMOTO, log.time, (self.initial.gain, self.initial.time_constant))
        for k in range(log.samples):
            measurement = Measurement(
                heading=float(log.heading[k]),
                rate_of_turn=float(log.rate_of_turn[k]),
                rudder=float(log.rudder[k]),
                speed=float(speed[k]),
            )
            if k == 0:
                yaw_filter.reset(measurement)
            else:
                yaw_filter.step(measurement)
            estimate = yaw_filter.parameters
            recorder.record(k, None if estimate is None else (estimate.gain, estimate.time_constant))
        return recorder.history()
