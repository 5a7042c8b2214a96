"""CourseKeeping-v0 for N ships at once: one simulator call per step for the whole batch."""

from __future__ import annotations

from ship_env.envs.course_keeping_task import CourseKeepingBatch, CourseKeepingTask
from ship_env.envs.vector_env import ShipVectorEnv


class CourseKeepingVectorEnv(ShipVectorEnv):
    """N independent ``CourseKeeping-v0`` episodes, stepped together in one ``Simulator.step``.

    Sub-environment i equals a :class:`~ship_env.envs.course_keeping.CourseKeepingEnv` seeded
    ``s + i``; autoreset, seeding, ``reset_mask`` and the info layout are those of
    :class:`~ship_env.envs.vector_env.ShipVectorEnv`. Episodes end by truncation after
    ``max_episode_steps`` (default 600), or when its ship leaves the model's validity
    (``info["diverged"]``: Episode end in :class:`~ship_env.envs.vector_env.ShipVectorEnv`).
    """

    task_class = CourseKeepingTask
    batch_class = CourseKeepingBatch
    default_max_episode_steps = 600
