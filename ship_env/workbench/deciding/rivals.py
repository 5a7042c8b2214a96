"""Rival forms: effects the runs could not tell from those the ladder added, and what each predicts beyond the runs.

Two forms can fit a ship's zig-zags equally well and part beyond them. On the container ship's sea trials
(``benchmarks/bench_free_running.py --truth container_226m``, seed 2) the ladder adds the hull's cross-flow drag,
a yaw damping in |r*| r*, where the truth's is Norrbin's cubic in r*^3: fitted to the four zig-zags, whose r* stays
under 0.52, the cubic alone scores 2.5 % above the cross-flow drag in sample, and Norrbin's effect with both its
terms fits an |r*| r* term and is the same model. At the hard-over turn's r* of 0.9 they part: the cross-flow drag
loses 43.9 % of the speed, the cubic 38.9 %, the truth 39.5 %. The fit's jackknife does not show this spread: its
folds all carry the form the ladder chose, and give the speed loss +-0.7 points.

A *rival* of an effect added alone on a rung is another candidate of that rung's diagnosis, not in the final model,
that would have paid there too (its held-out score ``min_gain`` below the rung's start, as the ladder asks). The
final model with the rival in place of the added effect is fitted to all runs, and so is each of the rival's terms
alone where it has several (a form is a term's shape as much as an effect). Those whose in-sample score lies within
``min_gain`` of the final model's (the ladder's own materiality: a difference the runs' noise could make) are sailed
as their preset would be, through the hard-over turning circle to both sides and the 10/10 zig-zag, beside the
final model: the columns are the spread of the form, beyond the runs where the turn goes. A rival that leaves the
model's validity there is not one: the ladder adds no effect with which the model cannot sail that turn.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Sequence
from dataclasses import dataclass, replace

from ship_env.manoeuvres import Figure, turning_circle, zigzag
from ship_env.model import ShipModel
from ship_env.text_table import Table
from ship_env.workbench.deciding.diagnose import with_effect_at_null
from ship_env.workbench.deciding.improve import Ladder
from ship_env.workbench.fitting.fit import FitError, FitOptions, fit
from ship_env.workbench.fitting.replay import ReplayModel
from ship_env.workbench.fitting.terms import default_terms, effect_terms, sailing_model
from ship_env.workbench.judging.free_running import JUDGED_FIGURES
from ship_env.workbench.logs.logs import Log

#: The zig-zag whose first overshoot is compared: rudder a and heading change b, deg.
ZIGZAG = (10.0, 10.0)
#: A figure's display unit as a preset's number states it, where they differ: a length in ship lengths and a share
#: are dimensionless.
PRESET_UNITS = {"L": "-", "%": "-"}


@dataclass(frozen=True)
class Rival:
    """An effect the runs could not tell from one the ladder added.

    Attributes:
        rung: the rung's label (``+ hull_crossflow``).
        added: the effect the ladder added there.
        rival: the candidate of that rung's diagnosis that would have paid there too.
    """

    rung: str
    added: str
    rival: str


def find_rivals(ladder: Ladder, min_gain: float) -> list[Rival]:
    """The candidates (the module docstring) that would have paid in place of each effect added alone on a rung, in
    the ladder's order and each rung's diagnosis's (the rival's held-out score there from its screening where it was
    not refitted in full)."""
    final = set(ladder.final.fit.setup.model.effects)
    found = []
    for before, rung in itertools.pairwise(ladder.rungs):
        if len(rung.added) != 1 or before.diagnosis is None:
            continue
        start = before.validation.score(ladder.scales)
        for candidate in before.diagnosis.ranked:
            validation = candidate.cross_validation or candidate.screened
            if validation is None or len(candidate.effects) != 1 or candidate.effect in final:
                continue
            if validation.score(ladder.scales) <= (1.0 - min_gain) * start:
                found.append(Rival(rung.label, rung.added[0], candidate.effect))
    return found


@dataclass(frozen=True)
class RivalFit:
    """The final model with a rival in its added effect's place, fitted to all runs.

    Attributes:
        rival: the rival.
        terms: the rival's terms fitted.
        alone: whether ``terms`` is one of the rival's several terms, the others held at their nulls.
        model: the fitted model, as its preset would sail it (:func:`~.terms.sailing_model`).
        score: its in-sample score on the runs.
    """

    rival: Rival
    terms: tuple[str, ...]
    alone: bool
    model: ShipModel
    score: float

    @property
    def title(self) -> str:
        """'norrbin for hull_crossflow', or with one term alone 'norrbin.cubic alone for hull_crossflow'."""
        rival = f"{self.terms[0]} alone" if self.alone else self.rival.rival
        return f"{rival} for {self.rival.added}"


def rival_fits(ladder: Ladder, logs: Sequence[Log], rival: Rival, options: FitOptions) -> list[RivalFit]:
    """The final model with ``rival.rival`` in place of ``rival.added``, fitted to all ``logs`` with the rival's
    terms (from the final fit's values, the rival's at their nulls), and with each of them alone where it has several
    (the others held at their nulls)."""
    final = ladder.final.fit
    without = ReplayModel(final.setup.model.without_effects(rival.added), *final.setup.current)
    swapped, _ = with_effect_at_null(without, rival.rival)
    dropped = set(effect_terms(rival.added))
    kept = [estimate.term.key for estimate in final.estimates if estimate.term.key not in dropped]
    own = [key for key in default_terms((rival.rival,), logs) if key not in kept]
    choices = [tuple(own)] + ([(key,) for key in own] if len(own) > 1 else [])
    fits = []
    for terms in choices:
        try:
            result = fit(swapped, logs, kept + list(terms), options)
        except FitError:
            continue
        model = sailing_model(result.setup.model, logs)
        fits.append(RivalFit(rival, terms, len(terms) < len(own), model, result.pooled.score(ladder.scales)))
    return fits


def judged_figures(model: ShipModel) -> dict[str, Figure]:
    """The free-running figures the workbench judges (:data:`~.free_running.JUDGED_FIGURES`), each with its value the
    mean of both hard-over turning circles' or the 10/10 zig-zag's first overshoot. ``FloatingPointError`` where the
    model leaves its validity."""
    found: dict[str, list[Figure]] = {}
    turns = [turning_circle(model, side * model.rudder_limit).figures() for side in (1.0, -1.0)]
    overshoot = zigzag(model, math.radians(ZIGZAG[0]), math.radians(ZIGZAG[1])).figures()
    for figure in (*turns[0], *turns[1], *overshoot):
        if figure.key in JUDGED_FIGURES and not isinstance(figure.value, str):
            found.setdefault(figure.key, []).append(figure)
    return {
        key: replace(found[key][0], value=sum(float(f.value) for f in found[key]) / len(found[key]))
        for key in JUDGED_FIGURES
        if key in found
    }


@dataclass(frozen=True)
class FormSpread:
    """The final model's judged figures and its rivals' (each rounded to its decimals; a figure not reached is
    absent), as ``improve --preset`` prints them and the preset records them (``fitted.rival_forms``).

    Attributes:
        score: the final model's in-sample score.
        final: its figures.
        rivals: per rival that sails other figures, its title, in-sample score and figures.
        same: the rivals whose figures are the final model's or an earlier rival's.
        min_gain: how far (a fraction of ``score``) a rival's in-sample score may lie above ``score``.
    """

    score: float
    final: dict[str, Figure]
    rivals: tuple[tuple[str, float, dict[str, Figure]], ...]
    same: tuple[str, ...]
    min_gain: float

    def text(self) -> str:
        """The rivals and a table of their figures beside the final model's."""
        if not self.rivals:
            return (
                f"rival forms: {'; '.join(self.same)} fit the runs within {self.min_gain:.0%} and sail as the final "
                "model does"
            )
        lines = [
            f"rival forms: fitted to all runs within {self.min_gain:.0%} of the final model's in-sample score "
            f"{self.score:.3g}, they part beyond the runs:",
            *(
                f"  rival {k}: {title}, in-sample score {score:.3g}"
                for k, (title, score, _) in enumerate(self.rivals, 1)
            ),
        ]
        if self.same:
            lines.append(f"  the same figures as the final model or a rival: {'; '.join(self.same)}")
        table = Table(
            (
                "sailed free, mean of the 35 deg turns",
                "final model",
                *(f"rival {k}" for k in range(1, len(self.rivals) + 1)),
            ),
            tuple(
                (figure_title(key), _text(key, self.final), *(_text(key, figures) for _, _, figures in self.rivals))
                for key in JUDGED_FIGURES
            ),
        )
        return "\n".join([*lines, table.text()])

    def summary(self) -> dict[str, object]:
        """The spread as a fitted preset records it (``fitted.rival_forms``; ``ship-env manoeuvre`` prints it), each
        figure under its :func:`figure_title` as a preset's number (``{value, unit}``, :data:`PRESET_UNITS`:
        ``ship-env scale`` Froude-scales it)."""

        def titled(figures: dict[str, Figure]) -> dict[str, dict[str, object]]:
            return {
                figure_title(key): {"value": figure.value, "unit": PRESET_UNITS.get(figure.unit, figure.unit)}
                for key, figure in figures.items()
            }

        return {
            "why": "forms the runs could not rule out, fitted to all runs in place of an effect the ladder added: "
            f"their in-sample score within {self.min_gain:.0%} of the final model's; the figures are the mean of the "
            f"35 deg turns and the {ZIGZAG[0]:g}/{ZIGZAG[1]:g} zig-zag's first overshoot",
            "final_model": {"in_sample_score": self.score, "figures": titled(self.final)},
            "rivals": [
                {"form": title, "in_sample_score": score, "figures": titled(figures)}
                for title, score, figures in self.rivals
            ],
            "same_figures": list(self.same),
        }


