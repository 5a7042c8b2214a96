"""The writer of the composed equations: the source of one function from the registered effects' contributions.

:mod:`ship_env.model.dynamics` asks a :class:`Writer` for the code of each composed function (the derivative,
the sway velocity, the contributions held over a step, the white noise, the actual rudder, the initial
states) for the effects a parameter record holds, then compiles it. The writer names no effect: it reads
each effect's contributions, draws and states from the registry entries it is given, and writes them
quantity by quantity in the order of ``contributions.QUANTITIES``, each behind its effect's on/off flag.
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from ship_env.model import contributions, draws
from ship_env.model import state as S
from ship_env.model.contributions import (
    INPUTS,
    QUANTITIES,
    STEP_INPUTS,
    STEP_QUANTITIES,
    WIND,
    derivative_quantity,
    white_noise_input,
)
from ship_env.model.effects.wind import relative_wind
from ship_env.model.noise import standard_normal_pair
from ship_env.model.registry import EFFECTS, PRINCIPAL_NAMES, RegisteredEffect, state_layout

_PREAMBLE = f"""    length = p["length"]
    heading = state[{S.HEADING}]
    rate_of_turn = state[{S.RATE_OF_TURN}]
    speed = conditions[{S.SERVICE_SPEED}] * (1.0 - state[{S.SPEED_LOSS}])  # (2.53)
    scheduling_speed = max(speed, p["minimum_speed"])
    normalised_rate = length * rate_of_turn / scheduling_speed  # (2.40)
    cos_heading = math.cos(heading)
    sin_heading = math.sin(heading)
