"""The library of physical effects, one module each, registered in the order the model applies them.

Each module declares its ``EFFECT`` (:class:`~ship_env.model.declarations.Effect`), its
``CONTRIBUTIONS`` to the state derivative (:class:`~ship_env.model.contributions.Contribution`) and
the ``STATES`` it owns, if any (:class:`~ship_env.model.contributions.State`): they follow the
motion's states in this order (``state.LIBRARY_STATES``). ``EFFECTS`` maps every registered
effect's name to its declaration: these built-ins, then the effects registered from outside
``ship_env`` (see ``registry``). A ship model is a choice of these effects plus a ship preset; see
:class:`ship_env.model.ShipModel`.

The contributions to one quantity are applied in this order (the asymmetry's part of H(r*) before
Norrbin's, then the hull's cross-flow drag; the speed loss's rate before the turning resistance's and
the rudder drag's and, registered last, the drift's resistance's; the lagging sway's velocity, registered
after the disturbances so that its state follows theirs, in place of the settled one).
"""

from __future__ import annotations

from ship_env.model.effects import (
    asymmetry,
    current,
    drift_resistance,
    gusts,
    hull_crossflow,
    kinematics,
    norrbin,
    propeller_astern,
    propeller_slipstream,
    rudder_drag,
    rudder_offset,
    speed_loss,
    steering_machine,
    sway,
    sway_lag,
    turning_resistance,
    wave_filter,
    wave_spectrum,
    wind_drift,
    wind_moment,
    yaw,
)
from ship_env.model.registry import EFFECTS, register_module, state_layout
from ship_env.model.state import LIBRARY_STATES

#: The built-in effects' modules, in the order they register.
LIBRARY = (
    yaw,
    asymmetry,
    norrbin,
    hull_crossflow,
    speed_loss,
    turning_resistance,
    rudder_drag,
    sway,
    steering_machine,
    rudder_offset,
    propeller_slipstream,
    propeller_astern,
    kinematics,
    current,
    wind_moment,
    wind_drift,
    wave_filter,
    gusts,
    wave_spectrum,
    sway_lag,
    drift_resistance,
)
for _module in LIBRARY:
    register_module(_module, "ship_env")
if state_layout([EFFECTS.entry(module.EFFECT.name) for module in LIBRARY]) != LIBRARY_STATES:
    raise ImportError("ship_env.model.effects: the library's states are not where state.LIBRARY_STATES puts them")

#: Effects every model has.
REQUIRED_EFFECTS: tuple[str, ...] = tuple(module.EFFECT.name for module in LIBRARY if module.EFFECT.required)

#: The minimal model: a first-order Nomoto ship with its steering machine (2.58, Fig. 2.9).
MINIMAL_EFFECTS: tuple[str, ...] = ("yaw", "kinematics", "steering_machine")

__all__ = ["EFFECTS", "LIBRARY", "MINIMAL_EFFECTS", "REQUIRED_EFFECTS"]
