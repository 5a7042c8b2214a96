"""PPO on a continuous action, written as CleanRL's single-file script is, knowing nothing but the id.

    python benchmarks/cleanrl_ppo_continuous.py [--total-timesteps 20000] [--capture-video] [--seed 1]

The environment is only its registered id, ``ship_env:ship_env/CourseChange-v0`` (``gym.make``
imports ``ship_env`` from it): ``gym.vector.SyncVectorEnv`` of ``gym.make(id)`` behind the wrappers
CleanRL's ``ppo_continuous_action.py`` puts there (RecordEpisodeStatistics, ClipAction,
NormalizeObservation, TransformObservation clipping at +-10, NormalizeReward, TransformReward clipping
at +-10), a tanh actor-critic of two 64-unit layers with a state-independent log std, GAE(lambda) and
the clipped surrogate objective with a clipped value loss, with CleanRL's hyperparameters (Gymnasium
1.x's API: the vector env's ``NEXT_STEP`` autoreset, the episode statistics in ``infos["episode"]``
where ``infos["_episode"]``). ``--capture-video`` makes sub-environment 0 with
``render_mode="rgb_array"`` behind ``gym.wrappers.RecordVideo`` (which needs moviepy: ``pip install
-e ".[video]"``), recording its first episode into ``--video-folder``; CleanRL's own trigger (episodes
0, 1, 8, 27, ...) is ``--video-every-cube``.

It prints each finished episode's return, then the wall and CPU time of the run (torch on
``--torch-threads`` threads, 1 by default, as a shared machine wants).
"""

from __future__ import annotations

import argparse
import os
import random
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import gymnasium as gym
import numpy as np
import torch
from torch import nn, optim
from torch.distributions.normal import Normal

ENV_ID = "ship_env:ship_env/CourseChange-v0"


def parse_args(argv: list[str] | None = None) -> argparse.Namespace:
    """CleanRL's arguments (those a run without tracking uses), with its defaults."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0], allow_abbrev=False)
    parser.add_argument("--env-id", default=ENV_ID)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--total-timesteps", type=int, default=1_000_000)
    parser.add_argument("--learning-rate", type=float, default=3e-4)
    parser.add_argument("--num-envs", type=int, default=1)
    parser.add_argument("--num-steps", type=int, default=2048, help="steps per environment per rollout")
    parser.add_argument("--no-anneal-lr", dest="anneal_lr", action="store_false")
    parser.add_argument("--gamma", type=float, default=0.99)
    parser.add_argument("--gae-lambda", type=float, default=0.95)
    parser.add_argument("--num-minibatches", type=int, default=32)
    parser.add_argument("--update-epochs", type=int, default=10)
    parser.add_argument("--clip-coef", type=float, default=0.2)
    parser.add_argument("--ent-coef", type=float, default=0.0)
    parser.add_argument("--vf-coef", type=float, default=0.5)
    parser.add_argument("--max-grad-norm", type=float, default=0.5)
    parser.add_argument("--capture-video", action="store_true", help="record sub-environment 0's first episode")
    parser.add_argument("--video-every-cube", action="store_true", help="CleanRL's trigger: episodes 0, 1, 8, 27")
    parser.add_argument("--video-folder", type=Path, default=Path("videos"))
    parser.add_argument("--torch-threads", type=int, default=1)
    parser.add_argument("--quiet", action="store_true", help="no line per finished episode")
    args = parser.parse_args(argv)
    args.batch_size = args.num_envs * args.num_steps
    args.minibatch_size = args.batch_size // args.num_minibatches
    args.num_iterations = -(-args.total_timesteps // args.batch_size)  # whole rollouts, at least the total
    return args


def make_env(env_id: str, index: int, args: argparse.Namespace) -> Callable[[], gym.Env]:
    """CleanRL's ``make_env``: the environment behind the standard wrappers (RecordVideo on env 0)."""

    def thunk() -> gym.Env:
        if args.capture_video and index == 0:
            env = gym.make(env_id, render_mode="rgb_array")
            trigger = None if args.video_every_cube else (lambda episode: episode == 0)
            env = gym.wrappers.RecordVideo(env, str(args.video_folder), episode_trigger=trigger)
        else:
            env = gym.make(env_id)
        env = gym.wrappers.FlattenObservation(env)
        env = gym.wrappers.RecordEpisodeStatistics(env)
        env = gym.wrappers.ClipAction(env)
        env = gym.wrappers.NormalizeObservation(env)
        env = gym.wrappers.TransformObservation(env, lambda obs: np.clip(obs, -10, 10), env.observation_space)
        env = gym.wrappers.NormalizeReward(env, gamma=args.gamma)
        env = gym.wrappers.TransformReward(env, lambda reward: np.clip(reward, -10, 10))
        return env

    return thunk


