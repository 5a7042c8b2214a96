"""Materiality: whether a fitted effect is large enough to be a physical effect.

Each effect declares the smallest departure of its parameters from their null values that means
something physically (``Parameter.material``: a rudder offset of 0.3 deg, a current of 1.5 % of
the service speed; see each effect's module). Every log carries a small mismatch with the model
that fits it -- how the rudder is sampled, sensor delays, the integrator -- and a fit can absorb it
into an effect that lowers the held-out error significantly (a rudder offset of 0.02 deg, six
standard errors from zero). An effect whose fitted terms *all* lie within their material size of
their null values absorbs such a mismatch: it is not a physical effect, and the ladder does not add
it. An effect with a term that declares no material size (or no null value) is never judged so.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

from ship_env.workbench.fitting.fit import Estimate, FitResult

#: SI units shown in other units, with the factor: radians as degrees.
_SHOWN_AS = {"rad": ("deg", 180.0 / math.pi), "rad/s": ("deg/s", 180.0 / math.pi)}


def shown(value: float, unit: str) -> str:
    """A value with its unit, angles in degrees ('0.02 deg', '0.004 m/s')."""
    label, factor = _SHOWN_AS.get(unit, (unit, 1.0))
    return f"{value * factor:.2g}" + ("" if label == "-" else f" {label}")


def _immaterial(estimates: Sequence[Estimate]) -> bool:
    """Whether every estimate declares a material size and lies within it of its null value."""
    return all(
        e.term.null is not None and e.term.material is not None and abs(e.value - e.term.null) <= e.term.material
        for e in estimates
    )


def mismatch(effects: Sequence[str], fit: FitResult) -> str | None:
    """Words saying that one of the added ``effects`` absorbs a mismatch (see the module docstring), or None.

    E.g. "rudder_offset absorbs a mismatch of size 0.02 deg (material from 0.3 deg): not a physical effect".
    """
    for effect in effects:
        estimates = [e for e in fit.estimates if e.term.effect == effect]
        if not estimates or not _immaterial(estimates):
            continue
        named = len(estimates) > 1
        sizes = ", ".join(
            (f"{e.term.key.partition('.')[2]} " if named else "") + shown(e.value - (e.term.null or 0.0), e.term.unit)
            for e in estimates
        )
        materials = ", ".join(shown(e.term.material or 0.0, e.term.unit) for e in estimates)
        return f"{effect} absorbs a mismatch of size {sizes} (material from {materials}): not a physical effect"
    return None
