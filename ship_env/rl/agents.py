"""Agent hyper-parameters: ``configs/agents/<algo>.yaml``, one entry per environment id (rl-zoo3's layout).

Each entry holds the training set-up, read here, and the algorithm's keyword arguments, passed
to its constructor as they are::

    ship_env/CourseChange-v0:
      n_envs: 16                     # sub-environments of the native vector environment
      n_timesteps: 1500000           # default length of a run (``--steps`` overrides it)
      policy: MlpPolicy
      env_kwargs: {disturbance: random, rudder_travel_weight: 0.3}
      normalize_reward: true         # scale rewards by a running estimate of the return's spread
      n_steps: 600                   # ... any keyword of stable_baselines3.PPO
      policy_kwargs:
        net_arch: [64, 64]
        activation_fn: torch.nn.Tanh
        features_extractor_class: ship_env.rl.features.ScaledObservation
        features_extractor_kwargs: {scales: [50, 5, 1, 1, 1]}

Unlike rl-zoo3, ``policy_kwargs`` is a YAML mapping, never Python source to evaluate; the
classes it names (:data:`CLASS_KEYWORDS`) are given by their dotted import paths.
"""

from __future__ import annotations

import importlib
import inspect
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import yaml

from ship_env.paths import config_dir

if TYPE_CHECKING:
    from stable_baselines3.common.base_class import BaseAlgorithm

#: The algorithms ``ship-env train`` offers: ``--algo`` name -> stable-baselines3 class name.
ALGORITHMS: dict[str, str] = {"ppo": "PPO", "sac": "SAC"}
#: Torch's intra-op threads during training unless told otherwise: on the 2-core machines this
#: project targets, 2 threads collapse under other load (design notes 9).
DEFAULT_TORCH_THREADS = 1
#: The ``policy_kwargs`` that name a class, given in the YAML by its dotted import path.
CLASS_KEYWORDS = ("activation_fn", "features_extractor_class", "optimizer_class")
#: The algorithm's keywords that the run sets itself, not the config.
RUN_KEYWORDS = frozenset({"self", "policy", "env", "seed", "device", "tensorboard_log", "verbose"})


@dataclass(frozen=True)
class AgentConfig:
    """How to train one algorithm on one environment.

    Attributes:
        algo: the algorithm's name (a key of :data:`ALGORITHMS`).
        env_id: the Gymnasium id trained on.
        n_envs: the number of sub-environments stepped together.
        n_timesteps: the run's default length in environment steps (all sub-environments together).
        policy: the stable-baselines3 policy name (``MlpPolicy``).
        env_kwargs: the environment's keyword arguments (the task's options and reward weights).
        normalize_reward: train on rewards divided by a running estimate of the discounted
            return's standard deviation (SB3's ``VecNormalize(norm_obs=False)``). The
            observations stay as they are, so the saved policy needs no statistics to steer.
        hyperparameters: the algorithm's other keyword arguments.
        source: the YAML file the entry was read from.
    """

    algo: str
    env_id: str
    n_envs: int
    n_timesteps: int
    policy: str
    env_kwargs: Mapping[str, Any] = field(default_factory=dict)
    normalize_reward: bool = False
    hyperparameters: Mapping[str, Any] = field(default_factory=dict)
    source: Path | None = None

    @property
    def algorithm(self) -> type[BaseAlgorithm]:
        """The stable-baselines3 class."""
        return algorithm_class(self.algo)

    def entry(self) -> dict[str, Any]:
        """The YAML entry (setup keys and hyper-parameters, classes as their dotted paths), for the run's metadata."""
        hyperparameters = dict(self.hyperparameters)
        if "policy_kwargs" in hyperparameters:
            hyperparameters["policy_kwargs"] = {
                key: f"{value.__module__}.{value.__qualname__}" if key in CLASS_KEYWORDS else value
                for key, value in hyperparameters["policy_kwargs"].items()
            }
        return {
            "n_envs": self.n_envs,
            "n_timesteps": self.n_timesteps,
            "policy": self.policy,
            "env_kwargs": dict(self.env_kwargs),
            "normalize_reward": self.normalize_reward,
            **hyperparameters,
        }


