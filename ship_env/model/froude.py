"""Froude scaling: a ship preset at another length that moves as the original does, in ship lengths.

Two geometrically similar ships sailed at the same Froude number Fn = U / sqrt(g L) make the same
waves and, where viscous forces do not matter, move alike: with the scale lambda = L_new / L_old
(ITTC Recommended Procedure 7.5-02-06-01, free-running model tests; Froude 1874), every quantity
changes by a power of lambda that its dimensions give, with water of the same density and the
same gravity:

    length  m      x lambda            time   s      x lambda^1/2
    speed   m/s    x lambda^1/2        rate   rad/s, rps  x lambda^-1/2
    area    m^2    x lambda^2          acceleration  rad/s^2  x lambda^-1
    mass    kg     x lambda^3          angle  rad, deg and anything dimensionless: kept

so a unit m^a s^b kg^c scales by lambda^(a + b/2 + 3c). The model's non-dimensional coefficients
(K*, tau*, the alphas of H(r*), the gammas of H_v(r*), c_s of the slipstream per (n D)^2, the wind
and wave coefficients made non-dimensional by the ship's own L, T and speed) are Froude-invariant
and kept. Every parameter, principal particular, envelope limit and fitted record is scaled by the
rule of its declared SI unit (``Parameter.unit``); a unit the rule cannot read (a temperature, a
currency) is refused, naming the parameter: its scaling is not known. The rule follows from the
dimensions alone, so it holds for a dimensional coefficient only where the model's equation is
dimensionally homogeneous in it (checked in each effect: ``wind_moment``'s N_w' in rad/m^2 scales
by lambda^-2, which is 1/2 rho_air a_n S L / I_zz' with S L ~ lambda^3 and I_zz' ~ lambda^5).

What Froude scaling leaves out is what a scaled fit cannot know: the hull's friction (Reynolds
number), and so a model-scale fit's rudder and propeller forces, carry the model's scale effects
(ITTC 7.5-02-06-01: a full-scale prediction corrects them); the wind is scaled as the ship is (a
wind of the same ratio to the ship's speed), and so are the sea state and a tidal period.

``scale_document`` rewrites a preset's YAML, each number's ``source`` saying from which preset and
by what factor, and appends the scaling to the preset's ``scaled:`` record; ``scaled_model`` (and
``ShipModel.scaled``) builds the scaled model, ``scaled_conditions`` the conditions the scaled ship
sails in, and ``ship-env scale`` writes the scaled preset.
"""

from __future__ import annotations

import argparse
import copy
import dataclasses
import math
import re
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import yaml

from ship_env.command_line import Command, UsageError, number, ship_preset
from ship_env.model.declarations import ENVELOPE_LIMITS, SHIP_RELATIVE_UNITS, UNIT_CONVERSIONS, Parameter
from ship_env.model.effects import EFFECTS
from ship_env.model.ship import PRINCIPAL, ShipModel, load_ship, ship_from_document
from ship_env.model.simulator import Conditions

#: The power of lambda each base unit scales by (a unit is a product of these, see the module docstring).
BASE_UNIT_EXPONENTS: dict[str, float] = {"m": 1.0, "s": 0.5, "kg": 3.0, "rad": 0.0, "rps": -0.5}

#: The SI unit of each condition a ship sails in (``Conditions``' fields, then the derived ones of ``state``).
CONDITION_UNITS: dict[str, str] = {
    "service_speed": "m/s",
    "propeller_rate": "rps",
    "current_speed": "m/s",
    "current_direction": "rad",
    "wind_speed": "m/s",
    "wind_direction": "rad",
    "wave_height": "m",
    "wave_period": "s",
    "wave_direction": "rad",
    "yaw_gain_factor": "-",
    "yaw_time_constant_factor": "-",
    "yaw_gain_change": "-",
    "yaw_time_constant_change": "-",
    "current_north": "m/s",
    "current_east": "m/s",
    "wind_north": "m/s",
    "wind_east": "m/s",
}

#: The SI unit of each quantity of a fitted preset's coverage (``workbench.judging.coverage.QUANTITIES``).
COVERAGE_UNITS: dict[str, str] = {"speed": "m/s", "rate": "-", "drift": "rad", "rudder": "rad", "propeller": "rps"}

