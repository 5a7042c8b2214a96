"""Fixed input scaling inside a policy network: the environment's observation stays as it is.

The course-change observation holds the heading error as a fraction of pi (design notes 4): a
1-deg error is 0.0056, too small for a freshly initialised network to act on, while a good
autopilot's rudder answers it in full (the PD's gain is about 19 rudder limits per unit of that
observation). :class:`ScaledObservation` multiplies each observation by a fixed factor before the
policy's and value's layers, so their weights start on the scale the task needs. The factors are
saved with the policy (a buffer of the module), so a policy file carries them.

:class:`ScaledObservationPolicy` is PPO's ``MlpPolicy`` with that extractor in front
(:class:`ScaledObservationLstmPolicy` RecurrentPPO's ``MlpLstmPolicy``), named in an
agent config as ``policy: ship_env.rl.features.ScaledObservationPolicy`` with the factors in
``policy_kwargs: "dict(features_extractor_kwargs=dict(scales=[50, 5, 1, 1, 1]))"`` (rl-zoo3
evaluates ``policy_kwargs`` without this package in scope, so the class is named by ``policy``).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import torch
from gymnasium import spaces
from sb3_contrib.common.recurrent.policies import RecurrentActorCriticPolicy
from stable_baselines3.common.policies import ActorCriticPolicy
from stable_baselines3.common.torch_layers import BaseFeaturesExtractor


class ScaledObservation(BaseFeaturesExtractor):
    """Features = observation * scales, element by element.

    Args:
        observation_space: a flat ``Box``.
        scales: one factor per observation element.
    """

    scales: torch.Tensor  # a buffer: moves with the module between devices, saved with it

    def __init__(self, observation_space: spaces.Box, scales: Sequence[float]) -> None:
        size = int(observation_space.shape[0])
        if len(observation_space.shape) != 1 or len(scales) != size:
            raise ValueError(
                f"scales: expected {size} factors for observations of shape {observation_space.shape}, "
                f"got {list(scales)}"
            )
        super().__init__(observation_space, features_dim=size)
        self.register_buffer("scales", torch.as_tensor(scales, dtype=torch.float32))

    def forward(self, observations: torch.Tensor) -> torch.Tensor:
        return observations * self.scales


class ScaledObservationPolicy(ActorCriticPolicy):
    """PPO's (and A2C's) ``MlpPolicy`` whose features extractor is :class:`ScaledObservation`
    (``features_extractor_kwargs={"scales": [...]}`` gives the factors)."""

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        kwargs.setdefault("features_extractor_class", ScaledObservation)
        super().__init__(*args, **kwargs)


class ScaledObservationLstmPolicy(RecurrentActorCriticPolicy):
    """sb3-contrib's ``MlpLstmPolicy`` (RecurrentPPO, ``--algo ppo_lstm``) whose features extractor is
    :class:`ScaledObservation`: the scaled observation feeds the LSTMs of the policy and the value."""

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        kwargs.setdefault("features_extractor_class", ScaledObservation)
        super().__init__(*args, **kwargs)
