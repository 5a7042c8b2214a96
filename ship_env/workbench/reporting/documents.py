"""The workbench's JSON documents: a fit (``fit --json``), an error ladder (``improve --json``), and a
fitted model read back (``--parameters``) onto the hull it was fitted on.

A fit's document holds the ship's hull, the effects, the fitted values with their standard errors
and units, what the fit took from the logs as inputs (``inputs``) and what they left it unable to
know (``not_identified``, :mod:`.terms`), the error scales, each run's envelope check and the
in-sample, held-out and validation errors (deg, deg/s, m/s, m). A ladder's document is its final
model's fit document plus ``ladder`` (per
rung: the effects added, the effects, the held-out and validation errors) and ``stopped`` (why the
climb stopped); both are read back by :func:`read_fitted_model`.

The **hull** (``hull``) is the preset's name (or the YAML file's path, ``yaml``), its principal
particulars as the model holds them (SI units) and a hash of them. A fitted model is loaded onto
that hull: by default the recorded preset or YAML file; a ship given instead must have the same
particulars (else :class:`DocumentError` names the file, both hulls and the particular that
differs). A document from an older version records no hull: it is loaded onto the ship given, or
else the preset its ``ship`` names, with a note that the particulars were not checked.
"""

from __future__ import annotations

import hashlib
import json
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from ship_env.model import PRINCIPAL, ShipModel, list_ships, load_ship
from ship_env.paths import config_dir
from ship_env.workbench.deciding.improve import Ladder
from ship_env.workbench.fitting.envelope import EnvelopeCheck
from ship_env.workbench.fitting.errors import CHANNEL_UNITS, ErrorScales, RunErrors
from ship_env.workbench.fitting.replay import ReplayModel
from ship_env.workbench.fitting.terms import not_identified, replay_inputs, with_values
from ship_env.workbench.judging.validation import CrossValidation
from ship_env.workbench.logs.logs import Log


class DocumentError(ValueError):
    """A fit's document that cannot be read, or that was fitted on another hull."""


def hull_record(model: ShipModel) -> dict[str, Any]:
    """The model's hull: its preset (or YAML file), principal particulars (SI units) and their hash."""
    principal = {parameter.name: model.parameter(parameter.name) for parameter in PRINCIPAL}
    path = model.ship.path
    is_preset = path is not None and path.parent.resolve() == (config_dir() / "ships").resolve()
    return {
        "preset": path.stem if is_preset and path is not None else None,
        "yaml": None if is_preset or path is None else str(path.resolve()),
        "name": model.ship.name,
        "principal": principal,
        "hash": hull_hash(principal),
    }


def hull_hash(principal: Mapping[str, float]) -> str:
    """A short hash of the principal particulars (SHA-256 of their sorted JSON, 16 hex digits)."""
    return hashlib.sha256(json.dumps(dict(principal), sort_keys=True).encode()).hexdigest()[:16]


def _errors(errors: RunErrors, scales: ErrorScales) -> dict[str, Any]:
    return {
        **errors.in_display_units(),
        "score": errors.score(scales),
        "samples": errors.samples,
        "diverged_runs": errors.diverged,
        "diverged_at_s": errors.diverged_at if math.isfinite(errors.diverged_at) else None,
    }


def fit_document(
    validation: CrossValidation,
    scales: ErrorScales,
    checks: Mapping[str, EnvelopeCheck] | None = None,
    logs: Sequence[Log] = (),
) -> dict[str, Any]:
    """A cross-validated fit to ``logs`` as a JSON document (see the module docstring)."""
    fitted = validation.fit
    model = fitted.setup.model
    document: dict[str, Any] = {
        "ship": model.ship.name,
        "hull": hull_record(model),
        "effects": list(model.effects),
        "values": fitted.values(),
        # An infinite standard error (a term the data do not determine) is null: JSON has no infinity.
        "std_errors": {e.term.key: e.std_error if math.isfinite(e.std_error) else None for e in fitted.estimates},
        "units": {e.term.key: e.term.unit for e in fitted.estimates},
        "inputs": replay_inputs(logs),
        "not_identified": not_identified(model, logs),
        "error_units": dict(CHANNEL_UNITS),
        "error_scales": {
            "heading": math.degrees(scales.heading),
            "rate_of_turn": math.degrees(scales.rate_of_turn),
            "speed": scales.speed_error,
            "track": scales.position,
            "in_words": scales.describe(),
        },
        "envelope": {name: {"outside": check.share, "why": check.reasons()} for name, check in (checks or {}).items()},
        "in_sample": {e.name: _errors(e, scales) for e in (*fitted.errors, fitted.pooled)},
        "held_out": {e.name: _errors(e, scales) for e in (*validation.held_out, validation.pooled)},
    }
    if validation.validation and validation.pooled_validation is not None:
        document["validation"] = {
            e.name: _errors(e, scales) for e in (*validation.validation, validation.pooled_validation)
        }
    if validation.coverage is not None:
        document["coverage"] = validation.coverage.as_dict()
        checks_beyond = validation.validation_checks()
        document["validation_coverage"] = {c.run: {"extrapolated": c.share, "why": c.reasons()} for c in checks_beyond}
    return document


