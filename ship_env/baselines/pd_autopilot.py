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

Gain scheduling. Write s = u/U_d for the speed against the design speed U_d. Gains fixed at U_d
leave the loop on the ship at speed u with (from the closed loop above, K and 1/tau both times s)

    omega_n(u) = s omega_n,   zeta(u) = s zeta + (1 - s) / (2 omega_n tau(U_d))

so at half speed omega_n halves and, for the baselines' tuning (omega_n = 0.06 rad/s, zeta = 1,
tau(U_d) = 40 s on the container ship), zeta falls to 0.60: the loop is twice as slow in seconds
and swings past the new heading. Two schedules keep a closed loop instead:

- ``"time"``: omega_n and zeta held in seconds, (5.79, 5.80) as they stand with the speed
  measured: K_p grows as (U_d/u)^2 and K_d about as much, since the rudder's moment falls as u^2.
  The course-changing autopilots use it: the turn and the settling take the same time at any
  speed, as long as the rudder does not saturate (at full helm the ship turns at K delta_max,
  proportional to u, whatever the gains).
- ``"distance"``: the closed loop held in the distance domain s* = (u/L) t, omega_n(u) =
  omega_n u / U_d: then K_p is fixed and K_d = K_d* L/u (3.52). The track predictor needs this:
  the predicted track is then the same at any speed (3.55, 3.56). In seconds it has the fixed
  gains' omega_n(u) with the design damping kept, so at half speed it turns onto the new heading
  later than the fixed gains, whose damping of 0.60 lets the heading rise sooner.

A gain that grows with 1/u^2 also multiplies the rudder's answer to the instruments' noise: on the
raw gyro the ``"time"`` schedule at half speed works the rudder far more than the fixed gains,
most of it noise the ship does not feel (the manoeuvre itself, noise-free, takes a little more
than their travel; the leaderboard's figures: ``docs/results/leaderboard.md``). On filtered signals
(the adaptive autopilots) the same schedule needs less rudder travel than the fixed PD.

Symbols: psi heading, psi_r ordered heading (rad), r rate of turn (rad/s), delta rudder (rad).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal, get_args

from ship_env.baselines.measurement import Measurement, wrap_angle
from ship_env.baselines.nomoto import NomotoParameters

#: How the gains follow the measured speed: see the module's docstring.
Schedule = Literal["time", "distance", "fixed"]

#: The scheduling speed is floored at this fraction of the design speed: the gains grow as 1/u or
#: 1/u^2 and a ship nearly stopped must not get unbounded ones.
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
        schedule: ``"time"`` holds omega_n and zeta in seconds at any speed (5.79, 5.80);
            ``"distance"`` holds them per ship length sailed, omega_n L/u constant (3.52);
            ``"fixed"`` keeps the gains computed at the design speed.
    """

    natural_frequency: float
    damping: float
    rudder_limit: float
    design_speed: float
    schedule: Schedule = "time"

    def __post_init__(self) -> None:
        for name in ("natural_frequency", "damping", "rudder_limit", "design_speed"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0.0):
                raise ValueError(f"{name}: expected a positive number, got {value!r}")
        if self.schedule not in get_args(Schedule):
            raise ValueError(f"schedule: expected one of {', '.join(get_args(Schedule))}, got {self.schedule!r}")

    def gains(self, ship: NomotoParameters, length: float, speed: float) -> PDGains:
        """The gains for a ship of parameters ``ship`` and length ``length`` (m) sailing at ``speed`` (m/s)."""
        if self.schedule == "fixed":
            return pd_gains(self.natural_frequency, self.damping, ship, length, self.design_speed)
        speed = max(speed, MINIMUM_SPEED_FRACTION * self.design_speed)
        natural_frequency = self.natural_frequency
        if self.schedule == "distance":
            natural_frequency *= speed / self.design_speed
        return pd_gains(natural_frequency, self.damping, ship, length, speed)

    def rudder(self, heading_error: float, rate_of_turn: float, gains: PDGains) -> float:
        """The limited rudder order of (3.45), rad."""
        order = gains.proportional * heading_error - gains.derivative * rate_of_turn
        return min(max(order, -self.rudder_limit), self.rudder_limit)


class PDAutopilot:
    """The PD autopilot on the raw instruments (compass, rate gyro, log), gains from known K*, tau*.

    Args:
        design: the tuning (see :class:`PDDesign`; ``schedule="fixed"`` is the fixed-gain variant).
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
