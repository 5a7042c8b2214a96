"""What every manoeuvre returns: its figures, the ship's length and speed, and the time series.

A result is a frozen dataclass holding the figures in SI units and radians (the package's
convention), plus the recorded time series. :meth:`ManoeuvreResult.figures` gives the same
figures as a reader expects them in a trial report: degrees, metres, seconds and ship lengths
where the IMO criteria (MSC.137(76) 5.3) use them.
"""

from __future__ import annotations

import math
import re
from abc import ABC, abstractmethod
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, ClassVar, TypeVar

import pandas as pd

from ship_env.model.declarations import UNIT_CONVERSIONS

if TYPE_CHECKING:
    from ship_env.manoeuvres.settings import TrialSettings
    from ship_env.model import ShipModel

#: One knot in m/s, for speeds shown in knots.
KNOT: float = UNIT_CONVERSIONS["kn"][1]

#: Columns of every manoeuvre's time series, one row per sample and run. ``run`` names the ship
#: (``"20 deg stbd"``: a batched manoeuvre has several); angles are in rad, positions in m north and
#: east of the first execute, time in s from it, speed is the forward speed u in m/s.
TIME_SERIES_COLUMNS: tuple[str, ...] = (
    "run",
    "time",
    "north",
    "east",
    "heading",
    "rate_of_turn",
    "rudder",
    "ordered_rudder",
    "speed",
)


@dataclass(frozen=True)
class Figure:
    """One reported figure in display units.

    Attributes:
        key: a stable identifier (``"tactical_diameter_lengths"``), used in JSON output.
        label: the words in a report ("tactical diameter").
        value: the number, or a word for a yes/no figure.
        unit: the display unit ("L", "deg", "deg/s", "m", "s", "%", "" for words).
        digits: decimals to print.
    """

    key: str
    label: str
    value: float | str
    unit: str
    digits: int = 1

    @property
    def text(self) -> str:
        """The value as printed: rounded, ``"n/a"`` when the event was not reached."""
        if isinstance(self.value, str):
            return self.value
        return fixed(self.value, self.digits)

    def text_with_error(self, error: float | None) -> str:
        """:attr:`text` with "+-" its standard error where one is given, finite and not 0 (a figure every fold of a
        fit sails alike, such as the rudder); a word has none."""
        if error is None or not math.isfinite(error) or error == 0.0 or isinstance(self.value, str):
            return self.text
        return f"{self.text} +-{fixed(error, self.digits)}"


Result = TypeVar("Result", bound="ManoeuvreResult")


@dataclass(frozen=True)
class ManoeuvreResult(ABC):
    """Fields every manoeuvre result has.

    Attributes:
        ship: the ship preset's name.
        length: L, the ship's length, m (the IMO figures are given in multiples of it).
        approach_speed: V, the steady speed before the first execute, m/s (the IMO test speed).
        time_series: the recorded runs, columns :data:`TIME_SERIES_COLUMNS`.
    """

    #: The manoeuvre's name ("turning circle").
    manoeuvre: ClassVar[str]

    ship: str
    length: float
    approach_speed: float
    time_series: pd.DataFrame = field(compare=False, repr=False)

    @classmethod
    def sailed(
        cls: type[Result], model: ShipModel, settings: TrialSettings, time_series: pd.DataFrame, **figures: Any
    ) -> Result:
        """The result of ``model`` sailed in ``settings``: the fields every result has, then ``figures``."""
        return cls(
            ship=model.ship.name,
            length=model.length,
            approach_speed=settings.approach_speed(model),
            time_series=time_series,
            **figures,
        )

    @property
    @abstractmethod
    def label(self) -> str:
        """What tells this run from others of its kind ("35 deg stbd", "10/10"); may be empty."""

    @property
    def title(self) -> str:
        """The manoeuvre and its label ("turning circle 35 deg stbd")."""
        return f"{self.manoeuvre} {self.label}".strip()

    @property
    def slug(self) -> str:
        """A file-name stem for this result ("turning_circle_35_deg_stbd")."""
        return re.sub(r"[^0-9A-Za-z.+-]+", "_", self.title)

    @abstractmethod
    def figures(self) -> tuple[Figure, ...]:
        """The figures in display units, in report order."""


def fixed(value: float, digits: int) -> str:
    """``value`` with ``digits`` decimals, "n/a" for NaN, and no "-0.00" for a tiny negative number."""
    if math.isnan(value):
        return "n/a"
    return f"{round(value, digits) + 0.0:.{digits}f}"


def metre_digits(length: float) -> int:
    """Decimals that show a distance on a ship of ``length`` m to about a hundredth of its length."""
    return max(0, 2 - math.floor(math.log10(length)))


def degrees_label(angle: float) -> str:
    """An angle in rad as a short signed label in whole or decimal degrees ("35", "-12.5")."""
    return f"{math.degrees(angle):g}"
