"""Layout of a ship's state and of the conditions it sails in.

A batch of ``N`` ships is a float64 array of shape ``(N, state size)``; one ship is a row. The
state is the ship's motion (:data:`MOTION_STATES`, every model has them), then the states the
registered effects own (their ``STATES``, ``contributions.State``), in the order the effects
register: the built-in library's first (:data:`LIBRARY_STATES`), then those of effects from outside
``ship_env``. A model's layout is ``ShipModel.state_names``.
Angles are in radians, the heading is not wrapped (it counts whole turns), positions in metres
in the earth-fixed frame (x0 north, y0 east), time in seconds.

The conditions are a row of :data:`CONDITION_NAMES` per ship: those a caller sets, then the current's
and the wind's velocity components :func:`derive_conditions` derives from them.
"""

from __future__ import annotations

import math

from ship_env.model.kernel import kernel

# The ship's motion (thesis ch. 2, DESIGN 3): time, position, heading, rate of turn, relative speed
# loss u* and actual rudder angle. The speed_loss effect governs u*'s rate (u* stays 0 without it).
TIME = 0  # s, time since the start of the run
NORTH = 1  # m, x0 (2.71)
EAST = 2  # m, y0 (2.72)
HEADING = 3  # rad, psi, clockwise from north, not wrapped
RATE_OF_TURN = 4  # rad/s, r, positive turning to starboard
SPEED_LOSS = 5  # -, u* = dU / U0 (2.41)
RUDDER = 6  # rad, actual rudder angle delta, positive gives positive r (2.23)
MOTION_SIZE = 7

MOTION_STATES = ("time", "north", "east", "heading", "rate_of_turn", "speed_loss", "rudder")

# Where the built-in effects' own states land (``effects/__init__`` checks it as they register):
# the disturbance states of the wave filter and of the gusts, then the lagging drift.
WAVE_HEADING = 7  # rad, HF wave-induced heading (Fig. 2.13), not part of the track (wave_filter)
WAVE_RATE = 8  # rad/s, HF wave-induced rate of turn (Fig. 2.13) (wave_filter)
GUST = 9  # m/s, random component on the relative wind speed (2.5.3) (gusts)
LIBRARY_STATES = (*MOTION_STATES, "wave_heading", "wave_rate", "gust", "lagging_drift")

# Conditions: held constant over one step, one row per ship, set by the caller (a scenario, an
# environment, or a measured log replayed step by step).
SERVICE_SPEED = 0  # m/s, U0: the speed through the water on a straight course (2.53)
PROPELLER_RATE = 1  # rps, n, for the propeller slipstream over the rudder
CURRENT_SPEED = 2  # m/s, Uc (2.71)
CURRENT_DIRECTION = 3  # rad, psi_c: the direction the current sets towards, clockwise from north
WIND_SPEED = 4  # m/s, true wind speed V_w (2.74)
WIND_DIRECTION = 5  # rad, psi_w: the direction the wind comes from, clockwise from north
WAVE_DIRECTION = 6  # rad, the direction the waves come from, clockwise from north
# The sailed ship's K* and tau* as changes from the model's, per ship (a batch of different ships in
# one simulator): K* (1 + change), tau* (1 + change); 0, nominal, in a row of zeros.
YAW_GAIN_CHANGE = 7  # -, relative change of K* (2.54)
YAW_TIME_CONSTANT_CHANGE = 8  # -, relative change of tau* (2.54)
# Derived from the conditions above wherever a row is written (:func:`derive_conditions`): the current
# and the true wind as velocities over the ground, north and east, so that the derivative, evaluated
# several times a step, does not take the cosine and sine of directions held over the step.
CURRENT_NORTH = 9  # m/s, U_c cos(psi_c) (2.71)
CURRENT_EAST = 10  # m/s, U_c sin(psi_c) (2.72)
WIND_NORTH = 11  # m/s, -V_w cos(psi_w): the air's velocity north (it blows towards psi_w + pi) (2.74)
WIND_EAST = 12  # m/s, -V_w sin(psi_w) (2.74)
CONDITION_SIZE = 13

CONDITION_NAMES = (
    "service_speed",
    "propeller_rate",
    "current_speed",
    "current_direction",
    "wind_speed",
    "wind_direction",
    "wave_direction",
    "yaw_gain_change",
    "yaw_time_constant_change",
    "current_north",
    "current_east",
    "wind_north",
    "wind_east",
)
#: The conditions a caller sets, and those :func:`derive_conditions` writes from them (read, never set).
SETTABLE_CONDITION_NAMES = CONDITION_NAMES[:CURRENT_NORTH]
DERIVED_CONDITION_NAMES = CONDITION_NAMES[CURRENT_NORTH:]


@kernel
def derive_conditions(rows):
    """Write the derived conditions of condition rows ``(N, CONDITION_SIZE)`` from those set, in place.

    Every row the model reads passes through here after its current or wind is set (a scenario's, a
    changed condition's, a replayed log's), so the derived columns never disagree with the others.
    """
    for i in range(rows.shape[0]):
        rows[i, CURRENT_NORTH] = rows[i, CURRENT_SPEED] * math.cos(rows[i, CURRENT_DIRECTION])  # (2.71)
        rows[i, CURRENT_EAST] = rows[i, CURRENT_SPEED] * math.sin(rows[i, CURRENT_DIRECTION])  # (2.72)
        rows[i, WIND_NORTH] = -rows[i, WIND_SPEED] * math.cos(rows[i, WIND_DIRECTION])  # V_w of (2.74)
        rows[i, WIND_EAST] = -rows[i, WIND_SPEED] * math.sin(rows[i, WIND_DIRECTION])


# Conditions a ship starts a run in that the row does not hold (``Conditions``): the sea state,
# which the ship meets through the components drawn where it starts (``contributions.Draw``).
START_CONDITION_NAMES = ("wave_height", "wave_period")