def form_spread(ladder: Ladder, logs: Sequence[Log], options: FitOptions, min_gain: float) -> FormSpread | None:
    """The rival forms the runs cannot tell from the final model's, and the figures each predicts beside its own (a
    rival whose figures are the final model's, to the decimals shown, is only named); None where there is none."""
    score = ladder.final.fit.pooled.score(ladder.scales)
    candidates = [
        fitted
        for rival in find_rivals(ladder, min_gain)
        for fitted in rival_fits(ladder, logs, rival, options)
        if fitted.score <= (1.0 + min_gain) * score
    ]
    if not candidates:
        return None
    final = _rounded(sailing_model(ladder.final.fit.setup.model, logs))
    if final is None:  # the final model cannot sail the turn: no spread to show beside it
        return None
    rivals: list[tuple[str, float, dict[str, Figure]]] = []
    same = []
    for fitted in candidates:
        figures = _rounded(fitted.model)
        if figures is None:  # it cannot sail the hard-over turn: not a ship the ladder would add (its rule 6)
            continue
        if figures == final or any(figures == other for _, _, other in rivals):
            same.append(fitted.title)
        else:
            rivals.append((fitted.title, fitted.score, figures))
    if not rivals and not same:
        return None
    return FormSpread(score, final, tuple(rivals), tuple(same), min_gain)


