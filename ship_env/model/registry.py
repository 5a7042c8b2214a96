"""The registry of physical effects: the built-in library and effects written outside ``ship_env``.

An effect is an :class:`~ship_env.model.declarations.Effect` declaration with its
:class:`~ship_env.model.contributions.Contribution` s to the state derivative. The built-in effects
register themselves (``effects/__init__.py``); an effect of your own registers

- from an installed package, through the entry-point group ``ship_env.effects``: the entry point
  names a module that holds ``EFFECT``, ``CONTRIBUTIONS`` and, if it owns states or draws random
  numbers where a ship starts, ``STATES`` and ``DRAWS`` (as the modules under ``effects/`` do), e.g.
  in ``pyproject.toml``::

      [project.entry-points."ship_env.effects"]
      shallow_water = "my_ships.shallow_water"

- or in a notebook or script, with :func:`register_effect`.

Then :class:`~ship_env.model.ShipModel`, the simulators, the environments and the workbench
(``fit --add``, ``diagnose``, ``improve``) use it like a built-in: its parameters come from the
ship's YAML (``effects: {shallow_water: {enabled: true, ...}}``) or, where the preset has none,
from the parameters' declared defaults.
"""

from __future__ import annotations

import dataclasses
import hashlib
import importlib.metadata
import inspect
import math
import sys
from collections.abc import Callable, Iterable, Iterator, Mapping, Sequence
from dataclasses import dataclass
from functools import cache
from types import ModuleType
from typing import Any, TypeVar

import numba

from ship_env.model import state as S
from ship_env.model.contributions import (
    HELD_QUANTITIES,
    INPUTS,
    QUANTITIES,
    STEP_INPUTS,
    STEP_QUANTITIES,
    WIND,
    Contribution,
    Draw,
    State,
    derivative_quantity,
    white_noise_input,
)
from ship_env.model.declarations import Effect, Parameter

#: The entry-point group effects outside ``ship_env`` register under.
ENTRY_POINT_GROUP = "ship_env.effects"

#: The principal particulars' names (``ship.PRINCIPAL``; here to keep the import order simple).
PRINCIPAL_NAMES = ("length", "breadth", "draught", "service_speed", "rudder_limit", "minimum_speed")
#: Names an effect's state or draw cannot take: what a contribution reads by these names already.
_RESERVED_NAMES = frozenset({*INPUTS, *QUANTITIES, *S.CONDITION_NAMES, *PRINCIPAL_NAMES})


@dataclass(frozen=True)
class RegisteredEffect:
    """An effect in the registry.

    Attributes:
        effect: its declaration.
        contributions: its terms in the state derivative.
        states: the state variables it owns (their rate acts only where it is on).
        origin: where it comes from: ``ship_env`` for the built-ins, else the module or entry point.
        draws: the random numbers it draws for each ship where the ship starts.
    """

    effect: Effect
    contributions: tuple[Contribution, ...]
    states: tuple[State, ...]
    origin: str
    draws: tuple[Draw, ...] = ()

    @property
    def builtin(self) -> bool:
        return self.origin == "ship_env"

    @property
    def new_states(self) -> tuple[State, ...]:
        """The states it adds to the layout (not the motion's, whose rate it may govern)."""
        return tuple(state for state in self.states if state.name not in S.MOTION_STATES)

    def arguments(self, contribution: Contribution | Callable[..., Any]) -> tuple[str, ...]:
        """The names a contribution's function (or a state's or draw's function) reads, in order."""
        function = contribution.function if isinstance(contribution, Contribution) else contribution
        return _arguments(function)


@cache
def _arguments(function: Callable[..., Any]) -> tuple[str, ...]:
    return tuple(inspect.signature(_python_function(function)).parameters)


def state_layout(entries: Sequence[RegisteredEffect]) -> tuple[str, ...]:
    """The names of the state variables, in order: the motion's, then the effects' own, in registration order."""
    return (*S.MOTION_STATES, *(state.name for entry in entries for state in entry.new_states))


def _python_function(function: Callable[..., Any]) -> Callable[..., Any]:
    return getattr(function, "py_func", function)


def _compiled(function: Callable[..., Any], label: str) -> Callable[..., Any]:
    """A function the compiled step calls, compiled (a plain Python function is compiled here, not cached).

    The step that calls it is cached on disk, and numba imports the function's module by its name when
    it loads the step again: a function from a module Python cannot find by name (one run from a file
    with ``importlib`` without entering it in ``sys.modules``) is refused here, saying how to enter it.
    """
    module = getattr(_python_function(function), "__module__", None)
    if module is not None and module not in sys.modules:
        raise ValueError(
            f"{label}: function {getattr(function, '__qualname__', function)!r} is from module {module!r}, "
            "which is not in sys.modules: the compiled step that calls it is cached on disk and imports its "
            f"module by name when it loads; import the module, or enter it before running it "
            f"(sys.modules[{module!r}] = module, as importlib's recipe for a source file does)"
        )
    if isinstance(function, numba.core.registry.CPUDispatcher):
        return function
    return numba.njit(fastmath=False, error_model="numpy")(function)


