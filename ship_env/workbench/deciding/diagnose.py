"""Which physical effect does the model lack? Evidence in the residuals, then the held-out proof.

For each effect the model lacks (and the logs can show, see :func:`~.terms.why_not_fitted`):

1. **Evidence** (no refit; a score test, the Lagrange-multiplier test of nonlinear least squares):
   the effect's *regressors* are the changes of the weighted residuals when each of its terms moves
   one scale from its null value (an offset of 0 -> 1 deg; for a term without a null, the change
   from the effect off to the effect on at the preset's value). Their part that the fitted terms
   could already produce is projected out (columns of the fit's Jacobian); what remains is
   correlated with the residual. ``variance_explained`` is the share of the residual's sum of
   squares the regressors take up, ``correlation`` its square root (the multiple correlation).
   The regression's coefficients also give the linearised estimate the refit starts from.
2. **Screening**: the effect is added and the model refitted cheaply -- a few Gauss-Newton
   iterations (``SCREENING_EVALUATIONS``) from the current fit with the new terms at their
   linearised estimates -- and its leave-one-run-out error computed: a held-out score to rank the
   candidates by at a fraction of a full fit's cost. Densely sampled runs are fitted at a coarser
   step (:func:`screening_runs`: every n-th sample, keeping ``SAMPLES_PER_LENGTH`` per ship length)
   and their held-out errors measured on every sample.
3. **Held-out error**: the ``CONFIRMED`` candidates with the best screened score, and the one
   with the most evidence, are refitted in full and cross-validated. The refit starts three
   times -- from the screening's fit, from the current fit with the new terms at their null
   values, and afresh from the ship preset's values (output-error fits have local minima; a new
   effect can move the others far) -- and keeps the fit with the lowest cost. The refitted
   candidates are ranked by the held-out error: the error that matters is on runs the fit did
   not see.
4. **Pairs** (:func:`pairs`): some effects only pay together, each hidden behind the other's
   absence; the strongest candidates are also added two at a time, screened, and the
   ``CONFIRMED_PAIRS`` best refitted.

Past the library (:func:`past_the_library`): where no candidate lowers the held-out score by
``EXPLAINS``, the signals the residual follows (:mod:`.signals`) say what to look for.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace
from itertools import combinations

import numpy as np

from ship_env.model import EFFECTS, ShipModel
from ship_env.workbench.deciding.signals import ResidualSignals, residual_signals
from ship_env.workbench.defaults import ON_REQUEST
from ship_env.workbench.fitting.errors import ErrorScales, RunErrors
from ship_env.workbench.fitting.fit import FitOptions, Problem
from ship_env.workbench.fitting.replay import ReplayModel, coarser_step
from ship_env.workbench.fitting.terms import (
    Term,
    effect_terms,
    make_term,
    value_of,
    why_not_fitted,
    with_values,
)
from ship_env.workbench.fitting.threads import one_thread
from ship_env.workbench.judging.validation import CrossValidation, ValidationJob, cross_validate_each
from ship_env.workbench.logs.logs import Log, every_nth

#: Cost evaluations of a screening fit (a few Gauss-Newton iterations from the current fit).
SCREENING_EVALUATIONS = 6
#: Candidates refitted in full after screening: those with the best screened held-out score.
CONFIRMED = 2
#: Pairs refitted in full after screening: two sets of new terms at their linearised estimates
#: screen less faithfully (on the berthing segments the pair that paid was screened third).
CONFIRMED_PAIRS = 3
#: An effect explains the residual where adding it at least halves the held-out score (the bar the
#: hidden-effect checks set); below it, :func:`past_the_library` speaks.
EXPLAINS = 0.5


@dataclass(frozen=True)
class Evidence:
    """What the residuals of the current fit say about one missing effect.

    Attributes:
        correlation: multiple correlation of the residual with the effect's regressors (after
            projecting out what the fitted terms explain), 0..1.
        variance_explained: its square: the share of the residual sum of squares they explain.
        linearised: the effect's terms as the linearised regression estimates them (start values).
    """

    correlation: float
    variance_explained: float
    linearised: dict[str, float]


def in_words(effects: Sequence[str]) -> str:
    """The effects as a naval engineer names them (their titles), joined by '; '."""
    return "; ".join(EFFECTS[name].title for name in effects)


@dataclass(frozen=True)
class CandidateResult:
    """One missing effect (or several added together): evidence and the held-out error with it added.

    ``screened`` is the cheap refit that ranked it (see the module docstring), ``cross_validation``
    the full refit (only for the best screened); ``skipped`` says why an effect was not tried (it
    cannot be fitted, or failed).
    """

    effects: tuple[str, ...]
    evidence: Evidence | None = None
    cross_validation: CrossValidation | None = None
    skipped: str = ""
    screened: CrossValidation | None = None

    @property
    def effect(self) -> str:
        """The effect's name, or the names joined by ' + '."""
        return " + ".join(self.effects)

    @property
    def title(self) -> str:
        """The effect in words."""
        return in_words(self.effects)

    @property
    def held_out(self) -> RunErrors | None:
        """The held-out errors of the full refit, else of the screening, else None."""
        validation = self.cross_validation or self.screened
        return None if validation is None else validation.pooled

    @property
    def refitted(self) -> CrossValidation:
        """The cross-validation with the effect added; raises for a candidate that was not refitted."""
        if self.cross_validation is None:
            raise ValueError(f"{self.effect}: not refitted ({self.skipped or 'evidence only'})")
        return self.cross_validation

    @property
    def refitted_briefly(self) -> CrossValidation:
        """The screening's cross-validation; raises for a candidate that was not screened."""
        if self.screened is None:
            raise ValueError(f"{self.effect}: not screened ({self.skipped or 'evidence only'})")
        return self.screened

    @property
    def variance_explained(self) -> float:
        """The share of the residual variance its evidence explains (0 without evidence)."""
        return 0.0 if self.evidence is None else self.evidence.variance_explained


