"""High-frequency wave yaw, added to the measured heading and rate of turn (thesis Figs. 2.13, 2.14).

Waves make the ship yaw at a high frequency without moving its track (2.5.4). For simulation the
thesis adds a wave signal to the undisturbed rate of turn, made by a second-order shaping filter
driven by white noise w (Fig. 2.14). Written for the wave heading psi_g and wave rate r_g = dpsi_g/dt:

    d^2 psi_g/dt^2 + 2 zeta omega_n dpsi_g/dt + omega_n^2 psi_g = k w
    k = sigma_r sqrt(4 zeta omega_n)

so r_g has the band-pass spectrum k^2 omega^2 / ((omega_n^2 - omega^2)^2 + (2 zeta omega_n omega)^2),
which peaks at omega_n, and its standard deviation is sigma_r. The measured heading is psi + psi_g
and the measured rate of turn r + r_g; the track (2.64, 2.65) uses the undisturbed psi.
"""

from __future__ import annotations

import math

from ship_env.model.effect_api import Contribution, Effect, Parameter, State, kernel

EFFECT = Effect(
    "wave_filter",
    "wave-induced high-frequency yaw on the measured heading (shaping filter)",
    "Figs. 2.13, 2.14",
    Parameter("natural_frequency", "rad/s", "omega_n, the filter's natural (peak) frequency", minimum=1e-6),
    Parameter("damping", "-", "zeta, the filter's relative damping", minimum=1e-6),
    Parameter("rate_rms", "rad/s", "sigma_r, standard deviation of the wave-induced rate of turn", minimum=0.0),
)


@kernel
def noise_gain(natural_frequency, damping, rate_rms):
    """k = sigma_r sqrt(4 zeta omega_n), the intensity of the white noise in d r_g / dt."""
    return rate_rms * math.sqrt(4.0 * damping * natural_frequency)


@kernel
def acceleration(wave_heading, wave_rate, wave_rate_white_noise, natural_frequency, damping, rate_rms):
    """d r_g / dt of the shaping filter (Fig. 2.14)."""
    return (
        -natural_frequency * natural_frequency * wave_heading
        - 2.0 * damping * natural_frequency * wave_rate
        + noise_gain(natural_frequency, damping, rate_rms) * wave_rate_white_noise
    )


@kernel
def heading_rate(wave_rate):
    """d psi_g / dt: the wave heading moves at the wave rate of turn."""
    return wave_rate


CONTRIBUTIONS = (
    Contribution("wave_heading_derivative", heading_rate),
    Contribution("wave_rate_derivative", acceleration),
)
STATES = (
    State("wave_heading", "rad", "psi_g, the HF wave-induced heading on the compass (Fig. 2.13)"),
    State("wave_rate", "rad/s", "r_g, the HF wave-induced rate of turn (Fig. 2.13)", white_noise=noise_gain),
)
