"""Norrbin non-linearity: the cubic term of H(r*) (thesis 2.27, 2.28, 2.45).

    H(r*) = ... + alpha3 r*^3

It bends the spiral characteristic: large rudder angles give less rate of turn than the linear
model, and a negative linear term (see ``yaw``) with alpha3 > 0 describes a course-unstable ship.
Steady turn: r* + alpha3 r*^3 = K* delta (2.26).
"""

from __future__ import annotations

from ship_env.model.declarations import Effect, Parameter
from ship_env.model.kernel import kernel

EFFECT = Effect(
    name="norrbin",
    title="non-linear yaw damping at large rate of turn (Norrbin cubic term)",
    equations="(2.27), (2.28)",
    parameters=(Parameter("cubic", "-", "alpha3 of H(r*), the cubic coefficient", minimum=0.0),),
)


@kernel
def restoring(normalised_rate, cubic):
    """The cubic part of H(r*) (2.27)."""
    return cubic * normalised_rate * normalised_rate * normalised_rate
