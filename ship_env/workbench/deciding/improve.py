"""Add effects one at a time while the held-out error falls: the error ladder.

Start from a model, validate it (leave one run out), diagnose the missing effects, add the one
with the lowest held-out error if it pays, and repeat. Where no single effect pays, the strongest
candidates are tried two at a time (some effects only pay together, :func:`~.diagnose.pairs`) and
the best pair is added if it does. Each rung of the ladder is a model and its held-out error; the
diagnosis made on a rung says why the next effects were chosen.

An effect *pays* (:func:`verdict`) when none of its held-out replays leaves the model's validity
(diverges, see :mod:`.errors`) and

1. it lowers the held-out score by at least ``min_gain`` (5 %);
2. the fall exceeds its uncertainty: ``GAIN_SIGMAS`` times the jackknife standard error, over the
   runs (or groups) left out, of the difference of the two scores -- a gain within it is noise;
3. its fitted terms differ from their null values (an offset of 0) by more than ``TERM_SIGMAS``
   standard errors for at least one term (the larger of the Jacobian's and the jackknife's), or
   all together by as much (:func:`_terms_at_null`: correlated terms, each poorly known alone);
   and by more than their material size for at least one term, where the effect declares one for
   each (:mod:`~.materiality`: a smaller effect absorbs a mismatch, it is not a physical effect);
4. with validation runs of another kind and ``require_validation``, it lowers their score by at
   least ``min_gain`` as well;
5. with validation runs, it does not raise their score by more than ``min_gain`` (the 5 % rule
   mirrored): an effect fitted on one kind of run that makes the other kind materially worse
   extrapolates badly -- typically a term such as Norrbin's cubic fitted on zig-zags whose rates of
   turn never reach the turning runs' (the stop reason names the quantities in which the
   validation runs go beyond the fitted runs' coverage, :mod:`.coverage`). The hull's cross-flow drag
   (``hull_crossflow``: damping that grows as r*|r*|, not r*^3) is a candidate on the same rung and
   extrapolates more gently. ``allow_worse_validation`` turns this rule off; ``require_validation``
   (4) is the stricter one.
6. sailed free as its preset would be, it holds a hard-over turning circle to both sides where the
   current model does (:func:`cannot_sail`): a fit is a ship, ordered hard over by the first trial
   or autopilot that sails it, beyond the rudder and rates of turn of the runs it was fitted to.

Where the current model cannot sail that turning circle and no candidate pays, the best candidate with which it
does is added, if its terms pass rule 3, its held-out score is no more than ``min_gain`` worse and the validation
runs are not made worse (:func:`_first_that_sails`): zig-zags cannot ask for the damping only a harder turn
shows, but they must support it.

Near the noise floor the gains fail 2 or 3: the ladder says so and stops.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace

import numpy as np
from scipy.stats import chi2

from ship_env.manoeuvres import turning_circle
from ship_env.model import ShipModel
from ship_env.workbench.deciding.diagnose import CONFIRMED, CandidateResult, Diagnosis, diagnose, in_words, pairs
from ship_env.workbench.deciding.diagnose import refit as refit_in_full
from ship_env.workbench.defaults import MIN_GAIN, PAIR_WIDTH
from ship_env.workbench.fitting.errors import ErrorScales
from ship_env.workbench.fitting.fit import Estimate, FitOptions, as_setup
from ship_env.workbench.fitting.parallel import start as start_workers
from ship_env.workbench.fitting.replay import ReplayModel
from ship_env.workbench.fitting.runs import screen_runs
from ship_env.workbench.fitting.terms import sailing_model, with_values
from ship_env.workbench.fitting.threads import one_thread
from ship_env.workbench.judging.coverage import beyond_in_words
from ship_env.workbench.judging.free_running import compare_free_running, figure_score
from ship_env.workbench.judging.materiality import mismatch
from ship_env.workbench.judging.validation import CrossValidation, ValidationJob, cross_validate, cross_validate_each
from ship_env.workbench.logs.logs import Log

#: Jackknife standard errors of the held-out score's fall that the fall must exceed.
GAIN_SIGMAS = 1.0
#: Standard errors by which one of an added effect's terms (or all of them together) must lie from its null value.
TERM_SIGMAS = 2.0
#: How validation runs may be scored (:class:`Rules`).
VALIDATE_BY = ("replay", "figures")
#: Smallest ratio of a covariance's least to its largest eigenvalue for the joint test of the terms to use it.
JOINT_CONDITION = 1e-12


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


@one_thread
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
    groups: Sequence[str] | None = None,
    validate_on: Sequence[Log] = (),
    require_validation: bool = False,
    allow_worse_validation: bool = False,
    validate_by: str = "replay",
    terms: Sequence[str] | None = None,
) -> Ladder:
    """Climb the error ladder greedily (see the module docstring).

    Args:
        model: the starting model; its effects' default terms are fitted (or ``terms``).
        logs: the runs (at least two: the error is held out); a run wholly outside the model's envelope is
            left out with a :class:`~.logs.LogWarning`, as the command line does (:func:`~.runs.screen_runs`).
        options: fit options (error scales, default scale-free for the runs kept; nuisance terms).
        candidates: effects that may be added (default: all that the logs can show, less those tried only where
            named, ``defaults.ON_REQUEST``).
        min_gain: an effect is added if it lowers the held-out score by at least this fraction.
        max_steps: most effects to add.
        refit: per step, refit only this many candidates with the most evidence.
        pair_width: where no single effect pays, try pairs of this many candidates (0: never).
        progress: called with a line of text at each step.
        groups: per run, the group it is left out with (default: each run alone).
        validate_on: runs of another kind, never fitted, scored by each rung's all-run fit.
        require_validation: an effect must also lower the validation runs' score by ``min_gain``.
        allow_worse_validation: add an effect even where it raises the validation runs' score by more than
            ``min_gain`` (by default it is not added).
        validate_by: how the validation runs are scored in rules 4 and 5: ``"replay"``, their held-out replay
            score, or ``"figures"``, their manoeuvres sailed free and judged by their IMO figures
            (:func:`~.free_running.figure_score`).
        terms: the starting model's terms to fit (default: its effects' default terms for the logs); a term left
            out keeps the starting model's value on every rung, and each rung fits its added effect's terms.
    """
    if validate_by not in VALIDATE_BY:
        raise ValueError(f"validate_by: expected one of {', '.join(VALIDATE_BY)}, got {validate_by!r}")
    setup = as_setup(model)
    logs, groups, validate_on = screen_runs(setup.model, logs, groups, validate_on)
    options = (options or FitOptions()).for_runs(setup.model, logs)
    start_workers(options.workers)
    say = progress or (lambda text: None)
    scales = options.error_scales
    validation = cross_validate(setup, logs, terms, options=options, groups=groups, validate_on=validate_on)
    say(f"start: {', '.join(validation.fit.setup.model.effects)}; held-out score {validation.score(scales):.3g}")
    rungs: list[Rung] = []
    added: tuple[str, ...] = ()
    rules = Rules(min_gain, require_validation and bool(validate_on), allow_worse_validation, validate_by)
    while True:
        if max_steps is not None and len(rungs) >= max_steps:
            rungs.append(Rung(added, validation))
            return Ladder(tuple(rungs), scales, f"reached the most steps, {max_steps}")
        diagnosis = diagnose(validation, logs, options, candidates, refit)
        tried = [c for c in diagnosis.ranked if c.cross_validation is not None]
        # Whether the current model sails its hard-over turning circles, asked once per rung.
        stuck = cannot_sail(validation.fit.setup.model, logs) if logs else None
        judging = Judging(validation, scales, rules, logs, options)
        best = _best_paying(tried, judging, say, stuck)
        tried_pairs: list[CandidateResult] = []
        if best is None and pair_width >= 2:
            tried_pairs = pairs(diagnosis, logs, options, pair_width)
            best = _best_paying(tried_pairs, judging, say, stuck)
        rungs.append(Rung(added, validation, diagnosis, tuple(tried_pairs)))
        for candidate in [c for c in tried + tried_pairs if c.cross_validation is not None]:
            # Say where the validation runs alone kept a better candidate out.
            worse = _worsens_validation(candidate, validation, scales, rules)
            better = best is None or candidate.refitted.score(scales) < best.refitted.score(scales)
            if worse and better and verdict(candidate, validation, scales, rules, logs) == worse:
                say(f"not added: {candidate.effect}: {worse}")
        refused: list[str] = []
        if best is None and stuck is not None:
            best, refused = _first_that_sails(diagnosis.ranked + tried_pairs, judging)
            if best is not None:
                say(f"{best.effect}: {_makes_a_ship(best, validation, scales)}")
        if best is None:
            adrift = "" if stuck is None else _cannot_sail_stop(stuck, refused)
            refitted = [c for c in tried + tried_pairs if c.cross_validation is not None]
            leading = sorted(refitted, key=lambda c: c.refitted.score(scales))
            if not leading:
                return Ladder(tuple(rungs), scales, f"no effect left to add{adrift}")
            first = leading[0]
            kind = "pair" if len(first.effects) > 1 else "effect"
            return Ladder(
                tuple(rungs),
                scales,
                f"the best next {kind}, {first.effect}: {verdict(first, validation, scales, rules, logs)}{adrift}",
            )
        score = validation.score(scales)
        added, validation = best.effects, best.refitted
        say(f"added {best.effect}: held-out score {score:.3g} -> {validation.score(scales):.3g}")


@dataclass(frozen=True)
class Rules:
    """When an effect pays: the smallest relative gain, whether validation runs must gain too, and whether
    they may get worse."""

    min_gain: float = MIN_GAIN
    require_validation: bool = False
    allow_worse_validation: bool = False
    #: How the validation runs are scored: ``"replay"`` (their held-out replay score) or ``"figures"`` (their
    #: manoeuvres sailed free, :func:`~.free_running.figure_score`: what a naval architect judges).
    validate_by: str = "replay"


@dataclass(frozen=True)
class Judging:
    """What a rung's candidates are judged against: the current model's cross-validation (``current``), the error
    scales, the rules, the runs and the fit options a candidate is refitted with."""

    current: CrossValidation
    scales: ErrorScales
    rules: Rules
    logs: Sequence[Log]
    options: FitOptions


def _best_paying(
    tried: Sequence[CandidateResult], judging: Judging, say: Callable[[str], None], current_stuck: str | None
) -> CandidateResult | None:
    """The candidate with the lowest held-out score among those that pay, or None. Each keeps only the terms that
    pay their way (:func:`_with_paying_terms`). Those that sail free
    (:func:`cannot_sail`) come first: where the current model sails (``current_stuck`` None, else why it does not),
    one that cannot is refused (said); where it cannot either, the best that sails is taken before a better-scoring
    one that does not (a step towards a ship is preferred to a better replay that is none), and the best of those
    only where none sails."""
    current, scales = judging.current, judging.scales
    refitted = [c for c in tried if c.cross_validation is not None]
    paying = [c for c in refitted if not verdict(c, current, scales, judging.rules)]
    if not paying:
        return None
    paying = [_with_paying_terms(c, judging, say) for c in paying]
    paying.sort(key=lambda c: c.refitted.score(scales))
    current_sails = current_stuck is None
    for candidate in paying:
        stuck = cannot_sail(candidate.refitted.fit.setup.model, judging.logs)
        if stuck is None:
            return candidate
        if current_sails:
            say(f"not added: {candidate.effect}: {_not_a_ship(candidate, current, scales, stuck)}")
    return None if current_sails else paying[0]


def _first_that_sails(tried: Sequence[CandidateResult], judging: Judging) -> tuple[CandidateResult | None, list[str]]:
    """Where the current model cannot sail a hard-over turning circle (:func:`cannot_sail`) and no candidate pays:
    the best-scoring one with which it sails, its terms clear of their nulls and material (rule 3), its replays
    valid, its held-out score no more than ``min_gain`` above the current one and the validation runs not made
    worse (rule 5), or None; and, for each candidate refused on the way though it sails, why. Candidates only
    screened are refitted in full first where their screening is within that bound and sails (the ``CONFIRMED``
    best). The runs cannot ask for what only a harder turn shows (a zig-zag's r* stays below a turning circle's),
    yet they must support it: a fit is a ship. Called only where the current model cannot sail (the caller
    has asked :func:`cannot_sail` once)."""
    current, scales, rules, logs = judging.current, judging.scales, judging.rules, judging.logs
    score = current.score(scales)
    bound = (1.0 + rules.min_gain) * score
    screened = sorted(
        (
            c
            for c in tried
            if c.cross_validation is None and c.screened is not None and c.screened.score(scales) <= bound
        ),
        key=lambda c: c.refitted_briefly.score(scales),
    )
    sailing = [c for c in screened if cannot_sail(c.refitted_briefly.fit.setup.model, logs) is None][:CONFIRMED]
    in_full = refit_in_full(current, logs, sailing, judging.options)
    refitted = [c for c in tried if c.cross_validation is not None] + in_full
    refitted = sorted((c for c in refitted if c.cross_validation is not None), key=lambda c: c.refitted.score(scales))
    refused: list[str] = []
    for candidate in refitted:
        validation = candidate.refitted
        if cannot_sail(validation.fit.setup.model, logs) is not None:
            continue
        change = 100.0 * (validation.score(scales) / score - 1.0)
        why = (
            _diverged_replays(validation)
            or _terms_at_null(candidate)
            or mismatch(candidate.effects, validation.fit)
            or _worsens_validation(candidate, current, scales, rules)
        )
        if why is None and validation.score(scales) > bound:
            why = f"changes the held-out score by {change:+.1f}% (at most {100.0 * rules.min_gain:+.0f}%)"
        if why is None:
            return candidate, refused
        refused.append(f"{candidate.effect}: {why}")
    return None, refused


def _cannot_sail_stop(stuck: str, refused: Sequence[str]) -> str:
    """The words the ladder's stop ends with where its final model cannot sail a hard-over turning circle."""
    tried = f"; of the candidates with which it sails, none is supported by the runs: {'; '.join(refused)}"
    return f"; and the final model cannot sail: {stuck}{tried if refused else ''}"


