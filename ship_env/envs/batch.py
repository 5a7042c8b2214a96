"""N ships sailing one task's episodes: the simulator plus every ship's episode record, in arrays.

:class:`ShipBatch` is what the single environment (a batch of one) and the native vector
environment (a batch of N) share, so both give the same numbers for the same seeds. A task's
batch subclass names its episode record's fields (:func:`episode_dtype`), its metrics record, and
the two compiled loops that update every ship after a step, serially and on all cores, made by
:func:`define_update_loops` around the task's per-ship kernel. Batches of at least
``PARALLEL_SHIPS`` ships update on all cores where that is faster, like the simulator's step
(:func:`~ship_env.model.simulator.batch_loop`); smaller ones in one thread.

Why the loops are generated: numba caches a compiled function by its source file and bytecode, and
a loop that gets the per-ship update from a closure or an argument is never found in the cache
(the closure's contents differ in every process): every process would compile the three tasks'
loops afresh (7 to 16 s, against 0.1 to 0.25 s from the cache, on 2 busy cores:
``benchmarks/bench_env_loops.py``). So one template's source is compiled into each task module as
if written there, and caches like the module's own.

Each update measures (:func:`ship_env.envs.sensors.measure`), observes, rewards, decides
termination and keeps the running metrics of every ship, or only of those just restarted.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable, Sequence
from typing import Any, ClassVar, Protocol

import numpy as np

from ship_env.envs.dict_maker import dict_literal
from ship_env.envs.envelope import ENVELOPE_FIELDS, envelope_info
from ship_env.envs.sensors import MEASUREMENT_NAMES, MEASUREMENT_SIZE, measure, observe_motion
from ship_env.envs.task import ShipTask
from ship_env.model import Conditions, ShipModel, Simulator
from ship_env.model import state as S
from ship_env.model.integrators import borrowed
from ship_env.model.kernel import entry_point, kernel
from ship_env.model.simulator import batch_loop

#: The keys of every task's step information (:meth:`ShipBatch.info`), before the task's own.
INFO_KEYS = ("measurement", "state", "metrics", "envelope")

# The loop over a batch's ships, written once: serially (range) or on all cores (prange). The ship's index
# is passed signed, as range gives it, so that prange's unsigned one compiles no second ``update_ship``.
_UPDATE_LOOP = """
@{decorator}
def {name}(restarted_only, ship, *arrays):
    arrays = borrowed(arrays)
    states, conditions, step_index, episodes, task = arrays[0], arrays[1], arrays[3], arrays[4], arrays[6]
    for i in {ships}(episodes.shape[0]):
        if episodes[i]["restarted"] or not restarted_only:
            check_envelope(states[i], conditions[i], step_index[i], episodes[i], task[0], ship[0])
            update_ship(np.int64(i), *arrays)
"""
# One ship's simulator step and update in one compiled call: the arrays bound once and the call made
# through its entry point (:func:`~ship_env.model.kernel.entry_point`), the order last.
_SAIL_SHIP = """
@kernel
def sail_ship(draws, dt, method, work, ship, arrays, order):
    draws, work = borrowed((draws, work))
    states, conditions, noise_keys, step_index = borrowed(arrays[:4])
    valid = step_ship(states[0], order, conditions[0], noise_keys[0], step_index[0], draws[0], ship, dt, method, work)
    step_index[0] += 1
    if valid:
        update_ships(False, ship, *arrays)
    return valid