def layer_init(layer: nn.Linear, std: float = float(np.sqrt(2)), bias_const: float = 0.0) -> nn.Linear:
    torch.nn.init.orthogonal_(layer.weight, std)
    torch.nn.init.constant_(layer.bias, bias_const)
    return layer


class Agent(nn.Module):
    """CleanRL's continuous actor-critic: two tanh layers of 64 each, a state-independent log std."""

    def __init__(self, observations: int, actions: int) -> None:
        super().__init__()
        self.critic = nn.Sequential(
            layer_init(nn.Linear(observations, 64)),
            nn.Tanh(),
            layer_init(nn.Linear(64, 64)),
            nn.Tanh(),
            layer_init(nn.Linear(64, 1), std=1.0),
        )
        self.actor_mean = nn.Sequential(
            layer_init(nn.Linear(observations, 64)),
            nn.Tanh(),
            layer_init(nn.Linear(64, 64)),
            nn.Tanh(),
            layer_init(nn.Linear(64, actions), std=0.01),
        )
        self.actor_logstd = nn.Parameter(torch.zeros(1, actions))

    def get_value(self, x: torch.Tensor) -> torch.Tensor:
        return self.critic(x)

    def get_action_and_value(
        self, x: torch.Tensor, action: torch.Tensor | None = None
    ) -> tuple[torch.Tensor, torch.Tensor, torch.Tensor, torch.Tensor]:
        action_mean = self.actor_mean(x)
        probs = Normal(action_mean, torch.exp(self.actor_logstd.expand_as(action_mean)))
        if action is None:
            action = probs.sample()
        return action, probs.log_prob(action).sum(1), probs.entropy().sum(1), self.critic(x)


