"""The ship's equations of motion: the registered effects' contributions composed into one derivative.

``derivatives`` evaluates d(state)/dt for one ship at one instant. It names no effect: its code is
written from the registry (``registry.EFFECTS``) for the effects a parameter record holds, each
contribution behind its effect's on/off flag, quantity by quantity in the order of
``contributions.QUANTITIES``:

1. speed u = U0 (1 - u*) (2.53) and normalised rate of turn r* = L r / u (2.40);
2. sway v, then the velocity over the ground (2.64);
3. the apparent wind (2.74), where an effect that reads it is on, then the contributions that
   read it;
4. effective rudder and rudder inflow, H(r*) and side moments;
5. yaw accelerations (the hull's, then the outside moments on top of the one held over the step),
   and the rates of the states effects own (speed loss, disturbance states).

The code is compiled where a compiled caller (``integrators.step_ship``) meets a record type: the
record's fields name the effects, and its ``equations_<hash>`` field the version of their
equations, so numba's on-disk cache holds one compiled step per set of effects and is never
reused for changed equations. :func:`source` shows the code for a record.

The actual rudder is not integrated here: the steering machine moves it exactly (see
``integrators``), and the derivative takes the rudder angle at the instant as an argument.
"""

from __future__ import annotations

import hashlib
import inspect
import math
import sys
import warnings
from collections.abc import Callable, Sequence
from functools import cache
from typing import Any

import numpy as np
from numba import types
from numba.core.errors import NumbaIRAssumptionWarning
from numba.extending import overload

from ship_env.model import contributions
from ship_env.model import state as S
from ship_env.model.contributions import INPUTS, QUANTITIES, STATE_DERIVATIVES, WIND
from ship_env.model.effects.wind import relative_wind
from ship_env.model.registry import EFFECTS, PRINCIPAL_NAMES, RegisteredEffect

#: The record field that names the version of the effects' equations (``equations_<hash>``).
FINGERPRINT_PREFIX = "equations_"

_INPUT_EXPRESSIONS = {
    "wave_white_noise": f"white_noise[{S.NOISE_WAVE}]",
    "gust_white_noise": f"white_noise[{S.NOISE_GUST}]",
}
_PREAMBLE = f"""    length = p["length"]
    heading = state[{S.HEADING}]
    rate_of_turn = state[{S.RATE_OF_TURN}]
    speed = conditions[{S.SERVICE_SPEED}] * (1.0 - state[{S.SPEED_LOSS}])  # (2.53)
    scheduling_speed = max(speed, p["minimum_speed"])
    normalised_rate = length * rate_of_turn / scheduling_speed  # (2.40)
    cos_heading = math.cos(heading)
    sin_heading = math.sin(heading)
"""


def _composer_source() -> str:
    """The source of what writes the composed code: this module, the quantities and the state layout."""
    return "".join(inspect.getsource(module) for module in (sys.modules[__name__], contributions, S))


def fingerprint(effects: Sequence[str]) -> str:
    """A short hash of the composed code's sources: the effects' equations and the composer's."""
    composed = f"{EFFECTS.fingerprint(effects)}:{_COMPOSER_SOURCE}"
    return hashlib.sha256(composed.encode()).hexdigest()[:16]


def record_effects(field_names: Sequence[str]) -> tuple[list[str], str]:
    """The effects a parameter record holds (its flags, in order) and its equations' fingerprint."""
    effects = [name[:-3] for name in field_names if name.endswith("_on") and name[:-3] in EFFECTS]
    found = next((name[len(FINGERPRINT_PREFIX) :] for name in field_names if name.startswith(FINGERPRINT_PREFIX)), "")
    if found != fingerprint(effects):
        raise ValueError(
            "derivatives: the parameter record was built for other equations than the effects registered now "
            f"({', '.join(effects)}); build the ShipModel again after registering an effect"
        )
    return effects, found


