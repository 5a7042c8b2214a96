"""A saved stable-baselines3 policy, read and checked against the environment it is to steer.

A policy file is SB3's ``model.zip`` (any algorithm: PPO, SAC, A2C, TD3...), optionally with the
``metadata.json`` a training run writes beside it (:mod:`ship_env.rl.metadata`), which names the
environment it was trained on. Only the policy network is rebuilt (its class, keyword arguments
and weights from the zip), so a policy loads without knowing the algorithm that trained it.

A policy file is read without running any code it carries (:mod:`ship_env.rl.safe_zip`): its
spaces and keyword arguments from the zip's readable fields, its class from an allow-list, its
weights as tensors alone. SB3's own load unpickles the zip's entries, which runs whatever code they
hold; ``trust_policy_code=True`` (the leaderboard's ``--trust-policy-code``) reads a file that way,
for a file its reader trusts that the safe reading cannot take.

Everything that makes a file unusable raises :class:`PolicyFileError`, whose message names the
file and the mismatch: not an SB3 zip, not readable without running its code (what it lacks, and
the option), trained on another environment, or observation or action spaces that differ from the
environment's.
"""

from __future__ import annotations

import inspect
import zipfile
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import torch
from gymnasium import spaces
from stable_baselines3.common.policies import BasePolicy
from stable_baselines3.common.save_util import load_from_zip_file

from ship_env.rl.metadata import METADATA_FILE, MODEL_FILE, PolicyMetadata
from ship_env.rl.safe_zip import SavedPolicy, UnreadableEntry, read_saved_policy, read_state_dicts

#: Saved attributes a policy does not need; not unpickled by the trusted load (their closures may not load elsewhere).
_SKIPPED_ATTRIBUTES = ("learning_rate", "lr_schedule", "clip_range", "clip_range_vf", "exploration_schedule")
#: How to read a file the safe reading cannot take, and what doing so means.
TRUST_OPTION = (
    "--trust-policy-code (trust_policy_code=True in Python) reads it with stable-baselines3's unpickling, "
    "which runs any code the file carries: only for a file you trust"
)


class PolicyFileError(ValueError):
    """A policy file that cannot steer the environment asked for; the message names the file."""


def _no_learning_rate(_progress: float) -> float:
    return 0.0


@dataclass(frozen=True)
class PolicyFile:
    """A saved policy as read from disk (:func:`read_policy_file`).

    Attributes:
        path: the ``model.zip``.
        saved: its class, keyword arguments and spaces.
        metadata: the training run's ``metadata.json`` beside it, if there is one.
    """

    path: Path
    saved: SavedPolicy
    metadata: PolicyMetadata | None
    _parameters: dict[str, Any] = field(repr=False)

    @property
    def observation_space(self) -> spaces.Space:
        """The observation space the policy was trained with."""
        return self.saved.observation_space

    @property
    def action_space(self) -> spaces.Space:
        """The action space the policy was trained with."""
        return self.saved.action_space

    @property
    def env_id(self) -> str | None:
        """The environment trained on, from the metadata (``None`` without it)."""
        return None if self.metadata is None else self.metadata.env_id

    @property
    def algo(self) -> str:
        """The algorithm that trained it (``"PPO"``) from the metadata, or without it the policy's class name."""
        return self.metadata.algo.upper() if self.metadata is not None else self.policy_class.__name__

    @property
    def policy_class(self) -> type:
        """The saved policy's class."""
        return self.saved.policy_class

    @property
    def policy_kwargs(self) -> dict[str, Any]:
        """The keyword arguments the saved policy was built with (its config's ``policy_kwargs``)."""
        return dict(self.saved.policy_kwargs)

    @property
    def weights(self) -> dict[str, torch.Tensor]:
        """The policy's state dict: its trained parameters and fixed buffers."""
        return self._parameters["policy"]

    @property
    def optimizer_state(self) -> dict[str, Any] | None:
        """The optimiser's state dict as saved (``None`` if it was not)."""
        return self._parameters.get("policy.optimizer")

    def mismatch(self, env_id: str, observation_space: spaces.Space, action_space: spaces.Space) -> str | None:
        """Why the policy cannot steer ``env_id`` with these spaces, or ``None`` if it can."""
        if self.env_id is not None and self.env_id != env_id:
            return f"it was trained on {self.env_id}, not {env_id} (its {METADATA_FILE})"
        if self.observation_space != observation_space:
            return f"its observation space {self.observation_space} differs from {env_id}'s {observation_space}"
        if self.action_space != action_space:
            return f"its action space {self.action_space} differs from {env_id}'s {action_space}"
        return None

    def check(self, env_id: str, observation_space: spaces.Space, action_space: spaces.Space) -> None:
        """:class:`PolicyFileError` if the policy cannot steer ``env_id`` with these spaces."""
        reason = self.mismatch(env_id, observation_space, action_space)
        if reason is not None:
            raise PolicyFileError(f"policy file {self.path}: {reason}")

    def policy(self) -> BasePolicy:
        """The policy network with its trained weights, in evaluation mode, on the CPU."""
        policy_class = self.policy_class
        kwargs = self.policy_kwargs
        if "use_sde" in inspect.signature(policy_class).parameters:
            kwargs.setdefault("use_sde", self.saved.use_sde)
        try:
            policy = policy_class(self.observation_space, self.action_space, _no_learning_rate, **kwargs)
            policy.load_state_dict(self.weights)
        except (KeyError, RuntimeError, TypeError) as error:
            raise PolicyFileError(
                f"policy file {self.path}: cannot rebuild its {policy_class.__name__}: {error}"
            ) from None
        policy.set_training_mode(False)
        return policy


