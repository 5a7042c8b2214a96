"""Wind drift (leeway): the sway velocity at which the hull's lateral resistance balances the wind.

The wind's lateral force (2.79, 2.83) is Y_w = -1/2 rho_air a_y S_wy V_wr^2 sin(gamma_r) (a wind
from starboard pushes to port). The hull resists a sideways velocity v with a lift part, linear in
u v, and a cross-flow drag part, quadratic in v:

    Y_hull = -1/2 rho_water L T (C_L u + C_D |v|) v

Setting Y_w + Y_hull = 0 and writing c_y = rho_air a_y S_wy / (rho_water L T) gives the leeway

    (C_L u + C_D |v|) v = -c_y V_wr^2 sin(gamma_r)

solved in closed form. It adds to the sway velocity in the kinematics; it moves the track but not
the heading. At speed it is ~ V_wr^2 / u (lift), near rest ~ V_wr (cross-flow drag).

Symbols: c_y lateral force ratio, C_L hull lift slope, C_D cross-flow drag coefficient, T draught.

Smallest physical size (``material``): c_y = 6e-5 gives a leeway of 0.1 deg in a beam wind of three
times the ship's speed (v / u = c_y (V_wr / u)^2 / C_L with C_L = 0.3).
"""

from __future__ import annotations

import math

from ship_env.model.effect_api import Contribution, Effect, Parameter, kernel
from ship_env.model.effects.kinematics import velocity_over_ground

EFFECT = Effect(
    "wind_drift",
    "wind drift (leeway from the wind's side force)",
    "(2.79), (2.83) balanced by the hull's lateral resistance",
    Parameter("force_ratio", "-", "c_y = rho_air a_y S_wy / (rho_water L T)", minimum=0.0, material=6e-5),
    Parameter("lift_slope", "-", "C_L, hull lateral lift per unit drift angle", minimum=0.0),
    Parameter("crossflow_drag", "-", "C_D, hull cross-flow drag coefficient", minimum=1e-6),
)


@kernel
def leeway(speed, relative_wind_speed, sin_angle, force_ratio, lift_slope, crossflow_drag):
    """Leeway velocity v_w in m/s (positive to starboard) from the lateral force balance.

    ``sin_angle`` is sin(gamma_r) of the apparent wind (see ``wind.relative_wind``).
    """
    force = -force_ratio * relative_wind_speed * relative_wind_speed * sin_angle
    if force == 0.0:
        return 0.0
    linear = lift_slope * max(speed, 0.0)
    # Root of C_D |v| v + C_L u v = force, written without cancellation.
    magnitude = 2.0 * abs(force) / (linear + math.sqrt(linear * linear + 4.0 * crossflow_drag * abs(force)))
    return math.copysign(magnitude, force)


@kernel
def drift_over_ground(
    speed, relative_wind_speed, sin_wind, cos_heading, sin_heading, force_ratio, lift_slope, crossflow_drag
):
    """The leeway's (dx0/dt, dy0/dt) in m/s: a sway velocity turned into the earth frame (2.64, 2.65)."""
    drift_velocity = leeway(speed, relative_wind_speed, sin_wind, force_ratio, lift_slope, crossflow_drag)
    return velocity_over_ground(0.0, drift_velocity, cos_heading, sin_heading)


CONTRIBUTIONS = (Contribution("ground_velocity", drift_over_ground),)
