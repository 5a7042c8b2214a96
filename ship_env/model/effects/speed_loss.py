"""Speed loss in a turn (thesis 2.55, 2.39, 2.53).

    tau_u* (L/u) du*/dt + H_u(u*) = K_u* r*^2                                       (2.55)
    H_u(u*) = u* + beta3 u*^3                                                        (2.39)
    u = U0 (1 - u*)                                                                  (2.53)

so du*/dt = (u/L) (K_u* r*^2 - H_u(u*)) / tau_u*. The steady loss with beta3 = 0 is
u* = K_u* r*^2. Because r = (u/L) r*, the falling speed makes the rate of turn overshoot in a
turning circle even though r* itself rises monotonically (thesis Fig. 2.7).

Symbols: u* relative speed loss, U0 service speed (m/s), tau_u* normalised time constant, K_u*
normalised gain, beta3 cubic coefficient.

Smallest physical sizes (``material``): K_u* = 0.04 loses 1 % of the speed in a steady turn at
r* = 0.5; beta3 = 0.3 changes H_u by 3 % at a loss u* = 0.3 (a hard-over turn).
"""

from __future__ import annotations

from ship_env.model.effect_api import Contribution, Effect, Parameter, State, kernel

EFFECT = Effect(
    "speed_loss",
    "loss of forward speed in a turn (added resistance from turning)",
    "(2.55), (2.39), (2.53)",
    Parameter("gain", "-", "K_u*, normalised gain from r*^2 to speed loss u*", minimum=0.0, material=0.04),
    Parameter("time_constant", "-", "tau_u*, normalised time constant in ship lengths", minimum=1e-6),
    Parameter("cubic", "-", "beta3 of H_u(u*) = u* + beta3 u*^3", minimum=0.0, material=0.3),
)


@kernel
def rate(scheduling_speed, normalised_rate, speed_loss, gain, time_constant, cubic, length):
    """du*/dt from (2.55) with H_u from (2.39)."""
    restoring_value = speed_loss + cubic * speed_loss * speed_loss * speed_loss
    return scheduling_speed / length * (gain * normalised_rate * normalised_rate - restoring_value) / time_constant


@kernel
def added_forcing_rate(forcing, scheduling_speed, length, time_constant):
    """(u / L) forcing / tau_u*, 1/s: the part of du*/dt that a forcing added to (2.55)'s K_u* r*^2 drives
    (the rudder's drag, the drift's resistance)."""
    return scheduling_speed / length * forcing / time_constant


CONTRIBUTIONS = (Contribution("speed_loss_derivative", rate),)
#: The effect governs the rate of the motion's speed loss u* (it stays 0, u = U0, where the effect is off).
STATES = (State("speed_loss", "-", "u* = dU / U0, the relative loss of forward speed (2.41)"),)