class _Writer:
    """Writes the composed function's source, one contribution at a time."""

    def __init__(self, entries: list[RegisteredEffect], fields: Sequence[str], checked: bool = False) -> None:
        self.entries = entries
        self.fields = set(fields)
        self.checked = checked
        self.lines: list[str] = []
        #: Contributions computed with the apparent wind: (effect, index) -> the variable holding them.
        self.early: dict[tuple[str, int], str] = {}
        self.namespace: dict[str, Any] = {"math": math, "relative_wind": relative_wind, "finite": _finite}

    def expression(self, argument: str, entry: RegisteredEffect) -> str:
        """The code that reads a contribution's argument."""
        own = {parameter.name for parameter in entry.effect.parameters}
        if argument in QUANTITIES or argument in INPUTS and argument not in _INPUT_EXPRESSIONS:
            return argument
        if argument in _INPUT_EXPRESSIONS:
            return _INPUT_EXPRESSIONS[argument]
        if argument == "rudder":
            return "rudder"
        if argument in S.STATE_NAMES:
            return f"state[{S.STATE_NAMES.index(argument)}]"
        if argument in S.CONDITION_NAMES:
            return f"conditions[{S.CONDITION_NAMES.index(argument)}]"
        if argument in own:
            return f'p["{entry.effect.field_name(argument)}"]'
        if argument in PRINCIPAL_NAMES or argument in self.fields:
            return f'p["{argument}"]'
        raise ValueError(
            f"effect {entry.effect.name!r} from {entry.origin}: argument {argument!r} of its contribution names "
            "nothing the model has: no input, quantity, state, condition, principal particular or parameter"
        )

    def call(self, entry: RegisteredEffect, index: int) -> str:
        contribution = entry.contributions[index]
        name = f"{entry.effect.name}_{index}"
        self.namespace[name] = contribution.function
        arguments = ", ".join(self.expression(argument, entry) for argument in entry.arguments(contribution))
        if self.checked:
            return f"finite({name}({arguments}), {entry.effect.name!r}, {contribution.quantity!r})"
        return f"{name}({arguments})"

    def emit(self, line: str, depth: int = 1) -> None:
        self.lines.append("    " * depth + line)

    def start(self, quantity: str, depth: int) -> None:
        """The quantity at its starting value."""
        if quantity == "ground_velocity":
            self.emit("north_rate = 0.0", depth)
            self.emit("east_rate = 0.0", depth)
        else:
            self.emit(f"{quantity} = {QUANTITIES[quantity][0]}", depth)

    def apply(self, entry: RegisteredEffect, index: int, depth: int) -> None:
        """One contribution: added to its quantity, or replacing it where it reads it."""
        quantity = entry.contributions[index].quantity
        call = self.call(entry, index)
        if quantity == "ground_velocity":
            self.emit(f"added_north, added_east = {call}", depth)
            self.emit("north_rate += added_north", depth)
            self.emit("east_rate += added_east", depth)
        elif quantity in entry.arguments(entry.contributions[index]):
            self.emit(f"{quantity} = {call}", depth)
        elif (entry.effect.name, index) in self.early:
            self.emit(f"{quantity} = {quantity} + {self.early[entry.effect.name, index]}", depth)
        else:
            self.emit(f"{quantity} = {quantity} + {call}", depth)

    def quantity(
        self,
        quantity: str,
        depth: int = 1,
        select: Callable[[RegisteredEffect, int], bool] | None = None,
        flag_checked: str = "",
        fresh: bool = True,
    ) -> None:
        """Apply the contributions to ``quantity`` (those ``select`` picks), each behind its effect's flag.

        A required effect, or the effect whose flag ``flag_checked`` the code already checked, needs none.
        A ``fresh`` quantity starts from its value in ``QUANTITIES``, or from a first contribution that
        always adds (a required effect's) without adding it to 0.
        """
        chosen = [
            (entry, index)
            for entry in self.entries
            for index, contribution in enumerate(entry.contributions)
            if contribution.quantity == quantity and (select is None or select(entry, index))
        ]
        if fresh:
            first = chosen[0] if chosen else None
            if (
                first is not None
                and QUANTITIES[quantity][0] in ("0.0", "(0.0, 0.0)")
                and (first[0].effect.required or first[0].effect.flag_name == flag_checked)
                and (first[0].effect.name, first[1]) not in self.early
                and quantity not in first[0].arguments(first[0].contributions[first[1]])
            ):
                target = "north_rate, east_rate" if quantity == "ground_velocity" else quantity
                self.emit(f"{target} = {self.call(*first)}", depth)
                chosen = chosen[1:]
            else:
                self.start(quantity, depth)
        for entry, index in chosen:
            if (entry.effect.name, index) in self.early:
                # Computed with the wind (0 where its effect is off): added as it stands.
                self.apply(entry, index, depth)
            elif entry.effect.required or entry.effect.flag_name == flag_checked:
                self.apply(entry, index, depth)
            else:
                self.emit(f'if p["{entry.effect.flag_name}"]:', depth)
                self.apply(entry, index, depth + 1)

    def reads_wind(self, entry: RegisteredEffect, index: int) -> bool:
        contribution = entry.contributions[index]
        return contribution.quantity not in WIND and bool(set(entry.arguments(contribution)) & set(WIND))

    def wind(self) -> None:
        """The apparent wind, where an effect that reads it is on, with what reads it.

        The contributions that read it and add to a later quantity are computed here, into a value
        that stays 0 where their effect is off, and added in their quantity's turn.
        """
        for name in WIND:
            self.emit(f"{name} = {QUANTITIES[name][0]}")
        readers = [(e, i) for e in self.entries for i in range(len(e.contributions)) if self.reads_wind(e, i)]
        flags = list(dict.fromkeys(entry.effect.flag_name for entry, _ in readers))
        later = [
            (e, i)
            for e, i in readers
            if e.contributions[i].quantity != "ground_velocity"
            and e.contributions[i].quantity not in e.arguments(e.contributions[i])
        ]
        for entry, index in later:
            self.early[entry.effect.name, index] = f"{entry.effect.name}_{index}_value"
            self.emit(f"{entry.effect.name}_{index}_value = 0.0")
        if not readers:
            return
        self.emit(f"if {' or '.join(f'p[{flag!r}]' for flag in flags)}:")
        self.emit(
            "relative_wind_speed, cos_wind, sin_wind = relative_wind("
            f"cos_heading, sin_heading, north_rate, east_rate, conditions[{S.WIND_SPEED}], "
            f"conditions[{S.WIND_DIRECTION}])",
            2,
        )
        for name in WIND:
            self.quantity(name, 2, fresh=False)
        self.quantity("ground_velocity", 2, self.reads_wind, fresh=False)
        for entry, index in later:
            self.emit(f'if p["{entry.effect.flag_name}"]:', 2)
            self.emit(f"{self.early[entry.effect.name, index]} = {self.call(entry, index)}", 3)

    def motion(self) -> None:
        """Sway and the velocity over the ground, the wind, and what reads it."""
        self.quantity("sway_velocity")
        self.quantity("ground_velocity", select=lambda e, i: not self.reads_wind(e, i))
        self.wind()

    def state_rates(self) -> None:
        """d/dt of every state: the kinematics, the yaw, and the states effects own (where their owner is on)."""
        rates = {
            S.TIME: "1.0",
            S.NORTH: "north_rate",
            S.EAST: "east_rate",
            S.HEADING: "rate_of_turn",
            S.RATE_OF_TURN: "hull_yaw_acceleration + yaw_acceleration",
            S.RUDDER: "0.0",
        }
        for index, rate in rates.items():
            self.emit(f"out[{index}] = {rate}")
        owned = [(name, entry) for entry in self.entries for name in entry.states]
        for index in range(S.STATE_SIZE):
            if index not in rates:
                self.emit(f"out[{index}] = 0.0")
        for owner in dict.fromkeys(entry.effect.name for _, entry in owned):
            entry = next(e for _, e in owned if e.effect.name == owner)
            depth = 1 if entry.effect.required else 2
            if depth == 2:
                self.emit(f'if p["{entry.effect.flag_name}"]:')
            for name in entry.states:
                quantity = STATE_DERIVATIVES[name]
                self.quantity(quantity, depth, flag_checked=entry.effect.flag_name)
                self.emit(f"out[{S.STATE_NAMES.index(name)}] = {quantity}", depth)

    def derivative(self) -> str:
        self.lines.append(_PREAMBLE.rstrip("\n"))
        self.motion()
        done = {"sway_velocity", "ground_velocity", *WIND, *STATE_DERIVATIVES.values()}
        for quantity in QUANTITIES:
            if quantity not in done:
                self.quantity(quantity)
        self.state_rates()
        body = "\n".join(self.lines)
        return f"def derivatives(state, rudder, conditions, white_noise, held_yaw_acceleration, p, out):\n{body}\n"

    def sway(self) -> str:
        self.lines.append(_PREAMBLE.rstrip("\n"))
        self.quantity("sway_velocity")
        body = "\n".join(self.lines)
        return f"def sway_velocity(state, conditions, p):\n{body}\n    return sway_velocity\n"


