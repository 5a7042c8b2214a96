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

from ship_env.envs.batch import ShipBatch, define_update_loops, measure_and_observe
from ship_env.envs.checks import check_number
from ship_env.envs.metrics import (
    COURSE_KEEPING_METRICS_DTYPE,
    RUDDER_WEIGHT,
    start_course_keeping_metrics,
    update_course_keeping_metrics,
)
from ship_env.envs.sensors import MEASURED_HEADING, RATE_BOUND, SPEED_BOUND, wrap
from ship_env.envs.task import TaskScenario
from ship_env.envs.weather import WEATHER_DRAWS, WeatherTask
from ship_env.model import state as S
from ship_env.model.kernel import kernel

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


@dataclass(frozen=True)
class CourseKeepingScenario(TaskScenario):
    """One episode's course and the sea it is held in.

    Attributes (besides :class:`~ship_env.envs.task.TaskScenario`'s):
        course: the ordered course, rad; the ship starts on it.
    """

    course: float

    @property
    def initial_heading(self) -> float:
        """The heading the ship starts on: the course, rad."""
        return self.course


class CourseKeepingTask(WeatherTask):
    """The options of the course-keeping task; the environments' keyword arguments.

    Args:
        disturbance: ``"wind_current_waves"`` (default), ``"wind_current"``, ``"calm"`` or
            ``"random"`` (one of the three per episode).
        rudder_limit_deg: delta_max, deg (default 10).
        rudder_weight: lambda of J = mean(e^2) + lambda mean(delta^2) (default 0.1).
        **options: the weather's ranges (:class:`~ship_env.envs.weather.WeatherTask`:
            ``wind_speed_range``, ``current_speed_range``, ``wave_height_range``,
            ``wave_period_range``) and the keywords every task shares
            (:class:`~ship_env.envs.task.ShipTask`).
    """

    history_observations = (OBS_HEADING_ERROR, OBS_RATE_OF_TURN, OBS_RUDDER)

    def __init__(
        self,
        *,
        disturbance: str = "wind_current_waves",
        rudder_limit_deg: float = 10.0,
        rudder_weight: float = RUDDER_WEIGHT,
        **options: Any,
    ) -> None:
        self.rudder_weight = check_number("rudder_weight", rudder_weight, 0.0)
        super().__init__(disturbance=disturbance, rudder_limit_deg=rudder_limit_deg, **options)
        #: The task's constants as the compiled update reads them (lambda).
        self.parameters = self.parameter_record(rudder_weight=self.rudder_weight)
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
        disturbance, conditions = self.draw_weather(draws[0], draws[2:], options)
        if "course_deg" in options:
            course = math.radians(check_number("options['course_deg']", options["course_deg"]))
        else:
            course = 2.0 * math.pi * draws[1]
        return CourseKeepingScenario(disturbance, conditions, seed, course)


@kernel
def update_ship(i, states, conditions, noise_keys, step_index, episodes, metrics, task, sensors):
    """Measure, observe and reward ship ``i`` after a step (or after a restart, reward 0).

    Reward: -((e / delta_max)^2 + lambda (delta / delta_max)^2) with e = wrap(course - psi) the
    true heading error and delta the actual rudder, so the mean reward is -J / delta_max^2.
    The observation comes from the measurements (the compass with the waves' yaw).
    """
    episode = episodes[i]
    restarted = episode["restarted"]
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

    measure_and_observe(i, state, conditions, noise_keys, step_index, episode, sensors, restarted, OBS_RATE_OF_TURN, p)
    episode["observation"][OBS_HEADING_ERROR] = (
        wrap(episode["course"] - episode["measurement"][MEASURED_HEADING]) / HEADING_SCALE
    )


update_ships, update_ships_parallel, sail_ship = define_update_loops(globals())


class CourseKeepingBatch(ShipBatch):
    """N ships keeping their courses (:class:`~ship_env.envs.batch.ShipBatch`).

    Each ship's ``episodes`` record holds ``observation`` float32 (4,), ``measurement``,
    ``reward`` and the ordered ``course``; ``metrics`` the running criterion.
    """

    task_fields = TASK_FIELDS
    #: ``course``: the ordered course, rad.
    task_info_keys = ("course",)
    metrics_dtype = COURSE_KEEPING_METRICS_DTYPE
    update_serial = staticmethod(update_ships)
    update_parallel = staticmethod(update_ships_parallel)
    sail_one = staticmethod(sail_ship)

    def start_episode(self, episode: np.void, scenario: CourseKeepingScenario) -> None:
        episode["course"] = scenario.course
