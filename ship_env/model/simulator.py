"""The simulator: N ships of one model, stepped together, reproducible from a seed.

:class:`Simulator` holds the batch's state ``(N, model.state_size)``, the conditions each ship sails in,
the random numbers its effects drew where it started (the sea it meets) and a random generator per
ship. ``step`` advances all ships in one compiled call, a large batch on all cores where that is
faster (:class:`Cores`); with ``N = 1`` it takes a lighter path. Ship ``i`` of a batch seeded with
``seed`` draws its randomness from ``seed + i`` (as Gymnasium's vector environments do), so a batch
gives the same numbers as single runs with those seeds (see ``noise``).
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass
from typing import Any

import numba
import numpy as np
from numpy.typing import ArrayLike

from ship_env.model import noise
from ship_env.model import state as S
from ship_env.model.dynamics import sway_velocity
from ship_env.model.effects import EFFECTS
from ship_env.model.integrators import METHODS, is_valid, new_workspace, step_ship, step_ships, step_ships_parallel
from ship_env.model.ship import ShipModel

#: Batches at least this large may step on all cores (:func:`batch_loop`); smaller ones step in one thread.
PARALLEL_SHIPS = 1024
#: A batch that may use all cores runs the way it did not choose after 16, 32, 64, ... calls, then
#: once in this many, to time it afresh.
RETIME_CALLS = 1024
#: The weight of a call's log time in its way's running mean: a slow call now and then does not
#: turn the choice, a few in a row do.
TIME_WEIGHT = 0.1

#: The conditions that must not be negative (a negative propeller rate turns astern: :func:`check_propeller_rates`).
_NOT_NEGATIVE = frozenset({"service_speed", "current_speed", "wind_speed", "wave_height", "yaw_gain_factor"})


def _sails_astern(effect: str) -> bool:
    """Whether an effect sails a propeller astern: its envelope allows it (``propeller_ahead_only=False``)."""
    return EFFECTS[effect].envelope.propeller_ahead_only is False


def check_propeller_rates(name: str, rates: np.ndarray, model: ShipModel) -> None:
    """``ValueError`` for a propeller turning astern (a negative rate, rps) where none of ``model``'s
    effects sails it (:func:`_sails_astern`: ``propeller_astern``); without one the model's equations hold
    for a propeller ahead only (its envelope's ``propeller_ahead_only``)."""
    if not np.any(rates < 0.0) or any(_sails_astern(effect) for effect in model.effects):
        return
    astern = [effect for effect in EFFECTS if _sails_astern(effect)]
    raise ValueError(
        f"{name}: {float(np.min(rates))!r} rps turns the propeller astern, which the model sails only with "
        f"{' or '.join(astern)} (not among its effects); add it to the model's effects or give a rate >= 0"
    )


class Cores:
    """A batch's compiled loop that runs in one thread or on all cores, whichever has lately been faster.

    On a machine to itself, two threads step or update 1024 ships faster than one
    (``benchmarks/bench_envs.py``; figures in ``docs/results/benchmarks.md``). Where other work keeps
    the cores busy the threads wait for each other, often a scheduler time slice (milliseconds) a
    call, many times the one-thread time. So the loop times its calls: each way keeps a running
    mean of its log call time (``TIME_WEIGHT``) and the faster way runs, but now and then
    (``RETIME_CALLS``) the other way runs and its mean restarts from that call's time. A way's
    first call (which starts the threads) is not timed. Both ways give the same numbers.

    Args:
        serial: the loop in one thread.
        parallel: the same loop on all cores.
    """

    def __init__(self, serial: Callable[..., Any], parallel: Callable[..., Any]) -> None:
        self._ways = (serial, parallel)
        self._log_seconds: list[float | None] = [None, None]
        self._started = [False, False]
        self._calls = 0
        self._next_retime = 16

    def __call__(self, *args: Any) -> Any:
        """The loop on ``args``, one way or the other (the same result)."""
        self._calls += 1
        retime = self._calls == self._next_retime
        if retime:
            self._next_retime += min(self._next_retime, RETIME_CALLS)
        one, all_cores = self._log_seconds
        if all_cores is None or one is None:
            way = 1 if all_cores is None else 0
        else:
            way = int(all_cores < one) ^ retime
        start = time.perf_counter()
        result = self._ways[way](*args)
        log_seconds = math.log(max(time.perf_counter() - start, 1e-9))
        mean = self._log_seconds[way]
        if not self._started[way]:
            self._started[way] = True
        elif mean is None or retime:
            self._log_seconds[way] = log_seconds
        else:
            self._log_seconds[way] = mean + TIME_WEIGHT * (log_seconds - mean)
        return result


def batch_loop(num_ships: int, serial: Callable[..., Any], parallel: Callable[..., Any]) -> Callable[..., Any]:
    """The loop a batch of ``num_ships`` runs: ``serial`` below ``PARALLEL_SHIPS`` ships or with one
    numba thread (``NUMBA_NUM_THREADS=1``), else :class:`Cores` choosing between the two."""
    if num_ships < PARALLEL_SHIPS or numba.get_num_threads() == 1:
        return serial
    return Cores(serial, parallel)


@dataclass(frozen=True)
class Conditions:
    """What a ship sails in. Angles in radians, clockwise from north; speeds in m/s.

    Attributes:
        service_speed: U0, speed through the water on a straight course; ``None`` takes the ship's.
        propeller_rate: n in rps (used by the propeller-slipstream effect), negative astern (sailed only by a
            model with an astern effect, ``propeller_astern``; the simulator refuses it otherwise); ``None``
            takes the ship's service conditions' (``ShipModel.service_propeller_rate``: 0 where its preset
            states none), at another speed than the ship's service speed in proportion to it (the same
            advance ratio J = U / (n D), as a fixed-pitch propeller's rate follows the speed it holds).
        current_speed, current_direction: the current and the direction it sets *towards*.
        wind_speed, wind_direction: the true wind and the direction it comes *from*.
        wave_height, wave_period, wave_direction: significant height (m), peak period (s) and the
            direction the waves come *from*, for the wave-spectrum effect.
        yaw_gain_factor, yaw_time_constant_factor: the sailed ship's K* and tau* as multiples of
            the model's (2.54), so the ships of one batch can differ; 1 sails the model.
    """

    service_speed: float | None = None
    propeller_rate: float | None = None
    current_speed: float = 0.0
    current_direction: float = 0.0
    wind_speed: float = 0.0
    wind_direction: float = 0.0
    wave_height: float = 0.0
    wave_period: float = 8.0
    wave_direction: float = 0.0
    yaw_gain_factor: float = 1.0
    yaw_time_constant_factor: float = 1.0

    def __post_init__(self) -> None:
        for name, value in vars(self).items():
            if value is None and name in ("service_speed", "propeller_rate"):
                continue
            if type(value) is not float and (
                isinstance(value, bool) or not isinstance(value, (int, float, np.floating, np.integer))
            ):
                raise TypeError(f"conditions.{name}: expected a number, got {value!r}")
            if not math.isfinite(value):
                raise ValueError(f"conditions.{name}: must be finite, got {value!r}")
            if value < 0.0 and name in _NOT_NEGATIVE:
                raise ValueError(f"conditions.{name}: must not be negative, got {value!r}")
        for name in ("wave_period", "yaw_time_constant_factor"):
            if getattr(self, name) <= 0.0:
                raise ValueError(f"conditions.{name}: must be positive, got {getattr(self, name)!r}")

    def row(self, default_speed: float, default_propeller_rate: float = 0.0) -> np.ndarray:
        """The conditions as one row of the simulator's condition array (the defaults where ``None``)."""
        row = np.zeros(S.CONDITION_SIZE)
        speed = default_speed if self.service_speed is None else self.service_speed
        row[S.SERVICE_SPEED] = speed
        if self.propeller_rate is not None:
            row[S.PROPELLER_RATE] = self.propeller_rate
        elif default_propeller_rate != 0.0 and speed != default_speed and default_speed > 0.0:
            row[S.PROPELLER_RATE] = default_propeller_rate * speed / default_speed  # the same advance ratio
        else:
            row[S.PROPELLER_RATE] = default_propeller_rate
        row[S.CURRENT_SPEED] = self.current_speed
        row[S.CURRENT_DIRECTION] = self.current_direction
        row[S.WIND_SPEED] = self.wind_speed
        row[S.WIND_DIRECTION] = self.wind_direction
        row[S.WAVE_DIRECTION] = self.wave_direction
        row[S.YAW_GAIN_CHANGE] = self.yaw_gain_factor - 1.0
        row[S.YAW_TIME_CONSTANT_CHANGE] = self.yaw_time_constant_factor - 1.0
        S.derive_conditions(row[np.newaxis])
        return row


class Simulator:
    """Steps ``num_ships`` ships of one :class:`ShipModel`.

    Args:
        model: the ship model (preset plus effects).
        num_ships: N, the batch size.
        dt: the integration step, s.
        method: ``"rk4"`` (default) or ``"euler"``.

    Example::

        sim = Simulator(ShipModel("container_226m"), dt=1.0)
        sim.reset(seed=0)
        for _ in range(600):
            sim.step(math.radians(10))
        sim.heading, sim.rate_of_turn
    """

    def __init__(self, model: ShipModel, num_ships: int = 1, dt: float = 0.5, method: str = "rk4") -> None:
        if not isinstance(num_ships, (int, np.integer)) or num_ships < 1:
            raise ValueError(f"num_ships: expected a positive whole number, got {num_ships!r}")
        if isinstance(dt, bool) or not isinstance(dt, (int, float)) or not math.isfinite(dt) or dt <= 0.0:
            raise ValueError(f"dt: expected a positive step in seconds, got {dt!r}")
        if method not in METHODS:
            raise ValueError(f"method: expected one of {sorted(METHODS)}, got {method!r}")
        self.model = model
        self.num_ships = int(num_ships)
        self.dt = float(dt)
        self.method = method
        self._method_code = METHODS[method]
        # The arrays are allocated once and written in place, so views of them stay valid.
        self.state = np.zeros((self.num_ships, model.state_size))
        self.conditions = np.zeros((self.num_ships, S.CONDITION_SIZE))
        #: Each ship's row of draws (``ShipModel.draw``): the random numbers its effects drew at its reset.
        self.draws = np.zeros((self.num_ships, model.draw_size))
        self.seeds = np.zeros(self.num_ships, dtype=np.int64)
        self.noise_keys = np.zeros(self.num_ships, dtype=np.uint64)
        self.step_index = np.zeros(self.num_ships, dtype=np.int64)
        self._orders = np.zeros(self.num_ships)
        self._valid = np.ones(self.num_ships, dtype=np.bool_)
        self._work = new_workspace(model.state_size)
        #: A fitted preset's covered ranges, checked while any is still to be warned of (``operating_point``).
        self._coverage = model.fitted_ranges
        self._link()
        self.reset()

    def _link(self) -> None:
        """Make the compiled loop and ship 0's rows (views of the arrays) that ``step`` passes: at
        construction, and again where a copy or a pickle (which make views independent arrays) is
        restored."""
        self._step_ships = batch_loop(self.num_ships, step_ships, step_ships_parallel)
        self._state0 = self.state[0]
        self._conditions0 = self.conditions[0]
        self._draws0 = self.draws[0]

    def __getstate__(self) -> dict[str, Any]:
        """The attributes a copy or a pickle carries: all but those :meth:`_link` makes."""
        state = self.__dict__.copy()
        for name in ("_step_ships", "_state0", "_conditions0", "_draws0"):
            del state[name]
        return state

    def __setstate__(self, state: dict[str, Any]) -> None:
        self.__dict__.update(state)
        self._link()

    # -- starting ------------------------------------------------------------------------------
    def reset(
        self,
        seed: int | Sequence[int] | None = None,
        conditions: Conditions | Sequence[Conditions] | None = None,
        heading: float | np.ndarray = 0.0,
        rudder: float | np.ndarray = 0.0,
        rate_of_turn: float | np.ndarray | None = None,
        ships: Sequence[int] | np.ndarray | None = None,
        speed: float | np.ndarray | None = None,
    ) -> None:
        """Start ships at the origin, at their service speed (or ``speed``), on ``heading`` (rad).

        Args:
            seed: one integer (the k-th restarted ship uses seed + k), one per restarted ship, or
                None for fresh entropy.
            conditions: one :class:`Conditions` for all restarted ships, or one per ship.
            heading: initial heading(s), rad.
            rudder: initial actual rudder angle(s), rad.
            rate_of_turn: initial rate(s) of turn, rad/s; ``None`` starts straight (r = 0).
            ships: indices of the ships to restart (the others sail on untouched); None for all.
            speed: initial speed(s) through the water u, m/s, positive; the speed loss starts at
                u* = 1 - u / U0 (2.41) and the ``speed_loss`` effect takes it towards its steady value;
                ``None`` starts at the service speed U0 (u* = 0).
        """
        self._check_start_speed(speed)
        rows = np.arange(self.num_ships) if ships is None else self._rows(ships)
        count = len(rows)
        seeds = self._seeds(seed, count)
        self.seeds[rows] = seeds
        self.noise_keys[rows] = noise.keys_from_seeds(seeds)
        self.step_index[rows] = 0
        per_ship = self._per_ship_conditions(conditions, count)
        self.conditions[rows] = np.stack(
            [c.row(self.model.service_speed, self.model.service_propeller_rate) for c in per_ship]
        )
        self._check_propeller_rates("conditions.propeller_rate", self.conditions[rows, S.PROPELLER_RATE])
        if self._coverage is not None:
            self._coverage.check_conditions(self.conditions[rows])
        self.state[rows] = 0.0
        self.state[rows, S.HEADING] = self._per_ship_value("heading", heading, count)
        self.state[rows, S.RUDDER] = np.clip(
            self._per_ship_value("rudder", rudder, count), -self.model.rudder_limit, self.model.rudder_limit
        )
        if rate_of_turn is not None:
            self.state[rows, S.RATE_OF_TURN] = self._per_ship_value("rate_of_turn", rate_of_turn, count)
        if speed is not None:
            speeds = self._per_ship_value("speed", speed, count)
            if np.any(speeds <= 0.0):
                raise ValueError(f"speed: expected positive speeds through the water in m/s, got {speed!r}")
            self.state[rows, S.SPEED_LOSS] = 1.0 - speeds / self.conditions[rows, S.SERVICE_SPEED]
        if not self.model.own_states_start_at_zero:
            started = self.state[rows]
            self.model.start_states(started, self.conditions[rows])
            self.state[rows] = started
        if self.model.draw_layout:
            start = {
                name: np.array([getattr(c, name) for c in per_ship], dtype=float) for name in S.START_CONDITION_NAMES
            }
            self.draws[rows] = self.model.draw(self.noise_keys[rows], self.conditions[rows], start)
        self._started(rows, per_ship)

    def _check_start_speed(self, speed: float | np.ndarray | None) -> None:
        """Refuse a starting ``speed`` before :meth:`reset` starts a ship (nothing here: any positive speed sails)."""

    def _started(self, rows: np.ndarray, conditions: Sequence[Conditions]) -> None:
        """What a simulator does once :meth:`reset` has started the ships ``rows`` in their ``conditions`` (nothing
        here: the native ships are started)."""

    def _check_propeller_rates(self, name: str, rates: np.ndarray) -> None:
        """Refuse a propeller astern the model does not sail (:func:`check_propeller_rates`)."""
        check_propeller_rates(name, rates, self.model)

    def _rows(self, ships: Sequence[int] | np.ndarray) -> np.ndarray:
        rows = np.asarray(ships)
        if rows.ndim != 1 or not np.issubdtype(rows.dtype, np.integer) or np.any((rows < 0) | (rows >= self.num_ships)):
            raise ValueError(f"ships: expected indices in [0, {self.num_ships}), got {ships!r}")
        if len(np.unique(rows)) != len(rows):
            raise ValueError(f"ships: indices must not repeat, got {ships!r}")
        return rows

    def _seeds(self, seed: int | Sequence[int] | None, count: int) -> np.ndarray:
        if seed is None:
            seed = int(np.random.SeedSequence().generate_state(1, np.uint32)[0])
        if isinstance(seed, bool):
            raise ValueError(f"seed: expected an integer or {count} integers, got {seed!r}")
        if isinstance(seed, (int, np.integer)):
            return int(seed) + np.arange(count, dtype=np.int64)
        seeds = list(seed)
        if len(seeds) != count or not all(isinstance(s, (int, np.integer)) for s in seeds):
            raise ValueError(f"seed: expected an integer or {count} integers, got {seed!r}")
        return np.asarray(seeds, dtype=np.int64)

    def _per_ship_conditions(
        self, conditions: Conditions | Iterable[Conditions] | None, count: int
    ) -> list[Conditions]:
        if conditions is None:
            return [Conditions()] * count
        if isinstance(conditions, Conditions):
            return [conditions] * count
        items = list(conditions)
        if len(items) != count or not all(isinstance(c, Conditions) for c in items):
            raise ValueError(f"conditions: expected one Conditions or {count} of them")
        return items

    def _per_ship_value(self, name: str, value: ArrayLike, count: int | None = None) -> np.ndarray:
        try:
            array = np.broadcast_to(np.asarray(value, dtype=float), (self.num_ships if count is None else count,))
        except (TypeError, ValueError):
            raise ValueError(f"{name}: expected a number or one per ship, got {value!r}") from None
        if not np.all(np.isfinite(array)):
            raise ValueError(f"{name}: must be finite, got {value!r}")
        return array

    # -- conditions while sailing ----------------------------------------------------------------
    def set_conditions(self, name: str, value: float | np.ndarray) -> None:
        """Change one condition (``service_speed``, ``propeller_rate``, ``wind_speed``, ...) now.

        Used to replay measured speed, propeller rate or wind step by step, or to switch a current
        on or off during a run. Angles in radians. The derived conditions follow
        (``state.derive_conditions``).
        """
        if name not in S.SETTABLE_CONDITION_NAMES:
            known = f"known: {', '.join(S.SETTABLE_CONDITION_NAMES)}"
            if name in S.DERIVED_CONDITION_NAMES:
                raise ValueError(f"conditions: {name!r} is derived from the current and the wind; set those ({known})")
            raise ValueError(f"conditions: unknown condition {name!r}; {known}")
        array = self._per_ship_value(name, value)
        if name in ("service_speed", "current_speed", "wind_speed") and np.any(array < 0.0):
            raise ValueError(f"conditions.{name}: must not be negative, got {value!r}")
        if name == "propeller_rate":
            self._check_propeller_rates(f"conditions.{name}", array)
        self.conditions[:, S.CONDITION_NAMES.index(name)] = array
        S.derive_conditions(self.conditions)

    # -- stepping --------------------------------------------------------------------------------
    def step(self, ordered_rudder: float | np.ndarray) -> None:
        """Advance every ship by ``dt`` with the given ordered rudder angle(s), rad.

        Orders beyond the rudder limit are clipped to it (the steering machine's limiter). A NaN
        or infinite order raises ``ValueError``.
        """
        if self.num_ships == 1:
            order = (
                float(np.asarray(ordered_rudder).reshape(-1)[0])
                if not isinstance(ordered_rudder, float)
                else ordered_rudder
            )
            if not math.isfinite(order):
                raise ValueError(f"ordered_rudder: must be a finite angle in rad, got {order!r}")
            valid = step_ship(
                self._state0,
                order,
                self._conditions0,
                self.noise_keys[0],
                self.step_index[0],
                self._draws0,
                self.model.record,
                self.dt,
                self._method_code,
                self._work,
            )
            self.step_index[0] += 1
            self.stepped(valid)
            return
        orders = np.asarray(ordered_rudder, dtype=float)
        if orders.ndim == 0:
            self._orders.fill(float(orders))
            orders = self._orders
        elif orders.shape != (self.num_ships,):
            raise ValueError(f"ordered_rudder: expected shape ({self.num_ships},), got {orders.shape}")
        if not np.all(np.isfinite(orders)):
            bad = int(np.flatnonzero(~np.isfinite(orders))[0])
            raise ValueError(f"ordered_rudder[{bad}]: must be a finite angle in rad, got {orders[bad]!r}")
        self._step_ships(
            self.state,
            orders,
            self.conditions,
            self.noise_keys,
            self.step_index,
            self.draws,
            self.model.record,
            self.dt,
            self._method_code,
            self._valid,
        )
        if not self._valid.all():
            self._raise_invalid(int(np.flatnonzero(~self._valid)[0]))
        if self._coverage is not None:
            self._check_coverage()

    def step_arguments(self) -> tuple[np.ndarray, float, int, np.ndarray]:
        """What a step of ship 0 (:func:`~ship_env.model.integrators.step_ship`) reads besides its state,
        conditions, noise key and step count: (``draws``, ``dt``, the method's code, the scratch space),
        for a caller that steps it in a compiled call of its own, counts the step and calls :meth:`stepped`."""
        return self.draws, self.dt, self._method_code, self._work

    def stepped(self, valid: bool) -> None:
        """What follows ship 0's step, counted (``valid``: its verdict): ``FloatingPointError`` where its
        state left the model's validity; a fitted preset's covered ranges checked."""
        if not valid:
            self._raise_invalid(0)
        if self._coverage is not None:
            self._check_coverage()

    def _check_coverage(self) -> None:
        """Warn where a ship left its fitted preset's covered ranges; stop checking once all are warned of."""
        coverage = self._coverage
        if coverage is not None and not coverage.check_motion(self.state, self.conditions, self.model.record):
            self._coverage = None

    def invalid_ships(self) -> np.ndarray:
        """(N,) bool: the ships whose state is outside the model's validity (not finite, or u* > 1)."""
        return np.array([not is_valid(row, row.shape[0]) for row in self.state])

    def _raise_invalid(self, ship: int) -> None:
        state = self.state[ship]
        bad = [
            f"{name} = {value!r}"
            for name, value in zip(self.model.state_names, state, strict=True)
            if not math.isfinite(value)
        ]
        speed_loss = self.model.state_names[S.SPEED_LOSS]
        if not bad:
            bad = [f"{speed_loss} u* = {state[S.SPEED_LOSS]:.3f} > 1 (forward speed negative)"]
        # The first parameter of the effect that governs u* (its gain): a tight turn slows the ship by it.
        governing = [
            f" (e.g. {name}.{EFFECTS[name].parameters[0].name} for a turn this tight)"
            for name in self.model.effects
            if EFFECTS[name].parameters and any(s.name == speed_loss for s in EFFECTS.entry(name).states)
        ]
        outside = [
            f"{name} ({EFFECTS.entry(name).origin})" for name in self.model.effects if not EFFECTS.entry(name).builtin
        ]
        raise FloatingPointError(
            f"ship {ship} left the model's validity at t = {state[S.TIME]:.1f} s: {', '.join(bad)}; "
            f"check the model's coefficients{''.join(governing[:1])} and the step dt = {self.dt}"
            + (f"; effects from outside ship_env in the model: {', '.join(outside)}" if outside else "")
        )

    # -- reading ---------------------------------------------------------------------------------
    @property
    def time(self) -> np.ndarray:
        return self.state[:, S.TIME]

    @property
    def position(self) -> np.ndarray:
        """(N, 2) north and east positions, m."""
        return self.state[:, S.NORTH : S.EAST + 1]

    @property
    def heading(self) -> np.ndarray:
        """True heading psi, rad, not wrapped."""
        return self.state[:, S.HEADING]

    @property
    def rate_of_turn(self) -> np.ndarray:
        """True rate of turn r, rad/s."""
        return self.state[:, S.RATE_OF_TURN]

    @property
    def rudder(self) -> np.ndarray:
        """Actual rudder angle, rad."""
        return self.state[:, S.RUDDER]

    @property
    def speed(self) -> np.ndarray:
        """Forward speed u = U0 (1 - u*), m/s (2.53)."""
        return self.conditions[:, S.SERVICE_SPEED] * (1.0 - self.state[:, S.SPEED_LOSS])

    @property
    def sway_velocity(self) -> np.ndarray:
        """Van Leeuwen sway velocity v, m/s (without leeway)."""
        return np.array(
            [sway_velocity(s, c, self.model.record[0]) for s, c in zip(self.state, self.conditions, strict=True)]
        )

    @property
    def measured_heading(self) -> np.ndarray:
        """Heading as a compass would read it: psi plus the HF wave heading (Fig. 2.13)."""
        return self.state[:, S.HEADING] + self.state[:, S.WAVE_HEADING]

    @property
    def measured_rate_of_turn(self) -> np.ndarray:
        """Rate of turn as a rate gyro would read it: r plus the HF wave rate (Fig. 2.13)."""
        return self.state[:, S.RATE_OF_TURN] + self.state[:, S.WAVE_RATE]
