"""Propeller slipstream over the rudder: rudder effectiveness that grows with propeller rate.

The rudder's lift scales with the square of its inflow speed u_R. Behind a propeller that inflow is
the ship's speed plus the propeller's induced velocity; momentum theory (actuator disc) gives a
far-slipstream speed with u_s^2 = u^2 + (8 K_T / pi) (n D)^2, of which the rudder sees a fraction.
The model uses

    u_R^2 = u^2 + c_s (n D)^2

in place of u^2 in the rudder term of the yaw equation (see ``yaw``), so the rudder moment is
K* (u_R / L)^2 delta / tau*. At low speed and high propeller rate (a ship accelerating from rest,
a harbour manoeuvre) the ship turns much faster than the speed-scheduled model predicts; at
rest with the propeller turning it still turns. With c_s = 0 the effect vanishes. A propeller
turning astern sends no slipstream over the rudder (see ``propeller_astern``).

Symbols: n propeller rate (rps), D propeller diameter (m), c_s slipstream coefficient
(about eta 8 K_T / pi, 0.1 to 0.5).

Smallest physical size (``material``): c_s = 0.01 changes the rudder's effectiveness by a few %
(3 %) at (n D / u)^2 = 3, a propeller's usual advance ratio u / (n D) of about 0.6.
"""

from __future__ import annotations

from ship_env.model.effect_api import Contribution, Effect, Parameter, kernel

EFFECT = Effect(
    "propeller_slipstream",
    "propeller slipstream over the rudder (more rudder effect at high propeller rate)",
    "rudder inflow u_R^2 = u^2 + c_s (n D)^2 in the rudder term of (2.54)",
    Parameter("coefficient", "-", "c_s, fraction of (n D)^2 added to the rudder inflow", minimum=0.0, material=0.01),
    Parameter("propeller_diameter", "m", "D, propeller diameter", minimum=0.0),
)


@kernel
def inflow_speed_squared(inflow_speed_squared, propeller_rate, coefficient, propeller_diameter):
    """u_R^2 = u^2 + c_s (n D)^2, m^2/s^2, from the inflow without it (u^2); a propeller astern adds nothing."""
    induced = max(propeller_rate, 0.0) * propeller_diameter
    return inflow_speed_squared + coefficient * induced * induced


CONTRIBUTIONS = (Contribution("inflow_speed_squared", inflow_speed_squared),)
