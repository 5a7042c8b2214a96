"""Standard manoeuvres and their IMO figures (MSC.137(76), MSC/Circ.1053).

Each manoeuvre sails the simulator from a steady straight approach in calm water and returns a
frozen dataclass of figures (SI units, radians) with the recorded time series::

    from ship_env.model import ShipModel
    from ship_env.manoeuvres import turning_circle, zigzag, check_criteria

    model = ShipModel("container_226m")
    circle = turning_circle(model)                       # 35 deg to starboard
    circle.tactical_diameter / circle.length             # in ship lengths
    check_criteria([circle, zigzag(model)])              # MSC.137(76) 5.3

The names here are imported from their modules when first asked for.
"""

from __future__ import annotations

import sys
from typing import TYPE_CHECKING, Any

from ship_env.lazy import FunctionsNamedAsModules as _FunctionsNamedAsModules
from ship_env.lazy import public_name as _public_name

if TYPE_CHECKING:
    from ship_env.manoeuvres.imo import CriterionCheck, check_criteria
    from ship_env.manoeuvres.plotting import plot_manoeuvre
    from ship_env.manoeuvres.pull_out import PullOut, pull_out
    from ship_env.manoeuvres.report import format_report, report_dict, ship_line
    from ship_env.manoeuvres.results import TIME_SERIES_COLUMNS, Figure, ManoeuvreResult
    from ship_env.manoeuvres.settings import TrialSettings
    from ship_env.manoeuvres.spiral import SpiralTest, reversed_spiral
    from ship_env.manoeuvres.turning_circle import TurningCircle, turning_circle
    from ship_env.manoeuvres.zigzag import ZigZag, zigzag

#: Each public name's module under ``ship_env.manoeuvres``.
_MODULES: dict[str, str] = {
    **dict.fromkeys(("CriterionCheck", "check_criteria"), "imo"),
    "plot_manoeuvre": "plotting",
    **dict.fromkeys(("PullOut", "pull_out"), "pull_out"),
    **dict.fromkeys(("format_report", "report_dict", "ship_line"), "report"),
    **dict.fromkeys(("TIME_SERIES_COLUMNS", "Figure", "ManoeuvreResult"), "results"),
    "TrialSettings": "settings",
    **dict.fromkeys(("SpiralTest", "reversed_spiral"), "spiral"),
    **dict.fromkeys(("TurningCircle", "turning_circle"), "turning_circle"),
    **dict.fromkeys(("ZigZag", "zigzag"), "zigzag"),
}

__all__ = [
    "TIME_SERIES_COLUMNS",
    "CriterionCheck",
    "Figure",
    "ManoeuvreResult",
    "PullOut",
    "SpiralTest",
    "TrialSettings",
    "TurningCircle",
    "ZigZag",
    "check_criteria",
    "format_report",
    "plot_manoeuvre",
    "pull_out",
    "report_dict",
    "reversed_spiral",
    "ship_line",
    "turning_circle",
    "zigzag",
]


def __getattr__(name: str) -> Any:
    """A public name from its module, or a submodule (``ship_env.manoeuvres.trial``), imported when first
    asked for: ``ship-env manoeuvre --help`` answers before pandas loads, and sailing a manoeuvre (the
    TrackFollow environment's arcs are turning circles) does not wait for matplotlib."""
    return _public_name(__name__, _MODULES, name)


def __dir__() -> list[str]:
    return sorted({*globals(), *_MODULES})


# The functions pull_out, turning_circle and zigzag keep their names when their modules are imported.
sys.modules[__name__].__class__ = _FunctionsNamedAsModules
