"""Song et al. (2022): EKF with forgetting factor, tanh-processed innovation and divergence guard, on our yaw model.

Song et al. identify a 4-DOF MMG model; here their filter runs on the thesis's speed-scheduled
first-order yaw model (2.54; 5.17, 5.39), with the normalised parameters in the state.

State (5):

    x = (r, psi, theta1, theta2, n),   theta1 = 1/tau*,   theta2 = K*/tau*

n an offset (yaw acceleration, rad/s^2: wind, rudder offset; the N_w of 5.17 per second).
Model, discretised by forward Euler at the sample time h as Song's (14), with the input the mean
of the rudder over the interval (their s(t), (9)) and u the speed over it:

    r(k+1)   = r(k) + h [ (u/L)^2 theta2 delta(k) - (u/L) theta1 r(k) + n(k) ] + w_r
    psi(k+1) = psi(k) + h r(k) + w_psi
    theta(k+1) = theta(k) + w_theta,   n(k+1) = n(k) + w_n        (w_theta = 0 unless a random walk is asked for)

Measurements y = (r~, psi~) = C x + v, C = [[1,0,0,0,0],[0,1,0,0,0]], v ~ N(0, R2); w ~ N(0, R1).

Recursion (Song 16-19 with the guard 20-23), Phi = df/dx at x^(k):

    x^(k+1|k) = f(x^(k), delta(k))                                                         (16)
    e(k+1)    = y(k+1) - C x^(k+1|k)                                                       (17)
    M(k+1)    = 1 if e^T e <= gamma tr{C [Phi P Phi^T + R1] C^T + R2}                       (22)
              = max(1, (1/m) tr{[e e^T - C R1 C^T - R2] [C Phi P Phi^T C^T]^-1}) otherwise  (23)
    P(k+1|k)  = [M(k+1) Phi P(k) Phi^T + R1] / alpha                                       (18)
    K(k+1)    = P(k+1|k) C^T [C P(k+1|k) C^T + R2]^-1                                      (19)
    x^(k+1)   = x^(k+1|k) + K(k+1) e~(k+1),   e~_i = c_i tanh(e_i / c_i),   c_i = kappa sqrt(S_ii)
    P(k+1)    = [I - K(k+1) C] P(k+1|k)

Reading of the paper, where it is ambiguous (their printed equations carry alpha* on the state and
the innovation as well):

- the forgetting factor alpha (0 < alpha <= 1) divides the prior covariance, as in RLS (thesis
  4.64): multiplying P by alpha < 1 would make old data weigh more, not less; it is not applied
  to the state estimate (a state scaled by alpha would be biased);
- "tan(omega e)" is the hyperbolic tangent of their reference [3]: each innovation component is
  passed through c tanh(e/c), linear for |e| << c and saturating at +-c, with c = kappa times its
  predicted standard deviation (kappa = 3: a 3-sigma innovation is cut by 1/4);
- e e^T (not the scalar e^T e) in (23), so that the trace is of an m x m matrix; m the number of
  measurements ("the filter dimension");
- a reserve coefficient gamma >= 1 in the convergence condition (22), as in the strong-tracking
  filters this guard comes from (their printed (20)-(22) have none, i.e. gamma = 1). With gamma = 1
  the guard acts on about 37 % of the samples of a consistent filter (e^T e against its mean with
  m = 2), each time multiplying the whole prior covariance, parameters included, by M; on our
  zig-zag logs that wrecks the estimates (K* 0.17 for 1.6). gamma = 25 (about a 5-sigma innovation)
  leaves a consistent filter alone and still acts on a real upset (a changed ship).

Divergence: M(k) > 1 means the innovation was larger than the filter predicted; the guard then
inflates P. When the guard acts ``patience`` samples in a row, or M exceeds ``inflation_limit``,
or the state leaves finite values, or the estimated time constant tau* L/u falls below half the
sample time (the Euler model's pole 1 - h (u/L) theta1 below -1: no ship, but a filter fitting
inconsistent measurements), :class:`~ship_env.baselines.filter_health.FilterDivergenceError` is raised.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from filterpy.kalman import ExtendedKalmanFilter

from ship_env.baselines.filter_health import FilterDivergenceError
from ship_env.baselines.nomoto import NomotoParameters
from ship_env.baselines.online_estimators.history import NOMOTO, HistoryRecorder, ParameterHistory
from ship_env.baselines.online_estimators.log import ExcitationLog

RATE, HEADING, INVERSE_TIME_CONSTANT, GAIN_RATIO, OFFSET = range(5)
STATE_SIZE = 5
PARAMETERS = slice(INVERSE_TIME_CONSTANT, GAIN_RATIO + 1)
_MEASUREMENT_MATRIX = np.eye(2, STATE_SIZE)


@dataclass(frozen=True)
class SongFilterNoise:
    """The filter's calibration (per sample variances come from densities times the sample time h).

    Attributes:
        gyro, compass: standard deviations of v (R2), rad/s and rad.
        rate_model, heading_model: spectral densities of w_r, w_psi (R1), (rad/s)^2/s, rad^2/s.
        parameter_walk: spectral densities of random walks of theta1 = 1/tau* and theta2 = K*/tau*,
            1/s, as the yaw filter's (``inverse_time_constant_walk``, ``gain_ratio_walk``); zero:
            Song's filter, which adapts by the forgetting factor alone.
        offset_walk: spectral density of n's random walk, (rad/s^2)^2/s.
        parameter_uncertainty: initial standard deviation of theta1, theta2 relative to their initial values.
        offset_uncertainty: initial standard deviation of n, rad/s^2.
    """

    gyro: float = math.radians(0.01)
    compass: float = math.radians(0.1)
    rate_model: float = math.radians(0.002) ** 2
    heading_model: float = math.radians(0.01) ** 2
    parameter_walk: tuple[float, float] = (0.0, 0.0)
    offset_walk: float = math.radians(1e-4) ** 2
    parameter_uncertainty: float = 1.0
    offset_uncertainty: float = math.radians(0.005)


class SongFilter:
    """Song's EKF on a log, reporting K* = theta2/theta1, tau* = 1/theta1; see the module docstring.

    Args:
        length: the ship's length L, m.
        initial: the K*, tau* to start from.
        forgetting: alpha (1: none).
        noise: the calibration.
        innovation_scale: kappa of the tanh processing (``math.inf``: the plain innovation).
        guard: whether M(k) of (22, 23) inflates P (False: M = 1).
        reserve: gamma of (22).
        patience: guard actions in a row that count as divergence.
        inflation_limit: the largest M that does not.
    """

    parameter_names = NOMOTO

    def __init__(
        self,
        length: float,
        initial: NomotoParameters,
        forgetting: float = 0.998,
        noise: SongFilterNoise | None = None,
        innovation_scale: float = 3.0,
        guard: bool = True,
        reserve: float = 25.0,
        patience: int = 100,
        inflation_limit: float = 1e6,
    ) -> None:
        if not 0.0 < forgetting <= 1.0:
            raise ValueError(f"forgetting factor must lie in (0, 1], got {forgetting!r}")
        self.length = length
        self.initial = initial
        self.forgetting = forgetting
        self.noise = noise or SongFilterNoise()
        self.innovation_scale = innovation_scale
        self.guard = guard
        self.reserve = reserve
        self.patience = patience
        self.inflation_limit = inflation_limit
        self.kalman = ExtendedKalmanFilter(dim_x=STATE_SIZE, dim_z=2)
        self.kalman.R = np.diag([self.noise.gyro, self.noise.compass]) ** 2
        self.guard_actions_in_a_row = 0
        self.last_inflation = 1.0
        features = [
            f"forgetting {forgetting:g}" if forgetting < 1.0 else "",
            "random walk" if any(self.noise.parameter_walk) else "",
            "tanh" if math.isfinite(innovation_scale) else "",
            "guard" if guard else "",
        ]
        self.name = f"Song EKF ({', '.join(feature for feature in features if feature) or 'plain'})"

    @property
    def initial_parameters(self) -> np.ndarray:
        """(theta1, theta2) of the initial K*, tau*."""
        return np.array([1.0 / self.initial.time_constant, self.initial.gain / self.initial.time_constant])

    def reset(self, rate: float, heading: float) -> None:
        noise = self.noise
        theta = self.initial_parameters
        self.kalman.x = np.array([[rate, heading, *theta, 0.0]]).T
        self.kalman.P = np.diag(
            [
                noise.gyro**2,
                noise.compass**2,
                *((noise.parameter_uncertainty * theta) ** 2),
                noise.offset_uncertainty**2,
            ]
        )
        self.guard_actions_in_a_row = 0

    def step(self, interval: float, speed: float, rudder: float, rate: float, heading: float) -> None:
        """Predict over ``interval`` s at ``speed`` m/s with ``rudder`` (rad, the interval's mean),
        then update with r~, psi~."""
        kalman = self.kalman
        x = kalman.x[:, 0]
        speed_per_length = speed / self.length
        transition = self._jacobian(x, interval, speed_per_length, rudder)
        process = self._process_noise(interval)
        r, psi, theta1, theta2, offset = x
        predicted = x.copy()
        predicted[RATE] = r + interval * (
            speed_per_length**2 * theta2 * rudder - speed_per_length * theta1 * r + offset
        )
        predicted[HEADING] = psi + interval * r
        innovation = np.array([rate, heading]) - predicted[:2]
        spread = transition @ kalman.P @ transition.T
        inflation = self._inflation(innovation, spread, process) if self.guard else 1.0
        kalman.x = predicted[:, None]
        kalman.P = (inflation * spread + process) / self.forgetting
        kalman.x_prior, kalman.P_prior = kalman.x.copy(), kalman.P.copy()
        kalman.update(
            np.array([[rate], [heading]]), _measurement_jacobian, _measurement_function, residual=self._processed
        )
        if not np.all(np.isfinite(kalman.x)):
            raise FilterDivergenceError(f"{self.name}: the state left finite values: {kalman.x[:, 0]}")
        pole = 1.0 - interval * speed_per_length * kalman.x[INVERSE_TIME_CONSTANT, 0]
        if not -1.0 < pole:
            raise FilterDivergenceError(
                f"{self.name}: tau* = {1.0 / kalman.x[INVERSE_TIME_CONSTANT, 0]:.3g} makes the time constant "
                f"tau* L/u shorter than half the sample time {interval:g} s (discrete pole {pole:.3g}): no ship"
            )

    def run(self, log: ExcitationLog) -> ParameterHistory:
        """K*, tau* after each sample of ``log`` (with speed)."""
        speed = log.speed_or_error(self.name)
        rudder = log.interval_rudder()
        recorder = HistoryRecorder(NOMOTO, log.time, (self.initial.gain, self.initial.time_constant))
        self.reset(log.rate_of_turn[0], log.heading[0])
        recorder.record(0, self._estimate())
        for k in range(1, log.samples):
            self.step(
                log.time[k] - log.time[k - 1],
                0.5 * (speed[k - 1] + speed[k]),
                rudder[k - 1],
                log.rate_of_turn[k],
                log.heading[k],
            )
            recorder.record(k, self._estimate())
        return recorder.history()

    @property
    def parameters(self) -> NomotoParameters | None:
        """K*, tau*; None while theta1 or theta2 is not positive."""
        estimate = self._estimate()
        return None if estimate is None else NomotoParameters(*estimate)

    def _estimate(self) -> tuple[float, float] | None:
        theta1, theta2 = self.kalman.x[PARAMETERS, 0]
        if not (theta1 > 0.0 and theta2 > 0.0):
            return None
        return float(theta2 / theta1), float(1.0 / theta1)

    def _inflation(self, innovation: np.ndarray, spread: np.ndarray, process: np.ndarray) -> float:
        """M(k+1) of (22, 23); counts the guard's actions and raises on divergence."""
        measurement_noise = self.kalman.R
        observed_spread = spread[:2, :2]
        if innovation @ innovation <= self.reserve * np.trace(observed_spread + process[:2, :2] + measurement_noise):
            self.guard_actions_in_a_row = 0
            self.last_inflation = 1.0
            return 1.0
        excess = np.outer(innovation, innovation) - process[:2, :2] - measurement_noise
        inflation = max(1.0, float(np.trace(excess @ np.linalg.inv(observed_spread))) / len(innovation))
        self.last_inflation = inflation
        self.guard_actions_in_a_row += 1
        if self.guard_actions_in_a_row >= self.patience or inflation > self.inflation_limit:
            raise FilterDivergenceError(
                f"{self.name}: the divergence guard acted {self.guard_actions_in_a_row} samples in a row "
                f"(M = {inflation:.3g}, limit {self.inflation_limit:.3g}); innovation "
                f"{np.array2string(innovation, precision=5)}"
            )
        return inflation

    def _processed(self, measured: np.ndarray, predicted: np.ndarray) -> np.ndarray:
        """e~ = c tanh(e / c), c = kappa sqrt(diag S), the residual function of filterpy's update."""
        innovation = measured - predicted
        if math.isinf(self.innovation_scale):
            return innovation
        scale = self.innovation_scale * np.sqrt(np.diag(self.kalman.S))[:, None]
        return scale * np.tanh(innovation / scale)

    def _jacobian(self, x: np.ndarray, interval: float, speed_per_length: float, rudder: float) -> np.ndarray:
        jacobian = np.eye(STATE_SIZE)
        jacobian[RATE, RATE] = 1.0 - interval * speed_per_length * x[INVERSE_TIME_CONSTANT]
        jacobian[RATE, INVERSE_TIME_CONSTANT] = -interval * speed_per_length * x[RATE]
        jacobian[RATE, GAIN_RATIO] = interval * speed_per_length**2 * rudder
        jacobian[RATE, OFFSET] = interval
        jacobian[HEADING, RATE] = interval
        return jacobian

    def _process_noise(self, interval: float) -> np.ndarray:
        noise = self.noise
        return np.diag([noise.rate_model, noise.heading_model, *noise.parameter_walk, noise.offset_walk]) * interval


def _measurement_jacobian(x: np.ndarray) -> np.ndarray:
    return _MEASUREMENT_MATRIX


def _measurement_function(x: np.ndarray) -> np.ndarray:
    return _MEASUREMENT_MATRIX @ x
