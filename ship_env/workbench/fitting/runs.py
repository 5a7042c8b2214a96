"""The runs a workbench command works on: every run checked against the model's envelope, and cut or grouped.

The same for the command line and for Python: :func:`prepare_runs` checks each run (fitted or
validation) against the model's envelope (:mod:`.envelope`), leaves out a run wholly outside it
(its errors would say nothing about the model), and, as asked, cuts the runs into their stretches
inside the envelope (``inside``: a run's segments are left out together) or groups them
(``group_by``: ``"folder"``, or a regular expression on the run's name whose first group, or whole
match, names the group). It returns the runs, their envelope checks and, as lines of text, what it did;
:func:`screen_runs` is the screening alone, which ``compare``, ``cross_validate`` and ``improve``
run on the runs they are given (each run left out is a :class:`~.logs.LogWarning`).
"""

from __future__ import annotations

import re
import warnings
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path

from ship_env.model import ShipModel
from ship_env.workbench.fitting.envelope import MIN_SEGMENT, EnvelopeCheck, check_envelope, inside_logs
from ship_env.workbench.fitting.errors import RunErrors, split_errors
from ship_env.workbench.fitting.replay import Simulated
from ship_env.workbench.logs.logs import Log, LogError, LogWarning


class GroupingError(ValueError):
    """A ``group_by`` rule that does not name a group for every run."""


@dataclass(frozen=True)
class WorkbenchRuns:
    """The runs a command works on, after the envelope check.

    Attributes:
        logs: the runs fitted and scored: whole runs, or with ``inside`` their segments inside the envelope.
        groups: per run in ``logs``, the group left out with it (None: each run alone).
        validation: the validation runs (never fitted), whole or cut like ``logs``.
        checks: per whole run (fitted or validation), its envelope check.
        messages: the runs left out, and how the others were cut and grouped, as lines of text.
    """

    logs: list[Log]
    groups: list[str] | None
    validation: list[Log]
    checks: dict[str, EnvelopeCheck]
    messages: list[str] = field(default_factory=list)


def left_out_message(check: EnvelopeCheck) -> str:
    """Why a run wholly outside the envelope is left out."""
    return (
        f"{check.run} lies wholly outside the model's envelope ({check.reasons()}): left out; its errors would "
        "say nothing about the model"
    )


def envelope_checks(model: ShipModel, logs: Sequence[Log]) -> dict[str, EnvelopeCheck]:
    """Each run's check against the model's envelope, by run name."""
    return {log.name: check_envelope(log, model.envelope, model.length) for log in logs}


def _wholly_outside(checks: dict[str, EnvelopeCheck]) -> list[str]:
    return [name for name, check in checks.items() if check.share == 1.0]


def screen_runs(
    model: ShipModel, logs: Sequence[Log], groups: Sequence[str] | None = None, validate_on: Sequence[Log] = ()
) -> tuple[list[Log], list[str] | None, list[Log]]:
    """The runs, their groups and the validation runs less those wholly outside the envelope (a LogWarning each)."""
    checks = envelope_checks(model, [*logs, *validate_on])
    outside = _wholly_outside(checks)
    for name in outside:
        warnings.warn(left_out_message(checks[name]), LogWarning, stacklevel=3)
    kept = [i for i, log in enumerate(logs) if log.name not in outside]
    return (
        [logs[i] for i in kept],
        None if groups is None else [groups[i] for i in kept],
        [log for log in validate_on if log.name not in outside],
    )


def group_of(log: Log, rule: str) -> str:
    """The group of a run: its folder (``rule`` "folder"), or the part of its name the pattern ``rule`` matches."""
    if rule == "folder":
        return Path(log.source).parent.name
    match = re.search(rule, log.name)
    if match is None:
        raise GroupingError(f"the pattern {rule!r} does not match the run {log.name!r}")
    return match.group(1) if match.groups() else match.group(0)


def prepare_runs(
    logs: Sequence[Log],
    model: ShipModel,
    inside: bool = False,
    min_segment: float = MIN_SEGMENT,
    group_by: str | None = None,
    validate_on: Sequence[Log] = (),
) -> WorkbenchRuns:
    """Check the runs against the model's envelope, leave out those wholly outside, cut or group them as asked.

    Args:
        logs: the runs to fit and score.
        model: the model whose envelope the runs are checked against.
        inside: keep only the stretches of each run inside the envelope, each at least ``min_segment`` s long.
        group_by: leave out groups of runs together: ``"folder"`` or a regular expression on the names.
        validate_on: validation runs, checked and cut like ``logs``, never fitted.

    Raises:
        GroupingError: ``group_by`` does not match a run.
        LogError: no run (or segment) lies inside the envelope.
    """
    checks = envelope_checks(model, [*logs, *validate_on])
    outside = _wholly_outside(checks)
    messages = [left_out_message(checks[name]) for name in outside]
    runs = [log for log in logs if log.name not in outside]
    validation = [log for log in validate_on if log.name not in outside]
    groups = None
    if inside:
        length = sum(log.duration for log in runs)
        runs, groups = inside_logs(runs, model.envelope, model.length, min_segment)
        validation, _ = inside_logs(validation, model.envelope, model.length, min_segment)
        messages.append(
            f"--inside: {len(runs)} segments inside the envelope ({sum(log.duration for log in runs):.0f} s of "
            f"{length:.0f} s), each replayed from its measured state; a run's segments are left out together"
        )
    if group_by is not None:
        groups = [group_of(log, group_by) for log in runs]
        messages.append(
            f"--group-by {group_by}: {len(set(groups))} groups left out in turn: {', '.join(dict.fromkeys(groups))}"
        )
    if not runs:
        reasons = "; ".join(f"{name}: {checks[name].reasons()}" for name in outside[:3])
        reasons += f"; and {len(outside) - 3} more runs" if len(outside) > 3 else ""
        raise LogError(
            f"no run (or segment) lies inside the model's envelope{f' ({reasons})' if reasons else ''}; nothing to "
            "fit or score. The preset's envelope: section states its limits (in the ship's own L and U0, unit: U0 "
            "or U0/L, where they hold at any scale)"
        )
    return WorkbenchRuns(runs, groups, validation, checks, messages)


def inside_outside_errors(
    logs: Sequence[Log], replays: Sequence[Simulated], checks: Mapping[str, EnvelopeCheck]
) -> dict[str, list[RunErrors]]:
    """Per run, its RMS errors over the samples ``inside`` and ``outside`` the envelope; empty unless a run has
    samples outside (a run without a check, such as a segment cut inside, is skipped)."""
    pairs = [(log, replay, checks[log.name]) for log, replay in zip(logs, replays, strict=True) if log.name in checks]
    if not any(check.share > 0.0 for _, _, check in pairs):
        return {}
    inside, outside = split_errors(
        [log for log, _, _ in pairs], [replay for _, replay, _ in pairs], [check.outside for _, _, check in pairs]
    )
    return {"inside": inside, "outside": outside}


__all__ = [
    "GroupingError",
    "WorkbenchRuns",
    "envelope_checks",
    "group_of",
    "inside_outside_errors",
    "left_out_message",
    "prepare_runs",
    "screen_runs",
]