def model_path(path: str | Path) -> Path:
    """The ``model.zip`` a path names: the file itself, or ``model.zip`` in a run's folder."""
    path = Path(path)
    return path / MODEL_FILE if path.is_dir() else path


def seed_models(path: str | Path) -> list[Path]:
    """The ``model.zip`` files a path names, one per training seed: the file itself or a run's
    folder (one), or a folder of runs (``seed<S>/model.zip`` each, as ``ship-env train --seeds``
    writes them; seed2 before seed10)."""
    path = Path(path)
    if path.is_dir() and not (path / MODEL_FILE).exists():
        runs = sorted(
            (folder for folder in path.glob("seed*") if (folder / MODEL_FILE).is_file()),
            key=lambda folder: (len(folder.name), folder.name),
        )
        if runs:
            return [folder / MODEL_FILE for folder in runs]
    return [model_path(path)]


def _read_trusting(path: Path) -> tuple[SavedPolicy, dict[str, Any]]:
    """The policy as stable-baselines3 loads it: every pickled entry of ``data`` unpickled, running its code."""
    try:
        data, parameters, _ = load_from_zip_file(
            path, custom_objects=dict.fromkeys(_SKIPPED_ATTRIBUTES, None), device=torch.device("cpu")
        )
    except Exception as error:  # SB3 raises ValueError, zipfile and pickle errors alike
        raise PolicyFileError(f"policy file {path}: not a stable-baselines3 model: {error}") from None
    if not data or not isinstance(data.get("policy_class"), type) or "policy" not in parameters:
        raise PolicyFileError(f"policy file {path}: not a stable-baselines3 model: no policy class and weights")
    for name in ("observation_space", "action_space"):
        if not isinstance(data.get(name), spaces.Space):
            raise PolicyFileError(f"policy file {path}: its {name} is {data.get(name)!r}, not a gymnasium space")
    saved = SavedPolicy(
        policy_class=data["policy_class"],
        policy_kwargs=dict(data.get("policy_kwargs") or {}),
        observation_space=data["observation_space"],
        action_space=data["action_space"],
        use_sde=bool(data.get("use_sde", False)),
    )
    return saved, parameters


def _read_safely(path: Path) -> tuple[SavedPolicy, dict[str, Any]]:
    """The policy read without running any of its code (:mod:`ship_env.rl.safe_zip`)."""
    try:
        with zipfile.ZipFile(path) as archive:
            try:
                saved, parameters = read_saved_policy(archive), read_state_dicts(archive)
            except UnreadableEntry as error:
                raise PolicyFileError(
                    f"policy file {path}: cannot be read without running code it may carry: {error}; {TRUST_OPTION}"
                ) from None
    except zipfile.BadZipFile as error:
        raise PolicyFileError(f"policy file {path}: not a stable-baselines3 model: {error}") from None
    if "policy" not in parameters:
        raise PolicyFileError(f"policy file {path}: not a stable-baselines3 model: no policy.pth (its weights)")
    return saved, parameters


def read_policy_file(path: str | Path, trust_policy_code: bool = False) -> PolicyFile:
    """Read a policy file (or a training run's folder) and the metadata beside it.

    Without ``trust_policy_code`` nothing in the file is unpickled (:mod:`ship_env.rl.safe_zip`); with
    it, stable-baselines3 unpickles the zip's entries, which runs any code they carry.
    ``PolicyFileError`` if it is missing, not a stable-baselines3 zip, not readable without running
    its code (naming what it lacks), or its metadata is unreadable.
    """
    path = model_path(path)
    if not path.is_file():
        raise PolicyFileError(f"policy file {path}: no such file")
    saved, parameters = _read_trusting(path) if trust_policy_code else _read_safely(path)
    metadata_path = path.with_name(METADATA_FILE)
    try:
        metadata = PolicyMetadata.read(metadata_path) if metadata_path.is_file() else None
    except ValueError as error:
        raise PolicyFileError(f"policy file {path}: {error}") from None
    return PolicyFile(path, saved, metadata, parameters)
