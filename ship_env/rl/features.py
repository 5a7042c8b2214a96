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

:class:`MirroredObservationPolicy` adds the task's port/starboard symmetry: a course change to
port is the mirror image of one to starboard, so the policy maps each observation onto the
starboard side (the signs of the mirrored elements flipped when the turn-direction element is
negative), acts there, and mirrors its action back. Both sides then share one network and every
episode trains it; an unconstrained network learns the two sides apart, and unequally.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import torch
from gymnasium import spaces
from sb3_contrib.common.recurrent.policies import RecurrentActorCriticPolicy
from stable_baselines3.common.distributions import DiagGaussianDistribution, Distribution
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


class MirroredObservationPolicy(ScaledObservationPolicy):
    """:class:`ScaledObservationPolicy` made mirror-symmetric: pi(-a | M o) = pi(a | o), V(M o) = V(o).

    M flips the sign of the ``mirrored`` observation elements; an observation whose
    ``mirror_sign`` element is negative (a turn to port) is mirrored before the networks see it,
    and the actions for it are mirrored (a continuous action's sign flipped), so the networks only
    ever see the starboard side. The course change's: ``mirror_sign=4`` (the turn direction),
    ``mirrored`` the heading errors, rates of turn, rudders and the turn direction.

    Args:
        mirror_sign: the observation element whose sign says which side an observation is on.
        mirrored: the observation elements that change sign in the mirror image (it among them).
        *args, **kwargs: :class:`ScaledObservationPolicy`'s.
    """

    unmirrored: torch.Tensor  # a buffer: 1 for the elements that keep their sign, 0 for the mirrored ones

    def __init__(self, *args: Any, mirror_sign: int, mirrored: Sequence[int], **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        size = spaces.flatdim(self.observation_space)
        if not 0 <= mirror_sign < size or mirror_sign not in mirrored:
            raise ValueError(
                f"mirror_sign: expected one of the mirrored elements {list(mirrored)}, got {mirror_sign!r}"
            )
        if not all(0 <= element < size for element in mirrored):
            raise ValueError(f"mirrored: expected elements of an observation of size {size}, got {list(mirrored)}")
        if not isinstance(self.action_space, spaces.Box):
            raise ValueError(f"action_space: expected a Box (a continuous action), got {self.action_space}")
        unmirrored = torch.ones(size)
        unmirrored[list(mirrored)] = 0.0
        self.register_buffer("unmirrored", unmirrored)
        self.mirror_sign = mirror_sign
        self.mirrored = tuple(mirrored)

    def _get_constructor_parameters(self) -> dict[str, Any]:
        return {**super()._get_constructor_parameters(), "mirror_sign": self.mirror_sign, "mirrored": self.mirrored}

    def _starboard(self, obs: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor]:
        """The observations seen from starboard and each one's side (+1 starboard, -1 port), shape (N, 1)."""
        side = torch.where(obs[:, self.mirror_sign : self.mirror_sign + 1] < 0.0, -1.0, 1.0)
        return obs * (self.unmirrored + (1.0 - self.unmirrored) * side), side

    def forward(
        self, obs: torch.Tensor, deterministic: bool = False
    ) -> tuple[torch.Tensor, torch.Tensor, torch.Tensor]:
        seen, side = self._starboard(obs)
        actions, values, log_prob = super().forward(seen, deterministic)
        return actions * side, values, log_prob

    def evaluate_actions(
        self, obs: Any, actions: torch.Tensor
    ) -> tuple[torch.Tensor, torch.Tensor, torch.Tensor | None]:
        seen, side = self._starboard(obs)
        return super().evaluate_actions(seen, actions * side)

    def get_distribution(self, obs: Any) -> Distribution:
        seen, side = self._starboard(obs)
        distribution = super().get_distribution(seen)
        assert isinstance(distribution, DiagGaussianDistribution)  # a Box action without gSDE
        gaussian = distribution.distribution
        distribution.distribution = torch.distributions.Normal(gaussian.mean * side, gaussian.stddev)
        return distribution

    def predict_values(self, obs: Any) -> torch.Tensor:
        return super().predict_values(self._starboard(obs)[0])


class ScaledObservationLstmPolicy(RecurrentActorCriticPolicy):
    """sb3-contrib's ``MlpLstmPolicy`` (RecurrentPPO, ``--algo ppo_lstm``) whose features extractor is
    :class:`ScaledObservation`: the scaled observation feeds the LSTMs of the policy and the value."""

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        kwargs.setdefault("features_extractor_class", ScaledObservation)
        super().__init__(*args, **kwargs)
