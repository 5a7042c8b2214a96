"""Replay measured runs through the model: the measured inputs in, the simulated outputs out.

Each run is replayed sample by sample with the measured rudder, propeller rate and wind held over
each interval (zero-order hold, as the simulator holds its conditions over a step): these are the
replay's *inputs* (:data:`INPUTS`). Two kinds of replay:

- **free**: the model's own heading, rate of turn, speed and track, integrated by the simulator's
  compiled step (``ship_env.model.integrators.step_ship_with_noise``, RK4, with zero white noise) from
  the run's initial state: the ship sailing free under the measured inputs;
- **track**: the measured heading and rate of turn -- and the measured speed, where the log has a
  speed channel -- are imposed and only the track is integrated (the speed loss too where the speed is
  not measured), by Heun's method on the model's own state derivative
  (``ship_env.model.dynamics.derivatives``). It isolates the track effects -- sway (2.47-2.49),
  leeway, current (2.71, 2.72) -- from errors in the heading and the speed.

**Speed is an output, not an input.** A speed channel sets only the run's service speed U0 and its
initial speed: U0 is the speed the ship keeps on a straight course at the run's propeller setting,
estimated as the highest speed of the run (the mean over the time it takes to sail one ship length,
where that mean is highest), since the model's speed u = U0 (1 - u*) (2.53) never exceeds U0 in steady
sailing (u* >= 0 with K_u* r*^2 >= 0, 2.55); the initial speed loss is u*(0) = 1 - u(0) / U0 with u(0)
the measured speed at the first sample (estimated over the initial window, :func:`initial_window`, as
the other states). From there the model's own speed loss (``speed_loss``, 2.55) is integrated and its
speed U0 (1 - u*) is the replay's ``SPEED`` column: a run that starts slower than U0 (a model test
from rest) accelerates towards it by the same first-order surge equation. A log that gives its service
speed (``Log.service_speed``) has that U0; a stretch cut from a run (``envelope.segments_inside``)
keeps its whole run's. Without a speed channel the log's or the ship's service speed is U0 and u*(0) =
0; the speed loss then shows only through the heading and the track, which do not identify it.
A log without a propeller channel is replayed at the ship's service propeller rate (its preset's
``service_conditions``; 0 where it states none).

Many replays run in one compiled call over all cores: a *task* is one run replayed with one
parameter record, so a fit evaluates every finite-difference perturbation of every run at once.
The batch's records may differ (unlike :class:`~ship_env.model.Simulator`, whose batch shares one).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numba import prange

from ship_env.model import EFFECTS, ShipModel, draws
from ship_env.model import state as S
from ship_env.model.contributions import WIND as WIND_QUANTITIES
from ship_env.model.contributions import derivative_quantity
from ship_env.model.dynamics import derivatives
from ship_env.model.integrators import RK4, WORK_ROWS, borrowed, step_ship_with_noise
from ship_env.model.kernel import kernel, parallel_kernel
from ship_env.workbench.logs.logs import Log

#: Columns of a replay's output: the track, heading, rate of turn and speed through the water u, m/s.
NORTH, EAST, HEADING, RATE, SPEED = 0, 1, 2, 3, 4
OUTPUT_SIZE = 5
#: What a replay takes from a log as an input (held over each sample interval), channel by channel where the
#: log has it; the speed is not among them (the module docstring).
INPUTS = ("rudder", "propeller_rate", "wind_speed", "wind_direction")
#: The shortest time, s, at a run's start from which its initial state is estimated (:func:`initial_window`).
INITIAL_WINDOW = 2.0
#: The usual time over which it is estimated, in ship lengths sailed at the run's service speed.
INITIAL_WINDOW_LENGTHS = 0.5
#: Samples per ship length sailed that a fit needs at most to see a zig-zag's rudder moves (:func:`coarser_step`): a
#: steering machine at IMO's rate (35 to 30 deg in 28 s at full scale, Froude-scaled for a model) moves the rudder by
#: 20 deg in 0.2 to 0.45 of the time the ship takes to sail its length, so each move keeps five samples or more.
SAMPLES_PER_LENGTH = 25.0


@dataclass(frozen=True)
class ReplayModel:
    """A ship model plus what a fit may add to the runs' conditions: a steady current.

    Attributes:
        model: the ship model (preset, effects, parameter values).
        current_north, current_east: the current's velocity, m/s (used when ``current`` is on).
    """

    model: ShipModel
    current_north: float = 0.0
    current_east: float = 0.0

    @property
    def current(self) -> tuple[float, float]:
        return (self.current_north, self.current_east) if self.model.has("current") else (0.0, 0.0)


@dataclass(frozen=True)
class PackedRuns:
    """The runs' measured inputs and outputs, concatenated for the compiled replay.

    Run ``i`` occupies rows ``offsets[i]:offsets[i + 1]`` of every per-sample array.
    ``measured_speed_loss`` is the measured speed as u* = 1 - max(u, 0) / U0 (imposed by the track
    replay), NaN in a run without a speed channel.
    """

    offsets: np.ndarray
    time: np.ndarray
    rudder: np.ndarray
    conditions: np.ndarray
    heading: np.ndarray
    rate_of_turn: np.ndarray
    initial_states: np.ndarray
    measured_speed_loss: np.ndarray

    @property
    def longest(self) -> int:
        return int(np.max(np.diff(self.offsets)))


#: The rates of the motion's states, as what ``dynamics`` makes them of; another state's rate is
#: ``<state>_derivative``. The rudder moves to the step's actual rudder.
_MOTION_RATES: dict[str, tuple[str, ...]] = {
    "time": (),
    "north": ("ground_velocity",),
    "east": ("ground_velocity",),
    "heading": ("rate_of_turn",),
    "rate_of_turn": ("hull_yaw_acceleration", "yaw_acceleration"),
    "rudder": ("actual_rudder",),
}
#: The velocity over the ground before the contributions that read the apparent wind, which it makes.
_STILL_AIR_GROUND_VELOCITY = "ground_velocity before the wind"
#: What the inputs and quantities read besides their contributions' arguments (``dynamics``' preamble,
#: the apparent wind from the velocity over the ground, the quantities' starting values).
_IMPLICIT: dict[str, tuple[str, ...]] = {
    "speed": ("speed_loss",),
    "scheduling_speed": ("speed_loss",),
    "normalised_rate": ("rate_of_turn", "speed_loss"),
    "cos_heading": ("heading",),
    "sin_heading": ("heading",),
    "relative_wind_speed": (_STILL_AIR_GROUND_VELOCITY, "heading"),
    "cos_wind": (_STILL_AIR_GROUND_VELOCITY, "heading"),
    "sin_wind": (_STILL_AIR_GROUND_VELOCITY, "heading"),
    "ground_velocity": (_STILL_AIR_GROUND_VELOCITY,),
    "effective_rudder": ("rudder",),
    "inflow_speed_squared": ("speed",),
}


def moved_replays(model: ShipModel, key: str, speed_measured: bool = False) -> tuple[bool, bool]:
    """Whether a change of the term ``key`` can move a free replay's heading, rate of turn and speed, and a
    track replay's north and east -- from the model's equations, not from numbers.

    A term moves a replay where some contribution of an effect of the model reads it (a white-noise
    intensity never does: a replay's white noise is zero) and what that contribution changes feeds
    the replay's outputs: the track replay imposes the measured heading and rate of turn (and the
    measured speed, where every log has one: ``speed_measured``) and holds the rudder, so a yaw term
    never moves it, and a current (read as the conditions
    ``current_speed``, ``current_direction`` and those derived from them, ``current_north``,
    ``current_east``) moves the heading only where a yaw contribution reads the current or the
    velocity over the ground. A term that is not an effect's parameter or the current (a principal
    particular) is taken to move both.
    """
    effect, _, name = key.partition(".")
    if effect == "current":
        names = {"current_speed", "current_direction", "current_north", "current_east"}
    elif name and effect in EFFECTS:
        names = {EFFECTS[effect].field_name(name)}  # read by another effect's contribution
    else:
        return True, True
    writers: dict[str, list[tuple[str, tuple[str, ...]]]] = {}  # quantity -> (effect, what it reads)
    for entry in (EFFECTS.entry(effect_name) for effect_name in model.effects):
        for quantity, function in ((c.quantity, c.function) for c in entry.contributions):
            arguments = entry.arguments(function)
            if quantity == "ground_velocity" and not set(WIND_QUANTITIES).intersection(arguments):
                quantity = _STILL_AIR_GROUND_VELOCITY
            writers.setdefault(quantity, []).append((entry.effect.name, arguments))

    def reads(owner: str, arguments: tuple[str, ...]) -> bool:
        return bool(names.intersection(arguments)) or (owner == effect and name in arguments)

    states = set(S.MOTION_STATES) | {state.name for e in model.effects for state in EFFECTS.entry(e).new_states}

    def moves(outputs: tuple[str, ...], imposed: tuple[str, ...]) -> bool:
        needed: set[str] = set()
        pending = list(outputs)
        while pending:
            what = pending.pop()
            if what in needed:
                continue
            needed.add(what)
            if what in states and what not in imposed:
                pending += _MOTION_RATES.get(what, (derivative_quantity(what),))
            pending += _IMPLICIT.get(what, ())
            for owner, arguments in writers.get(what, ()):
                if reads(owner, arguments):
                    return True
                pending += arguments
        return False

    imposed = ("heading", "rate_of_turn", "rudder", *(("speed_loss",) if speed_measured else ()))
    return moves(("heading", "rate_of_turn", "speed_loss"), ()), moves(("north", "east"), imposed)


def service_speed(log: Log, model: ShipModel) -> float:
    """The run's service speed U0, m/s: the log's own where it gives one; else, with a speed channel, its
    :func:`highest_speed`; else the ship's."""
    if log.service_speed is not None:
        return log.service_speed
    highest = highest_speed(log, model.length)
    return model.service_speed if highest is None else highest


