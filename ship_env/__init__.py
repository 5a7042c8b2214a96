"""ship_env: ship steering simulation (De Keizer / Van Leeuwen), Gymnasium environments, baselines.

Importing it registers the Gymnasium environments; the simulator's classes (``ship_env.ShipModel``,
``ship_env.Simulator``, ``ship_env.Conditions``) are imported on first use, so that the command line
answers ``--help`` and a mistyped option without loading the model.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

import ship_env.envs  # noqa: F401  (registers the Gymnasium environments)
from ship_env.lazy import submodule as _submodule

if TYPE_CHECKING:
    from ship_env.model import Conditions, ShipModel, Simulator

__version__ = "0.1.0"

__all__ = ["Conditions", "ShipModel", "Simulator", "__version__"]


def __getattr__(name: str) -> Any:
    """``Conditions``, ``ShipModel`` and ``Simulator`` from :mod:`ship_env.model`, and a subpackage
    (``ship_env.model``, ``ship_env.workbench``, ...), imported when first asked for."""
    if name in ("Conditions", "ShipModel", "Simulator"):
        return getattr(importlib.import_module("ship_env.model"), name)
    return _submodule(__name__, name)
