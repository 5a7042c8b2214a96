"""The indirect adaptive autopilot: the PD autopilot tuned by the yaw filter (thesis 5.5.2, Fig. 5.11).

Each sample the yaw filter (5.3) updates its estimates from gyro, compass, rudder and speed; the
PD gains (5.79, 5.80) are recomputed from the estimated K*^, tau*^ and the speed, and the PD acts
on the filtered heading and rate of turn, so the waves' high-frequency yaw does not work the
rudder:

    delta = clip(K_p(K*^, tau*^, u) (psi_r - psi^) - K_d(K*^, tau*^, u) r^, -delta_max, delta_max)

While the filter's estimate is no stable ship (early on, or after a disturbance) the last valid
estimate, at first the filter's initial parameters, is used.
"""

from __future__ import annotations

from ship_env.baselines.measurement import Measurement, wrap_angle
from ship_env.baselines.nomoto import NomotoParameters
from ship_env.baselines.pd_autopilot import PDDesign
from ship_env.baselines.yaw_filter import YawFilter


class IndirectAdaptiveAutopilot:
    """PD autopilot with gains from the yaw filter's K*, tau*, on filtered signals.

    An :class:`~ship_env.baselines.controller.Autopilot`.

    Args:
        design: the PD's tuning (closed-loop natural frequency, damping, rudder limit, scheduling).
        yaw_filter: the yaw filter; its sample time must be the autopilot's.
    """

    def __init__(self, design: PDDesign, yaw_filter: YawFilter) -> None:
        self.design = design
        self.yaw_filter = yaw_filter
        self.ship = yaw_filter.initial_parameters

    def reset(self, measurement: Measurement) -> None:
        self.yaw_filter.reset(measurement)
        self.ship = self.yaw_filter.initial_parameters

    @property
    def prediction_model(self) -> NomotoParameters:
        """The K*, tau* the gains are computed from: the track predictor's model (Fig. 5.16)."""
        return self.ship

    def order(self, setpoint: float, measurement: Measurement) -> float:
        self.yaw_filter.take_sample(measurement)
        self.ship = self.yaw_filter.parameters or self.ship
        gains = self.design.gains(self.ship, self.yaw_filter.length, measurement.speed)
        heading_error = wrap_angle(setpoint - self.yaw_filter.heading)
        return self.design.rudder(heading_error, self.yaw_filter.rate_of_turn, gains)
