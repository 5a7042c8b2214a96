"""Wind yaw moment and wind resistance in the normalised model (thesis 2.82-2.88).

    tau* dr*/ds* + H(r*) = K* delta + tau* N_w*                                       (2.85)
    tau_u* du*/ds* + H_u(u*) = K_u* r*^2 + tau_u* F_w*                                (2.86)
    N_w* = N_w' (L/u)^2 sin(2 gamma_r) V_wr^2                                         (2.87)
    F_w* = F_w' (L/u)^2 cos(gamma_r) V_wr^2                                           (2.88)

from C_n = a_n sin 2 gamma_r and C_x = a_x cos gamma_r (2.82, 2.84). The thesis's C_n holds for
a wind whose centre of effort is at midships. A ship with its accommodation aft (a tanker) or forward
has a centre of effort off midships, and a beam wind then turns it: C_n gains a term b_n sin gamma_r
(the first harmonic of Isherwood's wind-moment coefficients, beyond the thesis), with N_b' made of
b_n as N_w' is of a_n. In the time domain (ds* = (u/L) dt) they add to the yaw acceleration and the
speed-loss rate:

    dr/dt  += (N_w' sin(2 gamma_r) + N_b' sin(gamma_r)) V_wr^2
    du*/dt += F_w' (L/u) (cos(gamma_r) V_wr^2 - u^2)

The service speed U0 is the speed reached in still air, so the air resistance of the ship's own
motion (a head wind of u, cos(gamma_r) V_wr^2 = u^2) is already in it and is subtracted: only the
resistance the true wind adds changes the speed.

N_w' (rad/m^2) = 1/2 rho_air a_n S_wy L / I_zz', N_b' (likewise with b_n) and F_w' (1/m^2) are
constant for a ship. The N_w' moment vanishes head-on and beam-on; the N_b' moment is largest
beam-on; both flip sign with the side the wind comes from. A positive N_w' turns the bow into a
wind from forward of the beam; a positive N_b' turns the bow into the wind from either end (the
centre of effort aft of midships, as behind a tanker's accommodation). The wind resistance only acts where the
speed-loss equation (2.86) is on.

Smallest physical sizes (``material``, per 1/L^2: the rudder's yaw acceleration scales with
(u/L)^2): N_w' = N_b' = 5e-4 / L^2 make a yaw moment of 3 % of the rudder's at 10 deg of rudder
(K*/tau* = 1) in a wind of three times the ship's speed; F_w' = 3e-4 / L^2 slows the ship by 1 %
in a head wind of three times its speed (tau_u* = 4).
"""

from __future__ import annotations

from ship_env.model.effect_api import Contribution, Effect, Parameter, kernel

EFFECT = Effect(
    "wind_moment",
    "wind yaw moment and wind resistance",
    "(2.82)-(2.88)",
    Parameter(
        "yaw_coefficient",
        "rad/m^2",
        "N_w' of (2.87); sign: + turns the bow into the wind",
        material=5e-4,
        material_per="1/length^2",
    ),
    Parameter(
        "beam_coefficient",
        "rad/m^2",
        "N_b', yaw from a beam wind (centre of effort off midships); + bow into the wind",
        material=5e-4,
        material_per="1/length^2",
    ),
    Parameter(
        "surge_coefficient",
        "1/m^2",
        "F_w' of (2.88); + means a head wind slows the ship",
        material=3e-4,
        material_per="1/length^2",
    ),
)


@kernel
def yaw_acceleration(relative_wind_speed, cos_wind, sin_wind, yaw_coefficient, beam_coefficient):
    """Added dr/dt in rad/s^2 from (2.85, 2.87) and the beam term; sin(2 gamma_r) = 2 sin(gamma_r) cos(gamma_r)."""
    coefficient = yaw_coefficient * 2.0 * cos_wind + beam_coefficient
    return coefficient * sin_wind * relative_wind_speed * relative_wind_speed


@kernel
def speed_loss_rate(relative_wind_speed, cos_wind, scheduling_speed, surge_coefficient, length):
    """Added du*/dt in 1/s from (2.86, 2.88), beyond the still-air resistance in U0."""
    added = cos_wind * relative_wind_speed * relative_wind_speed - scheduling_speed * scheduling_speed
    return surge_coefficient * length / scheduling_speed * added


CONTRIBUTIONS = (
    Contribution("yaw_acceleration", yaw_acceleration),
    Contribution("speed_loss_derivative", speed_loss_rate),
)
