"""A preset's operating point: the conditions it sails in by default, and the ranges a fitted one knows.

A preset may state its **service conditions** (``service_conditions:``), the conditions the ship sails
in on a straight course at its service speed where a :class:`~ship_env.model.Conditions` gives none::

    service_conditions:
      propeller_rate: {value: 10.2, unit: rps, source: "median of the fitted runs' propeller rate"}

A preset without one sails as before (propeller rate 0). ``ship-env fit --preset`` and ``improve
--preset`` write the propeller rate the fitted runs had (:mod:`ship_env.workbench.reporting.presets`): a
slipstream term fitted at 10.2 rps then acts at 10.2 rps in ``Simulator``, the environments, the
manoeuvres and the leaderboard, not at 0 rps where the rudder is weaker.

A fitted preset also records the ranges its runs covered (``fitted.coverage``,
:mod:`ship_env.workbench.judging.coverage`): the propeller rate, ``r* = L |r| / max(u, u_min)``, the drift angle
``|atan2(-v, u)|``, the rudder angle ``|delta|`` and, where the logs measure it, the speed through the water
``u`` (a hard-over turn that slows the ship below the speeds of the zig-zags it was fitted to sails where the
rudder's inflow, the slipstream's share of it and the speed loss were never seen). A
:class:`~ship_env.model.Simulator` sailing it beyond them (:class:`FittedRanges`: the propeller rate where a
ship starts, the others after every step)
warns with a :class:`CoverageWarning` naming the quantity, its value and the range, once per preset
file and quantity in a process (a training loop is not flooded): the model extrapolates there. A
preset without ``fitted.coverage`` (every built-in) never warns. The propeller rate is checked only
where an effect that is on reads it.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from ship_env.model import state as S
from ship_env.model.declarations import Parameter
from ship_env.model.dynamics import sway_velocity
from ship_env.model.kernel import kernel

#: The conditions a preset's ``service_conditions:`` may state, with their units and meaning.
SERVICE_CONDITIONS: tuple[Parameter, ...] = (
    Parameter("propeller_rate", "rps", "n, the propeller rate on a straight course at the service speed"),
)


class CoverageWarning(UserWarning):
    """A fitted preset sailed beyond the ranges its runs covered: the model extrapolates there."""


@dataclass(frozen=True)
class Quantity:
    """A quantity a fit's coverage holds: its name in words, display unit and factor from SI, and whether it
    has a lower limit (a magnitude has none: it reaches down to 0)."""

    words: str
    unit: str
    factor: float
    two_sided: bool

    def value_words(self, value: float, digits: int = 3) -> str:
        """A value in the display unit: '35 deg', '0.62' (r*), to ``digits`` significant digits."""
        return f"{value * self.factor:.{digits}g}" + (f" {self.unit}" if self.unit else "")

    def range_words(self, low: float | None, high: float, digits: int = 3) -> str:
        """A range in the display unit: 'propeller rate 10.1 to 10.3 rps', '|r*| <= 0.35'."""
        unit = f" {self.unit}" if self.unit else ""
        if low is None:
            return f"|{self.words}| <= {high * self.factor:.{digits}g}{unit}"
        return f"{self.words} {low * self.factor:.{digits}g} to {high * self.factor:.{digits}g}{unit}"

    def digits_apart(self, value: float, limit: float) -> int:
        """The fewest significant digits, 3 or more, that show ``value`` and ``limit`` apart (a turn that just
        passes the runs' r* 0.237 reads 'r* 0.2372 beyond |r*| <= 0.2371', not '0.237 beyond 0.237')."""
        for digits in range(3, 17):
            if f"{value * self.factor:.{digits}g}" != f"{limit * self.factor:.{digits}g}":
                return digits
        return 17


#: The quantities of a fit's coverage, by key (:mod:`ship_env.workbench.judging.coverage`).
COVERAGE_QUANTITIES: dict[str, Quantity] = {
    "speed": Quantity("speed", "m/s", 1.0, True),
    "rate": Quantity("r*", "", 1.0, False),
    "drift": Quantity("drift angle", "deg", math.degrees(1.0), False),
    "rudder": Quantity("rudder", "deg", math.degrees(1.0), False),
    "propeller": Quantity("propeller rate", "rps", 1.0, True),
}
#: The motion's quantities a simulator checks after each step: their largest values, then the speed's smallest and
#: largest, in the order of :func:`motion_extremes`'s output.
MOTION_QUANTITIES = ("rate", "drift", "rudder", "speed")
#: The motion's quantities with an upper limit alone (magnitudes).
_MAGNITUDES = MOTION_QUANTITIES[:3]

#: (preset, quantity) pairs warned of in this process.
_WARNED: set[tuple[str, str]] = set()


@kernel
def motion_extremes(states, conditions, record, limits, out):
    """Over the ships, the largest r* = L |r| / max(u, u_min), drift angle |atan2(-v, u)| and rudder angle |delta|,
    and the smallest and largest speed u = U0 (1 - u*) (2.53), written to ``out`` (``MOTION_QUANTITIES``, the
    speed's two last); ``record`` the model's parameter record. Whether any lies beyond ``limits``: the three
    magnitudes' upper limits, then the speed's lower and upper ones."""
    p = record[0]
    out[0] = 0.0
    out[1] = 0.0
    out[2] = 0.0
    out[3] = math.inf
    out[4] = 0.0
    for i in range(states.shape[0]):
        state = states[i]
        speed = conditions[i, S.SERVICE_SPEED] * (1.0 - state[S.SPEED_LOSS])
        out[0] = max(out[0], p["length"] * abs(state[S.RATE_OF_TURN]) / max(speed, p["minimum_speed"]))
        if limits[1] < math.inf and speed >= p["minimum_speed"]:
            out[1] = max(out[1], abs(math.atan2(-sway_velocity(state, conditions[i], p), speed)))
        out[2] = max(out[2], abs(state[S.RUDDER]))
        out[3] = min(out[3], speed)
        out[4] = max(out[4], speed)
    return out[0] > limits[0] or out[1] > limits[1] or out[2] > limits[2] or out[3] < limits[3] or out[4] > limits[4]


@dataclass
class FittedRanges:
    """The ranges a fitted preset's runs covered, checked while it sails (see the module docstring).

    Attributes:
        preset: the preset's file (or name), as the warnings name it.
        ranges: quantity (a key of ``COVERAGE_QUANTITIES``) -> (low or None, high), SI units.
        propeller: whether the propeller rate is checked (an effect that is on reads it).
    """

    preset: str
    ranges: Mapping[str, tuple[float | None, float]]
    propeller: bool = True

    def __post_init__(self) -> None:
        self._motion = np.zeros(len(MOTION_QUANTITIES) + 1)
        self._motion_limits = np.full(len(MOTION_QUANTITIES) + 1, math.inf)
        self._update_limits()

    def _update_limits(self) -> None:
        """The motion's limits still to be warned of (inf, or -inf for the speed's lower one: none, or warned of
        already), in the order of :func:`motion_extremes`'s."""
        for k, quantity in enumerate(_MAGNITUDES):
            self._motion_limits[k] = self.ranges[quantity][1] if self._open(quantity) else math.inf
        low, high = self.ranges["speed"] if self._open("speed") else (None, math.inf)
        self._motion_limits[3] = -math.inf if low is None else low
        self._motion_limits[4] = high

    def _open(self, quantity: str) -> bool:
        return quantity in self.ranges and (self.preset, quantity) not in _WARNED

    @property
    def checking_motion(self) -> bool:
        """Whether any motion quantity is still to be warned of for this preset."""
        return any(self._open(quantity) for quantity in MOTION_QUANTITIES)

    def beyond(self, quantity: str, low: float, high: float) -> list[tuple[float, float]]:
        """Where values from ``low`` to ``high`` (SI) leave ``quantity``'s range: (value, limit) above its upper
        limit, then below its lower one; none inside it or for a quantity the ranges do not hold."""
        if quantity not in self.ranges:
            return []
        covered_low, covered_high = self.ranges[quantity]
        above = [(high, covered_high)] if high > covered_high else []
        return above + ([(low, covered_low)] if covered_low is not None and low < covered_low else [])

    def check(self, quantity: str, low: float, high: float, stacklevel: int = 2) -> None:
        """Warn (once per preset and quantity) where values from ``low`` to ``high`` (SI) leave the range (the
        first of :meth:`beyond`); ``stacklevel`` as ``warnings.warn``'s, counted from this method's caller."""
        if not self._open(quantity) or not (left := self.beyond(quantity, low, high)):
            return
        value, limit = left[0]
        covered_low, covered_high = self.ranges[quantity]
        _WARNED.add((self.preset, quantity))
        words = COVERAGE_QUANTITIES[quantity]
        digits = words.digits_apart(value, limit)
        warnings.warn(
            f"{self.preset}: sailed at {words.words} {words.value_words(value, digits)}, beyond the range its "
            f"fitted runs covered ({words.range_words(covered_low, covered_high, digits)}): the model extrapolates "
            "there (said once per preset and quantity)",
            CoverageWarning,
            stacklevel=stacklevel + 1,
        )

    def check_conditions(self, conditions: np.ndarray) -> None:
        """Check the propeller rate of ships starting in ``conditions`` (rows of the simulator's conditions)."""
        if self.propeller and len(conditions):
            rates = conditions[:, S.PROPELLER_RATE]
            self.check("propeller", float(rates.min()), float(rates.max()), stacklevel=3)  # the reset's caller

    def check_motion(self, states: np.ndarray, conditions: np.ndarray, record: np.ndarray) -> bool:
        """Check the ships' r*, drift, rudder and speed; whether any of them is still to be warned of."""
        if motion_extremes(states, conditions, record, self._motion_limits, self._motion):
            for quantity, value in zip(_MAGNITUDES, self._motion, strict=False):
                self.check(quantity, float(value), float(value), stacklevel=4)  # the step's caller
            self.check("speed", float(self._motion[3]), float(self._motion[4]), stacklevel=4)
            self._update_limits()
            return self.checking_motion
        return True


def fitted_ranges(preset: str, fitted: Mapping[str, Any] | None, propeller: bool) -> FittedRanges | None:
    """The ranges of a preset's ``fitted.coverage`` (None where it states none).

    Raises:
        ValueError: a coverage that is not a fit's, naming the preset and the field.
    """
    coverage = (fitted or {}).get("coverage")
    if coverage is None:
        return None
    ranges: dict[str, tuple[float | None, float]] = {}
    entries = coverage.get("ranges") if isinstance(coverage, Mapping) else None
    if not isinstance(entries, Mapping):
        raise ValueError(f"{preset}: fitted.coverage.ranges: expected a mapping of quantities, got {entries!r}")
    for key, limits in entries.items():
        where = f"{preset}: fitted.coverage.ranges.{key}"
        if key not in COVERAGE_QUANTITIES:
            raise ValueError(f"{where}: unknown quantity; known: {', '.join(COVERAGE_QUANTITIES)}")
        low = limits.get("low") if isinstance(limits, Mapping) else None
        high = limits.get("high") if isinstance(limits, Mapping) else None
        numbers = [value for value in (low, high) if value is not None]
        if high is None or not all(
            isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)
            for value in numbers
        ):
            raise ValueError(f"{where}: expected finite 'low' (or null) and 'high', got {limits!r}")
        ranges[key] = (None if low is None else float(low), float(high))
    return FittedRanges(preset, ranges, propeller)


__all__ = [
    "COVERAGE_QUANTITIES",
    "MOTION_QUANTITIES",
    "SERVICE_CONDITIONS",
    "CoverageWarning",
    "FittedRanges",
    "Quantity",
    "fitted_ranges",
    "motion_extremes",
]
