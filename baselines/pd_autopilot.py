"""The PD course-changing autopilot with gain scheduling (thesis 3.3.2.2, 5.5.2).

Control law with the rudder limiter (3.45, Fig. 3.5):

    delta = clip(K_p (psi_r - psi) - K_d r, -delta_max, delta_max)                    (3.45)

Gains by pole placement on the Nomoto ship tau dr/dt + r = K delta, tau = tau* L/u, K = K* u/L,
for a closed loop of natural frequency omega_n and damping zeta (Van Amerongen 1982):

    K_p = omega_n^2 (tau*/K*) (L/u)^2                                                  (5.79)
    K_d = (L/u) (2 zeta sqrt(K_p K* tau*) - 1) / K*                                    (5.80)

Check: the closed loop is tau psi'' + (1 + K K_d) psi' + K K_p psi = K K_p psi_r, so
omega_n^2 = K K_p / tau and 2 zeta omega_n = (1 + K K_d) / tau; with K, tau as above these give
(5.79) and, since sqrt(K_p K* tau*) = omega_n tau* L/u, (5.80).

Gain scheduling. The predictor of chapter 3 needs the closed loop to be the same in the distance
domain s* = (u/L) t whatever the speed, which holds when K_p is fixed and K_d = K_d* L/u (3.52).
(5.79, 5.80) give exactly that when the natural frequency is held constant per ship length,
omega_n(u) = omega_n* u/L: then K_p = omega_n*^2 tau*/K* and K_d = (L/u)(2 zeta omega_n* tau* - 1)/K*.
The scheduled autopilot therefore takes omega_n at a design speed U_d and uses
omega_n(u) = omega_n u / U_d; the fixed-gain variant computes the gains once at U_d. Halving the
speed halves K and doubles tau, so fixed gains leave the loop with omega_n/2 and damping
zeta/2 + 1/(4 omega_n tau(U_d)): less damped, more overshoot.

Symbols: psi heading, psi_r ordered heading (rad), r rate of turn (rad/s), delta rudder (rad).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from baselines.measurement import Measurement, wrap_angle
from baselines.nomoto import NomotoParameters

#: The scheduling speed is floored at this fraction of the design speed: the gains grow as 1/u and
#: a ship nearly stopped must not get an unbounded derivative gain.
MINIMUM_SPEED_FRACTION = 0.1


@dataclass(frozen=True)
class PDGains:
    """Gains of (3.45).

    Attributes:
        proportional: K_p, rad of rudder per rad of heading error.
        derivative: K_d, s: rad of rudder per rad/s of rate of turn.
    """

    proportional: float
    derivative: float


def pd_gains(natural_frequency: float, damping: float, ship: NomotoParameters, length: float, speed: float) -> PDGains:
    """K_p, K_d of (5.79, 5.80) for closed-loop ``natural_frequency`` (rad/s) and ``damping`` at ``speed`` (m/s)."""
    length_per_speed = length / speed
    proportional = natural_frequency**2 * ship.time_constant / ship.gain * length_per_speed**2
    derivative = (
        length_per_speed * (2.0 * damping * math.sqrt(proportional * ship.gain * ship.time_constant) - 1.0) / ship.gain
    )
    return PDGains(proportional, derivative)


@dataclass(frozen=True)
class PDDesign:
    """How the PD autopilot is tuned.

    Attributes:
        natural_frequency: omega_n of the closed loop at the design speed, rad/s.
        damping: zeta of the closed loop.
        rudder_limit: delta_max, rad.
        design_speed: U_d, m/s, the speed ``natural_frequency`` is given at.
        scheduled: True schedules the gains on the speed (omega_n L/u constant, (3.52));
            False keeps the gains computed at the design speed.
    """

    natural_frequency: float
    damping: float
    rudder_limit: float
    design_speed: float
    scheduled: bool = True

    def __post_init__(self) -> None:
        for name in ("natural_frequency", "damping", "rudder_limit", "design_speed"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0.0):
                raise ValueError(f"{name}: expected a positive number, got {value!r}")

    def gains(self, ship: NomotoParameters, length: float, speed: float) -> PDGains:
        """The gains for a ship of parameters ``ship`` and length ``length`` (m) sailing at ``speed`` (m/s)."""
        if not self.scheduled:
            return pd_gains(self.natural_frequency, self.damping, ship, length, self.design_speed)
        speed = max(speed, MINIMUM_SPEED_FRACTION * self.design_speed)
        return pd_gains(self.natural_frequency * speed / self.design_speed, self.damping, ship, length, speed)

    def rudder(self, heading_error: float, rate_of_turn: float, gains: PDGains) -> float:
        """The limited rudder order of (3.45), rad."""
        order = gains.proportional * heading_error - gains.derivative * rate_of_turn
        return min(max(order, -self.rudder_limit), self.rudder_limit)


class PDAutopilot:
    """The PD autopilot on the raw instruments (compass, rate gyro, log), gains from known K*, tau*.

    Args:
        design: the tuning (see :class:`PDDesign`; ``scheduled=False`` is the fixed-gain variant).
        ship: the ship's K*, tau* the gains are computed from.
        length: the ship's length L, m.
    """

    def __init__(self, design: PDDesign, ship: NomotoParameters, length: float) -> None:
        self.design = design
        self.ship = ship
        self.length = length

    def reset(self, measurement: Measurement) -> None:
        """Nothing to restart: the PD has no memory."""

    def order(self, setpoint: float, measurement: Measurement) -> float:
        gains = self.design.gains(self.ship, self.length, measurement.speed)
        return self.design.rudder(wrap_angle(setpoint - measurement.heading), measurement.rate_of_turn, gains)
