"""The model-reference adaptive autopilot: the yaw filter as reference model and compensator (thesis 5.5.3, 5.6.2.1).

The yaw filter identifies the ship, r(k) = a_s^ r + b_s^ delta + N_w^ (5.82). A reference model
r_R(k) = a_R r_R(k-1) + b_R delta(k-1) holds the averaged estimates (5.91):

    a_R(k) = a_R(k-1) + K_R (a_s^(k) - a_R(k-1))                                       (5.91)

kept here, like the filter's, on the speed-free 1/tau* and K*/tau* and converted to (a_R, b_R)
at the current speed by (5.4, 5.5); K_R = 0 holds the reference model (the filter then serves
only for compensation, 5.92), K_R = 1 makes it the latest estimate (no compensation, 5.93); the
reference model adapts in a time of about T_s / K_R. The PD autopilot's gains (5.79, 5.80) come
from the reference model's K_R*, tau_R*, and it acts on the filtered heading and rate. The
rudder sent to the ship is compensated for the ship's deviation from the reference model (5.90):

    delta'' = delta - (Delta a_s r^ + Delta b_s delta + N_w^) / b_s^                   (5.90)
    Delta a_s = a_s^ - a_R,  Delta b_s = b_s^ - b_R

so that the ship answers delta like the reference model does (5.86-5.89). The filter's rudder
input is the measured actual rudder (Fig. 5.15): the steering machine's lag and limit are seen by
the filter, and the reference model, driven by the actual rudder plus the compensation,
delta_R = delta_actual + Delta delta, gets the same input as the compensated ship.

6.3.2: the thesis adapts the parameters only during course changes (waves make them drift on a
steady course) while the offset N_w is always estimated; ``adaptation_band`` does this.

Monitoring: :attr:`ModelReferenceAutopilot.compensation` (Delta delta, rad) and
:attr:`ModelReferenceAutopilot.reference_rate` (r_R, rad/s) each sample.
"""

from __future__ import annotations

from ship_env.baselines.measurement import Measurement, wrap_angle
from ship_env.baselines.nomoto import NomotoParameters
from ship_env.baselines.pd_autopilot import PDDesign
from ship_env.baselines.yaw_filter import YawFilter


class ModelReferenceAutopilot:
    """The MRAC autopilot of Figs. 5.14, 5.15, 5.17 (an :class:`~ship_env.baselines.controller.Autopilot`).

    Args:
        design: the PD's tuning (closed-loop natural frequency, damping, rudder limit, scheduling).
        yaw_filter: the yaw filter; its sample time must be the autopilot's.
        reference: the reference model's initial K_R*, tau_R*.
        reference_gain: K_R of (5.91), per sample (0 holds the reference model).
        compensating: whether the ship's rudder is compensated by (5.90).
        adaptation_band: if set, a_s, b_s are estimated only while the heading error exceeds this
            angle, rad (6.3.2); None estimates them always.
    """

    def __init__(
        self,
        design: PDDesign,
        yaw_filter: YawFilter,
        reference: NomotoParameters,
        reference_gain: float,
        compensating: bool = True,
        adaptation_band: float | None = None,
    ) -> None:
        if not 0.0 <= reference_gain <= 1.0:
            raise ValueError(f"reference_gain: expected K_R in [0, 1], got {reference_gain!r}")
        self.design = design
        self.yaw_filter = yaw_filter
        self.initial_reference = reference
        self.reference_gain = reference_gain
        self.compensating = compensating
        self.adaptation_band = adaptation_band
        self.reference = reference
        self.compensation = 0.0
        self.reference_rate = 0.0

    def reset(self, measurement: Measurement) -> None:
        self.yaw_filter.reset(measurement)
        self.reference = self.initial_reference
        self.compensation = 0.0
        self.reference_rate = self.yaw_filter.rate_of_turn

    @property
    def prediction_model(self) -> NomotoParameters:
        """The reference model's K_R*, tau_R*: the track predictor's model (5.6.2.1, Fig. 5.17)."""
        return self.reference

    def order(self, setpoint: float, measurement: Measurement) -> float:
        yaw_filter = self.yaw_filter
        if yaw_filter.take_sample(measurement):
            self._advance_reference_model(yaw_filter.last_rudder)
        estimate = yaw_filter.parameters
        if estimate is not None:
            self._average_reference(estimate)
        heading_error = wrap_angle(setpoint - yaw_filter.heading)
        if self.adaptation_band is not None:
            yaw_filter.adapting = abs(heading_error) > self.adaptation_band
        gains = self.design.gains(self.reference, yaw_filter.length, yaw_filter.speed)
        rudder = self.design.rudder(heading_error, yaw_filter.rate_of_turn, gains)
        self.compensation = self._compensation(rudder) if estimate is not None else 0.0
        return rudder - self.compensation if self.compensating else rudder

    def _advance_reference_model(self, actual_rudder: float) -> None:
        """r_R(k) = a_R r_R(k-1) + b_R delta_R(k-1), delta_R = actual rudder + Delta delta (Fig. 5.15)."""
        a_r, b_r = self.reference.discrete(self.yaw_filter.sample_time, self.yaw_filter.speed, self.yaw_filter.length)
        model_input = actual_rudder + (self.compensation if self.compensating else 0.0)
        self.reference_rate = a_r * self.reference_rate + b_r * model_input

    def _average_reference(self, estimate: NomotoParameters) -> None:
        """(5.91) on 1/tau* and K*/tau*."""
        gain = self.reference_gain
        if gain == 0.0:
            return
        inverse_time_constant = 1.0 / self.reference.time_constant
        gain_ratio = self.reference.gain / self.reference.time_constant
        inverse_time_constant += gain * (1.0 / estimate.time_constant - inverse_time_constant)
        gain_ratio += gain * (estimate.gain / estimate.time_constant - gain_ratio)
        self.reference = NomotoParameters(gain_ratio / inverse_time_constant, 1.0 / inverse_time_constant)

    def _compensation(self, rudder: float) -> float:
        """Delta delta of (5.90), rad."""
        yaw_filter = self.yaw_filter
        a_s, b_s = yaw_filter.discrete_parameters
        a_r, b_r = self.reference.discrete(yaw_filter.sample_time, yaw_filter.speed, yaw_filter.length)
        deviation = (a_s - a_r) * yaw_filter.rate_of_turn + (b_s - b_r) * rudder + yaw_filter.offset
        return deviation / b_s
