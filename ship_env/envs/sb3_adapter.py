"""Training stable-baselines3 on a Gymnasium vector environment.

SB3 has its own ``VecEnv`` API (design notes 9): ``reset()`` returns only observations, seeds and
options are set beforehand, a finished episode is restarted in the same step with its last
observation in ``info["terminal_observation"]``, and infos are a list of dicts.
:class:`SB3VecEnvAdapter` presents a Gymnasium ``VectorEnv`` with ``AutoresetMode.NEXT_STEP`` and
``reset(options={"reset_mask": ...})`` (such as ``CourseChangeVectorEnv``) that way::

    import gymnasium as gym
    from stable_baselines3 import PPO
    from stable_baselines3.common.vec_env import VecMonitor

    vector_env = gym.make_vec("ship_env/CourseChange-v0", num_envs=64, vectorization_mode="vector_entry_point")
    model = PPO("MlpPolicy", VecMonitor(SB3VecEnvAdapter(vector_env)), n_steps=64)
    model.learn(100_000)

Per-step infos are not forwarded (SB3 does not read them); at an episode's end the env's info
holds ``terminal_observation``, ``TimeLimit.truncated``, the episode's ``metrics`` and ``diverged``
(whether its ship left the model's validity: a truncation, so SB3 bootstraps from the terminal
observation; ``VecMonitor(..., info_keywords=("diverged",))`` counts them).
"""

from __future__ import annotations

from typing import Any

import gymnasium as gym
import numpy as np
from gymnasium.vector import AutoresetMode, VectorEnv

from ship_env.extras import missing_extra

try:
    from stable_baselines3.common.vec_env.base_vec_env import VecEnv, VecEnvIndices, VecEnvObs, VecEnvStepReturn
except ImportError as error:
    raise missing_extra("rl", "ship_env.envs.sb3_adapter", error) from error


class SB3VecEnvAdapter(VecEnv):
    """A Gymnasium ``VectorEnv`` (next-step autoreset, ``reset_mask``) as an SB3 ``VecEnv``.

    Args:
        vector_env: the Gymnasium vector environment; it is closed with the adapter.
    """

    def __init__(self, vector_env: VectorEnv) -> None:
        if vector_env.metadata.get("autoreset_mode") != AutoresetMode.NEXT_STEP:
            raise ValueError(
                f"vector_env: expected metadata['autoreset_mode'] = AutoresetMode.NEXT_STEP, "
                f"got {vector_env.metadata.get('autoreset_mode')!r}"
            )
        self.vector_env = vector_env
        super().__init__(vector_env.num_envs, vector_env.single_observation_space, vector_env.single_action_space)

    def reset(self) -> VecEnvObs:
        """Reset all sub-environments with the seeds of ``seed()`` and the first sub-environment's options."""
        seeds = None if all(seed is None for seed in self._seeds) else self._seeds
        options = self._options[0] or None
        # Gymnasium's vector envs (and ship_env's) take one seed per sub-environment, beyond the base's int.
        observations, _ = self.vector_env.reset(seed=seeds, options=options)  # type: ignore[arg-type]
        self._reset_seeds()
        self._reset_options()
        return observations

    def step_async(self, actions: np.ndarray) -> None:
        self._actions = np.asarray(actions).reshape(self.vector_env.action_space.shape)

    def step_wait(self) -> VecEnvStepReturn:
        observations, rewards, terminated, truncated, info = self.vector_env.step(self._actions)
        dones = terminated | truncated
        infos: list[dict[str, Any]] = [{} for _ in range(self.num_envs)]
        if dones.any():
            metrics = info.get("metrics", {})
            diverged = info.get("diverged", np.zeros(self.num_envs, dtype=np.bool_))
            for i in np.flatnonzero(dones):
                infos[i] = {
                    "terminal_observation": observations[i].copy(),
                    "TimeLimit.truncated": bool(truncated[i] and not terminated[i]),
                    "metrics": {name: float(values[i]) for name, values in metrics.items() if not name.startswith("_")},
                    "diverged": bool(diverged[i]),
                }
            observations, _ = self.vector_env.reset(options={"reset_mask": dones})
        return observations, rewards.astype(np.float32), dones, infos

    def close(self) -> None:
        self.vector_env.close()

    def get_attr(self, attr_name: str, indices: VecEnvIndices = None) -> list[Any]:
        """The vector environment's attribute, once per requested index."""
        value = getattr(self.vector_env, attr_name)
        return [value for _ in self._get_indices(indices)]

    def set_attr(self, attr_name: str, value: Any, indices: VecEnvIndices = None) -> None:
        """Set an attribute of the vector environment (shared by all its sub-environments)."""
        setattr(self.vector_env, attr_name, value)

    def env_method(
        self, method_name: str, *method_args: Any, indices: VecEnvIndices = None, **method_kwargs: Any
    ) -> list[Any]:
        """Call a method of the vector environment once; its result for each requested index."""
        result = getattr(self.vector_env, method_name)(*method_args, **method_kwargs)
        return [result for _ in self._get_indices(indices)]

    def env_is_wrapped(self, wrapper_class: type[gym.Wrapper], indices: VecEnvIndices = None) -> list[bool]:
        """Sub-environments of a native vector environment are never wrapped."""
        return [False for _ in self._get_indices(indices)]
