"""Sway (drift) velocity in a turn, after Van Leeuwen (thesis 2.47-2.49, 2.56, 2.60).

    v* + H_v(r*) = 0,   v* = v / u,   H_v(r*) = gamma1* r* + gamma3* r*^3           (2.47-2.49)

so v = -u (gamma1* r* + gamma3* r*^3); with gamma3* = 0 this is v = -gamma r, gamma = gamma1* L
(2.60, 2.63). The ship turning to starboard (r > 0) drifts to port (v < 0): its bow points inside
the circle by the drift angle beta = atan(-v/u).
"""

from __future__ import annotations

from ship_env.model.effect_api import Contribution, Effect, Parameter, kernel

EFFECT = Effect(
    "sway",
    "drift angle in a turn (Van Leeuwen sway velocity)",
    "(2.47)-(2.49), (2.60)",
    Parameter("linear", "-", "gamma1*, sway per normalised rate of turn (gamma = gamma1* L)"),
    Parameter("cubic", "-", "gamma3*, cubic coefficient of H_v(r*)"),
)


@kernel
def velocity(speed, normalised_rate, linear, cubic):
    """v from (2.47)-(2.49), m/s, positive to starboard."""
    return -speed * (linear * normalised_rate + cubic * normalised_rate * normalised_rate * normalised_rate)


CONTRIBUTIONS = (Contribution("sway_velocity", velocity),)