def _source(function: Callable[..., Any]) -> str:
    """The source a compiled kernel depends on (the function's module, or the function alone), after the
    module's name: a cached kernel imports the module by that name where it is loaded, so the same code
    run as another module (a script, then the same file imported) is another kernel."""
    python = _python_function(function)
    module = inspect.getmodule(python)
    for target in (module, python):
        try:
            return f"{python.__module__}\n{inspect.getsource(target)}"  # type: ignore[arg-type]
        except (OSError, TypeError):
            continue
    code = python.__code__
    return f"{python.__module__}\n{(code.co_code, code.co_consts, code.co_names)!r}"


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
        states: Sequence[State] = (),
        origin: str | None = None,
        draws: Sequence[Draw] = (),
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
        states = self._check_states(effect, tuple(states), where)
        draws = _check_draws(effect, tuple(draws), states, where)
        checked = tuple(self._check_contribution(effect, c, states, draws, where, builtin) for c in contributions)
        for state in states:
            if not any(c.quantity == derivative_quantity(state.name) for c in checked):
                raise ValueError(
                    f"{where}: state {state.name!r}: it has no derivative; add "
                    f"Contribution({derivative_quantity(state.name)!r}, function) to the effect's contributions"
                )
        for state in states:
            for label, function in (("initial", state.initial), ("white_noise", state.white_noise)):
                if callable(function):
                    self._check_arguments(
                        effect, _arguments(function), states, set(), f"{where}: state {state.name!r}: {label}", builtin
                    )
        for draw in draws:
            self._check_draw_arguments(effect, draw, f"{where}: draw {draw.name!r}")
        states = tuple(
            state
            if state.white_noise is None
            else dataclasses.replace(
                state, white_noise=_compiled(state.white_noise, f"{where}: state {state.name!r}: white_noise")
            )
            for state in states
        )
        entry = RegisteredEffect(effect, checked, states, origin, draws)
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

    def _check_states(self, effect: Effect, states: tuple[object, ...], where: str) -> tuple[State, ...]:
        """Each a State with a unit and words, its name free (or a motion state whose rate no other effect governs)."""
        others = {state.name: e for e in self._entries.values() if e.effect.name != effect.name for state in e.states}
        checked = []
        for state, label in _declarations(states, State, where, "the state holds"):
            if state.name in others:
                owner = others[state.name]
                raise ValueError(
                    f"{label}: name: {state.name!r} is already a state of effect {owner.effect.name!r} "
                    f"from {owner.origin}; choose another name"
                )
            if state.name in S.MOTION_STATES and derivative_quantity(state.name) not in QUANTITIES:
                raise ValueError(
                    f"{label}: name: {state.name!r} is a state of the ship's motion, whose rate the model gives; "
                    "choose another name"
                )
            if state.name in _RESERVED_NAMES:
                raise ValueError(f"{label}: name: {state.name!r} is already an input, quantity, condition or principal")
            if not callable(state.initial) and (
                isinstance(state.initial, bool) or not isinstance(state.initial, (int, float))
            ):
                raise TypeError(f"{label}: initial: expected a number or a function, got {state.initial!r}")
            if not callable(state.initial) and not math.isfinite(state.initial):
                raise ValueError(f"{label}: initial: must be finite, got {state.initial!r}")
            if state.white_noise is not None and not callable(state.white_noise):
                raise TypeError(f"{label}: white_noise: expected None or a function, got {state.white_noise!r}")
            checked.append(state)
        return tuple(checked)

    def _check_contribution(
        self,
        effect: Effect,
        contribution: object,
        states: tuple[State, ...],
        draws: tuple[Draw, ...],
        where: str,
        origin_builtin: bool,
    ) -> Contribution:
        if not isinstance(contribution, Contribution):
            raise TypeError(f"{where}: contributions: expected Contribution(quantity, function), got {contribution!r}")
        quantity = contribution.quantity
        derivatives = {derivative_quantity(s.name): s.name for e in self._entries.values() for s in e.new_states}
        derivatives |= {derivative_quantity(s.name): s.name for s in states}
        derivatives |= {derivative_quantity(name): name for name in S.MOTION_STATES}
        if quantity not in QUANTITIES and quantity not in STEP_QUANTITIES and quantity not in derivatives:
            known = ", ".join([*QUANTITIES, *STEP_QUANTITIES, *(q for q in derivatives if q not in QUANTITIES)])
            raise ValueError(f"{where}: contribution quantity {quantity!r} is unknown; known: {known}")
        state = derivatives.get(quantity)
        if state is not None and not any(s.name == state for s in states) and not self._owner(state):
            raise ValueError(
                f"{where}: contribution to {quantity!r}: no effect owns the state {state!r}; "
                f"declare it in the effect's states"
            )
        if contribution.held and quantity not in HELD_QUANTITIES:
            raise ValueError(
                f"{where}: contribution to {quantity!r}: held: only {', '.join(HELD_QUANTITIES)} "
                "can be held over a step"
            )
        if not callable(contribution.function):
            raise TypeError(f"{where}: contribution to {quantity!r}: function: expected a function")
        if quantity in STEP_QUANTITIES:
            earlier = {quantity, *STEP_INPUTS[quantity]}
        elif contribution.held:
            earlier = set()
        elif quantity in QUANTITIES:
            order = list(QUANTITIES)
            earlier = set(order[: order.index(quantity) + 1]) | set(WIND)
        else:
            earlier = set(QUANTITIES) | {quantity}
        arguments = _arguments(contribution.function)
        label = f"{where}: contribution to {quantity!r}"
        self._check_arguments(effect, arguments, states, earlier | {draw.name for draw in draws}, label, origin_builtin)
        return Contribution(quantity, _compiled(contribution.function, label), contribution.held)

    def _check_arguments(
        self,
        effect: Effect,
        arguments: Sequence[str],
        states: tuple[State, ...],
        earlier: set[str],
        where: str,
        origin_builtin: bool,
    ) -> None:
        """Every argument names something the model has at that point."""
        own = {parameter.name for parameter in effect.parameters}
        fields = {f"{e.name}_{p.name}" for e in self.declarations() for p in e.parameters}
        fields |= {f"{effect.name}_{name}" for name in own}
        state_names = {s.name for e in self._entries.values() for s in e.states} | {s.name for s in states}
        noise = {white_noise_input(s.name) for s in states if s.white_noise is not None}
        known = set(INPUTS) | set(S.MOTION_STATES) | state_names | noise | set(S.CONDITION_NAMES)
        known |= set(PRINCIPAL_NAMES) | own | fields
        for argument in arguments:
            if argument in known or argument in earlier or origin_builtin:
                # A built-in may read a built-in's parameter registered after it: ``dynamics`` checks it.
                continue
            raise ValueError(
                f"{where}: argument {argument!r} names nothing the model has at that "
                f"point: use an input ({', '.join(INPUTS)}), a quantity computed before it, a state, a condition, a "
                f"principal particular, one of the effect's parameters ({', '.join(sorted(own)) or 'none'}) or "
                f"another effect's parameter as its record field (e.g. 'yaw_gain')"
            )

    def _check_draw_arguments(self, effect: Effect, draw: Draw, label: str) -> None:
        """Every argument of a draw's function names something known where a ship starts."""
        own = {parameter.name for parameter in effect.parameters}
        fields = {f"{e.name}_{p.name}" for e in self.declarations() for p in e.parameters}
        conditions = (*S.CONDITION_NAMES, *S.START_CONDITION_NAMES)
        known = {"uniforms", *conditions, *PRINCIPAL_NAMES, *own, *fields}
        for argument in _arguments(draw.function):
            if argument not in known:
                raise ValueError(
                    f"{label}: function: argument {argument!r} names nothing known where a ship starts: use "
                    f"'uniforms', a condition ({', '.join(conditions)}), a principal particular, one of the effect's "
                    f"parameters ({', '.join(sorted(own)) or 'none'}) or another effect's parameter as its record field"
                )

    def _owner(self, state: str) -> bool:
        return any(state == s.name for entry in self._entries.values() for s in entry.states)

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
                sources = [f"{c.quantity}:{c.held}:{_source(c.function)}" for c in entry.contributions]
                for state in entry.states:
                    functions = [f for f in (state.initial, state.white_noise) if callable(f)]
                    initial = "" if callable(state.initial) else repr(float(state.initial))
                    sources.append(f"{state.name}:{initial}:{''.join(_source(f) for f in functions)}")
                sources.extend(f"draw {draw.name}:{draw.shape}" for draw in entry.draws)
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
    for parameter, label in _declarations(effect.parameters, Parameter, where, "the number means"):
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