def _makes_a_ship(candidate: CandidateResult, current: CrossValidation, scales: ErrorScales) -> str:
    """Why a candidate that does not pay on its scores is added (:func:`_first_that_sails`)."""
    change = 100.0 * (candidate.refitted.score(scales) / current.score(scales) - 1.0)
    return (
        f"changes the held-out score by {change:+.1f}%, but without it the model cannot sail a hard-over turning "
        "circle and with it it does, its terms clear of their nulls and material: added, a fit must be a ship"
    )


def _with_paying_terms(candidate: CandidateResult, judging: Judging, say: Callable[[str], None]) -> CandidateResult:
    """The candidate with its added effects' terms that do not pay their way held at their null values.

    A term must pay as an effect must (rule 1, mirrored): with the added effects' terms the least clear of
    their nulls first (|value - null| / s.e.), each is held at its null and the rest refitted, and the simpler
    model is kept where it still pays and the term lowered the held-out score by less than ``min_gain``.
    Terms that trade one for the other on the runs (Norrbin's |r*| r* and r*^3 on zig-zags) are then not both
    kept to extrapolate as they please beyond the runs: the ladder keeps the one the runs need.
    """
    current, scales, rules, options = judging.current, judging.scales, judging.rules, judging.options
    while True:
        validation = candidate.refitted
        clearance = _clearance(candidate)
        if len(clearance) < 2:
            return candidate
        weakest, _ = min(clearance, key=lambda pair: pair[1])
        keys = [e.term.key for e in validation.fit.estimates if e is not weakest]
        null = weakest.term.null or 0.0
        job = ValidationJob(
            with_values(validation.fit.setup, {weakest.term.key: null}),
            judging.logs,
            keys,
            options,
            groups=current.groups or None,
            validate_on=current.validation_logs,
        )
        (outcome,) = cross_validate_each([job], options.workers)
        if isinstance(outcome, Exception):
            return candidate
        simpler = replace(candidate, cross_validation=outcome)
        full, reduced = validation.score(scales), outcome.score(scales)
        if full <= (1.0 - rules.min_gain) * reduced or verdict(simpler, current, scales, rules):
            return candidate
        say(
            f"{candidate.effect}: {weakest.term.key} held at {null:g} (with it the held-out score is "
            f"{100.0 * (full / reduced - 1.0):+.1f}%, needs -{100.0 * rules.min_gain:.0f}%)"
        )
        candidate = simpler


