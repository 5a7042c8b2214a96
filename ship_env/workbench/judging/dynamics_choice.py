"""Which model a fitted preset sails: the error ladder's effects, or the MMG standard's forces by inverse dynamics.

The error ladder (``ship-env fit``, ``improve``) fits the De Keizer / Van Leeuwen model, whose sway is algebraic or
lags and whose yaw damping is a function of r* alone; on a basin's zig-zags up to the hard-over rudder its turning
circle came out a third too wide, where the MMG standard's 3-DOF forces fitted by inverse dynamics
(``ship-env fit-mmg``, :mod:`~ship_env.workbench.fitting.inverse_dynamics`) predicted it within 2 %
(docs/results/free_running.md). Which of the two a preset sails is chosen on the fitted runs themselves, sailed
free from their first execute (the zig-zags closed loop on the heading), each by a fit that did not see it
(:func:`~.free_running.held_out_free_running`, :func:`~.free_running.held_out_mmg_sailing`), and scored sample by sample
as the workbench scores a replay (:func:`~.free_running.sailed_score`: heading, rate of turn and speed on the
scale-free scales). A zig-zag's first overshoot alone did not tell them apart: on the basin truth's thirteen
zig-zags the effects' overshoots came closer (0.26 against 0.35 of the 2 deg bound on one seed) while their speed
and heading sailed free were twice as far off (score 3.1 against 1.5), as their turning circle was:

- the MMG form is tried only where the runs can determine it (:func:`mmg_applies`): they reach the hard-over rudder
  (within :data:`HARD_OVER` of its limit), log the position, speed and propeller rate that inverse dynamics
  needs (the rate may be the preset's, as the replay takes it), and sail in calm air (the form has no wind
  forces). Zig-zags of 10 and 20 deg at sea do not determine its forces beyond them (on the sea-trial truths it
  missed turns that the ladder predicts);
- it sails the preset only where it sails every run and its score is below the ladder's by at least the ladder's
  own materiality, ``min_gain`` of the ladder's score (:data:`~ship_env.workbench.defaults.MIN_GAIN`): a form is
  not swapped for a difference the runs' noise could make.

The preset then holds the fitted MMG model as its ``dynamics:`` block (:mod:`ship_env.model.ship`), which the
environments, ``ship-env manoeuvre`` and the leaderboard sail by default; its effects stay what the bridge knows of
the ship and what the classic autopilots are designed from.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from ship_env.model import ShipModel
from ship_env.workbench.defaults import MIN_GAIN
from ship_env.workbench.fitting.errors import ErrorScales
from ship_env.workbench.judging.free_running import held_out_free_running, held_out_mmg_sailing, sailed_score
from ship_env.workbench.judging.validation import CrossValidation
from ship_env.workbench.logs.logs import Log

if TYPE_CHECKING:
    from ship_env.workbench.fitting.inverse_dynamics import Identification

#: The runs reach the hard-over rudder where their largest angle is at least this fraction of the limit.
HARD_OVER = 0.9


def mmg_applies(logs: Sequence[Log], model: ShipModel) -> bool:
    """Whether inverse dynamics can fit the MMG form to ``logs`` and the form is determined to the hard-over turn:
    every run logs position, speed and propeller rate (or ``model``'s preset states the rate,
    :func:`stated_propeller_rate`) in calm air (:attr:`~.logs.Log.has_wind_beyond_noise`), and some run reaches
    :data:`HARD_OVER` of ``model``'s rudder limit."""
    return reaches_hard_over(logs, model) and not why_not_mmg(logs, stated_propeller_rate(model))


def stated_propeller_rate(model: ShipModel) -> float | None:
    """The propeller rate, rps, of ``model``'s preset's service conditions, at which the replay sails a log without a
    propeller channel and inverse dynamics fits it; None where the preset states none."""
    rate = model.service_propeller_rate
    return rate if rate > 0.0 else None


def reaches_hard_over(logs: Sequence[Log], model: ShipModel) -> bool:
    """Whether some run's rudder reaches :data:`HARD_OVER` of ``model``'s limit."""
    return max(float(np.max(np.abs(log.rudder))) for log in logs) >= HARD_OVER * model.rudder_limit


def why_not_mmg(logs: Sequence[Log], propeller_rate: float | None = None) -> str:
    """Why inverse dynamics cannot fit the MMG form to ``logs`` ("" where it can): the runs that lack a channel it
    needs (the propeller rate not, where ``propeller_rate`` gives it), or sail in wind (the form has no wind
    forces)."""
    for channel, missing in (
        ("position", [log.name for log in logs if log.north is None]),
        ("speed", [log.name for log in logs if log.speed is None]),
        ("propeller rate", [log.name for log in logs if log.propeller_rate is None and propeller_rate is None]),
    ):
        if missing:
            return f"{len(missing)} of {len(logs)} runs log no {channel} ({', '.join(missing[:3])})"
    windy = [log.name for log in logs if log.has_wind_beyond_noise]
    if windy:
        return (
            f"{len(windy)} of {len(logs)} runs sail in wind beyond the anemometer's noise ({', '.join(windy[:3])}), "
            "which the MMG form has no forces for"
        )
    return ""


