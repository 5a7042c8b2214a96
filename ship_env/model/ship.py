"""Ship presets (``configs/ships/*.yaml``) and the :class:`ShipModel` built from them.

A preset gives the ship's principal particulars and, for each effect, whether it is on by default
and the values of its parameters. Every value carries its source; an assumed value says so::

    principal:
      length: {value: 225.87, unit: m, source: "thesis App. B, length over all"}
    effects:
      yaw:
        enabled: true
        gain: {value: 1.6, source: "thesis 6.4.4.1, identified at 19 kn"}

Values may be given in deg, deg/s, kn or rpm (``unit``); the model holds SI units and radians.

A preset written from a fit (``ship-env fit --preset``, :mod:`ship_env.workbench.reporting.presets`) gives each
fitted value its standard error in the value's unit (``std_error``; null where the data do not
determine it), and a top-level ``fitted:`` block saying what it was fitted to (the logs and their
hashes, the command, the held-out errors, the coverage, the version). Both are optional in every preset.

A preset may state its service conditions (``service_conditions:``, :mod:`ship_env.model.operating_point`):
the propeller rate it sails at where the conditions given to a simulator state none; a fitted preset
states the rate its runs had. Without it the propeller rate is 0.

A preset may say who sails it (``dynamics:``): the MMG standard's forces fitted by ``ship-env fit-mmg``
(:mod:`ship_env.model.mmg_fitted`, the block that command writes to its ``--output``). The environments,
``ship-env manoeuvre`` and the leaderboard then sail that model by default (their ``dynamics`` keyword set to
``"native"`` sails the preset's own effects instead); the preset's principal particulars and effects remain
what the bridge knows of the ship and what the classic autopilots are designed from. :class:`Simulator` sails
the effects alone.
"""

from __future__ import annotations

import copy
import math
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field, replace
from functools import cache, lru_cache
from pathlib import Path
from typing import Any

import numpy as np
import yaml

from ship_env.model import draws, dynamics
from ship_env.model import state as S
from ship_env.model.declarations import ENVELOPE_LIMITS, UNIT_CONVERSIONS, Envelope, Parameter, ship_units
from ship_env.model.dynamics import FINGERPRINT_PREFIX, check_contributions, fingerprint
from ship_env.model.effects import EFFECTS, MINIMAL_EFFECTS, REQUIRED_EFFECTS
from ship_env.model.mmg_record import MmgRecord, mmg_record
from ship_env.model.operating_point import SERVICE_CONDITIONS, FittedRanges, fitted_ranges
from ship_env.paths import config_dir

#: The YAML loader for ship presets: libyaml's safe loader where PyYAML was built with it (the same
#: documents, read several times faster: every environment made reads its ship), else PyYAML's own.
SAFE_LOADER = getattr(yaml, "CSafeLoader", yaml.SafeLoader)

PRINCIPAL: tuple[Parameter, ...] = (
    Parameter("length", "m", "L, the length that normalises the model (2.40)", minimum=1e-3),
    Parameter("breadth", "m", "B, moulded breadth (drawings only)", minimum=0.0),
    Parameter("draught", "m", "T, draught (drawings only)", minimum=0.0),
    Parameter("service_speed", "m/s", "U0, speed through the water on a straight course", minimum=0.0),
    Parameter("rudder_limit", "rad", "delta_max, hard-over rudder angle (Fig. 2.9)", minimum=1e-6, maximum=math.pi / 2),
    Parameter(
        "minimum_speed",
        "m/s",
        "speed floor used where the model divides by u (r* = L r / u); keeps a ship at rest finite",
        minimum=1e-6,
    ),
)
_PRINCIPAL_BY_NAME = {parameter.name: parameter for parameter in PRINCIPAL}
#: The principal particulars the ship-relative units (``declarations.SHIP_RELATIVE_UNITS``: L, U0) refer to.
SHIP_SCALES = ("length", "service_speed")
#: The sections a preset's YAML may hold.
TOP_LEVEL_KEYS = (
    "name",
    "description",
    "principal",
    "service_conditions",
    "envelope",
    "effects",
    "fitted",
    "scaled",
    "dynamics",
)


def record_dtype() -> np.dtype:
    """The layout of the compiled parameter record for the effects registered now.

    Principal particulars, then per effect its flag and parameters (``yaw_on``, ``yaw_gain``, ...)
    and where its draws start in a ship's row of draws (``wave_spectrum_waves_start``), then a flag
    ``equations_<hash>`` naming the version of the effects' equations. The same for every model
    while the registry does not change, so the kernels compile once per set of effects.
    """
    names = list(EFFECTS)
    return _record_dtype(tuple(names), fingerprint(names))