@dataclass(frozen=True)
class Diagnosis:
    """The current model's held-out error and the missing effects, best first."""

    baseline: CrossValidation
    candidates: tuple[CandidateResult, ...]
    scales: ErrorScales
    #: Past the library: the signals the fitted model's missing yaw acceleration follows.
    signals: ResidualSignals | None = None

    @property
    def ranked(self) -> list[CandidateResult]:
        """Refitted candidates by held-out score, the screened by theirs, those with evidence only, the skipped."""
        refitted = sorted(
            (c for c in self.candidates if c.cross_validation), key=lambda c: c.refitted.score(self.scales)
        )
        screened = _by_screened_score(
            [c for c in self.candidates if c.screened and not c.cross_validation], self.scales
        )
        evidence_only = sorted(
            (c for c in self.candidates if c.evidence and not c.held_out),
            key=lambda c: -c.variance_explained,
        )
        rest = [c for c in self.candidates if not c.evidence and not c.held_out]
        return refitted + screened + evidence_only + rest

    @property
    def best(self) -> CandidateResult | None:
        best = self.ranked[0] if self.candidates else None
        return best if best is not None and best.cross_validation is not None else None


def candidate_effects(
    setup: ReplayModel, logs: Sequence[Log], named: Sequence[str] | None = None
) -> tuple[list[str], dict[str, str]]:
    """The effects that could be added (in ``EFFECTS`` order) and, for the rest, why not; an effect tried only on
    request (``defaults.ON_REQUEST``) is one only where ``named`` names it."""
    possible, reasons = [], {}
    for effect in EFFECTS:
        if setup.model.has(effect):
            continue
        reason = why_not_fitted(effect, setup.model, logs)
        if reason is None and effect in ON_REQUEST and effect not in (named or ()):
            reason = ON_REQUEST[effect]
        if reason is None:
            possible.append(effect)
        else:
            reasons[effect] = reason
    return possible, reasons


def with_effect_at_null(setup: ReplayModel, *effects: str) -> tuple[ReplayModel, list[Term]]:
    """The model with ``effects`` added and their terms at their null values (where they have one)."""
    added = ReplayModel(setup.model.with_effects(*effects), setup.current_north, setup.current_east)
    terms = [make_term(key, added) for effect in effects for key in effect_terms(effect)]
    nulls = {term.key: term.null for term in terms if term.null is not None}
    return with_values(added, nulls), terms


def preset_values(setup: ReplayModel, keys: Sequence[str]) -> dict[str, float]:
    """The terms' values in the ship's preset (no current): a fresh start away from the current fit."""
    fresh = ReplayModel(ShipModel(setup.model.ship, setup.model.effects))
    return {key: value_of(fresh, key) for key in keys}