_COMPOSER_SOURCE = _composer_source()


def _finite(value: Any, effect: str, quantity: str) -> Any:
    """``value`` if every number in it is finite, else a ValueError naming the effect and quantity."""
    if all(math.isfinite(number) for number in np.atleast_1d(np.asarray(value, dtype=float))):
        return value
    raise ValueError(
        f"effect {effect!r} from {EFFECTS.entry(effect).origin}: its contribution to {quantity!r} is {value!r}"
    )


@cache
def _composed(kind: str, field_names: tuple[str, ...], fingerprint: str) -> tuple[Callable[..., Any], str]:
    """The composed Python function of ``kind`` ('derivatives', 'checked' or 'sway') for a record, and its source.

    'checked' is ``derivatives`` checking each contribution for a NaN or infinity as it goes.
    """
    effects, _ = record_effects(field_names)
    writer = _Writer([EFFECTS.entry(name) for name in effects], field_names, checked=kind == "checked")
    code = writer.sway() if kind == "sway" else writer.derivative()
    exec(compile(code, f"<ship_env.model.dynamics {kind} {fingerprint}>", "exec"), writer.namespace)
    return writer.namespace["sway_velocity" if kind == "sway" else "derivatives"], code


def _field_names(p: Any) -> tuple[str, ...]:
    """A record's field names, from numpy (a record) or numba (its type)."""
    if isinstance(p, types.Record):
        return tuple(p.fields)
    return tuple(np.asarray(p).dtype.names or ())


