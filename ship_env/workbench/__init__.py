"""The measurement workbench: compare the model with measured runs, see where it fails, learn which
physical effect is missing, add it and watch the held-out error fall.

::

    from ship_env.workbench import load_logs, cross_validate, diagnose, improve
    from ship_env.model import ShipModel

    logs = load_logs(["../shared/data/esso_osaka/zigzag"])        # built-in Esso Osaka format
    base = ShipModel("esso_osaka_model", ["yaw", "kinematics"])   # speed-scheduled Nomoto
    validation = cross_validate(base, logs)                        # fit, then leave one run out
    diagnosis = diagnose(validation, logs)                         # the missing effects, ranked
    ladder = improve(base, logs)                                   # add effects while the error falls

Modules: ``formats`` and ``logs`` (reading and checking logs), ``replay`` (the model driven by the
measured inputs), ``terms`` (what can be fitted), ``errors`` (RMS errors and the score), ``fit``
(output-error least squares), ``validation`` (leave one run out), ``diagnose``, ``improve`` (the error ladder),
``compare`` (errors and drawings), ``tables`` and ``report`` (text, Markdown), ``synthetic``
(logs made by the simulator, for checking the workbench on a known truth), ``demo_logs``
(``ship-env demo-logs``: such logs written as CSV with their truth, to try the workbench on).

This is off-line identification for a naval engineer with logs: whole runs, output-error fits,
a ladder of physical effects. The recursive estimators that run sample by sample on board (the
papers' EKF, RLS and MRAS) are the classic baselines' :mod:`ship_env.baselines.online_estimators`.

The names below are imported from their modules when first asked for, so that the command line
parses its arguments before the numerical libraries load. ``ship_env.workbench.fit``,
``.compare``, ``.diagnose`` and ``.improve`` name the functions, as ``from ship_env.workbench
import fit`` does (the modules: ``sys.modules["ship_env.workbench.fit"]``).
"""

from __future__ import annotations

import sys
from typing import TYPE_CHECKING, Any

from ship_env.lazy import FunctionsNamedAsModules as _FunctionsNamedAsModules
from ship_env.lazy import public_name as _public_name

if TYPE_CHECKING:
    from ship_env.workbench.compare import Comparison, compare, held_out_comparison, plot_comparison
    from ship_env.workbench.diagnose import Diagnosis, diagnose
    from ship_env.workbench.errors import ErrorScales, RunErrors
    from ship_env.workbench.fit import FitError, FitOptions, FitResult, fit, fit_each_run
    from ship_env.workbench.formats import ESSO_OSAKA, FORMATS, STANDARD, Column, FormatError, LogFormat
    from ship_env.workbench.improve import Ladder, improve
    from ship_env.workbench.logs import Log, LogError, LogWarning, load_log, load_logs, write_log
    from ship_env.workbench.replay import ReplayModel, simulate
    from ship_env.workbench.report import write_report
    from ship_env.workbench.validation import CrossValidation, cross_validate

#: Each public name's module under ``ship_env.workbench``.
_MODULES: dict[str, str] = {
    **dict.fromkeys(("Comparison", "compare", "held_out_comparison", "plot_comparison"), "compare"),
    **dict.fromkeys(("Diagnosis", "diagnose"), "diagnose"),
    **dict.fromkeys(("ErrorScales", "RunErrors"), "errors"),
    **dict.fromkeys(("FitError", "FitOptions", "FitResult", "fit", "fit_each_run"), "fit"),
    **dict.fromkeys(("ESSO_OSAKA", "FORMATS", "STANDARD", "Column", "FormatError", "LogFormat"), "formats"),
    **dict.fromkeys(("Ladder", "improve"), "improve"),
    **dict.fromkeys(("Log", "LogError", "LogWarning", "load_log", "load_logs", "write_log"), "logs"),
    **dict.fromkeys(("ReplayModel", "simulate"), "replay"),
    "write_report": "report",
    **dict.fromkeys(("CrossValidation", "cross_validate"), "validation"),
}


def __getattr__(name: str) -> Any:
    """A public name from its module, or a submodule (``ship_env.workbench.tables``), imported when
    first asked for."""
    return _public_name(__name__, _MODULES, name)


def __dir__() -> list[str]:
    return sorted({*globals(), *_MODULES})


# The functions fit, compare, diagnose and improve keep their names when their modules are imported.
sys.modules[__name__].__class__ = _FunctionsNamedAsModules

__all__ = [
    "ESSO_OSAKA",
    "FORMATS",
    "STANDARD",
    "Column",
    "Comparison",
    "CrossValidation",
    "Diagnosis",
    "ErrorScales",
    "FitError",
    "FitOptions",
    "FitResult",
    "FormatError",
    "Ladder",
    "Log",
    "LogError",
    "LogFormat",
    "LogWarning",
    "ReplayModel",
    "RunErrors",
    "compare",
    "cross_validate",
    "diagnose",
    "fit",
    "fit_each_run",
    "held_out_comparison",
    "improve",
    "load_log",
    "load_logs",
    "plot_comparison",
    "simulate",
    "write_log",
    "write_report",
]
