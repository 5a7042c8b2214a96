"""Fitted presets: a fit written as a ship preset that the simulators, environments and autopilots sail.

``ship-env fit --preset FILE`` and ``ship-env improve --preset FILE`` write the fitted model in the
presets' own format (``configs/ships/*.yaml``, :func:`ship_env.model.load_ship`), so that
``ShipModel(FILE)``, ``gym.make(..., ship=FILE)`` and ``compare --ship FILE`` take it like a built-in:

- ``principal``: the starting preset's particulars, copied with their sources;
- ``service_conditions``: the operating point the fitted runs had (:mod:`ship_env.model.operating_point`):
  the median of their propeller rate, where the logs measure it, so that the preset sails by default
  at the rate its propeller terms (slipstream, asymmetry) were fitted at, not at 0 rps;
- ``effects``: the fitted model's effects on, all others off. A fitted number is written in its SI
  unit at full (``repr``) precision, so that it reads back bit for bit, with its standard error in the
  same unit (``std_error``; null where the data do not determine it) and a ``source`` naming the logs
  it was fitted to (file names and the first 12 hex digits of each file's SHA-256). The standard error
  is the larger of the Jacobian's (which holds white residuals only) and the jackknife's over the
  left-out runs (which holds what differs from run to run: correlated residuals, noisy inputs, effects
  the model lacks, but is itself rough with few runs): on synthetic zig-zags the Jacobian's alone is
  5 to 30 times too small. Every number not
  fitted keeps the starting preset's entry (value, unit, source) where the model holds the preset's
  value, and is written with the model's value otherwise;
- ``envelope``: the ranges the fitted runs covered (:mod:`.coverage`) as the validity limits the
  model knows -- the lowest speed, the largest drift angle, the largest rate of turn (the largest
  r* at the highest speed, |r| = r* U / L) and a propeller turning ahead only where no log reverses
  it. Where the starting preset states a narrower limit, its limit is kept and its source says so;
- ``fitted``: what it was fitted to: the starting preset, the logs (and the validation logs) with
  their hashes, the command, the effects and terms, the starting preset's effects kept to sail orders
  (``kept_from_preset``: its steering machine where every log records the actual rudder, which the
  fit takes as an input, :func:`~.terms.sailing_model`), what the fit took from the logs as inputs
  (``inputs``: the rudder, propeller rate, wind; the speed only as each run's service and initial
  speed, :mod:`.replay`) and what the logs left it unable to know (``not_identified``: the speed loss
  where no log measures the speed), the fitted steady current (``conditions``: a finding about the
  runs, an effect of the test site such as a towing tank's circulation, not a property of the ship: the
  simulators, environments and leaderboard never sail it unless asked, :func:`site_conditions`), the
  pooled held-out (and validation) RMS errors in deg, deg/s, m/s and m, the coverage, and the ship_env
  version.

Where the runs reach the hard-over rudder and the MMG standard's forces fitted by inverse dynamics predict their
manoeuvres better (:mod:`~ship_env.workbench.judging.dynamics_choice`), the preset also holds that model as its
``dynamics:`` block (:func:`with_dynamics`), which sails it by default; ``ship-env fit-mmg --preset`` writes a
preset sailed by its fit (:func:`mmg_preset_document`).

A replay of a fitted preset's runs (:func:`preset_replay_model`: ``compare --ship FILE`` and the other
workbench commands) sails in the steady current the fit found, as the fit's own replay did.
"""

from __future__ import annotations

import copy
import dataclasses
import hashlib
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
import yaml

import ship_env
from ship_env.model import EFFECTS, PRINCIPAL, Conditions, ShipModel
from ship_env.model.declarations import ENVELOPE_LIMITS, UNIT_CONVERSIONS, Parameter, ship_units
from ship_env.model.mmg_fitted import mmg_document
from ship_env.workbench.fitting.errors import CHANNEL_UNITS, RunErrors
from ship_env.workbench.fitting.fit import Estimate
from ship_env.workbench.fitting.replay import ReplayModel
from ship_env.workbench.fitting.terms import (
    CURRENT_TERMS,
    not_identified,
    propeller_rates,
    replay_inputs,
    reverses_propeller,
    sailing_model,
)
from ship_env.workbench.judging.coverage import COVERAGE_PERCENTILE, Coverage
from ship_env.workbench.judging.validation import CrossValidation
from ship_env.workbench.logs.logs import Log

