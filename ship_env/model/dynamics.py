"""The ship's equations of motion: the registered effects' contributions composed into one derivative.

``derivatives`` evaluates d(state)/dt for one ship at one instant. It names no effect: its code is
written (by :class:`~ship_env.model.composer.Writer`) from the registry (``registry.EFFECTS``) for the
effects a parameter record holds, each contribution behind its effect's on/off flag, quantity by
quantity in the order of ``contributions.QUANTITIES``:

1. speed u = U0 (1 - u*) (2.53) and normalised rate of turn r* = L r / u (2.40);
2. sway v, then the velocity over the ground (2.64);
3. the apparent wind (2.74), where an effect that reads it is on, then the contributions that
   read it;
4. effective rudder and rudder inflow, H(r*) and side moments;
5. yaw accelerations (the hull's, then the outside moments on top of the one held over the step),
   and the rates of the states effects own (speed loss, disturbance states, a user effect's own).

The state's layout is the motion's states, then the effects' own (``registry.state_layout``); the
integrator's other per-step pieces are composed the same way, so that it names no effect either:
the contributions held over a step (:func:`held_yaw_acceleration`), the white noise that drives
the states declared noise-driven (:func:`draw_white_noise`), the actual rudder a rudder actuator
reaches (:func:`actual_rudder`); and the states' initial values (:func:`start_states`).

The code is compiled where a compiled caller (``integrators.step_ship``) meets a record type: the
record's fields name the effects, and its ``equations_<hash>`` field the version of their
equations, so numba's on-disk cache holds one compiled step per set of effects and is never
reused for changed equations. :func:`source` shows the code for a record.

The actual rudder is not integrated here: :func:`actual_rudder` moves it exactly (see
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

from ship_env.model import composer, contributions, draws, noise
from ship_env.model import state as S
from ship_env.model.composer import Writer
from ship_env.model.registry import EFFECTS, state_layout

#: The record field that names the version of the effects' equations (``equations_<hash>``).
FINGERPRINT_PREFIX = "equations_"


def _composer_source() -> str:
    """The source of what writes the composed code: this module, the writer, the quantities and the state layout."""
    modules = (sys.modules[__name__], composer, contributions, draws, S, noise)
    return "".join(inspect.getsource(module) for module in modules)


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


_COMPOSER_SOURCE = _composer_source()

#: The composed functions: kind -> (the writer's method, the function's name).
_KINDS = {
    "derivatives": ("derivative", "derivatives"),
    "checked": ("derivative", "derivatives"),
    "sway": ("sway", "sway_velocity"),
    "held": ("held", "held_yaw_acceleration"),
    "white_noise": ("white_noise", "draw_white_noise"),
    "rudder": ("rudder", "actual_rudder"),
    "initial": ("initial", "start_states"),
}


@cache
def _composed(kind: str, field_names: tuple[str, ...], fingerprint: str) -> tuple[Callable[..., Any], str]:
    """The composed Python function of ``kind`` (a key of ``_KINDS``) for a record, and its source.

    'checked' is ``derivatives`` checking each contribution for a NaN or infinity as it goes.
    """
    effects, _ = record_effects(field_names)
    writer = Writer([EFFECTS.entry(name) for name in effects], field_names, checked=kind == "checked")
    method, name = _KINDS[kind]
    code = getattr(writer, method)()
    exec(compile(code, f"<ship_env.model.dynamics {kind} {fingerprint}>", "exec"), writer.namespace)
    return writer.namespace[name], code


def _field_names(p: Any) -> tuple[str, ...]:
    """A record's field names, from numpy (a record) or numba (its type)."""
    if isinstance(p, types.Record):
        return tuple(p.fields)
    return tuple(np.asarray(p).dtype.names or ())


def _implementation(kind: str, p: Any) -> Callable[..., Any]:
    names = _field_names(p)
    _, fingerprint = record_effects(names)
    return _composed(kind, names, fingerprint)[0]


def source(record: np.ndarray, kind: str = "derivatives") -> str:
    """The code of ``derivatives`` (or another kind of ``_KINDS``) composed for a parameter record."""
    names = _field_names(record)
    return _composed(kind, names, record_effects(names)[1])[1]


def state_names(record: np.ndarray) -> tuple[str, ...]:
    """The state's layout for a parameter record: the motion's states, then the effects' own."""
    effects, _ = record_effects(_field_names(record))
    return state_layout([EFFECTS.entry(name) for name in effects])


def start_states(states: np.ndarray, conditions: np.ndarray, record: np.ndarray) -> None:
    """Write the effects' states' initial values into rows of ``states`` whose motion is set (in place).

    Args:
        states: (N, state size) states, one row per ship.
        conditions: (N, CONDITION_SIZE) the conditions each ship starts in.
        record: the model's parameter record (``ShipModel.record``).
    """
    names = _field_names(record)
    function = _composed("initial", names, record_effects(names)[1])[0]
    for state, row in zip(states, conditions, strict=True):
        function(state, row, record[0])


def derivatives(state, rudder, conditions, white_noise, draws, held_yaw_acceleration, p, out):
    """Write d(state)/dt into ``out`` for one ship.

    Args:
        state: the ship's state, layout in ``state``.
        rudder: the actual rudder angle at this instant, rad.
        conditions: the ship's conditions (service speed, propeller rate, current, wind, waves).
        white_noise: the white-noise inputs held over the step (already scaled by 1/sqrt(dt)).
        draws: the ship's row of draws (``ShipModel.draw``), the random numbers drawn where it started.
        held_yaw_acceleration: a yaw acceleration held over the step, rad/s^2 (the wave
            spectrum's excitation, 2.91).
        p: the model's parameter record (see ``ShipModel.record``).
        out: array of the state's size receiving the derivative.
    """
    _implementation("derivatives", p)(state, rudder, conditions, white_noise, draws, held_yaw_acceleration, p, out)


