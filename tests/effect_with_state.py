"""An effect with a state of its own, written outside ship_env: a rudder whose force lags its angle.

After the rudder moves, the flow over it needs time to build up its lift again (a stalled or
ventilated rudder recovering). A first-order lag of the angle that makes the force:

    d delta_l / dt = (delta - delta_l) / T_l,      delta_e -> delta_e + (delta_l - delta)

so the rudder force follows delta_l, which settles at delta. A ship starts with the flow settled.
"""

from __future__ import annotations

from ship_env.model.effect_api import Contribution, Effect, Parameter, State

EFFECT = Effect(
    "rudder_lag",
    "rudder force lagging the rudder angle (flow building up after the rudder moves)",
    "d delta_l/dt = (delta - delta_l) / T_l",
    Parameter("time_constant", "s", "T_l, the lag's time constant", 0.1, 60.0, default=2.0, source="assumed"),
)


def lagged(effective_rudder, rudder, lagged_rudder):
    """The rudder angle that makes the force: the lagged angle in place of the actual one, rad."""
    return effective_rudder + (lagged_rudder - rudder)


def lag_rate(rudder, lagged_rudder, time_constant):
    """d delta_l / dt, rad/s."""
    return (rudder - lagged_rudder) / time_constant


def settled(rudder):
    """The lagged angle of a ship that starts with the flow settled: the actual rudder."""
    return rudder


CONTRIBUTIONS = (Contribution("effective_rudder", lagged), Contribution("lagged_rudder_derivative", lag_rate))
STATES = (State("lagged_rudder", "rad", "delta_l, the rudder angle the flow has built up to", initial=settled),)
