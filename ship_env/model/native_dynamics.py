"""ship_env's own simulator behind the external-dynamics protocol: the protocol's reference adapter.

:class:`NativeDynamics` sails one ship of a :class:`~ship_env.model.ShipModel` in a one-ship
:class:`~ship_env.model.Simulator` and answers :class:`~ship_env.model.external.ShipDynamics`'s
``reset`` and ``step``. An environment given it as its ``dynamics`` sails the same ship as the
native environment, through the protocol: the same motion step by step, so the same observations,
rewards and metrics (to the rounding of the speed as u = U0 (1 - u*) and back), except where the
native ship's compass sees the waves' yaw (the disturbance states stay with the adapter).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from pathlib import Path

from ship_env.model import state as S
from ship_env.model.external import ShipMotion
from ship_env.model.ship import ShipModel
from ship_env.model.simulator import Conditions, Simulator


class NativeDynamics:
    """One ship of ship_env's model, stepped through the protocol.

    Args:
        model: the ship model, or a preset name or YAML path (its default effects).
        effects: the effects of a model built from a preset (``None``: its defaults).
    """

    def __init__(self, model: ShipModel | str | Path = "container_226m", effects: Sequence[str] | None = None) -> None:
        self.simulator = Simulator(model if isinstance(model, ShipModel) else ShipModel(model, effects), num_ships=1)

    def reset(self, start: ShipMotion, conditions: Conditions, seed: int) -> None:
        """Start at ``start`` (its drift follows from the model's sway) in ``conditions``."""
        simulator = self.simulator
        simulator.reset(
            seed=seed,
            conditions=conditions,
            heading=start.heading,
            rudder=start.rudder,
            rate_of_turn=start.rate_of_turn,
        )
        state = simulator.state[0]
        state[S.NORTH], state[S.EAST] = start.north, start.east
        state[S.SPEED_LOSS] = 1.0 - start.speed / simulator.conditions[0, S.SERVICE_SPEED]

    def step(self, rudder_order: float, propeller_rate: float | None, dt: float) -> ShipMotion:
        """One simulator step of ``dt`` (``FloatingPointError`` where the ship leaves the model's validity)."""
        simulator = self.simulator
        simulator.dt = dt
        if propeller_rate is not None:
            simulator.set_conditions("propeller_rate", propeller_rate)
        simulator.step(rudder_order)
        speed = float(simulator.speed[0])
        state = simulator.state[0]
        return ShipMotion(
            heading=float(state[S.HEADING]),
            rate_of_turn=float(state[S.RATE_OF_TURN]),
            north=float(state[S.NORTH]),
            east=float(state[S.EAST]),
            speed=speed,
            drift=math.atan2(-float(simulator.sway_velocity[0]), speed),
            rudder=float(state[S.RUDDER]),
        )
