"""The leaderboard's own seeded episode loop (SB3's ``evaluate_policy`` resets without seeds).

:func:`sail_suite` sails every episode of a suite with one entrant: it makes the sailed
environment (the suite's, sailing the condition's ship), designs each episode's fresh
controller for the nominal ship, resets with the episode's seed and options, and steps until the
episode ends. The result is a pure function of the entrant, the suite and the episode. A controller
that declares itself failed (a classic autopilot's filter diverging, ``FilterDivergenceError``) ends
its entrant's job on that suite: the episode's result names the failure and the remaining episodes
are not sailed (the leaderboard leaves the entrant out of that suite's table, saying why).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import gymnasium as gym
import numpy as np

import ship_env  # noqa: F401  (registers the environments)
from ship_env.baselines.controller import Controller
from ship_env.baselines.filter_health import FilterDivergenceError
from ship_env.envs.single_env import ShipEnv
from ship_env.envs.task import ShipTask
from ship_env.leaderboard.entrants import DesignedTask, Entrant
from ship_env.leaderboard.suites import Episode, Suite
from ship_env.model import ShipModel


@dataclass(frozen=True)
class EpisodeResult:
    """One entrant's episode.

    Attributes:
        suite: the suite's name.
        entrant: the entrant's name.
        kind: the entrant's kind (``"classic"``, ``"learned"``).
        training_seed: the training seed of the learned entrant's policy that sailed (``None``
            for a classic autopilot, or a policy without metadata).
        episode: the episode's label.
        seed: the episode's seed.
        metrics: the environment's final metrics (floats).
        finished: whether the episode ended by termination (TrackFollow: the last waypoint passed)
            rather than by the time limit.
        failure: why the controller failed in this episode ("" where it did not; its metrics are then empty).
    """

    suite: str
    entrant: str
    kind: str
    training_seed: int | None
    episode: str
    seed: int
    metrics: dict[str, float]
    finished: bool
    failure: str = ""


def sail(
    env: gym.Env, controller: Controller, episode: Episode, states: list[np.ndarray] | None = None
) -> tuple[dict, bool]:
    """Sail one episode; its final metrics and whether it terminated. ``states`` collects the true states."""
    observation, info = env.reset(seed=episode.seed, options=dict(episode.options))
    controller.reset(observation, info)
    terminated = truncated = False
    while not (terminated or truncated):
        if states is not None:
            states.append(info["state"])
        observation, _, terminated, truncated, info = env.step(controller.act(observation, info))
    if states is not None:
        states.append(info["state"])
    return {name: float(value) for name, value in info["metrics"].items()}, bool(terminated)


def ship_task(env: gym.Env) -> ShipTask:
    """The task of a ship environment made by ``gym.make`` (under its wrappers)."""
    unwrapped = env.unwrapped
    if not isinstance(unwrapped, ShipEnv):
        raise TypeError(f"expected a ship_env environment, got {type(unwrapped).__name__}")
    return unwrapped.task


def suite_envs(suite: Suite, entrant: Entrant) -> tuple[gym.Env, ShipModel]:
    """The environment the suite sails (with its condition's ship, observed as ``entrant`` was
    trained to) and the nominal ship's model."""
    env_kwargs: dict[str, Any] = {**suite.env_kwargs, **dict(entrant.observation_kwargs)}
    if suite.condition.varies:
        env_kwargs["ship_variation"] = suite.condition.ship_variation()
    env = gym.make(suite.env_id, **env_kwargs)
    return env, ship_task(env).model


def sail_recorded(entrant: Entrant, suite: Suite, episode: Episode) -> tuple[np.ndarray, ShipTask]:
    """Sail one episode of ``suite`` with ``entrant`` (a learned one's first training seed),
    recording it: the true states at each step (steps + 1, state size; layout
    ``ShipModel.state_names``) and the sailed task (its tracks)."""
    env, design_model = suite_envs(suite, entrant)
    states: list[np.ndarray] = []
    try:
        sail(env, entrant.build(DesignedTask(ship_task(env), design_model)), episode, states)
    finally:
        env.close()
    return np.asarray(states), ship_task(env)


def sail_suite(
    entrant: Entrant, suite: Suite, run: int = 0, on_episode: Callable[[], object] | None = None
) -> list[EpisodeResult]:
    """Sail every episode of ``suite`` with ``entrant`` (a learned one's ``run``-th training seed);
    ``on_episode`` is called after each."""
    env, design_model = suite_envs(suite, entrant)
    training_seed = entrant.training_seeds[run] if entrant.training_seeds else None
    results = []
    try:
        for episode in suite.episodes:
            controller = entrant.build(DesignedTask(ship_task(env), design_model), run)
            result = EpisodeResult(
                suite.name, entrant.name, entrant.kind, training_seed, episode.label, episode.seed, {}, False
            )
            try:
                metrics, finished = sail(env, controller, episode)
            except (FilterDivergenceError, FloatingPointError) as error:  # the controller's filter, or the ship model
                results.append(dataclasses.replace(result, failure=f"{type(error).__name__}: {error}"))
                break
            results.append(dataclasses.replace(result, metrics=metrics, finished=finished))
            if on_episode is not None:
                on_episode()
    finally:
        env.close()
    return results
