"""The tasks' scales for a ship: its length and speed against the ship the tasks were drawn for.

The tasks' constants were drawn for the thesis's ship, :data:`REFERENCE_SHIP` (``container_226m``,
L_ref = 225.87 m at U_ref = 9.5 m/s, L_ref / U_ref = 23.8 s): a control step of 1 s, course changes
of 600 steps, track legs of 2 to 2.5 nm, position fixes every 2 s with 5 m of noise. Any other ship sails
them as a geometrically similar ship at the same Froude number would (:class:`ShipScales`):

- **time in units of L / U**: ``time = (L / U) / (L_ref / U_ref)``. The control step ``dt``, the
  position fixes' and the track score's intervals, the cross-track rate's filter time and the
  arc-time observation's unit are the reference's times ``time``. An episode keeps its number of
  steps (600, 3600): a policy makes as many decisions per manoeuvre on every ship, its discount
  spans the same part of it, and the registrations' ``max_episode_steps`` hold for every ship.
- **distances in ship lengths**: ``length = L / L_ref``. The track legs (``track_scale``), the
  ``before_turn`` start, the waypoint-distance observation's unit and the position fixes' noise
  are the reference's times ``length``. With time in L / U a leg then lasts as many steps on every
  ship. The cross-track error is observed and bounded in ship lengths already.
- **speeds in units of U**: ``speed = U / U_ref``: the log's noise; the rate gyro's noise (rad/s)
  is the reference's over ``time``.
- **angles stay**: course changes, the settling band, the rudder limit, heading observations.
- **turning ability K***: the rate of turn is observed over the ship's own full-rudder rate
  K* (U / L) delta_max, and the reference tracks turn on its own steady turning radius
  L / (K* delta_max) (the preview's curvatures over it): both follow K* already. A scale taken from
  K* as well would move the legs and steps out of proportion with the ship's length and speed.

For the reference ship every factor is 1.0 exactly (a number over itself), so its episodes are bit
for bit those of the constants. A ship's scales come from its model as sailed (``ship_parameters``
included); ``ship_variation`` varies each episode's ship around them without changing them.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

from ship_env.model import ShipModel

#: The ship the tasks' constants were drawn for (the thesis's simulator experiment).
REFERENCE_SHIP = "container_226m"
#: The control step of the reference ship, s (the thesis's simulator: the rudder ordered once a second).
REFERENCE_DT = 1.0


@dataclass(frozen=True)
class ShipScales:
    """A ship's length and speed over the reference ship's, and its time scale.

    Attributes:
        length: L / L_ref: multiplies the tasks' distances.
        speed: U / U_ref: multiplies the tasks' speeds.
    """

    length: float
    speed: float

    @property
    def time(self) -> float:
        """(L / U) / (L_ref / U_ref): multiplies the tasks' times."""
        return self.length / self.speed

    @property
    def dt(self) -> float:
        """The ship's control step, s: :data:`REFERENCE_DT` times :attr:`time`."""
        return REFERENCE_DT * self.time


@functools.cache
def _reference_particulars() -> tuple[float, float]:
    """L_ref, m and U_ref, m/s: the reference preset's."""
    reference = ShipModel(REFERENCE_SHIP)
    return reference.length, reference.service_speed


def ship_scales(model: ShipModel) -> ShipScales:
    """The scales of ``model``'s tasks (the module's rule): its length and service speed over the reference's."""
    length, speed = _reference_particulars()
    return ShipScales(length=model.length / length, speed=model.service_speed / speed)