def algorithm_class(algo: str) -> type[BaseAlgorithm]:
    """The stable-baselines3 class of an ``--algo`` name (imported on first use: it brings torch)."""
    import stable_baselines3

    return getattr(stable_baselines3, ALGORITHMS[algo])


def agents_file(algo: str) -> Path:
    """``configs/agents/<algo>.yaml``."""
    return config_dir() / "agents" / f"{algo}.yaml"


def _import_class(where: str, dotted: object) -> type:
    """The class at a dotted import path (``torch.nn.ReLU``); ``ValueError`` naming ``where`` if there is none."""
    module_name, _, name = str(dotted).rpartition(".")
    try:
        found = getattr(importlib.import_module(module_name), name)
    except (ImportError, AttributeError, ValueError):
        found = None
    if not isinstance(found, type):
        raise ValueError(f"{where}: expected a class as a dotted import path such as torch.nn.ReLU, got {dotted!r}")
    return found


def _whole_number(where: str, value: object, minimum: int) -> int:
    if isinstance(value, bool) or not isinstance(value, int) or value < minimum:
        raise ValueError(f"{where}: expected a whole number >= {minimum}, got {value!r}")
    return value


def load_agent_config(algo: str, env_id: str, path: Path | None = None) -> AgentConfig:
    """The entry for ``env_id`` in ``path`` (default ``configs/agents/<algo>.yaml``).

    ``ValueError`` names the file and what is wrong: an unknown algorithm, no entry for the
    environment (listing the ones there are), a malformed setup key, or a keyword the
    algorithm does not take.
    """
    if algo not in ALGORITHMS:
        raise ValueError(f"algo: expected one of {', '.join(ALGORITHMS)}, got {algo!r}")
    path = agents_file(algo) if path is None else Path(path)
    if not path.is_file():
        raise ValueError(f"{path}: no such agent config")
    with path.open() as handle:
        document = yaml.safe_load(handle) or {}
    if not isinstance(document, Mapping):
        raise ValueError(f"{path}: expected a mapping of environment ids to hyper-parameters")
    if env_id not in document:
        raise ValueError(f"{path}: no entry for {env_id!r}; entries: {', '.join(map(str, document)) or 'none'}")
    entry = dict(document[env_id] or {})
    where = f"{path}: {env_id}"
    env_kwargs = entry.pop("env_kwargs", None) or {}
    if not isinstance(env_kwargs, Mapping):
        raise ValueError(f"{where}.env_kwargs: expected a mapping, got {env_kwargs!r}")
    policy = entry.pop("policy", "MlpPolicy")
    if not isinstance(policy, str):
        raise ValueError(f"{where}.policy: expected a policy name such as 'MlpPolicy', got {policy!r}")
    normalize_reward = entry.pop("normalize_reward", False)
    if not isinstance(normalize_reward, bool):
        raise ValueError(f"{where}.normalize_reward: expected true or false, got {normalize_reward!r}")
    n_envs = _whole_number(f"{where}.n_envs", entry.pop("n_envs", 1), 1)
    n_timesteps = _whole_number(f"{where}.n_timesteps", entry.pop("n_timesteps", 100_000), 1)
    policy_kwargs = entry.get("policy_kwargs")
    if policy_kwargs is not None:
        if not isinstance(policy_kwargs, Mapping):
            raise ValueError(f"{where}.policy_kwargs: expected a mapping, got {policy_kwargs!r}")
        entry["policy_kwargs"] = {
            key: _import_class(f"{where}.policy_kwargs.{key}", value) if key in CLASS_KEYWORDS else value
            for key, value in policy_kwargs.items()
        }
    accepted = set(inspect.signature(algorithm_class(algo).__init__).parameters) - RUN_KEYWORDS
    unknown = sorted(set(entry) - accepted)
    if unknown:
        raise ValueError(f"{where}: {ALGORITHMS[algo]} takes no keyword {', '.join(map(repr, unknown))}")
    return AgentConfig(algo, env_id, n_envs, n_timesteps, policy, dict(env_kwargs), normalize_reward, entry, path)
