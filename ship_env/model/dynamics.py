"""The ship's equations of motion: the effects composed into one state derivative.

``derivatives`` evaluates d(state)/dt for one ship at one instant. Each effect's equations live in
its own module under ``effects/``; here they are only combined, each behind its on/off flag in the
parameter record, in this order:

1. speed u = U0 (1 - u*) (2.53) and normalised rate of turn r* = L r / u (2.40);
2. sway v (Van Leeuwen), velocity over the ground (kinematics, current);
3. relative wind (2.74) with gusts, giving the wind moment, resistance and leeway;
4. effective rudder (offset) and rudder inflow (propeller slipstream);
5. yaw acceleration (De Keizer, Norrbin, wind, the wave spectrum's excitation), speed-loss rate;
6. disturbance states: HF wave filter, gusts.

The actual rudder is not integrated here: the steering machine moves it exactly (see
``integrators``), and the derivative takes the rudder angle at the instant as an argument.
"""

from __future__ import annotations

import math

from ship_env.model import state as S
from ship_env.model.effects import (
    asymmetry,
    current,
    gusts,
    kinematics,
    norrbin,
    propeller_slipstream,
    rudder_offset,
    speed_loss,
    sway,
    wave_filter,
    wind,
    wind_drift,
    wind_moment,
    yaw,
)
from ship_env.model.kernel import kernel


