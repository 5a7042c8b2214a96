"""Gymnasium environments, registered on ``import ship_env``.

``gymnasium.make("ship_env/<Id>")`` (or ``"ship_env:ship_env/<Id>"`` from a fresh interpreter)
gives the single environment, ``gymnasium.make_vec("ship_env/<Id>", num_envs=N,
vectorization_mode="vector_entry_point")`` the batched one stepping all N ships in one simulator
call. Keyword arguments pass through to the environment (see its docstring):

- ``ship_env/CourseChange-v0``: :class:`~ship_env.envs.course_change.CourseChangeEnv`,
  :class:`~ship_env.envs.course_change_vector.CourseChangeVectorEnv`;
- ``ship_env/TrackFollow-v0``: :class:`~ship_env.envs.track_follow.TrackFollowEnv`,
  :class:`~ship_env.envs.track_follow_vector.TrackFollowVectorEnv`;
- ``ship_env/CourseKeeping-v0``: :class:`~ship_env.envs.course_keeping.CourseKeepingEnv`,
  :class:`~ship_env.envs.course_keeping_vector.CourseKeepingVectorEnv`.
"""

from gymnasium.envs.registration import register

register(
    id="ship_env/CourseChange-v0",
    entry_point="ship_env.envs.course_change:CourseChangeEnv",
    vector_entry_point="ship_env.envs.course_change_vector:CourseChangeVectorEnv",
    max_episode_steps=600,
)
register(
    id="ship_env/TrackFollow-v0",
    entry_point="ship_env.envs.track_follow:TrackFollowEnv",
    vector_entry_point="ship_env.envs.track_follow_vector:TrackFollowVectorEnv",
    max_episode_steps=3600,
)
register(
    id="ship_env/CourseKeeping-v0",
    entry_point="ship_env.envs.course_keeping:CourseKeepingEnv",
    vector_entry_point="ship_env.envs.course_keeping_vector:CourseKeepingVectorEnv",
    max_episode_steps=600,
)