def samples_per_length(log: Log, model: ShipModel) -> float:
    """How densely a run samples the ship's motion: its samples per ship length sailed at its service speed,
    L / (U0 dt), with dt its median sample interval (inf for a single sample)."""
    interval = float(np.median(np.diff(log.time))) if log.samples > 1 else 0.0
    return model.length / (service_speed(log, model) * interval) if interval > 0.0 else math.inf


def coarser_step(logs: Sequence[Log], model: ShipModel) -> int:
    """The largest sample step (``--every``) that keeps every run at :data:`SAMPLES_PER_LENGTH` samples per ship length
    sailed or more (1: none coarser)."""
    sparsest = min(samples_per_length(log, model) for log in logs)
    if not math.isfinite(sparsest):
        return 1
    return max(math.floor(sparsest / SAMPLES_PER_LENGTH + 1e-9), 1)  # 1e-9: a whole ratio's rounding


def highest_speed(log: Log, length: float) -> float | None:
    """The highest mean speed of a run over the time a ship of ``length`` (m) takes to sail its length at the
    run's median speed (long enough that the sensor's noise hardly lifts the highest mean), m/s; None without
    a speed channel or where the ship never moves ahead."""
    if log.speed is None:
        return None
    speed = np.maximum(log.speed, 0.0)
    typical = float(np.median(speed))
    interval = float(np.median(np.diff(log.time))) if log.samples > 1 else 0.0
    window = length / typical if typical > 0.0 else 0.0
    count = int(min(max(round(window / interval), 1), log.samples)) if interval > 0.0 else 1
    highest = float(np.max(np.convolve(speed, np.full(count, 1.0 / count), mode="valid")))
    return highest if highest > 0.0 else None