def sway_velocity(state, conditions, p):
    """The sway velocity v (m/s) of one ship, without leeway, for observations and drawings."""
    return _implementation("sway", p)(state, conditions, p)


_JIT_OPTIONS = {"fastmath": False, "error_model": "numpy"}


@overload(derivatives, jit_options=_JIT_OPTIONS, inline="always")
def _derivatives_overload(state, rudder, conditions, white_noise, draws, held_yaw_acceleration, p, out):
    # The composed derivative is inlined into its compiled callers: called, a batch of minimal ships
    # steps slower than with the hand-written derivative; inlined, faster (docs/results/benchmarks.md,
    # benchmarks/bench_simulator.py). numba's pedantic SSA check
    # then warns that the inlined function's variables are "not in scope": a check of numba's own IR,
    # not of the code (the results are bit for bit the hand-written derivative's). Those warnings
    # alone, naming the inlined ``derivatives``' variables, are silenced while the caller compiles.
    warnings.filterwarnings("ignore", r"variable 'derivatives_v\d+_", NumbaIRAssumptionWarning)
    return _implementation("derivatives", p)


@overload(sway_velocity, jit_options=_JIT_OPTIONS)
def _sway_velocity_overload(state, conditions, p):
    return _implementation("sway", p)


def held_yaw_acceleration(state, conditions, draws, dt, p):
    """The yaw acceleration the contributions ``held`` over a step give, rad/s^2 (the sea's, 2.91).

    Evaluated once per step, with the time at mid-step and the other states at the step's start.
    """
    return _implementation("held", p)(state, conditions, draws, dt, p)


def draw_white_noise(state, conditions, noise_key, step_index, dt, p, out):
    """Write the step's white noise, one channel per noise-driven state, into ``out`` (0 where none is needed).

    The noise is drawn only where a noise-driven state's intensity is not zero: a gust's is I V_w,
    an exact zero in calm air, so skipping the draw there changes no bit of the state (only the sign
    of a zero slope may differ) and saves a logarithm, a square root, a sine and a cosine a step.
    """
    _implementation("white_noise", p)(state, conditions, noise_key, step_index, dt, p, out)


def actual_rudder(state, rudder, limited_order, duration, conditions, p):
    """The actual rudder ``duration`` s into a step that started at ``rudder``, for the limited order, rad."""
    return _implementation("rudder", p)(state, rudder, limited_order, duration, conditions, p)


@overload(held_yaw_acceleration, jit_options=_JIT_OPTIONS, inline="always")
def _held_overload(state, conditions, draws, dt, p):
    return _implementation("held", p)


@overload(draw_white_noise, jit_options=_JIT_OPTIONS, inline="always")
def _white_noise_overload(state, conditions, noise_key, step_index, dt, p, out):
    warnings.filterwarnings("ignore", r"variable 'draw_white_noise_v\d+_", NumbaIRAssumptionWarning)
    return _implementation("white_noise", p)


@overload(actual_rudder, jit_options=_JIT_OPTIONS, inline="always")
def _actual_rudder_overload(state, rudder, limited_order, duration, conditions, p):
    warnings.filterwarnings("ignore", r"variable 'actual_rudder_v\d+_", NumbaIRAssumptionWarning)
    return _implementation("rudder", p)


def state_size(p):
    """The number of state variables of a parameter record's layout: a constant of the compiled code,
    so that the integrator's loops over the state have a fixed length (unrolled as with a literal)."""
    return len(state_names(np.asarray(p)))


@overload(state_size, jit_options=_JIT_OPTIONS, inline="always")
def _state_size_overload(p):
    effects, _ = record_effects(_field_names(p))
    size = len(state_layout([EFFECTS.entry(name) for name in effects]))
    return lambda p: size


def check_contributions(model: Any) -> None:
    """Evaluate the contributions of a model's effects from outside ``ship_env`` at a few states.

    A contribution that gives a NaN or an infinity where the ship sails normally (at service
    speed, turning either way, in wind, current, waves and a propeller's slipstream) raises a
    ValueError naming the effect, where it comes from and the quantity, before any simulation
    runs; so does a draw of numbers of another shape than declared, or not finite.
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
    S.derive_conditions(conditions[np.newaxis])
    sea = {"wave_height": np.array([2.0]), "wave_period": np.array([8.0])}
    drawn = model.draw(noise.keys_from_seeds(np.zeros(1)), conditions[np.newaxis], sea)[0]
    size = len(state_names(model.record))
    out = np.zeros(size)
    for sign in (1.0, -1.0):
        state = np.zeros(size)
        state[S.HEADING] = 0.3
        state[S.RATE_OF_TURN] = sign * math.radians(0.3)
        state[S.SPEED_LOSS] = 0.05
        state[S.RUDDER] = sign * math.radians(20.0)
        start_states(state[np.newaxis], conditions[np.newaxis], model.record)
        for where, value in zip(state_names(model.record), state, strict=True):
            if not math.isfinite(value):
                owner = next(e for e in model.effects if any(s.name == where for s in EFFECTS.entry(e).states))
                raise ValueError(
                    f"effect {owner!r} from {EFFECTS.entry(owner).origin}: the initial value of its state "
                    f"{where!r} is {value!r}"
                )
        composed(state, state[S.RUDDER], conditions, np.ones(size), drawn, 0.0, record, out)