#: Numbers of a ``fitted:`` record that are counts or shares, kept as they are.
DIMENSIONLESS_RECORD_KEYS = frozenset({"percentile", "effects_score", "mmg_score", "in_sample_score"})

#: The units of a fitted MMG model's numbers (a preset's ``dynamics:`` block, :mod:`ship_env.model.mmg_fitted`) that
#: are not non-dimensional: the rigid body's and the sailing's. Its force coefficients are non-dimensional (X' =
#: X / (1/2 rho L d U^2)...) and kept.
MMG_UNITS: dict[str, dict[str, str]] = {
    "rigid_body": {
        "length": "m",
        "breadth": "m",
        "draught": "m",
        "centre_of_gravity": "m",
        "block_coefficient": "-",
        "gyration": "-",
    },
    "sailing": {
        "rudder_rate_deg_s": "deg/s",
        "rudder_limit_deg": "deg",
        "propeller_rate": "rps",
        "service_speed": "m/s",
    },
}

_FACTOR = re.compile(r"^([A-Za-z]+|1)(?:\^(-?\d+(?:\.\d+)?))?$")


class ScalingError(ValueError):
    """A number whose Froude scaling is not known (its unit, or where it stands in a preset)."""


def unit_exponent(unit: str, where: str) -> float:
    """The power of lambda a quantity in ``unit`` scales by (``m/s``: 0.5); ScalingError naming ``where`` if unknown.

    A unit is ``-`` (dimensionless), one of ``SHIP_RELATIVE_UNITS`` (``U0``, ``U0/L``: kept), or factors separated
    by ``*`` with at most one ``/`` (``rad/m^2``, ``kg*m/s^2``), each a base unit (``BASE_UNIT_EXPONENTS``), ``1``,
    or one of ``UNIT_CONVERSIONS`` (``deg``, ``kn``, ``rpm``, ...: scaled as the SI unit they convert to), with an
    optional ``^power``.
    """
    text = unit.strip()
    if text == "-" or text in SHIP_RELATIVE_UNITS:  # a fraction of the ship's own L or U0 scales with the ship
        return 0.0
    if text in UNIT_CONVERSIONS:
        return unit_exponent(UNIT_CONVERSIONS[text][0], where)
    numerator, slash, denominator = text.partition("/")
    if "/" in denominator or not numerator.strip() or (slash and not denominator.strip()):
        raise ScalingError(f"{where}: unit {unit!r}: expected factors with at most one '/'")
    exponent = 0.0
    for sign, part in ((1.0, numerator), (-1.0, denominator)):
        for factor in filter(None, (piece.strip() for piece in part.split("*"))):
            match = _FACTOR.match(factor)
            base = match.group(1) if match else factor
            if match is None or (base != "1" and base not in BASE_UNIT_EXPONENTS and base not in UNIT_CONVERSIONS):
                known = ", ".join([*BASE_UNIT_EXPONENTS, *UNIT_CONVERSIONS])
                raise ScalingError(
                    f"{where}: unit {unit!r}: the Froude scaling of {factor!r} is not known (known units: {known}, "
                    "'-' for a dimensionless number); scale this number by hand"
                )
            power = float(match.group(2) or 1.0)
            inner = 0.0 if base == "1" else unit_exponent(base, where) if base in UNIT_CONVERSIONS else None
            exponent += sign * power * (BASE_UNIT_EXPONENTS[base] if inner is None else inner)
    return exponent


def froude_factor(scale: float, exponent: float) -> float:
    """lambda^exponent, exactly 1 for a Froude-invariant quantity."""
    return 1.0 if exponent == 0.0 else scale**exponent


def check_scale(scale: float, where: str = "scale") -> float:
    """``scale`` if it is a positive finite ratio of lengths; ValueError naming ``where`` otherwise."""
    if isinstance(scale, bool) or not isinstance(scale, (int, float)) or not (math.isfinite(scale) and scale > 0.0):
        raise ValueError(f"{where}: expected a positive finite ratio of lengths lambda, got {scale!r}")
    return float(scale)


