"""Clone the predictor course changer into a TrackFollow-v0 policy network (behaviour cloning, DART noise).

The experiment of configs/agents/ppo_cloned_course_changer.yaml (its comments give the figures): can
the network that PPO trains on TrackFollow learn the wheel-over from the classic that holds it?

- **Demonstrations**: the predictor course changer (:func:`ship_env.baselines.presys.track_follow_controller`)
  sails ``--episodes`` episodes of the config's environment (``start="before_turn"``, every step, the
  course changer's own 1-s sample); in every other episode the rudder it orders is perturbed by
  DART noise (Laskey et al. 2017), an Ornstein-Uhlenbeck offset n of standard deviation ``--noise``
  (fraction of delta_max) and correlation time ``--correlation-time`` s,
  n_k = n_{k-1} (1 - T/tau) + sigma sqrt(2 T/tau) w_k, so that the ship leaves the course changer's
  own track and the records show how it steers back. Each record is the environment's observation
  and the course changer's order (not the perturbed rudder); its filters and its decisions read the
  ship as it sails, so the order is the course changer's own in that state.
- **Cloning**: the config's policy (its network and observation scales) with its action mean fitted
  to the orders by least squares, Adam in batches of 256, the learning rate 1e-3 (1 - epoch / epochs)
  + 1e-5 over ``--epochs``.
- The result is a ``model.zip`` with ``metadata.json``: the leaderboard ranks it
  (``ship-env leaderboard --policies``) and ``ship-env train --trained-agent`` fine-tunes it with PPO.

Episode seeds are ``1000 (seed + 1) + k``, far below the leaderboard's test suite's 10000..

Run:  python benchmarks/clone_course_changer.py --seed 0 --out runs/cloned/seed0
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from collections.abc import Callable
from pathlib import Path

import gymnasium as gym
import numpy as np
import torch
from stable_baselines3.common.policies import ActorCriticPolicy

from ship_env.baselines.controller import Controller
from ship_env.baselines.presys import track_follow_controller
from ship_env.rl.agents import DEFAULT_TORCH_THREADS, AgentConfig, load_agent_config
from ship_env.rl.metadata import MODEL_FILE, PolicyMetadata
from ship_env.rl.training import make_training_env

CONFIG = Path(__file__).resolve().parents[1] / "ship_env" / "configs" / "agents" / "ppo_cloned_course_changer.yaml"
ENV_ID = "ship_env/TrackFollow-v0"


def demonstrations(
    env: gym.Env,
    expert: Controller,
    episode_seeds: list[int],
    noise: float,
    correlation_time: float,
    rng: np.random.Generator,
) -> tuple[np.ndarray, np.ndarray]:
    """The observations and the expert's actions over the episodes ``episode_seeds``; every other
    episode (the second, fourth, ...) sails the expert's action plus the DART offset (module docstring),
    one step of the environment being the offset's sample time T (its ``decision_interval`` x ``dt``)."""
    step = env.unwrapped.task.dt * env.unwrapped.task.decision_interval
    decay = step / correlation_time
    observations, actions = [], []
    for k, seed in enumerate(episode_seeds):
        observation, info = env.reset(seed=seed)
        expert.reset(observation, info)
        sigma = noise if k % 2 else 0.0
        offset = 0.0
        done = False
        while not done:
            action = expert.act(observation, info)
            observations.append(observation.copy())
            actions.append(action.copy())
            offset += -offset * decay + sigma * math.sqrt(2.0 * decay) * float(rng.standard_normal())
            sailed = np.clip(action + offset, -1.0, 1.0).astype(np.float32)
            observation, _, terminated, truncated, info = env.step(sailed)
            done = terminated or truncated
    return np.asarray(observations, dtype=np.float32), np.asarray(actions, dtype=np.float32)