def verdict(
    candidate: CandidateResult,
    current: CrossValidation,
    scales: ErrorScales,
    rules: Rules,
    logs: Sequence[Log] = (),
) -> str:
    """Why the candidate does not pay (see the module docstring), or '' if it does; with the fitted ``logs``, a
    candidate that pays on its scores must also sail free where the current model does (:func:`cannot_sail`)."""
    validation = candidate.refitted
    diverged = _diverged_replays(validation)
    if diverged is not None:
        return diverged
    score, new = current.score(scales), validation.score(scales)
    gain = 1.0 - new / score
    if gain < rules.min_gain:
        return f"changes the held-out score by {-100.0 * gain:+.1f}% (needs -{100.0 * rules.min_gain:.0f}%)"
    spread = validation.score_jackknife(scales, current)
    if math.isfinite(spread) and score - new <= GAIN_SIGMAS * spread:
        return (
            f"lowers the held-out score by {100.0 * gain:.1f}%, within its uncertainty "
            f"({GAIN_SIGMAS:g} x {100.0 * spread / score:.1f}%, jackknife over the runs): near the noise floor "
            "of these logs, the gain is not told from the scatter between runs"
        )
    weak = _terms_at_null(candidate)
    if weak is not None:
        return f"lowers the held-out score by {100.0 * gain:.1f}%, but {weak}: near the noise floor of these logs"
    absorbed = mismatch(candidate.effects, validation.fit)
    if absorbed is not None:
        return f"lowers the held-out score by {100.0 * gain:.1f}%, but {absorbed}"
    scores = _validation_scores(candidate, current, scales, rules)
    if rules.require_validation and scores is not None:
        before, after = scores
        if after > (1.0 - rules.min_gain) * before:
            return (
                f"lowers the held-out score by {100.0 * gain:.1f}% but changes the validation runs' "
                f"{_scored_by(rules)} {_change(before, after)} (needs -{100.0 * rules.min_gain:.0f}%)"
            )
    worse = _worsens_validation(candidate, current, scales, rules, scores)
    if worse:
        return worse
    if logs:
        stuck = cannot_sail(validation.fit.setup.model, logs)
        if stuck is not None and cannot_sail(current.fit.setup.model, logs) is None:
            return _not_a_ship(candidate, current, scales, stuck)
    return ""


