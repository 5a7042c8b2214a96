"""Add effects one at a time while the held-out error falls: the error ladder.

Start from a model, validate it (leave one run out), diagnose the missing effects, add the one
with the lowest held-out error if it lowers the error by at least ``min_gain``, and repeat. Where
no single effect does, the strongest candidates are tried two at a time (some effects only pay
together, :func:`~.diagnose.pairs`) and the best pair is added if it does. Each rung of the ladder
is a model and its held-out error; the diagnosis made on a rung says why the next effects were
chosen.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

from ship_env.model import ShipModel
from ship_env.workbench.diagnose import CandidateResult, Diagnosis, diagnose, in_words, pairs
from ship_env.workbench.errors import ErrorScales
from ship_env.workbench.fit import FitOptions, as_setup
from ship_env.workbench.logs import Log
from ship_env.workbench.replay import ReplayModel
from ship_env.workbench.validation import CrossValidation, cross_validate

#: Smallest relative fall of the held-out score for which an effect is added.
MIN_GAIN = 0.05
#: Where no single effect pays, pairs of this many candidates (those with most evidence) are tried.
PAIR_WIDTH = 4


@dataclass(frozen=True)
class Rung:
    """One model of the ladder: the effects added to reach it, its validation and its diagnosis."""

    added: tuple[str, ...]
    validation: CrossValidation
    diagnosis: Diagnosis | None = None
    pairs: tuple[CandidateResult, ...] = ()

    @property
    def effects(self) -> tuple[str, ...]:
        return self.validation.fit.setup.model.effects

    @property
    def label(self) -> str:
        """'start', or '+ ' and the effects added."""
        return "+ " + " + ".join(self.added) if self.added else "start"

    @property
    def title(self) -> str:
        """The effects added in words (the model's effects on the first rung)."""
        if not self.added:
            return ", ".join(self.effects)
        return in_words(self.added)


@dataclass(frozen=True)
class Ladder:
    """The rungs from the starting model to the last improvement, and why the climb stopped."""

    rungs: tuple[Rung, ...]
    scales: ErrorScales
    stopped: str

    @property
    def added(self) -> list[str]:
        """The effects added, in order."""
        return [name for rung in self.rungs for name in rung.added]

    @property
    def final(self) -> CrossValidation:
        return self.rungs[-1].validation


def improve(
    model: ShipModel | ReplayModel,
    logs: Sequence[Log],
    options: FitOptions | None = None,
    candidates: Sequence[str] | None = None,
    min_gain: float = MIN_GAIN,
    max_steps: int | None = None,
    refit: int | None = None,
    progress: Callable[[str], None] | None = None,
    pair_width: int = PAIR_WIDTH,
) -> Ladder:
    """Climb the error ladder greedily (see the module docstring).

    Args:
        model: the starting model; its effects' default terms are fitted.
        logs: the runs (at least two: the error is held out).
        options: fit options (error scales, nuisance terms).
        candidates: effects that may be added (default: all that the logs can show).
        min_gain: an effect is added if it lowers the held-out score by at least this fraction.
        max_steps: most effects to add.
        refit: per step, refit only this many candidates with the most evidence.
        pair_width: where no single effect pays, try pairs of this many candidates (0: never).
        progress: called with a line of text at each step.
    """
    options = options or FitOptions()
    say = progress or (lambda text: None)
    scales = options.scales
    validation = cross_validate(as_setup(model), logs, options=options)
    say(f"start: {', '.join(validation.fit.setup.model.effects)}; held-out score {validation.score(scales):.3g}")
    rungs: list[Rung] = []
    added: tuple[str, ...] = ()
    while True:
        if max_steps is not None and len(rungs) >= max_steps:
            rungs.append(Rung(added, validation))
            return Ladder(tuple(rungs), scales, f"reached the most steps, {max_steps}")
        diagnosis = diagnose(validation, logs, options, candidates, refit)
        score = validation.score(scales)
        best = diagnosis.best
        tried_pairs: list[CandidateResult] = []
        if (best is None or _gain(best, score, scales) < min_gain) and pair_width >= 2:
            tried_pairs = pairs(diagnosis, logs, options, pair_width)
            if tried_pairs and (best is None or _gain(tried_pairs[0], score, scales) > _gain(best, score, scales)):
                best = tried_pairs[0]
        rungs.append(Rung(added, validation, diagnosis, tuple(tried_pairs)))
        if best is None:
            return Ladder(tuple(rungs), scales, "no effect left to add")
        if _gain(best, score, scales) < min_gain:
            return Ladder(
                tuple(rungs),
                scales,
                f"the best next {'pair' if len(best.effects) > 1 else 'effect'}, {best.effect}, changes the held-out "
                f"score by {-100.0 * _gain(best, score, scales):+.1f}% (needs -{100.0 * min_gain:.0f}%)",
            )
        added, validation = best.effects, best.refitted
        say(f"added {best.effect}: held-out score {score:.3g} -> {validation.score(scales):.3g}")


def _gain(candidate: CandidateResult, score: float, scales: ErrorScales) -> float:
    """The relative fall of the held-out score from ``score`` with the candidate added."""
    return 1.0 - candidate.refitted.score(scales) / score