def _words(exponent: float) -> str:
    return "kept: Froude-invariant" if exponent == 0.0 else f"x lambda^{exponent:g}"


@dataclasses.dataclass
class _Rewriter:
    """Rewrites a preset's document for one scaling, counting what it scaled and kept."""

    scale: float
    origin: str
    scaled: int = 0
    kept: int = 0

    def note(self, exponent: float) -> str:
        return f"Froude-scaled from {self.origin} by lambda = {self.scale:.10g} ({_words(exponent)})"

    def entry(self, entry: object, exponent: float, where: str) -> object:
        """A preset's number (``{value, unit, source, std_error}``) scaled by lambda^exponent, its source saying so."""
        if not isinstance(entry, Mapping) or "value" not in entry:
            raise ScalingError(f"{where}: expected a mapping with 'value' (a preset's number), got {entry!r}")
        written = dict(entry)
        value = entry["value"]
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            if exponent != 0.0:
                raise ScalingError(f"{where}: value {value!r} is not a number and cannot be scaled")
        elif exponent != 0.0:
            factor = froude_factor(self.scale, exponent)
            written["value"] = float(value) * factor
            error = entry.get("std_error")
            if isinstance(error, (int, float)) and not isinstance(error, bool):
                written["std_error"] = float(error) * factor
        self.scaled += exponent != 0.0
        self.kept += exponent == 0.0
        source = entry.get("source")
        written["source"] = f"{self.note(exponent)}: {source}" if source else self.note(exponent)
        return written

    def declared(self, entries: object, declarations: Mapping[str, Parameter], where: str) -> dict:
        """A section of numbers each declared by a parameter (principal, envelope, an effect's)."""
        if not isinstance(entries, Mapping):
            raise ScalingError(f"{where}: expected a mapping, got {entries!r}")
        section: dict[str, Any] = {}
        for key, entry in entries.items():
            label = f"{where}.{key}"
            if key == "enabled" and where.startswith("effects."):
                section[key] = entry
            elif key == "propeller_ahead_only" and where == "envelope":
                section[key] = self.entry(entry, 0.0, label) if isinstance(entry, Mapping) else entry
            elif key in declarations:
                parameter = declarations[key]
                written_in = entry.get("unit") if isinstance(entry, Mapping) else None
                unit = written_in if written_in in SHIP_RELATIVE_UNITS else parameter.unit  # relative: kept
                exponent = unit_exponent(unit, f"{label} ({parameter.description})")
                if parameter.integer and exponent != 0.0:
                    raise ScalingError(f"{label}: a whole number in {parameter.unit!r} cannot be scaled")
                section[key] = self.entry(entry, exponent, label)
            else:
                raise ScalingError(f"{label}: unknown field; its Froude scaling is not known")
        return section

    def record(self, node: object, where: str, units: Mapping[str, str] | None = None) -> object:
        """A record's numbers scaled by what they are (``fitted:``, or a section this module does not know):
        an entry (``{value, unit, source}``) by its unit, or by the condition its key names (``propeller_rate``),
        else as dimensionless (presets write a dimensionless number without a unit); a plain number keyed by a
        condition by the condition's unit; a coverage range by its quantity; a held-out error by its channel's
        unit (``error_units``); any other number is refused, naming where it stands."""
        key = where.rpartition(".")[2]
        if isinstance(node, Mapping) and "value" in node:
            unit = node.get("unit") or (units or {}).get(key) or CONDITION_UNITS.get(key, "-")
            return self.entry(node, unit_exponent(str(unit), where), where)
        if isinstance(node, Mapping):
            if key == "jackknife" and isinstance(node.get("terms"), list) and isinstance(node.get("values"), list):
                return self.jackknife(node, where)
            if key == "coverage" and isinstance(node.get("ranges"), Mapping):
                ranges = node["ranges"]
                unknown = [quantity for quantity in ranges if quantity not in COVERAGE_UNITS]
                if unknown:
                    raise ScalingError(f"{where}.ranges: the Froude scaling of {unknown[0]!r} is not known")
                return {
                    **{name: self.record(value, f"{where}.{name}") for name, value in node.items() if name != "ranges"},
                    "ranges": {
                        q: self.record(r, f"{where}.ranges.{q}", _both(COVERAGE_UNITS[q])) for q, r in ranges.items()
                    },
                }
            error_units = node.get("error_units") if isinstance(node.get("error_units"), Mapping) else None
            return {
                name: self.record(
                    value, f"{where}.{name}", error_units if name in ("held_out", "validation") else units
                )
                for name, value in node.items()
            }
        if isinstance(node, list):
            return [self.record(item, f"{where}[{index}]", units) for index, item in enumerate(node)]
        if node is None or isinstance(node, (str, bool)):
            return node
        if isinstance(node, (int, float)):
            unit = (units or {}).get(key) or CONDITION_UNITS.get(key)
            if unit is None and key in DIMENSIONLESS_RECORD_KEYS:
                unit = "-"
            if unit is None:
                raise ScalingError(
                    f"{where}: the Froude scaling of {node!r} is not known (no unit, and {key!r} names no condition)"
                )
            exponent = unit_exponent(unit, where)
            self.scaled += exponent != 0.0
            self.kept += exponent == 0.0
            return node if exponent == 0.0 else float(node) * froude_factor(self.scale, exponent)
        raise ScalingError(f"{where}: cannot scale {node!r} ({type(node).__name__})")

    def jackknife(self, node: Mapping[str, Any], where: str) -> dict[str, Any]:
        """A fitted preset's jackknife (the fold fits' values of its terms, SI units): each term's values scaled by
        its parameter's unit (``steering_machine.rudder_rate``: rad/s; a principal particular's own)."""
        exponents = []
        for term in node["terms"]:
            effect, _, name = str(term).rpartition(".")
            if not effect:
                declared = {parameter.name: parameter for parameter in PRINCIPAL}
            else:
                declared = {p.name: p for p in EFFECTS[effect].parameters} if effect in EFFECTS else {}
            if name not in declared:
                raise ScalingError(
                    f"{where}.terms: {term!r}: no parameter of that name; its Froude scaling is not known"
                )
            exponents.append(unit_exponent(declared[name].unit, f"{where}.terms: {term}"))
        values = []
        for index, fold in enumerate(node["values"]):
            if not isinstance(fold, list) or len(fold) != len(exponents):
                raise ScalingError(f"{where}.values[{index}]: expected {len(exponents)} numbers, one per term")
            values.append([float(v) * froude_factor(self.scale, e) for v, e in zip(fold, exponents, strict=True)])
        self.scaled += sum(exponent != 0.0 for exponent in exponents)
        return {**copy.deepcopy(dict(node)), "values": values}

    def dynamics(self, node: object, where: str) -> dict[str, Any]:
        """A preset's fitted MMG model (``dynamics:``): the rigid body's lengths, the steering machine's rate, the
        propeller rate, the service speed and the coverage's speeds scaled (:data:`MMG_UNITS`,
        :data:`COVERAGE_UNITS`); its non-dimensional force coefficients and their folds kept."""
        if not isinstance(node, Mapping):
            raise ScalingError(f"{where}: expected a mapping (a fitted MMG model), got {node!r}")
        written = copy.deepcopy(dict(node))
        for section, units in MMG_UNITS.items():
            values = node.get(section)
            if not isinstance(values, Mapping):
                raise ScalingError(f"{where}.{section}: expected a mapping, got {values!r}")
            written[section] = {
                name: self.record(value, f"{where}.{section}.{name}", units) for name, value in values.items()
            }
        coverage = node.get("coverage") or {}
        unknown = [quantity for quantity in coverage if quantity not in COVERAGE_UNITS]
        if unknown:
            raise ScalingError(f"{where}.coverage: the Froude scaling of {unknown[0]!r} is not known")
        written["coverage"] = {
            q: self.record(r, f"{where}.coverage.{q}", _both(COVERAGE_UNITS[q])) for q, r in coverage.items()
        }
        return written


