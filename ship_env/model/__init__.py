"""The ship as equations: one module per physical effect, composed by :class:`ShipModel`."""

from ship_env.model.effects import EFFECTS, MINIMAL_EFFECTS, REQUIRED_EFFECTS
from ship_env.model.ship import PRINCIPAL, Ship, ShipModel, list_ships, load_ship
from ship_env.model.simulator import Conditions, Simulator

__all__ = [
    "EFFECTS",
    "MINIMAL_EFFECTS",
    "PRINCIPAL",
    "REQUIRED_EFFECTS",
    "Conditions",
    "Ship",
    "ShipModel",
    "Simulator",
    "list_ships",
    "load_ship",
]
