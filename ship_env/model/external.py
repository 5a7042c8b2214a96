"""Bring your own ship dynamics: a ship simulated outside ship_env, sailed by every task unchanged.

A ship simulated elsewhere (an MMG model of your ship, an FMU, a co-simulation over a socket)
plugs in through :class:`ShipDynamics`, a protocol of two methods that any class satisfies
without inheriting from anything here:

- ``reset(start, conditions, seed)``: start the ship in ``start`` (a :class:`ShipMotion`: heading,
  rate of turn, position, forward speed, drift angle and actual rudder) in ``conditions``
  (:class:`~ship_env.model.Conditions`: the service speed it sails at, the current and the wind;
  an adapter that cannot sail a condition it is given raises ``ValueError`` saying so) with
  ``seed`` for its own randomness, if it has any;
- ``step(rudder_order, propeller_rate, dt)``: order the rudder (rad, positive to starboard, within
  the task's rudder limit; the ship's own steering machine moves the rudder), run the propeller
  at ``propeller_rate`` rps (``None``: the rate that holds the service speed on a straight
  course) for ``dt`` s, and return the motion at the end of the step: a :class:`ShipMotion`, or
  its seven numbers in :data:`MOTION_NAMES` order.

The environments take it as their ``dynamics`` keyword: an adapter (one ship), a zero-argument
callable that makes one (its class: one adapter per ship of a vector environment), or the
``"module:attribute"`` import path of such a callable (as Gymnasium's entry points; it travels to
Ray workers as text)::

    import gymnasium as gym

    class MyShip:
        def reset(self, start, conditions, seed): ...
        def step(self, rudder_order, propeller_rate, dt): return ShipMotion(...)

    env = gym.make("ship_env/CourseChange-v0", ship="kvlcc2", dynamics=MyShip())
    vec = gym.make_vec("ship_env/CourseChange-v0", num_envs=4, vectorization_mode="vector_entry_point",
                       ship="kvlcc2", dynamics=MyShip)

The task's ``ship`` preset still gives what the bridge knows of the ship: its length, service
speed and K* (the observations' scales, the reference tracks' turns) and the model the classic
autopilots are designed from; the adapter gives the motion. :class:`ExternalSimulator` holds the
motion in ship_env's state layout (:mod:`ship_env.model.state`; the disturbance states the native
effects own stay 0), so the instruments, observations, rewards and metrics are computed by the
tasks' own code. An adapter is started from its ship's row at the ship's first step after a reset
(a task may place the ship between the two, as TrackFollow does).

An adapter that raises, or returns a motion that is not seven finite numbers, ends its ship's
episode with :class:`ExternalDynamicsError` naming the adapter, the ship and the step: the single
environment raises it (reset it to sail again), the vector environment truncates that ship's
episode alone (``info["diverged"]``), as a native ship leaving its model's validity.

Shipped adapters: :class:`ship_env.model.native_dynamics.NativeDynamics` (ship_env's own
simulator behind the protocol: the reference) and :class:`ship_env.model.mmg_kvlcc2.MmgKvlcc2`
(shipmmg's MMG model of KVLCC2, with the optional ``shipmmg``).
"""

from __future__ import annotations

import dataclasses
import functools
import importlib
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Protocol, runtime_checkable

import numpy as np

from ship_env.model import state as S
from ship_env.model.mmg_record import MmgRecord
from ship_env.model.ship import ShipModel
from ship_env.model.simulator import Conditions, Simulator

#: The numbers of a :class:`ShipMotion`, in the order an adapter may return them.
MOTION_NAMES = ("heading", "rate_of_turn", "north", "east", "speed", "drift", "rudder")


@dataclass(frozen=True)
class ShipMotion:
    """A ship's motion as an external simulator reports it.

    Attributes:
        heading: psi, rad, clockwise from north, not wrapped.
        rate_of_turn: r, rad/s, positive turning to starboard.
        north, east: the position over the ground, m.
        speed: the forward (surge) speed through the water u, m/s.
        drift: the drift angle beta = atan2(-v, u), rad, v the sway velocity (positive to starboard).
        rudder: the actual rudder angle, rad, positive to starboard (giving a positive r).
    """

    heading: float
    rate_of_turn: float
    north: float
    east: float
    speed: float
    drift: float = 0.0
    rudder: float = 0.0

    def values(self) -> tuple[float, ...]:
        """The motion's numbers in :data:`MOTION_NAMES` order."""
        return tuple(getattr(self, name) for name in MOTION_NAMES)


