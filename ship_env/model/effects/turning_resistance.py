"""Turning resistance at the speed through the water: the speed loss's forcing falls as the ship slows.

This effect goes beyond the thesis.

The thesis's speed loss (2.55) drives u* by K_u* r*^2 at every speed:

    tau_u* (L/u) du*/dt + H_u(u*) = K_u* r*^2                                       (2.55)

so its steady loss u* = K_u* r*^2 grows without bound with r*: a K_u* fitted where r* is small (a zig-zag's
0.1-0.3) stops a hard-over turn dead (r* 0.5-1, u* > 1). The turn's added resistance is a hydrodynamic force:
the centripetal (m + m_y) v r, X_vr v r and X_vv v^2 of a manoeuvring model (Yasukawa & Yoshimura 2015, the
MMG standard's surge equation) each go as u^2 r*^2 with v* = v / u and r* = L r / u (2.40), where the thesis's
forcing, scaled by (u/L) against the resistance's linearised restoring u*, goes as u U0 r*^2. This effect puts
the speed through the water into the forcing, u / U0 = 1 - u* (2.53), to the power q:

    tau_u* (L/u) du*/dt + H_u(u*) = K_u* r*^2 (1 - u*)^q

q = 1 is the hydrodynamic force's u^2; q > 1 also holds the propeller's thrust at a constant rate rising as the
ship slows (its advance ratio falls), which the linear restoring leaves out. The steady loss with H_u = u* and
q = 1 is u* = K_u* r*^2 / (1 + K_u* r*^2): it stays below the speed however tight the turn, and with q = 0 the
effect vanishes (2.55 as it is). It reads the ``speed_loss`` effect's K_u* and tau_u* and acts only with it on
(where u* stays 0 the forcing is the thesis's).

Symbols: u* relative speed loss, U0 service speed, r* normalised rate of turn, K_u* and tau_u* the speed loss's
gain and time constant (``speed_loss``), q the speed exponent.

Smallest physical size (``material``): q = 0.1 changes the forcing by 3.5 % at a hard-over turn's loss u* = 0.3.

Sources: H. Yasukawa and Y. Yoshimura (2015), Introduction of MMG standard method for ship maneuvering
predictions, J. Marine Science and Technology 20, 37-52 (the surge equation and its hull forces X'_vv, X'_vr,
X'_rr in u^2); M. A. Abkowitz (1964), Lectures on ship hydrodynamics -- steering and manoeuvrability, Hy-5,
Hydro- og Aerodynamisk Laboratorium, Lyngby (the same terms as a Taylor series about the approach speed).
"""

from __future__ import annotations

from ship_env.model.effect_api import Contribution, Effect, Parameter, kernel

EFFECT = Effect(
    "turning_resistance",
    "turning resistance at the speed through the water (the speed loss's forcing falls as the ship slows)",
    "(2.55) with K_u* r*^2 (1 - u*)^q, (2.53)",
    Parameter(
        "speed_exponent",
        "-",
        "q, the power of u / U0 = 1 - u* in the speed loss's forcing",
        minimum=0.0,
        maximum=4.0,
        default=0.0,
        source="the null value: the thesis's forcing until a fit finds it",
        null=0.0,
        material=0.1,
    ),
)


@kernel
def rate(
    speed_loss_derivative,
    scheduling_speed,
    normalised_rate,
    speed_loss,
    speed_loss_gain,
    speed_loss_time_constant,
    length,
    speed_exponent,
):
    """du*/dt with the forcing K_u* r*^2 (1 - u*)^q in place of (2.55)'s K_u* r*^2."""
    relative_speed = max(1.0 - speed_loss, 0.0)
    forcing = speed_loss_gain * normalised_rate * normalised_rate
    return (
        speed_loss_derivative
        - scheduling_speed / length * forcing * (1.0 - relative_speed**speed_exponent) / speed_loss_time_constant
    )


CONTRIBUTIONS = (Contribution("speed_loss_derivative", rate),)
