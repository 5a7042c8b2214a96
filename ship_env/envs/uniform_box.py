"""The continuous action space: a Box whose ``sample()`` costs what a Discrete's does."""

from __future__ import annotations

import copy
from typing import Any, cast

import numpy as np
from gymnasium import spaces
from gymnasium.vector.utils import batch_space


class UniformBox(spaces.Box):
    """A float Box with one finite lower and one finite upper bound for every element.

    It is a :class:`gymnasium.spaces.Box` in every respect (``==`` a Box of the same bounds, shape and dtype;
    batched, flattened and checked as one) except that ``sample()`` takes a shorter way to the same numbers:
    Box's draws each element uniformly in [low, high) from ``np_random`` (``Generator.uniform``, element by
    element in C order) after sorting the elements by the kind of their interval, about 20 us a call; this
    one makes the same single ``uniform`` call over the whole shape, about 2.5 us, so that the same seed
    gives the same samples bit for bit. A loop that draws its actions with ``action_space.sample()``, as
    ``gymnasium.utils.performance.benchmark_step`` does, then spends its time in the environment. A vector
    environment's batch of them (``gymnasium.vector.utils.batch_space``) is one too.

    Args:
        low: the lower bound of every element.
        high: the upper bound of every element.
        shape: the shape of a sample.
        dtype: a floating dtype.
        seed: the seed of ``np_random`` (as Box's).
    """

    def __init__(
        self,
        low: float,
        high: float,
        shape: tuple[int, ...],
        dtype: type[np.floating[Any]] | np.dtype[Any] = np.float32,
        seed: int | np.random.Generator | None = None,
    ) -> None:
        if not np.issubdtype(dtype, np.floating):
            raise ValueError(f"UniformBox: dtype: expected a floating dtype, got {np.dtype(dtype)}")
        if not (np.isfinite(low) and np.isfinite(high) and low < high):
            raise ValueError(f"UniformBox: expected finite bounds with low < high, got low={low!r}, high={high!r}")
        super().__init__(low, high, shape=shape, dtype=cast("np.dtype[np.floating[Any]]", np.dtype(dtype)), seed=seed)
        # The bounds as Box.sample() reads them: in the space's dtype, then as floats.
        self._bounds = (float(self.low.flat[0]), float(self.high.flat[0]))

    def sample(self, mask: None = None, probability: None = None) -> np.ndarray:
        """A sample: ``np_random.uniform(low, high, shape)`` in the space's dtype, as ``Box.sample()`` draws
        it (a mask or a probability is refused by Box's own error)."""
        if mask is not None or probability is not None:
            return super().sample(mask, probability)
        return self.np_random.uniform(*self._bounds, self.shape).astype(self.dtype)


@batch_space.register(UniformBox)
def _batch_uniform_box(space: UniformBox, n: int = 1) -> UniformBox:
    """``n`` copies of the space stacked on a new first axis, with a copy of its generator (as Gymnasium
    batches a Box)."""
    low, high = space._bounds
    return UniformBox(low, high, (n, *space.shape), space.dtype, seed=copy.deepcopy(space.np_random))
