"""One interface for every controller on the leaderboard: classic autopilots and learned policies.

An episode is sailed the same way whoever steers::

    observation, info = env.reset(seed=seed)
    controller.reset(observation, info)
    while not (terminated or truncated):
        action = controller.act(observation, info)
        observation, reward, terminated, truncated, info = env.step(action)

``act`` returns the environment's action: the ordered rudder as a fraction of the environment's
rudder limit, in [-1, 1], shape (1,) (or, for a learned policy, whatever its action space holds: a
rudder level of the discrete action, an integer). A learned policy reads the observation; the classic
autopilots read the instruments in ``info["measurement"]`` (:class:`~ship_env.baselines.measurement.Measurement`)
and the ordered heading, and work in radians (:class:`Autopilot`); :class:`AutopilotController`
puts one of them behind this interface.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any, Protocol, runtime_checkable

import numpy as np
from gymnasium import spaces

from ship_env.baselines.measurement import Measurement

#: The environments' continuous action: the ordered rudder over the rudder limit.
RUDDER_FRACTION = spaces.Box(-1.0, 1.0, shape=(1,), dtype=np.float32)


@runtime_checkable
class Controller(Protocol):
    """Steers one ship through episodes of an environment."""

    def reset(self, observation: np.ndarray, info: Mapping[str, Any]) -> None:
        """Start an episode from the environment's first observation and info."""

    def act(self, observation: np.ndarray, info: Mapping[str, Any]) -> np.ndarray:
        """The action for this step, in the environment's action space (the continuous rudder: ordered
        rudder / the environment's rudder limit, shape (1,))."""


@runtime_checkable
class Autopilot(Protocol):
    """A course-changing autopilot in physical units: it orders the rudder, rad, once a sample."""

    def reset(self, measurement: Measurement) -> None:
        """Start from the instruments' first reading (filters initialise on it)."""

    def order(self, setpoint: float, measurement: Measurement) -> float:
        """The ordered rudder, rad, for the ordered heading ``setpoint`` (rad) given this sample."""


class AutopilotController:
    """An :class:`Autopilot` on an environment whose ``info`` carries ``new_heading`` (CourseChange-v0).

    Args:
        autopilot: the autopilot.
        rudder_limit: the environment's rudder limit delta_max, rad, which scales the action.
    """

    def __init__(self, autopilot: Autopilot, rudder_limit: float) -> None:
        if not rudder_limit > 0.0:
            raise ValueError(f"rudder_limit: expected a positive angle in rad, got {rudder_limit!r}")
        self.autopilot = autopilot
        self.rudder_limit = rudder_limit

    def reset(self, observation: np.ndarray, info: Mapping[str, Any]) -> None:
        self.autopilot.reset(Measurement.from_info(info))

    def act(self, observation: np.ndarray, info: Mapping[str, Any]) -> np.ndarray:
        rudder = self.autopilot.order(float(info["new_heading"]), Measurement.from_info(info))
        return np.array([np.clip(rudder / self.rudder_limit, -1.0, 1.0)], dtype=np.float32)


class Policy(Protocol):
    """What :class:`SB3Controller` needs of a policy: stable-baselines3's ``predict``."""

    def predict(
        self,
        observation: np.ndarray,
        state: tuple[np.ndarray, ...] | None = None,
        episode_start: np.ndarray | None = None,
        deterministic: bool = False,
    ) -> tuple[np.ndarray, tuple[np.ndarray, ...] | None]: ...


class SB3Controller:
    """A stable-baselines3 model (or anything with its ``predict``) as a :class:`Controller`.

    The policy acts deterministically; a recurrent policy's hidden state is carried from step to
    step and restarted with each episode. Its actions keep their action space's dtype and shape
    (a ``Box``'s float array, a ``Discrete``'s integer, a ``MultiDiscrete``'s integer array).

    Args:
        policy: e.g. ``PPO.load("ppo_course_change.zip")``.
        action_space: the environment's action space; ``None`` (default): the policy's
            ``action_space`` (a stable-baselines3 model's), or the continuous rudder
            (``Box(-1, 1, (1,))``) for a policy without one.
    """

    def __init__(self, policy: Policy, action_space: spaces.Space | None = None) -> None:
        self.policy = policy
        if action_space is None:
            action_space = getattr(policy, "action_space", None)
        if action_space is None:
            action_space = RUDDER_FRACTION
        #: The actions' space, whose dtype and shape ``act`` returns.
        self.action_space = action_space
        self._hidden_state: tuple[np.ndarray, ...] | None = None
        self._episode_start = np.ones(1, dtype=bool)

    def reset(self, observation: np.ndarray, info: Mapping[str, Any]) -> None:
        self._hidden_state = None
        self._episode_start = np.ones(1, dtype=bool)

    def act(self, observation: np.ndarray, info: Mapping[str, Any]) -> np.ndarray:
        action, self._hidden_state = self.policy.predict(
            observation, state=self._hidden_state, episode_start=self._episode_start, deterministic=True
        )
        self._episode_start = np.zeros(1, dtype=bool)
        return np.asarray(action, dtype=self.action_space.dtype).reshape(self.action_space.shape or ())
