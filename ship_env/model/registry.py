"""The registry of physical effects: the built-in library and effects written outside ``ship_env``.

An effect is an :class:`~ship_env.model.declarations.Effect` declaration with its
:class:`~ship_env.model.contributions.Contribution` s to the state derivative. The built-in effects
register themselves (``effects/__init__.py``); an effect of your own registers

- from an installed package, through the entry-point group ``ship_env.effects``: the entry point
  names a module that holds ``EFFECT`` and ``CONTRIBUTIONS`` (as the modules under ``effects/``
  do), e.g. in ``pyproject.toml``::

      [project.entry-points."ship_env.effects"]
      shallow_water = "my_ships.shallow_water"

- or in a notebook or script, with :func:`register_effect`.

Then :class:`~ship_env.model.ShipModel`, the simulators, the environments and the workbench
(``fit --add``, ``diagnose``, ``improve``) use it like a built-in: its parameters come from the
ship's YAML (``effects: {shallow_water: {enabled: true, ...}}``) or, where the preset has none,
from the parameters' declared defaults.
"""

from __future__ import annotations

import hashlib
import importlib.metadata
import inspect
import math
from collections.abc import Callable, Iterator, Mapping, Sequence
from dataclasses import dataclass
from types import ModuleType
from typing import Any

import numba

from ship_env.model import state as S
from ship_env.model.contributions import INPUTS, QUANTITIES, STATE_DERIVATIVES, WIND, Contribution
from ship_env.model.declarations import Effect, Parameter

#: The entry-point group effects outside ``ship_env`` register under.
ENTRY_POINT_GROUP = "ship_env.effects"

#: The principal particulars' names (``ship.PRINCIPAL``; here to keep the import order simple).
PRINCIPAL_NAMES = ("length", "breadth", "draught", "service_speed", "rudder_limit", "minimum_speed")


@dataclass(frozen=True)
class RegisteredEffect:
    """An effect in the registry.

    Attributes:
        effect: its declaration.
        contributions: its terms in the state derivative.
        states: the state variables it owns (their derivative acts only where it is on).
        origin: where it comes from: ``ship_env`` for the built-ins, else the module or entry point.
    """

    effect: Effect
    contributions: tuple[Contribution, ...]
    states: tuple[str, ...]
    origin: str

    @property
    def builtin(self) -> bool:
        return self.origin == "ship_env"

    def arguments(self, contribution: Contribution) -> tuple[str, ...]:
        """The names a contribution's function reads, in order."""
        return tuple(inspect.signature(_python_function(contribution.function)).parameters)


def _python_function(function: Callable[..., Any]) -> Callable[..., Any]:
    return getattr(function, "py_func", function)


def _compiled(function: Callable[..., Any]) -> Callable[..., Any]:
    """A contribution's function compiled (a plain Python function is compiled here, not cached)."""
    if isinstance(function, numba.core.registry.CPUDispatcher):
        return function
    return numba.njit(fastmath=False, error_model="numpy")(function)


def _source(function: Callable[..., Any]) -> str:
    """The source a compiled kernel depends on: the function's module, or the function alone."""
    python = _python_function(function)
    module = inspect.getmodule(python)
    for target in (module, python):
        try:
            return inspect.getsource(target)  # type: ignore[arg-type]
        except (OSError, TypeError):
            continue
    code = python.__code__
    return repr((code.co_code, code.co_consts, code.co_names))