def _implementation(kind: str, p: Any) -> Callable[..., Any]:
    names = _field_names(p)
    _, fingerprint = record_effects(names)
    return _composed(kind, names, fingerprint)[0]


def source(record: np.ndarray) -> str:
    """The code of ``derivatives`` composed for a parameter record (``ShipModel.record``)."""
    names = _field_names(record)
    return _composed("derivatives", names, record_effects(names)[1])[1]


def derivatives(state, rudder, conditions, white_noise, held_yaw_acceleration, p, out):
    """Write d(state)/dt into ``out`` for one ship.

    Args:
        state: the ship's state, layout in ``state``.
        rudder: the actual rudder angle at this instant, rad.
        conditions: the ship's conditions (service speed, propeller rate, current, wind, waves).
        white_noise: the white-noise inputs held over the step (already scaled by 1/sqrt(dt)).
        held_yaw_acceleration: a yaw acceleration held over the step, rad/s^2 (the wave
            spectrum's excitation, 2.91).
        p: the model's parameter record (see ``ShipModel.record``).
        out: array of the state's size receiving the derivative.
    """
    _implementation("derivatives", p)(state, rudder, conditions, white_noise, held_yaw_acceleration, p, out)


def sway_velocity(state, conditions, p):
    """The sway velocity v (m/s) of one ship, without leeway, for observations and drawings."""
    return _implementation("sway", p)(state, conditions, p)


_JIT_OPTIONS = {"fastmath": False, "error_model": "numpy"}


@overload(derivatives, jit_options=_JIT_OPTIONS, inline="always")
def _derivatives_overload(state, rudder, conditions, white_noise, held_yaw_acceleration, p, out):
    # The composed derivative is inlined into its compiled callers: called, a batch of minimal ships
    # steps 3-7 % slower than with the hand-written derivative; inlined, some 10 % faster (one thread,
    # benchmarks/bench_simulator.py). numba's pedantic SSA check
    # then warns that the inlined function's variables are "not in scope": a check of numba's own IR,
    # not of the code (the results are bit for bit the hand-written derivative's). Those warnings
    # alone, naming the inlined ``derivatives``' variables, are silenced while the caller compiles.
    warnings.filterwarnings("ignore", r"variable 'derivatives_v\d+_", NumbaIRAssumptionWarning)
    return _implementation("derivatives", p)


@overload(sway_velocity, jit_options=_JIT_OPTIONS)
def _sway_velocity_overload(state, conditions, p):
    return _implementation("sway", p)


def check_contributions(model: Any) -> None:
    """Evaluate the contributions of a model's effects from outside ``ship_env`` at a few states.

    A contribution that gives a NaN or an infinity where the ship sails normally (at service
    speed, turning either way, in wind, current and a propeller's slipstream) raises a ValueError
    naming the effect, where it comes from and the quantity, before any simulation runs.
    """
    if all(EFFECTS.entry(name).builtin for name in model.effects):
        return
    record = model.record[0]
    names = _field_names(model.record)
    composed = _composed("checked", names, record_effects(names)[1])[0]
    conditions = np.zeros(S.CONDITION_SIZE)
    conditions[S.SERVICE_SPEED] = model.service_speed
    conditions[S.PROPELLER_RATE] = 1.5
    conditions[S.CURRENT_SPEED] = 0.3
    conditions[S.WIND_SPEED] = 10.0
    conditions[S.WIND_DIRECTION] = math.radians(45.0)
    out = np.zeros(S.STATE_SIZE)
    for sign in (1.0, -1.0):
        state = np.zeros(S.STATE_SIZE)
        state[S.HEADING] = 0.3
        state[S.RATE_OF_TURN] = sign * math.radians(0.3)
        state[S.SPEED_LOSS] = 0.05
        rudder = sign * math.radians(20.0)
        composed(state, rudder, conditions, np.ones(S.NOISE_SIZE), 0.0, record, out)
