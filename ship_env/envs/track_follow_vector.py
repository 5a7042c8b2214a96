"""TrackFollow-v0 for N ships at once: one simulator call per step for the whole batch."""

from __future__ import annotations

from ship_env.envs.track_follow_task import TrackFollowBatch, TrackFollowTask
from ship_env.envs.vector_env import ShipVectorEnv


class TrackFollowVectorEnv(ShipVectorEnv):
    """N independent ``TrackFollow-v0`` episodes, stepped together in one ``Simulator.step``.

    Sub-environment i equals a :class:`~ship_env.envs.track_follow.TrackFollowEnv` seeded ``s + i``;
    autoreset, seeding, ``reset_mask`` and the info layout are those of
    :class:`~ship_env.envs.vector_env.ShipVectorEnv`. An episode terminates when its ship passes the
    last waypoint (``info["score"]`` is then set, masked to those sub-environments) and is truncated
    after ``max_episode_steps`` (default 3600), or when its ship leaves the model's validity
    (``info["diverged"]``: Episode end in :class:`~ship_env.envs.vector_env.ShipVectorEnv`).
    """

    task_class = TrackFollowTask
    batch_class = TrackFollowBatch
    default_max_episode_steps = 3600
