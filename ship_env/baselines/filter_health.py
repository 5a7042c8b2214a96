"""Guarding a Kalman filter against bad measurements and against its own divergence.

Each update is checked with the normalised innovation squared (NIS)

    NIS = eps^T S^-1 eps,   S = H P H^T + R

which for a consistent filter is chi-square distributed with m degrees of freedom (m the number
of measurements in the update). An update whose NIS exceeds the chi-square quantile of
``false_alarm`` is an outlier: the filter undoes it (its prior stands) and counts it. ``patience``
outliers in a row mean the filter no longer describes what it measures (a diverged filter, a
failed sensor, a model far from the ship): :class:`FilterDivergenceError` is raised, with the
filter's name, the NIS and the innovation. A missing measurement (NaN) is never an outlier: the
filters leave it out of the update before the check.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np


class FilterDivergenceError(RuntimeError):
    """A filter's innovations stayed far outside their covariance: its estimates cannot be trusted."""


@dataclass
class InnovationGate:
    """The NIS check of one filter (see the module docstring).

    Attributes:
        name: the filter's name, for the report.
        false_alarm: probability that a consistent filter's update is rejected.
        patience: outliers in a row that declare the filter diverged.
        outliers_in_a_row: the current run of rejected updates.
        outliers: rejected updates since the filter started.
        last_nis: NIS of the latest update.
    """

    name: str
    false_alarm: float = 1e-9
    patience: int = 10
    outliers_in_a_row: int = 0
    outliers: int = 0
    last_nis: float = 0.0
    _thresholds: dict[int, float] = field(default_factory=dict, repr=False)

    def threshold(self, dimension: int) -> float:
        """The NIS above which an update of ``dimension`` measurements is an outlier."""
        if dimension not in self._thresholds:
            from scipy.stats import chi2  # here, not at import: scipy.stats takes 1.3 s to import

            self._thresholds[dimension] = float(chi2.isf(self.false_alarm, dimension))
        return self._thresholds[dimension]

    def accepts(self, innovation: np.ndarray, innovation_covariance_inverse: np.ndarray) -> bool:
        """Whether the update stands; raises :class:`FilterDivergenceError` after ``patience`` outliers in a row."""
        innovation = np.asarray(innovation, dtype=float).reshape(-1)
        self.last_nis = float(innovation @ innovation_covariance_inverse @ innovation)
        if self.last_nis <= self.threshold(innovation.size):
            self.outliers_in_a_row = 0
            return True
        self.outliers += 1
        self.outliers_in_a_row += 1
        if self.outliers_in_a_row >= self.patience:
            raise FilterDivergenceError(
                f"{self.name}: {self.outliers_in_a_row} innovations in a row outside the gate "
                f"(NIS {self.last_nis:.3g} > {self.threshold(innovation.size):.3g}); last innovation "
                f"{np.array2string(innovation, precision=4)}"
            )
        return False
