"""Rudder drag: the rudder's resistance along the ship slows it while the rudder is over.

This effect goes beyond the thesis.

The thesis's speed loss (2.55) is forced by the rate of turn alone. The rudder's normal force F_N also pulls
back along the ship: in the MMG standard's surge equation (Yasukawa & Yoshimura 2015) the rudder adds

    X_R = -(1 - t_R) F_N sin(delta),   F_N = 1/2 rho A_R f_alpha u_R^2 sin(alpha_R)

with the rudder meeting its inflow u_R at about its own angle (alpha_R ~ delta in a steady straight inflow): a
drag in u_R^2 sin^2(delta). A zig-zag holds 10-20 deg for part of each leg while its rate of turn passes through
zero; a hard-over turn holds 35 deg throughout, so the rudder's drag, which r*^2 does not describe, adds to the
turn's speed loss. In (2.55), where a forcing F decelerates the ship by (u U0 / (tau_u* L)) F, this drag is

    tau_u* (L/u) du*/dt + H_u(u*) = K_u* r*^2 + C_R* sin^2(delta_e) u_R^2 / (u U0)

with delta_e the effective rudder angle (``rudder_offset``'s), u_R^2 the rudder's inflow (u^2, or with the
propeller's slipstream where ``propeller_slipstream`` is on) and U0 the service speed. Without the slipstream
the forcing is C_R* sin^2(delta_e) (1 - u*) (2.53): it falls as the ship slows, as the drag in u^2 does; with it,
the propeller's share of the inflow keeps the drag up. It reads the ``speed_loss`` effect's tau_u* and acts only
with it on (where u* stays 0 the speed is U0 throughout). With C_R* = 0 the effect vanishes.

Symbols: u* relative speed loss, u the speed, U0 service speed, delta_e the effective rudder angle, u_R the
rudder's inflow speed, tau_u* the speed loss's time constant (``speed_loss``), C_R* the normalised rudder drag
coefficient; t_R, rho, A_R and f_alpha are the MMG standard's (rudder's thrust deduction, water density, rudder
area, lift gradient), folded into C_R*.

Smallest physical size (``material``): C_R* = 0.1 loses about 1 % of the speed with the rudder held at 20 deg
(sin^2(20 deg) = 0.117, u* = 0.012 with H_u = u*) and 3 % at 35 deg.

Sources: H. Yasukawa and Y. Yoshimura (2015), Introduction of MMG standard method for ship maneuvering
predictions, J. Marine Science and Technology 20, 37-52 (the surge equation's rudder force X_R and the rudder's
normal force F_N).
"""

from __future__ import annotations

import math

from ship_env.model.effect_api import Contribution, Effect, Parameter, kernel
from ship_env.model.effects.speed_loss import added_forcing_rate

EFFECT = Effect(
    "rudder_drag",
    "rudder drag (the rudder's resistance along the ship adds to the speed loss)",
    "(2.55) with K_u* r*^2 + C_R* sin^2(delta_e) u_R^2 / (u U0)",
    Parameter(
        "drag_coefficient",
        "-",
        "C_R*, the rudder's drag in the speed loss's forcing",
        minimum=0.0,
        maximum=20.0,
        default=0.0,
        source="the null value: no rudder drag until a fit finds it",
        null=0.0,
        material=0.1,
    ),
)


@kernel
def rate(
    speed_loss_derivative,
    scheduling_speed,
    effective_rudder,
    inflow_speed_squared,
    service_speed,
    speed_loss_time_constant,
    length,
    minimum_speed,
    drag_coefficient,
):
    """du*/dt with the rudder's drag C_R* sin^2(delta_e) u_R^2 / (u U0) added to (2.55)'s forcing."""
    sine = math.sin(effective_rudder)
    reference_speed_squared = scheduling_speed * max(service_speed, minimum_speed)  # u U0, each floored alike
    drag = drag_coefficient * sine * sine * inflow_speed_squared / reference_speed_squared
    return speed_loss_derivative + added_forcing_rate(drag, scheduling_speed, length, speed_loss_time_constant)


CONTRIBUTIONS = (Contribution("speed_loss_derivative", rate),)
