"""Standard manoeuvres and their IMO figures (MSC.137(76), MSC/Circ.1053).

Each manoeuvre sails the simulator from a steady straight approach in calm water and returns a
frozen dataclass of figures (SI units, radians) with the recorded time series::

    from ship_env.model import ShipModel
    from ship_env.manoeuvres import turning_circle, zigzag, check_criteria

    model = ShipModel("container_226m")
    circle = turning_circle(model)                       # 35 deg to starboard
    circle.tactical_diameter / circle.length             # in ship lengths
    check_criteria([circle, zigzag(model)])              # MSC.137(76) 5.3
"""

from typing import Any

from ship_env.manoeuvres.imo import CriterionCheck, check_criteria
from ship_env.manoeuvres.pull_out import PullOut, pull_out
from ship_env.manoeuvres.report import format_report, report_dict, ship_line
from ship_env.manoeuvres.results import TIME_SERIES_COLUMNS, Figure, ManoeuvreResult
from ship_env.manoeuvres.settings import TrialSettings
from ship_env.manoeuvres.spiral import SpiralTest, reversed_spiral
from ship_env.manoeuvres.turning_circle import TurningCircle, turning_circle
from ship_env.manoeuvres.zigzag import ZigZag, zigzag

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
    """``plot_manoeuvre``, imported on first use: it needs matplotlib, which sailing a manoeuvre (the
    TrackFollow environment's arcs are turning circles) does not wait for."""
    if name == "plot_manoeuvre":
        from ship_env.manoeuvres.plotting import plot_manoeuvre

        return plot_manoeuvre
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted({*globals(), "plot_manoeuvre"})
