"""The command-line argument types that name a ship and its effects (``--ship``, ``--effects``, lists
of effects), read alike by ``ship-env manoeuvre`` and the workbench's commands.

Each raises ``argparse.ArgumentTypeError``, which argparse reports with the argument's name and exit
status 2 (:mod:`ship_env.command_line`).
"""

from __future__ import annotations

import argparse
from collections.abc import Callable
from pathlib import Path

from ship_env.command_line import name_list, ship_preset
from ship_env.model.effects import EFFECTS
from ship_env.model.ship import ShipModel, list_ships

#: The named effect sets of ``--effects``; anything else is a comma-separated list of effects.
EFFECT_SETS: dict[str, Callable[[str], ShipModel]] = {
    "minimal": ShipModel.minimal,
    "default": ShipModel,
    "full": ShipModel.full,
}


def ship_name(text: str) -> str:
    """Check a ship preset name or a YAML file path, and that the preset reads (otherwise the reason, naming the
    file and the field: an envelope written for another scale)."""
    if not (text in list_ships() or (text.endswith((".yaml", ".yml")) and Path(text).is_file())):
        raise argparse.ArgumentTypeError(f"unknown ship {text!r}; known: {', '.join(list_ships())} (or a YAML file)")
    return ship_preset(text)


#: Read a comma-separated list of effects (the registry as it is when the arguments are parsed).
effect_names = name_list("effect", EFFECTS)


def effect_set(text: str) -> str:
    """Check an effect set name or a comma-separated list of effects; returns it normalised."""
    if text in EFFECT_SETS:
        return text
    try:
        return ",".join(effect_names(text))
    except argparse.ArgumentTypeError as error:
        raise argparse.ArgumentTypeError(f"{error}; or one of {', '.join(EFFECT_SETS)} alone") from None