def ladder_document(
    ladder: Ladder, checks: Mapping[str, EnvelopeCheck] | None = None, logs: Sequence[Log] = ()
) -> dict[str, Any]:
    """An error ladder on ``logs`` as a JSON document: its final model's fit document, each rung and why it
    stopped."""
    scales = ladder.scales
    rungs = []
    for rung in ladder.rungs:
        entry: dict[str, Any] = {
            "added": list(rung.added),
            "effects": list(rung.effects),
            "held_out": _errors(rung.validation.pooled, scales),
        }
        if rung.validation.pooled_validation is not None:
            entry["validation"] = _errors(rung.validation.pooled_validation, scales)
        rungs.append(entry)
    return {**fit_document(ladder.final, scales, checks, logs), "ladder": rungs, "stopped": ladder.stopped}


def write_document(document: Mapping[str, Any], path: Path) -> Path:
    """Write a document as indented JSON (the caller has claimed ``path``, :func:`~.outputs.claim_file`)."""
    path.write_text(json.dumps(document, indent=2) + "\n")
    return path


@dataclass(frozen=True)
class FittedModel:
    """A fitted model read back: the model on its hull, and a note where the hull could not be checked."""

    setup: ReplayModel
    note: str = ""


def _read(path: Path) -> dict[str, Any]:
    try:
        document = json.loads(path.read_text())
    except OSError as error:
        raise DocumentError(f"cannot read {str(path)!r}: {error.strerror}") from None
    except ValueError as error:
        raise DocumentError(f"{path} is not JSON: {error}") from None
    if not isinstance(document, dict) or not {"effects", "values"} <= set(document):
        raise DocumentError(f"{path} is not a fit written by 'ship-env fit --json' or 'improve --json'")
    return document


def _recorded_ship(path: Path, hull: Mapping[str, Any]) -> str:
    """The preset name or YAML path a document's hull was recorded from (it must still be there)."""
    yaml, preset = hull.get("yaml"), hull.get("preset")
    if yaml and Path(yaml).is_file():
        return str(yaml)
    if preset and preset in list_ships():
        return str(preset)
    where = f"the YAML file {yaml!r}" if yaml else f"the preset {preset!r}"
    raise DocumentError(
        f"{path} was fitted on {hull.get('name')!r} ({where}), which is not found here; "
        "pass --ship with that ship's preset or YAML file"
    )


def _describe(name: str, principal: Mapping[str, float]) -> str:
    return f"{name!r} (" + ", ".join(f"{key} {value:g}" for key, value in principal.items()) + ")"


def _check_hull(path: Path, hull: Mapping[str, Any], model: ShipModel) -> None:
    """A DocumentError naming the file, both hulls and the first particular that differs, if one does."""
    recorded = hull.get("principal")
    if not isinstance(recorded, Mapping):
        raise DocumentError(f"{path}: 'hull' holds no 'principal' particulars")
    here = {parameter.name: model.parameter(parameter.name) for parameter in PRINCIPAL}
    for key, value in recorded.items():
        if key in here and not math.isclose(float(value), here[key], rel_tol=1e-9, abs_tol=1e-12):
            raise DocumentError(
                f"{path} was fitted on the hull {_describe(str(hull.get('name')), recorded)}, not on "
                f"{_describe(model.ship.name, here)}: their {key} differs ({float(value):g} against {here[key]:g}); "
                "leave out --ship to use the fit's own hull"
            )


def read_fitted_model(path: Path, ship: str | Path | None = None, added: tuple[str, ...] = ()) -> FittedModel:
    """The fitted model of a fit's or ladder's document, on the hull it was fitted on.

    Args:
        path: the document.
        ship: a preset name or YAML file to load it onto instead; it must have the recorded particulars.
        added: effects to add to the document's (at their preset values).

    Raises:
        DocumentError: unreadable, not a fit, its hull not found, or ``ship`` another hull.
    """
    document = _read(path)
    hull = document.get("hull")
    note = ""
    if isinstance(hull, Mapping):
        name = _recorded_ship(path, hull) if ship is None else ship
    else:
        recorded = document.get("ship")
        if ship is None and (not isinstance(recorded, str) or recorded not in list_ships()):
            raise DocumentError(f"{path} records no hull nor a known preset ({recorded!r}); pass --ship")
        name = ship if ship is not None else str(recorded)
        note = f"{path} records no hull (written by an older version): loaded onto {name}, its particulars unchecked"
    try:
        model = ShipModel(load_ship(name), [*document["effects"], *added])
        if isinstance(hull, Mapping):
            _check_hull(path, hull, model)
        return FittedModel(with_values(ReplayModel(model), document["values"]), note)
    except (KeyError, TypeError) as error:
        raise DocumentError(f"{path} is not a fit written by 'ship-env fit --json': {error}") from None
    except DocumentError:
        raise
    except ValueError as error:
        raise DocumentError(f"{path}: {error}") from None


__all__ = [
    "DocumentError",
    "FittedModel",
    "fit_document",
    "hull_hash",
    "hull_record",
    "ladder_document",
    "read_fitted_model",
    "write_document",
]
