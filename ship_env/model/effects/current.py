"""Uniform current, optionally varying slowly like a tidal stream (thesis 2.71, 2.72).

    dx0/dt += U_c cos(psi_c),   dy0/dt += U_c sin(psi_c)                             (2.71, 2.72)

psi_c is the direction the current sets towards, clockwise from north. A tidal variation is
optional: U_c(t) = U_c (1 + a sin(2 pi t / T)), psi_c(t) = psi_c + b sin(2 pi t / T), with
a = ``variation``, b = ``swing``, T = ``period``; a = b = 0 gives a steady current, whose
U_c cos(psi_c) and U_c sin(psi_c) are the conditions ``current_north`` and ``current_east``, derived
once where the conditions are written (``state.derive_conditions``).

A steady current's components are conditions of a run, not parameters of the ship: a fit
estimates them as declared by :data:`STEADY_COMPONENT`, whose smallest physical size (``material``)
is 1.5 % of the service speed -- a set a navigator would not notice over a few ship lengths.
"""

from __future__ import annotations

import math

from ship_env.model.effect_api import Contribution, Effect, Parameter, kernel

EFFECT = Effect(
    "current",
    "current (set and drift of the water)",
    "(2.71), (2.72)",
    Parameter("variation", "-", "a, relative amplitude of the tidal speed variation", minimum=0.0, maximum=1.0),
    Parameter("swing", "rad", "b, amplitude of the tidal direction swing", minimum=0.0),
    Parameter("period", "s", "T, period of the tidal variation", minimum=1e-6),
)


@kernel
def drift(time, current_north, current_east, current_speed, current_direction, variation, swing, period):
    """The current's contribution (dx0/dt, dy0/dt) in m/s at ``time``."""
    if variation == 0.0 and swing == 0.0:
        return current_north, current_east
    phase = math.sin(2.0 * math.pi * time / period)
    speed = current_speed * (1.0 + variation * phase)
    direction = current_direction + swing * phase
    return speed * math.cos(direction), speed * math.sin(direction)


#: A steady current's north or east component, as a fit estimates it (``current.north``, ``current.east``).
STEADY_COMPONENT = Parameter(
    "component",
    "m/s",
    "steady current's component, the same in every run",
    null=0.0,
    material=0.015,
    material_per="service_speed",
)

CONTRIBUTIONS = (Contribution("ground_velocity", drift),)