def _both(unit: str) -> dict[str, str]:
    return {"low": unit, "high": unit}


def scale_document(document: Mapping[str, Any], scale: float, origin: str, name: str | None = None) -> dict[str, Any]:
    """A preset's YAML document Froude-scaled by ``scale`` (lambda = new length / old length).

    Args:
        document: the preset as read (``Ship.document``); not changed.
        scale: lambda.
        origin: the preset it comes from, as each source names it (``kvlcc2.yaml``).
        name: the scaled preset's name (default: the original's with ``_scaled``).

    Returns:
        The scaled document: principal, envelope and effects scaled by their declared units, each
        number's ``source`` saying from which preset and by what factor; ``fitted:`` and any other
        record scaled as :meth:`_Rewriter.record` says; ``scaled:`` with this scaling appended.

    Raises:
        ScalingError: a number whose scaling is not known, naming it.
    """
    scale = check_scale(scale)
    rewriter = _Rewriter(scale, origin)
    principal = {parameter.name: parameter for parameter in PRINCIPAL}
    old_length = document.get("principal", {}).get("length", {}).get("value")
    written: dict[str, Any] = {}
    for key, section in document.items():
        if key == "name":
            written[key] = name or f"{section}_scaled"
        elif key == "description":
            written[key] = section
        elif key == "principal":
            written[key] = rewriter.declared(section, principal, key)
        elif key == "envelope":
            written[key] = rewriter.declared(section, {p.name: p for p in ENVELOPE_LIMITS}, key)
        elif key == "effects":
            if not isinstance(section, Mapping):
                raise ScalingError(f"effects: expected a mapping, got {section!r}")
            unknown = [effect for effect in section if effect not in EFFECTS]
            if unknown:
                raise ScalingError(f"effects.{unknown[0]}: unknown effect; its Froude scaling is not known")
            written[key] = {
                effect: rewriter.declared(
                    entries or {}, {p.name: p for p in EFFECTS[effect].parameters}, f"effects.{effect}"
                )
                for effect, entries in section.items()
            }
        elif key == "scaled":
            written[key] = copy.deepcopy(section)
        elif key == "dynamics":
            written[key] = None if section is None else rewriter.dynamics(section, key)
        else:
            written[key] = rewriter.record(section, key)
    if name is not None or "name" not in written:
        written["name"] = name or f"{origin.rsplit('.', 1)[0]}_scaled"
    new_length = written.get("principal", {}).get("length", {}).get("value")
    step = {
        "from_preset": origin,
        "factor": scale,
        "from_length": old_length,
        "to_length": new_length,
        "rule": "Froude: lengths x lambda, times and speeds x lambda^1/2, rates x lambda^-1/2, "
        "non-dimensional coefficients kept (ship_env.model.froude)",
        "numbers_scaled": rewriter.scaled,
        "numbers_kept": rewriter.kept,
    }
    written["scaled"] = [*(written.get("scaled") or []), step]
    description = str(written.get("description", "")).strip()
    written["description"] = (
        f"{description} Froude-scaled from {origin} (L = {old_length:g} m) by lambda = {scale:.10g} "
        f"to L = {new_length:g} m."
    ).strip()
    return written


