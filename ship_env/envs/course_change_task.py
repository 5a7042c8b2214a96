"""The course-change task, shared by ``CourseChangeEnv`` (one ship) and ``CourseChangeVectorEnv`` (N).

What a course change is lives here once:

- :class:`CourseChangeTask` holds the task's options (disturbances, course changes, reward
  weights, plus the ship, rudder, step, instruments and action of :class:`~ship_env.envs.task.ShipTask`)
  and draws an episode's :class:`Scenario` from a random generator;
- :class:`CourseChangeBatch` sails N ships in one :class:`~ship_env.model.Simulator` and, in one
  compiled call (:func:`update_ship` per ship), computes what the bridge measures
  (:mod:`ship_env.envs.sensors`), the observations, the rewards and the running metrics
  (:mod:`ship_env.envs.metrics`).

The single environment is a batch of one, the vector environment a batch of N, so both give the
same numbers for the same seeds. Angles are radians, clockwise from north; a positive rudder and a
positive course change are to starboard.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ship_env.envs.batch import ShipBatch, define_update_loops, measure_and_observe
from ship_env.envs.checks import check_choice, check_number
from ship_env.envs.metrics import METRICS_DTYPE, start_metrics, update_metrics
from ship_env.envs.sensors import MEASURED_HEADING, RATE_BOUND, SPEED_BOUND, wrap
from ship_env.envs.task import TaskScenario
from ship_env.envs.tracks import THESIS_COURSE_CHANGES_DEG
from ship_env.envs.weather import CUSTOM_DISTURBANCE, DISTURBANCES, WEATHER_DRAWS, WeatherTask
from ship_env.model import state as S
from ship_env.model.kernel import kernel

#: Uniform numbers drawn per scenario: level, magnitude, sign, initial heading, then the weather's.
_SCENARIO_DRAWS = 4 + WEATHER_DRAWS

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
OBSERVATION_LOW = np.array([-1.0, -RATE_BOUND, -1.0, 0.0, -1.0], dtype=np.float32)
OBSERVATION_HIGH = np.array([1.0, RATE_BOUND, 1.0, SPEED_BOUND, 1.0], dtype=np.float32)

#: The levels ``rudder_travel_weight`` may weigh apart: those drawn, and ``"custom"`` (conditions given at reset).
WEIGHTED_LEVELS = (*DISTURBANCES, CUSTOM_DISTURBANCE)
#: The rudder-travel weight of a level a mapping leaves out (and the task's default).
DEFAULT_RUDDER_TRAVEL_WEIGHT = 0.2

#: Per-ship episode data besides the common record (:func:`~ship_env.envs.batch.episode_dtype`).
TASK_FIELDS = (
    ("new_heading", np.float64),  # rad, unwrapped: initial heading + course change
    ("turn_direction", np.float64),  # +1 starboard, -1 port
    ("rudder_travel_weight", np.float64),  # the reward's weight at the episode's disturbance level
)


def check_rudder_travel_weight(value: object) -> dict[str, float]:
    """Each level's rudder-travel weight (``WEIGHTED_LEVELS``) from one number for all, or from a
    mapping level -> weight whose left-out levels take ``DEFAULT_RUDDER_TRAVEL_WEIGHT``.

    ``ValueError`` names an unknown level or a negative or non-finite weight, ``TypeError`` a weight
    that is not a number.
    """
    if not isinstance(value, Mapping):
        return dict.fromkeys(WEIGHTED_LEVELS, check_number("rudder_travel_weight", value, 0.0))
    weights = dict.fromkeys(WEIGHTED_LEVELS, DEFAULT_RUDDER_TRAVEL_WEIGHT)
    for level, weight in value.items():
        check_choice("rudder_travel_weight's level", level, WEIGHTED_LEVELS)
        weights[level] = check_number(f"rudder_travel_weight[{level!r}]", weight, 0.0)
    return weights


@dataclass(frozen=True)
class Scenario(TaskScenario):
    """One episode's course change and the sea it is sailed in.

    Attributes (besides :class:`~ship_env.envs.task.TaskScenario`'s):
        course_change: the ordered change, rad, positive to starboard.
        initial_heading: the steady course sailed at the start, rad.
    """

    course_change: float
    initial_heading: float

    @property
    def new_heading(self) -> float:
        """The ordered new heading, rad, not wrapped."""
        return self.initial_heading + self.course_change


class CourseChangeTask(WeatherTask):
    """The options of the course-change task; the environments' keyword arguments.

    Args:
        disturbance: ``"calm"`` (default), ``"wind_current"``, ``"wind_current_waves"`` or
            ``"random"`` (one of the three per episode).
        course_changes_deg: the course-change magnitudes drawn from, deg, each in (0, 180].
        rudder_limit_deg: delta_max, deg (default 20).
        heading_error_weight: reward per step for |heading error| / pi.
        rudder_travel_weight: reward per step for |actual rudder move| / delta_max; one number, or a
            mapping from the disturbance level (``"calm"``, ``"wind_current"``,
            ``"wind_current_waves"``, ``"custom"``) to the weight of that level's episodes, a level
            left out weighted ``DEFAULT_RUDDER_TRAVEL_WEIGHT`` (0.2): an autopilot's weather setting,
            less rudder for more heading error in a rougher sea. The policy is not told the level.
        settle_band_deg: the settling band of the metrics, deg.
        **options: the weather's ranges (:class:`~ship_env.envs.weather.WeatherTask`:
            ``wind_speed_range``, ``current_speed_range``, ``wave_height_range``,
            ``wave_period_range``) and the keywords every task shares
            (:class:`~ship_env.envs.task.ShipTask`).
    """

    history_observations = (OBS_HEADING_ERROR, OBS_RATE_OF_TURN, OBS_RUDDER)

    def __init__(
        self,
        *,
        disturbance: str = "calm",
        course_changes_deg: Sequence[float] = THESIS_COURSE_CHANGES_DEG,
        rudder_limit_deg: float = 20.0,
        heading_error_weight: float = 1.0,
        rudder_travel_weight: float | Mapping[str, float] = DEFAULT_RUDDER_TRAVEL_WEIGHT,
        settle_band_deg: float = 2.0,
        **options: Any,
    ) -> None:
        if isinstance(course_changes_deg, (str, bytes)) or not isinstance(course_changes_deg, Sequence):
            raise TypeError(f"course_changes_deg: expected a list of angles in deg, got {course_changes_deg!r}")
        if not course_changes_deg:
            raise ValueError("course_changes_deg: expected at least one course change")
        self.course_changes = tuple(
            math.radians(check_number(f"course_changes_deg[{i}]", value, 1e-6, 180.0))
            for i, value in enumerate(course_changes_deg)
        )
        self.heading_error_weight = check_number("heading_error_weight", heading_error_weight, 0.0)
        #: The rudder-travel weight of each disturbance level (``WEIGHTED_LEVELS``).
        self.rudder_travel_weights = check_rudder_travel_weight(rudder_travel_weight)
        self.settle_band = math.radians(check_number("settle_band_deg", settle_band_deg, 0.0, 180.0))
        super().__init__(disturbance=disturbance, rudder_limit_deg=rudder_limit_deg, **options)
        #: The task's constants as the compiled update reads them.
        self.parameters = self.parameter_record(
            heading_error_weight=self.heading_error_weight,
            settle_band=self.settle_band,
            dt=self.dt,
        )
        #: What the compiled update reads besides the simulator's and the batch's arrays.
        self.kernel_arguments = (self.parameters, self.sensors)
        self.observation_space = self.observation_box(OBSERVATION_LOW, OBSERVATION_HIGH)

    # -- scenarios -------------------------------------------------------------------------------
    def draw_task_scenario(self, rng: np.random.Generator, options: Mapping[str, Any] | None = None) -> Scenario:
        """Draw an episode from ``rng``; ``options`` may pin any part of it (``RESET_OPTIONS``).

        Every draw takes the same numbers from ``rng`` whatever the level or options, so one seed
        gives one sequence of episodes. Distributions: level uniform over ``DISTURBANCES`` (if
        ``"random"``); magnitude uniform over the course changes, sign +-1 with equal chance;
        initial heading uniform in [0, 360) deg; the weather as
        :meth:`~ship_env.envs.weather.WeatherRanges.conditions` draws it.
        """
        draws = rng.random(_SCENARIO_DRAWS).tolist()
        seed = int(rng.integers(2**31))
        options = self.check_options(options, RESET_OPTIONS)
        disturbance, conditions = self.draw_weather(draws[0], draws[4:], options)

        if "course_change_deg" in options:
            degrees = check_number("options['course_change_deg']", options["course_change_deg"], -180.0, 180.0)
            change = math.radians(degrees)
            if change == 0.0:
                raise ValueError("options['course_change_deg']: expected a non-zero course change")
        else:
            magnitude = self.course_changes[int(draws[1] * len(self.course_changes))]
            change = magnitude if draws[2] < 0.5 else -magnitude

        if "initial_heading_deg" in options:
            heading = math.radians(check_number("options['initial_heading_deg']", options["initial_heading_deg"]))
        else:
            heading = 2.0 * math.pi * draws[3]
        return Scenario(disturbance, conditions, seed, change, heading)


@kernel
def update_ship(i, states, conditions, noise_keys, step_index, episodes, metrics, task, sensors):
    """Measure, observe and reward ship ``i`` after a step (or after a restart, reward 0).

    Reads the simulator's arrays (``states``, ``conditions``, ``noise_keys``, ``step_index``),
    writes ``episodes[i]`` and ``metrics[i]``. Reward:
    -(w_e |wrap(psi_new - psi)| / pi + w_d |delta - delta_prev| / delta_max) on the true heading psi
    and the actual rudder delta, w_d the episode's (its disturbance level's); the observation comes
    from the measurements.
    """
    episode = episodes[i]
    restarted = episode["restarted"]
    p = task[0]
    state = states[i]
    heading_error = episode["new_heading"] - state[S.HEADING]
    rudder = state[S.RUDDER]
    if restarted:
        start_metrics(metrics[i], heading_error, p["settle_band"])
        episode["reward"] = 0.0
        episode["restarted"] = False
    else:
        rudder_move = abs(rudder - episode["rudder"])
        episode["reward"] = -(
            p["heading_error_weight"] * abs(wrap(heading_error)) / math.pi
            + episode["rudder_travel_weight"] * rudder_move / p["rudder_limit"]
        )
        update_metrics(
            metrics[i], state[S.TIME], heading_error, episode["turn_direction"], rudder_move, p["dt"], p["settle_band"]
        )
    episode["rudder"] = rudder

    measure_and_observe(i, state, conditions, noise_keys, step_index, episode, sensors, restarted, OBS_RATE_OF_TURN, p)
    observation = episode["observation"]
    observation[OBS_HEADING_ERROR] = wrap(episode["new_heading"] - episode["measurement"][MEASURED_HEADING]) / math.pi
    observation[OBS_TURN_DIRECTION] = episode["turn_direction"]


update_ships, update_ships_parallel, sail_ship = define_update_loops(globals())


class CourseChangeBatch(ShipBatch):
    """N ships sailing course changes (:class:`~ship_env.envs.batch.ShipBatch`).

    Each ship's ``episodes`` record holds ``observation`` float32 (5,), ``measurement``, ``reward``,
    the ordered ``new_heading`` and the episode's ``rudder_travel_weight``; ``metrics`` the running
    course-change metrics.
    """

    task: CourseChangeTask
    task_fields = TASK_FIELDS
    #: ``new_heading``: the ordered heading, rad, unwrapped; ``rudder_travel_weight``: the reward's weight
    #: of the episode's disturbance level.
    task_info_keys = ("new_heading", "rudder_travel_weight")
    metrics_dtype = METRICS_DTYPE
    update_serial = staticmethod(update_ships)
    update_parallel = staticmethod(update_ships_parallel)
    sail_one = staticmethod(sail_ship)

    def start_episode(self, episode: np.void, scenario: Scenario) -> None:
        episode["new_heading"] = scenario.new_heading
        episode["turn_direction"] = math.copysign(1.0, scenario.course_change)
        episode["rudder_travel_weight"] = self.task.rudder_travel_weights[scenario.disturbance]
