"""Throughput of the environments.

    python benchmarks/bench_envs.py [--quick]

Measures, best of a few repeats:

1. single-env ``step`` steps/s of each environment (CourseChange-v0 with the default model (calm)
   and the full model (every effect on, wind, current and waves); TrackFollow-v0 in the thesis's
   wind and current; CourseKeeping-v0 in wind, current and waves), on the raw env and through
   ``gymnasium.make``'s wrappers (target >= 50k/s with the full model);
2. the native vector envs' env-steps/s at N = 1024 (target >= 2M/s), with a breakdown of one
   vector step: the simulator's step, the task's compiled update, the info dicts. Batches of
   ``PARALLEL_SHIPS`` (1024) ships step and update on all cores where that is faster
   (``ship_env.model.simulator.Cores``): on a 2-core machine to itself, about twice as fast as one
   thread; on one busy with other work (see the load average printed), in one thread.
   ``NUMBA_NUM_THREADS=1`` measures the one-thread step;
3. stable-baselines3 PPO training steps/s (rollouts and updates, ``torch.set_num_threads(1)``) on
   the CourseChange vector env through ``SB3VecEnvAdapter``, beside the same PPO on a
   ``DummyVecEnv`` of single envs.
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from collections.abc import Callable

import gymnasium as gym
import numba
import numpy as np

import ship_env  # noqa: F401  (registers the environments)
from ship_env.envs.course_change import CourseChangeEnv
from ship_env.envs.course_change_vector import CourseChangeVectorEnv
from ship_env.envs.course_keeping import CourseKeepingEnv
from ship_env.envs.course_keeping_vector import CourseKeepingVectorEnv
from ship_env.envs.single_env import ShipEnv
from ship_env.envs.track_follow import TrackFollowEnv
from ship_env.envs.track_follow_vector import TrackFollowVectorEnv
from ship_env.envs.vector_env import ShipVectorEnv
from ship_env.model import EFFECTS

ENV_ID = "ship_env/CourseChange-v0"
VECTOR_MODE = "vector_entry_point"
#: name: (single env, vector env, keyword arguments).
CONFIGURATIONS: dict[str, tuple[type[ShipEnv], type[ShipVectorEnv], dict]] = {
    "CourseChange, default model, calm": (CourseChangeEnv, CourseChangeVectorEnv, {}),
    "CourseChange, full model, wind+current+waves": (
        CourseChangeEnv,
        CourseChangeVectorEnv,
        {"disturbance": "wind_current_waves", "effects": tuple(EFFECTS)},
    ),
    "TrackFollow, thesis wind+current": (TrackFollowEnv, TrackFollowVectorEnv, {}),
    "CourseKeeping, wind+current+waves": (CourseKeepingEnv, CourseKeepingVectorEnv, {}),
}
SINGLE_TARGET = 50_000.0
VECTOR_TARGET = 2_000_000.0


def best_seconds(run: Callable[[], None], repeats: int) -> float:
    """The shortest wall time of ``repeats`` runs (the machine may be shared)."""
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        run()
        times.append(time.perf_counter() - start)
    return min(times)


def single_env_rate(env: gym.Env, steps: int, repeats: int) -> float:
    env.reset(seed=0)
    action = np.array([0.3], dtype=np.float32)

    def run() -> None:
        for _ in range(steps):
            env.step(action)

    run()  # compile and warm up
    return steps / best_seconds(run, repeats)


def vector_env_rates(
    vector_class: type[ShipVectorEnv], options: dict, num_envs: int, steps: int, repeats: int
) -> dict[str, float]:
    """Env-steps/s of the vector env, and the microseconds of each part of one step."""
    env = vector_class(num_envs=num_envs, **options)
    env.reset(seed=0)
    actions = np.random.default_rng(0).uniform(-1.0, 1.0, size=(num_envs, 1)).astype(np.float32)
    orders = actions[:, 0].astype(np.float64) * env.task.rudder_limit
    batch = env.batch

    def run_steps() -> None:
        for _ in range(steps):
            env.step(actions)

    def part(work: Callable[[], object]) -> float:
        def run() -> None:
            for _ in range(steps):
                work()

        return best_seconds(run, repeats) / steps * 1e6

    run_steps()
    rate = steps * num_envs / best_seconds(run_steps, repeats)
    return {
        "env-steps/s": rate,
        "step us": 1e6 * num_envs / rate,
        "simulator us": part(lambda: batch.simulator.step(orders)),
        "task update us": part(batch.update),
        "info us": part(lambda: env._info(np.zeros(0, dtype=np.intp), [], env._all_envs)),
    }


def threading_layer() -> str:
    """numba's threading layer, once a parallel kernel has run (batches of ``PARALLEL_SHIPS`` or more)."""
    try:
        return numba.threading_layer()
    except ValueError:
        return "not started (every batch here updated in one thread)"


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


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="fewer steps and repeats (a smoke run)")
    arguments = parser.parse_args()
    repeats = 2 if arguments.quick else 5
    single_steps = 5_000 if arguments.quick else 50_000
    vector_steps = 50 if arguments.quick else 300
    ppo_steps = 4096 if arguments.quick else 16_384
    print("command:", " ".join([sys.executable.rsplit("/", 1)[-1], *sys.argv]))
    print(
        f"machine: {os.cpu_count()} cores, load average {os.getloadavg()[0]:.1f} at the start; "
        f"OMP_WAIT_POLICY={os.environ.get('OMP_WAIT_POLICY', '(unset)')}"
    )

    print("\n1. single env, step (target >= 50k steps/s with the full model)")
    for name, (single_class, _, options) in CONFIGURATIONS.items():
        raw = single_env_rate(single_class(**options), single_steps, repeats)
        made = single_env_rate(gym.make(single_class.env_id, max_episode_steps=10**9, **options), single_steps, repeats)
        print(f"   {name:45s} raw {raw / 1e3:7.1f}k/s   gym.make (wrappers) {made / 1e3:7.1f}k/s")

    print("\n2. vector env, N = 1024 (target >= 2M env-steps/s); one step's parts in microseconds")
    for name, (_, vector_class, options) in CONFIGURATIONS.items():
        rates = vector_env_rates(vector_class, options, 1024, vector_steps, repeats)
        print(
            f"   {name:45s} {rates['env-steps/s'] / 1e6:5.2f}M env-steps/s = {rates['step us']:6.0f} us/step: "
            f"simulator {rates['simulator us']:5.0f}, task update {rates['task update us']:4.0f}, "
            f"info {rates['info us']:4.0f}"
        )
    print(f"   numba threading layer: {threading_layer()}")

    print("\n3. PPO training (MlpPolicy, 2048-step rollouts, batch 256, 4 epochs, torch 1 thread)")
    from stable_baselines3.common.vec_env import DummyVecEnv

    from ship_env.envs.sb3_adapter import SB3VecEnvAdapter

    for num_envs in (16, 64):
        rate = ppo_rate(
            lambda n=num_envs: SB3VecEnvAdapter(gym.make_vec(ENV_ID, num_envs=n, vectorization_mode=VECTOR_MODE)),
            ppo_steps,
            num_envs,
        )
        print(f"   vector env + SB3VecEnvAdapter, {num_envs:3d} envs   {rate:7.0f} steps/s")
    rate = ppo_rate(lambda: DummyVecEnv([lambda: gym.make(ENV_ID)] * 16), ppo_steps, 16)
    print(f"   DummyVecEnv of 16 gym.make envs          {rate:7.0f} steps/s")


if __name__ == "__main__":
    main()