if TYPE_CHECKING:
    from ship_env.workbench.fitting.inverse_dynamics import Identification

#: Hex digits of a log file's SHA-256 kept in a preset (48 bits: no two files of a campaign collide).
HASH_DIGITS = 12


@dataclass(frozen=True)
class LogFile:
    """A log a preset was fitted to: its file's name and the start of the file's SHA-256 (None: not a file)."""

    name: str
    sha256: str | None

    def words(self) -> str:
        return f"{self.name} (sha256 {self.sha256})" if self.sha256 else f"{self.name} (not read from a file)"


def log_file(log: Log) -> LogFile:
    """The file ``log`` was read from, with the first ``HASH_DIGITS`` hex digits of its content's SHA-256."""
    path = Path(log.source)
    if not log.source or not path.is_file():
        return LogFile(log.name, None)
    return LogFile(path.name, hashlib.sha256(path.read_bytes()).hexdigest()[:HASH_DIGITS])


def _number(value: float, unit: str, source: str, std_error: float | None = None, fitted: bool = False) -> dict:
    """A preset's entry for a number in its SI unit (no unit for a dimensionless one)."""
    entry: dict[str, Any] = {"value": float(value)}
    if unit != "-":
        entry["unit"] = unit
    if fitted:
        entry["std_error"] = std_error
    entry["source"] = source
    return entry


def _raw_preset(model: ShipModel) -> Mapping[str, Any]:
    """The starting preset's YAML as written (empty for a ship not read from a file)."""
    path = model.ship.path
    if path is None:
        return {}
    document = yaml.safe_load(path.read_text())
    return document if isinstance(document, Mapping) else {}


def _kept_entry(model: ShipModel, key: str, raw: object, parameter: Parameter, value: float) -> dict:
    """A number not fitted: the preset's entry where the model holds the preset's value, else the model's."""
    section, _, name = key.partition(".")
    held = model.ship.principal.get(name) if section == "principal" else model.ship.values.get(section, {}).get(name)
    if isinstance(raw, Mapping) and held == value:
        return dict(raw)
    source = model.ship.sources.get(key) if held == value else None
    if source is None:
        source = parameter.source or f"the starting model's value (set over {model.ship.name}'s)"
    return _number(value, parameter.unit, source)


def standard_errors(validation: CrossValidation) -> dict[str, float]:
    """Per fitted term, the larger of its Jacobian and jackknife standard errors (SI units; inf: not determined)."""
    jackknife = validation.jackknife_errors() if len(validation.folds) >= 2 else {}
    return {e.term.key: max(e.std_error, jackknife.get(e.term.key, 0.0)) for e in validation.fit.estimates}


def _fitted_entry(estimate: Estimate, std_error: float, logs_in_words: str) -> dict:
    """A fitted number with its standard error (None where infinite: not determined) and its source."""
    edge = "; at the edge of its fitted range" if estimate.at_bound else ""
    spread = std_error if math.isfinite(std_error) else None
    source = f"fitted by ship-env {ship_env.__version__} to {logs_in_words}{edge} (see 'fitted')"
    return _number(estimate.value, estimate.term.unit, source, spread, fitted=True)


def _principal_section(model: ShipModel, raw: Mapping[str, Any], fitted: Mapping[str, dict]) -> dict:
    entries = raw.get("principal") or {}
    section = {}
    for parameter in PRINCIPAL:
        key = parameter.name
        section[key] = fitted.get(key) or _kept_entry(
            model, f"principal.{key}", entries.get(key), parameter, model.parameter(key)
        )
    return section