def ratio(model: ShipModel, scale: float | None = None, length: float | None = None) -> float:
    """lambda from exactly one of ``scale`` and the new ``length`` (m); ValueError naming the argument otherwise."""
    if (scale is None) == (length is None):
        raise ValueError("scaled: give either the factor lambda or the new length, not both and not neither")
    if length is not None:
        return check_scale(length, "length") / model.length
    return check_scale(scale, "factor")  # type: ignore[arg-type]


def scaled_model(model: ShipModel, scale: float | None = None, length: float | None = None) -> ShipModel:
    """``model`` Froude-scaled by lambda = ``scale``, or to ``length`` (m): the same effects, its overrides
    scaled by their units, its preset rewritten by :func:`scale_document`."""
    factor = ratio(model, scale, length)
    ship = model.ship
    document = ship.document
    if document is None:
        if ship.path is None:
            raise ValueError(f"scaled: ship {ship.name!r} holds no preset document to scale")
        document = load_ship(ship.path).document
    origin = ship.path.name if ship.path is not None else ship.name
    scaled = ship_from_document(scale_document(document or {}, factor, origin), f"{ship.name} scaled")
    overrides = {key: value * _override_factor(key, factor) for key, value in model.overrides.items()}
    return ShipModel(scaled, model.effects, overrides)


