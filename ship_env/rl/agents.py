"""Agent hyper-parameters: ``configs/agents/<algo>.yaml``, one entry per environment id, in rl-zoo3's format.

The files load unchanged in rl-zoo3 (``python -m rl_zoo3.train --algo ppo --env
ship_env/CourseChange-v0 --gym-packages ship_env -conf ship_env/configs/agents/ppo.yaml``), and
``ship-env train`` reads the same keys the same way::

    ship_env/CourseChange-v0:
      n_envs: 16                     # sub-environments stepped together
      n_timesteps: 1500000           # default length of a run (``--steps`` overrides it)
      policy: ship_env.rl.features.ScaledObservationPolicy   # an SB3 alias or a dotted class path
      env_kwargs: {disturbance: random, rudder_travel_weight: 0.3}
      normalize: "{'norm_obs': False, 'norm_reward': True}"  # VecNormalize's keywords (gamma: the entry's)
      env_wrapper: gymnasium.wrappers.ClipReward              # optional: class path, or [{path: kwargs}, ...]
      callback: stable_baselines3.common.callbacks.StopTrainingOnMaxEpisodes  # optional, likewise
      learning_rate: lin_0.0003     # a number, or rl-zoo3's linear schedule lin_<start>
      n_steps: 600                   # ... any keyword of the stable-baselines3 algorithm
      policy_kwargs: "dict(net_arch=[64, 64], activation_fn=nn.Tanh, features_extractor_kwargs=dict(scales=[50, 5]))"

As in rl-zoo3, ``normalize``, ``policy_kwargs``, ``replay_buffer_class`` and
``replay_buffer_kwargs`` given as strings are Python expressions, evaluated here with only
``dict``, ``nn`` (``torch.nn``) and ``th`` (``torch``) in scope (the names rl-zoo3 offers its
configs); a mapping is taken as it is. The rl-zoo3 keys ``ship-env train`` does not support
(:data:`UNSUPPORTED_KEYS`), observation normalisation (the saved policy must steer without the
statistics) and keywords the algorithm does not take are refused with the key named.
"""

from __future__ import annotations

import importlib
import inspect
import os
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field, replace
from functools import partial
from pathlib import Path
from typing import TYPE_CHECKING, Any

import yaml

from ship_env.extras import require
from ship_env.paths import config_dir

if TYPE_CHECKING:
    import gymnasium as gym
    from stable_baselines3.common.base_class import BaseAlgorithm
    from stable_baselines3.common.callbacks import BaseCallback

#: The algorithms ``ship-env train`` offers: ``--algo`` name (rl-zoo3's) -> the stable-baselines3 class
#: name, or the sb3-contrib one (:data:`CONTRIB_ALGORITHMS`).
ALGORITHMS: dict[str, str] = {"ppo": "PPO", "sac": "SAC", "ppo_lstm": "RecurrentPPO"}
#: The ``--algo`` names whose class is sb3-contrib's: PPO with an LSTM in its policy and value networks.
CONTRIB_ALGORITHMS = frozenset({"ppo_lstm"})
#: Torch's intra-op threads during training unless told otherwise: on the 2-core machines this
#: project targets, 2 threads collapse under other load (design notes 9).
DEFAULT_TORCH_THREADS = 1
#: The variable that sets torch's intra-op threads where the user chose them (torch reads it too).
TORCH_THREADS_VARIABLE = "OMP_NUM_THREADS"
#: rl-zoo3's keys that set up the run rather than the algorithm.
SETUP_KEYS = ("n_envs", "n_timesteps", "policy", "env_kwargs", "normalize", "env_wrapper", "callback")
#: rl-zoo3's keys that ``ship-env train`` does not support.
UNSUPPORTED_KEYS = ("frame_stack", "vec_env_wrapper", "monitor_kwargs", "noise_type", "noise_std")
#: The algorithm's keywords that rl-zoo3 evaluates when they are strings.
EVALUATED_KEYWORDS = ("policy_kwargs", "replay_buffer_class", "replay_buffer_kwargs")
#: The algorithm's keywords that rl-zoo3 reads as a schedule: a number, or ``lin_<start>``.
SCHEDULE_KEYWORDS = ("learning_rate", "clip_range", "clip_range_vf")
#: The algorithm's keywords that the run sets itself, not the config.
RUN_KEYWORDS = frozenset({"self", "policy", "env", "seed", "device", "tensorboard_log", "verbose"})


