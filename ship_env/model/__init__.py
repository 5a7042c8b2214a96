"""The ship as equations: one module per physical effect, composed by :class:`ShipModel`."""

from ship_env.model.contributions import Contribution, Draw, State
from ship_env.model.declarations import Effect, Parameter
from ship_env.model.effects import EFFECTS, MINIMAL_EFFECTS, REQUIRED_EFFECTS
from ship_env.model.registry import register_effect
from ship_env.model.ship import PRINCIPAL, Ship, ShipModel, list_ships, load_ship
from ship_env.model.simulator import Conditions, Simulator

__all__ = [
    "EFFECTS",
    "MINIMAL_EFFECTS",
    "PRINCIPAL",
    "REQUIRED_EFFECTS",
    "Conditions",
    "Contribution",
    "Draw",
    "Effect",
    "Parameter",
    "Ship",
    "ShipModel",
    "Simulator",
    "State",
    "list_ships",
    "load_ship",
    "register_effect",
]
