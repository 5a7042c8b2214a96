"""One training run: an agent config, the native vector environment, ``model.zip`` and its metadata.

The environment is ``gymnasium.make_vec(env_id, num_envs=n_envs, vectorization_mode=
"vector_entry_point")``, all ships stepped in one simulator call, presented to stable-baselines3
by :class:`~ship_env.envs.sb3_adapter.SB3VecEnvAdapter` (design notes 9: SB3's own ``VecEnv``
API). Torch runs with :data:`~ship_env.rl.agents.DEFAULT_TORCH_THREADS` intra-op threads unless
told otherwise. With the same seed, thread count and package versions a run repeats exactly. A run
may continue a saved agent (``trained_agent``: rl-zoo3's ``--trained-agent``) instead of starting
from new weights.
"""

from __future__ import annotations

import hashlib
import importlib.util
import time
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import gymnasium as gym
import torch
from stable_baselines3.common.base_class import BaseAlgorithm
from stable_baselines3.common.callbacks import BaseCallback
from stable_baselines3.common.vec_env import VecEnv, VecMonitor, VecNormalize

import ship_env  # noqa: F401  (registers the environments)
from ship_env.envs.sb3_adapter import SB3VecEnvAdapter
from ship_env.rl.agents import DEFAULT_TORCH_THREADS, AgentConfig
from ship_env.rl.metadata import MODEL_FILE, PolicyMetadata
from ship_env.rl.policy_file import PolicyFile, PolicyFileError, read_policy_file

#: The folder under a run's output that holds its TensorBoard logs (when tensorboard is installed).
TENSORBOARD_FOLDER = "tensorboard"


def make_training_env(config: AgentConfig) -> VecEnv:
    """The vector environment of ``config`` as an SB3 ``VecEnv`` recording episode returns (the
    environment's own), normalised as the config asks.

    Without ``env_wrapper`` it is the native vector environment (all ships in one simulator call);
    with wrappers, Gymnasium's synchronous vector environment of wrapped single environments.
    """
    if config.env_wrappers:
        vector_env = gym.make_vec(
            config.env_id,
            num_envs=config.n_envs,
            vectorization_mode="sync",
            wrappers=list(config.env_wrappers),
            **config.env_kwargs,
        )
    else:
        vector_env = gym.make_vec(
            config.env_id, num_envs=config.n_envs, vectorization_mode="vector_entry_point", **config.env_kwargs
        )
    env = VecMonitor(SB3VecEnvAdapter(vector_env))
    return env if config.normalize is None else VecNormalize(env, **config.normalize)


def tensorboard_installed() -> bool:
    """Whether SB3 can write TensorBoard logs here."""
    return importlib.util.find_spec("tensorboard") is not None


def continue_agent(config: AgentConfig, saved: PolicyFile, env: VecEnv, **run_keywords: Any) -> BaseAlgorithm:
    """The saved agent, ready to train on ``env`` with ``config``'s hyper-parameters, as rl-zoo3's
    ``--trained-agent`` continues one: its weights and optimiser state are the saved agent's, every
    other keyword the config's (``run_keywords``: the run's seed, device, log folder).

    Where the config's policy class and ``policy_kwargs`` are the saved agent's, the agent is
    loaded as it was saved; where they are others (say the same network behind
    :class:`~ship_env.rl.features.MirroredObservationPolicy`), the config's policy is built and
    given the saved weights (:func:`load_weights`). :class:`~ship_env.rl.policy_file.PolicyFileError`
    naming the file if it was trained with another algorithm, on another environment, with other
    spaces, or with a network whose weights do not fit the config's policy.
    """
    if saved.metadata is not None and saved.metadata.algo != config.algo:
        raise PolicyFileError(f"policy file {saved.path}: trained with {saved.metadata.algo}, not {config.algo}")
    saved.check(config.env_id, env.observation_space, env.action_space)
    policy_kwargs = config.hyperparameters.get("policy_kwargs") or {}
    if _policy_class(config) is saved.policy_class and policy_kwargs == saved.policy_kwargs:
        hyperparameters = {key: value for key, value in config.hyperparameters.items() if key != "policy_kwargs"}
        return config.algorithm.load(
            saved.path, env=env, custom_objects=hyperparameters, **run_keywords, **hyperparameters
        )
    model = config.algorithm(config.policy, env, **run_keywords, **config.hyperparameters)
    load_weights(model, saved)
    return model


def _policy_class(config: AgentConfig) -> type:
    """The policy class a config names (an alias such as ``MlpPolicy`` resolved by its algorithm)."""
    if isinstance(config.policy, type):
        return config.policy
    return config.algorithm.policy_aliases.get(config.policy, type(None))