def fit_actor(
    policy: ActorCriticPolicy,
    observations: np.ndarray,
    actions: np.ndarray,
    epochs: int,
    seed: int,
    batch_size: int = 256,
    learning_rate: float = 1e-3,
    final_learning_rate: float = 1e-5,
) -> float:
    """Fit ``policy``'s action mean (features, actor layers, action head) to ``actions`` by least
    squares (the module docstring); returns the last epoch's mean squared error."""
    torch.manual_seed(seed)
    x = torch.as_tensor(observations)
    y = torch.as_tensor(actions)
    parameters = [
        *policy.features_extractor.parameters(),
        *policy.mlp_extractor.policy_net.parameters(),
        *policy.action_net.parameters(),
    ]
    optimiser = torch.optim.Adam(parameters, lr=learning_rate)
    squared_error = math.nan
    for epoch in range(epochs):
        for group in optimiser.param_groups:
            group["lr"] = learning_rate * (1.0 - epoch / epochs) + final_learning_rate
        total = 0.0
        for batch in torch.randperm(len(x)).split(batch_size):
            features = policy.extract_features(x[batch], policy.pi_features_extractor)
            mean = policy.action_net(policy.mlp_extractor.forward_actor(features))
            loss = ((mean - y[batch]) ** 2).mean()
            optimiser.zero_grad()
            loss.backward()
            optimiser.step()
            total += float(loss.detach()) * len(batch)
        squared_error = total / len(x)
    return squared_error


def clone(
    config: AgentConfig,
    out: Path,
    command: str,
    *,
    seed: int,
    episodes: int,
    noise: float,
    correlation_time: float,
    epochs: int,
    expert: Callable[[object], Controller] = track_follow_controller,
) -> float:
    """Demonstrations from ``expert`` on ``config``'s environment, the config's policy fitted to them,
    saved into ``out`` (``model.zip``, ``metadata.json``); returns the fit's mean squared error."""
    start = time.perf_counter()
    env = gym.make(config.env_id, **config.env_kwargs)
    seeds = [1000 * (seed + 1) + k for k in range(episodes)]
    rng = np.random.default_rng(seed)
    observations, actions = demonstrations(env, expert(env.unwrapped.task), seeds, noise, correlation_time, rng)
    env.close()
    vector_env = make_training_env(config)
    model = config.algorithm(config.policy, vector_env, seed=seed, device="cpu", **config.hyperparameters)
    squared_error = fit_actor(model.policy, observations, actions, epochs, seed)
    vector_env.close()
    out.mkdir(parents=True, exist_ok=True)
    model.save(out / MODEL_FILE)
    PolicyMetadata.of_run(
        config,
        seed=seed,
        steps=0,
        timesteps=0,
        wall_time_s=time.perf_counter() - start,
        torch_threads=torch.get_num_threads(),
        command=command,
    ).write(out)
    return squared_error


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0], allow_abbrev=False)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--out", type=Path, required=True)
    parser.add_argument("--config", type=Path, default=CONFIG, help="agent config with a TrackFollow-v0 entry")
    parser.add_argument("--episodes", type=int, default=36)
    parser.add_argument("--noise", type=float, default=0.1, help="DART offset's standard deviation, x delta_max")
    parser.add_argument("--correlation-time", type=float, default=5.0, help="DART offset's correlation time, s")
    parser.add_argument("--epochs", type=int, default=30)
    args = parser.parse_args(argv)
    torch.set_num_threads(DEFAULT_TORCH_THREADS)
    command = "python benchmarks/clone_course_changer.py " + " ".join(sys.argv[1:] if argv is None else argv)
    config = load_agent_config("ppo", ENV_ID, args.config)
    squared_error = clone(
        config,
        args.out,
        command,
        seed=args.seed,
        episodes=args.episodes,
        noise=args.noise,
        correlation_time=args.correlation_time,
        epochs=args.epochs,
    )
    print(f"seed {args.seed}: {args.episodes} episodes, fit mean squared error {squared_error:.5f} -> {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