def initial_window(log: Log, length: float, speed: float) -> float:
    """Seconds at a run's start from which its initial state is estimated by default: the time to sail
    ``INITIAL_WINDOW_LENGTHS`` ship lengths at the run's service speed ``speed`` (U0), at least
    ``INITIAL_WINDOW`` and at most half the run. A 320 m tanker at 8 m/s averages 20 s of its sensors, a 3 m
    model at 0.6 m/s 2.5 s: short against the ship's own time scale (its yaw time constant tau* L / U, 1.5
    to 3 ship lengths), long enough that sea-trial sensors at 1 Hz average out. A free replay carries its
    initial errors to the end: an initial rate of turn off by 0.02 deg/s (a rate gyro's noise, a straight
    line through 3 samples) turns a tanker, whose yaw time constant is 90 s, 1.8 deg off its course."""
    longest = 0.5 * float(log.time[-1] - log.time[0])
    usual = INITIAL_WINDOW_LENGTHS * length / speed if speed > 0.0 else INITIAL_WINDOW
    return min(max(usual, INITIAL_WINDOW), longest)


def initial_state(log: Log, window: float = INITIAL_WINDOW, speed: float | None = None) -> np.ndarray:
    """The run's motion (``state.MOTION_STATES``) at its first sample, estimated from its first ``window`` seconds.

    Less noisy than the first sample alone, and unbiased where the ship already accelerates: the rate
    of turn is the intercept of a straight line through the measured rate, the position and the speed
    that of a straight line; the heading, with a rate gyro, the mean of psi_k - integral_{t0}^{t_k} r dt
    (the measured rate integrated by the trapezoidal rule: psi(t0) plus the compass's noise, whatever the
    ship does), without one the intercept of a parabola, and the rate its slope; the actual rudder is the
    first rudder sample. With the run's service speed ``speed`` (U0, :func:`service_speed`) and a speed
    channel, the speed loss is u*(0) = 1 - u(0) / U0, within [0, 1]; else 0. A ``window`` of 0 takes the
    first samples as they are.
    """
    inside = log.time - log.time[0] <= window
    elapsed = log.time[inside] - log.time[0]

    def polynomial(values: np.ndarray, degree: int) -> np.ndarray:
        """Coefficients, constant first, of a polynomial fitted over the window (lower degree if few samples)."""
        degree = min(degree, len(elapsed) - 1)
        coefficients = np.polynomial.polynomial.polyfit(elapsed, values[inside], degree) if degree > 0 else values[:1]
        return np.pad(coefficients, (0, 3 - len(coefficients)))

    state = np.zeros(S.MOTION_SIZE)
    state[S.TIME] = log.time[0]
    if log.rate_of_turn is None:
        heading = polynomial(log.heading, 2)
        state[S.HEADING], state[S.RATE_OF_TURN] = heading[0], heading[1]
    else:
        rate, time = log.rate_of_turn[inside], log.time[inside]
        turned = np.concatenate(([0.0], np.cumsum(np.diff(time) * 0.5 * (rate[1:] + rate[:-1]))))  # psi - psi(t0)
        state[S.HEADING] = float(np.mean(log.heading[inside] - turned))
        state[S.RATE_OF_TURN] = polynomial(log.rate_of_turn, 1)[0]
    if log.north is not None and log.east is not None:
        state[S.NORTH] = polynomial(log.north, 1)[0]
        state[S.EAST] = polynomial(log.east, 1)[0]
    state[S.RUDDER] = log.rudder[0]
    if speed is not None and log.speed is not None:
        state[S.SPEED_LOSS] = min(max(1.0 - polynomial(np.maximum(log.speed, 0.0), 1)[0] / speed, 0.0), 1.0)
    return state