def evidence(current: CrossValidation, logs: Sequence[Log], effect: str, options: FitOptions) -> Evidence:
    """The score-test evidence for adding ``effect`` to the current fit (see the module docstring)."""
    fitted = current.fit
    base_keys = [estimate.term.key for estimate in fitted.estimates]
    at_null, terms = with_effect_at_null(fitted.setup, effect)
    problem = Problem(at_null, logs, base_keys + [term.key for term in terms], options)
    x_fit = problem.start()
    x_fit[len(base_keys) + len(terms) :] = fitted.solution[len(base_keys) :]
    without = fitted.residual
    columns = []
    for j, term in enumerate(terms):
        probe = x_fit.copy()
        index = len(base_keys) + j
        if term.null is not None:
            probe[index] = (term.null + term.scale) / term.scale
        columns.append(problem.residual(probe) - without)
    regressors = np.column_stack(columns)
    jacobian = fitted.jacobian
    if jacobian.shape[1]:
        regressors = regressors - jacobian @ np.linalg.lstsq(jacobian, regressors, rcond=None)[0]
    coefficients = np.linalg.lstsq(regressors, -without, rcond=None)[0]
    explained = regressors @ coefficients
    share = float(explained @ explained / (without @ without)) if without @ without > 0 else 0.0
    linearised = {}
    for term, step in zip(terms, coefficients, strict=True):
        if term.null is not None:
            linearised[term.key] = float(np.clip(term.null + step * term.scale, term.lower, term.upper))
    return Evidence(correlation=math.sqrt(min(max(share, 0.0), 1.0)), variance_explained=share, linearised=linearised)


@one_thread
def diagnose(
    current: CrossValidation,
    logs: Sequence[Log],
    options: FitOptions | None = None,
    effects: Sequence[str] | None = None,
    refit: int | None = None,
) -> Diagnosis:
    """Evidence for each missing effect, then the held-out error with it added and refitted.

    Args:
        current: the current model's cross-validation (its all-run fit is the one diagnosed).
        logs: the runs, as fitted.
        options: the fit options (the same as the current fit's).
        effects: the candidate effects (default: every effect the model lacks that the logs can show, less those
            tried only on request, ``defaults.ON_REQUEST``).
        refit: refit only this many candidates, those with the most evidence (default: all).
    """
    options = (options or FitOptions()).for_runs(current.fit.setup.model, logs)
    possible, reasons = candidate_effects(current.fit.setup, logs, effects)
    chosen = possible if effects is None else [effect for effect in effects if effect in possible]
    skipped = [
        CandidateResult((effect,), skipped=reasons.get(effect, "already in the model"))
        for effect in (reasons if effects is None else [e for e in effects if e not in possible])
    ]
    with_evidence = [(effect, evidence(current, logs, effect, options)) for effect in chosen]
    with_evidence.sort(key=lambda item: -item[1].variance_explained)
    count = len(with_evidence) if refit is None else refit
    results = screen_and_confirm(current, logs, [{effect: found} for effect, found in with_evidence[:count]], options)
    results += [CandidateResult((effect,), found) for effect, found in with_evidence[count:]]
    return Diagnosis(
        baseline=current,
        candidates=tuple(results + skipped),
        scales=options.error_scales,
        signals=residual_signals(current.fit.setup, logs),
    )


def screening_runs(logs: Sequence[Log], model: ShipModel) -> list[Log]:
    """The runs a screening fits: every n-th sample, n the largest step that keeps every run at
    ``SAMPLES_PER_LENGTH`` samples per ship length sailed (:func:`~.replay.coarser_step`; five or more
    in each of a zig-zag's rudder moves). Its held-out errors are measured on every sample, and the
    candidates it ranks best are confirmed on every sample: a model test logged at 20 Hz is screened
    at 5 Hz, its screening's fits in about a quarter of the time."""
    step = coarser_step(logs, model)
    return [every_nth(log, step) for log in logs]


def screen(
    current: CrossValidation, logs: Sequence[Log], founds: Sequence[Mapping[str, Evidence]], options: FitOptions
) -> list[CandidateResult]:
    """Add each set of effects found (with their evidence) to the current model, refit briefly and cross-validate.

    The refit is ``SCREENING_EVALUATIONS`` evaluations from the current fit with the new terms at
    their linearised estimates, without the validation runs (see the module docstring).
    """
    quick = replace(options, max_evaluations=SCREENING_EVALUATIONS)
    runs = screening_runs(logs, current.fit.setup.model)
    scored_on = logs if any(run is not log for run, log in zip(runs, logs, strict=True)) else ()
    jobs = []
    for found in founds:
        added, terms = with_effect_at_null(current.fit.setup, *found)
        keys = [estimate.term.key for estimate in current.fit.estimates] + [term.key for term in terms]
        linearised = {key: value for evidence_ in found.values() for key, value in evidence_.linearised.items()}
        jobs.append(
            ValidationJob(
                with_values(added, linearised), runs, keys, quick, groups=current.groups or None, scored_on=scored_on
            )
        )
    results = []
    for found, outcome in zip(founds, cross_validate_each(jobs, options.workers), strict=True):
        own_evidence = next(iter(found.values())) if len(found) == 1 else None
        if isinstance(outcome, Exception):
            results.append(CandidateResult(tuple(found), own_evidence, skipped=f"refit failed: {outcome}"))
        else:
            results.append(CandidateResult(tuple(found), own_evidence, screened=outcome))
    return results


