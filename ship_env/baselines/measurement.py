"""What the bridge's instruments read at one sample, in SI units and radians.

The environments report these in ``info["measurement"]`` (compass, rate gyro, rudder angle
indicator, log, position fix); every controller and filter of ``baselines`` reads this record,
so the same controller runs on the environments and on a simulator driven directly.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any


@dataclass(frozen=True)
class Measurement:
    """One sample of the instruments (thesis 5.2, Fig. 5.1).

    Attributes:
        heading: compass heading, rad (any branch: the filters unwrap it).
        rate_of_turn: rate gyro, rad/s.
        rudder: actual rudder angle, rad (the rudder angle indicator).
        speed: log speed through the water, m/s.
        north, east: position fix, m; NaN when there is none.
        fix_time: when the fix was taken, s; an environment holds its latest fix between fixes,
            and a fix whose time has been seen before is not a new one. NaN: every finite
            fix is new.
    """

    heading: float
    rate_of_turn: float
    rudder: float
    speed: float
    north: float = math.nan
    east: float = math.nan
    fix_time: float = math.nan

    @classmethod
    def from_info(cls, info: Mapping[str, Any]) -> Measurement:
        """The record from an environment's ``info`` (its ``measurement`` mapping)."""
        reading = info["measurement"]
        return cls(
            heading=float(reading["heading"]),
            rate_of_turn=float(reading["rate_of_turn"]),
            rudder=float(reading["rudder"]),
            speed=float(reading["speed"]),
            north=float(reading.get("north", math.nan)),
            east=float(reading.get("east", math.nan)),
            fix_time=float(reading.get("fix_time", math.nan)),
        )


def wrap_angle(angle: float) -> float:
    """``angle`` wrapped to [-pi, pi)."""
    return (angle + math.pi) % (2.0 * math.pi) - math.pi