"""
#: The loops over a batch's ships, compiled into a task module by :func:`define_update_loops`: the
#: envelope's check (:func:`~ship_env.envs.envelope.check_envelope`: the limits in the task's parameter
#: record, its first task array; the model's record for the sway) and its ``update_ship(i, states,
#: conditions, noise_keys, step_index, episodes, metrics, *task_arrays)`` for every ship, or with
#: ``restarted_only`` for those just restarted; the arrays borrowed (no reference counts). And
#: ``sail_ship(draws, dt, method, work, ship, arrays, order)``: ship 0's simulator step
#: (:func:`~ship_env.model.integrators.step_ship`, its step counted) and, where its state stays
#: valid, its update; it returns the step's verdict.
UPDATE_LOOPS_SOURCE = "\n".join(
    (
        "import numpy as np",
        "from numba import prange",
        "from ship_env.envs.envelope import check_envelope",
        "from ship_env.model.integrators import borrowed, step_ship",
        "from ship_env.model.kernel import kernel, parallel_kernel",
        _UPDATE_LOOP.format(decorator="kernel", name="update_ships", ships="range"),
        _UPDATE_LOOP.format(decorator="parallel_kernel", name="update_ships_parallel", ships="prange"),
        _SAIL_SHIP,
    )
)


def define_update_loops(
    module_globals: dict[str, Any],
) -> tuple[Callable[..., None], Callable[..., None], Callable[..., bool]]:
    """Define ``update_ships``, ``update_ships_parallel`` and ``sail_ship`` (:data:`UPDATE_LOOPS_SOURCE`)
    in a task module around its ``update_ship`` and return them: compiled as the module's own source, they are
    cached beside its other kernels (numba keys the cache by the file and the bytecode, so a change
    to the template is compiled afresh). Call it as ``define_update_loops(globals())``."""
    exec(compile(UPDATE_LOOPS_SOURCE, module_globals["__file__"], "exec"), module_globals)
    return module_globals["update_ships"], module_globals["update_ships_parallel"], module_globals["sail_ship"]


def ship_info_maker(metric_names: Sequence[str], task_keys: Sequence[str]) -> Callable[..., dict[str, Any]]:
    """A function of ``(measurement, state, metrics, envelope, fields, ship)`` that returns one ship's step
    information (:meth:`ShipBatch.info`) as one dict literal compiled for its keys (:data:`INFO_KEYS`, then
    ``task_keys``): 0.4 of 2.2 us less than making each part's dict in a call of its own. ``measurement``
    and ``metrics`` are the values in the order of :data:`MEASUREMENT_NAMES` and ``metric_names``, made
    dicts; ``state`` and ``envelope`` are taken as they are; a task key's value is ``fields[key][ship]``."""
    task_items = "".join(f", {key!r}: fields[{key!r}][ship]" for key in task_keys)
    made: Callable[..., dict[str, Any]] = eval(
        "lambda measurement, state, metrics, envelope, fields, ship: {"
        f"'measurement': {dict_literal(MEASUREMENT_NAMES, 'measurement')}, 'state': state, "
        f"'metrics': {dict_literal(metric_names, 'metrics')}, 'envelope': envelope{task_items}}}"
    )
    return made


@kernel
def measure_and_observe(i, state, conditions, noise_keys, step_index, episode, sensors, restarted, first, task):
    """Read ship ``i``'s instruments into its ``episode`` record (:func:`~ship_env.envs.sensors.measure`)
    and observe its motion at ``observation[first:first + 3]`` (:func:`~ship_env.envs.sensors.observe_motion`);
    ``task`` is the task's parameter record (its ``rudder_limit``, ``full_rudder_rate_per_speed`` and
    ``observed_speed_scale``: the speed observed over it, or over the ship's service speed if 0)."""
    service_speed = conditions[i, S.SERVICE_SPEED]
    speed_scale = task["observed_speed_scale"] if task["observed_speed_scale"] > 0.0 else service_speed
    measured = episode["measurement"]
    measure(state, service_speed, episode["wave_yaw"], noise_keys[i], step_index[i], sensors, restarted, measured)
    observe_motion(
        episode["observation"],
        first,
        measured,
        state[S.RUDDER],
        service_speed,
        speed_scale,
        task["full_rudder_rate_per_speed"],
        task["rudder_limit"],
    )


def episode_dtype(observation_size: int, task_fields: Sequence[tuple]) -> np.dtype:
    """A task's per-ship episode record: the fields every task has, then ``task_fields``.

    Common fields: ``restarted`` (a new episode, not yet observed), ``terminated``, ``wave_yaw``
    (1 if the sea shows in the compass and gyro, H_s > 0), ``rudder`` (rad, the actual rudder at
    the previous update), ``reward``, ``observation`` (float32), ``measurement``
    (:mod:`ship_env.envs.sensors`) and the envelope's (:data:`~ship_env.envs.envelope.ENVELOPE_FIELDS`).
    """
    return np.dtype(
        [
            ("restarted", np.bool_),
            ("terminated", np.bool_),
            ("wave_yaw", np.float64),
            ("rudder", np.float64),
            ("reward", np.float64),
            ("observation", np.float32, (observation_size,)),
            ("measurement", np.float64, (MEASUREMENT_SIZE,)),
            *ENVELOPE_FIELDS,
            *task_fields,
        ]
    )