def load_weights(model: BaseAlgorithm, saved: PolicyFile) -> None:
    """Give ``model``'s policy the saved agent's weights and optimiser state.

    The weights must fit exactly: every saved tensor is one of the policy's, of the same shape, and
    every trained parameter of the policy is saved. The policy's fixed buffers that the saved agent
    lacks stay as its ``policy_kwargs`` made them (the mirror's element signs); one it has too must
    hold the same values (the observation scales). :class:`~ship_env.rl.policy_file.PolicyFileError`
    naming both classes and the first tensor that does not fit.
    """
    policy = model.policy
    reason = weights_mismatch(policy, saved.weights)
    if reason is not None:
        raise PolicyFileError(
            f"policy file {saved.path}: its {saved.policy_class.__name__}'s weights do not fit the config's "
            f"{type(policy).__name__}: {reason}"
        )
    policy.load_state_dict(saved.weights, strict=False)
    if saved.optimizer_state is not None:
        policy.optimizer.load_state_dict(saved.optimizer_state)


def weights_mismatch(policy: torch.nn.Module, weights: Mapping[str, torch.Tensor]) -> str | None:
    """Why ``weights`` (a saved state dict) do not fit ``policy`` (:func:`load_weights`), or ``None``."""
    own = policy.state_dict()
    parameters = dict(policy.named_parameters())
    for key, saved in weights.items():
        if key not in own:
            return f"{key} is not one of its tensors"
        if own[key].shape != saved.shape:
            return f"{key} has shape {tuple(saved.shape)}, not {tuple(own[key].shape)}"
        if key not in parameters and not torch.equal(own[key], saved):
            return f"{key} (fixed by policy_kwargs) holds other values"
    missing = [key for key in parameters if key not in weights]
    return None if not missing else f"{missing[0]} is not saved"


def starting_agent(saved: PolicyFile) -> dict[str, Any]:
    """What a continued run records of the agent it started from: its ``model.zip``'s path and
    SHA-256, and the command that trained it (``None`` without its metadata)."""
    return {
        "path": str(saved.path),
        "sha256": hashlib.sha256(saved.path.read_bytes()).hexdigest(),
        "command": None if saved.metadata is None else saved.metadata.command,
    }


@dataclass(frozen=True)
class TrainingRun:
    """A finished run: the trained model and what was written.

    Attributes:
        model: the trained algorithm (its ``policy`` steers).
        model_path: ``<out>/model.zip``.
        metadata: what ``<out>/metadata.json`` holds.
    """

    model: BaseAlgorithm
    model_path: Path
    metadata: PolicyMetadata


def train(
    config: AgentConfig,
    out: Path,
    command: str,
    *,
    steps: int | None = None,
    seed: int = 0,
    torch_threads: int = DEFAULT_TORCH_THREADS,
    progress_bar: bool = True,
    callback: BaseCallback | None = None,
    trained_agent: Path | None = None,
) -> TrainingRun:
    """Train ``config``'s algorithm on its environment and save model and metadata into ``out``.

    Args:
        config: the algorithm, environment and hyper-parameters.
        out: the run's folder (created).
        command: the command line that reproduces the run, recorded in the metadata.
        steps: environment steps to train (default ``config.n_timesteps``).
        seed: seeds torch, numpy and the environments (sub-environment i with ``seed + i``).
        torch_threads: torch's intra-op threads.
        progress_bar: show SB3's progress bar (tqdm and rich).
        callback: an SB3 callback (it may stop the run early by returning False), run after the
            config's own (``callback``).
        trained_agent: continue training the agent saved there (a ``model.zip`` or its run's
            folder: :func:`continue_agent`) instead of new weights; the metadata records it
            (:func:`starting_agent`). It is read, and loaded, as stable-baselines3 loads an agent,
            which unpickles the zip's entries and so runs any code they carry: one's own agents only.
    """
    steps = config.n_timesteps if steps is None else steps
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    torch.set_num_threads(torch_threads)
    env = make_training_env(config)
    run_keywords: dict[str, Any] = {
        "seed": seed,
        "device": "cpu",
        "tensorboard_log": str(out / TENSORBOARD_FOLDER) if tensorboard_installed() else None,
    }
    saved = None if trained_agent is None else read_policy_file(trained_agent, trust_policy_code=True)
    if saved is None:
        model = config.algorithm(config.policy, env, **run_keywords, **config.hyperparameters)
    else:
        try:
            model = continue_agent(config, saved, env, **run_keywords)
        except PolicyFileError:
            env.close()
            raise
    callbacks = [make() for make in config.callbacks] + ([] if callback is None else [callback])
    start = time.perf_counter()
    try:
        model.learn(total_timesteps=steps, callback=callbacks, progress_bar=progress_bar)
    finally:
        env.close()
    wall_time = time.perf_counter() - start
    model_path = out / MODEL_FILE
    model.save(model_path)
    metadata = PolicyMetadata.of_run(
        config,
        seed=seed,
        steps=steps,
        timesteps=int(model.num_timesteps),
        wall_time_s=wall_time,
        torch_threads=torch_threads,
        command=command,
        trained_agent=None if saved is None else starting_agent(saved),
    )
    metadata.write(out)
    return TrainingRun(model, model_path, metadata)
