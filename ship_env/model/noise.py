"""Reproducible random numbers per ship, computed inside the compiled step.

Each ship has a 64-bit key derived from its seed. The random numbers it needs at step k are a
pure function of (key, k): the SplitMix64 finaliser (Steele, Lea & Flood 2014) hashes the counter
into 64 random bits, two such draws make two independent standard normal samples by the
Box-Muller transform (a caller needing several samples takes them in pairs).
This is the counter-based design of Random123/Philox: a ship's stream does not depend on how many
other ships share the batch or in which order they are stepped, so a batch of N ships gives
exactly the numbers of N single runs, and no generator state has to be kept or copied.
"""

from __future__ import annotations

import math

import numpy as np

from ship_env.model.kernel import kernel

_GOLDEN_GAMMA = np.uint64(0x9E3779B97F4A7C15)
_MIX_1 = np.uint64(0xBF58476D1CE4E5B9)
_MIX_2 = np.uint64(0x94D049BB133111EB)
_SHIFT_30 = np.uint64(30)
_SHIFT_27 = np.uint64(27)
_SHIFT_31 = np.uint64(31)
_SHIFT_11 = np.uint64(11)
_TWO_TO_MINUS_53 = 1.0 / 9007199254740992.0

# Counter domains, so that the numbers drawn for different purposes never coincide. The step noise
# (``dynamics.draw_white_noise``) uses the counters from 0, one a step for each pair of channels,
# the k-th pair's from k 2^40.
# The numbers effects draw where a ship starts (``contributions.Draw``): the k-th draw of the
# registered effects (in registration order) from DRAW_DOMAIN + k DRAW_STRIDE on.
DRAW_DOMAIN = np.uint64(0x5A5A5A5A00000000)
DRAW_STRIDE = 1 << 32
MEASUREMENT_DOMAIN = np.uint64(0x1234567800000000)  # sensor noise of the environments' instruments


@kernel
def mix(value):
    """The SplitMix64 finaliser: 64 well-mixed bits from a uint64."""
    z = (value ^ (value >> _SHIFT_30)) * _MIX_1
    z = (z ^ (z >> _SHIFT_27)) * _MIX_2
    return z ^ (z >> _SHIFT_31)


@kernel
def uniform(key, counter):
    """A uniform sample in (0, 1) for (key, counter); both uint64."""
    bits = mix(key + counter * _GOLDEN_GAMMA)
    return (float(bits >> _SHIFT_11) + 0.5) * _TWO_TO_MINUS_53


@kernel
def standard_normal_pair(key, counter):
    """Two independent standard normal samples for (key, counter), by Box-Muller on two uniforms."""
    radius = math.sqrt(-2.0 * math.log(uniform(key, np.uint64(2) * counter)))
    angle = 2.0 * math.pi * uniform(key, np.uint64(2) * counter + np.uint64(1))
    return radius * math.cos(angle), radius * math.sin(angle)


def keys_from_seeds(seeds: np.ndarray) -> np.ndarray:
    """One uint64 key per ship from its integer seed (any int64 value)."""
    seeds = np.asarray(seeds, dtype=np.int64).astype(np.uint64)
    return _keys(seeds)


@kernel
def _keys(seeds):
    keys = np.empty_like(seeds)
    for i in range(seeds.shape[0]):
        keys[i] = mix(mix(seeds[i] + _GOLDEN_GAMMA))
    return keys


@kernel
def uniform_table(keys, domain, count):
    """(len(keys), count) uniform samples, row i from ship i's key in a counter domain (at reset)."""
    out = np.empty((keys.shape[0], count))
    for i in range(keys.shape[0]):
        for j in range(count):
            out[i, j] = uniform(keys[i], domain + np.uint64(j))
    return out
