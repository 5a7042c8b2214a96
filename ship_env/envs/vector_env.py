"""The native vector environment every task shares: N ships, one simulator call per step."""

from __future__ import annotations

from typing import Any, ClassVar

import numpy as np
from gymnasium.utils import seeding
from gymnasium.vector import AutoresetMode, VectorEnv
from gymnasium.vector.utils import batch_space

from ship_env.envs.batch import ShipBatch
from ship_env.envs.checks import check_whole_number
from ship_env.envs.task import ShipTask


def _with_masks(info: dict[str, Any], mask: np.ndarray) -> dict[str, Any]:
    """A vector info in Gymnasium's layout: every key with its ``_key`` mask, nested dicts alike."""
    batched: dict[str, Any] = {}
    for key, value in info.items():
        batched[key] = _with_masks(value, mask) if isinstance(value, dict) else value
        batched[f"_{key}"] = mask
    return batched


class ShipVectorEnv(VectorEnv):
    """N independent episodes of a task, stepped together in one ``Simulator.step``.

    The task, observations, rewards, information and metrics are those of the task's single
    environment (the same compiled code), and sub-environment i behaves exactly as a single
    environment: ``reset(seed=s)`` seeds it with ``s + i`` and every later episode is drawn from
    its own generator, so the trajectories equal N single environments' with those seeds.

    Autoreset follows Gymnasium's ``AutoresetMode.NEXT_STEP``: the step that ends an episode
    (termination or truncation, see Episode end) returns its last observation; the next ``step``
    restarts that sub-environment, ignores its action and returns the first observation of the new
    episode with reward 0 and the reset's information (with ``scenario``).
    ``reset(options={"reset_mask": mask})`` restarts only the masked sub-environments (with the
    single environment's options beside it, which act as there: options that bring waves to a model
    without the wave effects make every ship sail the model with them from then on, each ship's
    observations and rewards as they were; only the wave filter's states in ``info["state"]`` move,
    as in an environment made with waves, unseen by a ship in a sea without waves).

    Infos are dicts of arrays, each key with its boolean ``_key`` mask (Gymnasium's vector
    layout); ``scenario`` is an object array, set for the sub-environments that started an
    episode at that call; the keys a terminating step adds are masked to the terminated ones, and
    ``diverged`` to the diverged ones.
    After ``reset`` the masks mark the sub-environments it restarted.

    Episode end: a sub-environment's episode terminates where its task says, or is truncated after
    ``max_episode_steps``, or is truncated when its ship leaves the model's validity (a state not
    finite, or the forward speed negative: where the single environment and ``Simulator.step``
    raise ``FloatingPointError``). Only that sub-environment's episode ends: ``info["diverged"]``
    (a bool array, with its ``_diverged`` mask, present at a step where a ship diverged) marks it,
    its observation and information are those of its last valid simulator step (``state``: the
    state that left the validity), its reward the sum over the simulator steps before the diverging
    one (0 with a ``decision_interval`` of 1), and it restarts at the next step like any ended
    episode; the other ships sail on with the numbers they would have without it. Truncated, not
    terminated: leaving the model's validity is a limit of the simulation, not a state of the task
    (a real ship sails on), as Gymnasium's ``truncated`` covers "an agent physically going out of
    bounds"; a learner then bootstraps from the last observation, as after the time limit, so a
    policy gains nothing by driving a ship out of the model.

    Args:
        num_envs: N, the number of ships.
        max_episode_steps: the episode length in steps (``make_vec`` passes the spec's).
        render_mode: must be None: draw a single environment instead.
        **task_options: the task's keywords, as for the single environment.
    """

    metadata: dict[str, Any] = {"render_modes": [], "autoreset_mode": AutoresetMode.NEXT_STEP}
    task_class: ClassVar[type[ShipTask]]
    batch_class: ClassVar[type[ShipBatch]]
    default_max_episode_steps: ClassVar[int]

    def __init__(
        self,
        num_envs: int = 1,
        max_episode_steps: int | None = None,
        render_mode: str | None = None,
        **task_options: Any,
    ) -> None:
        if render_mode is not None:
            raise ValueError(f"render_mode: the vector env does not render, got {render_mode!r}; use the single env")
        if max_episode_steps is None:
            max_episode_steps = self.default_max_episode_steps
        self.max_episode_steps = check_whole_number("max_episode_steps", max_episode_steps, 1)
        self.task = self.task_class(**task_options)
        self.batch = self.batch_class(self.task, num_envs, end_diverged_episodes=True)
        self.num_envs = self.batch.num_ships
        self.single_observation_space = self.task.observation_space
        self.single_action_space = self.task.action_space
        self.observation_space = batch_space(self.single_observation_space, self.num_envs)
        self.action_space = batch_space(self.single_action_space, self.num_envs)
        self.render_mode = render_mode
        self._generators = [seeding.np_random()[0] for _ in range(self.num_envs)]
        self._elapsed_steps = np.zeros(self.num_envs, dtype=np.int64)
        self._autoreset = np.zeros(self.num_envs, dtype=np.bool_)
        self._orders = np.zeros(self.num_envs)
        self._all_envs = np.ones(self.num_envs, dtype=np.bool_)
        self._all_envs.setflags(write=False)  # shared by the ``_key`` masks of every info

    def __setstate__(self, state: dict[str, Any]) -> None:
        """A copy or a pickle restored: the masks every info shares are read-only again (numpy
        restores arrays writable)."""
        self.__dict__.update(state)
        self._all_envs.setflags(write=False)

    def reset(
        self, *, seed: int | list[int | None] | None = None, options: dict[str, Any] | None = None
    ) -> tuple[np.ndarray, dict[str, Any]]:
        """Start new episodes: all sub-environments, or those in ``options["reset_mask"]``.

        ``seed``: None (go on with each sub-environment's generator), an integer s (sub-environment
        i is seeded with s + i) or one seed or None per sub-environment.
        """
        options = dict(options or {})
        mask = options.pop("reset_mask", self._all_envs)
        if not (
            isinstance(mask, np.ndarray) and mask.shape == (self.num_envs,) and mask.dtype == np.bool_ and mask.any()
        ):
            raise ValueError(
                f"options['reset_mask']: expected a bool array of shape ({self.num_envs},) with a True, got {mask!r}"
            )
        mask = mask.copy()
        ships = np.flatnonzero(mask)
        if isinstance(seed, bool):
            raise ValueError(f"seed: expected None, an integer or {self.num_envs} seeds, got {seed!r}")
        if isinstance(seed, (int, np.integer)):
            super().reset(seed=int(seed))
            seeds: list[int | None] = [int(seed) + i for i in range(self.num_envs)]
        elif seed is None:
            seeds = [None] * self.num_envs
        else:
            seeds = list(seed)
            if len(seeds) != self.num_envs:
                raise ValueError(f"seed: expected None, an integer or {self.num_envs} seeds, got {seed!r}")
        for ship in ships:
            if seeds[ship] is not None:
                self._generators[ship] = seeding.np_random(seeds[ship])[0]
        scenarios = self._restart(ships, options)
        self.batch.update(restarted_only=True)
        return self.batch.observations, self._info(ships, scenarios, mask)

    def step(self, actions: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, dict[str, Any]]:
        """Step every ship (``decision_interval`` simulator steps); restart those whose episode ended at
        the previous step (NEXT_STEP)."""
        orders = self.task.rudder_orders(actions, self.num_envs, self._orders)
        self._elapsed_steps += 1
        ships = np.flatnonzero(self._autoreset)
        scenarios: list[Any] = []

        def restart() -> None:
            if ships.size:
                scenarios.extend(self._restart(ships, {}))

        self.batch.sail(orders, self._autoreset.copy(), restart)
        observations, rewards, terminated = self.batch.outcomes()
        diverged = self.batch.diverged.copy()
        truncated = (self._elapsed_steps >= self.max_episode_steps) | diverged
        self._autoreset = terminated | truncated
        info = self._info(ships, scenarios, self._all_envs)
        if terminated.any():
            info.update(_with_masks(self.batch.end_info(slice(None)), terminated))
        if diverged.any():
            info.update(_with_masks({"diverged": diverged}, diverged))
        return observations, rewards, terminated, truncated, info

    def _restart(self, ships: np.ndarray, options: dict[str, Any]) -> list[Any]:
        """Draw and start new episodes for ``ships``."""
        scenarios = [self.task.draw_scenario(self._generators[ship], options) for ship in ships]
        self.batch.restart(ships, scenarios)
        self._elapsed_steps[ships] = 0
        self._autoreset[ships] = False
        return scenarios

    def _info(self, ships: np.ndarray, scenarios: list[Any], mask: np.ndarray) -> dict[str, Any]:
        """The batch's info with ``mask`` on every key, plus the scenarios of the ``ships`` that started."""
        info = _with_masks(self.batch.info(slice(None)), mask)
        if ships.size:
            info["scenario"] = np.full(self.num_envs, None, dtype=object)
            info["scenario"][ships] = scenarios
            info["_scenario"] = np.zeros(self.num_envs, dtype=np.bool_)
            info["_scenario"][ships] = True
        return info
