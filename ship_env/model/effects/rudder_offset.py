"""Rudder offset: the rudder angle at which the ship goes straight is not zero.

    delta_e = delta + delta_0

A constant offset models a mis-aligned rudder indicator or the asymmetric side force of a single
right-handed propeller; it is equivalent to alpha0 = -K* delta_0 in H(r*) (2.27) at one speed,
but, being an angle, it scales with the rudder's effectiveness (e.g. with the slipstream).

Smallest physical size (``material``): 0.3 deg, a few tenths of a degree -- within a rudder
indicator's resolution and alignment tolerance (about 0.5 deg) it is a mismatch, not a mis-aligned rudder.
"""

from __future__ import annotations

import math

from ship_env.model.effect_api import Contribution, Effect, Parameter, kernel

EFFECT = Effect(
    "rudder_offset",
    "rudder offset (neutral rudder angle not at zero; propeller asymmetry)",
    "(2.27) alpha0, as an angle",
    Parameter("angle", "rad", "delta_0, added to the actual rudder angle", material=math.radians(0.3)),
)


@kernel
def effective_rudder(effective_rudder, angle):
    """delta_e = delta + delta_0."""
    return effective_rudder + angle


CONTRIBUTIONS = (Contribution("effective_rudder", effective_rudder),)