class EffectRegistry(Mapping[str, Effect]):
    """The registered effects by name, in registration order: a mapping to their declarations.

    The entry points of ``ship_env.effects`` are loaded at the first look-up.
    """

    def __init__(self) -> None:
        self._entries: dict[str, RegisteredEffect] = {}
        self._entry_points_loaded = False
        self._fingerprints: dict[str, str] = {}

    # -- the Mapping -------------------------------------------------------------------------------
    def __getitem__(self, name: str) -> Effect:
        self._load()
        return self._entries[name].effect

    def __iter__(self) -> Iterator[str]:
        self._load()
        return iter(list(self._entries))

    def __len__(self) -> int:
        self._load()
        return len(self._entries)

    def __contains__(self, name: object) -> bool:
        self._load()
        return name in self._entries

    def __repr__(self) -> str:
        return f"EffectRegistry({', '.join(self)})"

    # -- registering -------------------------------------------------------------------------------
    def entry(self, name: str) -> RegisteredEffect:
        """An effect's registration (declaration, contributions, states, origin)."""
        self._load()
        if name not in self._entries:
            raise ValueError(f"effects: unknown effect {name!r}; known: {', '.join(self._entries)}")
        return self._entries[name]

    def register(
        self,
        effect: Effect,
        contributions: Sequence[Contribution],
        states: Sequence[str] = (),
        origin: str | None = None,
    ) -> RegisteredEffect:
        """Check an effect and add it (see :func:`register_effect`)."""
        origin = origin or _caller_module()
        builtin = origin == "ship_env"
        where = f"effect {getattr(effect, 'name', effect)!r} from {origin}"
        if not isinstance(effect, Effect):
            raise TypeError(f"{where}: expected an Effect declaration, got {effect!r}")
        if not effect.name.isidentifier():
            raise ValueError(f"{where}: name: expected a Python identifier, got {effect.name!r}")
        existing = self._entries.get(effect.name)
        if existing is not None and (existing.builtin or builtin):
            raise ValueError(
                f"{where}: name: {effect.name!r} is already the name of the effect from {existing.origin} "
                f"({existing.effect.title}); choose another name"
            )
        if not builtin and effect.required:
            raise ValueError(f"{where}: required: only the built-in effects can be required")
        _check_parameters(effect, where, builtin)
        states = tuple(states)
        for state in states:
            if state not in STATE_DERIVATIVES:
                raise ValueError(
                    f"{where}: states: {state!r} is not a state with a derivative of its own; "
                    f"known: {', '.join(STATE_DERIVATIVES)}"
                )
            owner = next(
                (e for e in self._entries.values() if state in e.states and e.effect.name != effect.name), None
            )
            if owner is not None:
                raise ValueError(f"{where}: states: {state!r} is already owned by effect {owner.effect.name!r}")
        checked = tuple(self._check_contribution(effect, c, states, where, builtin) for c in contributions)
        entry = RegisteredEffect(effect, checked, states, origin)
        self._entries[effect.name] = entry
        self._fingerprints.pop(effect.name, None)
        return entry

    def unregister(self, name: str) -> None:
        """Remove an effect registered from outside ``ship_env`` (a test, a notebook starting over)."""
        entry = self.entry(name)
        if entry.builtin:
            raise ValueError(f"effects: {name!r} is built in and cannot be removed")
        del self._entries[name]
        self._fingerprints.pop(name, None)

    def _check_contribution(
        self, effect: Effect, contribution: object, states: tuple[str, ...], where: str, origin_builtin: bool
    ) -> Contribution:
        if not isinstance(contribution, Contribution):
            raise TypeError(f"{where}: contributions: expected Contribution(quantity, function), got {contribution!r}")
        quantity = contribution.quantity
        if quantity not in QUANTITIES:
            raise ValueError(f"{where}: contribution quantity {quantity!r} is unknown; known: {', '.join(QUANTITIES)}")
        owned = {derivative: state for state, derivative in STATE_DERIVATIVES.items()}
        if quantity in owned and owned[quantity] not in states and not self._owner(owned[quantity]):
            raise ValueError(
                f"{where}: contribution to {quantity!r}: no effect owns the state {owned[quantity]!r}; "
                f"declare it in the effect's states"
            )
        if not callable(contribution.function):
            raise TypeError(f"{where}: contribution to {quantity!r}: function: expected a function")
        own = {parameter.name for parameter in effect.parameters}
        fields = {f"{e.name}_{p.name}" for e in self.declarations() for p in e.parameters}
        fields |= {f"{effect.name}_{name}" for name in own}
        known = set(INPUTS) | set(S.STATE_NAMES) | set(S.CONDITION_NAMES) | set(PRINCIPAL_NAMES) | own | fields
        order = list(QUANTITIES)
        earlier = set(order[: order.index(quantity) + 1]) | set(WIND)
        for argument in inspect.signature(_python_function(contribution.function)).parameters:
            if argument in known or argument in earlier or origin_builtin:
                # A built-in may read a built-in's parameter registered after it: ``dynamics`` checks it.
                continue
            raise ValueError(
                f"{where}: contribution to {quantity!r}: argument {argument!r} names nothing the model has at that "
                f"point: use an input ({', '.join(INPUTS)}), a quantity computed before it, a state, a condition, a "
                f"principal particular, one of the effect's parameters ({', '.join(sorted(own)) or 'none'}) or "
                f"another effect's parameter as its record field (e.g. 'yaw_gain')"
            )
        return Contribution(quantity, _compiled(contribution.function))

    def _owner(self, state: str) -> bool:
        return any(state in entry.states for entry in self._entries.values())

    # -- reading ---------------------------------------------------------------------------------
    def declarations(self) -> list[Effect]:
        """The registered effects' declarations (without loading entry points)."""
        return [entry.effect for entry in self._entries.values()]

    def fingerprint(self, names: Sequence[str]) -> str:
        """A short hash of the named effects' equations (their contributions' source)."""
        digest = hashlib.sha256()
        for name in names:
            if name not in self._fingerprints:
                entry = self.entry(name)
                sources = [f"{c.quantity}:{_source(c.function)}" for c in entry.contributions]
                self._fingerprints[name] = hashlib.sha256("\n".join(sources).encode()).hexdigest()
            digest.update(f"{name}={self._fingerprints[name]};".encode())
        return digest.hexdigest()[:16]

    # -- entry points ----------------------------------------------------------------------------
    def load_entry_points(self) -> None:
        """Register the effects of every installed ``ship_env.effects`` entry point (once each)."""
        self._entry_points_loaded = True
        for entry_point in importlib.metadata.entry_points(group=ENTRY_POINT_GROUP):
            origin = f"entry point {entry_point.name!r} ({entry_point.value})"
            if entry_point.name in self._entries and self._entries[entry_point.name].origin == origin:
                continue
            try:
                loaded = entry_point.load()
            except Exception as error:
                raise ImportError(f"effect {entry_point.name!r} from {origin}: cannot import it: {error}") from error
            register_module(loaded, origin)

    def _load(self) -> None:
        if not self._entry_points_loaded:
            self.load_entry_points()


