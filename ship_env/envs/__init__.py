"""Gymnasium environments, registered on ``import ship_env``.

``gymnasium.make("ship_env/CourseChange-v0")`` (or ``"ship_env:ship_env/CourseChange-v0"`` from a
fresh interpreter) gives :class:`~ship_env.envs.course_change.CourseChangeEnv`;
``gymnasium.make_vec("ship_env/CourseChange-v0", num_envs=N)`` the batched
:class:`~ship_env.envs.course_change_vector.CourseChangeVectorEnv`. Keyword arguments pass through
to the environment (see its docstring).
"""

from gymnasium.envs.registration import register

register(
    id="ship_env/CourseChange-v0",
    entry_point="ship_env.envs.course_change:CourseChangeEnv",
    vector_entry_point="ship_env.envs.course_change_vector:CourseChangeVectorEnv",
    max_episode_steps=600,
)