def _conditions(log: Log, model: ShipModel, speed: float) -> np.ndarray:
    """The run's conditions sample by sample, at its service speed ``speed`` (U0, m/s)."""
    rows = np.zeros((log.samples, S.CONDITION_SIZE))
    rows[:, S.SERVICE_SPEED] = speed
    if log.propeller_rate is not None:
        rows[:, S.PROPELLER_RATE] = log.propeller_rate  # signed: astern is negative (``propeller_astern``)
    else:  # the ship's operating point (0 where its preset states none)
        rows[:, S.PROPELLER_RATE] = model.service_propeller_rate
    if log.wind_speed is not None and log.wind_direction is not None:
        rows[:, S.WIND_SPEED] = np.maximum(log.wind_speed, 0.0)
        rows[:, S.WIND_DIRECTION] = log.wind_direction
    S.derive_conditions(rows)
    return rows


def pack_runs(logs: Sequence[Log], model: ShipModel, window: float | None = None) -> PackedRuns:
    """Concatenate the logs' inputs and outputs; ``model`` supplies the default service speed, its
    state's layout and its effects' own states' initial values at each run's first sample, estimated over
    ``window`` seconds (default: each run's :func:`initial_window`)."""
    speeds = [service_speed(log, model) for log in logs]
    conditions = [_conditions(log, model, speed) for log, speed in zip(logs, speeds, strict=True)]
    initial_states = np.zeros((len(logs), model.state_size))
    initial_states[:, : S.MOTION_SIZE] = [
        initial_state(log, initial_window(log, model.length, speed) if window is None else window, speed)
        for log, speed in zip(logs, speeds, strict=True)
    ]
    model.start_states(initial_states, np.stack([rows[0] for rows in conditions]))
    measured_speed_loss = [
        np.full(log.samples, np.nan) if log.speed is None else 1.0 - np.maximum(log.speed, 0.0) / speed
        for log, speed in zip(logs, speeds, strict=True)
    ]
    return PackedRuns(
        offsets=np.concatenate([[0], np.cumsum([log.samples for log in logs])]).astype(np.int64),
        time=np.concatenate([log.time for log in logs]),
        rudder=np.concatenate([log.rudder for log in logs]),
        conditions=np.concatenate(conditions),
        heading=np.concatenate([log.heading for log in logs]),
        rate_of_turn=np.concatenate([log.rate_of_turn_or_smoothed for log in logs]),
        initial_states=initial_states,
        measured_speed_loss=np.concatenate(measured_speed_loss),
    )


