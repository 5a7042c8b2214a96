"""An effect written outside ship_env, as a user would: its declaration and its contribution.

A rudder that loses force in proportion to its angle (a quadratic loss of lift, as a rudder partly
in the hull's wake shows): delta_e = delta (1 - k |delta|). Its smallest physical size (``material``):
k = 0.1 loses 3.5 % of the rudder force at 20 deg.
"""

from __future__ import annotations

from ship_env.model.effect_api import Contribution, Effect, Parameter

EFFECT = Effect(
    "rudder_lift_loss",
    "rudder lift lost at large angles (delta_e = delta (1 - k |delta|))",
    "delta_e = delta (1 - k |delta|)",
    Parameter(
        "loss",
        "1/rad",
        "k, fraction of rudder force lost per radian",
        0.0,
        1.5,
        default=0.0,
        source="assumed: none",
        null=0.0,
        material=0.1,
    ),
)


def lift_loss(effective_rudder, loss):
    """The rudder angle that makes the force, rad."""
    return effective_rudder * (1.0 - loss * abs(effective_rudder))


CONTRIBUTIONS = (Contribution("effective_rudder", lift_loss),)
