"""Add effects one at a time while the held-out error falls: the error ladder.

Start from a model, validate it (leave one run out), diagnose the missing effects, add the one
with the lowest held-out error if it lowers the error by at least ``min_gain``, and repeat. Each
rung of the ladder is a model and its held-out error; the diagnosis made on a rung says why the
next effect was chosen.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

from ship_env.identify.diagnose import Diagnosis, diagnose
from ship_env.identify.errors import ErrorScales
from ship_env.identify.fit import FitOptions, as_setup
from ship_env.identify.logs import Log
from ship_env.identify.replay import ReplayModel
from ship_env.identify.validation import CrossValidation, cross_validate
from ship_env.model import ShipModel

#: Smallest relative fall of the held-out score for which an effect is added.
MIN_GAIN = 0.05


@dataclass(frozen=True)
class Rung:
    """One model of the ladder: the effect added to reach it, its validation and its diagnosis."""

    added: str | None
    validation: CrossValidation
    diagnosis: Diagnosis | None = None

    @property
    def effects(self) -> tuple[str, ...]:
        return self.validation.fit.setup.model.effects


@dataclass(frozen=True)
class Ladder:
    """The rungs from the starting model to the last improvement, and why the climb stopped."""

    rungs: tuple[Rung, ...]
    scales: ErrorScales
    stopped: str

    @property
    def added(self) -> list[str]:
        return [rung.added for rung in self.rungs if rung.added]

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
        progress: called with a line of text at each step.
    """
    options = options or FitOptions()
    say = progress or (lambda text: None)
    scales = options.scales
    validation = cross_validate(as_setup(model), logs, options=options)
    say(f"start: {', '.join(validation.fit.setup.model.effects)}; held-out score {validation.score(scales):.3g}")
    rungs: list[Rung] = []
    added: str | None = None
    while True:
        if max_steps is not None and len(rungs) >= max_steps:
            rungs.append(Rung(added, validation))
            return Ladder(tuple(rungs), scales, f"reached the most steps, {max_steps}")
        diagnosis = diagnose(validation, logs, options, candidates, refit)
        rungs.append(Rung(added, validation, diagnosis))
        best = diagnosis.best
        if best is None:
            return Ladder(tuple(rungs), scales, "no effect left to add")
        score, new_score = validation.score(scales), best.held_out.score(scales)
        if new_score > score * (1.0 - min_gain):
            return Ladder(
                tuple(rungs),
                scales,
                f"the best next effect, {best.effect}, changes the held-out score by "
                f"{100.0 * (new_score / score - 1.0):+.1f}% (needs -{100.0 * min_gain:.0f}%)",
            )
        added, validation = best.effect, best.cross_validation
        say(f"added {added}: held-out score {score:.3g} -> {new_score:.3g}")