@kernel
def _track_step(state, first, conditions, time, heading, rate, speed_loss, params, slope, stage, white_noise, draws):
    """Advance north, east, the speed loss and the effects' own states over one interval with the measured
    heading imposed (Heun); the measured speed too where there is one (``speed_loss`` not NaN)."""
    p = params[0]
    dt = time[first + 1] - time[first]
    speed_measured = not math.isnan(speed_loss[first])
    state[S.HEADING] = heading[first]
    state[S.RATE_OF_TURN] = rate[first]
    if speed_measured:
        state[S.SPEED_LOSS] = speed_loss[first]
    # One call site for both slopes (inlined once: half the compile time, the same numbers).
    for index in range(2):
        for j in range(state.shape[0]):
            stage[j] = state[j] if index == 0 else state[j] + dt * slope[0, j]
        stage[S.HEADING] = heading[first + index]
        stage[S.RATE_OF_TURN] = rate[first + index]
        if speed_measured:
            stage[S.SPEED_LOSS] = speed_loss[first + index]
        derivatives(stage, state[S.RUDDER], conditions, white_noise, draws, 0.0, p, slope[index])
    for j in (S.TIME, S.NORTH, S.EAST, S.SPEED_LOSS):
        state[j] += 0.5 * dt * (slope[0, j] + slope[1, j])
    for j in range(S.MOTION_SIZE, state.shape[0]):
        state[j] += 0.5 * dt * (slope[0, j] + slope[1, j])
    state[S.HEADING] = heading[first + 1]
    state[S.RATE_OF_TURN] = rate[first + 1]
    if speed_measured:
        state[S.SPEED_LOSS] = speed_loss[first + 1]
    return math.isfinite(state[S.NORTH]) and math.isfinite(state[S.EAST]) and state[S.SPEED_LOSS] <= 1.0


@kernel
def _record(out, task, sample, state, service_speed):
    out[task, sample, NORTH] = state[S.NORTH]
    out[task, sample, EAST] = state[S.EAST]
    out[task, sample, HEADING] = state[S.HEADING]
    out[task, sample, RATE] = state[S.RATE_OF_TURN]
    out[task, sample, SPEED] = service_speed * (1.0 - state[S.SPEED_LOSS])  # (2.53)


