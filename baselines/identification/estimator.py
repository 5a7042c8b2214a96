"""The one interface every on-line estimator of this package has."""

from __future__ import annotations

from typing import Protocol

from baselines.identification.history import ParameterHistory
from baselines.identification.log import ExcitationLog


class Estimator(Protocol):
    """Runs over a log sample by sample (on-line) and reports its parameter estimates after each sample.

    Attributes:
        name: what it is, for tables and plots.
        parameter_names: the parameters it reports (:data:`~baselines.identification.history.NOMOTO`
            or :data:`~baselines.identification.history.PERERA`).

    ``run`` raises :class:`~baselines.filter_health.FilterDivergenceError` when the estimator
    diverges and :class:`~baselines.identification.log.ExcitationLogError` for a log it cannot use.
    """

    name: str
    parameter_names: tuple[str, ...]

    def run(self, log: ExcitationLog) -> ParameterHistory: ...
