"""The position filter: a Kalman filter for speed, drift, current and position (thesis 5.4).

State (6, the thesis's x_p):

    x = (u, gamma, u_cx, u_cy, x_s, y_s)

u forward speed through the water (m/s), gamma the sway constant (m, v = -gamma r, 5.48), u_cx,
u_cy the current towards north and east (m/s), x_s, y_s the position north and east (m).
Inputs (r^, psi^): the filtered rate of turn and heading from the yaw filter. Measurements
(u~, x~_s, y~_s): the log and a position fix.

Process (sample time T_s; inputs and states at k-1):

    u(k) = u + w_u,  gamma(k) = gamma + w_gamma,  u_cx(k) = u_cx + w_cx,  u_cy(k) = u_cy + w_cy   (5.49-5.53)
    v = -gamma r^                                                                            (5.51)
    x_s(k) = x_s + T_s (u cos psi^ - v sin psi^ + u_cx)                                       (5.54, 5.56)
    y_s(k) = y_s + T_s (u sin psi^ + v cos psi^ + u_cy)                                       (5.55, 5.57)

Measurement: u~ = u + v_u, x~_s = x_s + v_x, y~_s = y_s + v_y (5.67-5.69).

With the heading and rate of turn as inputs the model is linear in the state (the reason the
thesis splits yaw and position filters, 5.2), so this is filterpy's linear ``KalmanFilter`` with a
transition matrix rebuilt each sample:

    F = I + T_s [e_x (cos psi^, r^ sin psi^, 1, 0, 0, 0) + e_y (sin psi^, -r^ cos psi^, 0, 1, 0, 0)]

Noise: u, gamma, u_cx, u_cy are random walks and x_s, y_s carry a small model error, with the
spectral densities of :class:`PositionFilterNoise` (variance per sample = density x T_s);
R = diag(sigma_log^2, sigma_fix^2, sigma_fix^2).

Bad input: samples without a fix (NaN north/east, or a fix whose ``fix_time`` was used before:
the usual case between fixes) or without a log reading update with what there is; an innovation
far outside its covariance is rejected, and a run of them raises
:class:`~ship_env.baselines.filter_health.FilterDivergenceError`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from filterpy.kalman import KalmanFilter

from ship_env.baselines.filter_health import InnovationGate
from ship_env.baselines.measurement import Measurement
from ship_env.envs.ship_scales import ShipScales

SPEED, SWAY_CONSTANT, CURRENT_NORTH, CURRENT_EAST, NORTH, EAST = range(6)
STATE_SIZE = 6
_MEASURED_STATES = np.array([SPEED, NORTH, EAST])


@dataclass(frozen=True)
class PositionFilterNoise:
    """The position filter's calibration (thesis 5.4, last paragraphs).

    Attributes:
        log: sigma of the log's speed error, m/s.
        position_fix: sigma of a position fix's error per axis, m (6.3.3: 50 m).
        speed_walk: spectral density of the random walk of u, (m/s)^2 / s.
        sway_walk: spectral density of the random walk of gamma, m^2 / s (0 holds gamma).
        current_walk: spectral density of the random walk of each current component, (m/s)^2 / s.
        position_model: spectral density of the model error on the position, m^2 / s.
        initial_current: initial sigma of each current component, m/s.
        initial_sway: initial sigma of gamma, m.
    """

    log: float = 0.05
    position_fix: float = 50.0
    speed_walk: float = 1e-3
    sway_walk: float = 0.1
    current_walk: float = 2e-5
    position_model: float = 0.1
    initial_current: float = 2.0
    initial_sway: float = 50.0

    def for_ship(self, scales: ShipScales) -> PositionFilterNoise:
        """This calibration, made for the reference ship, on a ship of ``scales``
        (:mod:`ship_env.envs.ship_scales`): lengths in ship lengths, speeds in units of U, times in
        L / U, so each spectral density scales with its units over time."""
        length, speed, time = scales.length, scales.speed, scales.time
        return PositionFilterNoise(
            log=self.log * speed,
            position_fix=self.position_fix * length,
            speed_walk=self.speed_walk * speed**2 / time,
            sway_walk=self.sway_walk * length**2 / time,
            current_walk=self.current_walk * speed**2 / time,
            position_model=self.position_model * length**2 / time,
            initial_current=self.initial_current * speed,
            initial_sway=self.initial_sway * length,
        )


class PositionFilter:
    """Filtered speed and position, the sway constant and the current, from log, fixes and the yaw filter.

    Call :meth:`reset` with the first sample, then :meth:`step` once per sample with the yaw
    filter's rate of turn and heading.

    Args:
        sample_time: T_s, s.
        sway_constant: the initial gamma, m (gamma* L, 5.77).
        noise: the filter's calibration.
        gate: the innovation check (default: the NIS gate of :mod:`ship_env.baselines.filter_health`).
    """

    def __init__(
        self,
        sample_time: float,
        sway_constant: float = 0.0,
        noise: PositionFilterNoise | None = None,
        gate: InnovationGate | None = None,
    ) -> None:
        if not sample_time > 0.0:
            raise ValueError(f"sample_time: expected a positive time in s, got {sample_time!r}")
        self.sample_time = sample_time
        self.initial_sway_constant = sway_constant
        self.noise = noise = noise or PositionFilterNoise()
        self.gate = gate or InnovationGate("position filter")
        self.kalman = KalmanFilter(dim_x=STATE_SIZE, dim_z=3)
        self.kalman.R = np.diag([noise.log**2, noise.position_fix**2, noise.position_fix**2])
        self.kalman.Q = sample_time * np.diag(
            [
                noise.speed_walk,
                noise.sway_walk,
                noise.current_walk,
                noise.current_walk,
                noise.position_model,
                noise.position_model,
            ]
        )
        self._rate_of_turn = 0.0
        self._heading = 0.0
        self._last_fix_time = -math.inf

    def reset(self, measurement: Measurement, rate_of_turn: float, heading: float) -> None:
        """Start on the first sample; a missing fix starts the position at the origin, very uncertain."""
        noise = self.noise
        has_fix = not (math.isnan(measurement.north) or math.isnan(measurement.east))
        position_sigma = noise.position_fix if has_fix else 1e4
        self.kalman.x = np.array(
            [
                [
                    0.0 if math.isnan(measurement.speed) else measurement.speed,
                    self.initial_sway_constant,
                    0.0,
                    0.0,
                    measurement.north if has_fix else 0.0,
                    measurement.east if has_fix else 0.0,
                ]
            ]
        ).T
        speed_sigma = noise.log if not math.isnan(measurement.speed) else 10.0
        self.kalman.P = (
            np.diag(
                [
                    speed_sigma,
                    noise.initial_sway,
                    noise.initial_current,
                    noise.initial_current,
                    position_sigma,
                    position_sigma,
                ]
            )
            ** 2
        )
        self._rate_of_turn = rate_of_turn
        self._heading = heading
        self._last_fix_time = -math.inf
        self._new_fix(measurement)
        self.gate.outliers_in_a_row = 0

    def step(self, measurement: Measurement, rate_of_turn: float, heading: float) -> None:
        """Predict over the last sample with the previous r^, psi^, then update with this sample's log and fix."""
        self.kalman.predict(F=self._transition())
        self._rate_of_turn = rate_of_turn
        self._heading = heading
        readings = np.array([measurement.speed, measurement.north, measurement.east])
        if not self._new_fix(measurement):
            readings[1:] = math.nan
        available = ~np.isnan(readings)
        if not available.any():
            self.kalman.update(None)
            return
        rows = np.flatnonzero(available)
        kalman = self.kalman
        kalman.update(
            readings[rows].reshape(-1, 1),
            R=kalman.R[np.ix_(rows, rows)],
            H=np.eye(STATE_SIZE)[_MEASURED_STATES[rows]],
        )
        if not self.gate.accepts(kalman.y, kalman.SI):
            kalman.x = kalman.x_prior.copy()
            kalman.P = kalman.P_prior.copy()

    def _new_fix(self, measurement: Measurement) -> bool:
        """Whether the sample brings a fix not used before; remembers its time."""
        if math.isnan(measurement.north) or math.isnan(measurement.east):
            return False
        if math.isnan(measurement.fix_time):
            return True
        if measurement.fix_time <= self._last_fix_time:
            return False
        self._last_fix_time = measurement.fix_time
        return True

    def _transition(self) -> np.ndarray:
        cos_heading = math.cos(self._heading)
        sin_heading = math.sin(self._heading)
        rate = self._rate_of_turn
        step = self.sample_time
        transition = np.eye(STATE_SIZE)
        transition[NORTH, SPEED] = step * cos_heading
        transition[NORTH, SWAY_CONSTANT] = step * rate * sin_heading
        transition[NORTH, CURRENT_NORTH] = step
        transition[EAST, SPEED] = step * sin_heading
        transition[EAST, SWAY_CONSTANT] = -step * rate * cos_heading
        transition[EAST, CURRENT_EAST] = step
        return transition

    # -- estimates ------------------------------------------------------------------------------
    @property
    def speed(self) -> float:
        """u^, forward speed through the water, m/s."""
        return float(self.kalman.x[SPEED, 0])

    @property
    def sway_constant(self) -> float:
        """gamma^, m (v = -gamma r)."""
        return float(self.kalman.x[SWAY_CONSTANT, 0])

    @property
    def current(self) -> tuple[float, float]:
        """(u_cx^, u_cy^), the current towards north and east, m/s."""
        return float(self.kalman.x[CURRENT_NORTH, 0]), float(self.kalman.x[CURRENT_EAST, 0])

    @property
    def current_uncertainty(self) -> float:
        """The larger standard deviation of the current's two estimates, m/s (the filter's covariance)."""
        return math.sqrt(max(self.kalman.P[CURRENT_NORTH, CURRENT_NORTH], self.kalman.P[CURRENT_EAST, CURRENT_EAST]))

    @property
    def position(self) -> tuple[float, float]:
        """(x_s^, y_s^), north and east, m."""
        return float(self.kalman.x[NORTH, 0]), float(self.kalman.x[EAST, 0])