@kernel
def _read_outcomes(episodes, observations, rewards, terminated):
    """Every ship's observation, reward and termination out of its record, in one pass (numpy
    copies each strided field in a pass of its own, several times slower)."""
    episodes, observations = borrowed((episodes, observations))
    for i in range(episodes.shape[0]):
        episode = episodes[i]
        observation = episode["observation"]
        for k in range(observation.shape[0]):
            observations[i, k] = observation[k]
        rewards[i] = episode["reward"]
        terminated[i] = episode["terminated"]


class Scenario(Protocol):
    """What starting an episode needs from a task's scenario."""

    seed: int
    conditions: Conditions

    @property
    def initial_heading(self) -> float: ...


def pick(array: np.ndarray, index: Any) -> Any:
    """``array[index]``: a scalar as it is, an array as a copy."""
    value = array[index]
    return value.copy() if isinstance(value, np.ndarray) else value


def _only(info: dict[str, Any], keys: frozenset[str]) -> dict[str, Any]:
    """The items of ``info`` whose key is in ``keys``."""
    return {key: value for key, value in info.items() if key in keys}


def snapshot(array: np.ndarray, ships: int | slice) -> np.ndarray:
    """The structured array to read the ships' fields from: for one ship (an index) ``array``
    itself, whose fields read at the index are values; for all (``slice(None)``) a copy, made as
    bytes (numpy copies records field by field, and each field on its own, several times slower)."""
    return array.view(np.uint8).copy().view(array.dtype) if isinstance(ships, slice) else array


