"""Yaw: De Keizer's speed-scheduled rate-of-turn equation (thesis 2.54, 2.27).

    tau* (L/u) dr/dt + (u/L) H(r*) = K* (u/L) delta                                (2.54)
    H(r*) = alpha1 r*  (+ alpha0 + alpha2 r*^2, ``asymmetry``; + alpha2' |r*| r* + alpha3 r*^3, ``norrbin``)  (2.27)
    r* = L r / u                                                                    (2.40)

Solved for the yaw acceleration:

    dr/dt = [ (u_R/L)^2 K* delta_e - (u/L)^2 H(r*) - M_p / L^2 ] / tau*

where ``u_R^2`` is the squared inflow speed at the rudder (``u^2`` unless the propeller
slipstream effect adds to it) and ``delta_e`` the effective rudder angle (``delta`` unless a rudder
offset is on); M_p is the propeller's side moment (``asymmetry``; 0 without it). The normalised
model (2.54) has alpha1 = 1; alpha1 < 0 with alpha3 > 0 describes a course-unstable ship (2.27).
With H(r*) = r* this is the Nomoto model tau dr/dt + r = K delta with tau = tau* L/u and
K = K* u/L (2.58, 2.61): the steady rate of turn is r = K delta.

Symbols: r rate of turn (rad/s), u forward speed (m/s), L ship length (m), delta rudder (rad),
K* normalised gain, tau* normalised time constant, alpha1 linear coefficient.
"""

from __future__ import annotations

from ship_env.model.effect_api import Contribution, Effect, Parameter, kernel

EFFECT = Effect(
    "yaw",
    "yaw response to the rudder (speed-scheduled first-order Nomoto, De Keizer)",
    "(2.54), (2.27), (2.61)",
    Parameter("gain", "-", "K*, normalised rudder-to-rate-of-turn gain", minimum=0.0),
    Parameter("time_constant", "-", "tau*, normalised time constant in ship lengths", minimum=1e-6),
    Parameter("linear", "-", "alpha1 of H(r*): 1 in (2.54); negative for a course-unstable ship"),
    required=True,
)


@kernel
def restoring(normalised_rate, linear):
    """The linear part of H(r*) (2.27)."""
    return linear * normalised_rate


@kernel
def acceleration(speed, inflow_speed_squared, effective_rudder, restoring, side_moment, gain, time_constant, length):
    """dr/dt from (2.54): rudder moment at the rudder inflow speed minus the hull's H(r*) and any side moment."""
    return (inflow_speed_squared * gain * effective_rudder - speed * speed * restoring - side_moment) / (
        time_constant * length * length
    )


@kernel
def ship_acceleration(
    speed,
    inflow_speed_squared,
    effective_rudder,
    restoring,
    side_moment,
    gain,
    time_constant,
    length,
    yaw_gain_change,
    yaw_time_constant_change,
):
    """dr/dt of this ship: the model's K* and tau* changed by the conditions' factors (a batch of ships)."""
    return acceleration(
        speed,
        inflow_speed_squared,
        effective_rudder,
        restoring,
        side_moment,
        gain * (1.0 + yaw_gain_change),
        time_constant * (1.0 + yaw_time_constant_change),
        length,
    )


CONTRIBUTIONS = (Contribution("restoring", restoring), Contribution("hull_yaw_acceleration", ship_acceleration))