@kernel
def _replay_task(task, work, row, records, tasks, runs, no_draws, out, valid_samples):
    """Replay task ``task`` of ``_replay`` with the scratch space ``work`` and a row of conditions ``row``."""
    task_record, task_run, task_track, task_initial, task_current = tasks
    offsets, time, rudder, conditions, heading, rate, speed_loss = runs
    # Borrowed (see ``integrators.borrowed``): the arrays pass on to each step at no reference-counting cost.
    work, row, records, task_initial, time, rudder, conditions, heading, rate, speed_loss, no_draws, out = borrowed(
        (work, row, records, task_initial, time, rudder, conditions, heading, rate, speed_loss, no_draws, out)
    )
    size = task_initial.shape[1]
    step_work = work[:WORK_ROWS]
    slope = work[WORK_ROWS : WORK_ROWS + 2]
    stage = work[WORK_ROWS + 2]
    white_noise = work[WORK_ROWS + 3]  # zero: a replay's white noise is its expected value
    state = work[WORK_ROWS + 4]
    params = records[task_record[task] : task_record[task] + 1]
    first = offsets[task_run[task]]
    count = offsets[task_run[task] + 1] - first
    for j in range(size):
        state[j] = task_initial[task, j]
    # The task's current, derived once (``state.derive_conditions``) and written into every step's row.
    row[S.CURRENT_SPEED] = math.hypot(task_current[task, 0], task_current[task, 1])
    row[S.CURRENT_DIRECTION] = math.atan2(task_current[task, 1], task_current[task, 0])
    S.derive_conditions(row[np.newaxis])
    current_speed, current_direction = row[S.CURRENT_SPEED], row[S.CURRENT_DIRECTION]
    current_north, current_east = row[S.CURRENT_NORTH], row[S.CURRENT_EAST]
    inside = True
    valid_samples[task] = count
    _record(out, task, 0, state, conditions[first, S.SERVICE_SPEED])
    for k in range(count - 1):
        i = first + k
        for j in range(S.CONDITION_SIZE):
            row[j] = conditions[i, j]
        row[S.CURRENT_SPEED] = current_speed
        row[S.CURRENT_DIRECTION] = current_direction
        row[S.CURRENT_NORTH] = current_north
        row[S.CURRENT_EAST] = current_east
        if inside:
            if task_track[task]:
                inside = _track_step(
                    state, i, row, time, heading, rate, speed_loss, params, slope, stage, white_noise, no_draws
                )
            else:
                inside = step_ship_with_noise(
                    state, rudder[i], row, white_noise, no_draws, params, time[i + 1] - time[i], RK4, step_work
                )
            if not inside:
                valid_samples[task] = k + 1
        if inside:
            _record(out, task, k + 1, state, row[S.SERVICE_SPEED])
        else:
            for j in range(OUTPUT_SIZE):
                out[task, k + 1, j] = out[task, k, j]


@parallel_kernel
def _replay(records, tasks, runs, no_draws, out, valid_samples):
    """Replay every task (one run with one record) into ``out[task, sample, column]``.

    ``tasks`` holds the tasks' arrays (record index, run index, track flag, initial state, current),
    ``runs`` the packed runs' (offsets, time, rudder, conditions, heading, rate of turn, measured speed loss).
    ``valid_samples[task]`` receives how many samples the task's state stayed inside the model's
    validity (the run's length if it never left); after that its outputs are held at the last valid
    state, so that a fitter sees a large but finite error. A replayed log
    meets no random numbers: its effects' draws (a random sea) are ``no_draws``, zeros, and their
    white noise (gusts) is zero, its expected value.
    """
    size = tasks[3].shape[1]
    for task in prange(tasks[0].shape[0]):
        # The step's scratch space, then the track step's two slopes, its stage and white noise, the state;
        # the task's index as a signed integer, as in ``_replay``'s typing before prange's unsigned loop, so
        # that ``_replay_task`` is compiled once.
        _replay_task(
            np.int64(task),
            np.zeros((WORK_ROWS + 5, size)),
            np.zeros(S.CONDITION_SIZE),
            records,
            tasks,
            runs,
            no_draws,
            out,
            valid_samples,
        )


@dataclass(frozen=True)
class Tasks:
    """A batch of replays: task ``i`` replays run ``run[i]`` with record ``record[i]``.

    Attributes:
        record: index into the records array.
        run: index of the run in the packed runs.
        track: True for a track replay (measured heading imposed), False for a free one.
        initial_offset: (tasks, MOTION_SIZE) added to the motion of the run's estimated initial state.
        current: (tasks, 2) the current's north and east velocity, m/s.
    """

    record: np.ndarray
    run: np.ndarray
    track: np.ndarray
    initial_offset: np.ndarray
    current: np.ndarray

    @classmethod
    def build(
        cls,
        record: Sequence[int],
        run: Sequence[int],
        track: Sequence[bool],
        initial_offset: np.ndarray | None = None,
        current: np.ndarray | None = None,
    ) -> Tasks:
        count = len(record)
        return cls(
            record=np.asarray(record, dtype=np.int64),
            run=np.asarray(run, dtype=np.int64),
            track=np.asarray(track, dtype=np.bool_),
            initial_offset=np.zeros((count, S.MOTION_SIZE)) if initial_offset is None else initial_offset,
            current=np.zeros((count, 2)) if current is None else current,
        )


