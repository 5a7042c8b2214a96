"""A short run of the model and of an environment, printed as JSON: the same with the compiled kernels
and as pure Python (``NUMBA_DISABLE_JIT=1``), which ``test_model_simulator`` compares."""

from __future__ import annotations

import json
import math

import numpy as np

from ship_env.envs.course_keeping import CourseKeepingEnv
from ship_env.model import Conditions, ShipModel, Simulator


def short_run() -> dict[str, list[float]]:
    """Two ships 10 s in wind, current and waves (the batch loop, the sea drawn at the start), and one
    environment step with instrument noise (the single ship's step and the task's update)."""
    conditions = Conditions(
        wind_speed=9.0, wind_direction=math.radians(300.0), current_speed=1.0, wave_height=2.5, wave_period=8.0
    )
    simulator = Simulator(ShipModel("container_226m").with_effects("wave_filter", "wave_spectrum"), num_ships=2, dt=1.0)
    simulator.reset(seed=3, conditions=conditions)
    for _ in range(10):
        simulator.step(np.radians([10.0, -20.0]))
    env = CourseKeepingEnv(disturbance="wind_current_waves")
    env.reset(seed=4)
    observation, reward, _, _, info = env.step(np.array([0.5], dtype=np.float32))
    return {
        "simulator": simulator.state.ravel().tolist(),
        "observation": observation.astype(float).tolist(),
        "reward": [reward],
        "env_state": info["state"].tolist(),
    }


if __name__ == "__main__":
    print(json.dumps(short_run()))
