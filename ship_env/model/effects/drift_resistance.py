"""The drift's resistance in a turn: the speed loss forced by the sway velocity times the rate of turn.

This effect goes beyond the thesis.

The thesis's speed loss (2.55) is forced by the rate of turn alone, K_u* r*^2. In a manoeuvring model the
turn's added resistance comes mostly from the drift: the surge equation of the MMG standard (Yasukawa &
Yoshimura 2015, (m + m_x) du/dt = X_H + X_R + X_P + (m + m_y) v r) carries the centripetal (m + m_y) v r
and the hull's X_vr v r, together 0.51 for KVLCC2 (m' + m_y' + X'_vr in the primes of Tables 1-3), against
X'_rr = 0.011 and X'_vv v'^2 at most 0.005 in a hard-over turn. In a steady turn the drift is settled
(v* = -gamma1* r*, 2.47) and v r goes as r*^2, the thesis's forcing; in a zig-zag the drift lags the rate of
turn (``sway_lag``) and v r departs from r*^2, so a K_u* fitted on zig-zags carries their mix of lagging and
settled drift into a hard-over turn, where the drift is settled. This effect adds the drift's forcing to (2.55):

    tau_u* (L/u) du*/dt + H_u(u*) = K_u* r*^2 + K_vr* (-v r*) / U0

where -v r* / U0 = (u / U0) (-v* r*) = (1 - u*) (-v* r*) (2.53): the force (m + m_y) v r in the units of
(2.55)'s forcing, as the rudder's drag is (``rudder_drag``). v is the sway velocity every effect reads
(``sway``, or ``sway_lag``'s lagging drift where it is on); without sway the effect does nothing. It reads the
``speed_loss`` effect's tau_u* and acts only with it on.

On the basin truth's zig-zags (MMG's KVLCC2 as a 7 m model) the default ladder does not add it while H_u's cubic
is held at the preset's; with the cubic fitted the fit puts the whole speed loss on the drift (K_u* 0, K_vr* 9),
as MMG's surge equation does (docs/results/free_running.md).

Symbols: u* relative speed loss, u forward speed, U0 service speed, v sway velocity (+ to starboard),
v* = v / u, r* normalised rate of turn (2.40), K_u* and tau_u* the speed loss's gain and time constant
(``speed_loss``), K_vr* the drift's gain.

Smallest physical size (``material``): K_vr* = 0.1 loses 1 % of the speed in a steady turn at r* = 0.5
with a drift v* = -0.2.

Sources: H. Yasukawa and Y. Yoshimura (2015), Introduction of MMG standard method for ship maneuvering
predictions, J. Marine Science and Technology 20, 37-52 (the surge equation (4), the hull's X'_vr and
Tables 1-3 for KVLCC2); M. A. Abkowitz (1964), Lectures on ship hydrodynamics -- steering and
manoeuvrability, Hy-5, Hydro- og Aerodynamisk Laboratorium, Lyngby (the term (m + X_vr) v r).
"""

from __future__ import annotations

from ship_env.model.effect_api import Contribution, Effect, Parameter, kernel
from ship_env.model.effects.speed_loss import added_forcing_rate

EFFECT = Effect(
    "drift_resistance",
    "the drift's resistance in a turn (the speed loss forced by the sway velocity times the rate of turn)",
    "(2.55) with K_u* r*^2 + K_vr* (-v r*) / U0",
    Parameter(
        "gain",
        "-",
        "K_vr*, the gain from the drift's forcing -v r* / U0 to the speed loss",
        minimum=0.0,
        maximum=20.0,
        default=0.0,
        source="the null value: the thesis's speed loss, forced by r*^2 alone, until a fit finds it",
        null=0.0,
        material=0.1,
    ),
)


@kernel
def rate(
    speed_loss_derivative,
    scheduling_speed,
    sway_velocity,
    normalised_rate,
    service_speed,
    speed_loss_time_constant,
    length,
    minimum_speed,
    gain,
):
    """du*/dt with the drift's forcing K_vr* (-v r*) / U0 added to (2.55)'s."""
    forcing = -gain * sway_velocity * normalised_rate / max(service_speed, minimum_speed)
    return speed_loss_derivative + added_forcing_rate(forcing, scheduling_speed, length, speed_loss_time_constant)


CONTRIBUTIONS = (Contribution("speed_loss_derivative", rate),)