def figure_title(key: str) -> str:
    """A judged figure's name and unit: 'tactical diameter [L]', 'first overshoot 10/10 [deg]'."""
    if key == "first_overshoot":
        return f"first overshoot {ZIGZAG[0]:g}/{ZIGZAG[1]:g} [deg]"
    units = {"advance_lengths": "[L]", "tactical_diameter_lengths": "[L]", "steady_rate_of_turn": "[deg/s]"}
    return f"{key.replace('_lengths', '').replace('_', ' ')} {units.get(key, '[%]')}"


def _rounded(model: ShipModel) -> dict[str, Figure] | None:
    """Each judged figure with its value rounded to the decimals it is shown with (absent where the model does not
    reach it); None where the model leaves its validity."""
    try:
        figures = judged_figures(model)
    except FloatingPointError:
        return None
    return {
        key: replace(figure, value=round(float(figure.value), figure.digits))
        for key, figure in figures.items()
        if math.isfinite(float(figure.value))
    }


def _text(key: str, figures: dict[str, Figure]) -> str:
    return figures[key].text if key in figures else "n/a"


__all__ = [
    "FormSpread",
    "Rival",
    "RivalFit",
    "figure_title",
    "find_rivals",
    "form_spread",
    "judged_figures",
    "rival_fits",
]