@cache
def _record_dtype(names: tuple[str, ...], fingerprint: str) -> np.dtype:
    fields: list[tuple[str, type]] = [(parameter.name, np.float64) for parameter in PRINCIPAL]
    for name in names:
        effect = EFFECTS[name]
        fields.append((effect.flag_name, np.bool_))
        fields.extend((effect.field_name(parameter.name), np.float64) for parameter in effect.parameters)
        fields.extend((draws.start_field(name, draw), np.int64) for draw in EFFECTS.entry(name).draws)
    fields.append((f"{FINGERPRINT_PREFIX}{fingerprint}", np.bool_))
    return np.dtype(fields)


@dataclass(frozen=True)
class Ship:
    """A ship preset as read from its YAML file, values in SI units.

    Attributes:
        name: the preset's name (the file's stem).
        description: what the ship is.
        principal: principal particulars by name (``length``, ``service_speed``...).
        values: per effect, its parameter values by name.
        enabled: the effects on by default.
        sources: where each number comes from, keyed ``principal.length`` or ``yaw.gain``.
        assumed: the keys of numbers that are assumed rather than taken from a source.
        envelope: the conditions the base model (no optional effect) is valid for.
        std_errors: the standard errors of fitted numbers (SI units; None: not determined), keyed as ``sources``.
        fitted: what a fitted preset was fitted to (its ``fitted:`` block as written), or None.
        scaled: the Froude scalings that made it from another preset, oldest first (its ``scaled:``
            block as written; see :mod:`ship_env.model.froude`).
        document: the YAML document it was read from (what :mod:`~ship_env.model.froude` rewrites).
        service_conditions: the conditions it sails in where a simulator's conditions state none
            (``propeller_rate`` in rps; :mod:`~ship_env.model.operating_point`); empty: none stated.
        dynamics: the model that sails it by default where it is not ship_env's own (its ``dynamics:`` block: a
            fitted MMG model, :mod:`~ship_env.model.mmg_fitted`), or None.
    """

    name: str
    description: str
    principal: Mapping[str, float]
    values: Mapping[str, Mapping[str, float]]
    enabled: tuple[str, ...]
    sources: Mapping[str, str] = field(default_factory=dict)
    assumed: frozenset[str] = frozenset()
    path: Path | None = None
    envelope: Envelope = field(default_factory=Envelope)
    std_errors: Mapping[str, float | None] = field(default_factory=dict)
    fitted: Mapping[str, Any] | None = None
    scaled: tuple[Mapping[str, Any], ...] = ()
    document: Mapping[str, Any] | None = field(default=None, repr=False, compare=False)
    service_conditions: Mapping[str, float] = field(default_factory=dict)
    dynamics: MmgRecord | None = field(default=None, repr=False, compare=False)


@dataclass
class _Provenance:
    """What a preset says of its numbers besides their values, collected while it is read."""

    sources: dict[str, str] = field(default_factory=dict)
    assumed: set[str] = field(default_factory=set)
    std_errors: dict[str, float | None] = field(default_factory=dict)


def list_ships() -> list[str]:
    """Names of the ship presets in ``configs/ships``."""
    return sorted(path.stem for path in (config_dir() / "ships").glob("*.yaml"))


def _read_value(
    parameter: Parameter,
    entry: object,
    where: str,
    provenance: _Provenance,
    units: Mapping[str, tuple[str, float]] = UNIT_CONVERSIONS,
) -> float:
    """A number's value in SI units (``units``: the conversions known, :func:`ship_units` once the ship's length and
    service speed are read); its source, whether it is assumed and its standard error go to ``provenance``."""
    if not isinstance(entry, Mapping):
        raise TypeError(f"{where}: expected a mapping with 'value' and 'source', got {entry!r}")
    unknown = set(entry) - {"value", "unit", "source", "assumed", "std_error"}
    if unknown:
        raise ValueError(f"{where}: unknown keys {sorted(unknown)}")
    if "value" not in entry:
        raise ValueError(f"{where}: missing 'value'")
    source = entry.get("source")
    if not isinstance(source, str) or not source.strip():
        raise ValueError(f"{where}: every number needs a 'source' (say 'assumed' and why if it is)")
    flag = entry.get("assumed", False)
    if not isinstance(flag, bool):
        raise TypeError(f"{where}.assumed: expected true or false, got {flag!r}")
    unit = entry.get("unit")
    if unit is not None and not isinstance(unit, str):
        raise TypeError(f"{where}.unit: expected a string, got {unit!r}")
    key = where.split(":", 1)[-1]
    provenance.sources[key] = source
    if flag:
        provenance.assumed.add(key)
    if "std_error" in entry:
        spread = replace(parameter, minimum=0.0, maximum=math.inf, integer=False)
        error = entry["std_error"]
        provenance.std_errors[key] = None if error is None else spread.convert(error, unit, f"{where}.std_error", units)
    return parameter.convert(entry["value"], unit, where, units)