class ShipBatch:
    """N ships of one task in one :class:`~ship_env.model.Simulator`.

    Subclasses set ``task_fields`` (their episode record's own fields), ``task_info_keys`` (the fields
    of it that each step's information gives, under their names), ``metrics_dtype``,
    ``update_serial`` and ``update_parallel`` (compiled loops called as ``loop(restarted_only, model
    record, state, conditions, noise_keys, step_index, episodes, metrics, *task.kernel_arguments)``),
    ``sail_one`` (the compiled step and update of a batch of one ship, :data:`UPDATE_LOOPS_SOURCE`), and
    implement :meth:`start_episode`.

    After ``restart`` or a simulator step, ``update`` fills each ship's ``episodes`` record
    (``observation``, ``measurement``, ``reward``, ``terminated``) and its running ``metrics``.

    A ship whose state leaves the model's validity (``Simulator.step`` raises ``FloatingPointError``)
    stops the batch, unless ``end_diverged_episodes``: then only that ship's episode ends, marked in
    ``diverged`` (see :meth:`sail`), and the other ships sail on as if it were not there.
    """

    task_fields: ClassVar[Sequence[tuple]]
    task_info_keys: ClassVar[tuple[str, ...]] = ()
    metrics_dtype: ClassVar[np.dtype]
    update_serial: ClassVar[Callable[..., None]]
    update_parallel: ClassVar[Callable[..., None]]
    sail_one: ClassVar[Callable[..., bool]]

    def __init__(self, task: ShipTask, num_ships: int, end_diverged_episodes: bool = False) -> None:
        self.task = task
        self.simulator = task.simulator(num_ships)
        self.num_ships = self.simulator.num_ships
        self.end_diverged_episodes = end_diverged_episodes
        #: The ships whose state left the model's validity in the last :meth:`sail`, and that state.
        self.diverged = np.zeros(self.num_ships, dtype=np.bool_)
        self.diverged_states = np.zeros_like(self.simulator.state)
        self.scenarios: list[Any] = [None] * self.num_ships
        self.episodes = np.zeros(self.num_ships, dtype=episode_dtype(task.observation_space.shape[0], self.task_fields))
        self.metrics = np.zeros(self.num_ships, dtype=self.metrics_dtype)
        self._link()
        known = (*INFO_KEYS, *self.task_info_keys)
        if task.info_keys is not None:
            unknown = [key for key in task.info_keys if key not in known]
            if unknown:
                raise ValueError(f"info_keys: unknown keys {unknown} in {task.info_keys!r}; known: {', '.join(known)}")
        #: The keys :meth:`info` gives (it builds none where there are none).
        self.info_keys = frozenset(known if task.info_keys is None else task.info_keys)
        self._every_info_key = len(self.info_keys) == len(known)

    def _link(self) -> None:
        """Make the compiled update loop, the sailing of one ship (:meth:`_ship_sailing`), the
        views of the episode records' fields that one ship's :meth:`info` and :meth:`outcome` read (a
        view's lookup in a dict costs a fifth of numpy's field access) and the maker of one ship's
        information (:func:`ship_info_maker`): at construction, and again where a copy or a
        pickle (which make views independent arrays, and carry no made function) is restored."""
        self._update = batch_loop(self.num_ships, type(self).update_serial, type(self).update_parallel)
        self._sail_ship = self._ship_sailing()
        self._fields = {name: self.episodes[name] for name in self.episodes.dtype.names or ()}
        self._ship_info = ship_info_maker(self.metrics_dtype.names or (), self.task_info_keys)

    def _ship_sailing(self) -> Callable[[float], bool] | None:
        """One ship's :meth:`sail` of one simulator step in one compiled call (the task's ``sail_one``
        through its entry point, every argument but the order bound), which returns the step's verdict:
        for a batch of one ship of ship_env's simulator that ends no diverged episode, holds each
        order one step and remembers no observations; else ``None``. Made afresh with the simulator."""
        task = self.task
        if (
            self.num_ships != 1
            or task.sailing_model is None
            or self.end_diverged_episodes
            or task.decision_interval != 1
            or task.observation_history
        ):
            return None
        simulator = self.simulator
        arrays = (simulator.state, simulator.conditions, simulator.noise_keys, simulator.step_index)
        arguments = (
            *simulator.step_arguments(),
            simulator.model.record,
            (*arrays, self.episodes, self.metrics, *task.kernel_arguments),
        )
        return functools.partial(entry_point(type(self).sail_one, *arguments, 0.0), *arguments)

    def __getstate__(self) -> dict[str, Any]:
        """The attributes a copy or a pickle carries: all but those :meth:`_link` makes afresh where they
        are restored: numba rebuilds a pickled compiled function from its code, without its cache, and
        compiles it again (a spawned worker: 11.7 s against 4.1 s, ``tests/test_envs_copies.py``)."""
        state = self.__dict__.copy()
        del state["_update"], state["_sail_ship"], state["_fields"], state["_ship_info"]
        return state

    def __setstate__(self, state: dict[str, Any]) -> None:
        self.__dict__.update(state)
        self._link()

    def restart(self, ships: np.ndarray, scenarios: Sequence[Scenario]) -> None:
        """Start new episodes for ``ships`` (sorted indices), one scenario each; the others sail on.

        Where the scenarios need a model with more effects (``ShipTask.model_for``: waves the model has no
        effect for), every ship sails that model from now on (:meth:`_sail_model`)."""
        model = self.task.model_for(scenario.conditions for scenario in scenarios)
        if model is not self.simulator.model:
            self._sail_model(model)
        self._start_simulator(ships, scenarios)
        episodes = self.episodes
        episodes["wave_yaw"][ships] = [scenario.conditions.wave_height > 0.0 for scenario in scenarios]
        episodes["restarted"][ships] = True
        self.diverged[ships] = False
        episodes["terminated"][ships] = False
        for ship, scenario in zip(ships, scenarios, strict=True):
            self.start_episode(episodes[ship], scenario)
            self.scenarios[ship] = scenario

    def _sail_model(self, model: ShipModel) -> None:
        """Sail ``model`` from now on: a simulator of it that goes on from this one's ships, their states,
        conditions, seeds, step counts and the draws of the effects both models have (a ship sailing on
        meets no waves: the new effects' draws stay 0)."""
        old = self.simulator
        new = Simulator(model, num_ships=self.num_ships, dt=old.dt, method=old.method)
        columns = [model.state_names.index(name) for name in old.model.state_names]
        new.state[:, columns] = old.state
        for name in ("conditions", "seeds", "noise_keys", "step_index"):
            getattr(new, name)[:] = getattr(old, name)
        kept = {(placed.entry.effect.name, placed.draw.name): placed for placed in old.model.draw_layout}
        for placed in model.draw_layout:
            before = kept.get((placed.entry.effect.name, placed.draw.name))
            if before is not None:
                new.draws[:, placed.start : placed.start + placed.size] = old.draws[
                    :, before.start : before.start + before.size
                ]
        self.simulator = new
        self._sail_ship = self._ship_sailing()

    def _start_simulator(self, ships: np.ndarray, scenarios: Sequence[Scenario]) -> None:
        """Start the simulator's ``ships`` as their ``scenarios`` start them."""
        self.simulator.reset(
            seed=[scenario.seed for scenario in scenarios],
            conditions=[scenario.conditions for scenario in scenarios],
            heading=np.asarray([scenario.initial_heading for scenario in scenarios]),
            ships=ships,
        )

    def start_episode(self, episode: np.void, scenario: Any) -> None:
        """Write a new episode's task fields into its record."""
        raise NotImplementedError

    def update(self, restarted_only: bool = False) -> None:
        """Measure, observe and reward every ship, or only the restarted ones (one compiled call)."""
        if self.task.observation_history:
            previous = self.episodes["observation"][:, list(self.task.history_observations)]
            restarted = self.episodes["restarted"].copy()
            stepped = np.zeros_like(restarted) if restarted_only else ~restarted
        self._update_records(restarted_only)
        if self.task.observation_history:
            self._remember(previous, stepped, restarted)

    def sail(
        self,
        orders: float | np.ndarray,
        restarting: np.ndarray | None = None,
        restart: Callable[[], None] | None = None,
    ) -> None:
        """Hold the ordered rudder ``orders`` (rad) for the task's ``decision_interval`` simulator steps,
        updating every ship after each, and leave in the records the environment step's outcome.

        Each ship's ``reward`` is the sum over the steps; a ship whose episode terminates within the
        interval keeps the records (episode and metrics) of its terminal step (its simulator state
        sails on until its restart). ``restart`` (the vector environment's autoreset) starts new
        episodes for the ``restarting`` ships (a bool mask) after the last simulator step, before
        the last update: those get their first observation and reward 0.

        With ``end_diverged_episodes``, a ship whose state leaves the model's validity at a simulator
        step is marked in ``diverged`` and keeps the records of the step before (a finite
        observation), its reward the sum over the steps before that one (0 with a
        ``decision_interval`` of 1); its state is kept in ``diverged_states`` and its simulator row
        starts afresh from its scenario, so no state outside the validity is stepped or measured
        again before its restart. The other ships' numbers do not depend on it.
        """
        if self._sail_ship is not None and restart is None and isinstance(orders, float) and math.isfinite(orders):
            self.simulator.stepped(self._sail_ship(orders))  # the step and the update in one call
            return
        interval = self.task.decision_interval
        if self.end_diverged_episodes:
            self.diverged[:] = False
        if interval == 1:  # the plain step: nothing to hold or sum
            diverged = self._step_simulator(orders, restarting)
            if restart is not None:
                restart()
            if diverged is None:
                self.update()
                return
            last_episodes, last_metrics = self.episodes[diverged], self.metrics[diverged]
            self.update()
            self.episodes[diverged], self.metrics[diverged] = last_episodes, last_metrics
            self.episodes["reward"][diverged] = 0.0
            return
        restarting = np.zeros(self.num_ships, dtype=np.bool_) if restarting is None else restarting
        history = self.task.observation_history
        if history:
            previous = self.episodes["observation"][:, list(self.task.history_observations)]
        total = np.zeros(self.num_ships)
        ended = restarting.copy()  # ships whose records no longer change
        held_episodes = self.episodes.copy()
        held_metrics = self.metrics.copy()
        for step in range(interval):
            diverged = self._step_simulator(orders, ended)
            if restart is not None and step == interval - 1:
                restart()
            if diverged is not None:  # it keeps the records of the step before
                held_episodes[diverged] = self.episodes[diverged]
                held_metrics[diverged] = self.metrics[diverged]
                ended |= diverged
            self._update_records(False)
            sailing = ~ended
            total[sailing] += self.episodes["reward"][sailing]
            finished = sailing & self.episodes["terminated"]
            held_episodes[finished] = self.episodes[finished]
            held_metrics[finished] = self.metrics[finished]
            ended |= finished
        terminated = ended & ~restarting
        self.episodes[terminated] = held_episodes[terminated]
        self.metrics[terminated] = held_metrics[terminated]
        self.episodes["reward"][~restarting] = total[~restarting]
        if history:
            self._remember(previous, ~restarting, restarting)

    def _step_simulator(self, orders: float | np.ndarray, ended: np.ndarray | None) -> np.ndarray | None:
        """One simulator step. A ship whose state leaves the model's validity raises
        ``FloatingPointError`` unless ``end_diverged_episodes``: then every such ship's row starts
        afresh from its scenario, and those whose episode had not ``ended`` (a mask; None: none had)
        are marked in ``diverged``, their states kept in ``diverged_states``, and returned as a mask
        (None if there are none; :meth:`sail`)."""
        try:
            self.simulator.step(orders)
            return None
        except FloatingPointError:
            state = self.simulator.state
            invalid = self.simulator.invalid_ships()
            if not (self.end_diverged_episodes and invalid.any()):
                raise
        diverged = invalid if ended is None else invalid & ~ended
        self.diverged_states[diverged] = state[diverged]
        self.diverged |= diverged
        ships = np.flatnonzero(invalid)
        self._start_simulator(ships, [self.scenarios[ship] for ship in ships])
        return diverged if diverged.any() else None

    def _update_records(self, restarted_only: bool) -> None:
        """The task's compiled update of every ship's records, or of the restarted ones only."""
        simulator = self.simulator
        self._update(
            restarted_only,
            self.task.model.record,
            simulator.state,
            simulator.conditions,
            simulator.noise_keys,
            simulator.step_index,
            self.episodes,
            self.metrics,
            *self.task.kernel_arguments,
        )

    def _remember(self, previous: np.ndarray, stepped: np.ndarray, restarted: np.ndarray) -> None:
        """Shift the ``stepped`` ships' remembered observations by one step (``previous`` the newest);
        fill a ``restarted`` ship's history with its first observation (a ship sailing steadily)."""
        remembered = list(self.task.history_observations)
        observations = self.episodes["observation"]
        history = observations[:, len(observations[0]) - len(remembered) * self.task.observation_history :]
        history = history.reshape(self.num_ships, self.task.observation_history, len(remembered))
        history[stepped, 1:] = history[stepped, :-1]
        history[stepped, 0] = previous[stepped]
        history[restarted] = observations[restarted][:, None, remembered]

    @property
    def observations(self) -> np.ndarray:
        """(N, observation size) float32, a copy."""
        return self.episodes["observation"].copy()

    def outcomes(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Copies of the last update's observations (N, observation size) float32, rewards (N,) and
        terminations (N,) bool (the ships whose episode reached its terminal state)."""
        observations = np.empty(self.episodes["observation"].shape, dtype=np.float32)
        rewards = np.empty(self.num_ships)
        terminated = np.empty(self.num_ships, dtype=np.bool_)
        _read_outcomes(self.episodes, observations, rewards, terminated)
        return observations, rewards, terminated

    def outcome(self, ship: int) -> tuple[np.ndarray, float, bool]:
        """Ship ``ship``'s last update's observation (a copy), reward and termination (Python numbers),
        read from the records' field views."""
        fields = self._fields
        return fields["observation"][ship].copy(), fields["reward"].item(ship), fields["terminated"].item(ship)

    def info(self, ships: int | slice) -> dict[str, Any]:
        """The step's information for one ship (an index: scalars) or all (``slice(None)``: arrays), its
        keys those of the task's ``info_keys`` (all by default, in this order; none built with ``()``).

        ``measurement``: the bridge's instruments (``sensors.MEASUREMENT_NAMES``); ``state``: the
        ship's true state (layout ``ship_env.model.state``; of a ship that diverged in the last
        :meth:`sail`, the state that left the model's validity); ``metrics``: the episode's metrics so
        far (final at its last step); ``envelope``: whether the ship has stayed inside its model's
        validity envelope this episode and, once it left, where and why
        (:func:`~ship_env.envs.envelope.envelope_info`); then the task's own keys (``task_info_keys``: its
        episode record's fields of these names). Arrays are copies (the measurements and metrics views of
        one copy of the records); one ship's measurements and metrics are Python numbers, each record read
        in one call, its task keys numpy scalars read from the records' field views, and its information
        made by one compiled literal (:func:`ship_info_maker`).
        """
        if not self.info_keys:
            return {}
        if isinstance(ships, slice):
            episodes = snapshot(self.episodes, ships)
            metrics = snapshot(self.metrics, ships)
            measurements = episodes["measurement"][ships].T
            state = pick(self.simulator.state, ships)
            if self.diverged.any():
                state[self.diverged] = self.diverged_states[self.diverged]
            info = {
                "measurement": {name: measurements[k] for k, name in enumerate(MEASUREMENT_NAMES)},
                "state": state,
                "metrics": {name: metrics[name][ships] for name in self.metrics_dtype.names or ()},
                "envelope": envelope_info(episodes, ships),
                **{key: episodes[key][ships] for key in self.task_info_keys},
            }
        else:
            fields = self._fields
            info = self._ship_info(
                fields["measurement"][ships].tolist(),
                self.simulator.state[ships].copy(),
                self.metrics.item(ships),  # item(i) makes no record scalar
                envelope_info(fields, ships),
                fields,
                ships,
            )
        return info if self._every_info_key else _only(info, self.info_keys)

    def end_info(self, ships: int | slice) -> dict[str, Any]:
        """Keys added to the information of the step that terminates an episode."""
        return {}
