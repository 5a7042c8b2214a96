"""TrackFollow-v0: sail the reference tracks of the thesis's simulator experiment."""

from __future__ import annotations

from ship_env.envs.rendering import Guide
from ship_env.envs.single_env import ShipEnv
from ship_env.envs.track_follow_task import TrackFollowBatch, TrackFollowTask


class TrackFollowEnv(ShipEnv):
    """
    ## Description

    The tracking task of the thesis's simulator experiment (Passenier 1989, 6.4.3-6.4.4): sail a
    reference track of six legs as accurately as possible. Each of the six tracks T1..T6 has five
    course changes, of 15, 30, 45, 75 and 105 deg in the order of Table 6.1.b (T1: 75 45 30 105 15;
    T2: 15 75 105 30 45; T3: 45 15 105 75 30; T4: 105 30 75 15 45; T5: 30 15 45 75 105; T6: 45 105
    15 30 75), alternately to starboard and to port, starboard first (the thesis gives no
    directions; see :mod:`ship_env.envs.tracks`), with legs of 2 to 2.5 nm, the first course
    north. The reference track rounds each waypoint on the ship's own steady turn at the rudder
    limit (radius about 860 m for the container ship at 10 deg), as the thesis corrected its
    score "for the ship's inherent manoeuvrability" (6.4.4.2).

    The ship is the experiment's 226 m container ship at 9.5 m/s (19 kn) with the rudder limited
    to 10 deg (6.4.4.2), in the disturbances of Table 6.2: a current of 2.5 kn setting towards
    SW (225 deg) and a wind of 7 m/s blowing from NW (315 deg), with gusts. The thesis writes
    "South West" and "North West"; the usual conventions (a current by where it goes, a wind by
    where it comes from) are assumed. Another ship (``ship=``) sails the tracks, the step and this
    weather in its own scales (:mod:`ship_env.envs.ship_scales`): legs in proportion to its length,
    the step 1 s in units of L / U, the wind's and the current's speeds in units of its speed.

    ## Action Space

    ``Box(-1, 1, (1,), float32)``: the ordered rudder as a fraction of delta_max
    (``rudder_limit_deg``, default 10 deg), positive to starboard, clipped to [-1, 1]; NaN,
    infinite or wrongly shaped actions raise ``ValueError``. With ``action_type="discrete"``:
    ``Discrete(rudder_levels)``, action k ordering -delta_max + 2 k delta_max / (rudder_levels - 1).

    ## Observation Space

    ``Box(8,) float32``, from the bridge's instruments (the latest position fix, taken every
    ``fix_interval`` = 2 s, compass, gyro, log), relative to the leg being sailed:

    | Num | Observation       | Definition                                                   | Min | Max |
    |-----|-------------------|--------------------------------------------------------------|-----|-----|
    | 0   | cross-track error | signed distance of the fix to the reference track / L        | -10 | 10  |
    | 1   | heading error     | wrap(leg course - compass heading) / pi                      | -1  | 1   |
    | 2   | rate of turn      | gyro rate / (K* U0 / L * delta_max), clipped                 | -4  | 4   |
    | 3   | rudder            | actual rudder / delta_max                                    | -1  | 1   |
    | 4   | speed             | log speed / service speed U0, clipped                        | 0   | 2   |
    | 5   | next course change| the change at the leg's end waypoint / pi, 0 on the last leg | -1  | 1   |
    | 6   | waypoint distance | fix to the leg's end waypoint along the leg, nm, clipped     | -1  | 3   |
    | 7   | cross-track rate  | the fixes' cross-track error's rate, filtered (30 s) / U0    | -1  | 1   |

    On another ship than the 226 m container ship at 19 kn the nm and the times are its own
    (:mod:`ship_env.envs.ship_scales`): the waypoint distance is over ``track_scale`` nm (L / 226 m,
    the tracks drawn in proportion), the fixes' interval, the rate's filter time (30 s) and the
    arc time's minutes are in units of L / U (times (L / U) / 24 s), so a policy sees the same
    numbers on a geometrically similar ship at the same Froude number.

    With ``track_preview=True`` four more, the rounded reference track at and ahead of the fix's
    nearest point on it (what a track pilot's display shows; the wheel-over point lies a reaction
    time, about 30 s for the container ship at 10 deg, before the arc's start):

    | Num | Observation        | Definition                                                  | Min | Max |
    |-----|--------------------|-------------------------------------------------------------|-----|-----|
    | 8   | track heading error| wrap(the track's course there - compass heading) / pi       | -1  | 1   |
    | 9   | track turn         | the track's curvature there * L / (K* delta_max), clipped   | -2  | 2   |
    | 10  | time to next arc   | along the track to the next arc's start / U0, min (0 on one)| 0   | 5   |
    | 11  | next turn          | the next arc's curvature * L / (K* delta_max), clipped      | -2  | 2   |

    The arcs are the ship's steady turns at delta_max, so a turn reads about +-0.94 (+ starboard).
    With ``observation_history=n`` the heading error, rate of turn and rudder (1, 2, 3) of the n
    previous steps follow, newest first, with their bounds.

    The cross-track error is positive with the ship to starboard of the track (steer to port);
    L = 225.87 m for the container ship. The leg advances when the ship crosses the bisector of
    the corner at the leg's end (the line through the waypoint and the turn's centre), so the
    heading error jumps by the course change there; observations 5 and 6 let a policy put the
    rudder over before it (the wheel-over point lies about a turning radius' tangent plus the
    ship's reaction distance ahead of the arc). The cross-track rate (a track pilot's cross-track
    speed) is what the set of the current and the wind shows as: holding it at zero with the
    cross-track error at zero needs the heading off the leg's course by the drift angle.

    ## Rewards

    Each step: ``-(cross_track_weight * (e / L)^2 + rudder_travel_weight * |d delta| / delta_max)``
    with e the true cross-track error (e / L clipped to +-``cross_track_reward_bound``, default 10,
    so a lost ship costs at most 100 a step) and d delta the actual rudder's move over the step;
    weights 1 and 0.1 by default. Within the clip, the cross-track part of the return is the sum of
    the squared errors whose root mean, sampled every 2 s, is the score. With
    ``decision_interval=k`` one environment step holds the rudder order for k simulator steps and
    its reward is their sum.

    ## Starting State

    At the first waypoint (the origin) on the first leg's course, at service speed, rate of turn
    0, rudder amidships; with ``start="before_turn"`` on a random one of the first five legs, 1 to
    1.6 nm before its end waypoint, on its course (a training curriculum: every episode meets a
    turn within minutes). The track (if ``"random"``) and the simulator's seed (gusts, sensor
    noise) are drawn from the environment's ``np_random``. ``reset(options=...)`` may pin the
    ``track`` or give the ``conditions`` (a :class:`~ship_env.model.Conditions`, reported as
    disturbance ``"custom"``). Conditions with waves sail them: from the first such episode the model
    takes on the wave effects (``wave_filter``, ``wave_spectrum``; compiled then, and computed every
    step after). With ``effects`` given, conditions none of them sails are refused with
    ``ValueError`` naming the effects to add.

    ## Episode End

    The episode terminates when the ship passes the last waypoint (crosses the perpendicular to the
    last leg there); the step that does so adds ``info["score"]``. It is truncated after
    ``max_episode_steps`` (3600 in the registration: one hour at the container ship's 1-s step; a
    track takes 44 to 48 minutes in the thesis's current). The default step and the tracks follow the
    ship (``dt`` 1 s and the legs in units of L / U and L: :mod:`ship_env.envs.ship_scales`), so a
    track takes as many steps on every ship at its service speed; with a ``dt`` or ``track_scale`` of
    your own, give ``max_episode_steps`` in proportion. ``info["envelope"]`` says whether and where
    the ship left its model's validity envelope (the episode sails on). A ship driven outside the model's validity (a
    non-finite state or negative forward speed) raises ``FloatingPointError``; the vector
    environment truncates that ship's episode alone.

    ## Information

    ``reset`` and ``step`` return in ``info``: ``measurement`` (the instruments,
    :mod:`ship_env.envs.sensors`: compass ``heading`` rad, gyro ``rate_of_turn`` rad/s, ``rudder``
    rad, log ``speed`` m/s, and the latest GPS fix ``north``, ``east`` m with its ``fix_time`` s,
    5 m noise, every 2 s, for the position filter and track predictor of thesis 5.4, 5.6);
    ``state``, the ship's true state; ``envelope``, whether the ship has stayed inside its model's
    validity envelope (the preset's ``envelope:``) this episode and, once it left, the first step
    outside and why (``inside``, ``quantity``: ``"speed"``, ``"froude"``, ``"drift"``, ``"rate"``
    or ``"propeller"``, ``step``, ``time`` s, ``value`` and ``limit`` in SI units;
    :mod:`ship_env.envs.envelope`); ``leg`` (0-based) and ``cross_track_error`` (m, true);
    ``metrics``, the episode's track metrics so far (:mod:`ship_env.envs.metrics`:
    ``rms_cross_track_error`` m, the score of eq. 6.5 sampled every 2 s, ``max_cross_track_error``
    m, ``rudder_travel`` deg). ``reset`` adds ``scenario``
    (:class:`~ship_env.envs.track_follow_task.TrackScenario`). At termination ``score`` holds
    ``rms_cross_track_error`` beside the thesis's navigators' mean RMS errors (Table 6.4),
    ``thesis_parallel_indexing`` 117 m, ``thesis_ground_speed_vector`` 95 m and
    ``thesis_track_predictor`` 33 m. The reference tracks themselves are ``env.unwrapped.task.tracks``
    (:class:`~ship_env.envs.tracks.ReferenceTrack`); :func:`ship_env.envs.tracks.cross_track_error`
    and :func:`ship_env.envs.metrics.track_metrics` score any recorded run the same way.

    ## Arguments

    ```python
    import gymnasium as gym
    env = gym.make("ship_env/TrackFollow-v0", track="T3")
    ```

    ``render_mode`` (``"human"``, ``"rgb_array"``) and the task's keywords (see
    :class:`~ship_env.envs.track_follow_task.TrackFollowTask`): ``track`` (``"T1"`` ..
    ``"T6"``, ``"random"`` default), ``disturbance`` (``"thesis"`` default, ``"calm"``),
    ``rudder_limit_deg``, ``cross_track_weight``, ``rudder_travel_weight``, ``fix_interval``
    (s; default the thesis's 2 s in units of L / U), ``track_preview``, ``line_of_sight_weight``,
    ``cross_track_reward_bound``, ``start``, ``track_scale`` (default L / 226 m); and
    the keywords every task shares, each described at :class:`~ship_env.envs.task.ShipTask`:
    ``ship``, ``ship_parameters``, ``effects``, ``dt``, ``sensor_noise_scale``, ``action_type``,
    ``rudder_levels``, ``observation_history``, ``decision_interval``, ``observe_design_speed``,
    ``ship_variation``, ``dynamics`` and ``info_keys``.

    ## Version History

    * v0: initial version.
    """

    task: TrackFollowTask
    task_class = TrackFollowTask
    batch_class = TrackFollowBatch
    env_id = "ship_env/TrackFollow-v0"

    def render_guides(self) -> list[Guide]:
        outline = self.task.tracks[self.batch.scenarios[0].track].outline()
        return [Guide("reference track", outline[:, 0], outline[:, 1])]

    def render_caption(self) -> str:
        episode = self.batch.episodes[0]
        return (
            f"{self.batch.scenarios[0].track} leg {episode['leg'] + 1}   "
            f"cross-track {episode['cross_track_error']:+.0f} m"
        )
