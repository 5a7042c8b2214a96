"""How a recursive estimator keeps adapting: the parameter covariance before each update.

Without either, the gain of a recursive least-squares or Kalman parameter estimator falls to zero
and it stops following a ship that changes (thesis 4.4.1). Two remedies, compared in stelling 5 of
the thesis ("additive system noise on the parameters is methodologically better founded than a
multiplicative forgetting factor") and in :mod:`ship_env.baselines.online_estimators.adaptation_comparison`:

- :class:`ForgettingFactor`: P(k|k-1) = P(k-1) / lambda, 0 < lambda <= 1 (thesis 4.64; Nguyen's
  (19); Song's alpha): old samples weigh lambda^age, memory about 1 / (1 - lambda) samples;
- :class:`RandomWalk`: P(k|k-1) = P(k-1) + Q_theta, theta(k) = theta(k-1) + w_theta (thesis 4.108):
  the parameters are modelled as drifting, which keeps P from falling to zero in the directions
  the data inform, and lets it grow only linearly in those they do not.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class ForgettingFactor:
    """P(k|k-1) = P(k-1) / ``factor`` (thesis 4.64)."""

    factor: float

    def __post_init__(self) -> None:
        if not 0.0 < self.factor <= 1.0:
            raise ValueError(f"forgetting factor must lie in (0, 1], got {self.factor!r}")

    @property
    def name(self) -> str:
        return f"forgetting {self.factor:g}"

    def predict(self, covariance: np.ndarray) -> np.ndarray:
        return covariance / self.factor


@dataclass(frozen=True)
class RandomWalk:
    """P(k|k-1) = P(k-1) + diag(``variances``): each parameter drifts by white steps of these
    variances per sample (4.108)."""

    variances: tuple[float, ...]

    def __post_init__(self) -> None:
        if any(not (value >= 0.0) for value in self.variances):
            raise ValueError(f"random-walk variances must be non-negative, got {self.variances!r}")

    @classmethod
    def relative(
        cls, density: float, scales: tuple[float, ...], sample_time: float, noise_variance: float = 1.0
    ) -> RandomWalk:
        """Walks whose steps per sample have variance ``density`` x ``sample_time`` x scale^2 (``density``
        in 1/s: the relative drift's spectral density), divided by the estimator's noise variance R
        where its covariance is relative to R (Nguyen's form, R = 1 there)."""
        return cls(tuple(density * sample_time * scale**2 / noise_variance for scale in scales))

    @property
    def name(self) -> str:
        return "random walk"

    def predict(self, covariance: np.ndarray) -> np.ndarray:
        if len(self.variances) != len(covariance):
            raise ValueError(f"random walk of {len(self.variances)} parameters for a covariance of {len(covariance)}")
        return covariance + np.diag(self.variances)


#: Either remedy.
Adaptation = ForgettingFactor | RandomWalk
