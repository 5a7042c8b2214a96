"""Wave yaw moment from a Pierson-Moskowitz sea (thesis 2.89-2.91).

The sea is a sum of regular wave components drawn from the spectrum

    S(omega) = A omega^-p exp(-B omega^-q),  p = 5, q = 4                           (2.89)
    A = 5/16 H_s^2 omega_p^4,  B = 5/4 omega_p^4,  omega_p = 2 pi / T_p

(the Pierson-Moskowitz / Bretschneider form for significant height H_s and peak period T_p).
Component i has amplitude a_i = sqrt(2 S(omega_i) d omega), wave number k_i = omega_i^2 / g (deep
water) and a random phase. The ship meets it at its own position, so the excitation has the
encounter frequency

    omega_e = omega_0 - omega_0^2 U cos(gamma_w) / g                                 (2.90)

without it being imposed. Its yaw excitation is

    N_g = H_g(omega) sin(2 gamma_w)                                                  (2.91)

with H_g taken proportional to the wave slope k_i a_i: dr/dt += c_g sum_i k_i a_i
cos(omega_i t - k_i (x0 cos beta + y0 sin beta) + phi_i) sin(2 gamma_w), beta the direction the
waves travel towards and gamma_w = psi - beta. Unlike ``wave_filter`` it moves the track a little.

Each ship draws its sea where it starts (``DRAWS``): the components' frequencies and phases from its
seed, their amplitudes from the spectrum of the sea state it starts in (``Conditions.wave_height``
and ``wave_period``).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike

from ship_env.model.effect_api import Contribution, Draw, Effect, Parameter, kernel

GRAVITY = 9.81  # m/s^2

EFFECT = Effect(
    "wave_spectrum",
    "wave yaw moment from a wave spectrum (encounter frequency, sin 2 gamma_w)",
    "(2.89)-(2.91)",
    Parameter("yaw_coefficient", "rad/s^2", "c_g, yaw acceleration per radian of wave slope", minimum=0.0),
    Parameter("components", "-", "number of regular wave components", minimum=1, maximum=256, integer=True),
)


def spectral_density(
    frequency: np.ndarray, significant_height: float | np.ndarray, peak_period: float | np.ndarray
) -> np.ndarray:
    """S(omega) of (2.89) with p = 5, q = 4, in m^2 s/rad."""
    peak_frequency = 2.0 * math.pi / peak_period
    a = 5.0 / 16.0 * significant_height**2 * peak_frequency**4
    b = 5.0 / 4.0 * peak_frequency**4
    return a * frequency**-5.0 * np.exp(-b * frequency**-4.0)


def components(wave_height: ArrayLike, wave_period: ArrayLike, uniforms: np.ndarray) -> np.ndarray:
    """Regular wave components of Pierson-Moskowitz seas, one per pair of uniform samples.

    Frequencies lie in equal bands from 0.6 to 3 times the peak frequency, each placed at random
    within its band (so the sum does not repeat itself), with random phases. Works for one sea or
    for a batch of seas at once (leading dimensions broadcast).

    Args:
        wave_height: H_s, the significant wave height, m (a number, or an array of the batch's shape).
        wave_period: T_p, the peak period, s (likewise).
        uniforms: (..., 2, count) samples in (0, 1): the places in the bands and the phases.

    Returns:
        array of shape (..., 3, count): frequency (rad/s), amplitude (m), phase (rad).
    """
    count = uniforms.shape[-1]
    height = np.asarray(wave_height, dtype=float)[..., np.newaxis]
    period = np.asarray(wave_period, dtype=float)[..., np.newaxis]
    peak_frequency = 2.0 * math.pi / period
    band = 2.4 * peak_frequency / count
    frequency = 0.6 * peak_frequency + band * (np.arange(count) + uniforms[..., 0, :])
    amplitude = np.sqrt(2.0 * spectral_density(frequency, height, period) * band)
    phase = 2.0 * math.pi * uniforms[..., 1, :]
    return np.stack([frequency, amplitude, phase], axis=-2)


@kernel
def encounter_frequency(frequency, speed, encounter_angle):
    """omega_e of (2.90); encounter_angle gamma_w is 0 in following seas."""
    return frequency - frequency * frequency * speed * math.cos(encounter_angle) / GRAVITY


@kernel
def yaw_acceleration(time, north, east, heading, wave_direction, waves, yaw_coefficient):
    """Added dr/dt in rad/s^2 from (2.91), summed over the components in ``waves`` (3, count)."""
    travel_direction = wave_direction + math.pi
    cos_travel = math.cos(travel_direction)
    sin_travel = math.sin(travel_direction)
    slope = 0.0
    for i in range(waves.shape[1]):
        frequency = waves[0, i]
        wave_number = frequency * frequency / GRAVITY
        phase = frequency * time - wave_number * (north * cos_travel + east * sin_travel) + waves[2, i]
        slope += wave_number * waves[1, i] * math.cos(phase)
    return yaw_coefficient * slope * math.sin(2.0 * (heading - travel_direction))


#: The sea's excitation is evaluated once per step, at mid-step, and held over it: a sum over many
#: components is too costly for every Runge-Kutta stage.
CONTRIBUTIONS = (Contribution("yaw_acceleration", yaw_acceleration, held=True),)
DRAWS = (
    Draw(
        "waves",
        "rad/s, m, rad",
        "the sea the ship meets: frequency, amplitude and phase of each regular component",
        (3, "components"),
        components,
        uniforms=(2, "components"),
    ),
)