@runtime_checkable
class ShipDynamics(Protocol):
    """A ship simulated outside ship_env (see the module's docstring)."""

    def reset(self, start: ShipMotion, conditions: Conditions, seed: int) -> None:
        """Start the ship in ``start`` and ``conditions`` (service speed resolved, never ``None``)."""

    def step(self, rudder_order: float, propeller_rate: float | None, dt: float) -> ShipMotion | Sequence[float]:
        """Sail ``dt`` s with the rudder ordered to ``rudder_order`` rad and the propeller at
        ``propeller_rate`` rps (``None``: the service speed's rate); the motion at the step's end."""
        ...


#: What an environment's ``dynamics`` keyword takes: an adapter, a callable making one, its import path, or a fitted
#: MMG model (its file, or its record: :class:`~ship_env.model.mmg_fitted.MmgRecord`).
DynamicsSource = ShipDynamics | Callable[[], ShipDynamics] | str | Path | MmgRecord

#: The ``dynamics`` keyword that sails a preset's own effects by ship_env's simulator where the preset names another
#: model (its ``dynamics:`` block).
NATIVE = "native"


def preset_dynamics(model: ShipModel, dynamics: DynamicsSource | None) -> DynamicsSource | None:
    """Who sails ``model``: ``dynamics`` where given; ``None`` takes the preset's own (its ``dynamics:`` block, a
    fitted MMG model), or ship_env's simulator where it names none; :data:`NATIVE` ship_env's simulator (None)."""
    if dynamics is None:
        return model.ship.dynamics
    if isinstance(dynamics, str) and dynamics == NATIVE:
        return None
    return dynamics


class ExternalDynamicsError(FloatingPointError):
    """An external simulator failed at a step: it raised, or returned a motion that is not seven
    finite numbers. A ``FloatingPointError``, like a native ship leaving its model's validity, so
    the environments end that ship's episode the same way."""


def adapter_name(adapter: object) -> str:
    """An adapter as error messages name it: its class's module and name."""
    kind = type(adapter)
    return f"{kind.__module__}.{kind.__qualname__}"


def dynamics_factory(source: DynamicsSource) -> Callable[[], ShipDynamics]:
    """A callable making one adapter per ship from an environment's ``dynamics`` keyword.

    ``source``: an adapter (it sails one ship: the factory gives it once), a class or other
    zero-argument callable making one, ``"module:attribute"``, the import path of such a callable, or the path
    of a fitted MMG model written by ``ship-env fit-mmg`` (a ``.yaml`` file, or its
    :class:`~ship_env.model.mmg_fitted.MmgRecord`: :class:`~ship_env.model.mmg_fitted.MmgFitted`).
    ``ValueError`` or ``TypeError`` names what is wrong with it.
    """
    from ship_env.model.mmg_fitted import MmgFitted, read_mmg  # it builds on this module

    if isinstance(source, MmgRecord):
        return functools.partial(MmgFitted, source)
    if isinstance(source, Path) or (isinstance(source, str) and source.endswith((".yaml", ".yml"))):
        record = read_mmg(source)  # read once here: a bad file is named now, not at each ship's start
        return functools.partial(MmgFitted, record)
    if isinstance(source, str):
        module_name, _, attribute = source.partition(":")
        if not module_name or not attribute:
            raise ValueError(f"dynamics: expected 'module:attribute', got {source!r}")
        try:
            source = getattr(importlib.import_module(module_name), attribute)
        except (ImportError, AttributeError) as error:
            raise ValueError(f"dynamics: cannot import {source!r}: {error}") from error
    if isinstance(source, ShipDynamics) and not isinstance(source, type):
        adapter = source
        given: list[ShipDynamics] = []

        def once() -> ShipDynamics:
            if given:
                raise ValueError(
                    f"dynamics: the adapter {adapter_name(adapter)} sails one ship; give its class (or a callable "
                    "making one) for a vector environment"
                )
            given.append(adapter)
            return adapter

        return once
    if callable(source):
        return source
    raise TypeError(
        f"dynamics: expected an adapter with reset() and step(), its class, or 'module:attribute'; got {source!r}"
    )


