"""The IMO manoeuvrability criteria (MSC.137(76) 5.3), checked on manoeuvre results.

- 5.3.1 turning ability: in the turning circle with 35 deg rudder the advance should not exceed
  4.5 L and the tactical diameter 5 L;
- 5.3.2 initial turning ability: with 10 deg rudder the ship should not have travelled more than
  2.5 L by the time the heading has changed 10 deg (read from the 10/10 zig-zag's first swing);
- 5.3.3.1 the first overshoot of the 10/10 zig-zag should not exceed 10 deg if L/V < 10 s,
  20 deg if L/V >= 30 s, and 5 + (L/V)/2 deg in between;
- 5.3.3.2 its second overshoot should not exceed 25 deg, 40 deg and 17.5 + 0.75 L/V deg likewise;
- 5.3.3.3 the first overshoot of the 20/20 zig-zag should not exceed 25 deg.

L is the ship's length (m) and V the test speed (m/s), the approach speed of the trial. Values and
limits are held in the criteria's own units, degrees and ship lengths.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass
from typing import TypeGuard

from ship_env.manoeuvres.results import ManoeuvreResult
from ship_env.manoeuvres.turning_circle import TurningCircle
from ship_env.manoeuvres.zigzag import ZigZag


@dataclass(frozen=True)
class CriterionCheck:
    """One criterion applied to one result.

    Attributes:
        clause: the paragraph of MSC.137(76) ("5.3.1").
        description: what is checked, on which run ("tactical diameter, turning circle 35 deg stbd").
        value: the ship's figure, in ``unit``.
        limit: the largest value the criterion allows, in ``unit``.
        unit: "L" or "deg".
    """

    clause: str
    description: str
    value: float
    limit: float
    unit: str

    @property
    def passed(self) -> bool:
        """Whether the figure does not exceed the limit (a figure not reached fails)."""
        return self.value <= self.limit


def first_overshoot_limit_10_10(length: float, speed: float) -> float:
    """The largest first overshoot of the 10/10 zig-zag, deg (MSC.137(76) 5.3.3.1)."""
    return min(max(5.0 + 0.5 * length / speed, 10.0), 20.0)


def second_overshoot_limit_10_10(length: float, speed: float) -> float:
    """The largest second overshoot of the 10/10 zig-zag, deg (MSC.137(76) 5.3.3.2)."""
    return min(max(17.5 + 0.75 * length / speed, 25.0), 40.0)


def _is_angle(angle: float, degrees: float) -> bool:
    """Whether an angle in rad is ``degrees`` to either side."""
    return math.isclose(abs(angle), math.radians(degrees), rel_tol=1e-9)


def _is_zigzag(result: ManoeuvreResult, degrees: float) -> TypeGuard[ZigZag]:
    """Whether ``result`` is the zig-zag test degrees/degrees, to either side."""
    return (
        isinstance(result, ZigZag)
        and _is_angle(result.rudder_angle, degrees)
        and _is_angle(result.heading_change, degrees)
    )


def _turning_checks(circle: TurningCircle) -> list[CriterionCheck]:
    """5.3.1: advance and tactical diameter of the 35 deg turning circle."""
    return [
        CriterionCheck("5.3.1", f"advance, {circle.title}", circle.advance / circle.length, 4.5, "L"),
        CriterionCheck(
            "5.3.1", f"tactical diameter, {circle.title}", circle.tactical_diameter / circle.length, 5.0, "L"
        ),
    ]


def _zigzag_10_10_checks(test: ZigZag) -> list[CriterionCheck]:
    """5.3.2 from the first swing, 5.3.3.1 and 5.3.3.2 from the overshoots of the 10/10 zig-zag."""
    length, speed = test.length, test.approach_speed
    return [
        CriterionCheck(
            "5.3.2",
            f"distance to 10 deg heading change, {test.title}",
            test.initial_turning_distance / length,
            2.5,
            "L",
        ),
        CriterionCheck(
            "5.3.3.1",
            f"first overshoot, {test.title}",
            math.degrees(test.first_overshoot),
            first_overshoot_limit_10_10(length, speed),
            "deg",
        ),
        CriterionCheck(
            "5.3.3.2",
            f"second overshoot, {test.title}",
            math.degrees(test.second_overshoot),
            second_overshoot_limit_10_10(length, speed),
            "deg",
        ),
    ]


def _zigzag_20_20_checks(test: ZigZag) -> list[CriterionCheck]:
    """5.3.3.3: first overshoot of the 20/20 zig-zag."""
    return [
        CriterionCheck("5.3.3.3", f"first overshoot, {test.title}", math.degrees(test.first_overshoot), 25.0, "deg")
    ]


def check_criteria(results: Iterable[ManoeuvreResult]) -> list[CriterionCheck]:
    """The MSC.137(76) 5.3 criteria that apply to the given results, one check per figure and run."""
    checks: list[CriterionCheck] = []
    for result in results:
        if isinstance(result, TurningCircle) and _is_angle(result.rudder_angle, 35.0):
            checks += _turning_checks(result)
        elif _is_zigzag(result, 10.0):
            checks += _zigzag_10_10_checks(result)
        elif _is_zigzag(result, 20.0):
            checks += _zigzag_20_20_checks(result)
    return checks
