"""Perera et al. (2015): an extended Kalman filter for the states and parameters of their model (13).

State (10, their (15)):

    x = (psi, psi', psi'', a1, a2, a3, b1, b2, delta, delta')

System model, continuous (their (14), (16), (22)), w ~ N(0, Q) white:

    x' = f(x) + w,   f(x) = (psi', psi'', a1 psi'^3 + a2 psi' + a3 psi'' + b1 delta + b2 delta', 0, ..., 0)

so the parameters, the rudder and its rate are random walks driven by their parts of Q. One
deviation by default: f[delta] = delta' instead of 0 (the rudder moves with its measured rate
between samples; see ``rudder_integrates_rate`` of :class:`PereraFilter` for why).
Measurements, discrete (their (18)-(20), (23)), v ~ N(0, R):

    z(k) = (psi, psi', delta, delta')(k) + v(k),   H = d h / d x constant (ones at those four states)

Filter (their (27)-(31), Gelb's continuous-discrete EKF) on filterpy's ``ExtendedKalmanFilter``:

- state propagation (27): x^ integrated over the sample interval by RK4 (``substeps`` steps);
- covariance extrapolation (28), P' = F P + P F^T + Q, discretised as P <- Phi P Phi^T + Q T_s
  with Phi = expm(F(x^) T_s) at the estimate before the interval, summed as its Taylor series to
  the power :data:`TRANSITION_ORDER` (error (|F| T_s)^5 / 120: below 1e-4 for |a3| T_s < 0.5;
  Perera's fast pole is 3.3 rad/s, T_s = 0.1 s), and Q T_s the first-order discretisation of the
  noise; the Jacobian F = df/dx has
  F[psi, psi'] = F[psi', psi''] = 1 and, in the psi'' row, 3 a1 psi'^2 + a2 (psi'), a3 (psi''),
  psi'^3 (a1), psi' (a2), psi'' (a3), delta (b1), delta' (b2), b1 (delta), b2 (delta'), and
  F[delta, delta'] = 1 with the deviation above;
- update (29)-(31) with the Joseph form filterpy uses.

Divergence: an update whose normalised innovation is far outside its covariance is undone, and a
run of them raises :class:`~ship_env.baselines.filter_health.FilterDivergenceError`
(:class:`~ship_env.baselines.filter_health.InnovationGate`); so does a state that leaves finite values.
The filter reports Perera's five parameters (:data:`~ship_env.baselines.online_estimators.history.PERERA`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from filterpy.kalman import ExtendedKalmanFilter

from ship_env.baselines.filter_health import FilterDivergenceError, InnovationGate
from ship_env.baselines.online_estimators.history import PERERA, HistoryRecorder, ParameterHistory
from ship_env.baselines.online_estimators.log import ExcitationLog
from ship_env.baselines.online_estimators.perera_model import (
    PereraNoise,
    PereraParameters,
    PereraSetting,
    acceleration_rate,
)

HEADING, RATE, ACCELERATION, A1, A2, A3, B1, B2, RUDDER, RUDDER_RATE = range(10)
STATE_SIZE = 10
PARAMETERS = slice(A1, B2 + 1)
MEASURED = (HEADING, RATE, RUDDER, RUDDER_RATE)

#: Powers of F T_s in the Taylor series of the transition matrix Phi = expm(F T_s).
TRANSITION_ORDER = 4

_MEASUREMENT_MATRIX = np.zeros((4, STATE_SIZE))
_MEASUREMENT_MATRIX[np.arange(4), MEASURED] = 1.0


@dataclass(frozen=True)
class PereraFilterNoise:
    """The filter's calibration: Q of (22), R of (23), P(0) of (25).

    Attributes:
        heading, rate, acceleration: spectral densities of w on psi, psi', psi'' (model error),
            rad^2/s, (rad/s)^2/s, (rad/s^2)^2/s.
        parameters: spectral density of each parameter's random walk, relative to the square of
            its initial value, 1/s (one number for all five).
        rudder, rudder_rate: spectral densities of the random walks of delta and delta', rad^2/s,
            (rad/s)^2/s: large, so that the filter follows their measurements.
        measurement: the measurement noise's standard deviations.
        parameter_uncertainty: initial standard deviation of each parameter relative to its initial value.
        acceleration_uncertainty: initial standard deviation of psi'', rad/s^2.
    """

    heading: float = 1e-10
    rate: float = 1e-10
    acceleration: float = 1e-8
    parameters: float = 1e-7
    rudder: float = 1.0
    rudder_rate: float = 10.0
    measurement: PereraNoise = PereraNoise()
    parameter_uncertainty: float = 1.0
    acceleration_uncertainty: float = 0.01

    @classmethod
    def matched(cls, setting: PereraSetting, parameters: float = 1e-8) -> PereraFilterNoise:
        """The calibration that knows the simulated noise: R from ``setting.noise``, the psi'' model
        error from its held jerk (density sigma^2 T_s), and ``parameters`` for the random walks."""
        return cls(
            acceleration=setting.disturbance**2 * setting.sample_time,
            parameters=parameters,
            measurement=setting.noise,
        )


class _PereraEKF(ExtendedKalmanFilter):
    """filterpy's EKF whose prediction integrates f (16) by RK4 over ``interval`` s in ``substeps`` steps
    (with delta' = delta' when ``rudder_integrates_rate``, see :class:`PereraFilter`)."""

    interval: float = 0.0
    substeps: int = 1
    rudder_integrates_rate: bool = True

    def predict_x(self, u: float = 0.0) -> None:
        x = self.x[:, 0]
        parameters = x[PARAMETERS].copy()
        rudder_rate = x[RUDDER_RATE]
        moving = self.rudder_integrates_rate
        motion = np.array([x[HEADING], x[RATE], x[ACCELERATION], x[RUDDER]])

        def derivative(m: np.ndarray) -> np.ndarray:
            jerk = acceleration_rate(parameters, m[1], m[2], m[3], rudder_rate)
            return np.array([m[1], m[2], jerk, rudder_rate if moving else 0.0])

        h = self.interval / self.substeps
        for _ in range(self.substeps):
            k1 = derivative(motion)
            k2 = derivative(motion + 0.5 * h * k1)
            k3 = derivative(motion + 0.5 * h * k2)
            k4 = derivative(motion + h * k3)
            motion = motion + h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4)
        x[HEADING], x[RATE], x[ACCELERATION], x[RUDDER] = motion


def transition_matrix(jacobian: np.ndarray, interval: float) -> np.ndarray:
    """Phi = expm(F T_s) by its Taylor series to the power :data:`TRANSITION_ORDER`."""
    scaled = jacobian * interval
    term = np.eye(len(jacobian))
    transition = term.copy()
    for power in range(1, TRANSITION_ORDER + 1):
        term = term @ scaled / power
        transition += term
    return transition


def system_jacobian(x: np.ndarray, rudder_integrates_rate: bool = True) -> np.ndarray:
    """F = df/dx of (16) at ``x`` (the continuous-time Jacobian of (28)), with F[delta, delta'] = 1
    when the rudder integrates its rate."""
    rate, acceleration = x[RATE], x[ACCELERATION]
    a1, a2, a3, b1, b2 = x[PARAMETERS]
    jacobian = np.zeros((STATE_SIZE, STATE_SIZE))
    jacobian[HEADING, RATE] = 1.0
    jacobian[RATE, ACCELERATION] = 1.0
    row = jacobian[ACCELERATION]
    row[RATE] = 3.0 * a1 * rate**2 + a2
    row[ACCELERATION] = a3
    row[A1], row[A2], row[A3] = rate**3, rate, acceleration
    row[B1], row[B2] = x[RUDDER], x[RUDDER_RATE]
    row[RUDDER], row[RUDDER_RATE] = b1, b2
    jacobian[RUDDER, RUDDER_RATE] = 1.0 if rudder_integrates_rate else 0.0
    return jacobian


class PereraFilter:
    """Perera's EKF; see the module docstring for the model.

    Call :meth:`reset` with the first sample, then :meth:`step` with each following one, or
    :meth:`run` over a whole :class:`ExcitationLog`.

    Args:
        initial: the parameters to start from (Perera starts from "constant values").
        noise: the calibration.
        substeps: RK4 steps per sample interval in the state propagation.
        rudder_integrates_rate: propagate delta with its rate, delta' = delta' (default), instead
            of Perera's d(delta)/dt = 0 of (16). A real rudder moves between samples; holding it
            in the prediction leaves out b1 delta' (t - t(k)), which the filter can only
            absorb into b2: b2 comes out b1 T_s / 2 too large (+14 % at T_s = 0.1 s). False
            reproduces (16) as printed.
        gate: the innovation check (default: the NIS gate of :mod:`ship_env.baselines.filter_health`).
    """

    parameter_names = PERERA

    def __init__(
        self,
        initial: PereraParameters,
        noise: PereraFilterNoise | None = None,
        substeps: int = 2,
        rudder_integrates_rate: bool = True,
        gate: InnovationGate | None = None,
    ) -> None:
        self.initial = initial
        self.noise = noise or PereraFilterNoise()
        self.name = "Perera EKF" if rudder_integrates_rate else "Perera EKF as printed (d delta/dt = 0)"
        self.gate = gate or InnovationGate(self.name)
        self.kalman = _PereraEKF(dim_x=STATE_SIZE, dim_z=4)
        self.kalman.substeps = substeps
        self.kalman.rudder_integrates_rate = rudder_integrates_rate
        measurement = self.noise.measurement
        self.kalman.R = (
            np.diag([measurement.heading, measurement.rate_of_turn, measurement.rudder, measurement.rudder_rate]) ** 2
        )
        scale = np.array([max(abs(value), 1e-3) for value in initial.as_tuple()])
        self._parameter_walk = self.noise.parameters * scale**2

    def reset(self, heading: float, rate: float, rudder: float, rudder_rate: float) -> None:
        """Start at the first sample: measured psi, psi', delta, delta', psi'' = 0, the initial parameters."""
        noise = self.noise
        measurement = noise.measurement
        initial = np.array(self.initial.as_tuple())
        self.kalman.x = np.array([[heading, rate, 0.0, *initial, rudder, rudder_rate]]).T
        scale = np.maximum(np.abs(initial), 1e-3)
        self.kalman.P = np.diag(
            [
                measurement.heading**2,
                measurement.rate_of_turn**2,
                noise.acceleration_uncertainty**2,
                *((noise.parameter_uncertainty * scale) ** 2),
                measurement.rudder**2,
                measurement.rudder_rate**2,
            ]
        )
        self.gate.outliers_in_a_row = 0

    def step(self, interval: float, heading: float, rate: float, rudder: float, rudder_rate: float) -> None:
        """Propagate over ``interval`` s (27, 28), then update with this sample's measurements (29-31)."""
        kalman = self.kalman
        kalman.interval = interval
        kalman.F = transition_matrix(system_jacobian(kalman.x[:, 0], kalman.rudder_integrates_rate), interval)
        kalman.Q = self._process_noise() * interval
        kalman.predict()
        z = np.array([[heading], [rate], [rudder], [rudder_rate]])
        kalman.update(z, _measurement_jacobian, _measurement_function)
        if not self.gate.accepts(kalman.y, kalman.SI):
            kalman.x = kalman.x_prior.copy()
            kalman.P = kalman.P_prior.copy()
        if not np.all(np.isfinite(kalman.x)):
            raise FilterDivergenceError(f"{self.name}: the state left finite values: {kalman.x[:, 0]}")

    @property
    def parameters(self) -> PereraParameters:
        """(a1, a2, a3, b1, b2)^ after the latest sample."""
        return PereraParameters(*map(float, self.kalman.x[PARAMETERS, 0]))

    def run(self, log: ExcitationLog) -> ParameterHistory:
        """The parameter estimates after each sample of ``log`` (its rudder rate measured, or differenced)."""
        rudder_rate = log.rudder_rate_or_difference()
        recorder = HistoryRecorder(PERERA, log.time, self.initial.as_tuple())
        self.reset(log.heading[0], log.rate_of_turn[0], log.rudder[0], rudder_rate[0])
        recorder.record(0, self.kalman.x[PARAMETERS, 0])
        for k in range(1, log.samples):
            self.step(log.time[k] - log.time[k - 1], log.heading[k], log.rate_of_turn[k], log.rudder[k], rudder_rate[k])
            recorder.record(k, self.kalman.x[PARAMETERS, 0])
        return recorder.history()

    def _process_noise(self) -> np.ndarray:
        noise = self.noise
        densities = np.zeros(STATE_SIZE)
        densities[HEADING], densities[RATE], densities[ACCELERATION] = noise.heading, noise.rate, noise.acceleration
        densities[PARAMETERS] = self._parameter_walk
        densities[RUDDER], densities[RUDDER_RATE] = noise.rudder, noise.rudder_rate
        return np.diag(densities)


def _measurement_jacobian(x: np.ndarray) -> np.ndarray:
    return _MEASUREMENT_MATRIX


def _measurement_function(x: np.ndarray) -> np.ndarray:
    return _MEASUREMENT_MATRIX @ x
