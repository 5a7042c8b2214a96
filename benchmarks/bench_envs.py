"""Throughput of the environments, as ratios against Gymnasium's own environments measured in the same run.

    python benchmarks/bench_envs.py [--rounds 3] [--quick] [--no-cold] [--ppo]

A shared machine cannot judge an absolute figure (other work takes the cores), so each figure is
a ratio against a peer measured beside it, in the same process and the same round, with
``gymnasium.utils.performance`` as the harness. Each round (the load average printed before it):

1. one environment through ``gym.make``: CourseChange-v0 against CartPole-v1, steps/s with the
   actions drawn beforehand, and with ``action_space.sample()`` in the loop (``benchmark_step``;
   a ``Box.sample()`` costs several times a ``Discrete`` one, and more than our step), and with
   ``info_keys=()`` (no information built, for a learner that reads none); target 1.0x;
2. the native vector environment at N = 1024, the preset's default effects (and every effect on, with
   wind, current and waves), against CartPole's native vector env (``gym.make_vec("CartPole-v1",
   num_envs=1024, vectorization_mode="vector_entry_point")``): env-steps/s with actions drawn
   beforehand, and ``benchmark_vector_step`` (sampling in the loop); target 1.0x;
3. rendering (``render_mode="rgb_array"``, 600 x 600): frames/s of ``render()`` alone
   (``benchmark_render``) and of ``step()`` + ``render()`` (what RecordVideo does), over the
   environment's 30 frames/s (its ``render_fps``); target 1.0x;
4. the first ``gym.make`` + ``reset`` + ``step`` of CourseChange-v0 in a fresh interpreter with an
   empty numba cache (``NUMBA_CACHE_DIR`` an empty folder), over the 15-s target, beside CartPole's
   in a fresh interpreter; and where the time goes: each phase, and the compilations numba ran
   (``numba.core.event``), the longest first.

Then the min and median over the rounds of every ratio (absolute figures as information), and the
parts of one ``gym.make`` step and of one vector step (N = 1024; microseconds, median and mean per
call: a loaded machine pre-empts some calls, which the mean shows), and with ``--ppo``
stable-baselines3 PPO's training steps/s.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from typing import Any

import gymnasium as gym
import numpy as np
from gymnasium.utils.performance import benchmark_render, benchmark_step, benchmark_vector_step

import ship_env  # noqa: F401  (registers the environments)
from ship_env.model import EFFECTS

ENV_ID = "ship_env/CourseChange-v0"
PEER_ID = "CartPole-v1"
NUM_ENVS = 1024
VECTOR_MODE = "vector_entry_point"
#: The vector configurations: name -> keyword arguments.
VECTOR_OPTIONS = {
    "default effects, calm": {},
    "every effect, wind+current+waves": {"disturbance": "wind_current_waves", "effects": tuple(EFFECTS)},
}
TARGET_FRAMES_PER_SECOND = 30.0
TARGET_COLD_SECONDS = 15.0
DRAWN_ACTIONS = 4096  # actions drawn beforehand, cycled
COLD = "4. first make+reset+step, empty cache: 15 s over ours"


def benchmark_step_drawn(env: gym.Env, target_duration: float, seed: int = 0) -> float:
    """``benchmark_step`` with the actions drawn beforehand: steps/s of ``env.step`` alone."""
    env.action_space.seed(seed)
    actions = [env.action_space.sample() for _ in range(DRAWN_ACTIONS)]
    env.reset(seed=seed)
    steps = 0
    start = time.perf_counter()
    while True:
        _, _, terminated, truncated, _ = env.step(actions[steps % DRAWN_ACTIONS])
        steps += 1
        if terminated or truncated:
            env.reset()
        elapsed = time.perf_counter() - start
        if elapsed > target_duration:
            return steps / elapsed


def benchmark_vector_step_drawn(env: gym.vector.VectorEnv, target_duration: float, seed: int = 0) -> float:
    """``benchmark_vector_step`` with the actions drawn beforehand: env-steps/s (NEXT_STEP autoreset: a
    sub-environment's restarting step is not counted, as there)."""
    env.action_space.seed(seed)
    actions = [env.action_space.sample() for _ in range(64)]
    env.reset(seed=seed)
    env.step(actions[0])  # warm up (compilation, threads)
    env.reset(seed=seed)
    steps = calls = 0
    previous_done = np.zeros(env.num_envs, dtype=np.bool_)
    start = time.perf_counter()
    while True:
        _, _, terminated, truncated, _ = env.step(actions[calls % len(actions)])
        calls += 1
        steps += env.num_envs - int(np.count_nonzero(previous_done))
        previous_done = terminated | truncated
        elapsed = time.perf_counter() - start
        if elapsed > target_duration:
            return steps / elapsed


def step_and_render(env: gym.Env, target_duration: float) -> float:
    """Frames/s of ``step`` + ``render`` (RecordVideo's loop), the action amidships-to-starboard."""
    action = np.full(env.action_space.shape, 0.5, dtype=env.action_space.dtype)
    frames = 0
    start = time.perf_counter()
    while True:
        _, _, terminated, truncated, _ = env.step(action)
        if terminated or truncated:
            env.reset()
        env.render()
        frames += 1
        elapsed = time.perf_counter() - start
        if elapsed > target_duration:
            return frames / elapsed


# -- the first make, reset and step with an empty cache -----------------------------------------
_COLD_CHILD = """
import json, sys, time
start = time.perf_counter()
from numba.core import event
with event.install_recorder("numba:compile") as recorder:
    phases = {}
    import gymnasium as gym
    if sys.argv[1] != "CartPole-v1":
        import ship_env
    phases["import"] = time.perf_counter() - start
    env = gym.make(sys.argv[1])
    phases["make"] = time.perf_counter() - start - sum(phases.values())
    env.reset(seed=0)
    phases["reset"] = time.perf_counter() - start - sum(phases.values())
    env.step(env.action_space.sample())
    phases["step"] = time.perf_counter() - start - sum(phases.values())
started, compiles, depth = {}, [], 0
for moment, happening in recorder.buffer:
    if happening.is_start:
        started[id(happening.data)] = (moment, depth)
        depth += 1
    else:
        depth -= 1
        began, level = started.pop(id(happening.data))
        if level == 0:  # compiled for a call from Python, its callees included
            dispatcher = happening.data["dispatcher"]
            compiles.append((dispatcher.py_func.__module__ + "." + dispatcher.py_func.__qualname__, moment - began))
seconds = time.perf_counter() - start
print(json.dumps({"seconds": seconds, "cpu": time.process_time(), "phases": phases, "compiles": compiles}))
"""


def cold_start(env_id: str) -> dict[str, Any]:
    """The first make + reset + step of ``env_id`` in a fresh interpreter with an empty numba cache."""
    with tempfile.TemporaryDirectory() as cache:
        result = subprocess.run(
            [sys.executable, "-c", _COLD_CHILD, env_id],
            env={**os.environ, "NUMBA_CACHE_DIR": cache},
            capture_output=True,
            text=True,
            check=False,
        )
    if result.returncode:
        raise RuntimeError(result.stderr)
    return json.loads(result.stdout.strip().splitlines()[-1])


# -- one round ----------------------------------------------------------------------------------
def one_round(duration: float, cold: bool, cold_details: list[dict[str, Any]]) -> dict[str, dict[str, float]]:
    """Every comparison once, ours beside its peer: name -> {"ours", "peer", "ratio"}; with ``cold``, the
    first make's phases and compilations appended to ``cold_details``."""
    figures: dict[str, dict[str, float]] = {}

    def compare(name: str, ours: float, peer: float) -> None:
        figures[name] = {"ours": ours, "peer": peer, "ratio": ours / peer}

    ours_env, peer_env = gym.make(ENV_ID), gym.make(PEER_ID)
    benchmark_step_drawn(ours_env, 0.2)  # warm up (compilation)
    for name, harness in (("actions drawn beforehand", benchmark_step_drawn), ("sample() in the loop", benchmark_step)):
        peer = harness(peer_env, duration, seed=0)
        compare(f"1. gym.make step, {name}", harness(ours_env, duration, seed=0), peer)
    lean_env = gym.make(ENV_ID, info_keys=())
    benchmark_step_drawn(lean_env, 0.2)
    peer = benchmark_step_drawn(peer_env, duration, seed=0)
    compare("1. gym.make step, info_keys=(), actions drawn beforehand", benchmark_step_drawn(lean_env, duration), peer)

    peer_vector = gym.make_vec(PEER_ID, num_envs=NUM_ENVS, vectorization_mode=VECTOR_MODE)
    for options_name, options in VECTOR_OPTIONS.items():
        ours_vector = gym.make_vec(ENV_ID, num_envs=NUM_ENVS, vectorization_mode=VECTOR_MODE, **options)
        for name, harness in (
            ("actions drawn beforehand", benchmark_vector_step_drawn),
            ("benchmark_vector_step", benchmark_vector_step),
        ):
            peer = harness(peer_vector, duration, seed=0)
            compare(f"2. vector N={NUM_ENVS}, {options_name}, {name}", harness(ours_vector, duration, seed=0), peer)
        ours_vector.close()

    rendered = gym.make(ENV_ID, render_mode="rgb_array", disturbance="wind_current_waves")
    rendered.reset(seed=0)
    step_and_render(rendered, 0.2)  # warm up (matplotlib, the still picture)
    compare("3. render() alone, frames/s over 30", benchmark_render(rendered, duration), TARGET_FRAMES_PER_SECOND)
    compare("3. step() + render(), frames/s over 30", step_and_render(rendered, duration), TARGET_FRAMES_PER_SECOND)
    rendered.close()

    if cold:
        ours = cold_start(ENV_ID)
        peer = cold_start(PEER_ID)
        # A time: the target over ours, so that 1.0x or more meets it, as for the rates.
        compare(COLD, TARGET_COLD_SECONDS, ours["seconds"])
        figures[COLD].update(cold_cpu=ours["cpu"], peer_seconds=peer["seconds"])
        cold_details.append(ours)
    return figures


def time_parts(parts: dict[str, Callable[[], object]], steps: int) -> dict[str, tuple[float, float]]:
    """Each part's microseconds per call, (median, mean) over ``steps`` calls, the parts called round-robin
    (so that load shifts every part alike)."""
    times: dict[str, list[float]] = {name: [] for name in parts}
    for _ in range(steps):
        for name, work in parts.items():
            start = time.perf_counter()
            work()
            times[name].append(1e6 * (time.perf_counter() - start))
    return {name: (statistics.median(values), statistics.fmean(values)) for name, values in times.items()}


def single_step_parts(steps: int) -> dict[str, tuple[float, float]]:
    """One ``gym.make`` step's parts (default effects), microseconds per call: (median, mean)."""
    wrapped = gym.make(ENV_ID)
    lean = gym.make(ENV_ID, info_keys=())
    env = wrapped.unwrapped
    for made in (wrapped, lean):
        made.reset(seed=0)
    action = np.array([0.25], dtype=np.float32)
    order = env.task.rudder_order(action)
    batch = env.batch
    parts: dict[str, Callable[[], object]] = {
        "whole step through gym.make's wrappers": lambda: wrapped.step(action),
        "the same, info_keys=()": lambda: lean.step(action),
        "unwrapped step": lambda: env.step(action),
        "action to rudder order": lambda: env.task.rudder_order(action),
        "step and update (one compiled call)": lambda: batch.sail(order),
        "info dict": lambda: batch.info(0),
        "observation, reward, termination": lambda: batch.outcome(0),
    }
    return time_parts(parts, steps)


def vector_step_parts(steps: int) -> dict[str, tuple[float, float]]:
    """One vector step's parts at N = 1024 (default effects), microseconds per call: (median, mean)."""
    env = gym.make_vec(ENV_ID, num_envs=NUM_ENVS, vectorization_mode=VECTOR_MODE).unwrapped
    noiseless = gym.make_vec(ENV_ID, num_envs=NUM_ENVS, vectorization_mode=VECTOR_MODE, sensor_noise_scale=0.0)
    for made in (env, noiseless):
        made.reset(seed=0)
    actions = np.random.default_rng(0).uniform(-1.0, 1.0, size=(NUM_ENVS, 1)).astype(np.float32)
    orders = actions[:, 0].astype(np.float64) * env.task.rudder_limit
    batch = env.batch
    no_ships = np.zeros(0, dtype=np.intp)
    parts: dict[str, Callable[[], object]] = {
        "whole step": lambda: env.step(actions),
        "actions to rudder orders": lambda: env.task.rudder_orders(actions, NUM_ENVS, env._orders),
        "simulator step": lambda: batch.simulator.step(orders),
        "task update (compiled)": batch.update,
        "the same, sensor_noise_scale=0": noiseless.unwrapped.batch.update,
        "observations, rewards, terminations": batch.outcomes,
        "info dicts": lambda: env._info(no_ships, [], env._all_envs),
    }
    return time_parts(parts, steps)


def ppo_rate(make_env: Callable[[], object], total_steps: int, num_envs: int) -> float:
    """PPO training steps/s (rollouts plus updates), one torch thread."""
    import torch
    from stable_baselines3 import PPO
    from stable_baselines3.common.vec_env import VecMonitor

    torch.set_num_threads(1)
    model = PPO("MlpPolicy", VecMonitor(make_env()), n_steps=2048 // num_envs, batch_size=256, n_epochs=4, seed=0)
    model.learn(2048)  # warm up
    start = time.perf_counter()
    model.learn(total_steps, reset_num_timesteps=False)
    return total_steps / (time.perf_counter() - start)


def _figure(value: float) -> str:
    if value >= 1e6:
        return f"{value / 1e6:.2f}M"
    if value >= 1e3:
        return f"{value / 1e3:.1f}k"
    return f"{value:.1f}"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0], allow_abbrev=False)
    parser.add_argument("--rounds", type=int, default=3, help="rounds of every comparison (default 3)")
    parser.add_argument("--quick", action="store_true", help="0.3 s per measurement instead of 2 s (a smoke run)")
    parser.add_argument("--no-cold", action="store_true", help="skip the first make from an empty cache")
    parser.add_argument("--ppo", action="store_true", help="also time stable-baselines3 PPO training")
    arguments = parser.parse_args()
    duration = 0.3 if arguments.quick else 2.0
    print("command:", " ".join([sys.executable.rsplit("/", 1)[-1], *sys.argv]))
    print(f"machine: {os.cpu_count()} cores; numba threads {os.environ.get('NUMBA_NUM_THREADS', '(all)')}")

    rounds = []
    cold_details: list[dict[str, Any]] = []
    for number in range(arguments.rounds):
        print(f"round {number + 1}: load average {os.getloadavg()[0]:.1f} at its start", flush=True)
        rounds.append(one_round(duration, not arguments.no_cold, cold_details))
    print(f"load average {os.getloadavg()[0]:.1f} at the end")

    print(f"\nratios ours / peer in the same round, min and median of {len(rounds)} rounds (target 1.0x):")
    for name in rounds[0]:
        ratios = [figures[name]["ratio"] for figures in rounds]
        ours = [figures[name]["ours"] for figures in rounds]
        peer = [figures[name]["peer"] for figures in rounds]
        print(
            f"  {name:76s} {min(ratios):5.2f}x / {statistics.median(ratios):5.2f}x   "
            f"(ours {_figure(statistics.median(ours))}, peer {_figure(statistics.median(peer))}: medians)"
        )
    if cold_details:
        seconds = [detail["seconds"] for detail in cold_details]
        cpu = [detail["cpu"] for detail in cold_details]
        peer_seconds = [figures[COLD]["peer_seconds"] for figures in rounds]
        print(
            f"\n4. first make+reset+step of {ENV_ID}, empty numba cache: {min(seconds):.1f} / "
            f"{statistics.median(seconds):.1f} s wall (min / median), {min(cpu):.1f} / {statistics.median(cpu):.1f} "
            f"CPU-s of the process (its import included); CartPole-v1 {statistics.median(peer_seconds):.1f} s"
        )
        last = cold_details[-1]
        print("   phases (last round), s: " + ", ".join(f"{k} {v:.1f}" for k, v in last["phases"].items()))
        compiles = sorted(last["compiles"], key=lambda item: -item[1])
        total = sum(spent for _, spent in compiles)
        print(f"   compilations for calls from Python (last round, their callees included), {total:.1f} s:")
        for function, spent in compiles[:8]:
            print(f"     {spent:6.1f} s  {function}")

    print(f"\none gym.make step's parts, {ENV_ID}, default effects, us per call (median / mean):")
    for name, (median, mean) in single_step_parts(2000 if arguments.quick else 20_000).items():
        print(f"  {name:40s} {median:8.2f} / {mean:8.2f}")

    print(f"\none vector step's parts, N = {NUM_ENVS}, default effects, us per call (median / mean):")
    for name, (median, mean) in vector_step_parts(50 if arguments.quick else 300).items():
        print(f"  {name:40s} {median:8.0f} / {mean:8.0f}")

    if arguments.ppo:
        from stable_baselines3.common.vec_env import DummyVecEnv

        from ship_env.envs.sb3_adapter import SB3VecEnvAdapter

        steps = 4096 if arguments.quick else 16_384
        print("\nPPO training (MlpPolicy, 2048-step rollouts, batch 256, 4 epochs, torch 1 thread), steps/s:")
        for num_envs in (16, 64):
            rate = ppo_rate(
                lambda n=num_envs: SB3VecEnvAdapter(gym.make_vec(ENV_ID, num_envs=n, vectorization_mode=VECTOR_MODE)),
                steps,
                num_envs,
            )
            print(f"  vector env + SB3VecEnvAdapter, {num_envs:3d} envs   {rate:7.0f}")
        rate = ppo_rate(lambda: DummyVecEnv([lambda: gym.make(ENV_ID)] * 16), steps, 16)
        print(f"  DummyVecEnv of 16 gym.make envs          {rate:7.0f}")


if __name__ == "__main__":
    main()