def _not_a_ship(candidate: CandidateResult, current: CrossValidation, scales: ErrorScales, stuck: str) -> str:
    """Why a candidate that pays on its scores is refused: its preset cannot sail (``stuck``, :func:`cannot_sail`)."""
    gain = 1.0 - candidate.refitted.score(scales) / current.score(scales)
    return f"lowers the held-out score by {100.0 * gain:.1f}%, but {stuck}: not added, a fit must be a ship"


def cannot_sail(model: ShipModel, logs: Sequence[Log]) -> str | None:
    """Words saying that the fitted model, sailed as its preset would be (:func:`~.terms.sailing_model`: the
    logs' operating point, the starting preset's steering machine where they record the actual rudder), leaves
    the model's validity in a hard-over turning circle to either side; None where it sails both. A fit's
    replays never go beyond the runs' rudder and rates of turn; its preset is ordered hard over by the first
    turning trial or autopilot that sails it (a Norrbin cubic or cross-flow drag fitted on zig-zags, with an
    asymmetry, can leave the steady-turn curve H(r*) without a root there)."""
    sailed = sailing_model(model, logs)
    for side, name in ((1.0, "starboard"), (-1.0, "port")):
        try:
            turning_circle(sailed, side * sailed.rudder_limit)
        except FloatingPointError as error:
            angle = math.degrees(sailed.rudder_limit)
            return f"sailed free through the hard-over ({angle:.0f} deg) turning circle to {name} it fails ({error})"
    return None