def _effects_section(model: ShipModel, raw: Mapping[str, Any], fitted: Mapping[str, dict]) -> dict:
    """Every effect the preset or the model gives values for: on where the fitted model has it."""
    raw_effects = raw.get("effects") or {}
    section: dict[str, dict] = {}
    for effect_name, effect in EFFECTS.items():
        entries = raw_effects.get(effect_name) or {}
        written: dict[str, Any] = {"enabled": model.has(effect_name)}
        for parameter in effect.parameters:
            key = f"{effect_name}.{parameter.name}"
            if key in fitted:
                written[parameter.name] = fitted[key]
                continue
            try:
                value = model.parameter(key)
            except KeyError:  # an effect that is off and that the preset gives no value for
                continue
            written[parameter.name] = _kept_entry(model, key, entries.get(parameter.name), parameter, value)
        if effect_name in raw_effects or model.has(effect_name):
            section[effect_name] = written
    return section


@dataclass(frozen=True)
class DataLimit:
    """A validity limit the fitted data state: its value in the preset's unit, its unit and its source."""

    value: float | bool
    unit: str | None
    source: str

    def entry(self) -> dict:
        return {"value": self.value, **({"unit": self.unit} if self.unit else {}), "source": self.source}

    def words(self) -> str:
        """The limit as a source quotes it: '3.5 deg/s', or 'ahead and astern' for the propeller."""
        if isinstance(self.value, bool):
            return "ahead only" if self.value else "ahead and astern"
        return f"{self.value:.4g}" + (f" {self.unit}" if self.unit else "")


_DATA_RANGE = "the fitted data's range"


def data_limits(coverage: Coverage, logs: Sequence[Log], model: ShipModel) -> dict[str, DataLimit]:
    """The validity limits the fitted runs' coverage states (see the module docstring)."""
    ranges = coverage.ranges
    share = f"{coverage.percentile:g} % of its samples"
    limits: dict[str, DataLimit] = {}
    speed = ranges.get("speed")
    if speed is not None and speed.low is not None:
        limits["minimum_speed"] = DataLimit(speed.low, "m/s", f"{_DATA_RANGE}: the speed {share} sail at or above")
    if "drift" in ranges:
        limits["maximum_drift"] = DataLimit(
            math.degrees(ranges["drift"].high), "deg", f"{_DATA_RANGE}: the drift angle {share} stay within"
        )
    if "rate" in ranges:
        fastest = speed.high if speed is not None else model.service_speed
        rate = ranges["rate"].high * fastest / model.length
        limits["maximum_rate"] = DataLimit(
            math.degrees(rate),
            "deg/s",
            f"{_DATA_RANGE}: r* up to {ranges['rate'].high:.4g} ({share} stay within) at up to {fastest:.4g} m/s, "
            f"|r| = r* U / L with L {model.length:g} m",
        )
    if any(log.propeller_rate is not None for log in logs):
        astern = [log.name for log in logs if reverses_propeller(log)]
        limits["propeller_ahead_only"] = (
            DataLimit(False, None, f"{_DATA_RANGE}: the propeller turns astern in {', '.join(astern)}")
            if astern
            else DataLimit(True, None, f"{_DATA_RANGE}: no log turns its propeller astern")
        )
    return limits


def _narrower(key: str, preset: float | bool, data: float | bool) -> bool:
    """Whether the preset's limit is strictly narrower than the data's."""
    if key == "propeller_ahead_only":
        return bool(preset) and not data
    return preset > data if key.startswith("minimum") else preset < data


def _preset_limit(key: str, entry: object, units: Mapping[str, tuple[str, float]]) -> float | bool | None:
    """A preset's envelope limit in the unit the data's limits are written in (deg for angles); ``units``: the
    conversions the preset's ship knows (``declarations.ship_units``: its L and U0 too)."""
    if not isinstance(entry, Mapping):
        return None
    value = entry.get("value")
    if key == "propeller_ahead_only":
        return bool(value)
    parameter = {p.name: p for p in ENVELOPE_LIMITS}[key]
    si = parameter.convert(value, entry.get("unit"), f"envelope.{key}", units)
    return math.degrees(si) if parameter.unit.startswith("rad") else si


