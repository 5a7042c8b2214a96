"""Checking the environments' keyword arguments and reset options: one message style for all."""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np


def check_number(name: str, value: object, minimum: float = -math.inf, maximum: float = math.inf) -> float:
    """``value`` as a float; ``TypeError`` if it is not a number, ``ValueError`` if outside [minimum, maximum]."""
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise TypeError(f"{name}: expected a number, got {value!r}")
    if not (math.isfinite(value) and minimum <= value <= maximum):
        raise ValueError(f"{name}: expected a finite number in [{minimum}, {maximum}], got {value!r}")
    return float(value)


def check_whole_number(name: str, value: object, minimum: int) -> int:
    """``value`` as an int; ``ValueError`` unless it is a whole number of at least ``minimum``."""
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < minimum:
        raise ValueError(f"{name}: expected a whole number of at least {minimum}, got {value!r}")
    return int(value)


def check_range(name: str, value: object, minimum: float = 0.0) -> tuple[float, float]:
    """``value`` as (low, high) with minimum <= low <= high."""
    if not isinstance(value, Sequence) or isinstance(value, str) or len(value) != 2:
        raise TypeError(f"{name}: expected (low, high), got {value!r}")
    low = check_number(f"{name}[0]", value[0], minimum)
    high = check_number(f"{name}[1]", value[1], low)
    return low, high


def check_choice(name: str, value: object, choices: Sequence[str]) -> str:
    """``value`` if it is one of ``choices``, else ``ValueError`` listing them."""
    if value not in choices:
        raise ValueError(f"{name}: expected one of {', '.join(choices)}, got {value!r}")
    return str(value)
