"""ship_env: ship steering simulation (De Keizer / Van Leeuwen), Gymnasium environments, baselines."""

import ship_env.envs  # noqa: F401  (registers the Gymnasium environments)
from ship_env.model import Conditions, ShipModel, Simulator

__version__ = "0.1.0"

__all__ = ["Conditions", "ShipModel", "Simulator", "__version__"]
