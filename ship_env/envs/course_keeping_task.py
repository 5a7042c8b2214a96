"""The course-keeping task, shared by ``CourseKeepingEnv`` (one ship) and ``CourseKeepingVectorEnv`` (N).

- :class:`CourseKeepingTask` holds the task's options (disturbances, the criterion's rudder
  weight, plus the ship, rudder, step, instruments and action of
  :class:`~ship_env.envs.task.ShipTask`) and draws an episode's :class:`CourseKeepingScenario`;
- :class:`CourseKeepingBatch` sails N ships in one simulator and, in one compiled call
  (:func:`update_ship` per ship), measures, observes, rewards and keeps the criterion
  J = mean(e^2) + lambda mean(delta^2) (:mod:`ship_env.envs.metrics`).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
from numba import prange

from ship_env.envs.batch import ShipBatch
from ship_env.envs.checks import check_choice, check_number
from ship_env.envs.metrics import (
    COURSE_KEEPING_METRICS_DTYPE,
    RUDDER_WEIGHT,
    start_course_keeping_metrics,
    update_course_keeping_metrics,
)
from ship_env.envs.sensors import (
    MEASURED_HEADING,
    RATE_BOUND,
    SPEED_BOUND,
    measure,
    observe_motion,
    wrap,
)
from ship_env.envs.task import ShipTask
from ship_env.envs.variation import ShipFactors
from ship_env.envs.weather import (
    CUSTOM_DISTURBANCE,
    DISTURBANCES,
    RANDOM_DISTURBANCE,
    WAVE_EFFECTS,
    WEATHER_DRAWS,
    WeatherRanges,
    check_conditions,
    has_waves,
)
from ship_env.model import Conditions
from ship_env.model import state as S
from ship_env.model.integrators import borrowed
from ship_env.model.kernel import kernel, parallel_kernel

#: Uniform numbers drawn per scenario: level, course, then the weather's.
_SCENARIO_DRAWS = 2 + WEATHER_DRAWS

#: Keys ``reset(options=...)`` accepts.
RESET_OPTIONS = frozenset({"disturbance", "course_deg", "conditions"})

# Observation layout (float32, normalised; see CourseKeepingEnv's docstring).
OBS_HEADING_ERROR = 0  # wrap(course - compass heading) / HEADING_SCALE
OBS_RATE_OF_TURN = 1  # gyro rate / (K* U0 / L * delta_max)
OBS_RUDDER = 2  # actual rudder / delta_max
OBS_SPEED = 3  # log speed / U0
OBSERVATION_SIZE = 4
#: The heading error's unit in the observation: course keeping errors are a few degrees.
HEADING_SCALE = math.radians(10.0)
HEADING_BOUND = math.pi / HEADING_SCALE  # 18: the whole circle
OBSERVATION_LOW = np.array([-HEADING_BOUND, -RATE_BOUND, -1.0, 0.0], dtype=np.float32)
OBSERVATION_HIGH = np.array([HEADING_BOUND, RATE_BOUND, 1.0, SPEED_BOUND], dtype=np.float32)

#: Per-ship episode data besides the common record: the ordered course, rad.
TASK_FIELDS = (("course", np.float64),)

#: The task's constants as the compiled update reads them.
TASK_DTYPE = np.dtype(
    [
        ("rudder_limit", np.float64),
        ("full_rudder_rate_per_speed", np.float64),
        ("rudder_weight", np.float64),  # lambda
    ]
)


@dataclass(frozen=True)
class CourseKeepingScenario:
    """One episode's course and the sea it is held in.

    Attributes:
        disturbance: the level it was drawn at (``"calm"``, ...), or ``"custom"``.
        course: the ordered course, rad; the ship starts on it.
        conditions: wind, current, waves and speed for the simulator.
        seed: the simulator's seed for the episode (its gusts, wave yaw, sea and sensor noise).
        ship: the ship's K*, tau*, speed and weather factors when ``ship_variation`` drew them
            (:class:`~ship_env.envs.variation.ShipFactors`), else ``None`` (the preset's ship).
    """

    disturbance: str
    course: float
    conditions: Conditions
    seed: int
    ship: ShipFactors | None = None

    @property
    def initial_heading(self) -> float:
        """The heading the ship starts on: the course, rad."""
        return self.course


class CourseKeepingTask(ShipTask):
    """The options of the course-keeping task; the environments' keyword arguments.

    Args:
        disturbance: ``"wind_current_waves"`` (default), ``"wind_current"``, ``"calm"`` or
            ``"random"`` (one of the three per episode).
        rudder_limit_deg: delta_max, deg (default 10).
        rudder_weight: lambda of J = mean(e^2) + lambda mean(delta^2) (default 0.1).
        wind_speed_range, current_speed_range: m/s, drawn uniformly.
        wave_height_range, wave_period_range: significant height (m) and peak period (s).
        **ship_options: the keywords every task shares (:class:`~ship_env.envs.task.ShipTask`):
            ``ship``, ``ship_parameters``, ``effects`` (``None``: the preset's defaults, plus
            ``wave_filter`` and ``wave_spectrum`` when ``disturbance`` can bring waves), ``dt``,
            ``sensor_noise_scale``, ``fix_interval``, ``action_type``, ``rudder_levels``.
    """

    history_observations = (OBS_HEADING_ERROR, OBS_RATE_OF_TURN, OBS_RUDDER)

    def __init__(
        self,
        *,
        disturbance: str = "wind_current_waves",
        rudder_limit_deg: float = 10.0,
        rudder_weight: float = RUDDER_WEIGHT,
        wind_speed_range: tuple[float, float] = (5.0, 10.0),
        current_speed_range: tuple[float, float] = (0.5, 1.5),
        wave_height_range: tuple[float, float] = (1.0, 4.0),
        wave_period_range: tuple[float, float] = (6.0, 10.0),
        **ship_options: Any,
    ) -> None:
        self.disturbance = check_choice("disturbance", disturbance, (*DISTURBANCES, RANDOM_DISTURBANCE))
        self.rudder_weight = check_number("rudder_weight", rudder_weight, 0.0)
        self.weather = WeatherRanges(wind_speed_range, current_speed_range, wave_height_range, wave_period_range)
        waves = WAVE_EFFECTS if has_waves(disturbance) else ()
        super().__init__(rudder_limit_deg=rudder_limit_deg, extra_effects=waves, **ship_options)

        self.parameters = np.zeros(1, dtype=TASK_DTYPE)
        record = self.parameters[0]
        record["rudder_limit"] = self.rudder_limit
        record["full_rudder_rate_per_speed"] = self.full_rudder_rate_per_speed
        record["rudder_weight"] = self.rudder_weight
        #: What the compiled update reads besides the simulator's and the batch's arrays.
        self.kernel_arguments = (self.parameters, self.sensors)
        self.observation_space = self.observation_box(OBSERVATION_LOW, OBSERVATION_HIGH)

    def draw_task_scenario(
        self, rng: np.random.Generator, options: Mapping[str, Any] | None = None
    ) -> CourseKeepingScenario:
        """Draw an episode from ``rng``; ``options`` may pin any part of it (``RESET_OPTIONS``).

        Level uniform over ``DISTURBANCES`` (if ``"random"``), course uniform in [0, 360) deg, the
        weather as :meth:`~ship_env.envs.weather.WeatherRanges.conditions` draws it. Every draw
        takes the same numbers from ``rng``, so one seed gives one sequence of episodes.
        """
        draws = rng.random(_SCENARIO_DRAWS).tolist()
        seed = int(rng.integers(2**31))
        options = self.check_options(options, RESET_OPTIONS)
        disturbance = options.get("disturbance", self.disturbance)
        if disturbance == RANDOM_DISTURBANCE:
            disturbance = DISTURBANCES[int(draws[0] * len(DISTURBANCES))]
        else:
            check_choice("options['disturbance']", disturbance, DISTURBANCES)
        if "course_deg" in options:
            course = math.radians(check_number("options['course_deg']", options["course_deg"]))
        else:
            course = 2.0 * math.pi * draws[1]
        if "conditions" in options:
            conditions = check_conditions("options['conditions']", options["conditions"])
            disturbance = CUSTOM_DISTURBANCE
        else:
            conditions = self.weather.conditions(disturbance, draws[2:])
        return CourseKeepingScenario(disturbance, course, conditions, seed)


@kernel
def update_ship(i, restarted_only, states, conditions, noise_keys, step_index, episodes, metrics, task, sensors):
    """Measure, observe and reward ship ``i`` after a step (or after a restart, reward 0).

    Reward: -((e / delta_max)^2 + lambda (delta / delta_max)^2) with e = wrap(course - psi) the
    true heading error and delta the actual rudder, so the mean reward is -J / delta_max^2.
    The observation comes from the measurements (the compass with the waves' yaw).
    """
    episode = episodes[i]
    restarted = episode["restarted"]
    if restarted_only and not restarted:
        return
    p = task[0]
    state = states[i]
    heading_error = wrap(episode["course"] - state[S.HEADING])
    rudder = state[S.RUDDER]
    if restarted:
        start_course_keeping_metrics(metrics[i])
        episode["reward"] = 0.0
        episode["restarted"] = False
    else:
        relative_error = heading_error / p["rudder_limit"]
        relative_rudder = rudder / p["rudder_limit"]
        episode["reward"] = -(relative_error * relative_error + p["rudder_weight"] * relative_rudder * relative_rudder)
        update_course_keeping_metrics(
            metrics[i], heading_error, rudder, abs(rudder - episode["rudder"]), p["rudder_weight"]
        )
    episode["rudder"] = rudder

    service_speed = conditions[i, S.SERVICE_SPEED]
    measured = episode["measurement"]
    measure(state, service_speed, episode["wave_yaw"], noise_keys[i], step_index[i], sensors, restarted, measured)

    observation = episode["observation"]
    observation[OBS_HEADING_ERROR] = wrap(episode["course"] - measured[MEASURED_HEADING]) / HEADING_SCALE
    observe_motion(
        observation,
        OBS_RATE_OF_TURN,
        measured,
        rudder,
        service_speed,
        p["full_rudder_rate_per_speed"],
        p["rudder_limit"],
    )


@kernel
def update_ships(restarted_only, *arrays):
    """``update_ship`` for every ship of a batch (``arrays``: those of ``update_ship``, borrowed)."""
    arrays = borrowed(arrays)
    for i in range(arrays[0].shape[0]):
        update_ship(i, restarted_only, *arrays)


@parallel_kernel
def update_ships_parallel(restarted_only, *arrays):
    """``update_ships`` on all cores."""
    arrays = borrowed(arrays)
    for i in prange(arrays[0].shape[0]):
        update_ship(i, restarted_only, *arrays)


class CourseKeepingBatch(ShipBatch):
    """N ships keeping their courses (:class:`~ship_env.envs.batch.ShipBatch`).

    Each ship's ``episodes`` record holds ``observation`` float32 (4,), ``measurement``,
    ``reward`` and the ordered ``course``; ``metrics`` the running criterion.
    """

    metrics_dtype = COURSE_KEEPING_METRICS_DTYPE
    update_serial = staticmethod(update_ships)
    update_parallel = staticmethod(update_ships_parallel)

    def __init__(self, task: CourseKeepingTask, num_ships: int) -> None:
        super().__init__(task, num_ships, TASK_FIELDS)

    def start_episode(self, episode: np.void, scenario: CourseKeepingScenario) -> None:
        episode["course"] = scenario.course

    def task_info(self, episodes: np.ndarray, ships: int | slice) -> dict[str, Any]:
        """``course``: the ordered course, rad."""
        return {"course": episodes["course"][ships]}
