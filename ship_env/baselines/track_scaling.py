"""On-line estimate of the track-scaling factor K_rho (thesis 5.6.2.2, 5.110-5.112, Fig. 5.18).

The ship's normalised rate of turn is taken as K_rho times the predicted one at the same heading
(5.96), and K_rho as a constant with a random walk, observed through the predicted rate:

    K_rho(k) = K_rho(k-1) + w_k(k-1)                                                    (5.110)
    r^*(k) = r_p*(psi^(k)) K_rho(k) + v_k(k)                                            (5.111)
    r^*(k) = L r^(k) / u^(k)                                                            (5.112)

r^, psi^ from the yaw filter, u^ from the position filter (or the log), r_p*(psi) the prediction
made at wheel-over (:meth:`~ship_env.baselines.track_predictor.PredictedTrack.normalised_rate_at`). A
scalar Kalman filter (filterpy's ``KalmanFilter``, H = r_p*(psi^) each sample): where the
prediction does not turn (r_p* = 0) the observation carries no information and K_rho stays.
"""

from __future__ import annotations

import numpy as np
from filterpy.kalman import KalmanFilter

from ship_env.baselines.track_predictor import PredictedTrack


class TrackScalingEstimator:
    """K_rho from the filtered rate of turn against a prediction.

    Args:
        walk: standard deviation of w_k per sample.
        observation: standard deviation of v_k, the error of r^* (-).
        initial: standard deviation of K_rho when an estimate starts at 1.
        turning_fraction: the share of the prediction's largest |r_p*| below which a sample is
            not used.
    """

    def __init__(
        self, walk: float = 0.002, observation: float = 0.02, initial: float = 0.3, turning_fraction: float = 0.5
    ) -> None:
        self.initial = initial
        self.turning_fraction = turning_fraction
        self.kalman = KalmanFilter(dim_x=1, dim_z=1)
        self.kalman.Q = np.array([[walk**2]])
        self.kalman.R = np.array([[observation**2]])
        self.reset()

    def reset(self) -> None:
        """Start over at K_rho = 1 (each manoeuvre gets its own factor, Fig. 6.7.a)."""
        self.kalman.x = np.ones((1, 1))
        self.kalman.P = np.array([[self.initial**2]])

    def update(self, rate_of_turn: float, heading: float, speed: float, prediction: PredictedTrack) -> None:
        """One sample: the yaw filter's r^, psi^ (rad/s, rad) and the speed u^ (m/s) against ``prediction``."""
        predicted_rate = prediction.normalised_rate_at(heading)
        self.kalman.predict()
        if abs(predicted_rate) < self.turning_fraction * prediction.largest_normalised_rate:
            return
        normalised_rate = prediction.length * rate_of_turn / speed
        self.kalman.update(np.array([[normalised_rate]]), H=np.array([[predicted_rate]]))

    @property
    def value(self) -> float:
        """K_rho."""
        return float(self.kalman.x[0, 0])