def _validation_scores(
    candidate: CandidateResult, current: CrossValidation, scales: ErrorScales, rules: Rules
) -> tuple[float, float] | None:
    """The validation runs' score before and with the candidate (their pooled replay score, or with
    ``rules.validate_by == "figures"`` their manoeuvres' :func:`~.free_running.figure_score`), or None without
    validation runs (or, by figures, without a manoeuvre among them)."""
    if rules.validate_by == "figures":
        runs = current.validation_logs
        if not runs:
            return None
        before = figure_score(compare_free_running(current.fit.setup, runs))
        after = figure_score(compare_free_running(candidate.refitted.fit.setup, runs))
        return None if math.isnan(before) or math.isnan(after) else (before, after)  # inf: cannot sail them
    replayed, with_it = current.pooled_validation, candidate.refitted.pooled_validation
    return (replayed.score(scales), with_it.score(scales)) if replayed and with_it else None


def _scored_by(rules: Rules) -> str:
    """What the validation runs' score is, in words."""
    return "score of their manoeuvres' figures" if rules.validate_by == "figures" else "score"


def _change(before: float, after: float, sign: str = "+") -> str:
    """The validation runs' score changing from ``before`` to ``after``, in words (infinite: cannot sail them);
    ``sign``: the format's sign option ("+" always shows it, "-" only for a fall)."""
    if math.isinf(after) and math.isfinite(before):
        return "to infinite: the model cannot sail their manoeuvres"
    return f"by {100.0 * (after / before - 1.0):{sign}.1f}%"


