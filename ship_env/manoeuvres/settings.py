"""How a trial is sailed and integrated: the approach speed, the step and the integrator.

Shared by the trial that sails (:mod:`.trial`) and the results it returns (:mod:`.results`), which
record the approach speed the settings give.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

from ship_env.model import ShipModel

if TYPE_CHECKING:
    from ship_env.model.external import DynamicsSource


@dataclass(frozen=True)
class TrialSettings:
    """How a trial is sailed and integrated.

    Attributes:
        speed: the approach speed V through the water, m/s; ``None`` takes the ship's service speed.
        dt: the integration step, s.
        method: the integrator, ``"rk4"`` or ``"euler"``.
        dynamics: who sails the ship: ``None``, the model's preset (ship_env's own simulator of the model, or the
            fitted MMG model its ``dynamics:`` block holds); ``"native"``, ship_env's simulator whatever the preset
            names; else an external ship's dynamics (:mod:`ship_env.model.external`: an adapter's class or factory,
            its ``"module:attribute"`` path, or a fitted MMG file of ``ship-env fit-mmg``), the model then giving
            the particulars, the rudder limit and the approach speed.
    """

    speed: float | None = None
    dt: float = 0.5
    method: str = "rk4"
    dynamics: DynamicsSource | None = None

    def __post_init__(self) -> None:
        if self.speed is not None and not (math.isfinite(self.speed) and self.speed > 0.0):
            raise ValueError(f"speed: expected a positive approach speed in m/s, got {self.speed!r}")

    def approach_speed(self, model: ShipModel) -> float:
        """V, the approach speed for this ship, m/s."""
        return model.service_speed if self.speed is None else float(self.speed)

    def seconds_for(self, model: ShipModel, lengths: float) -> float:
        """The time to sail ``lengths`` ship lengths at the approach speed, s (s* = u t / L, 2.42)."""
        return lengths * model.length / self.approach_speed(model)
