"""The one interface every on-line estimator of this package has."""

from __future__ import annotations

from typing import Protocol

from ship_env.baselines.online_estimators.history import ParameterHistory
from ship_env.baselines.online_estimators.log import ExcitationLog


class Estimator(Protocol):
    """Runs over a log sample by sample (on-line) and reports its parameter estimates after each sample.

    Attributes:
        name: what it is, for tables and plots.
        parameter_names: the parameters it reports (:data:`~ship_env.baselines.online_estimators.history.NOMOTO`
            or :data:`~ship_env.baselines.online_estimators.history.PERERA`).

    ``run`` raises :class:`~ship_env.baselines.filter_health.FilterDivergenceError` when the estimator
    diverges and :class:`~ship_env.baselines.online_estimators.log.ExcitationLogError` for a log it cannot use.
    """

    @property
    def name(self) -> str: ...

    @property
    def parameter_names(self) -> tuple[str, ...]: ...

    def run(self, log: ExcitationLog) -> ParameterHistory: ...
