"""The library of physical effects, one module each, in the order the model applies them.

``EFFECTS`` maps each effect's name to its declaration (:class:`~ship_env.model.declarations.Effect`).
A ship model is a choice of these effects plus a ship preset; see :class:`ship_env.model.ShipModel`.
"""

from __future__ import annotations

from ship_env.model.declarations import Effect
from ship_env.model.effects import (
    asymmetry,
    current,
    gusts,
    kinematics,
    norrbin,
    propeller_slipstream,
    rudder_offset,
    speed_loss,
    steering_machine,
    sway,
    wave_filter,
    wave_spectrum,
    wind_drift,
    wind_moment,
    yaw,
)

EFFECTS: dict[str, Effect] = {
    module.EFFECT.name: module.EFFECT
    for module in (
        yaw,
        norrbin,
        asymmetry,
        speed_loss,
        sway,
        steering_machine,
        rudder_offset,
        propeller_slipstream,
        kinematics,
        current,
        wind_moment,
        wind_drift,
        gusts,
        wave_filter,
        wave_spectrum,
    )
}

#: Effects every model has.
REQUIRED_EFFECTS: tuple[str, ...] = tuple(name for name, effect in EFFECTS.items() if effect.required)

#: The minimal model: a first-order Nomoto ship with its steering machine (2.58, Fig. 2.9).
MINIMAL_EFFECTS: tuple[str, ...] = ("yaw", "kinematics", "steering_machine")

__all__ = ["EFFECTS", "MINIMAL_EFFECTS", "REQUIRED_EFFECTS"]
