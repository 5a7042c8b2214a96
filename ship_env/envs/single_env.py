"""The single-ship Gymnasium environment every task shares: a batch of one ship."""

from __future__ import annotations

from typing import Any, ClassVar

import numpy as np
from gymnasium import Env, logger

from ship_env.envs.batch import ShipBatch
from ship_env.envs.rendering import Guide, ShipRenderer
from ship_env.envs.task import ShipTask


class ShipEnv(Env[np.ndarray, Any]):
    """One ship sailing a task's episodes; subclasses name the task and its batch and document both.

    ``reset`` draws a scenario from the environment's ``np_random`` (options pin parts of it) and
    returns the first observation with ``info`` (the batch's information plus ``scenario``);
    ``step`` orders the rudder, advances the simulator one control step (``decision_interval`` simulator
    steps, the order held) and returns the batch's
    observation, reward and termination, never truncating (the registration's time limit does).
    The step that terminates an episode adds the batch's ``end_info``. Rendering draws the ship's
    track, hull and rudder, the disturbances and the task's guides (:meth:`render_guides`).
    """

    metadata: dict[str, Any] = {"render_modes": ["human", "rgb_array"], "render_fps": 30}
    task_class: ClassVar[type[ShipTask]]
    batch_class: ClassVar[type[ShipBatch]]
    env_id: ClassVar[str]

    def __init__(self, render_mode: str | None = None, **task_options: Any) -> None:
        modes = self.metadata["render_modes"]
        if render_mode is not None and render_mode not in modes:
            raise ValueError(f"render_mode: expected one of {modes} or None, got {render_mode!r}")
        self.task = self.task_class(**task_options)
        self.batch = self.batch_class(self.task, 1)
        self.observation_space = self.task.observation_space
        self.action_space = self.task.action_space
        self.render_mode = render_mode
        self._ordered_rudder = 0.0
        self._track: list[np.ndarray] = []
        self._renderer: ShipRenderer | None = None

    def __getstate__(self) -> dict[str, Any]:
        """The attributes a copy or a pickle carries: all but the renderer (its figure or window),
        which the copy makes afresh when it first renders."""
        return {**self.__dict__, "_renderer": None}

    def reset(
        self, *, seed: int | None = None, options: dict[str, Any] | None = None
    ) -> tuple[np.ndarray, dict[str, Any]]:
        super().reset(seed=seed)
        scenario = self.task.draw_scenario(self.np_random, options)
        self.batch.restart(np.zeros(1, dtype=np.intp), [scenario])
        self.batch.update()
        self._ordered_rudder = 0.0
        info = self.batch.info(0)
        info["scenario"] = scenario
        if self.render_mode is not None:
            self._track = [self.batch.simulator.position[0].copy()]
        if self.render_mode == "human":
            self.render()
        return self.batch.observations[0], info

    def step(self, action: Any) -> tuple[np.ndarray, float, bool, bool, dict[str, Any]]:
        self._ordered_rudder = self.task.rudder_order(action)
        batch = self.batch
        batch.sail(self._ordered_rudder)
        if self.render_mode is not None:
            self._track.append(batch.simulator.position[0].copy())
        if self.render_mode == "human":
            self.render()
        observation, reward, terminated = batch.outcome(0)
        info = batch.info(0)
        if terminated:
            info.update(batch.end_info(0))
        return observation, reward, terminated, False, info

    def render_guides(self) -> list[Guide]:
        """The task's lines drawn beside the ship (a new heading, a reference track)."""
        return []

    def render_caption(self) -> str:
        """The task's part of a frame's title."""
        return ""

    def render(self) -> np.ndarray | None:
        if self.render_mode is None:
            logger.warn(
                "You are calling render method without specifying any render mode. You can specify the render_mode at "
                f'initialization, e.g. gym.make("{self.env_id}", render_mode="rgb_array")'
            )
            return None
        if self.batch.scenarios[0] is None:
            raise RuntimeError("render: call reset() before render()")
        if self._renderer is None:
            model = self.task.model
            self._renderer = ShipRenderer(
                self.render_mode,
                self.metadata["render_fps"],
                model.length,
                model.parameter("breadth"),
                self.task.rudder_limit,
            )
        return self._renderer.draw(
            np.asarray(self._track),
            self.batch.simulator.state[0],
            self.batch.scenarios[0].conditions,
            self._ordered_rudder,
            self.render_guides(),
            self.render_caption(),
        )

    def close(self) -> None:
        if self._renderer is not None:
            self._renderer.close()
            self._renderer = None
