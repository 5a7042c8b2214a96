"""The first-order Nomoto model the baselines predict with, in its continuous and discrete forms.

Continuous, speed-scheduled (De Keizer, thesis 5.1 / 2.58, 2.61):

    tau* (L/u) dr/dt + r = K* (u/L) delta                                             (5.1)

Discrete, forward Euler with sample time T_s (5.2, 5.3):

    r(k) = a_s r(k-1) + b_s delta(k-1)                                                (5.3)
    a_s = 1 - (T_s / tau*) (u/L)                                                      (5.4)
    b_s = (K* / tau*) T_s (u/L)^2                                                     (5.5)

Symbols: r rate of turn (rad/s), delta rudder (rad), u forward speed (m/s), L ship length (m),
K* normalised gain, tau* normalised time constant. ``a_s`` and ``b_s`` depend on the speed; the
normalised parameters do not, which is why the filters and the reference model keep these.
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class NomotoParameters:
    """The normalised Nomoto parameters of a ship (5.1).

    Attributes:
        gain: K*, normalised rudder-to-rate-of-turn gain (-).
        time_constant: tau*, normalised time constant in ship lengths (-).
    """

    gain: float
    time_constant: float

    def __post_init__(self) -> None:
        if not (self.gain > 0.0 and self.time_constant > 0.0):
            raise ValueError(
                f"Nomoto parameters must be positive, got K* = {self.gain!r}, tau* = {self.time_constant!r}"
            )

    def discrete(self, sample_time: float, speed: float, length: float) -> tuple[float, float]:
        """(a_s, b_s) of (5.4, 5.5) at forward speed ``speed`` (m/s) and sample time ``sample_time`` (s)."""
        speed_per_length = speed / length
        a_s = 1.0 - sample_time / self.time_constant * speed_per_length
        b_s = self.gain / self.time_constant * sample_time * speed_per_length**2
        return a_s, b_s

    @classmethod
    def from_discrete(cls, a_s: float, b_s: float, sample_time: float, speed: float, length: float) -> NomotoParameters:
        """K*, tau* from (a_s, b_s) by inverting (5.4, 5.5): the recovery of (5.27, 5.28).

        tau* = T_s (u/L) / (1 - a_s),   K* = b_s / ((1 - a_s) (u/L)).
        Raises ``ValueError`` where the discrete pair is no stable positive-gain ship (a_s >= 1 or b_s <= 0).
        """
        speed_per_length = speed / length
        return cls(
            gain=b_s / ((1.0 - a_s) * speed_per_length),
            time_constant=sample_time * speed_per_length / (1.0 - a_s),
        )

    def scaled(self, factor: float) -> NomotoParameters:
        """Both parameters times ``factor`` (the thesis starts its filters at K*/4, tau*/4: 6.3.2)."""
        return NomotoParameters(self.gain * factor, self.time_constant * factor)
