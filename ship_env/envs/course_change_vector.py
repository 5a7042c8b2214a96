"""CourseChange-v0 for N ships at once: one simulator call per step for the whole batch."""

from __future__ import annotations

from ship_env.envs.course_change_task import CourseChangeBatch, CourseChangeTask
from ship_env.envs.vector_env import ShipVectorEnv


class CourseChangeVectorEnv(ShipVectorEnv):
    """N independent ``CourseChange-v0`` episodes, stepped together in one ``Simulator.step``.

    Sub-environment i equals a :class:`~ship_env.envs.course_change.CourseChangeEnv` seeded
    ``s + i``; autoreset, seeding, ``reset_mask`` and the info layout are those of
    :class:`~ship_env.envs.vector_env.ShipVectorEnv`. A course change never terminates: episodes end
    by truncation after ``max_episode_steps`` (default 600), or when its ship leaves the model's
    validity (``info["diverged"]``: Episode end in
    :class:`~ship_env.envs.vector_env.ShipVectorEnv`).
    """

    task_class = CourseChangeTask
    batch_class = CourseChangeBatch
    default_max_episode_steps = 600
