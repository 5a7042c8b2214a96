"""CourseChange-v0: turn a ship from a steady course onto a new heading."""

from __future__ import annotations

import math

from ship_env.envs.course_change_task import CourseChangeBatch, CourseChangeTask
from ship_env.envs.rendering import Guide
from ship_env.envs.single_env import ShipEnv


class CourseChangeEnv(ShipEnv):
    """
    ## Description

    The course-changing task of the thesis's simulator experiment (Passenier 1989, 6.4.3-6.4.4):
    a ship sails a steady course at its service speed; at time 0 a new heading is ordered, the
    change drawn from the experiment's 15, 30, 45, 75 and 105 deg (Table 6.1.a), to port or to
    starboard. Ordering the rudder once a second, bring the ship onto the new heading quickly,
    without overshoot and without working the steering machine more than needed.

    The ship (default the 226 m container ship of the experiment, 19 kn, K* = 1.6, tau* = 1.7,
    steering machine 2.5 deg/s) is simulated by :mod:`ship_env.model`: De Keizer's
    speed-scheduled yaw with the Norrbin term, speed loss and sway (2.54-2.58), the steering
    machine (Fig. 2.9), and at the chosen disturbance level wind (2.73-2.88, moment, drift and
    gusts), current (2.71, 2.72) and waves (the high-frequency yaw the compass sees, Fig. 2.13,
    and a Pierson-Moskowitz sea's yaw moment, 2.89-2.91).

    ## Action Space

    ``Box(-1, 1, (1,), float32)``: the ordered rudder as a fraction of the rudder limit delta_max
    (``rudder_limit_deg``, default 20 deg), positive to starboard. Values outside [-1, 1] are
    clipped to it (the steering machine's limiter); NaN, infinite or wrongly shaped actions raise
    ``ValueError``. The actual rudder follows the order at the steering machine's rate. With
    ``action_type="discrete"``: ``Discrete(rudder_levels)``, action k ordering
    -delta_max + 2 k delta_max / (rudder_levels - 1).

    ## Observation Space

    ``Box(5,) float32``, from the bridge's instruments (noise and the waves' yaw included):

    | Num | Observation    | Definition                                           | Min | Max |
    |-----|----------------|------------------------------------------------------|-----|-----|
    | 0   | heading error  | wrap(new heading - compass heading) / pi             | -1  | 1   |
    | 1   | rate of turn   | gyro rate / (K* U0 / L * delta_max), clipped         | -4  | 4   |
    | 2   | rudder         | actual rudder / delta_max                            | -1  | 1   |
    | 3   | speed          | log speed / service speed U0, clipped                | 0   | 2   |
    | 4   | turn direction | +1 if the change was ordered to starboard, -1 port   | -1  | 1   |

    K* U0 / L * delta_max is the linear steady rate of turn at full rudder (6.4.4.2), about
    1.35 deg/s for the default ship and limit. The turn direction tells a 180-deg change's way.
    With ``observation_history=n`` the heading error, rate of turn and rudder (0, 1, 2) of the n
    previous steps follow, newest first (``Box(5 + 3 n,)``): a policy without memory can then see
    how the ship answers its rudder. With ``observe_design_speed=True`` the speed is over the
    preset's service speed instead, so a ship sailing slower than designed shows it.

    ## Rewards

    Each step: ``-(heading_error_weight * |e| / pi + rudder_travel_weight * |d delta| / delta_max)``
    with e the *true* heading error wrap(new heading - psi) and d delta the actual rudder's move
    over the step; weights 1 and 0.2 by default. The heading part of the return is the integrated
    absolute heading error in units of pi * dt, the leaderboard's ranking metric.
    ``rudder_travel_weight`` may also be a mapping from the disturbance level to its weight, an
    autopilot's weather setting (``{"calm": 0.15, "wind_current": 0.5, "wind_current_waves": 0.8}``:
    more rudder for less heading error in still water, less chasing of the waves' yaw in a sea);
    each episode's rewards use its level's weight (``"custom"`` for conditions given at reset; a
    level left out weighs 0.2), reported in ``info["rudder_travel_weight"]``. The observation does
    not show the level: a policy must tell the sea from what it sees.

    A policy that must hold up off the design ship trains with ``ship_variation=True`` (K*, tau*
    x0.5..x2, half to full speed, the weather's strength varied), ``observation_history=4`` (it
    sees how this ship answers its rudder) and ``observe_design_speed=True``, behind
    ``ship_env.rl.features.MirroredObservationPolicy`` (a turn to port steered as the mirror image
    of one to starboard), at ``rudder_travel_weight=0.5`` for 5M steps (``configs/agents/ppo.yaml``,
    which says what else was tried): the shipped policy, first or inside the best classic
    autopilot's interval on 10 of the leaderboard's 12 CourseChange suites; the policy trained on
    the nominal ship only holds 4. Trained with one weight per sea (calm 0.3, wind and current 0.5,
    waves 0.8) it held none: the rudder chatters.

    ## Starting State

    At the origin, on an initial heading drawn uniformly in [0, 360) deg, at service speed, rate
    of turn 0, rudder amidships. The course change, the disturbance level (if ``"random"``), wind
    (speed in ``wind_speed_range``, from a uniform direction), current (``current_speed_range``,
    towards a uniform direction) and waves (H_s, T_p in their ranges, from the wind's direction
    +-30 deg) are drawn from the environment's ``np_random``; so is the simulator's seed for the
    gusts, the sea, the wave yaw and the sensor noise. ``reset(options=...)`` may pin
    ``disturbance``, ``course_change_deg`` (signed), ``initial_heading_deg`` or ``conditions``
    (a :class:`~ship_env.model.Conditions`, reported as disturbance ``"custom"``; not with
    ``disturbance``). An option that brings waves to an environment made ``"calm"`` or
    ``"wind_current"`` sails them: from its first episode with waves the model takes on the wave
    effects (``wave_filter``, ``wave_spectrum``; compiled then, and computed every step after, as in
    an environment made with waves). With ``effects`` given, an option that brings weather none of
    them sails is refused with ``ValueError`` naming the effects to add.

    ## Episode End

    The episode is truncated after ``max_episode_steps`` (600 in the registration: 600 s at the
    container ship's 1-s step). The default step is 1 s in units of the ship's L / U
    (:mod:`ship_env.envs.ship_scales`: 0.36 s for a 3 m model at 0.35 m/s, 1.69 s for a 320 m tanker
    at 15.5 kn), so 600 steps span 26 L / U on every ship, time for a 105-deg change and its
    settling; with a ``dt`` of your own, give ``max_episode_steps`` in proportion. It never
    terminates: a course change has no terminal state. ``info["envelope"]`` says whether and where
    the ship left its model's validity envelope (the episode sails on). A model driven
    outside its validity (a non-finite state or negative forward speed, which the presets do not
    reach within their rudder limit) is a divergence: the simulator raises ``FloatingPointError``;
    the vector environment truncates that ship's episode alone (``info["diverged"]``).

    ## Information

    ``reset`` and ``step`` return in ``info``: ``measurement`` (the instruments,
    :mod:`ship_env.envs.sensors`: compass ``heading`` in [0, 2 pi) rad with the waves' yaw, gyro
    ``rate_of_turn`` rad/s, ``rudder`` rad, log ``speed`` m/s, the latest position fix ``north``
    and ``east`` m and its ``fix_time`` s, for estimators such as the yaw and position filters of
    thesis 5.3-5.4); ``state``, the ship's true state (layout in
    :mod:`ship_env.model.state`); ``envelope``, whether the ship has stayed inside its model's
    validity envelope (the preset's ``envelope:``, :mod:`ship_env.envs.envelope`) this episode:
    ``inside`` (bool) and, once it left, the first step outside and why, ``quantity``
    (``"speed"``, ``"froude"``, ``"drift"``, ``"rate"`` or ``"propeller"``; ``""`` while inside),
    ``step`` (the simulator step since the start; -1 while inside), ``time`` s, ``value`` and
    ``limit`` (SI units: m/s, -, rad, rad/s, rps; 0 while inside); ``new_heading`` (rad,
    unwrapped); ``rudder_travel_weight`` (the reward's, at the episode's disturbance level);
    ``metrics``, the episode's metrics so far (:mod:`ship_env.envs.metrics`: integrated heading
    error deg s, overshoot deg, settling time s, rudder travel deg), final at its last step. ``reset`` adds ``scenario``
    (:class:`~ship_env.envs.course_change_task.Scenario`).

    ## Arguments

    ```python
    import gymnasium as gym
    env = gym.make("ship_env/CourseChange-v0", disturbance="random", rudder_limit_deg=10.0)
    ```

    ``render_mode`` (``"human"``, ``"rgb_array"``) and the task's keywords (see
    :class:`~ship_env.envs.course_change_task.CourseChangeTask`): ``disturbance`` (``"calm"``
    default, ``"wind_current"``, ``"wind_current_waves"``, ``"random"``), ``course_changes_deg``,
    ``rudder_limit_deg``, ``heading_error_weight``, ``rudder_travel_weight`` (a number, or one per
    disturbance level), ``settle_band_deg``,
    ``wind_speed_range``, ``current_speed_range``, ``wave_height_range``, ``wave_period_range``
    (default: the container ship's ranges in the sailed ship's scales,
    :meth:`~ship_env.envs.weather.WeatherRanges.scaled`); and
    the keywords every task shares, each described at :class:`~ship_env.envs.task.ShipTask`:
    ``ship``, ``ship_parameters``, ``effects``, ``dt``, ``sensor_noise_scale``, ``fix_interval``
    (default 0: a fix every step), ``action_type``, ``rudder_levels``, ``observation_history``,
    ``decision_interval``, ``observe_design_speed``, ``ship_variation``, ``dynamics`` and ``info_keys``.

    ## Version History

    * v0: initial version.
    """

    task_class = CourseChangeTask
    batch_class = CourseChangeBatch
    env_id = "ship_env/CourseChange-v0"

    def render_guides(self) -> list[Guide]:
        return [Guide("new heading", heading=self.batch.scenarios[0].new_heading)]

    def render_caption(self) -> str:
        return f"new {math.degrees(self.batch.scenarios[0].new_heading) % 360.0:05.1f} deg"
