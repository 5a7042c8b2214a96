"""The first-order Nomoto ship sampled with a held rudder, and its K*, tau* from the discrete pair.

Between samples T_s apart, with the rudder held at its interval value delta(k), T r' + r = K delta
gives exactly (zero-order hold)

    r(k) = a r(k-1) + b delta(k),   a = exp(-T_s / T),   b = K (1 - a)

so K = b / (1 - a), T = -T_s / ln a, and with T = tau* L/u, K = K* u/L (thesis 2.61)

    K* = K L / u,   tau* = T u / L.

(The thesis's yaw filter uses the forward-Euler form a = 1 - T_s/T of (5.4); the two agree to
T_s / (2 T), 0.6 % for the container ship at T_s = 0.5 s. The estimators here regress on the
sampled data, for which the hold form is exact.)
"""

from __future__ import annotations

import math

from ship_env.baselines.nomoto import NomotoParameters


def discrete_pair(parameters: NomotoParameters, sample_time: float, speed: float, length: float) -> tuple[float, float]:
    """(a, b) of the held-rudder model for K*, tau* at ``speed`` m/s and length ``length`` m."""
    time_constant = parameters.time_constant * length / speed
    gain = parameters.gain * speed / length
    a = math.exp(-sample_time / time_constant)
    return a, gain * (1.0 - a)


def nomoto_from_discrete(
    a: float, b: float, sample_time: float, speed: float, length: float
) -> NomotoParameters | None:
    """K*, tau* from (a, b); None where the pair is no stable ship of positive gain (a outside (0, 1), b <= 0)."""
    if not (0.0 < a < 1.0 and b > 0.0 and speed > 0.0):
        return None
    time_constant = -sample_time / math.log(a)
    gain = b / (1.0 - a)
    return NomotoParameters(gain=gain * length / speed, time_constant=time_constant * speed / length)
