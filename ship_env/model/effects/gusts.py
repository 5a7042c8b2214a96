"""Wind gusts: a zero-mean random component on the relative wind speed (thesis 2.5.3).

The gust g is a first-order Gauss-Markov process (coloured noise) driven by unit white noise w:

    dg/dt = -g / T_g + sigma_g sqrt(2 / T_g) w,      sigma_g = I V_w

so its stationary standard deviation is sigma_g = I V_w (I the turbulence intensity) and its
correlation time T_g. It is added to V_wr before the wind forces are computed.
"""

from __future__ import annotations

import math

from ship_env.model.effect_api import Contribution, Effect, Parameter, State, kernel

EFFECT = Effect(
    "gusts",
    "wind gusts (turbulence on the wind speed)",
    "(2.5.3): stochastic component on V_wr",
    Parameter("intensity", "-", "I, gust standard deviation as a fraction of the true wind speed", minimum=0.0),
    Parameter("time_constant", "s", "T_g, correlation time of the gusts", minimum=1e-6),
)


@kernel
def noise_intensity(wind_speed, intensity, time_constant):
    """sigma_g sqrt(2 / T_g): the intensity of the white noise in dg/dt, 0 in calm air."""
    return intensity * wind_speed * math.sqrt(2.0 / time_constant)


@kernel
def rate(gust, wind_speed, gust_white_noise, intensity, time_constant):
    """dg/dt of the Gauss-Markov gust process."""
    return -gust / time_constant + noise_intensity(wind_speed, intensity, time_constant) * gust_white_noise


@kernel
def gusty_wind(relative_wind_speed, gust):
    """V_wr with the gust on it, never below zero."""
    return max(relative_wind_speed + gust, 0.0)


CONTRIBUTIONS = (Contribution("relative_wind_speed", gusty_wind), Contribution("gust_derivative", rate))
STATES = (
    State("gust", "m/s", "g, the random component on the apparent wind speed (2.5.3)", white_noise=noise_intensity),
)
