"""Steering machine: rudder limiter and rudder-rate limiter (thesis 2.3.4, Fig. 2.9).

The ordered rudder delta_r is limited to +-delta_max (always, by the integrator: it is the rudder's
hard-over angle); the actual rudder follows it at a rate limited to +-rudder_rate (typically 2.5 to 7 deg/s). With
this effect off the actual rudder equals the limited order at once.

The rate limiter is integrated exactly: over a time h the actual rudder moves towards the order by
at most rudder_rate * h, so 0 -> 35 deg takes exactly 35 / rate seconds.
"""

from __future__ import annotations

from ship_env.model.effect_api import Contribution, Effect, Parameter, kernel

EFFECT = Effect(
    "steering_machine",
    "steering-machine rate limit (rudder follows the order at a limited speed)",
    "(2.3.4), Fig. 2.9",
    Parameter("rudder_rate", "rad/s", "maximum rate of the actual rudder", minimum=1e-6),
)


@kernel
def rudder_after(rudder, limited_order, duration, rudder_rate):
    """The actual rudder ``duration`` seconds later, moving towards the order at most at the rate."""
    largest_move = rudder_rate * duration
    return rudder + min(max(limited_order - rudder, -largest_move), largest_move)


#: The steering machine moves the actual rudder itself, exactly, over each step: no derivative.
CONTRIBUTIONS = (Contribution("actual_rudder", rudder_after),)