def _check_parameters(effect: Effect, where: str, builtin: bool) -> None:
    """Every parameter has a unit and a description; one outside ``ship_env`` also a finite range."""
    names = set()
    for parameter in effect.parameters:
        label = f"{where}: parameter {getattr(parameter, 'name', parameter)!r}"
        if not isinstance(parameter, Parameter):
            raise TypeError(f"{label}: expected a Parameter, got {parameter!r}")
        if not parameter.name.isidentifier() or parameter.name in names:
            raise ValueError(f"{label}: name: expected a Python identifier unique in the effect")
        names.add(parameter.name)
        if not isinstance(parameter.unit, str) or not parameter.unit.strip():
            raise ValueError(f"{label}: unit: every parameter needs its SI unit ('-' if dimensionless)")
        if not parameter.description.strip():
            raise ValueError(f"{label}: description: say what the number means")
        if not builtin and not (math.isfinite(parameter.minimum) and math.isfinite(parameter.maximum)):
            raise ValueError(
                f"{label}: range: give a finite minimum and maximum (got [{parameter.minimum}, {parameter.maximum}]); "
                f"a fit keeps the value inside them"
            )
        if parameter.minimum > parameter.maximum:
            raise ValueError(f"{label}: range: minimum {parameter.minimum} is above maximum {parameter.maximum}")
        if parameter.default is not None:
            parameter.convert(parameter.default, None, f"{label}: default")
            if not parameter.source.strip():
                raise ValueError(f"{label}: source: a default needs its source (say 'assumed' and why if it is)")


def _caller_module() -> str:
    """The module that called :func:`register_effect`, named for error messages."""
    frame = inspect.currentframe()
    while frame is not None:
        module = frame.f_globals.get("__name__", "")
        if not module.startswith("ship_env.model"):
            return f"module {module}"
        frame = frame.f_back
    return "unknown module"


#: The registered effects, built-in and user-written, in registration order.
EFFECTS = EffectRegistry()


def register_effect(
    effect: Effect, contributions: Sequence[Contribution], states: Sequence[str] = ()
) -> RegisteredEffect:
    """Register an effect written outside ``ship_env`` (from a notebook or a script).

    Args:
        effect: its declaration: name, title, equations, parameters (each with a unit, a finite
            range and, where the presets lack it, a default with its source).
        contributions: its terms in the state derivative (see ``ship_env.model.contributions``).
        states: the state variables it owns (``STATE_DERIVATIVES``), usually none.

    Registering again under the same name replaces an effect from outside ``ship_env`` (a cell run
    again); a built-in's name is refused. Models built afterwards use it.

    Raises:
        ValueError, TypeError: naming the effect, where it comes from and the field at fault.
    """
    return EFFECTS.register(effect, contributions, states)


def register_module(module: ModuleType | Any, origin: str) -> RegisteredEffect:
    """Register the effect of a module with ``EFFECT``, ``CONTRIBUTIONS`` and optionally ``STATES``."""
    effect = getattr(module, "EFFECT", None)
    contributions = getattr(module, "CONTRIBUTIONS", None)
    if effect is None or contributions is None:
        raise ValueError(
            f"effect from {origin}: {getattr(module, '__name__', module)!r} has no EFFECT and CONTRIBUTIONS "
            f"(an effect module declares both, as the modules in ship_env/model/effects do)"
        )
    return EFFECTS.register(effect, contributions, getattr(module, "STATES", ()), origin)