def replay(runs: PackedRuns, records: np.ndarray, tasks: Tasks) -> tuple[np.ndarray, np.ndarray]:
    """Run a batch of replays.

    Args:
        runs: the packed runs.
        records: parameter records (``ShipModel.record`` rows, dtype ``ship.record_dtype()``).
        tasks: what to replay.

    Returns:
        ``(outputs, valid_samples)``: outputs of shape (tasks, longest run, OUTPUT_SIZE) with columns north,
        east, heading, rate of turn, speed (samples beyond a task's run are zero), and per task how many of its
        samples lie inside the model's validity (all of them unless the replay diverged).
    """
    count = len(tasks.record)
    outputs = np.zeros((count, runs.longest, OUTPUT_SIZE))
    valid_samples = np.zeros(count, dtype=np.int64)
    initial = runs.initial_states[tasks.run]
    initial[:, : S.MOTION_SIZE] += tasks.initial_offset
    _replay(
        records,
        (tasks.record, tasks.run, tasks.track, initial, tasks.current),
        (
            runs.offsets,
            runs.time,
            runs.rudder,
            runs.conditions,
            runs.heading,
            runs.rate_of_turn,
            runs.measured_speed_loss,
        ),
        np.zeros(draws.row_size(records)),
        outputs,
        valid_samples,
    )
    return outputs, valid_samples


@dataclass(frozen=True)
class Simulated:
    """One run replayed: the free simulation and the track with the measured heading (and speed, where measured).

    ``speed`` is the free replay's speed through the water, m/s, ``track_speed`` the track replay's (the
    measured one where the log has a speed channel). ``valid_samples`` counts the samples before either
    replay left the model's validity (all of them if neither did); from there on its outputs hold the last
    valid state.
    """

    time: np.ndarray
    heading: np.ndarray
    rate_of_turn: np.ndarray
    north: np.ndarray
    east: np.ndarray
    speed: np.ndarray
    track_north: np.ndarray
    track_east: np.ndarray
    track_speed: np.ndarray
    valid_samples: int

    @property
    def valid(self) -> bool:
        """Whether both replays stayed inside the model's validity."""
        return self.valid_samples == len(self.time)

    @property
    def diverged_at(self) -> float:
        """The time of the first sample outside the model's validity, s; NaN if the replays stayed inside."""
        return math.nan if self.valid else float(self.time[self.valid_samples])


def free_and_track_tasks(count: int, record: int = 0, current: tuple[float, float] = (0.0, 0.0)) -> Tasks:
    """Every run replayed freely (tasks 0..count-1), then along its measured heading (count..2 count-1)."""
    return Tasks.build(
        record=[record] * 2 * count,
        run=list(range(count)) * 2,
        track=[False] * count + [True] * count,
        current=np.tile(current, (2 * count, 1)),
    )


def unpack(logs: Sequence[Log], outputs: np.ndarray, valid_samples: np.ndarray) -> list[Simulated]:
    """The replays of :func:`free_and_track_tasks`, one :class:`Simulated` per run."""
    count = len(logs)
    results = []
    for i, log in enumerate(logs):
        free, track = outputs[i, : log.samples], outputs[count + i, : log.samples]
        results.append(
            Simulated(
                time=log.time,
                heading=free[:, HEADING],
                rate_of_turn=free[:, RATE],
                north=free[:, NORTH],
                east=free[:, EAST],
                speed=free[:, SPEED],
                track_north=track[:, NORTH],
                track_east=track[:, EAST],
                track_speed=track[:, SPEED],
                valid_samples=int(min(valid_samples[i], valid_samples[count + i])),
            )
        )
    return results


def simulate(setup: ReplayModel, logs: Sequence[Log], window: float | None = None) -> list[Simulated]:
    """Replay each log with one model from its measured initial state: free and track replays."""
    runs = pack_runs(logs, setup.model, window)
    outputs, valid_samples = replay(runs, setup.model.record, free_and_track_tasks(len(logs), current=setup.current))
    return unpack(logs, outputs, valid_samples)