@kernel
def derivatives(state, rudder, conditions, white_noise, wave_yaw, p, out):
    """Write d(state)/dt into ``out`` for one ship.

    Args:
        state: the ship's state, layout in ``state``.
        rudder: the actual rudder angle at this instant, rad.
        conditions: the ship's conditions (service speed, propeller rate, current, wind, waves).
        white_noise: the white-noise inputs held over the step (already scaled by 1/sqrt(dt)).
        wave_yaw: the wave-spectrum yaw acceleration held over the step, rad/s^2 (2.91).
        p: the model's parameter record (see ``ShipModel.record``).
        out: array of the state's size receiving the derivative.
    """
    length = p["length"]
    heading = state[S.HEADING]
    rate_of_turn = state[S.RATE_OF_TURN]
    speed = conditions[S.SERVICE_SPEED] * (1.0 - state[S.SPEED_LOSS])  # (2.53)
    # The normalisation divides by the speed: below ``minimum_speed`` the floor is used.
    scheduling_speed = max(speed, p["minimum_speed"])
    normalised_rate = length * rate_of_turn / scheduling_speed  # (2.40)

    sway_velocity = 0.0
    if p["sway_on"]:
        sway_velocity = sway.velocity(speed, normalised_rate, p["sway_linear"], p["sway_cubic"])
    cos_heading = math.cos(heading)
    sin_heading = math.sin(heading)
    north_rate, east_rate = kinematics.velocity_over_ground(speed, sway_velocity, cos_heading, sin_heading)
    if p["current_on"]:
        current_north, current_east = current.drift(
            state[S.TIME],
            conditions[S.CURRENT_SPEED],
            conditions[S.CURRENT_DIRECTION],
            p["current_variation"],
            p["current_swing"],
            p["current_period"],
        )
        north_rate += current_north
        east_rate += current_east

    wind_yaw = 0.0
    wind_loss = 0.0
    if p["wind_moment_on"] or p["wind_drift_on"]:
        wind_speed, cos_wind, sin_wind = wind.relative_wind(
            cos_heading, sin_heading, north_rate, east_rate, conditions[S.WIND_SPEED], conditions[S.WIND_DIRECTION]
        )
        if p["gusts_on"]:
            wind_speed = max(wind_speed + state[S.GUST], 0.0)
        if p["wind_moment_on"]:
            wind_yaw = wind_moment.yaw_acceleration(
                wind_speed, cos_wind, sin_wind, p["wind_moment_yaw_coefficient"], p["wind_moment_beam_coefficient"]
            )
            wind_loss = wind_moment.speed_loss_rate(
                wind_speed, cos_wind, scheduling_speed, p["wind_moment_surge_coefficient"], length
            )
        if p["wind_drift_on"]:
            drift_velocity = wind_drift.leeway(
                speed,
                wind_speed,
                sin_wind,
                p["wind_drift_force_ratio"],
                p["wind_drift_lift_slope"],
                p["wind_drift_crossflow_drag"],
            )
            drift_north, drift_east = kinematics.velocity_over_ground(0.0, drift_velocity, cos_heading, sin_heading)
            north_rate += drift_north
            east_rate += drift_east

    effective_rudder = rudder
    if p["rudder_offset_on"]:
        effective_rudder = rudder_offset.effective_rudder(rudder, p["rudder_offset_angle"])
    inflow_speed_squared = speed * speed
    if p["propeller_slipstream_on"]:
        inflow_speed_squared = propeller_slipstream.inflow_speed_squared(
            speed,
            conditions[S.PROPELLER_RATE],
            p["propeller_slipstream_coefficient"],
            p["propeller_slipstream_propeller_diameter"],
        )

    restoring = yaw.restoring(normalised_rate, p["yaw_linear"])
    side_moment = 0.0
    if p["asymmetry_on"]:
        restoring += asymmetry.restoring(normalised_rate, p["asymmetry_constant"], p["asymmetry_quadratic"])
        side_moment = asymmetry.side_force_moment(
            conditions[S.PROPELLER_RATE], p["propeller_slipstream_propeller_diameter"], p["asymmetry_side_force"]
        )
    if p["norrbin_on"]:
        restoring += norrbin.restoring(normalised_rate, p["norrbin_cubic"], p["norrbin_odd_quadratic"])
    yaw_acceleration = yaw.acceleration(
        speed,
        inflow_speed_squared,
        effective_rudder,
        restoring,
        side_moment,
        p["yaw_gain"] * (1.0 + conditions[S.YAW_GAIN_CHANGE]),
        p["yaw_time_constant"] * (1.0 + conditions[S.YAW_TIME_CONSTANT_CHANGE]),
        length,
    )
    yaw_acceleration += wind_yaw + wave_yaw

    speed_loss_rate = 0.0
    if p["speed_loss_on"]:
        speed_loss_rate = wind_loss + speed_loss.rate(
            scheduling_speed,
            normalised_rate,
            state[S.SPEED_LOSS],
            p["speed_loss_gain"],
            p["speed_loss_time_constant"],
            p["speed_loss_cubic"],
            length,
        )

    out[S.TIME] = 1.0
    out[S.NORTH] = north_rate
    out[S.EAST] = east_rate
    out[S.HEADING] = rate_of_turn
    out[S.RATE_OF_TURN] = yaw_acceleration
    out[S.SPEED_LOSS] = speed_loss_rate
    out[S.RUDDER] = 0.0
    out[S.WAVE_HEADING] = 0.0
    out[S.WAVE_RATE] = 0.0
    out[S.GUST] = 0.0
    if p["wave_filter_on"]:
        out[S.WAVE_HEADING] = state[S.WAVE_RATE]
        out[S.WAVE_RATE] = wave_filter.acceleration(
            state[S.WAVE_HEADING],
            state[S.WAVE_RATE],
            white_noise[S.NOISE_WAVE],
            p["wave_filter_natural_frequency"],
            p["wave_filter_damping"],
            p["wave_filter_rate_rms"],
        )
    if p["gusts_on"]:
        out[S.GUST] = gusts.rate(
            state[S.GUST],
            conditions[S.WIND_SPEED],
            white_noise[S.NOISE_GUST],
            p["gusts_intensity"],
            p["gusts_time_constant"],
        )


@kernel
def sway_velocity(state, conditions, p):
    """The Van Leeuwen sway velocity v (m/s) of one ship, for observations and drawings."""
    if not p["sway_on"]:
        return 0.0
    speed = conditions[S.SERVICE_SPEED] * (1.0 - state[S.SPEED_LOSS])
    normalised_rate = p["length"] * state[S.RATE_OF_TURN] / max(speed, p["minimum_speed"])
    return sway.velocity(speed, normalised_rate, p["sway_linear"], p["sway_cubic"])
