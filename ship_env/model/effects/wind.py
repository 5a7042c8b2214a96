"""Relative (apparent) wind, shared by the wind effects (thesis 2.74, Fig. 2.11).

    V_wr = V_w - U                                                                  (2.74)

V_w is the true wind velocity (the air's velocity over the ground), U the ship's velocity over
the ground (speed, drift and current). The relative wind speed V_wr = |V_wr| and the relative wind
angle gamma_r is where the apparent wind comes from, measured clockwise from the bow, in
(-pi, pi]: 0 head wind, +pi/2 wind on the starboard beam, as an anemometer on board reads it.
The true wind direction psi_w is likewise where the wind comes from, clockwise from north.
"""

from __future__ import annotations

import math

from ship_env.model.kernel import kernel


@kernel
def wrap_angle(angle):
    """An angle wrapped to (-pi, pi]."""
    return math.atan2(math.sin(angle), math.cos(angle))


@kernel
def relative_wind(heading, north_velocity, east_velocity, wind_speed, wind_direction):
    """(V_wr, gamma_r): apparent wind speed (m/s) and angle off the bow (rad) from (2.74)."""
    air_north = -wind_speed * math.cos(wind_direction) - north_velocity
    air_east = -wind_speed * math.sin(wind_direction) - east_velocity
    speed = math.sqrt(air_north * air_north + air_east * air_east)
    coming_from = math.atan2(-air_east, -air_north)
    return speed, wrap_angle(coming_from - heading)