class ExternalSimulator(Simulator):
    """A :class:`~ship_env.model.Simulator` whose ships are stepped by external adapters.

    The state, conditions, seeds and instrument-noise keys are the native simulator's (so the
    tasks read them unchanged); each step passes every ship's rudder order and propeller rate to
    its adapter and writes the motion it returns into the ship's row: time, position, heading,
    rate of turn, actual rudder, and the speed as the speed loss u* = 1 - u / U0 (2.41). The drift
    angles are kept in :attr:`drift`. A vector environment's N adapters step one after another in
    this process (an adapter that runs elsewhere, an FMU or a co-simulation peer, may run in parallel).

    Args:
        model: the ship model of the task's preset (its layout and particulars; not stepped).
        make_dynamics: makes one adapter per ship (:func:`dynamics_factory`).
        num_ships: N.
        dt: the step, s.
    """

    def __init__(
        self, model: ShipModel, make_dynamics: Callable[[], ShipDynamics], num_ships: int = 1, dt: float = 0.5
    ) -> None:
        # Made before the native simulator's set-up, which resets every ship.
        self.adapters = [make_dynamics() for _ in range(num_ships)]
        for adapter in self.adapters:
            if not isinstance(adapter, ShipDynamics):
                raise TypeError(
                    f"dynamics: {adapter!r} has no reset() and step() (ship_env.model.external.ShipDynamics)"
                )
        #: Drift angle beta of each ship, rad (:class:`ShipMotion`).
        self.drift = np.zeros(len(self.adapters))
        self._starting = np.ones(len(self.adapters), dtype=np.bool_)
        self._failed = np.zeros(len(self.adapters), dtype=np.bool_)
        #: Each ship's conditions as its reset gave them (the service speed resolved): what its adapter sails.
        self.sailed_conditions = [Conditions()] * len(self.adapters)
        super().__init__(model, num_ships, dt)

    def _check_start_speed(self, speed: float | np.ndarray | None) -> None:
        """``ValueError`` for a ``speed`` at :meth:`~Simulator.reset`: an adapter starts its ship at the service speed
        of its conditions."""
        if speed is not None:
            raise ValueError(
                f"speed: {speed!r}: a ship simulated by {adapter_name(self.adapters[0])} starts at its service "
                "speed; give the speed as conditions' service_speed"
            )

    def _started(self, rows: np.ndarray, conditions: Sequence[Conditions]) -> None:
        """:meth:`~Simulator.reset`'s ships, started by their adapters at their next step; ``ValueError`` for
        conditions with K* or tau* factors: they scale ship_env's own model."""
        for row, sailed in zip(rows, conditions, strict=True):
            if sailed.yaw_gain_factor != 1.0 or sailed.yaw_time_constant_factor != 1.0:
                raise ValueError(
                    "conditions: K* and tau* factors scale ship_env's own model; the ship simulated by "
                    f"{adapter_name(self.adapters[row])} cannot sail them"
                )
            self.sailed_conditions[row] = dataclasses.replace(
                sailed, service_speed=float(self.conditions[row, S.SERVICE_SPEED])
            )
        self.drift[rows] = 0.0
        self._starting[rows] = True
        self._failed[rows] = False

    def _check_propeller_rates(self, name: str, rates: np.ndarray) -> None:
        """Nothing to refuse: each adapter sails its propeller rate, ahead or astern, as its ship does."""

    def step(self, ordered_rudder: float | np.ndarray) -> None:
        """Advance every ship by ``dt``: each adapter's ``step`` (started first if just reset).

        Orders beyond the rudder limit are clipped to it; a NaN order raises ``ValueError``. An
        adapter that fails ends its ship's episode (:class:`ExternalDynamicsError`, after every
        other ship has stepped); stepping that ship again before its reset raises the same.
        """
        orders = np.broadcast_to(np.asarray(ordered_rudder, dtype=float), (self.num_ships,))
        if not np.all(np.isfinite(orders)):
            bad = int(np.flatnonzero(~np.isfinite(orders))[0])
            raise ValueError(f"ordered_rudder[{bad}]: must be a finite angle in rad, got {orders[bad]!r}")
        limit = self.model.rudder_limit
        failures: list[tuple[int, str, Exception | None]] = []
        for ship, adapter in enumerate(self.adapters):
            if self._failed[ship]:
                failures.append((ship, "its episode ended when its ship dynamics failed; reset it", None))
                continue
            problem, error = self._step_ship(ship, adapter, min(max(float(orders[ship]), -limit), limit))
            if problem is not None:
                self._failed[ship] = True
                failures.append((ship, problem, error))
        if failures:
            ship, problem, error = failures[0]
            step = int(self.step_index[ship]) + 1
            raise ExternalDynamicsError(
                f"ship dynamics {adapter_name(self.adapters[ship])}, ship {ship}, step {step} "
                f"(t = {self.state[ship, S.TIME]:.1f} s): {problem}; the episode ended (reset to sail again)"
            ) from error

    def _step_ship(self, ship: int, adapter: ShipDynamics, order: float) -> tuple[str | None, Exception | None]:
        """Step one ship's adapter and write its motion; (what went wrong, the exception) or (None, None)."""
        row = self.state[ship]
        service_speed = float(self.conditions[ship, S.SERVICE_SPEED])
        if self._starting[ship]:
            start = ShipMotion(
                float(row[S.HEADING]),
                float(row[S.RATE_OF_TURN]),
                float(row[S.NORTH]),
                float(row[S.EAST]),
                service_speed * (1.0 - float(row[S.SPEED_LOSS])),
                float(self.drift[ship]),
                float(row[S.RUDDER]),
            )
            try:
                adapter.reset(start, self.sailed_conditions[ship], int(self.seeds[ship]))
            except Exception as error:  # the adapter is someone else's code: any failure ends the episode
                return f"reset raised {type(error).__name__}: {error}", error
            self._starting[ship] = False
        rate = float(self.conditions[ship, S.PROPELLER_RATE])
        try:
            motion = adapter.step(order, rate if rate > 0.0 else None, self.dt)
        except Exception as error:  # as above
            return f"step raised {type(error).__name__}: {error}", error
        values, problem = motion_values(motion)
        if problem is not None:
            return problem, None
        heading, rate_of_turn, north, east, speed, drift, rudder = values
        row[S.TIME] += self.dt
        row[S.NORTH], row[S.EAST], row[S.HEADING], row[S.RATE_OF_TURN] = north, east, heading, rate_of_turn
        row[S.RUDDER] = rudder
        row[S.SPEED_LOSS] = 1.0 - speed / service_speed
        self.drift[ship] = drift
        self.step_index[ship] += 1
        return None, None

    def invalid_ships(self) -> np.ndarray:
        """The ships whose adapter failed (their episodes ended)."""
        return self._failed.copy()

    @property
    def sway_velocity(self) -> np.ndarray:
        """Sway velocity v = -u tan(beta), m/s, from the adapters' speed and drift."""
        return -self.speed * np.tan(self.drift)


def motion_values(motion: object) -> tuple[tuple[float, ...], str | None]:
    """An adapter's returned motion as its seven numbers, or what is wrong with it."""
    if isinstance(motion, ShipMotion):
        motion = motion.values()
    try:
        array = np.asarray(motion, dtype=float)
    except (TypeError, ValueError):
        return (), f"step returned {motion!r}, not a ShipMotion or {len(MOTION_NAMES)} numbers"
    if array.shape != (len(MOTION_NAMES),):
        return (), (
            f"step returned shape {array.shape}, expected a ShipMotion or {len(MOTION_NAMES)} numbers "
            f"({', '.join(MOTION_NAMES)})"
        )
    bad = [
        f"{name} = {value!r}"
        for name, value in zip(MOTION_NAMES, array.tolist(), strict=True)
        if not math.isfinite(value)
    ]
    if bad:
        return (), f"step returned non-finite {', '.join(bad)}"
    return tuple(array.tolist()), None