def envelope_section(
    raw: Mapping[str, Any],
    limits: Mapping[str, DataLimit],
    units: Mapping[str, tuple[str, float]] = UNIT_CONVERSIONS,
) -> dict:
    """The data's limits, but the preset's where it states a narrower one (its source then says so); ``units``: the
    conversions the preset's ship knows (``declarations.ship_units``, for limits written in its L and U0)."""
    preset_entries = dict(raw.get("envelope") or {})
    section: dict[str, Any] = {}
    for key in [*preset_entries, *(key for key in limits if key not in preset_entries)]:
        data = limits.get(key)
        preset = _preset_limit(key, preset_entries.get(key), units)
        if data is None:
            section[key] = dict(preset_entries[key])
        elif preset is not None and _narrower(key, preset, data.value):
            kept = dict(preset_entries[key])
            kept["source"] = f"{kept['source']} (kept: narrower than {_DATA_RANGE}, {data.words()})"
            section[key] = kept
        else:
            section[key] = data.entry()
    return section


def service_conditions_section(logs: Sequence[Log]) -> dict[str, Any]:
    """The fitted runs' operating point: the median of their propeller rate ({} where no log measures it)."""
    rates = propeller_rates(logs)
    if rates is None:
        return {}
    measured = [log for log in logs if log.propeller_rate is not None]
    low, median, high = np.percentile(rates, [100.0 - COVERAGE_PERCENTILE, 50.0, COVERAGE_PERCENTILE])
    source = (
        f"{_DATA_RANGE}: the median propeller rate of {len(measured)} fitted logs "
        f"({100.0 - COVERAGE_PERCENTILE:g} to {COVERAGE_PERCENTILE:g} % of their samples {low:.4g} to {high:.4g} rps)"
    )
    return {"propeller_rate": _number(float(median), "rps", source)}


def _errors(errors: RunErrors) -> dict[str, float]:
    return {name: float(value) for name, value in errors.in_display_units().items()}


def preset_document(
    validation: CrossValidation,
    logs: Sequence[Log],
    command: str,
    name: str,
    validation_logs: Sequence[Log] = (),
) -> dict[str, Any]:
    """A cross-validated fit as a ship preset (see the module docstring).

    Args:
        validation: the fit to all runs and its held-out (and validation) errors.
        logs: the runs it was fitted to (their files are hashed).
        command: the command line that produced it.
        name: the preset's name.
        validation_logs: the runs scored and never fitted (``--validate-on``).
    """
    fit = validation.fit
    model = fit.setup.model
    files = list(dict.fromkeys(log_file(log) for log in logs))  # a run cut into stretches is one file
    in_words = f"{len(files)} logs: " + ", ".join(file.words() for file in files)
    errors = standard_errors(validation)
    entries = {e.term.key: _fitted_entry(e, errors[e.term.key], in_words) for e in fit.estimates}
    fitted = {key: entry for key, entry in entries.items() if key not in CURRENT_TERMS}
    principal_keys = {parameter.name for parameter in PRINCIPAL}
    raw = _raw_preset(model)
    start = model.ship.path.name if model.ship.path is not None else model.ship.name
    limits = data_limits(validation.coverage, logs, model) if validation.coverage is not None else {}
    sailed = sailing_model(model, logs)  # the fitted model plus what it needs to sail orders (not fitted)
    kept = [name for name in sailed.effects if not model.has(name)]
    record: dict[str, Any] = {
        "version": ship_env.__version__,
        "command": command,
        "from_preset": start,
        "logs": [{"file": file.name, "sha256": file.sha256} for file in files],
        "effects": list(model.effects),
        "terms": [estimate.term.key for estimate in fit.estimates],
        **({"kept_from_preset": kept} if kept else {}),
        "inputs": replay_inputs(logs),
        "not_identified": not_identified(model, logs),
        "std_errors": "the larger of the Jacobian's and the jackknife's over the left-out runs",
        "error_units": dict(CHANNEL_UNITS),
        "held_out": _errors(validation.pooled),
        **({"jackknife": _jackknife_section(validation)} if len(validation.folds) >= 2 else {}),
    }
    if validation_logs:
        checked = dict.fromkeys(log_file(log) for log in validation_logs)
        record["validation_logs"] = [{"file": file.name, "sha256": file.sha256} for file in checked]
    if validation.pooled_validation is not None:
        record["validation"] = _errors(validation.pooled_validation)
    conditions = {key: entry for key, entry in entries.items() if key in CURRENT_TERMS}
    if conditions:
        record["conditions"] = conditions
    if validation.coverage is not None:
        record["coverage"] = validation.coverage.as_dict()
    service = service_conditions_section(logs)
    return {
        "name": name,
        "description": (
            f"{model.ship.name} ({start}) with {', '.join(model.effects)} fitted to {len(files)} logs by "
            f"ship-env {ship_env.__version__}{''.join(f', {name} kept from {start}' for name in kept)}; "
            f"held-out RMS heading error {record['held_out']['heading']:.3g} deg. "
            "Valid inside the envelope below: the ranges the fitted runs covered."
        ),
        "principal": _principal_section(model, raw, {k: v for k, v in fitted.items() if k in principal_keys}),
        **({"service_conditions": service} if service else {}),
        "envelope": envelope_section(raw, limits, ship_units(model.length, model.ship.principal["service_speed"])),
        "effects": _effects_section(sailed, raw, fitted),
        "fitted": record,
    }


