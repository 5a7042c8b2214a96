"""Declarations shared by every physical effect: what a parameter is and what an effect is.

An :class:`Effect` names a physical effect in the words a naval engineer uses, lists its
parameters (name, SI unit, meaning, valid range) and cites the thesis equations it implements.
The numbers themselves live in one place only: the ship's YAML file in ``configs/ships``.

An :class:`Envelope` states the conditions a model is valid for (speed, propeller ahead or astern,
drift angle, rate of turn): a ship preset gives the base model's, and an effect that models what the
base model leaves out (e.g. propeller astern) widens it when it is on.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass, fields

#: What a parameter's material size may be given per (``Parameter.material_per``): the ship's
#: particulars it scales with, as a function of the length L (m) and the service speed U (m/s).
MATERIAL_REFERENCES: dict[str, Callable[[float, float], float]] = {
    "": lambda length, service_speed: 1.0,
    "service_speed": lambda length, service_speed: service_speed,
    "1/length^2": lambda length, service_speed: 1.0 / length**2,
    "service_speed/length": lambda length, service_speed: service_speed / length,
}

# Units a YAML file may use, with the factor that converts them to the SI unit the model uses.
UNIT_CONVERSIONS: dict[str, tuple[str, float]] = {
    "deg": ("rad", math.pi / 180.0),
    "deg/s": ("rad/s", math.pi / 180.0),
    "kn": ("m/s", 1852.0 / 3600.0),
    "rpm": ("rps", 1.0 / 60.0),
}

#: Units relative to the ship itself, which a preset may use where a number is a fraction of its own length L or
#: service speed U0 (an assumed limit such as "a quarter of the service speed"): the number then holds for the
#: same hull at any length a preset gives it, written by hand or by ``ship-env scale``, and Froude scaling keeps it.
SHIP_RELATIVE_UNITS: dict[str, tuple[str, Callable[[float, float], float]]] = {
    "L": ("m", lambda length, service_speed: length),
    "U0": ("m/s", lambda length, service_speed: service_speed),
    "U0/L": ("rad/s", lambda length, service_speed: service_speed / length),
    "L/U0": ("s", lambda length, service_speed: length / service_speed),
}


def ship_units(length: float, service_speed: float) -> dict[str, tuple[str, float]]:
    """The conversions of :data:`UNIT_CONVERSIONS` and of :data:`SHIP_RELATIVE_UNITS` for a ship of this length
    (m) and service speed (m/s), as :meth:`Parameter.convert` takes them."""
    relative = {unit: (target, factor(length, service_speed)) for unit, (target, factor) in SHIP_RELATIVE_UNITS.items()}
    return {**UNIT_CONVERSIONS, **relative}


@dataclass(frozen=True)
class Parameter:
    """One model parameter.

    Attributes:
        name: the field name, unique within its effect (``gain``, ``time_constant``).
        unit: the SI unit the model uses ("-" for dimensionless).
        description: what the number means, with the thesis symbol where there is one.
        minimum, maximum: the valid range (inclusive); a value outside it is rejected.
        integer: whether the value must be a whole number (a count).
        default: the value a model takes where the ship's config gives none (an effect written outside
            ``ship_env`` that the presets do not know), or None: the config must give it.
        source: where ``default`` comes from (required with a default: every number has a source).
        null: the value at which the effect vanishes, where there is one (a fit probes from it).
        material: the smallest departure from ``null`` that means something physically (a rudder
            offset of a few tenths of a degree), or None (not declared). In the SI unit, or per
            unit of ``material_per``.
        material_per: the ship's particulars ``material`` is given per, where the physical size
            depends on the ship (a key of ``MATERIAL_REFERENCES``: "" for none, "service_speed" for
            a current of 1.5 % of it, "1/length^2" for a coefficient in 1/m^2, ...).
    """

    name: str
    unit: str
    description: str
    minimum: float = -math.inf
    maximum: float = math.inf
    integer: bool = False
    default: float | None = None
    source: str = ""
    null: float | None = None
    material: float | None = None
    material_per: str = ""

    def __post_init__(self) -> None:
        if self.material is not None and not (math.isfinite(self.material) and self.material > 0.0):
            raise ValueError(f"parameter {self.name!r}: material must be a positive number, got {self.material!r}")
        if self.material_per not in MATERIAL_REFERENCES:
            raise ValueError(
                f"parameter {self.name!r}: material_per {self.material_per!r} is not one of "
                f"{', '.join(repr(key) for key in MATERIAL_REFERENCES)}"
            )

    def material_size(self, length: float, service_speed: float) -> float | None:
        """The material size in the SI unit for a ship of this length (m) and service speed (m/s), or None."""
        if self.material is None:
            return None
        return self.material * MATERIAL_REFERENCES[self.material_per](length, service_speed)

    def convert(
        self, value: object, unit: str | None, where: str, units: Mapping[str, tuple[str, float]] = UNIT_CONVERSIONS
    ) -> float:
        """Check a value read from a config and convert it to this parameter's SI unit (``units``: the conversions
        known, :func:`ship_units` where the ship's length and service speed are)."""
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise TypeError(f"{where}: expected a number in {self.unit}, got {value!r} ({type(value).__name__})")
        number = float(value)
        if unit is not None and unit != self.unit:
            target, factor = units.get(unit, (None, 1.0))
            if target != self.unit:
                relative = f"; {', '.join(SHIP_RELATIVE_UNITS)} only where the ship's length and speed are read first"
                known = f"{', '.join(units)}{'' if SHIP_RELATIVE_UNITS.keys() <= units.keys() else relative}"
                raise ValueError(f"{where}: unit {unit!r} cannot be converted to {self.unit!r} (units known: {known})")
            number *= factor
        if not math.isfinite(number):
            raise ValueError(f"{where}: value must be finite, got {value!r}")
        if not self.minimum <= number <= self.maximum:
            raise ValueError(f"{where}: value {number!r} {self.unit} is outside [{self.minimum}, {self.maximum}]")
        if self.integer and number != int(number):
            raise ValueError(f"{where}: expected a whole number, got {value!r}")
        return number


