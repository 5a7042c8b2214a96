"""The yaw filter: an extended Kalman filter for the rate of turn, heading and Nomoto parameters (thesis 5.3).

State (7, the thesis's x_y, 5.3 "Resuming"), in this order:

    x = (a_s, b_s, N_w, r, v_f, psi, psi_v)

a_s, b_s the discrete Nomoto parameters (5.4, 5.5) at the current speed; N_w the offset (wind
moment, rudder offset) in rad/s per sample; r the rate of turn (rad/s); v_f the low-pass part of
the wave rate (rad/s); psi the low-frequency heading (rad, unwrapped); psi_v the wave heading (rad).
Inputs u = (delta, u^): the actual rudder delta (rad, the measured one: Fig. 5.15) and the forward
speed u^ (m/s). Measurements z = (r~, psi~): rate gyro and compass.

Process (sample time T_s):

    a_s(k) = a_s(k-1) + w_a,  b_s(k) = b_s(k-1) + w_b,  N_w(k) = N_w(k-1) + w_n      (5.18-5.20)
    r(k)   = a_s r(k-1) + b_s delta(k-1) + N_w(k-1) + w_r                               (5.17)
    v_f(k) = a_f v_f(k-1) + b_f w(k-1),   a_f = 1 - T_s/tau_f, b_f = T_s/tau_f          (5.29)
    psi(k) = psi(k-1) + T_s r(k-1)                                                      (5.39)
    psi_v(k) = psi_v(k-1) - T_s v_f(k-1) + T_s w(k-1)                                   (5.40)

Measurement:

    r~(k)   = r(k) - v_f(k) + w(k) + v_r(k)                                             (5.33)
    psi~(k) = psi(k) + psi_v(k) + v_psi(k)                                              (5.41)

so the wave rate v = w - v_f (5.30) is white noise w high-passed by the colouring filter: slow
rate changes are believed, fast ones (time constant below tau_f) are filtered as waves.

Noise: w_r, w_a, w_b, w_n are random walks / model error with the spectral densities of
:class:`YawFilterNoise` (variance per sample = density x T_s); w (variance sigma_w^2) enters v_f
and psi_v together, which gives Q its (v_f, psi_v) cross term b_f T_s sigma_w^2; R =
diag(sigma_w^2 + sigma_gyro^2, sigma_compass^2). The correlation between w(k) in the measurement
and w(k) in the next prediction is not modelled (as in the thesis's 7-state filter).

The EKF's Jacobian F = df/dx is the identity plus dr/da_s = r, dr/db_s = delta, dr/dN_w = 1,
dr/dr = a_s, dv_f/dv_f = a_f, dpsi/dr = T_s, dpsi_v/dv_f = -T_s; H is constant:
[[0,0,0,1,-1,0,0], [0,0,0,0,0,1,1]].

Speed. a_s and b_s belong to one speed. Before each prediction they are rescheduled from the
speed of the previous sample u0 to the new u by (5.4, 5.5), which keeps 1/tau* and K*/tau*
fixed: a_s <- 1 - (1 - a_s) u/u0, b_s <- b_s (u/u0)^2, with P transformed by the same Jacobian.
This is the update of the normalised parameters (5.27, 5.28), and :attr:`YawFilter.parameters`
recovers K* = b_s / ((1 - a_s) u/L), tau* = T_s (u/L) / (1 - a_s).

Parameter adaptation (a_s, b_s) can be switched off (6.3.2: the thesis adapts only during course
changes, so waves do not make the parameters drift; the offset N_w is always estimated). Off, the
parameters are held as known: their rows and columns of P are set to zero (kept aside and
restored when adaptation is switched on again), so the Kalman gain leaves them alone.

Bad input: a NaN gyro or compass reading is left out of the update, a NaN rudder or speed is
replaced by the last valid one; an innovation far outside its
covariance is rejected, and a run of them raises :class:`~ship_env.baselines.filter_health.FilterDivergenceError`
(see :mod:`ship_env.baselines.filter_health`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from filterpy.kalman import ExtendedKalmanFilter

from ship_env.baselines.filter_health import InnovationGate
from ship_env.baselines.measurement import Measurement, wrap_angle
from ship_env.baselines.nomoto import NomotoParameters
from ship_env.envs.ship_scales import ShipScales, ship_scales
from ship_env.model import ShipModel

A_S, B_S, OFFSET, RATE, WAVE_LOW_PASS, HEADING, WAVE_HEADING = range(7)
STATE_SIZE = 7
PARAMETERS = slice(A_S, B_S + 1)
RATE_MEASUREMENT, HEADING_MEASUREMENT = 0, 1

#: The filter's speed floor on the reference ship (m/s): the discrete parameters degenerate at rest. Another ship
#: floors at the same fraction of its speed (:func:`ship_yaw_filter`).
MINIMUM_SPEED = 0.5

_MEASUREMENT_MATRIX = np.zeros((2, STATE_SIZE))
_MEASUREMENT_MATRIX[RATE_MEASUREMENT, RATE] = 1.0
_MEASUREMENT_MATRIX[RATE_MEASUREMENT, WAVE_LOW_PASS] = -1.0
_MEASUREMENT_MATRIX[HEADING_MEASUREMENT, HEADING] = 1.0
_MEASUREMENT_MATRIX[HEADING_MEASUREMENT, WAVE_HEADING] = 1.0


@dataclass(frozen=True)
class YawFilterNoise:
    """The yaw filter's calibration: the noise it assumes (thesis 5.3, last paragraphs).

    The defaults are calibrated on the simulator's sea (``wave_filter`` effect: a narrow-band wave
    rate of 0.1 deg/s RMS peaking at 0.5 rad/s) and the environments' instruments.

    Attributes:
        wave_rate: sigma_w, standard deviation of the wave rate w the gyro sees, rad/s. The
            filter takes w for white; the sea's wave rate is narrow-band, its samples far from
            independent, so sigma_w is set at three times its RMS (0.3 deg/s): the filter then
            averages over several wave periods, as it should.
        wave_time_constant: tau_f of the colouring filter (5.29), s: rate changes faster than
            this are taken for waves.
        gyro: sigma of the rate gyro's own error v_r, rad/s.
        compass: sigma of the compass's own error v_psi, rad.
        rate_model: spectral density of the model error w_r on r, (rad/s)^2 / s.
        heading_model: spectral density of the model error on psi (the Euler step), rad^2 / s.
        inverse_time_constant_walk: spectral density of the random walk of 1/tau*, 1/s.
        gain_ratio_walk: spectral density of the random walk of K*/tau*, 1/s.
        offset_walk: spectral density of the random walk of the offset as a yaw acceleration
            N_w / T_s, (rad/s^2)^2 / s.
        parameter_uncertainty: initial standard deviation of 1/tau* and K*/tau*, relative to
            their initial values (1: no prior knowledge).
        offset_uncertainty: initial standard deviation of the offset as a yaw acceleration, rad/s^2.
    """

    wave_rate: float = math.radians(0.3)
    wave_time_constant: float = 5.0
    gyro: float = math.radians(0.01)
    compass: float = math.radians(0.1)
    rate_model: float = math.radians(0.002) ** 2
    heading_model: float = math.radians(0.01) ** 2
    inverse_time_constant_walk: float = 3e-6
    gain_ratio_walk: float = 3e-6
    offset_walk: float = math.radians(1e-4) ** 2
    parameter_uncertainty: float = 1.0
    offset_uncertainty: float = math.radians(0.005)

    def for_ship(self, scales: ShipScales) -> YawFilterNoise:
        """This calibration, made for the reference ship, on a ship of ``scales``
        (:mod:`ship_env.envs.ship_scales`): times in L / U, so a rate (rad/s) scales by 1 / time, an angle and
        K*, tau* stay, and each spectral density scales with its units squared over time."""
        time = scales.time
        return YawFilterNoise(
            wave_rate=self.wave_rate / time,
            wave_time_constant=self.wave_time_constant * time,
            gyro=self.gyro / time,
            compass=self.compass,
            rate_model=self.rate_model / time**3,
            heading_model=self.heading_model / time,
            inverse_time_constant_walk=self.inverse_time_constant_walk / time,
            gain_ratio_walk=self.gain_ratio_walk / time,
            offset_walk=self.offset_walk / time**5,
            parameter_uncertainty=self.parameter_uncertainty,
            offset_uncertainty=self.offset_uncertainty / time**2,
        )


class _YawEKF(ExtendedKalmanFilter):
    """filterpy's EKF with the yaw model's non-linear prediction f(x, delta) (5.17, 5.29, 5.39, 5.40)."""

    wave_pole: float = 0.0  # a_f
    sample_time: float = 0.0  # T_s

    def predict_x(self, u: float = 0.0) -> None:
        x = self.x[:, 0]
        a_s, b_s, offset, rate, wave_low_pass, heading, wave_heading = x
        rudder = float(u)
        x[RATE] = a_s * rate + b_s * rudder + offset
        x[WAVE_LOW_PASS] = self.wave_pole * wave_low_pass
        x[HEADING] = heading + self.sample_time * rate
        x[WAVE_HEADING] = wave_heading - self.sample_time * wave_low_pass


class YawFilter:
    """Filtered rate of turn and heading, and the ship's K*, tau* and offset, from gyro, compass, rudder and speed.

    See the module docstring for the model. Call :meth:`reset` with the first sample, then
    :meth:`step` once per sample (every ``sample_time`` seconds); a control loop that hands every
    sample, the first included, calls :meth:`take_sample` instead.

    Args:
        length: the ship's length L, m.
        sample_time: T_s, s.
        parameters: the initial K*, tau* (the thesis starts without prior knowledge at K*/4, tau*/4).
        noise: the filter's calibration (:meth:`YawFilterNoise.for_ship` on another ship than the reference).
        gate: the innovation check (default: the NIS gate of :mod:`ship_env.baselines.filter_health`).
        minimum_speed: the speed floor, m/s (:data:`MINIMUM_SPEED` for the reference ship).
    """

    def __init__(
        self,
        length: float,
        sample_time: float,
        parameters: NomotoParameters,
        noise: YawFilterNoise | None = None,
        gate: InnovationGate | None = None,
        minimum_speed: float = MINIMUM_SPEED,
    ) -> None:
        noise = noise or YawFilterNoise()
        if not (length > 0.0 and sample_time > 0.0):
            raise ValueError(f"length and sample_time must be positive, got {length!r}, {sample_time!r}")
        if not minimum_speed > 0.0:
            raise ValueError(f"minimum_speed must be positive, got {minimum_speed!r}")
        if not 0.0 < sample_time < noise.wave_time_constant:
            raise ValueError(
                f"sample_time {sample_time!r} must be below the wave time constant {noise.wave_time_constant!r}"
            )
        self.length = length
        self.sample_time = sample_time
        self.initial_parameters = parameters
        self.noise = noise
        self.gate = gate or InnovationGate("yaw filter")
        self.kalman = _YawEKF(dim_x=STATE_SIZE, dim_z=2, dim_u=1)
        self.kalman.sample_time = sample_time
        self.kalman.wave_pole = 1.0 - sample_time / noise.wave_time_constant
        self.minimum_speed = minimum_speed
        self.speed = minimum_speed
        self._rudder = 0.0
        self._adapting = True
        self._frozen_parameter_covariance = np.zeros((2, 2))
        self._on_reset_sample = True

    # -- running --------------------------------------------------------------------------------
    def reset(self, measurement: Measurement, speed: float | None = None) -> None:
        """Start on the first sample: r, psi from the instruments, the parameters at their initial values.

        ``speed`` (m/s) replaces the log's speed where a better estimate is at hand (the position filter's).
        """
        speed = measurement.speed if speed is None else speed
        self.speed = self.minimum_speed if math.isnan(speed) else max(speed, self.minimum_speed)
        a_s, b_s = self.initial_parameters.discrete(self.sample_time, self.speed, self.length)
        rate = 0.0 if math.isnan(measurement.rate_of_turn) else measurement.rate_of_turn
        heading = 0.0 if math.isnan(measurement.heading) else measurement.heading
        kalman = self.kalman
        kalman.x = np.array([[a_s, b_s, 0.0, rate, 0.0, heading, 0.0]]).T
        noise = self.noise
        speed_per_length = self.speed / self.length
        inverse_time_constant = 1.0 / self.initial_parameters.time_constant
        gain_ratio = self.initial_parameters.gain / self.initial_parameters.time_constant
        variances = np.array(
            [
                (noise.parameter_uncertainty * inverse_time_constant * self.sample_time * speed_per_length) ** 2,
                (noise.parameter_uncertainty * gain_ratio * self.sample_time * speed_per_length**2) ** 2,
                (noise.offset_uncertainty * self.sample_time) ** 2,
                noise.wave_rate**2 + noise.gyro**2,
                noise.wave_rate**2 * self.sample_time / (2.0 * noise.wave_time_constant),
                noise.compass**2 + noise.wave_rate**2 * self.sample_time * noise.wave_time_constant,
                noise.wave_rate**2 * self.sample_time * noise.wave_time_constant / 2.0,
            ]
        )
        kalman.P = np.diag(variances)
        kalman.R = np.diag([noise.wave_rate**2 + noise.gyro**2, noise.compass**2])
        self._frozen_parameter_covariance = kalman.P[PARAMETERS, PARAMETERS].copy()
        if not self._adapting:
            self._hold_parameters()
        self._rudder = 0.0 if math.isnan(measurement.rudder) else measurement.rudder
        self.gate.outliers_in_a_row = 0
        self._on_reset_sample = True

    def step(self, measurement: Measurement, speed: float | None = None) -> None:
        """Predict over the last sample with the previous rudder, then update with this sample's gyro and compass.

        ``speed`` (m/s) replaces the log's speed where a better estimate is at hand (the position filter's).
        """
        speed = measurement.speed if speed is None else speed
        self._reschedule(self.speed if math.isnan(speed) else max(speed, self.minimum_speed))
        kalman = self.kalman
        kalman.F = self._jacobian(self._rudder)
        kalman.Q = self._process_noise()
        kalman.predict(u=self._rudder)
        if not math.isnan(measurement.rudder):
            self._rudder = measurement.rudder
        self._update(measurement.rate_of_turn, measurement.heading)

    def take_sample(self, measurement: Measurement, speed: float | None = None) -> bool:
        """:meth:`step` on ``measurement``, except on the first sample after :meth:`reset`, which reset
        has already read; returns whether the filter stepped."""
        if self._on_reset_sample:
            self._on_reset_sample = False
            return False
        self.step(measurement, speed)
        return True

    # -- parameter adaptation -------------------------------------------------------------------
    @property
    def adapting(self) -> bool:
        """Whether a_s, b_s are being estimated; set False to hold them (6.3.2)."""
        return self._adapting

    @adapting.setter
    def adapting(self, value: bool) -> None:
        if value == self._adapting:
            return
        self._adapting = value
        if value:
            self.kalman.P[PARAMETERS, PARAMETERS] = self._frozen_parameter_covariance
        else:
            self._frozen_parameter_covariance = self.kalman.P[PARAMETERS, PARAMETERS].copy()
            self._hold_parameters()

    def _hold_parameters(self) -> None:
        self.kalman.P[PARAMETERS, :] = 0.0
        self.kalman.P[:, PARAMETERS] = 0.0

    # -- estimates ------------------------------------------------------------------------------
    @property
    def rate_of_turn(self) -> float:
        """r^, rad/s."""
        return float(self.kalman.x[RATE, 0])

    @property
    def heading(self) -> float:
        """psi^, the low-frequency heading, rad, unwrapped (continuous from the first compass reading)."""
        return float(self.kalman.x[HEADING, 0])

    @property
    def last_rudder(self) -> float:
        """The actual rudder of the latest sample, rad (the input of the next prediction)."""
        return self._rudder

    @property
    def offset(self) -> float:
        """N_w^, the offset in rad/s per sample (5.17)."""
        return float(self.kalman.x[OFFSET, 0])

    @property
    def discrete_parameters(self) -> tuple[float, float]:
        """(a_s^, b_s^) at the current speed (5.4, 5.5)."""
        return float(self.kalman.x[A_S, 0]), float(self.kalman.x[B_S, 0])

    @property
    def parameters(self) -> NomotoParameters | None:
        """K*^, tau*^ recovered by (5.27, 5.28); None while the estimate is no stable ship (a_s >= 1 or b_s <= 0)."""
        a_s, b_s = self.discrete_parameters
        if not (a_s < 1.0 and b_s > 0.0):
            return None
        return NomotoParameters.from_discrete(a_s, b_s, self.sample_time, self.speed, self.length)

    # -- the model ------------------------------------------------------------------------------
    def _reschedule(self, speed: float) -> None:
        """Carry a_s, b_s (and P) from the previous sample's speed to ``speed`` at fixed 1/tau*, K*/tau*."""
        ratio = speed / self.speed
        self.speed = speed
        if ratio == 1.0:
            return
        x = self.kalman.x
        x[A_S, 0] = 1.0 - (1.0 - x[A_S, 0]) * ratio
        x[B_S, 0] *= ratio**2
        scale = np.ones(STATE_SIZE)
        scale[A_S] = ratio
        scale[B_S] = ratio**2
        self.kalman.P = self.kalman.P * np.outer(scale, scale)

    def _jacobian(self, rudder: float) -> np.ndarray:
        x = self.kalman.x[:, 0]
        jacobian = np.eye(STATE_SIZE)
        jacobian[RATE, A_S] = x[RATE]
        jacobian[RATE, B_S] = rudder
        jacobian[RATE, OFFSET] = 1.0
        jacobian[RATE, RATE] = x[A_S]
        jacobian[WAVE_LOW_PASS, WAVE_LOW_PASS] = self.kalman.wave_pole
        jacobian[HEADING, RATE] = self.sample_time
        jacobian[WAVE_HEADING, WAVE_LOW_PASS] = -self.sample_time
        return jacobian

    def _process_noise(self) -> np.ndarray:
        noise = self.noise
        sample_time = self.sample_time
        speed_per_length = self.speed / self.length
        wave_gain = sample_time / noise.wave_time_constant  # b_f
        q = np.zeros((STATE_SIZE, STATE_SIZE))
        if self._adapting:
            q[A_S, A_S] = noise.inverse_time_constant_walk * sample_time * (sample_time * speed_per_length) ** 2
            q[B_S, B_S] = noise.gain_ratio_walk * sample_time * (sample_time * speed_per_length**2) ** 2
        q[OFFSET, OFFSET] = noise.offset_walk * sample_time * sample_time**2
        q[RATE, RATE] = noise.rate_model * sample_time
        q[HEADING, HEADING] = noise.heading_model * sample_time
        wave_variance = noise.wave_rate**2
        q[WAVE_LOW_PASS, WAVE_LOW_PASS] = wave_gain**2 * wave_variance
        q[WAVE_HEADING, WAVE_HEADING] = sample_time**2 * wave_variance
        q[WAVE_LOW_PASS, WAVE_HEADING] = q[WAVE_HEADING, WAVE_LOW_PASS] = wave_gain * sample_time * wave_variance
        return q

    def _update(self, measured_rate: float, measured_heading: float) -> None:
        available = [i for i, value in enumerate((measured_rate, measured_heading)) if not math.isnan(value)]
        if not available:
            self.kalman.update(None, _measurement_jacobian, _measurement_function)
            return
        kalman = self.kalman
        predicted_heading = kalman.x[HEADING, 0] + kalman.x[WAVE_HEADING, 0]
        # The compass reads any branch: bring it next to the prediction, so the residual is small.
        heading = predicted_heading + wrap_angle(measured_heading - predicted_heading)
        z = np.array([[measured_rate, heading][i] for i in available]).reshape(-1, 1)
        rows = np.array(available)
        kalman.update(
            z,
            _measurement_jacobian,
            _measurement_function,
            R=kalman.R[np.ix_(rows, rows)],
            args=(rows,),
            hx_args=(rows,),
        )
        if not self.gate.accepts(kalman.y, kalman.SI):
            kalman.x = kalman.x_prior.copy()
            kalman.P = kalman.P_prior.copy()


def _measurement_jacobian(x: np.ndarray, rows: np.ndarray | None = None) -> np.ndarray:
    return _MEASUREMENT_MATRIX if rows is None else _MEASUREMENT_MATRIX[rows]


def _measurement_function(x: np.ndarray, rows: np.ndarray | None = None) -> np.ndarray:
    return _measurement_jacobian(x, rows) @ x


def ship_yaw_filter(model: ShipModel, sample_time: float, parameters: NomotoParameters) -> YawFilter:
    """The yaw filter for ``model``'s ship, starting at ``parameters``: the reference ship's calibration and speed
    floor in the ship's own scales (:mod:`ship_env.envs.ship_scales`: times in L / U, speeds in U), so that a 7 m
    model and a 320 m tanker are filtered as the reference ship is; the reference ship gets them exactly."""
    scales = ship_scales(model)
    return YawFilter(
        model.length,
        sample_time,
        parameters,
        YawFilterNoise().for_ship(scales),
        minimum_speed=MINIMUM_SPEED * scales.speed,
    )