def _read_envelope(
    entries: object, label: str, provenance: _Provenance, units: Mapping[str, tuple[str, float]]
) -> Envelope:
    """The preset's ``envelope:`` section: numeric limits and ``propeller_ahead_only``, each with its source."""
    if not isinstance(entries, Mapping):
        raise TypeError(f"{label}: envelope: expected a mapping, got {entries!r}")
    by_name = {parameter.name: parameter for parameter in ENVELOPE_LIMITS}
    limits: dict[str, Any] = {}  # float limits and the propeller flag, checked as read
    for key, entry in entries.items():
        where = f"{label}:envelope.{key}"
        if key == "propeller_ahead_only":
            flag = entry.get("value") if isinstance(entry, Mapping) else entry
            if not isinstance(flag, bool):
                raise TypeError(f"{where}: expected a value true or false, got {flag!r}")
            number = Parameter(key, "-", "whether the propeller must turn ahead", minimum=0.0, maximum=1.0)
            _read_value(number, {**entry, "value": float(flag)}, where, provenance)
            limits[key] = flag
        elif key in by_name:
            limits[key] = _read_value(by_name[key], entry, where, provenance, units)
        else:
            known = ", ".join([*by_name, "propeller_ahead_only"])
            raise ValueError(f"{label}: envelope: unknown limit {key!r}; known: {known}")
    return Envelope(**limits)


@lru_cache(maxsize=64)
def _parsed(text: str) -> Any:
    """A ship YAML file's document, parsed once per text: every environment made reads its ship, and
    the file is read each time, so an edited file is parsed afresh. Callers get a copy (``load_ship``)."""
    return yaml.load(text, Loader=SAFE_LOADER)


def load_ship(name_or_path: str | Path) -> Ship:
    """Read a ship preset by name (``container_226m``) or from a YAML file path."""
    path = Path(name_or_path)
    if path.suffix not in (".yaml", ".yml"):
        path = config_dir() / "ships" / f"{name_or_path}.yaml"
        if not path.is_file():
            raise ValueError(f"ship: unknown preset {str(name_or_path)!r}; known: {', '.join(list_ships())}")
    return ship_from_document(copy.deepcopy(_parsed(path.read_text())), path.name, path)