def _check_draws(effect: Effect, draws: tuple[object, ...], states: tuple[State, ...], where: str) -> tuple[Draw, ...]:
    """Each a Draw with a unit and words, a name its contributions can read it by, and shapes of whole numbers."""
    counts = {parameter.name for parameter in effect.parameters if parameter.integer}
    taken = _RESERVED_NAMES | set(S.MOTION_STATES) | {p.name for p in effect.parameters} | {s.name for s in states}
    checked = []
    for draw, label in _declarations(draws, Draw, where, "the numbers are"):
        if draw.name in taken:
            raise ValueError(
                f"{label}: name: {draw.name!r} is already an input, quantity, condition, principal, state or "
                "parameter; choose another name"
            )
        for field, shape in (("shape", draw.shape), ("uniforms", draw.uniforms)):
            if shape is None and field == "uniforms":
                continue
            if not isinstance(shape, tuple) or not shape:
                raise TypeError(f"{label}: {field}: expected a tuple of sizes, got {shape!r}")
            for size in shape:
                if isinstance(size, str) and size in counts:
                    continue
                if isinstance(size, bool) or not isinstance(size, int) or size < 1:
                    raise ValueError(
                        f"{label}: {field}: {size!r} is not a positive whole number nor one of the effect's "
                        f"whole-number parameters ({', '.join(sorted(counts)) or 'none'})"
                    )
        if not callable(draw.function):
            raise TypeError(f"{label}: function: expected a function of the uniforms, got {draw.function!r}")
        if "uniforms" not in _arguments(draw.function):
            raise ValueError(f"{label}: function: it must read its argument 'uniforms' (the samples it draws from)")
        checked.append(draw)
    return tuple(checked)