@dataclass(frozen=True)
class AgentConfig:
    """How to train one algorithm on one environment.

    Attributes:
        algo: the algorithm's name (a key of :data:`ALGORITHMS`).
        env_id: the Gymnasium id trained on.
        entry: the YAML entry as written (recorded in the run's metadata).
        n_envs: the number of sub-environments stepped together.
        n_timesteps: the run's default length in environment steps (all sub-environments together).
        policy: the stable-baselines3 policy: an alias (``MlpPolicy``) or a class.
        env_kwargs: the environment's keyword arguments (the task's options and reward weights).
        normalize: ``VecNormalize``'s keyword arguments (rewards divided by a running estimate of
            the discounted return's spread), ``None`` for no normalisation.
        env_wrappers: the wrappers around each sub-environment, innermost first.
        callbacks: makers of the SB3 callbacks of a run (each called once per run).
        hyperparameters: the algorithm's other keyword arguments, parsed.
        source: the YAML file the entry was read from.
    """

    algo: str
    env_id: str
    entry: Mapping[str, Any]
    n_envs: int
    n_timesteps: int
    policy: str | type = "MlpPolicy"
    env_kwargs: Mapping[str, Any] = field(default_factory=dict)
    normalize: Mapping[str, Any] | None = None
    env_wrappers: tuple[Callable[[gym.Env], gym.Wrapper], ...] = ()
    callbacks: tuple[Callable[[], BaseCallback], ...] = ()
    hyperparameters: Mapping[str, Any] = field(default_factory=dict)
    source: Path | None = None

    @property
    def algorithm(self) -> type[BaseAlgorithm]:
        """The stable-baselines3 class."""
        return algorithm_class(self.algo)

    def on_ship(self, ship: str) -> AgentConfig:
        """This config sailing ``ship`` (a preset name or a ship YAML path): its ``env_kwargs``' ``ship`` replaced."""
        return replace(self, env_kwargs={**self.env_kwargs, "ship": ship})

    def with_ship_variation(self, ship_variation: str) -> AgentConfig:
        """This config with its ``env_kwargs``' ``ship_variation`` replaced (``"fitted"``: ships drawn from
        a fitted preset's standard errors, :mod:`ship_env.envs.variation`)."""
        return replace(self, env_kwargs={**self.env_kwargs, "ship_variation": ship_variation})


def evaluation_torch_threads() -> int:
    """Torch's intra-op threads to sail learned policies on: :data:`TORCH_THREADS_VARIABLE`'s value where
    the user set it to a positive whole number, else :data:`DEFAULT_TORCH_THREADS`."""
    text = os.environ.get(TORCH_THREADS_VARIABLE, "").strip()
    return int(text) if text.isdigit() and int(text) > 0 else DEFAULT_TORCH_THREADS


def algorithm_class(algo: str) -> type[BaseAlgorithm]:
    """The stable-baselines3 (or sb3-contrib) class of an ``--algo`` name (imported on first use: it
    brings torch)."""
    if algo in CONTRIB_ALGORITHMS:
        require("rl", f"--algo {algo}", "sb3_contrib")
        import sb3_contrib

        return getattr(sb3_contrib, ALGORITHMS[algo])
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


def _evaluated(where: str, value: object) -> object:
    """A string evaluated as rl-zoo3 does (``dict``, ``nn`` and ``th`` in scope); other values as they are."""
    if not isinstance(value, str):
        return value
    import torch

    try:
        return eval(value, {"__builtins__": {"dict": dict}, "nn": torch.nn, "th": torch})  # noqa: S307
    except Exception as error:
        raise ValueError(f"{where}: cannot evaluate {value!r}: {error}") from None


def _classes_with_kwargs(where: str, value: object) -> list[tuple[type, dict[str, Any]]]:
    """rl-zoo3's ``env_wrapper`` / ``callback`` value: a class path, or a list of paths or ``{path: kwargs}``."""
    found = []
    for item in value if isinstance(value, list) else [value]:
        if isinstance(item, Mapping) and len(item) == 1:
            ((name, kwargs),) = item.items()
        else:
            name, kwargs = item, {}
        if not isinstance(kwargs, Mapping):
            raise ValueError(f"{where}.{name}: expected keyword arguments as a mapping, got {kwargs!r}")
        found.append((_import_class(where, name), dict(kwargs)))
    return found


def _schedule(where: str, value: object) -> object:
    """rl-zoo3's schedules: ``lin_<start>`` falls linearly to 0 over the run; a number stays as it is."""
    if not isinstance(value, str):
        return value
    kind, _, start = value.partition("_")
    try:
        initial = float(start)
    except ValueError:
        initial = None
    if kind != "lin" or initial is None:
        raise ValueError(f"{where}: expected a number or a linear schedule such as 'lin_0.0003', got {value!r}")
    from stable_baselines3.common.utils import LinearSchedule

    return LinearSchedule(initial, 0.0, 1.0)