def _jackknife_section(validation: CrossValidation) -> dict[str, Any]:
    """The fold fits' values of the ship's fitted terms (SI units; not the site's current), from which the fit's
    uncertainty in what the preset predicts is sailed (:mod:`ship_env.manoeuvres.uncertainty`)."""
    terms = [estimate.term.key for estimate in validation.fit.estimates if estimate.term.key not in CURRENT_TERMS]
    return {
        "about": "per fold, the terms fitted with its runs left out (the jackknife of the standard errors)",
        "left_out": [list(fold.left_out) for fold in validation.folds],
        "terms": terms,
        "values": [[float(fold.values[key]) for key in terms] for fold in validation.folds],
    }


def fitted_current(model: ShipModel) -> tuple[float, float]:
    """The steady current (m/s north, east) recorded in a fitted preset's ``fitted.conditions``; (0, 0) where none.

    Raises:
        ValueError: a recorded current term without a numeric ``value`` (naming the file and the field).
    """
    fitted = model.ship.fitted or {}
    conditions = fitted.get("conditions") or {}
    where = model.ship.path or model.ship.name
    if not isinstance(conditions, Mapping):
        raise ValueError(
            f"{where}: fitted.conditions: expected a mapping of {' and '.join(CURRENT_TERMS)}, got {conditions!r}"
        )
    current = []
    for key in CURRENT_TERMS:
        entry = conditions.get(key, {"value": 0.0})
        value = entry.get("value") if isinstance(entry, Mapping) else None
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
            raise ValueError(
                f"{where}: fitted.conditions.{key}: expected a mapping with a finite 'value' in m/s, got {entry!r}"
            )
        current.append(float(value))
    return current[0], current[1]


def preset_replay_model(model: ShipModel) -> ReplayModel:
    """``model`` with the steady current its preset was fitted in (used where ``model`` has the ``current`` effect):
    a replay of the preset's own runs (``compare --ship``) keeps the current those runs had."""
    return ReplayModel(model, *fitted_current(model))


def site_conditions(model: ShipModel, conditions: Conditions | None = None) -> Conditions:
    """``conditions`` (default: calm, at the preset's service conditions) with the steady current the preset's
    runs were found in (``fitted.conditions``): how one asks to sail a fitted preset at its test site, e.g.
    ``Simulator(model).reset(conditions=site_conditions(model))``. Nothing else sails that current.

    Raises:
        ValueError: a recorded current that is not a number (:func:`fitted_current`).
    """
    north, east = fitted_current(model)
    return dataclasses.replace(
        conditions or Conditions(),
        current_speed=math.hypot(north, east),
        current_direction=math.atan2(east, north) % (2.0 * math.pi),
    )