def ship_from_document(document: object, label: str, path: Path | None = None) -> Ship:
    """A ship preset from its YAML document (``label`` names it in errors; ``path``: the file it was read from)."""
    if not isinstance(document, Mapping):
        raise TypeError(f"{path or label}: expected a mapping at the top level")
    unknown = set(document) - set(TOP_LEVEL_KEYS)
    if unknown:
        raise ValueError(f"{path or label}: unknown top-level keys {sorted(unknown)}")
    provenance = _Provenance()
    fitted = document.get("fitted")
    if fitted is not None and not isinstance(fitted, Mapping):
        raise TypeError(f"{label}: fitted: expected a mapping (what the preset was fitted to), got {fitted!r}")
    scaled = document.get("scaled") or []
    if not isinstance(scaled, list) or not all(isinstance(step, Mapping) for step in scaled):
        raise TypeError(f"{label}: scaled: expected a list of mappings (the scalings that made it), got {scaled!r}")

    principal_entries = document.get("principal") or {}
    if not isinstance(principal_entries, Mapping):
        raise TypeError(f"{label}: principal: expected a mapping, got {principal_entries!r}")
    strange = [key for key in principal_entries if key not in _PRINCIPAL_BY_NAME]
    if strange:
        raise ValueError(f"{label}: principal: unknown field {strange[0]!r}; known: {', '.join(_PRINCIPAL_BY_NAME)}")
    missing = [name for name in _PRINCIPAL_BY_NAME if name not in principal_entries]
    if missing:
        raise ValueError(f"{label}: principal: missing {', '.join(missing)}")

    def read_principal(key: str, units: Mapping[str, tuple[str, float]]) -> float:
        return _read_value(
            _PRINCIPAL_BY_NAME[key], principal_entries[key], f"{label}:principal.{key}", provenance, units
        )

    scales = {key: read_principal(key, UNIT_CONVERSIONS) for key in SHIP_SCALES}  # what L and U0 refer to
    units = ship_units(scales["length"], scales["service_speed"])
    principal = {key: scales[key] if key in scales else read_principal(key, units) for key in principal_entries}

    effect_entries = document.get("effects") or {}
    if not isinstance(effect_entries, Mapping):
        raise TypeError(f"{label}: effects: expected a mapping, got {effect_entries!r}")
    values: dict[str, dict[str, float]] = {}
    enabled: list[str] = []
    for effect_name, entries in effect_entries.items():
        if effect_name not in EFFECTS:
            raise ValueError(f"{label}: effects: unknown effect {effect_name!r}; known: {', '.join(EFFECTS)}")
        effect = EFFECTS[effect_name]
        entries = entries or {}
        if not isinstance(entries, Mapping):
            raise TypeError(f"{label}: effects.{effect_name}: expected a mapping, got {entries!r}")
        by_name = {parameter.name: parameter for parameter in effect.parameters}
        values[effect_name] = {}
        for key, entry in entries.items():
            if key == "enabled":
                if not isinstance(entry, bool):
                    raise TypeError(f"{label}: effects.{effect_name}.enabled: expected true or false, got {entry!r}")
                if entry:
                    enabled.append(effect_name)
                continue
            if key not in by_name:
                raise ValueError(
                    f"{label}: effects.{effect_name}: unknown parameter {key!r}; known: {', '.join(by_name) or 'none'}"
                )
            where = f"{label}:{effect_name}.{key}"
            values[effect_name][key] = _read_value(by_name[key], entry, where, provenance, units)
    envelope = _read_envelope(document.get("envelope") or {}, label, provenance, units)
    if envelope.minimum_speed is not None and envelope.minimum_speed >= principal["service_speed"]:
        raise ValueError(
            f"{label}: envelope.minimum_speed: {envelope.minimum_speed:g} m/s is not below the service speed "
            f"{principal['service_speed']:g} m/s, so the model would not hold at the ship's own speed (a limit written "
            "for another scale? give it as a fraction of the service speed, unit: U0)"
        )
    service_entries = document.get("service_conditions") or {}
    if not isinstance(service_entries, Mapping):
        raise TypeError(f"{label}: service_conditions: expected a mapping, got {service_entries!r}")
    by_name = {parameter.name: parameter for parameter in SERVICE_CONDITIONS}
    service_conditions: dict[str, float] = {}
    for key, entry in service_entries.items():
        if key not in by_name:
            raise ValueError(f"{label}: service_conditions: unknown condition {key!r}; known: {', '.join(by_name)}")
        where = f"{label}:service_conditions.{key}"
        service_conditions[key] = _read_value(by_name[key], entry, where, provenance, units)
    sailed_by = None
    if document.get("dynamics") is not None:
        sailed_by = mmg_record(document["dynamics"], f"{path or label}: dynamics")
    return Ship(
        name=str(document.get("name", path.stem if path is not None else label)),
        description=str(document.get("description", "")).strip(),
        principal=principal,
        values=values,
        enabled=tuple(name for name in EFFECTS if name in enabled or name in REQUIRED_EFFECTS),
        sources=provenance.sources,
        assumed=frozenset(provenance.assumed),
        path=path,
        envelope=envelope,
        std_errors=provenance.std_errors,
        fitted=fitted,
        scaled=tuple(scaled),
        document=document,
        service_conditions=service_conditions,
        dynamics=sailed_by,
    )


def _check_effect_names(names: Iterable[str]) -> list[str]:
    checked = []
    for name in names:
        if not isinstance(name, str) or name not in EFFECTS:
            raise ValueError(f"effects: unknown effect {name!r}; known: {', '.join(EFFECTS)}")
        checked.append(name)
    return checked


