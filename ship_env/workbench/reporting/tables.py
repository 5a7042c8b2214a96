"""The workbench's tables, written as aligned text for the terminal or as Markdown for reports.

Every table is built once as a header and rows of strings (:class:`~ship_env.text_table.Table`),
then rendered.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

from ship_env.model.declarations import Envelope
from ship_env.text_table import Table
from ship_env.workbench.deciding.diagnose import CandidateResult, Diagnosis
from ship_env.workbench.deciding.improve import Ladder
from ship_env.workbench.fitting.envelope import EnvelopeCheck
from ship_env.workbench.fitting.errors import ErrorScales, RunErrors, pooled
from ship_env.workbench.fitting.replay import Simulated
from ship_env.workbench.judging.coverage import QUANTITIES, Coverage, CoverageCheck, errors_inside_beyond
from ship_env.workbench.judging.materiality import mismatch
from ship_env.workbench.judging.validation import CrossValidation
from ship_env.workbench.logs.logs import Log


def number(value: float, digits: int = 2) -> str:
    """A number with fixed decimals, or '-' where it is not measured (NaN)."""
    return "-" if not math.isfinite(value) else f"{value:.{digits}f}"


def significant(value: float, digits: int = 4) -> str:
    return "-" if not math.isfinite(value) else f"{value:.{digits}g}"


def std_error_cell(value: float) -> str:
    """A standard error, 'not determined' where it is infinite (the data do not determine the term)."""
    return "not determined" if value == math.inf else significant(value, 2)


ERROR_HEADER = ("heading [deg]", "rate [deg/s]", "speed [m/s]", "position [m]", "track [m]", "score")


def error_cells(errors: RunErrors, scales: ErrorScales) -> tuple[str, ...]:
    """RMS heading, rate of turn, speed (the free replay's: '-' without a speed channel), free position and
    track, and the score."""
    shown = errors.in_display_units()
    return (
        number(shown["heading"]),
        number(shown["rate_of_turn"], 3),
        significant(shown["speed"], 2),
        number(shown["position"]),
        number(shown["track"]),
        number(errors.score(scales)),
    )


def diverged_words(errors: RunErrors) -> str:
    """When a run's replay left the model's validity, or how many runs' did (pooled); '' if none."""
    if not errors.diverged:
        return ""
    if math.isfinite(errors.diverged_at):
        return f"diverged at t = {errors.diverged_at:.1f} s"
    return f"{errors.diverged} run{'s' * (errors.diverged > 1)} diverged"


def error_table(errors: Sequence[RunErrors], scales: ErrorScales, total: RunErrors | None = None) -> Table:
    """Per-run RMS errors, and a pooled row if given; a column says which replays diverged, where some did."""
    shown = [*errors, *([] if total is None else [total])]
    if not any(e.diverged for e in shown):
        return Table(("run", *ERROR_HEADER), tuple((e.name, *error_cells(e, scales)) for e in shown))
    rows = tuple((e.name, *error_cells(e, scales), diverged_words(e)) for e in shown)
    return Table(("run", *ERROR_HEADER, "model validity"), rows)


def estimate_table(validation: CrossValidation) -> Table:
    """The all-run fit's terms with their standard errors (Jacobian; jackknife over the folds)."""
    jackknife = validation.jackknife_errors()
    rows = tuple(
        (
            e.term.key,
            significant(e.value),
            std_error_cell(e.std_error),
            significant(jackknife[e.term.key], 2),
            e.term.unit,
            "at bound" if e.at_bound else "",
        )
        for e in validation.fit.estimates
    )
    return Table(("term", "value", "std. error (Jacobian)", "std. error (jackknife)", "unit", ""), rows)


def _screened_mark(candidate: CandidateResult) -> str:
    """'(screened) ' for a candidate whose score is its screening's (a brief refit), else ''."""
    return "(screened) " if candidate.screened is not None and candidate.cross_validation is None else ""


def _absorbed(candidate: CandidateResult) -> str:
    """'; ' and the words of an added effect that absorbs a mismatch (:mod:`~.materiality`), else ''."""
    validation = candidate.cross_validation or candidate.screened
    words = None if validation is None else mismatch(candidate.effects, validation.fit)
    return "" if words is None else f"; {words}"


def _diverged_note(held_out: RunErrors | None) -> str:
    """'; N runs diverged (held out)' where some held-out replays left the model's validity, else ''."""
    if held_out is None or not held_out.diverged:
        return ""
    return f"; {diverged_words(held_out)} (held out)"


def _candidate_notes(candidate: CandidateResult) -> str:
    """What went wrong with a candidate's refit: held-out replays that diverged, numerical warnings."""
    validation = candidate.cross_validation or candidate.screened
    if validation is None:
        return ""
    warnings = validation.fit.warnings_line()
    return _diverged_note(validation.pooled) + (f"; {warnings}" if warnings else "")


def diagnosis_table(diagnosis: Diagnosis) -> Table:
    """The missing effects, best first: evidence, held-out score and its change, and the effect in words."""
    scales = diagnosis.scales
    current = diagnosis.baseline.pooled
    baseline = current.score(scales)
    effects = diagnosis.baseline.fit.setup.model.effects
    rows = [
        (
            "",
            "(current model)",
            "",
            "",
            number(math.degrees(current.heading)),
            number(current.track),
            number(baseline),
            "",
            f"effects: {', '.join(effects)}",
        )
    ]
    for rank, candidate in enumerate(diagnosis.ranked, start=1):
        found = candidate.evidence
        held_out = candidate.held_out
        score = held_out.score(scales) if held_out else math.nan
        rows.append(
            (
                str(rank) if held_out or found else "",
                candidate.effect,
                number(found.correlation, 3) if found else "-",
                number(100.0 * found.variance_explained, 1) if found else "-",
                number(math.degrees(held_out.heading)) if held_out else "-",
                number(held_out.track) if held_out else "-",
                number(score),
                f"{100.0 * (score / baseline - 1.0):+.0f}%" if held_out else "-",
                candidate.skipped
                or _screened_mark(candidate) + candidate.title + _absorbed(candidate) + _candidate_notes(candidate),
            )
        )
    return Table(
        (
            "rank",
            "effect",
            "corr",
            "var. expl. [%]",
            "held-out heading [deg]",
            "held-out track [m]",
            "score",
            "change",
            "physical effect",
        ),
        tuple(rows),
        words=2,
    )


def ladder_table(ladder: Ladder) -> Table:
    """The error ladder: each model's held-out errors, the score's change from the rung before, and
    beside them the validation runs' errors and score where there are validation runs."""
    rows = []
    previous = previous_validation = None
    validated = bool(ladder.rungs[0].validation.validation)
    for rung in ladder.rungs:
        held_out = rung.validation.pooled
        score = held_out.score(ladder.scales)
        extra: tuple[str, ...] = ()
        other = rung.validation.pooled_validation
        if validated and other is not None:
            other_score = other.score(ladder.scales)
            change = "" if previous_validation is None else f"{100.0 * (other_score / previous_validation - 1.0):+.0f}%"
            extra = (number(math.degrees(other.heading)), number(other.track), number(other_score), change)
            previous_validation = other_score
        rows.append(
            (
                rung.label,
                *error_cells(held_out, ladder.scales),
                "" if previous is None else f"{100.0 * (score / previous - 1.0):+.0f}%",
                *extra,
                rung.title + _diverged_note(held_out),
            )
        )
        previous = score
    header = ("model", *(f"held-out {h}" for h in ERROR_HEADER), "change")
    if validated:
        header += ("validation heading [deg]", "validation track [m]", "validation score", "validation change")
    return Table((*header, "effects / effect added"), tuple(rows))


def log_table(logs: Sequence[Log]) -> Table:
    """The runs: length, duration, channels and what the loader noted."""
    rows = tuple(
        (
            log.name,
            str(log.samples),
            number(log.duration, 1),
            f"{log.rudder_kind} rudder; " + ", ".join(c for c in log.channels() if c not in ("time", "rudder")),
            "; ".join(log.notes),
        )
        for log in logs
    )
    return Table(("run", "samples", "duration [s]", "channels", "notes"), rows)


def envelope_table(checks: Sequence[EnvelopeCheck]) -> Table:
    """Per run, the share of samples outside the model's envelope and why."""
    rows = tuple(
        (check.run, str(len(check.outside)), number(100.0 * check.share, 0), check.reasons() or "-") for check in checks
    )
    return Table(("run", "samples", "outside [%]", "why"), rows)


def envelope_line(envelope: Envelope) -> str:
    """The envelope's limits in words."""
    parts = []
    if envelope.minimum_speed is not None:
        parts.append(f"speed >= {envelope.minimum_speed:.3g} m/s")
    if envelope.minimum_froude is not None:
        parts.append(f"Froude number >= {envelope.minimum_froude:g}")
    if envelope.propeller_ahead_only:
        parts.append("propeller ahead")
    if envelope.maximum_drift is not None:
        parts.append(f"drift angle <= {math.degrees(envelope.maximum_drift):.0f} deg")
    if envelope.maximum_rate is not None:
        parts.append(f"rate of turn <= {math.degrees(envelope.maximum_rate):.3g} deg/s")
    return ", ".join(parts) or "no limits stated"


def coverage_table(checks: Sequence[CoverageCheck], coverage: Coverage) -> Table:
    """Per run, the share of samples beyond the fitted runs' coverage, and per quantity of the coverage the
    run's extreme against the fitted runs' limit with the share of samples beyond it ('2.30x (58 %)')."""
    keys = list(coverage.ranges)

    def cell(check: CoverageCheck, key: str) -> str:
        parts = [e for e in check.exceedances if e.quantity == key]
        return "; ".join(f"{e.ratio() or ('above' if e.above else 'below')} ({100.0 * e.share:.0f} %)" for e in parts)

    rows = tuple(
        (check.run, str(check.samples), number(100.0 * check.share, 0), *(cell(check, key) or "-" for key in keys))
        for check in checks
    )
    return Table(("run", "samples", "extrapolated [%]", *(QUANTITIES[key].words for key in keys)), rows)


def coverage_sections(
    title: str,
    coverage: Coverage,
    checks: Sequence[CoverageCheck],
    logs: Sequence[Log],
    replays: Sequence[Simulated],
    scales: ErrorScales,
) -> list[tuple[str, Table | None]]:
    """The runs checked against the fitted runs' coverage: a line of the ranges, the share of each run
    extrapolated and why, and its errors inside and beyond the coverage (where any run goes beyond)."""
    sections: list[tuple[str, Table | None]] = [
        (
            f"coverage of the fitted runs (percentiles {100.0 - coverage.percentile:g} to {coverage.percentile:g} "
            f"of their samples): {coverage.describe()}",
            None,
        ),
        (
            f"{title} beyond the fitted runs' coverage, where the model extrapolates: the share of samples, and per "
            "quantity the run's extreme (1st or 99th percentile) against the fitted runs' limit (share beyond it)",
            coverage_table(checks, coverage),
        ),
    ]
    if any(check.exceedances for check in checks):
        for label, errors in zip(("inside", "beyond"), errors_inside_beyond(logs, replays, checks), strict=True):
            table = error_table(errors, scales, pooled(errors))
            sections.append((f"{title}, RMS errors over the samples {label} the fitted runs' coverage", table))
    return sections


def sections_text(sections: Sequence[tuple[str, Table | None]]) -> str:
    """Sections (a heading, and a table or None; :func:`coverage_sections`) as text for the terminal."""
    return "\n".join(f"\n{heading}" + ("" if table is None else f"\n{table.text()}") for heading, table in sections)


def validation_coverage_text(validation: CrossValidation, scales: ErrorScales) -> str:
    """The validation runs against the fitted runs' coverage (:func:`coverage_sections`) as text; empty without
    validation runs or a coverage."""
    if validation.coverage is None or not validation.validation_logs:
        return ""
    checks, logs, replays = validation.validation_checks(), validation.validation_logs, validation.validation_replays
    return sections_text(coverage_sections("validation runs", validation.coverage, checks, logs, replays, scales))
