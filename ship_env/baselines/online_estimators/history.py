"""Parameter values over a run: an estimator's estimates, or the truth a simulated log was made with.

The Nomoto estimators report the normalised first-order parameters (K*, tau*) of the speed-scheduled
model (thesis 2.54, 2.61), whatever they estimate inside; Perera's filter reports its five
(a1, a2, a3, b1, b2) of psi''' = a1 psi'^3 + a2 psi' + a3 psi'' + b1 delta + b2 delta' (Perera 13).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

#: The normalised Nomoto parameters K* (gain) and tau* (time constant), thesis (2.54).
NOMOTO = ("K*", "tau*")
#: Perera's five parameters of (13), in the order of their state vector (15).
PERERA = ("a1", "a2", "a3", "b1", "b2")


@dataclass(frozen=True, eq=False)
class ParameterHistory:
    """Parameter values at each sample of a log.

    Attributes:
        names: the parameters, e.g. :data:`NOMOTO`.
        time: t(k), s.
        values: shape (samples, parameters); row k the values after sample k.
        valid: shape (samples,); False where an estimator had no usable estimate (e.g. a discrete
            pair that is no stable ship); such rows hold the last usable values, or the initial
            ones, never NaN.
    """

    names: tuple[str, ...]
    time: np.ndarray
    values: np.ndarray
    valid: np.ndarray

    def __post_init__(self) -> None:
        if self.values.shape != (len(self.time), len(self.names)) or self.valid.shape != self.time.shape:
            raise ValueError(
                f"parameter history: values {self.values.shape} and valid {self.valid.shape} do not fit "
                f"{len(self.time)} samples of {self.names}"
            )

    @classmethod
    def constant(cls, names: tuple[str, ...], time: np.ndarray, values: tuple[float, ...]) -> ParameterHistory:
        """The same values at every sample (a simulated ship that does not change)."""
        return cls(names, time, np.tile(np.asarray(values, dtype=float), (len(time), 1)), np.ones(len(time), bool))

    def final(self) -> dict[str, float]:
        """The values after the last sample."""
        return dict(zip(self.names, map(float, self.values[-1]), strict=True))


class HistoryRecorder:
    """Collects an estimator's estimates sample by sample into a :class:`ParameterHistory`.

    ``record(k, values)`` with ``values`` None marks sample k invalid and repeats the last usable
    values (the initial ones before the first).
    """

    def __init__(self, names: tuple[str, ...], time: np.ndarray, initial: tuple[float, ...]) -> None:
        self.names = names
        self.time = time
        self.values = np.empty((len(time), len(names)))
        self.valid = np.zeros(len(time), dtype=bool)
        self._last = np.asarray(initial, dtype=float)

    def record(self, k: int, values: tuple[float, ...] | np.ndarray | None) -> None:
        if values is not None:
            self._last = np.asarray(values, dtype=float)
            self.valid[k] = True
        self.values[k] = self._last

    def history(self) -> ParameterHistory:
        return ParameterHistory(self.names, self.time, self.values, self.valid)