def _worsens_validation(
    candidate: CandidateResult,
    current: CrossValidation,
    scales: ErrorScales,
    rules: Rules,
    scores: tuple[float, float] | None = None,
) -> str | None:
    """Words saying that the candidate raises the validation runs' score by more than ``min_gain`` (rule 5),
    naming where they lie beyond the fitted runs' coverage; None if it does not, or where that is allowed.
    ``scores``: the validation runs' scores before and with the candidate, where already known
    (:func:`_validation_scores`; by figures, each is a free sail of every validation run)."""
    validation = candidate.refitted
    scores = scores or _validation_scores(candidate, current, scales, rules)
    if rules.allow_worse_validation or scores is None:
        return None
    before, after = scores
    if not after > (1.0 + rules.min_gain) * before:
        return None
    gain = 1.0 - validation.score(scales) / current.score(scales)
    beyond = beyond_in_words(current.validation_checks())
    return (
        f"lowers the held-out score by {100.0 * gain:.1f}% but raises the validation runs' {_scored_by(rules)} "
        f"{_change(before, after, '-')} (more than {100.0 * rules.min_gain:.0f}%"
        f"{'; validation runs ' + beyond if beyond else ''}): not added (--allow-worse-validation adds it)"
    )


def _diverged_replays(validation: CrossValidation) -> str | None:
    """Words naming the runs whose held-out replays left the model's validity, and when; None if none did."""
    diverged = [e for e in validation.held_out if e.diverged]
    if not diverged:
        return None
    shown = ", ".join(f"{e.name} at t = {e.diverged_at:.1f} s" for e in diverged)
    return (
        f"its held-out replays of {len(diverged)} run{'s' * (len(diverged) > 1)} leave the model's validity "
        f"({shown}): not added, a model that diverges is not an improvement"
    )