def train(args: argparse.Namespace) -> dict[str, Any]:
    """The run: ``{"episodes": [(global step, return, length), ...], "wall_s", "cpu_s", "steps"}``."""
    wall_start, cpu_start = time.perf_counter(), time.process_time()
    random.seed(args.seed)
    np.random.seed(args.seed)
    torch.manual_seed(args.seed)
    torch.backends.cudnn.deterministic = True
    torch.set_num_threads(args.torch_threads)
    device = torch.device("cpu")

    envs = gym.vector.SyncVectorEnv([make_env(args.env_id, i, args) for i in range(args.num_envs)])
    assert isinstance(envs.single_action_space, gym.spaces.Box), "only continuous action space is supported"
    observation_shape = envs.single_observation_space.shape
    action_shape = envs.single_action_space.shape
    assert observation_shape is not None and action_shape is not None
    agent = Agent(int(np.prod(observation_shape)), int(np.prod(action_shape))).to(device)
    optimizer = optim.Adam(agent.parameters(), lr=args.learning_rate, eps=1e-5)

    obs = torch.zeros((args.num_steps, args.num_envs, *observation_shape)).to(device)
    actions = torch.zeros((args.num_steps, args.num_envs, *action_shape)).to(device)
    logprobs = torch.zeros((args.num_steps, args.num_envs)).to(device)
    rewards = torch.zeros((args.num_steps, args.num_envs)).to(device)
    dones = torch.zeros((args.num_steps, args.num_envs)).to(device)
    values = torch.zeros((args.num_steps, args.num_envs)).to(device)

    global_step = 0
    episodes: list[tuple[int, float, int]] = []
    next_obs_array, _ = envs.reset(seed=args.seed)
    next_obs = torch.Tensor(next_obs_array).to(device)
    next_done = torch.zeros(args.num_envs).to(device)

    for iteration in range(1, args.num_iterations + 1):
        if args.anneal_lr:
            frac = 1.0 - (iteration - 1.0) / args.num_iterations
            optimizer.param_groups[0]["lr"] = frac * args.learning_rate

        for step in range(args.num_steps):
            global_step += args.num_envs
            obs[step] = next_obs
            dones[step] = next_done
            with torch.no_grad():
                action, logprob, _, value = agent.get_action_and_value(next_obs)
                values[step] = value.flatten()
            actions[step] = action
            logprobs[step] = logprob

            next_obs_array, reward, terminations, truncations, infos = envs.step(action.cpu().numpy())
            next_done_array = np.logical_or(terminations, truncations)
            rewards[step] = torch.tensor(reward).to(device).view(-1)
            next_obs = torch.Tensor(next_obs_array).to(device)
            next_done = torch.Tensor(next_done_array).to(device)

            if "episode" in infos:
                for i in np.flatnonzero(infos["_episode"]):
                    episode = (global_step, float(infos["episode"]["r"][i]), int(infos["episode"]["l"][i]))
                    episodes.append(episode)
                    if not args.quiet:
                        print(f"global_step={episode[0]}, episodic_return={episode[1]:.2f}", flush=True)

        # GAE(lambda) bootstrapped from the value of the next observation.
        with torch.no_grad():
            next_value = agent.get_value(next_obs).reshape(1, -1)
            advantages = torch.zeros_like(rewards).to(device)
            lastgaelam = torch.zeros(args.num_envs).to(device)
            for t in reversed(range(args.num_steps)):
                if t == args.num_steps - 1:
                    nextnonterminal = 1.0 - next_done
                    nextvalues = next_value
                else:
                    nextnonterminal = 1.0 - dones[t + 1]
                    nextvalues = values[t + 1]
                delta = rewards[t] + args.gamma * nextvalues * nextnonterminal - values[t]
                lastgaelam = delta + args.gamma * args.gae_lambda * nextnonterminal * lastgaelam
                advantages[t] = lastgaelam
            returns = advantages + values

        b_obs = obs.reshape((-1, *observation_shape))
        b_logprobs = logprobs.reshape(-1)
        b_actions = actions.reshape((-1, *action_shape))
        b_advantages = advantages.reshape(-1)
        b_returns = returns.reshape(-1)
        b_values = values.reshape(-1)

        b_inds = np.arange(args.batch_size)
        for _epoch in range(args.update_epochs):
            np.random.shuffle(b_inds)
            for start in range(0, args.batch_size, args.minibatch_size):
                mb_inds = b_inds[start : start + args.minibatch_size]
                _, newlogprob, entropy, newvalue = agent.get_action_and_value(b_obs[mb_inds], b_actions[mb_inds])
                ratio = (newlogprob - b_logprobs[mb_inds]).exp()

                mb_advantages = b_advantages[mb_inds]
                mb_advantages = (mb_advantages - mb_advantages.mean()) / (mb_advantages.std() + 1e-8)
                pg_loss = torch.max(
                    -mb_advantages * ratio, -mb_advantages * torch.clamp(ratio, 1 - args.clip_coef, 1 + args.clip_coef)
                ).mean()

                newvalue = newvalue.view(-1)
                v_loss_unclipped = (newvalue - b_returns[mb_inds]) ** 2
                v_clipped = b_values[mb_inds] + torch.clamp(
                    newvalue - b_values[mb_inds], -args.clip_coef, args.clip_coef
                )
                v_loss_clipped = (v_clipped - b_returns[mb_inds]) ** 2
                v_loss = 0.5 * torch.max(v_loss_unclipped, v_loss_clipped).mean()

                loss = pg_loss - args.ent_coef * entropy.mean() + v_loss * args.vf_coef
                optimizer.zero_grad()
                loss.backward()
                nn.utils.clip_grad_norm_(agent.parameters(), args.max_grad_norm)
                optimizer.step()

    envs.close()
    return {
        "episodes": episodes,
        "steps": global_step,
        "wall_s": time.perf_counter() - wall_start,
        "cpu_s": time.process_time() - cpu_start,
    }


def main(argv: list[str] | None = None) -> dict[str, Any]:
    args = parse_args(argv)
    result = train(args)
    videos = sorted(args.video_folder.glob("*.mp4")) if args.capture_video else []
    load = os.getloadavg()[0]
    print(
        f"{result['steps']} steps of {args.env_id} in {result['wall_s']:.1f} s wall, {result['cpu_s']:.1f} CPU-s "
        f"({len(result['episodes'])} episodes; load average {load:.1f})"
    )
    for video in videos:
        print(f"video: {video} ({video.stat().st_size / 1e3:.0f} kB)")
    return {**result, "videos": videos}


if __name__ == "__main__":
    main()
