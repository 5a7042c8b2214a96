"""CourseKeeping-v0: hold a course in wind, current and waves with little rudder."""

from __future__ import annotations

import math

from ship_env.envs.course_keeping_task import CourseKeepingBatch, CourseKeepingTask
from ship_env.envs.rendering import Guide
from ship_env.envs.single_env import ShipEnv


class CourseKeepingEnv(ShipEnv):
    """
    ## Description

    The autopilot's everyday task: hold an ordered course while wind, current and waves yaw the
    ship, without working the rudder more than needed. Every rudder movement costs propulsion
    (the ship's speed loss in turns, 2.55) and wears the steering machine, while a heading error
    lengthens the voyage; the classic criterion weighs the two,
    J = mean(e^2) + lambda mean(delta^2) (e the heading error, delta the rudder, deg; lambda 0.1
    by default: see :mod:`ship_env.envs.metrics`). The compass and gyro see the waves'
    high-frequency yaw (Fig. 2.13) which no rudder can remove: a good autopilot filters it
    (thesis 5.3) instead of chasing it.

    The ship (default the 226 m container ship at 19 kn) is simulated by :mod:`ship_env.model`
    with wind (moment, drift, gusts), current, the wave filter's HF yaw on the instruments and the
    Pierson-Moskowitz sea's yaw moment (2.89-2.91).

    ## Action Space

    ``Box(-1, 1, (1,), float32)``: the ordered rudder as a fraction of delta_max
    (``rudder_limit_deg``, default 10 deg), positive to starboard, clipped to [-1, 1]; NaN,
    infinite or wrongly shaped actions raise ``ValueError``. With ``action_type="discrete"``:
    ``Discrete(rudder_levels)``, action k ordering -delta_max + 2 k delta_max / (rudder_levels - 1).

    ## Observation Space

    ``Box(4,) float32``, from the bridge's instruments (noise and the waves' yaw included):

    | Num | Observation   | Definition                                        | Min | Max |
    |-----|---------------|---------------------------------------------------|-----|-----|
    | 0   | heading error | wrap(course - compass heading) / 10 deg           | -18 | 18  |
    | 1   | rate of turn  | gyro rate / (K* U0 / L * delta_max), clipped      | -4  | 4   |
    | 2   | rudder        | actual rudder / delta_max                         | -1  | 1   |
    | 3   | speed         | log speed / service speed U0, clipped             | 0   | 2   |

    With ``observation_history=n`` the heading error, rate of turn and rudder (0, 1, 2) of the n
    previous steps follow, newest first.

    ## Rewards

    Each step: ``-((e / delta_max)^2 + lambda (delta / delta_max)^2)`` with e = wrap(course - psi)
    the *true* heading error (without the waves' HF yaw) and delta the actual rudder at the end
    of the step, so the mean reward of an episode is -J / delta_max^2 (delta_max in deg).

    ## Starting State

    On the ordered course, drawn uniformly in [0, 360) deg, at service speed, rate of turn 0,
    rudder amidships. The disturbance level (if ``"random"``), the wind (speed in
    ``wind_speed_range``, from a uniform direction), the current (``current_speed_range``,
    towards a uniform direction) and the waves (H_s, T_p in their ranges, from the wind's
    direction +-30 deg) are drawn from the environment's ``np_random``; so is the simulator's seed
    for the gusts, the sea, the wave yaw and the sensor noise. ``reset(options=...)`` may pin
    ``disturbance``, ``course_deg`` or ``conditions`` (a :class:`~ship_env.model.Conditions`,
    reported as disturbance ``"custom"``; not with ``disturbance``). An option that brings waves to an
    environment made ``"calm"`` or ``"wind_current"`` sails them: from its first episode with waves the
    model takes on the wave effects (``wave_filter``, ``wave_spectrum``; compiled then, and computed
    every step after, as in an environment made with waves). With ``effects`` given, an option that
    brings weather none of them sails is refused with ``ValueError`` naming the effects to add.

    ## Episode End

    A fixed duration: the episode is truncated after ``max_episode_steps`` (600 in the registration:
    10 minutes at the container ship's 1-s step, 26 L / U on every ship at its default step). It
    never terminates. ``info["envelope"]`` says whether and where the ship left its model's validity
    envelope (the episode sails on). A ship driven outside the model's
    validity (a non-finite state or negative forward speed) raises ``FloatingPointError``; the
    vector environment truncates that ship's episode alone.

    ## Information

    ``reset`` and ``step`` return in ``info``: ``measurement`` (the instruments,
    :mod:`ship_env.envs.sensors`: compass ``heading`` rad with the waves' yaw, gyro
    ``rate_of_turn`` rad/s, ``rudder`` rad, log ``speed`` m/s, position fix ``north``, ``east`` m
    and ``fix_time`` s, for estimators such as the yaw filter of thesis 5.3); ``state``, the
    ship's true state; ``envelope``, whether the ship has stayed inside its model's validity
    envelope this episode and, once it left, where and why (as CourseChange-v0's); ``course``
    (rad); ``metrics``, the criterion so far (:mod:`ship_env.envs.metrics`: ``cost`` J deg^2,
    ``mean_squared_heading_error`` deg^2, ``mean_squared_rudder`` deg^2, ``rudder_travel`` deg),
    final at the episode's last step. ``reset`` adds ``scenario``
    (:class:`~ship_env.envs.course_keeping_task.CourseKeepingScenario`).

    ## Arguments

    ```python
    import gymnasium as gym
    env = gym.make("ship_env/CourseKeeping-v0", wave_height_range=(3.0, 5.0), rudder_weight=0.5)
    ```

    ``render_mode`` (``"human"``, ``"rgb_array"``) and the task's keywords (see
    :class:`~ship_env.envs.course_keeping_task.CourseKeepingTask`): ``disturbance``
    (``"wind_current_waves"`` default, ``"wind_current"``, ``"calm"``, ``"random"``),
    ``rudder_limit_deg``, ``rudder_weight``, ``wind_speed_range``, ``current_speed_range``,
    ``wave_height_range``, ``wave_period_range``; and
    the keywords every task shares, each described at :class:`~ship_env.envs.task.ShipTask`:
    ``ship``, ``ship_parameters``, ``effects``, ``dt``, ``sensor_noise_scale``, ``fix_interval``, ``action_type``,
    ``rudder_levels``, ``observation_history``, ``decision_interval``, ``observe_design_speed``,
    ``ship_variation``, ``dynamics`` and ``info_keys``.

    ## Version History

    * v0: initial version.
    """

    task_class = CourseKeepingTask
    batch_class = CourseKeepingBatch
    env_id = "ship_env/CourseKeeping-v0"

    def render_guides(self) -> list[Guide]:
        return [Guide("course", heading=self.batch.scenarios[0].course)]

    def render_caption(self) -> str:
        return f"course {math.degrees(self.batch.scenarios[0].course) % 360.0:05.1f} deg"