def _override_factor(key: str, scale: float) -> float:
    principal = {parameter.name: parameter for parameter in PRINCIPAL}
    if key in principal:
        parameter = principal[key]
    else:
        effect, _, name = key.partition(".")
        parameter = {p.name: p for p in EFFECTS[effect].parameters}[name]
    return froude_factor(scale, unit_exponent(parameter.unit, f"parameters[{key!r}]"))


def scaled_conditions(conditions: Conditions, scale: float) -> Conditions:
    """The conditions the Froude-scaled ship sails in: speeds x lambda^1/2, the propeller rate x lambda^-1/2,
    the wave height x lambda, its period x lambda^1/2, directions and factors kept."""
    scale = check_scale(scale)
    values: dict[str, float] = {}
    for field in dataclasses.fields(conditions):
        value = getattr(conditions, field.name)
        if value is not None:  # a service speed of None takes the (scaled) ship's
            exponent = unit_exponent(CONDITION_UNITS[field.name], f"conditions.{field.name}")
            values[field.name] = value * froude_factor(scale, exponent)
    return dataclasses.replace(conditions, **values)


# -- ship-env scale -------------------------------------------------------------------------------
def run_scale(args: argparse.Namespace) -> int:
    """``ship-env scale``: write the scaled preset and say what changed."""
    from ship_env.workbench.outputs import claim_file

    model = ShipModel(args.preset)
    try:
        factor = ratio(model, args.factor, args.length)
    except ValueError as error:
        raise UsageError("--factor/--length", str(error)) from None
    claim_file(args.output, args.force, "-o")
    ship = model.ship
    origin = ship.path.name if ship.path is not None else ship.name
    try:
        document = scale_document(ship.document or {}, factor, origin, name=args.output.stem)
    except ScalingError as error:
        raise UsageError("IN", str(error)) from None
    args.output.write_text(yaml.safe_dump(document, sort_keys=False, width=120, allow_unicode=True))
    scaled = ShipModel(args.output)
    step = document["scaled"][-1]
    print(
        f"{origin} (L = {model.length:g} m, U0 = {model.service_speed:.4g} m/s) -> {args.output} "
        f"(L = {scaled.length:g} m, U0 = {scaled.service_speed:.4g} m/s): lambda = {factor:.6g}; lengths "
        f"x {factor:.4g}, times and speeds x {factor**0.5:.4g}, rates x {factor**-0.5:.4g}; "
        f"{step['numbers_scaled']} numbers scaled, {step['numbers_kept']} kept (Froude-invariant)"
    )
    return 0


def _arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("preset", type=ship_preset, metavar="IN", help="ship preset name or YAML file to scale")
    size = parser.add_mutually_exclusive_group(required=True)
    size.add_argument(
        "--length", type=number("a positive length in m", above=0.0), default=None, metavar="L", help="new length, m"
    )
    size.add_argument(
        "--factor",
        type=number("a positive ratio of lengths", above=0.0),
        default=None,
        metavar="LAMBDA",
        help="ratio of the new length to the old",
    )
    parser.add_argument("-o", "--output", type=Path, required=True, metavar="OUT", help="the scaled preset (YAML)")
    parser.add_argument("--force", action="store_true", help="overwrite OUT")


COMMAND = Command(
    "scale",
    description=(
        "Write IN Froude-scaled to the length L (or by the factor LAMBDA = new length / old length) as OUT:\n"
        "lengths x LAMBDA, times and speeds x LAMBDA^1/2, rates and the propeller rate x LAMBDA^-1/2,\n"
        "non-dimensional coefficients kept; each number's source and the preset's 'scaled' record say from\n"
        "which preset and by what factor. A number whose scaling is not known is refused, naming it."
    ),
    examples=(
        "ship-env scale kvlcc2 --length 7 -o kvlcc2_model.yaml",
        "ship-env manoeuvre --ship kvlcc2_model.yaml",
        "ship-env scale fitted_model.yaml --factor 45.714 -o fitted_full_scale.yaml",
    ),
    handler=run_scale,
    arguments=_arguments,
)