"""


class Writer:
    """Writes the composed function's source, one contribution at a time."""

    def __init__(self, entries: list[RegisteredEffect], fields: Sequence[str], checked: bool = False) -> None:
        self.entries = entries
        self.fields = set(fields)
        self.checked = checked
        self.lines: list[str] = []
        #: Contributions computed with the apparent wind: (effect, index) -> the variable holding them.
        self.early: dict[tuple[str, int], str] = {}
        #: Arguments read otherwise than usual in the function being written (the held time).
        self.overrides: dict[str, str] = {}
        self.namespace: dict[str, Any] = {
            "math": math,
            "np": np,
            "relative_wind": relative_wind,
            "finite": _finite,
            "standard_normal_pair": standard_normal_pair,
        }
        self.layout = state_layout(entries)
        #: The states driven by white noise, in the order of their noise channels.
        self.noise = [(entry, state) for entry in entries for state in entry.states if state.white_noise is not None]
        self.derivatives = {derivative_quantity(name) for name in self.layout}

    def expression(self, argument: str, entry: RegisteredEffect) -> str:
        """The code that reads a contribution's argument."""
        own = {parameter.name for parameter in entry.effect.parameters}
        if argument in self.overrides:
            return self.overrides[argument]
        for draw in entry.draws:
            if argument == draw.name:
                return self.draw(entry, draw)
        channels = [white_noise_input(state.name) for _, state in self.noise]
        if argument in channels:
            return f"white_noise[{channels.index(argument)}]"
        if argument in QUANTITIES or argument in INPUTS or argument in self.derivatives:
            return argument
        if argument in STEP_QUANTITIES or any(argument in n for n in STEP_INPUTS.values()):
            return argument
        if argument == "rudder":
            return "rudder"
        if argument in self.layout:
            return f"state[{self.layout.index(argument)}]"
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

    def draw(self, entry: RegisteredEffect, draw: contributions.Draw) -> str:
        """The code that reads one of an effect's draws: its slice of the ship's row, in its shape."""
        start = f'p["{draws.start_field(entry.effect.name, draw)}"]'
        sizes = [
            f'int(p["{entry.effect.field_name(size)}"])' if isinstance(size, str) else str(size) for size in draw.shape
        ]
        view = f"draws[{start} : {start} + {' * '.join(sizes)}]"
        return view if len(sizes) == 1 else f"{view}.reshape(({', '.join(sizes)}))"

    def call(self, entry: RegisteredEffect, index: int) -> str:
        contribution = entry.contributions[index]
        return self.call_function(entry, contribution.function, f"{entry.effect.name}_{index}", contribution.quantity)

    def call_function(self, entry: RegisteredEffect, function: Callable[..., Any], name: str, what: str) -> str:
        """The code that calls one of an effect's functions on what its arguments name."""
        self.namespace[name] = function
        arguments = ", ".join(self.expression(argument, entry) for argument in entry.arguments(function))
        if self.checked:
            return f"finite({name}({arguments}), {entry.effect.name!r}, {what!r})"
        return f"{name}({arguments})"

    def function(self, signature: str, returns: str = "") -> str:
        """The source of a function of the lines written, after the preamble's lines they read."""
        body = "\n".join(self.lines)
        preamble: list[str] = []
        for line in reversed(_PREAMBLE.rstrip("\n").split("\n")):
            if re.search(rf"\b{line.split('=')[0].strip()}\b", body + "".join(preamble)):
                preamble.insert(0, line)
        returned = f"\n    return {returns}" if returns else ""
        return f"def {signature}:\n" + "\n".join([*preamble, body]) + f"{returned}\n"

    def emit(self, line: str, depth: int = 1) -> None:
        self.lines.append("    " * depth + line)

    def start(self, quantity: str, depth: int) -> None:
        """The quantity at its starting value."""
        if quantity == "ground_velocity":
            self.emit("north_rate = 0.0", depth)
            self.emit("east_rate = 0.0", depth)
        else:
            self.emit(f"{quantity} = {_start(quantity)}", depth)

    def apply(self, entry: RegisteredEffect, index: int, depth: int) -> None:
        """One contribution: added to its quantity, or replacing it where it reads it."""
        quantity = entry.contributions[index].quantity
        call = self.call(entry, index)
        if quantity == "ground_velocity":
            self.emit(f"added_north, added_east = {call}", depth)
            self.emit("north_rate += added_north", depth)
            self.emit("east_rate += added_east", depth)
        elif quantity in entry.arguments(entry.contributions[index]) or quantity in STEP_QUANTITIES:
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
            if contribution.quantity == quantity
            and (select(entry, index) if select is not None else not contribution.held)
        ]
        if fresh:
            first = chosen[0] if chosen else None
            if (
                first is not None
                and _start(quantity) in ("0.0", "(0.0, 0.0)")
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
            f"cos_heading, sin_heading, north_rate, east_rate, conditions[{S.WIND_NORTH}], conditions[{S.WIND_EAST}])",
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
        for index in range(len(self.layout)):
            if index not in rates:
                self.emit(f"out[{index}] = 0.0")
        for entry in self.entries:
            if not entry.states:
                continue
            depth = 1 if entry.effect.required else 2
            if depth == 2:
                self.emit(f'if p["{entry.effect.flag_name}"]:')
            for state in entry.states:
                quantity = derivative_quantity(state.name)
                self.quantity(quantity, depth, flag_checked=entry.effect.flag_name)
                self.emit(f"out[{self.layout.index(state.name)}] = {quantity}", depth)

    def derivative(self) -> str:
        self.motion()
        done = {"sway_velocity", "ground_velocity", *WIND, *self.derivatives}
        for quantity in QUANTITIES:
            if quantity not in done:
                self.quantity(quantity)
        self.state_rates()
        return self.function(
            "derivatives(state, rudder, conditions, white_noise, draws, held_yaw_acceleration, p, out)"
        )

    def held(self) -> str:
        """The contributions held over the step, each on top of the last, with the time at mid-step."""
        self.emit("mid_step_time = state[0] + 0.5 * dt")
        self.overrides = {"time": "mid_step_time", "rudder": f"state[{S.RUDDER}]"}
        self.emit("held = 0.0")
        first = True
        for entry in self.entries:
            for index, contribution in enumerate(entry.contributions):
                if not contribution.held:
                    continue
                # The first is assigned, not added to 0: the sum keeps a -0.0 as the hand-written step did.
                update = self.call(entry, index) if first else f"held + {self.call(entry, index)}"
                if entry.effect.required:
                    self.emit(f"held = {update}")
                else:
                    self.emit(f'if p["{entry.effect.flag_name}"]:')
                    self.emit(f"held = {update}", 2)
                first = False
        return self.function("held_yaw_acceleration(state, conditions, draws, dt, p)", "held")

    def white_noise(self) -> str:
        """Unit white noise for the noise-driven states (over sqrt(dt)), drawn where an intensity is not 0.

        Channel pair k of step j is drawn at counter j + k 2^40: the first pair's are the step's
        own counters whatever else is registered.
        """
        self.overrides = {"rudder": f"state[{S.RUDDER}]"}
        for channel in range(len(self.noise)):
            self.emit(f"out[{channel}] = 0.0")
        self.emit("draw = False")
        for position, (entry, state) in enumerate(self.noise):
            assert state.white_noise is not None  # ``self.noise`` holds the noise-driven states
            condition = f"{self.call_function(entry, state.white_noise, f'noise_{position}', state.name)} != 0.0"
            if not entry.effect.required:
                condition = f'p["{entry.effect.flag_name}"] and {condition}'
            self.emit(f"if not draw and {condition}:")
            self.emit("draw = True", 2)
        if self.noise:
            self.emit("if draw:")
            for pair in range(0, len(self.noise), 2):
                counter = f"np.uint64(step_index) + np.uint64({(pair // 2) << 40})" if pair else "np.uint64(step_index)"
                self.emit(f"first, second = standard_normal_pair(noise_key, {counter})", 2)
                self.emit(f"out[{pair}] = first / math.sqrt(dt)", 2)
                if pair + 1 < len(self.noise):
                    self.emit(f"out[{pair + 1}] = second / math.sqrt(dt)", 2)
        return self.function("draw_white_noise(state, conditions, noise_key, step_index, dt, p, out)")

    def rudder(self) -> str:
        """The actual rudder ``duration`` s into the step: the limited order, or where an actuator takes it."""
        self.quantity("actual_rudder", select=lambda entry, index: True)
        return self.function("actual_rudder(state, rudder, limited_order, duration, conditions, p)", "actual_rudder")

    def initial(self) -> str:
        """Write the effects' states' initial values into a state whose motion is set."""
        self.overrides = {"rudder": f"state[{S.RUDDER}]"}
        for entry in self.entries:
            for state in entry.new_states:
                index = self.layout.index(state.name)
                if not callable(state.initial):
                    self.emit(f"state[{index}] = {float(state.initial)!r}")
                    continue
                self.emit(f"state[{index}] = 0.0")
                call = self.call_function(entry, state.initial, f"initial_{index}", state.name)
                if entry.effect.required:
                    self.emit(f"state[{index}] = {call}")
                else:
                    self.emit(f'if p["{entry.effect.flag_name}"]:')
                    self.emit(f"state[{index}] = {call}", 2)
        return self.function("start_states(state, conditions, p)")

    def sway(self) -> str:
        self.quantity("sway_velocity")
        return self.function("sway_velocity(state, conditions, p)", "sway_velocity")


def _start(quantity: str) -> str:
    """A quantity's starting value: as ``QUANTITIES`` (or ``STEP_QUANTITIES``) says, 0 for a state's rate."""
    if quantity in QUANTITIES:
        return QUANTITIES[quantity][0]
    return STEP_QUANTITIES[quantity][0] if quantity in STEP_QUANTITIES else "0.0"


def _finite(value: Any, effect: str, quantity: str) -> Any:
    """``value`` if every number in it is finite, else a ValueError naming the effect and quantity."""
    if all(math.isfinite(number) for number in np.atleast_1d(np.asarray(value, dtype=float))):
        return value
    raise ValueError(
        f"effect {effect!r} from {EFFECTS.entry(effect).origin}: its contribution to {quantity!r} is {value!r}"
    )