class ShipModel:
    """A ship preset with a chosen set of physical effects, ready to simulate.

    Turning an effect on or off changes only this model's flags: the equations of the other effects
    are untouched. Parameter values come from the preset and may be overridden by name.

    Args:
        ship: a preset name, a YAML path or a loaded :class:`Ship`.
        effects: the effects to include (the required ``yaw`` and ``kinematics`` are always in);
            ``None`` takes the preset's default set.
        parameters: overrides, keyed ``"effect.parameter"`` (``"yaw.gain"``) or a principal
            particular (``"length"``), in SI units.

    Example::

        model = ShipModel("container_226m").without_effects("wind_moment")
        model.parameter("yaw.gain")  # 1.6
    """

    def __init__(
        self,
        ship: str | Path | Ship = "container_226m",
        effects: Iterable[str] | None = None,
        parameters: Mapping[str, float] | None = None,
    ) -> None:
        self.ship = ship if isinstance(ship, Ship) else load_ship(ship)
        if isinstance(effects, str):
            raise TypeError(f"effects: expected a list of effect names, got the string {effects!r}")
        chosen = set(self.ship.enabled if effects is None else _check_effect_names(effects))
        self.effects: tuple[str, ...] = tuple(n for n in EFFECTS if n in chosen or n in REQUIRED_EFFECTS)
        self._principal = dict(self.ship.principal)
        self._values = {name: dict(values) for name, values in self.ship.values.items()}
        for effect_name in self.effects:
            for parameter in EFFECTS[effect_name].parameters:
                if parameter.default is not None:
                    self._values.setdefault(effect_name, {}).setdefault(parameter.name, float(parameter.default))
        self.overrides: dict[str, float] = {}
        for key, value in (parameters or {}).items():
            self._set(key, value)
        self.record = self._build_record()
        #: The random numbers the effects that are on draw for each ship where it starts (``draws``).
        self.draw_layout = draws.layout(list(EFFECTS), self.record[0])
        for placed in self.draw_layout:
            self.record[0][draws.start_field(placed.entry.effect.name, placed.draw)] = placed.start
        #: The layout of the model's state: the motion's states, then the registered effects' own.
        self.state_names: tuple[str, ...] = dynamics.state_names(self.record)
        #: Whether every effect's own state starts at 0 (a reset has nothing more to set).
        self.own_states_start_at_zero = all(
            not callable(state.initial) and state.initial == 0.0
            for name in EFFECTS
            for state in EFFECTS.entry(name).new_states
        )
        check_contributions(self)
        #: The ranges a fitted preset's runs covered, checked while it sails; None for a preset that states none.
        self.fitted_ranges: FittedRanges | None = fitted_ranges(
            str(self.ship.path) if self.ship.path is not None else self.ship.name,
            self.ship.fitted,
            any(
                "propeller_rate" in entry.arguments(contribution)
                for entry in (EFFECTS.entry(name) for name in self.effects)
                for contribution in entry.contributions
            ),
        )

    def _set(self, key: str, value: float) -> None:
        if key in _PRINCIPAL_BY_NAME:
            self._principal[key] = _PRINCIPAL_BY_NAME[key].convert(value, None, f"parameters[{key!r}]")
        else:
            effect_name, _, name = key.partition(".")
            effect = EFFECTS.get(effect_name)
            by_name = {parameter.name: parameter for parameter in effect.parameters} if effect else {}
            if name not in by_name:
                raise ValueError(
                    f"parameters: unknown parameter {key!r}; "
                    "use 'effect.parameter' (e.g. 'yaw.gain') or a principal particular"
                )
            self._values.setdefault(effect_name, {})[name] = by_name[name].convert(value, None, f"parameters[{key!r}]")
        self.overrides[key] = float(value)

    def _build_record(self) -> np.ndarray:
        record = np.zeros(1, dtype=record_dtype())
        where = self.ship.path.name if self.ship.path is not None else f"ship {self.ship.name!r}"
        for name, particular in self._principal.items():
            record[0][name] = particular
        for effect_name, effect in EFFECTS.items():
            on = effect_name in self.effects
            record[0][effect.flag_name] = on
            for parameter in effect.parameters:
                value = self._values.get(effect_name, {}).get(parameter.name)
                if value is None:
                    if on:
                        raise ValueError(
                            f"{where}: effect {effect_name!r} is on but has no value for "
                            f"{parameter.name!r} ({parameter.description})"
                        )
                    continue
                record[0][effect.field_name(parameter.name)] = value
        return record

    # -- variants -------------------------------------------------------------------------------
    def with_effects(self, *names: str) -> ShipModel:
        """This model with more effects on."""
        return ShipModel(self.ship, self.effects + tuple(_check_effect_names(names)), self.overrides)

    def without_effects(self, *names: str) -> ShipModel:
        """This model with some effects off (required effects cannot be removed)."""
        for name in _check_effect_names(names):
            if name in REQUIRED_EFFECTS:
                raise ValueError(f"effects: {name!r} is required and cannot be turned off")
        return ShipModel(self.ship, [n for n in self.effects if n not in names], self.overrides)

    def with_parameters(self, parameters: Mapping[str, float]) -> ShipModel:
        """This model with some parameter values replaced (keys as in the constructor)."""
        return ShipModel(self.ship, self.effects, {**self.overrides, **parameters})

    def without_coverage_check(self) -> ShipModel:
        """This model, sailed without checking its preset's fitted ranges (:attr:`fitted_ranges` None): for the
        sailing a tool does on the user's behalf and judges itself (how far a manoeuvre goes beyond the runs, the
        workbench's validation of a new fit). The simulator's warnings, said once per preset and quantity in a
        process, are then left for the user's own sailing."""
        unchecked = copy.copy(self)
        unchecked.fitted_ranges = None
        return unchecked

    def scaled(self, factor: float | None = None, *, length: float | None = None) -> ShipModel:
        """This ship Froude-scaled by ``factor`` (lambda, new length / old) or to ``length`` (m), its preset
        rewritten with each number's source saying so (:func:`ship_env.model.froude.scaled_model`)."""
        from ship_env.model.froude import scaled_model  # froude builds on this module

        return scaled_model(self, factor, length)

    @classmethod
    def minimal(cls, ship: str | Path | Ship = "container_226m") -> ShipModel:
        """The first-order Nomoto ship with its steering machine (2.58, Fig. 2.9)."""
        return cls(ship, MINIMAL_EFFECTS)

    @classmethod
    def full(cls, ship: str | Path | Ship = "container_226m") -> ShipModel:
        """The ship with every effect on."""
        return cls(ship, EFFECTS)

    # -- values ----------------------------------------------------------------------------------
    def parameter(self, key: str) -> float:
        """A parameter's value in SI units, keyed as in the constructor."""
        if key in _PRINCIPAL_BY_NAME:
            return float(self._principal[key])
        effect_name, _, name = key.partition(".")
        try:
            return float(self._values[effect_name][name])
        except KeyError:
            raise KeyError(f"parameter {key!r} has no value in ship {self.ship.name!r}") from None

    @property
    def length(self) -> float:
        return float(self._principal["length"])

    @property
    def service_speed(self) -> float:
        return float(self._principal["service_speed"])

    @property
    def service_propeller_rate(self) -> float:
        """n, rps: the propeller rate of the preset's service conditions (0 where it states none)."""
        return float(self.ship.service_conditions.get("propeller_rate", 0.0))

    @property
    def rudder_limit(self) -> float:
        return float(self._principal["rudder_limit"])

    @property
    def envelope(self) -> Envelope:
        """The conditions this model is valid for: the preset's, widened by the effects that are on."""
        return self.ship.envelope.widened(*(EFFECTS[name].envelope for name in self.effects))

    def has(self, effect: str) -> bool:
        """Whether an effect is on."""
        return effect in self.effects

    @property
    def state_size(self) -> int:
        """The number of state variables a ship of this model has (``state_names``)."""
        return len(self.state_names)

    @property
    def draw_size(self) -> int:
        """The number of random numbers the effects draw for a ship where it starts (``draws``)."""
        return sum(placed.size for placed in self.draw_layout)

    def draw(self, keys: np.ndarray, conditions: np.ndarray, start_conditions: Mapping[str, np.ndarray]) -> np.ndarray:
        """The ships' rows of draws, (len(keys), ``draw_size``): see :func:`ship_env.model.draws.draw`."""
        return draws.draw(self.draw_layout, self.record[0], keys, conditions, start_conditions)

    def start_states(self, states: np.ndarray, conditions: np.ndarray) -> None:
        """Set the effects' own states to their initial values in rows of ``states`` whose motion is set.

        Args:
            states: (N, state_size) states, written in place after the motion's states.
            conditions: (N, CONDITION_SIZE) the conditions each ship starts in.
        """
        if not self.own_states_start_at_zero:
            dynamics.start_states(states, conditions, self.record)
        else:
            states[:, S.MOTION_SIZE :] = 0.0

    def __repr__(self) -> str:
        return f"ShipModel({self.ship.name!r}, effects={list(self.effects)})"