def _terms_at_null(candidate: CandidateResult) -> str | None:
    """Words saying that the added effects' terms are not clear of their null values, or None if they are.

    A term is clear where |value - null| exceeds ``TERM_SIGMAS`` standard errors (the larger of the
    Jacobian's and the jackknife's). Terms fitted together can each lie within that and together far
    from their nulls: Norrbin's |r*| r* and r*^3 fitted on zig-zags trade one for the other, so each is
    poorly known while their sum is not. So k > 1 terms are also clear together where their Mahalanobis
    distance d = sqrt(dtheta^T C^-1 dtheta) from the nulls, with C the Jacobian's or the jackknife's
    covariance (whichever gives the smaller d, as the larger standard error is taken for one term),
    exceeds the chi-square quantile with k degrees of freedom at the probability that ``TERM_SIGMAS``
    standard errors hold for one term (95.4 % for 2; d > 2.49 for k = 2). With one term the two tests
    are the same.
    """
    validation = candidate.refitted
    clearance = _clearance(candidate)
    if not clearance:
        return None
    if max(ratio for _, ratio in clearance) > TERM_SIGMAS:
        return None
    added = [e for e, _ in clearance]
    shown = ", ".join(f"{e.term.key} {ratio:.1f}" for e, ratio in clearance)
    alone = (
        f"its terms lie within {TERM_SIGMAS:g} standard errors of their null values (|value - null| / s.e.: {shown})"
    )
    if len(added) == 1:
        return alone
    together = _joint_distance(validation, added)
    limit = _joint_limit(len(added))
    if together is not None and together > limit:
        return None
    distance = "not known" if together is None else f"{together:.1f}"
    return f"{alone}, and together within {limit:.2f} (their distance from the nulls in standard errors: {distance})"


def _clearance(candidate: CandidateResult) -> list[tuple[Estimate, float]]:
    """The added effects' terms that have a null value, each with |value - null| / s.e. (the larger of the
    Jacobian's and the jackknife's standard errors)."""
    validation = candidate.refitted
    jackknife = validation.jackknife_errors()
    return [
        (e, abs(e.value - (e.term.null or 0.0)) / max(e.std_error, jackknife[e.term.key], 1e-300))
        for e in validation.fit.estimates
        if e.term.effect in candidate.effects and e.term.null is not None
    ]


def _joint_distance(validation: CrossValidation, estimates: Sequence[Estimate]) -> float | None:
    """The terms' Mahalanobis distance from their nulls, the smaller with either covariance (see
    :func:`_terms_at_null`); None where a covariance is not finite and positive definite (a term the
    runs do not determine, or fewer folds than terms)."""
    keys = [e.term.key for e in estimates]
    offset = np.array([e.value - (e.term.null or 0.0) for e in estimates])
    distances = []
    for covariance in (validation.fit.covariance(keys), validation.jackknife_covariance(keys)):
        if not np.all(np.isfinite(covariance)):
            return None
        eigenvalues = np.linalg.eigvalsh(covariance)
        if eigenvalues[0] <= JOINT_CONDITION * eigenvalues[-1]:
            return None
        distances.append(math.sqrt(float(offset @ np.linalg.solve(covariance, offset))))
    return min(distances)


def _joint_limit(count: int) -> float:
    """The distance that ``count`` terms must exceed together: the chi-square quantile, ``count`` degrees of
    freedom, at the two-sided normal probability of ``TERM_SIGMAS`` (the limit is ``TERM_SIGMAS`` for one)."""
    return math.sqrt(float(chi2.ppf(math.erf(TERM_SIGMAS / math.sqrt(2.0)), count)))