#: What an effect declares by name, unit and description.
_Declaration = TypeVar("_Declaration", Parameter, State, Draw)


def _declarations(
    items: Iterable[object], kind: type[_Declaration], where: str, meaning: str
) -> Iterator[tuple[_Declaration, str]]:
    """Each item with its label for errors, once checked to be a ``kind`` named by an identifier
    unique among ``items``, with a unit and a description (its error: "say what ``meaning``")."""
    names: set[str] = set()
    for item in items:
        label = f"{where}: {kind.__name__.lower()} {getattr(item, 'name', item)!r}"
        if not isinstance(item, kind):
            raise TypeError(f"{label}: expected a {kind.__name__}(name, unit, description, ...), got {item!r}")
        if not item.name.isidentifier() or item.name in names:
            raise ValueError(f"{label}: name: expected a Python identifier unique in the effect")
        names.add(item.name)
        if not isinstance(item.unit, str) or not item.unit.strip():
            raise ValueError(f"{label}: unit: every {kind.__name__.lower()} needs its SI unit ('-' if dimensionless)")
        if not item.description.strip():
            raise ValueError(f"{label}: description: say what {meaning}")
        yield item, label


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
    effect: Effect, contributions: Sequence[Contribution], states: Sequence[State] = (), draws: Sequence[Draw] = ()
) -> RegisteredEffect:
    """Register an effect written outside ``ship_env`` (from a notebook or a script).

    Args:
        effect: its declaration: name, title, equations, parameters (each with a unit, a finite
            range and, where the presets lack it, a default with its source).
        contributions: its terms in the state derivative (see ``ship_env.model.contributions``).
        states: the state variables it owns (:class:`~ship_env.model.contributions.State`), each with its
            rate among the contributions (``<name>_derivative``); usually none.
        draws: the random numbers it draws for each ship where the ship starts
            (:class:`~ship_env.model.contributions.Draw`), which its contributions read; usually none.

    Registering again under the same name replaces an effect from outside ``ship_env`` (a cell run
    again); a built-in's name is refused. Models built afterwards use it.

    Raises:
        ValueError, TypeError: naming the effect, where it comes from and the field at fault.
    """
    return EFFECTS.register(effect, contributions, states, draws=draws)


def register_module(module: ModuleType | Any, origin: str) -> RegisteredEffect:
    """Register the effect of a module with ``EFFECT``, ``CONTRIBUTIONS`` and optionally ``STATES`` and ``DRAWS``."""
    effect = getattr(module, "EFFECT", None)
    contributions = getattr(module, "CONTRIBUTIONS", None)
    if effect is None or contributions is None:
        raise ValueError(
            f"effect from {origin}: {getattr(module, '__name__', module)!r} has no EFFECT and CONTRIBUTIONS "
            f"(an effect module declares both, as the modules in ship_env/model/effects do)"
        )
    return EFFECTS.register(
        effect, contributions, getattr(module, "STATES", ()), origin, draws=getattr(module, "DRAWS", ())
    )
