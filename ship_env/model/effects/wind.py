"""Relative (apparent) wind, shared by the wind effects (thesis 2.74, Fig. 2.11).

    V_wr = V_w - U                                                                  (2.74)

V_w is the true wind velocity (the air's velocity over the ground), U the ship's velocity over
the ground (speed, drift and current). V_w's components north and east, -V_w (cos psi_w, sin psi_w),
are the conditions ``wind_north`` and ``wind_east``, derived once where the conditions are written
(``state.derive_conditions``). The relative wind speed V_wr = |V_wr| and the relative wind
angle gamma_r is where the apparent wind comes from, measured clockwise from the bow, in
(-pi, pi]: 0 head wind, +pi/2 wind on the starboard beam, as an anemometer on board reads it.
The true wind direction psi_w is likewise where the wind comes from, clockwise from north.
"""

from __future__ import annotations

import math

from ship_env.model.effect_api import kernel


@kernel
def relative_wind(cos_heading, sin_heading, north_velocity, east_velocity, wind_north, wind_east):
    """(V_wr, cos gamma_r, sin gamma_r): apparent wind speed (m/s) and its angle off the bow (2.74).

    The angle comes as its cosine and sine, the components of the apparent wind's coming-from
    direction in ship axes (forward, starboard): the wind forces need only these, and no angle has
    to be wrapped. ``atan2(sin, cos)`` gives gamma_r itself.
    """
    air_north = wind_north - north_velocity
    air_east = wind_east - east_velocity
    speed = math.sqrt(air_north * air_north + air_east * air_east)
    if speed == 0.0:
        return 0.0, 1.0, 0.0
    forward = -(air_north * cos_heading + air_east * sin_heading)
    starboard = air_north * sin_heading - air_east * cos_heading
    return speed, forward / speed, starboard / speed