def _whole_number(where: str, value: object, minimum: int) -> int:
    if isinstance(value, bool) or not isinstance(value, int) or value < minimum:
        raise ValueError(f"{where}: expected a whole number >= {minimum}, got {value!r}")
    return value


def _normalize(where: str, value: object, gamma: object) -> dict[str, Any] | None:
    """rl-zoo3's ``normalize``: false, true (observations and rewards) or VecNormalize's keywords."""
    if value is False:
        return None
    kwargs = {} if value is True else _evaluated(where, value)
    if not isinstance(kwargs, Mapping):
        raise ValueError(f"{where}: expected true, false or VecNormalize's keywords, got {value!r}")
    kwargs = dict(kwargs)
    if kwargs.get("norm_obs", True):
        raise ValueError(
            f"{where}: observation normalisation (norm_obs) is not supported: a saved policy must steer "
            "without the running statistics; scale the observations in the network "
            "(ship_env.rl.features.ScaledObservationPolicy) and normalise rewards only: "
            "\"{'norm_obs': False, 'norm_reward': True}\""
        )
    if gamma is not None:
        kwargs["gamma"] = gamma  # as rl-zoo3: the algorithm's discount
    return kwargs


def load_agent_config(algo: str, env_id: str, path: Path | None = None) -> AgentConfig:
    """The entry for ``env_id`` in ``path`` (default ``configs/agents/<algo>.yaml``).

    ``ValueError`` names the file and what is wrong: an unknown algorithm, no entry for the
    environment (listing the ones there are), a malformed or unsupported key, or a keyword the
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
    written = dict(document[env_id] or {})
    where = f"{path}: {env_id}"
    unsupported = [key for key in UNSUPPORTED_KEYS if key in written]
    if unsupported:
        raise ValueError(f"{where}: rl-zoo3's key {unsupported[0]!r} is not supported by ship-env train")
    setup = {key: written[key] for key in SETUP_KEYS if key in written}
    hyperparameters = {key: value for key, value in written.items() if key not in SETUP_KEYS}
    accepted = set(inspect.signature(algorithm_class(algo).__init__).parameters) - RUN_KEYWORDS
    unknown = sorted(set(hyperparameters) - accepted)
    if unknown:
        raise ValueError(
            f"{where}: {ALGORITHMS[algo]} takes no keyword {', '.join(map(repr, unknown))} "
            f"(nor is it a setup key: {', '.join(SETUP_KEYS)})"
        )
    for key in EVALUATED_KEYWORDS:
        if key in hyperparameters:
            hyperparameters[key] = _evaluated(f"{where}.{key}", hyperparameters[key])
    for key in SCHEDULE_KEYWORDS:
        if key in hyperparameters:
            hyperparameters[key] = _schedule(f"{where}.{key}", hyperparameters[key])
    env_kwargs = setup.get("env_kwargs") or {}
    if not isinstance(env_kwargs, Mapping):
        raise ValueError(f"{where}.env_kwargs: expected a mapping, got {env_kwargs!r}")
    policy = setup.get("policy", "MlpPolicy")
    if not isinstance(policy, str):
        raise ValueError(f"{where}.policy: expected a policy name such as 'MlpPolicy', got {policy!r}")
    wrappers = _classes_with_kwargs(f"{where}.env_wrapper", setup["env_wrapper"]) if "env_wrapper" in setup else []
    callbacks = _classes_with_kwargs(f"{where}.callback", setup["callback"]) if "callback" in setup else []
    return AgentConfig(
        algo=algo,
        env_id=env_id,
        entry=written,
        n_envs=_whole_number(f"{where}.n_envs", setup.get("n_envs", 1), 1),
        n_timesteps=_whole_number(f"{where}.n_timesteps", setup.get("n_timesteps", 100_000), 1),
        policy=_import_class(f"{where}.policy", policy) if "." in policy else policy,
        env_kwargs=dict(env_kwargs),
        normalize=_normalize(f"{where}.normalize", setup.get("normalize", False), hyperparameters.get("gamma")),
        env_wrappers=tuple(partial(wrapper, **kwargs) for wrapper, kwargs in wrappers),
        callbacks=tuple(partial(callback, **kwargs) for callback, kwargs in callbacks),
        hyperparameters=hyperparameters,
        source=path,
    )