@dataclass(frozen=True)
class DynamicsChoice:
    """The two forms' fitted runs sailed free, each by a fit that did not see it, and which sails the preset.

    Attributes:
        ladder_score: the error ladder's :func:`~.free_running.sailed_score` over the fitted runs (inf: it cannot
            sail one; NaN: no run was sailed).
        mmg_score: the fitted MMG model's, likewise (inf also where it could not be identified).
        identified: the fitted MMG model, or None where it could not be identified.
        chosen: whether the MMG model sails the preset.
        reason: why, in words.
        runs: how many runs were sailed (0 where the MMG form could not be fitted to them: ``reason`` says why).
    """

    ladder_score: float
    mmg_score: float
    identified: Identification | None
    chosen: bool
    reason: str
    runs: int

    def lines(self) -> list[str]:
        """The choice in words, as ``fit``/``improve --preset`` print it."""
        if not self.runs:
            return [f"the runs reach the hard-over rudder; the preset sails {self.reason}"]
        return [
            "the runs reach the hard-over rudder: the MMG standard's forces fitted by inverse dynamics too; the "
            f"{self.runs} fitted runs sailed free, each by a fit that did not see it (score over heading, rate of "
            f"turn and speed): effects {self.ladder_score:.3g}, MMG {self.mmg_score:.3g}",
            f"  the preset sails {self.reason}",
        ]

    def summary(self) -> dict[str, object]:
        """The choice as a fitted preset records it (``fitted.dynamics``)."""
        return {
            "sailed_by": "mmg_3dof" if self.chosen else "effects",
            "why": self.reason,
            "score": "the fitted runs sailed free from their first execute, each by a fit that did not see it: "
            "sqrt(mean (RMS / scale)^2) over heading, rate of turn and speed, the workbench's scale-free scales",
            "effects_score": _finite_or_text(self.ladder_score),
            "mmg_score": _finite_or_text(self.mmg_score) if self.identified is not None else "not fitted",
        }


def _finite_or_text(score: float) -> float | str:
    return score if math.isfinite(score) else ("cannot sail every run" if score == math.inf else "no run sailed")


def choose_dynamics(
    validation: CrossValidation, logs: Sequence[Log], min_gain: float = MIN_GAIN
) -> DynamicsChoice | None:
    """Which model sails the preset of ``validation``'s fit to ``logs`` (the module docstring): the effects where the
    MMG form cannot be fitted to them (:func:`why_not_mmg`, the reason), None where they do not reach the hard-over
    rudder (:func:`reaches_hard_over`): nothing to choose there."""
    from ship_env.workbench.fitting.inverse_dynamics import IdentificationError, identify
    from ship_env.workbench.fitting.smoothing import SmoothingError

    setup = validation.fit.setup
    if not reaches_hard_over(logs, setup.model):
        return None
    propeller_rate = stated_propeller_rate(setup.model)
    why = why_not_mmg(logs, propeller_rate)  # with the runs reaching hard over: mmg_applies
    if why:
        return DynamicsChoice(math.nan, math.inf, None, False, f"the effects: the MMG forces are not fitted: {why}", 0)
    scales = ErrorScales.for_runs(setup.model, logs)
    ladder = held_out_free_running(validation, logs, ())
    ladder_score = sailed_score(ladder, logs, scales)
    try:
        identified = identify(logs, setup.model, propeller_rate=propeller_rate)
    except (IdentificationError, SmoothingError, np.linalg.LinAlgError) as error:  # the effects' preset still stands
        return DynamicsChoice(ladder_score, math.inf, None, False, f"the effects: the MMG form: {error}", len(ladder))
    mmg = held_out_mmg_sailing(setup, identified, logs, [])
    mmg_score = sailed_score(mmg, logs, scales)
    chosen, reason = preferred(ladder_score, mmg_score, [result.run for result in mmg if result.cannot_sail], min_gain)
    return DynamicsChoice(ladder_score, mmg_score, identified, chosen, reason, len(mmg))


def preferred(ladder_score: float, mmg_score: float, stuck: Sequence[str], min_gain: float) -> tuple[bool, str]:
    """Whether the MMG model sails the preset, and why in words: where it sails every run (``stuck``: those it
    cannot) with a score ``min_gain`` below the effects' (or the effects cannot sail them all)."""
    if stuck:
        return False, f"the effects: the MMG model cannot sail {', '.join(stuck)}"
    if not math.isfinite(mmg_score):
        return False, "the effects: no fitted run reads as a turn or a zig-zag to sail the MMG model through"
    if math.isfinite(ladder_score) and mmg_score > (1.0 - min_gain) * ladder_score:
        return (
            False,
            f"the effects: the MMG model's score {mmg_score:.3g} is not {min_gain:.0%} below {ladder_score:.3g}",
        )
    against = f"{ladder_score:.3g}" if math.isfinite(ladder_score) else "the effects, which cannot sail every run"
    return True, f"the MMG model: its score {mmg_score:.3g} against {against}"


__all__ = [
    "HARD_OVER",
    "DynamicsChoice",
    "choose_dynamics",
    "mmg_applies",
    "preferred",
    "reaches_hard_over",
    "stated_propeller_rate",
    "why_not_mmg",
]
