"""An effect that draws random numbers where a ship starts, written outside ship_env: a swell's yaw.

A long swell yaws the ship with a few sinusoids. Their frequencies lie in equal bands from 0.8 to
1.2 times the swell's peak frequency 2 pi / T_p (the sea state the ship starts in), each at random
within its band, and their phases are random; each ship draws both where it starts, from its seed:

    dr/dt += a / n sum_i sin(omega_i t + phi_i)
"""

from __future__ import annotations

import math

import numpy as np

from ship_env.model.effect_api import Contribution, Draw, Effect, Parameter

EFFECT = Effect(
    "swell_yaw",
    "yaw from a long swell of random phases",
    "dr/dt = a / n sum_i sin(omega_i t + phi_i)",
    Parameter("amplitude", "rad/s^2", "a, the swell's yaw acceleration", 0.0, 1e-3, default=2e-5, source="assumed"),
    Parameter("count", "-", "n, the number of sinusoids", 1, 16, integer=True, default=3, source="assumed"),
)


def sinusoids(uniforms, wave_period):
    """Each ship's sinusoids from its uniforms (ships, 2, n): frequencies (rad/s), then phases (rad)."""
    count = uniforms.shape[-1]
    peak = 2.0 * math.pi / wave_period[:, np.newaxis]
    frequency = peak * (0.8 + 0.4 * (np.arange(count) + uniforms[:, 0]) / count)
    return np.stack([frequency, 2.0 * math.pi * uniforms[:, 1]], axis=1)


def swell_yaw(time, swell, amplitude):
    """The added dr/dt, rad/s^2."""
    total = 0.0
    for i in range(swell.shape[1]):
        total += math.sin(swell[0, i] * time + swell[1, i])
    return amplitude * total / swell.shape[1]


CONTRIBUTIONS = (Contribution("yaw_acceleration", swell_yaw),)
DRAWS = (Draw("swell", "rad/s, rad", "the swell's sinusoids: frequency and phase of each", (2, "count"), sinusoids),)