def refit(
    current: CrossValidation,
    logs: Sequence[Log],
    screened: Sequence[CandidateResult],
    options: FitOptions,
) -> list[CandidateResult]:
    """The screened candidates refitted and cross-validated, with the validation runs.

    Each fit starts from the screening's fit, from the current fit with the new terms at their null
    values and from the ship preset's values; the fit with the lowest cost is kept.
    """
    jobs = []
    for candidate in screened:
        fitted = candidate.refitted_briefly
        keys = [estimate.term.key for estimate in fitted.fit.estimates]
        added, _ = with_effect_at_null(current.fit.setup, *candidate.effects)
        starts = ({key: value_of(added, key) for key in keys}, preset_values(added, keys))
        jobs.append(
            ValidationJob(
                fitted.fit.setup,
                logs,
                keys,
                options,
                starts=starts,
                groups=current.groups or None,
                validate_on=current.validation_logs,
            )
        )
    return [
        replace(candidate, skipped=f"refit failed: {outcome}")
        if isinstance(outcome, Exception)
        else replace(candidate, cross_validation=outcome)
        for candidate, outcome in zip(screened, cross_validate_each(jobs, options.workers), strict=True)
    ]


def screen_and_confirm(
    current: CrossValidation,
    logs: Sequence[Log],
    founds: Sequence[Mapping[str, Evidence]],
    options: FitOptions,
    confirmed: int = CONFIRMED,
) -> list[CandidateResult]:
    """Screen each set of effects; refit in full the ``confirmed`` best and the first (most evidence).

    A few evaluations can leave a candidate whose terms must move far well short of its optimum:
    the one the residuals point to most is refitted whatever its screening says.
    """
    screened = screen(current, logs, founds, options)
    best = _by_screened_score([c for c in screened if c.screened], options.error_scales)[:confirmed]
    best += [c for c in screened[:1] if c.screened]
    chosen = [c for c in screened if any(c is b for b in best)]
    refitted = iter(refit(current, logs, chosen, options))
    return [next(refitted) if any(c is b for b in best) else c for c in screened]


def _by_screened_score(candidates: Sequence[CandidateResult], scales: ErrorScales) -> list[CandidateResult]:
    return sorted(candidates, key=lambda c: c.screened.score(scales) if c.screened else math.inf)


@one_thread
def pairs(
    diagnosis: Diagnosis, logs: Sequence[Log], options: FitOptions | None = None, width: int = 4
) -> list[CandidateResult]:
    """The effects added two at a time: every pair of the ``width`` candidates with most evidence.

    Some effects only pay together: a rudder that works harder at high propeller rate
    (``propeller_slipstream``) is hidden behind a wind moment the model lacks, and the other way
    round. The pairs refitted in full, best held-out score first, then the screened ones.
    """
    options = (options or FitOptions()).for_runs(diagnosis.baseline.fit.setup.model, logs)
    strongest = sorted(
        ((c.effect, c.evidence) for c in diagnosis.candidates if c.evidence is not None and len(c.effects) == 1),
        key=lambda named: -named[1].variance_explained,
    )[:width]
    founds = [dict(pair) for pair in combinations(strongest, 2)]
    results = screen_and_confirm(diagnosis.baseline, logs, founds, options, CONFIRMED_PAIRS)
    refitted = sorted((c for c in results if c.cross_validation), key=lambda c: c.refitted.score(diagnosis.scales))
    screened = [c for c in results if c.screened and not c.cross_validation]
    return refitted + _by_screened_score(screened, diagnosis.scales)


def past_the_library(diagnosis: Diagnosis, min_gain: float = EXPLAINS) -> str | None:
    """Where no effect of the library lowers the held-out score by ``min_gain``: the signals in words; else None."""
    if diagnosis.signals is None:
        return None
    best = diagnosis.best
    baseline = diagnosis.baseline.score(diagnosis.scales)
    if (
        best is not None
        and best.held_out is not None
        and best.held_out.score(diagnosis.scales) <= (1.0 - min_gain) * baseline
    ):
        return None
    verdict = (
        "no effect of the library lowers the held-out score"
        if best is None
        else f"no effect of the library lowers the held-out score by {100 * min_gain:.0f}% (best: {best.effect})"
    )
    return f"{verdict}; {diagnosis.signals.text()}"
