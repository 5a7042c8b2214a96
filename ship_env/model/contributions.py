"""What an effect adds to the ship's state derivative: its contributions to named quantities.

The model computes d(state)/dt in a fixed sequence of *quantities* (:data:`QUANTITIES`): the sway
velocity, the velocity over the ground, the apparent wind, the effective rudder and the rudder's
inflow, H(r*), the yaw accelerations, the speed-loss rate and the disturbance states' rates. An
effect declares, for each quantity it changes, a :class:`Contribution`: a function of floats
whose *argument names* say what it reads. ``dynamics`` composes the contributions of the effects
that are registered into one compiled function; each runs only where its effect is on.

A contribution either *adds* to its quantity or, when it takes the quantity itself as an
argument, *replaces* it (``effective_rudder(effective_rudder, angle)`` returns the new angle).
Contributions to one quantity run in the order the effects were registered.

An argument may name:

- a quantity computed before it (see :data:`QUANTITIES`, in order) or one of :data:`INPUTS`;
- a state variable (``heading``, ``speed_loss``...; see ``state.STATE_NAMES``), with ``rudder`` the
  actual rudder at the instant;
- a condition (``propeller_rate``, ``wind_speed``...; see ``state.CONDITION_NAMES``);
- a principal particular (``length``, ``draught``...);
- one of the effect's own parameters by its name (``gain``), or any effect's parameter by its
  record field (``propeller_slipstream_propeller_diameter``).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

#: Values every contribution may read, computed first: u = U0 (1 - u*) (2.53), the speed floored at
#: ``minimum_speed`` where the model divides by it, r* = L r / u (2.40), cos(psi), sin(psi), and
#: the white noise held over the step (unit intensity, scaled by 1/sqrt(dt)).
INPUTS: dict[str, str] = {
    "speed": "u, forward speed through the water, m/s (2.53)",
    "scheduling_speed": "u floored at the principal minimum_speed, m/s: use it where dividing by u",
    "normalised_rate": "r* = L r / u, the normalised rate of turn (2.40)",
    "cos_heading": "cos(psi)",
    "sin_heading": "sin(psi)",
    "wave_white_noise": "white noise driving the wave filter, 1/sqrt(s)",
    "gust_white_noise": "white noise driving the gusts, 1/sqrt(s)",
}

#: The quantities, in the order they are computed, with their starting value and what they hold.
#: ``ground_velocity`` is a pair (north, east); a contribution that reads the apparent wind adds to
#: it after the wind is known (the wind is computed from the velocity over the ground before that).
QUANTITIES: dict[str, tuple[str, str]] = {
    "sway_velocity": ("0.0", "v, sway velocity through the water, m/s, + to starboard (2.47)"),
    "ground_velocity": ("(0.0, 0.0)", "(dx0/dt, dy0/dt), velocity over the ground north and east, m/s (2.64)"),
    "relative_wind_speed": ("0.0", "V_wr, apparent wind speed, m/s (2.74); computed where an effect reads it"),
    "cos_wind": ("1.0", "cos(gamma_r), the apparent wind's angle off the bow (2.74)"),
    "sin_wind": ("0.0", "sin(gamma_r), + for a wind from starboard (2.74)"),
    "effective_rudder": ("rudder", "delta_e, the rudder angle that makes the rudder force, rad"),
    "inflow_speed_squared": ("speed * speed", "u_R^2, squared inflow speed at the rudder, m^2/s^2"),
    "restoring": ("0.0", "H(r*), the hull's yaw damping function of r* (2.27)"),
    "side_moment": ("0.0", "M_p, a side moment in the units of u_R^2 K* delta, m^2/s^2 (yaw.py)"),
    "hull_yaw_acceleration": ("0.0", "dr/dt from the rudder and the hull, rad/s^2 (2.54)"),
    "yaw_acceleration": ("held_yaw_acceleration", "dr/dt added by outside moments (wind, waves), rad/s^2"),
    "speed_loss_derivative": ("0.0", "du*/dt, 1/s (2.55); acts where the speed_loss effect is on"),
    "wave_heading_derivative": ("0.0", "d/dt of the HF wave heading, rad/s"),
    "wave_rate_derivative": ("0.0", "d/dt of the HF wave rate of turn, rad/s^2"),
    "gust_derivative": ("0.0", "d/dt of the gust on the apparent wind speed, m/s^2"),
}

#: The apparent wind: computed (2.74) only where an effect that reads it is on.
WIND = ("relative_wind_speed", "cos_wind", "sin_wind")

#: The state variables whose derivative is a quantity, written only where the effect that owns the
#: state (``STATES`` of its module) is on; otherwise the state stays where it is.
STATE_DERIVATIVES: dict[str, str] = {
    "speed_loss": "speed_loss_derivative",
    "wave_heading": "wave_heading_derivative",
    "wave_rate": "wave_rate_derivative",
    "gust": "gust_derivative",
}


@dataclass(frozen=True)
class Contribution:
    """One effect's term in one quantity of the state derivative.

    Attributes:
        quantity: the quantity it changes (a key of :data:`QUANTITIES`).
        function: a function of floats (compiled with ``ship_env.model.kernel.kernel``, or plain
            Python, which is then compiled); its argument names say what it reads (module
            docstring). It returns the quantity's new value if it reads the quantity, else the
            amount it adds (a pair for ``ground_velocity``).
    """

    quantity: str
    function: Callable[..., Any]
