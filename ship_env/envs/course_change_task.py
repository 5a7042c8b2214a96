"""The course-change task, shared by ``CourseChangeEnv`` (one ship) and ``CourseChangeVectorEnv`` (N).

What a course change is lives here once:

- :class:`CourseChangeTask` holds the task's options (ship, disturbances, course changes, rudder
  limit, step, reward weights, sensor noise), builds the ship model and draws an episode's
  :class:`Scenario` from a random generator;
- :class:`CourseChangeBatch` sails N ships in one :class:`~ship_env.model.Simulator` and, in one
  compiled call (:func:`update_ship` per ship), computes what the bridge measures, the
  observations, the rewards and the running metrics (:mod:`ship_env.envs.metrics`).

The single environment is a batch of one, the vector environment a batch of N, so both give the
same numbers for the same seeds. Angles are radians, clockwise from north; a positive rudder and a
positive course change are to starboard.

The sensors (thesis 5.3, 5.4, Fig. 5.1): a compass and a rate gyro that see the high-frequency wave
yaw (Fig. 2.13) plus white noise, the rudder angle indicator, a log measuring the speed through
the water, and position fixes. Their noise comes from the ship's counter-based random stream
(:mod:`ship_env.model.noise`) in a domain of its own, so a seed repeats it exactly.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from gymnasium import spaces
from numba import prange

from ship_env.envs.metrics import METRICS_DTYPE, start_metrics, update_metrics
from ship_env.model import Conditions, ShipModel, Simulator, load_ship
from ship_env.model import state as S
from ship_env.model.kernel import kernel, parallel_kernel
from ship_env.model.noise import MEASUREMENT_DOMAIN, standard_normal

#: Disturbance levels; ``"random"`` draws one of them per episode.
DISTURBANCES = ("calm", "wind_current", "wind_current_waves")
RANDOM_DISTURBANCE = "random"
#: The level reported for an episode whose conditions were given in ``reset(options=...)``.
CUSTOM_DISTURBANCE = "custom"

#: The course changes of the thesis's simulator experiment (6.4.3, Table 6.1.a), deg.
THESIS_COURSE_CHANGES_DEG = (15.0, 30.0, 45.0, 75.0, 105.0)

#: Effects added to the preset's defaults when the disturbance level can have waves.
WAVE_EFFECTS = ("wave_filter", "wave_spectrum")
#: Waves come from within this angle of the wind's direction (assumed: a wind sea).
WAVE_SPREAD = math.radians(30.0)

#: Uniform numbers drawn per scenario: level, magnitude, sign, initial heading, seven for the weather.
_SCENARIO_DRAWS = 11

#: Keys ``reset(options=...)`` accepts.
RESET_OPTIONS = frozenset({"disturbance", "course_change_deg", "initial_heading_deg", "conditions"})

# Observation layout (float32, normalised; see CourseChangeEnv's docstring).
OBS_HEADING_ERROR = 0  # wrap(new heading - compass heading) / pi
OBS_RATE_OF_TURN = 1  # gyro rate / (K* U0 / L * delta_max)
OBS_RUDDER = 2  # actual rudder / delta_max
OBS_SPEED = 3  # log speed / U0
OBS_TURN_DIRECTION = 4  # +1 change ordered to starboard, -1 to port
OBSERVATION_SIZE = 5
#: Bounds of the rate and speed observations (clipped there): well beyond what the rudder can give.
RATE_BOUND = 4.0
SPEED_BOUND = 2.0
OBSERVATION_LOW = np.array([-1.0, -RATE_BOUND, -1.0, 0.0, -1.0], dtype=np.float32)
OBSERVATION_HIGH = np.array([1.0, RATE_BOUND, 1.0, SPEED_BOUND, 1.0], dtype=np.float32)

# Measurement layout: what the bridge's instruments read.
MEASUREMENT_NAMES = ("heading", "rate_of_turn", "rudder", "speed", "north", "east")
MEASURED_HEADING = 0  # rad in [0, 2 pi), compass: psi + HF wave heading + noise
MEASURED_RATE_OF_TURN = 1  # rad/s, rate gyro: r + HF wave rate + noise
MEASURED_RUDDER = 2  # rad, rudder angle indicator (exact)
MEASURED_SPEED = 3  # m/s, log: speed through the water + noise
MEASURED_NORTH = 4  # m, position fix + noise
MEASURED_EAST = 5  # m, position fix + noise
MEASUREMENT_SIZE = 6

#: Standard deviations of the sensors' white noise at ``sensor_noise_scale = 1``. Assumed values
#: typical of modern sensors; the thesis's position-filter test used fixes of 50 m every 2 s,
#: "more than ... G.P.S." (6.3.3).
SENSOR_NOISE = {
    "heading": math.radians(0.1),  # rad
    "rate_of_turn": math.radians(0.01),  # rad/s
    "speed": 0.05,  # m/s
    "position": 5.0,  # m
}

_NOISE_CHANNELS = np.uint64(5)  # heading, rate of turn, speed, north, east

#: Batches this large update their ships on all cores; smaller ones in one thread, where starting
#: the threads would cost more than it saves.
PARALLEL_SHIPS = 256

#: Per-ship episode data: what the compiled update reads and what it writes.
EPISODE_DTYPE = np.dtype(
    [
        ("new_heading", np.float64),  # rad, unwrapped: initial heading + course change
        ("turn_direction", np.float64),  # +1 starboard, -1 port
        ("wave_yaw", np.float64),  # 1 if the sea shows in the compass and gyro (H_s > 0), else 0
        ("rudder", np.float64),  # rad, the actual rudder at the previous update
        ("restarted", np.bool_),  # a new episode, not yet observed
        ("reward", np.float64),
        ("observation", np.float32, (OBSERVATION_SIZE,)),
        ("measurement", np.float64, (MEASUREMENT_SIZE,)),
    ]
)

#: The task's constants as the compiled update reads them.
TASK_DTYPE = np.dtype(
    [
        ("dt", np.float64),
        ("rudder_limit", np.float64),
        ("steady_rate_per_speed", np.float64),  # K* delta_max / L: steady rate at full rudder per m/s
        ("heading_noise", np.float64),
        ("rate_noise", np.float64),
        ("speed_noise", np.float64),
        ("position_noise", np.float64),
        ("heading_error_weight", np.float64),
        ("rudder_travel_weight", np.float64),
        ("settle_band", np.float64),
    ]
)


@dataclass(frozen=True)
class Scenario:
    """One episode's course change and the sea it is sailed in.

    Attributes:
        disturbance: the level it was drawn at (``"calm"``, ...), or ``"custom"``.
        course_change: the ordered change, rad, positive to starboard.
        initial_heading: the steady course sailed at the start, rad.
        conditions: wind, current, waves and speed for the simulator.
        seed: the simulator's seed for the episode (its gusts, wave yaw, sea and sensor noise).
    """

    disturbance: str
    course_change: float
    initial_heading: float
    conditions: Conditions
    seed: int

    @property
    def new_heading(self) -> float:
        """The ordered new heading, rad, not wrapped."""
        return self.initial_heading + self.course_change


def _check_number(name: str, value: object, minimum: float = -math.inf, maximum: float = math.inf) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise TypeError(f"{name}: expected a number, got {value!r}")
    if not (math.isfinite(value) and minimum <= value <= maximum):
        raise ValueError(f"{name}: expected a finite number in [{minimum}, {maximum}], got {value!r}")
    return float(value)


def _check_range(name: str, value: object, minimum: float = 0.0) -> tuple[float, float]:
    if not isinstance(value, Sequence) or isinstance(value, str) or len(value) != 2:
        raise TypeError(f"{name}: expected (low, high), got {value!r}")
    low = _check_number(f"{name}[0]", value[0], minimum)
    high = _check_number(f"{name}[1]", value[1], low)
    return low, high


def _within(bounds: tuple[float, float], fraction: float) -> float:
    return bounds[0] + (bounds[1] - bounds[0]) * fraction


class CourseChangeTask:
    """The options of the course-change task; the environments' keyword arguments.

    Args:
        ship: a ship preset name (``configs/ships``) or a YAML path.
        ship_parameters: parameter overrides for the preset, ``{"yaw.gain": 1.2}`` (SI units).
        effects: the model's effects; ``None`` takes the preset's defaults, plus the wave effects
            (``wave_filter``, ``wave_spectrum``) when ``disturbance`` can bring waves.
        disturbance: ``"calm"``, ``"wind_current"``, ``"wind_current_waves"`` or ``"random"``
            (one of the three per episode).
        course_changes_deg: the course-change magnitudes drawn from, deg, each in (0, 180].
        rudder_limit_deg: delta_max, the hard-over angle action +-1 orders, deg (it becomes the
            model's rudder limit).
        dt: the control step, s (one simulator step).
        heading_error_weight: reward per step for |heading error| / pi.
        rudder_travel_weight: reward per step for |actual rudder move| / delta_max.
        settle_band_deg: the settling band of the metrics, deg.
        wind_speed_range, current_speed_range: m/s, drawn uniformly.
        wave_height_range, wave_period_range: significant height (m) and peak period (s).
        sensor_noise_scale: multiplies ``SENSOR_NOISE``; 0 gives noise-free instruments.
    """

    def __init__(
        self,
        *,
        ship: str | Path = "container_226m",
        ship_parameters: Mapping[str, float] | None = None,
        effects: Sequence[str] | None = None,
        disturbance: str = "calm",
        course_changes_deg: Sequence[float] = THESIS_COURSE_CHANGES_DEG,
        rudder_limit_deg: float = 20.0,
        dt: float = 1.0,
        heading_error_weight: float = 1.0,
        rudder_travel_weight: float = 0.2,
        settle_band_deg: float = 2.0,
        wind_speed_range: tuple[float, float] = (5.0, 10.0),
        current_speed_range: tuple[float, float] = (0.5, 1.5),
        wave_height_range: tuple[float, float] = (1.0, 4.0),
        wave_period_range: tuple[float, float] = (6.0, 10.0),
        sensor_noise_scale: float = 1.0,
    ) -> None:
        if disturbance not in (*DISTURBANCES, RANDOM_DISTURBANCE):
            raise ValueError(
                f"disturbance: expected one of {', '.join((*DISTURBANCES, RANDOM_DISTURBANCE))}, got {disturbance!r}"
            )
        if isinstance(course_changes_deg, (str, bytes)) or not isinstance(course_changes_deg, Sequence):
            raise TypeError(f"course_changes_deg: expected a list of angles in deg, got {course_changes_deg!r}")
        if not course_changes_deg:
            raise ValueError("course_changes_deg: expected at least one course change")
        self.disturbance = disturbance
        self.course_changes = tuple(
            math.radians(_check_number(f"course_changes_deg[{i}]", value, 1e-6, 180.0))
            for i, value in enumerate(course_changes_deg)
        )
        self.rudder_limit = math.radians(_check_number("rudder_limit_deg", rudder_limit_deg, 1e-3, 90.0))
        self.dt = _check_number("dt", dt, 1e-6)
        self.heading_error_weight = _check_number("heading_error_weight", heading_error_weight, 0.0)
        self.rudder_travel_weight = _check_number("rudder_travel_weight", rudder_travel_weight, 0.0)
        self.settle_band = math.radians(_check_number("settle_band_deg", settle_band_deg, 0.0, 180.0))
        self.wind_speed_range = _check_range("wind_speed_range", wind_speed_range)
        self.current_speed_range = _check_range("current_speed_range", current_speed_range)
        self.wave_height_range = _check_range("wave_height_range", wave_height_range)
        self.wave_period_range = _check_range("wave_period_range", wave_period_range, 1e-3)
        noise_scale = _check_number("sensor_noise_scale", sensor_noise_scale, 0.0)

        preset = load_ship(ship)
        if effects is None:
            waves = WAVE_EFFECTS if disturbance in ("wind_current_waves", RANDOM_DISTURBANCE) else ()
            effects = (*preset.enabled, *waves)
        self.model = ShipModel(preset, effects, {**(ship_parameters or {}), "rudder_limit": self.rudder_limit})

        self.parameters = np.zeros(1, dtype=TASK_DTYPE)
        record = self.parameters[0]
        record["dt"] = self.dt
        record["rudder_limit"] = self.rudder_limit
        record["steady_rate_per_speed"] = self.model.parameter("yaw.gain") * self.rudder_limit / self.model.length
        record["heading_noise"] = noise_scale * SENSOR_NOISE["heading"]
        record["rate_noise"] = noise_scale * SENSOR_NOISE["rate_of_turn"]
        record["speed_noise"] = noise_scale * SENSOR_NOISE["speed"]
        record["position_noise"] = noise_scale * SENSOR_NOISE["position"]
        record["heading_error_weight"] = self.heading_error_weight
        record["rudder_travel_weight"] = self.rudder_travel_weight
        record["settle_band"] = self.settle_band

        self.observation_space = spaces.Box(OBSERVATION_LOW, OBSERVATION_HIGH, dtype=np.float32)
        self.action_space = spaces.Box(-1.0, 1.0, shape=(1,), dtype=np.float32)

    # -- scenarios -------------------------------------------------------------------------------
    def draw_scenario(self, rng: np.random.Generator, options: Mapping[str, Any] | None = None) -> Scenario:
        """Draw an episode from ``rng``; ``options`` may pin any part of it (``RESET_OPTIONS``).

        Every draw takes the same numbers from ``rng`` whatever the level or options, so one seed
        gives one sequence of episodes. Distributions: level uniform over ``DISTURBANCES`` (if
        ``"random"``); magnitude uniform over the course changes, sign +-1 with equal chance;
        initial heading uniform in [0, 360) deg; wind speed and current speed uniform in their
        ranges, wind from and current towards uniform directions; waves of uniform H_s and T_p
        from the wind's direction +-30 deg.
        """
        draws = rng.random(_SCENARIO_DRAWS).tolist()
        seed = int(rng.integers(2**31))
        options = dict(options or {})
        unknown = sorted(set(options) - RESET_OPTIONS)
        if unknown:
            raise ValueError(f"options: unknown keys {unknown}; known: {', '.join(sorted(RESET_OPTIONS))}")

        disturbance = options.get("disturbance", self.disturbance)
        if disturbance == RANDOM_DISTURBANCE:
            disturbance = DISTURBANCES[int(draws[0] * len(DISTURBANCES))]
        elif disturbance not in DISTURBANCES:
            raise ValueError(f"options['disturbance']: expected one of {', '.join(DISTURBANCES)}, got {disturbance!r}")

        if "course_change_deg" in options:
            degrees = _check_number("options['course_change_deg']", options["course_change_deg"], -180.0, 180.0)
            change = math.radians(degrees)
            if change == 0.0:
                raise ValueError("options['course_change_deg']: expected a non-zero course change")
        else:
            magnitude = self.course_changes[int(draws[1] * len(self.course_changes))]
            change = magnitude if draws[2] < 0.5 else -magnitude

        if "initial_heading_deg" in options:
            heading = math.radians(_check_number("options['initial_heading_deg']", options["initial_heading_deg"]))
        else:
            heading = 2.0 * math.pi * draws[3]

        if "conditions" in options:
            conditions = options["conditions"]
            if not isinstance(conditions, Conditions):
                raise TypeError(f"options['conditions']: expected a Conditions, got {conditions!r}")
            if conditions.service_speed is not None and conditions.service_speed <= 0.0:
                raise ValueError(
                    f"options['conditions'].service_speed: must be positive, got {conditions.service_speed!r}"
                )
            disturbance = CUSTOM_DISTURBANCE
        else:
            conditions = self._conditions(disturbance, draws[4:])
        return Scenario(disturbance, change, heading, conditions, seed)

    def _conditions(self, disturbance: str, draws: list[float]) -> Conditions:
        if disturbance == "calm":
            return Conditions()
        wind_direction = 2.0 * math.pi * draws[1]
        weather = {
            "wind_speed": _within(self.wind_speed_range, draws[0]),
            "wind_direction": wind_direction,
            "current_speed": _within(self.current_speed_range, draws[2]),
            "current_direction": 2.0 * math.pi * draws[3],
        }
        if disturbance == "wind_current_waves":
            weather["wave_height"] = _within(self.wave_height_range, draws[4])
            weather["wave_period"] = _within(self.wave_period_range, draws[5])
            weather["wave_direction"] = (wind_direction + WAVE_SPREAD * (2.0 * draws[6] - 1.0)) % (2.0 * math.pi)
        return Conditions(**weather)

    # -- actions ---------------------------------------------------------------------------------
    @staticmethod
    def action_array(action: object, shape: tuple[int, ...]) -> np.ndarray:
        """The action as a float64 array of ``shape``; raise ``ValueError`` if it is not that or not finite."""
        try:
            array = np.asarray(action, dtype=np.float64)
        except (TypeError, ValueError):
            raise ValueError(f"action: expected an array of shape {shape} in [-1, 1], got {action!r}") from None
        if array.shape != shape:
            raise ValueError(f"action: expected shape {shape}, got {action!r} of shape {array.shape}")
        if not np.isfinite(array).all():
            index = tuple(int(i) for i in np.argwhere(~np.isfinite(array))[0])
            raise ValueError(f"action{list(index)}: must be finite, got {float(array[index])} in action {action!r}")
        return array


@kernel
def _wrap(angle):
    """An angle wrapped to [-pi, pi)."""
    return (angle + math.pi) % (2.0 * math.pi) - math.pi


@kernel
def _sensor_noise(key, step, channel, deviation):
    """White sensor noise of one channel at one step, from the ship's random stream."""
    if deviation == 0.0:
        return 0.0
    counter = MEASUREMENT_DOMAIN + np.uint64(step) * _NOISE_CHANNELS + np.uint64(channel)
    return deviation * standard_normal(key, counter)


@kernel
def update_ship(i, restarted_only, states, conditions, noise_keys, step_index, episodes, metrics, task):
    """Measure, observe and reward ship ``i`` after a step (or after a restart, reward 0).

    Reads the simulator's arrays (``states``, ``conditions``, ``noise_keys``, ``step_index``),
    writes ``episodes[i]`` and ``metrics[i]``. Reward:
    -(w_e |wrap(psi_new - psi)| / pi + w_d |delta - delta_prev| / delta_max) on the true heading psi
    and the actual rudder delta; the observation comes from the measurements. With
    ``restarted_only`` a ship that was not restarted is left as it is.
    """
    episode = episodes[i]
    if restarted_only and not episode["restarted"]:
        return
    p = task[0]
    state = states[i]
    heading_error = episode["new_heading"] - state[S.HEADING]
    rudder = state[S.RUDDER]
    if episode["restarted"]:
        start_metrics(metrics[i], heading_error, p["settle_band"])
        episode["reward"] = 0.0
        episode["restarted"] = False
    else:
        rudder_move = abs(rudder - episode["rudder"])
        episode["reward"] = -(
            p["heading_error_weight"] * abs(_wrap(heading_error)) / math.pi
            + p["rudder_travel_weight"] * rudder_move / p["rudder_limit"]
        )
        update_metrics(
            metrics[i], state[S.TIME], heading_error, episode["turn_direction"], rudder_move, p["dt"], p["settle_band"]
        )
    episode["rudder"] = rudder

    key = noise_keys[i]
    step = step_index[i]
    service_speed = conditions[i, S.SERVICE_SPEED]
    wave_yaw = episode["wave_yaw"]
    heading = state[S.HEADING] + wave_yaw * state[S.WAVE_HEADING] + _sensor_noise(key, step, 0, p["heading_noise"])
    rate = state[S.RATE_OF_TURN] + wave_yaw * state[S.WAVE_RATE] + _sensor_noise(key, step, 1, p["rate_noise"])
    speed = service_speed * (1.0 - state[S.SPEED_LOSS]) + _sensor_noise(key, step, 2, p["speed_noise"])
    measured = episode["measurement"]
    measured[MEASURED_HEADING] = heading % (2.0 * math.pi)
    measured[MEASURED_RATE_OF_TURN] = rate
    measured[MEASURED_RUDDER] = rudder
    measured[MEASURED_SPEED] = speed
    measured[MEASURED_NORTH] = state[S.NORTH] + _sensor_noise(key, step, 3, p["position_noise"])
    measured[MEASURED_EAST] = state[S.EAST] + _sensor_noise(key, step, 4, p["position_noise"])

    observation = episode["observation"]
    observation[OBS_HEADING_ERROR] = _wrap(episode["new_heading"] - heading) / math.pi
    steady_rate = p["steady_rate_per_speed"] * service_speed
    observation[OBS_RATE_OF_TURN] = min(max(rate / steady_rate, -RATE_BOUND), RATE_BOUND)
    observation[OBS_RUDDER] = rudder / p["rudder_limit"]
    observation[OBS_SPEED] = min(max(speed / service_speed, 0.0), SPEED_BOUND)
    observation[OBS_TURN_DIRECTION] = episode["turn_direction"]


@kernel
def update_ships(restarted_only, states, conditions, noise_keys, step_index, episodes, metrics, task):
    """``update_ship`` for every ship of a batch."""
    for i in range(states.shape[0]):
        update_ship(i, restarted_only, states, conditions, noise_keys, step_index, episodes, metrics, task)


@parallel_kernel
def update_ships_parallel(restarted_only, states, conditions, noise_keys, step_index, episodes, metrics, task):
    """``update_ship`` for every ship of a batch, on all cores."""
    for i in prange(states.shape[0]):
        update_ship(i, restarted_only, states, conditions, noise_keys, step_index, episodes, metrics, task)


def _pick(array: np.ndarray, index: Any) -> Any:
    """``array[index]``: a scalar as it is, an array as a copy."""
    value = array[index]
    return value.copy() if isinstance(value, np.ndarray) else value


class CourseChangeBatch:
    """N ships sailing course changes: the simulator plus every ship's episode, in arrays.

    After ``restart`` or a simulator step, ``update`` fills each ship's ``episodes`` record
    (``observation`` float32 (5,), ``measurement`` (6,), ``reward``) and its running ``metrics``.
    """

    def __init__(self, task: CourseChangeTask, num_ships: int) -> None:
        self.task = task
        self.simulator = Simulator(task.model, num_ships=num_ships, dt=task.dt)
        self.num_ships = self.simulator.num_ships
        self.scenarios: list[Scenario | None] = [None] * self.num_ships
        self.episodes = np.zeros(self.num_ships, dtype=EPISODE_DTYPE)
        self.metrics = np.zeros(self.num_ships, dtype=METRICS_DTYPE)

    def restart(self, ships: np.ndarray, scenarios: Sequence[Scenario]) -> None:
        """Start new episodes for ``ships`` (sorted indices), one scenario each; the others sail on."""
        seeds = [scenario.seed for scenario in scenarios]
        conditions = [scenario.conditions for scenario in scenarios]
        headings = [scenario.initial_heading for scenario in scenarios]
        self.simulator.reset(seed=seeds, conditions=conditions, heading=np.asarray(headings), ships=ships)
        for ship, scenario in zip(ships, scenarios):
            episode = self.episodes[ship]
            episode["new_heading"] = scenario.new_heading
            episode["turn_direction"] = math.copysign(1.0, scenario.course_change)
            episode["wave_yaw"] = 1.0 if scenario.conditions.wave_height > 0.0 else 0.0
            episode["restarted"] = True
            self.scenarios[ship] = scenario

    def update(self, restarted_only: bool = False) -> None:
        """Measure, observe and reward every ship, or only the restarted ones (one compiled call)."""
        simulator = self.simulator
        update = update_ships_parallel if self.num_ships >= PARALLEL_SHIPS else update_ships
        update(
            restarted_only,
            simulator.state,
            simulator.conditions,
            simulator.noise_keys,
            simulator.step_index,
            self.episodes,
            self.metrics,
            self.task.parameters,
        )

    @property
    def observations(self) -> np.ndarray:
        """(N, 5) float32, a copy."""
        return self.episodes["observation"].copy()

    @property
    def rewards(self) -> np.ndarray:
        """(N,), a copy."""
        return self.episodes["reward"].copy()

    def info(self, ships: int | slice) -> dict[str, Any]:
        """The step's information for one ship (an index: scalars) or all (``slice(None)``: arrays).

        ``measurement``: the bridge's instruments (``MEASUREMENT_NAMES``: compass heading in
        [0, 2 pi) rad, rate gyro rad/s, rudder angle rad, log speed m/s, position fix north and
        east m); ``state``: the ship's true state (layout ``ship_env.model.state``);
        ``new_heading``: the ordered heading, rad, unwrapped; ``metrics``: the episode's metrics
        so far (final at its last step; :mod:`ship_env.envs.metrics`). Arrays are copies.
        """
        measurements = self.episodes["measurement"]
        return {
            "measurement": {name: _pick(measurements, (ships, k)) for k, name in enumerate(MEASUREMENT_NAMES)},
            "state": _pick(self.simulator.state, ships),
            "new_heading": _pick(self.episodes["new_heading"], ships),
            "metrics": {name: _pick(self.metrics[name], ships) for name in METRICS_DTYPE.names},
        }
