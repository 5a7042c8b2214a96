"""Norrbin non-linearity: the odd non-linear terms of H(r*) (thesis 2.27, 2.28, 2.45).

    H(r*) = ... + alpha2' |r*| r* + alpha3 r*^3

They bend the spiral characteristic: large rudder angles give less rate of turn than the linear
model, and a negative linear term (see ``yaw``) with alpha3 > 0 describes a course-unstable ship.
Steady turn: r* + alpha2' |r*| r* + alpha3 r*^3 = K* delta (2.26). The |r*| r* term is Norrbin's
quadratic form of the hull's non-linear yaw damping. In (2.54) it adds -(alpha2' / tau*) |r| r to
dr/dt whatever the speed (the (u/L)^2 of (2.54) cancels the (L/u)^2 of r*^2): the hull's cross-flow
drag against turning of strip theory, -1/2 rho T C_D |x r| x r per unit length integrated over the
hull, which still damps the yaw of a ship nearly at rest; a negative alpha2' with alpha3 > 0 flattens
the spiral at moderate rates of turn, as in a full-form tanker that is only just course-stable
(the slope dH/dr* dips towards zero between small and large turns). With alpha2' = alpha3 = 0
the effect vanishes.

Smallest physical sizes (``material``): alpha3 = 0.1 and alpha2' = 0.05 each change H(r*), and so
the steady rate of turn, by a few % (2.5 %) at r* = 0.5, about the largest rate of a 35 deg turn.
"""

from __future__ import annotations

from ship_env.model.effect_api import Contribution, Effect, Parameter, kernel

EFFECT = Effect(
    "norrbin",
    "non-linear yaw damping (Norrbin's |r| r and cubic terms: the spiral curve's shape)",
    "(2.27), (2.28)",
    Parameter("cubic", "-", "alpha3 of H(r*), the cubic coefficient", minimum=0.0, material=0.1),
    Parameter("odd_quadratic", "-", "alpha2' of H(r*), the coefficient of |r*| r*", material=0.05),
)


@kernel
def restoring(normalised_rate, cubic, odd_quadratic):
    """The |r*| r* and cubic part of H(r*) (2.27)."""
    cubic_part = cubic * normalised_rate * normalised_rate * normalised_rate
    return cubic_part + odd_quadratic * abs(normalised_rate) * normalised_rate


CONTRIBUTIONS = (Contribution("restoring", restoring),)