@dataclass(frozen=True)
class Envelope:
    """The conditions a model is valid for; ``None`` states no limit.

    Attributes:
        minimum_speed: the lowest speed through the water, m/s.
        minimum_froude: the lowest Froude number u / sqrt(g L).
        propeller_ahead_only: whether the propeller must turn ahead (n >= 0).
        maximum_drift: the largest drift angle |atan2(-v, u)|, rad.
        maximum_rate: the largest rate of turn |r|, rad/s.
    """

    minimum_speed: float | None = None
    minimum_froude: float | None = None
    propeller_ahead_only: bool | None = None
    maximum_drift: float | None = None
    maximum_rate: float | None = None

    def widened(self, *others: Envelope) -> Envelope:
        """This envelope with each limit relaxed to the widest another states (an effect's envelope)."""
        values = dict(vars(self))
        for other in others:
            for name, limit in vars(other).items():
                current = values[name]
                if limit is None or current is None:  # no limit stated widens nothing; no limit is widest
                    continue
                if name.startswith("minimum"):
                    values[name] = min(current, limit)
                elif name.startswith("maximum"):
                    values[name] = max(current, limit)
                else:
                    values[name] = current and limit
        return Envelope(**values)


#: The numeric limits of an envelope as a preset's YAML states them (``envelope:`` section).
ENVELOPE_LIMITS: tuple[Parameter, ...] = (
    Parameter("minimum_speed", "m/s", "lowest speed through the water the model is valid for", minimum=0.0),
    Parameter("minimum_froude", "-", "lowest Froude number u / sqrt(g L) the model is valid for", minimum=0.0),
    Parameter("maximum_drift", "rad", "largest drift angle the model is valid for", minimum=0.0, maximum=math.pi),
    Parameter("maximum_rate", "rad/s", "largest rate of turn the model is valid for", minimum=0.0),
)


@dataclass(frozen=True, init=False)
class Effect:
    """A physical effect of the model: its name, its words, its equations and its parameters.

    Declared as ``Effect(name, title, equations, *parameters, required=False, envelope=Envelope())``:
    the parameters one after another (see ``effect_api``).

    Attributes:
        name: the identifier used in configs and on the command line (``wind_moment``).
        title: the effect in a naval engineer's words ("wind yaw moment and added resistance").
        equations: the thesis equations it implements ("(2.85)-(2.88)").
        parameters: the parameters it reads from the ship's config.
        required: whether a model can do without it (the yaw equation and kinematics cannot).
        envelope: the limits this effect widens the model's envelope to when it is on (an astern
            propeller effect: ``propeller_ahead_only=False``); no limit stated widens nothing.
    """

    name: str
    title: str
    equations: str
    parameters: tuple[Parameter, ...]
    required: bool
    envelope: Envelope

    def __init__(
        self,
        name: str,
        title: str,
        equations: str,
        *parameters: Parameter,
        required: bool = False,
        envelope: Envelope | None = None,
    ) -> None:
        for parameter in parameters:
            if not isinstance(parameter, Parameter):
                raise TypeError(
                    f"effect {name!r}: parameters: expected Parameter(...) arguments one after another, "
                    f"got {parameter!r}"
                )
        values = (name, title, equations, parameters, required, Envelope() if envelope is None else envelope)
        for attribute, value in zip(fields(self), values, strict=True):
            object.__setattr__(self, attribute.name, value)  # how a frozen dataclass sets its fields

    def field_name(self, parameter: str) -> str:
        """The name of a parameter in the compiled parameter record (``yaw_gain``)."""
        return f"{self.name}_{parameter}"

    @property
    def flag_name(self) -> str:
        """The name of this effect's on/off flag in the compiled parameter record."""
        return f"{self.name}_on"
