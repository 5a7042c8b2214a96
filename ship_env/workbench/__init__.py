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

Its modules are in subpackages by stage, in order: ``logs`` (``formats`` and ``logs``: reading and
checking logs), ``fitting`` (``replay``, the model driven by the measured inputs; ``terms``, what can
be fitted; ``errors``, the RMS errors and the score; ``envelope`` and ``runs``, where the model holds;
``fit``, output-error least squares; ``threads`` and ``parallel``; ``smoothing`` and
``inverse_dynamics``, the MMG standard's 3-DOF forces fitted by equation error), ``judging`` (``coverage``,
``validation`` leaving one run out, ``materiality``, ``bands``, ``compare`` and ``free_running``),
``deciding`` (``signals``, ``diagnose`` and ``improve``, the error ladder), ``reporting``
(``tables``, ``report``, ``documents`` and ``presets``) and ``synthetic`` (``synthetic``, logs made
by the simulator, for checking the workbench on a known truth; ``demo_logs``, ``ship-env
demo-logs``). A stage imports only from the stages before it, and from ``defaults`` and ``outputs``
here; the commands (``cli`` and ``cli_fit``, ``cli_fit_mmg``, ``cli_compare``, ``cli_diagnose``,
``cli_improve``) from every stage.

This is off-line identification for a naval engineer with logs: whole runs, output-error fits,
a ladder of physical effects. The recursive estimators that run sample by sample on board (the
papers' EKF, RLS and MRAS) are the classic baselines' :mod:`ship_env.baselines.online_estimators`.

The names below are imported from their modules when first asked for, so that the command line
parses its arguments before the numerical libraries load. ``ship_env.workbench.fit``,
``.compare``, ``.diagnose`` and ``.improve`` are the functions (their modules are
``ship_env.workbench.fitting.fit``, ``.judging.compare``, ``.deciding.diagnose`` and ``.deciding.improve``).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from ship_env.lazy import public_name as _public_name

if TYPE_CHECKING:
    from ship_env.workbench.deciding.diagnose import Diagnosis, diagnose
    from ship_env.workbench.deciding.improve import Ladder, improve
    from ship_env.workbench.fitting.errors import ErrorScales, RunErrors
    from ship_env.workbench.fitting.fit import FitError, FitOptions, FitResult, fit, fit_each_run
    from ship_env.workbench.fitting.replay import ReplayModel, simulate
    from ship_env.workbench.judging.compare import Comparison, compare, held_out_comparison, plot_comparison
    from ship_env.workbench.judging.validation import CrossValidation, cross_validate
    from ship_env.workbench.logs.formats import ESSO_OSAKA, FORMATS, STANDARD, Column, FormatError, LogFormat
    from ship_env.workbench.logs.logs import Log, LogError, LogWarning, load_log, load_logs, write_log
    from ship_env.workbench.reporting.report import write_report

#: Each public name's module under ``ship_env.workbench`` (none of them a module's name there).
_MODULES: dict[str, str] = {
    **dict.fromkeys(("Comparison", "compare", "held_out_comparison", "plot_comparison"), "judging.compare"),
    **dict.fromkeys(("Diagnosis", "diagnose"), "deciding.diagnose"),
    **dict.fromkeys(("ErrorScales", "RunErrors"), "fitting.errors"),
    **dict.fromkeys(("FitError", "FitOptions", "FitResult", "fit", "fit_each_run"), "fitting.fit"),
    **dict.fromkeys(("ESSO_OSAKA", "FORMATS", "STANDARD", "Column", "FormatError", "LogFormat"), "logs.formats"),
    **dict.fromkeys(("Ladder", "improve"), "deciding.improve"),
    **dict.fromkeys(("Log", "LogError", "LogWarning", "load_log", "load_logs", "write_log"), "logs.logs"),
    **dict.fromkeys(("ReplayModel", "simulate"), "fitting.replay"),
    "write_report": "reporting.report",
    **dict.fromkeys(("CrossValidation", "cross_validate"), "judging.validation"),
}


def __getattr__(name: str) -> Any:
    """A public name from its module, or a subpackage or command module (``ship_env.workbench.reporting``),
    imported when first asked for."""
    return _public_name(__name__, _MODULES, name)


def __dir__() -> list[str]:
    return sorted({*globals(), *_MODULES})


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