def fitted_mmg_document(identified: Identification, command: str, from_preset: str) -> dict[str, Any]:
    """The fitted MMG model as ``ship-env fit-mmg`` writes it (:func:`~ship_env.model.mmg_fitted.mmg_document`): each
    coefficient with its jackknife standard error, after the command, the preset it started from, the runs and the
    share of each force it explains."""
    surge, sway, yaw = identified.fitted.determination
    about = {
        "command": command,
        "from_preset": from_preset,
        "runs": list(identified.runs),
        "determination": {"surge": surge, "sway": sway, "yaw": yaw},
    }
    return mmg_document(identified.record, identified.standard_errors, about)


def with_dynamics(
    document: Mapping[str, Any], identified: Identification, command: str, choice: Mapping[str, Any]
) -> dict[str, Any]:
    """A fitted preset's ``document`` sailed by the fitted MMG model ``identified`` (its ``dynamics:`` block,
    :mod:`ship_env.model.ship`), with the ``choice`` that made it so in its ``fitted`` block (``dynamics``)."""
    fitted = document.get("fitted") or {}
    written = {**document, "fitted": {**fitted, "dynamics": dict(choice)}}
    written["dynamics"] = fitted_mmg_document(identified, command, str(fitted.get("from_preset", "")))
    written["description"] = (
        f"{document.get('description', '')} Sailed by the MMG standard's forces fitted to the same logs by inverse "
        "dynamics (dynamics: below), which predict their manoeuvres better (fitted.dynamics)."
    ).strip()
    return written


def mmg_preset_document(model: ShipModel, identified: Identification, command: str, name: str) -> dict[str, Any]:
    """``model``'s preset sailed by the fitted MMG model ``identified`` (``ship-env fit-mmg --preset``): its particulars
    and effects kept (what the bridge knows of the ship, what the autopilots are designed from), its service speed
    and propeller rate the runs', the model as its ``dynamics:`` block."""
    start = model.ship.path.name if model.ship.path is not None else model.ship.name
    raw = copy.deepcopy(dict(model.ship.document or _raw_preset(model)))
    record = identified.record
    runs = (
        f"{len(identified.runs)} runs ({', '.join(identified.runs[:3])}{', ...' if len(identified.runs) > 3 else ''})"
    )
    principal = dict(raw.get("principal") or {})
    principal["service_speed"] = _number(
        record.service_speed, "m/s", f"the straight-course speed of the {runs} the MMG model was fitted to"
    )
    return {
        **raw,
        "name": name,
        "description": (
            f"{model.ship.name} ({start}) sailed by the MMG standard's forces fitted to {runs} by inverse dynamics "
            f"(ship-env {ship_env.__version__}, dynamics: below); its particulars and effects are {start}'s, for the "
            "bridge's scales and the classic autopilots' design."
        ),
        "principal": principal,
        "service_conditions": {
            "propeller_rate": _number(record.propeller_rate, "rps", f"the median propeller rate of the {runs}")
        },
        "dynamics": fitted_mmg_document(identified, command, start),
    }


def write_preset(document: Mapping[str, Any], path: Path) -> Path:
    """Write a preset as YAML, floats at ``repr`` precision (the caller has claimed ``path``)."""
    path.write_text(yaml.safe_dump(dict(document), sort_keys=False, width=120, allow_unicode=True))
    return path


__all__ = [
    "HASH_DIGITS",
    "DataLimit",
    "LogFile",
    "data_limits",
    "envelope_section",
    "fitted_current",
    "fitted_mmg_document",
    "log_file",
    "mmg_preset_document",
    "preset_document",
    "preset_replay_model",
    "service_conditions_section",
    "site_conditions",
    "standard_errors",
    "with_dynamics",
    "write_preset",
]
