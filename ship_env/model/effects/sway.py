"""Sway (drift) velocity in a turn, after Van Leeuwen (thesis 2.47-2.49, 2.56, 2.60).

    v* + H_v(r*) = 0,   v* = v / u,   H_v(r*) = gamma1* r* + gamma3* r*^3           (2.47-2.49)

so v = -u (gamma1* r* + gamma3* r*^3); with gamma3* = 0 this is v = -gamma r, gamma = gamma1* L
(2.60, 2.63). The ship turning to starboard (r > 0) drifts to port (v < 0): its bow points inside
the circle by the drift angle beta = atan(-v/u).

Smallest physical sizes (``material``): gamma1* = 0.02 and gamma3* = 0.08 each give a drift angle of
about 0.6 deg at r* = 0.5 (a track that drifts 1 % of the distance sailed).
"""

from __future__ import annotations

from ship_env.model.effect_api import Contribution, Effect, Parameter, kernel

EFFECT = Effect(
    "sway",
    "drift angle in a turn (Van Leeuwen sway velocity)",
    "(2.47)-(2.49), (2.60)",
    Parameter("linear", "-", "gamma1*, sway per normalised rate of turn (gamma = gamma1* L)", material=0.02),
    Parameter("cubic", "-", "gamma3*, cubic coefficient of H_v(r*)", material=0.08),
)


@kernel
def settled_drift(normalised_rate, linear, cubic):
    """v* = -H_v(r*) = -(gamma1* r* + gamma3* r*^3) (2.47)-(2.49)."""
    return -(linear * normalised_rate + cubic * normalised_rate * normalised_rate * normalised_rate)


@kernel
def velocity(speed, normalised_rate, linear, cubic):
    """v = u v* from (2.47)-(2.49), m/s, positive to starboard."""
    return speed * settled_drift(normalised_rate, linear, cubic)


CONTRIBUTIONS = (Contribution("sway_velocity", velocity),)
