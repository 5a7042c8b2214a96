"""The workbench's settings its commands offer as choices and defaults (nuisance terms, stretches,
gains), in a module light enough for ``ship-env fit --help`` and a mistyped option to answer before
the fitting's numerical libraries load; the modules that use them import them from here."""

from __future__ import annotations

import math

from ship_env.model import state as S

#: Per-run nuisance terms: name -> (state index, scale, bound), SI units.
NUISANCE: dict[str, tuple[int, float, float]] = {
    "heading": (S.HEADING, math.radians(1.0), math.radians(45.0)),
    "rate_of_turn": (S.RATE_OF_TURN, math.radians(0.1), math.radians(10.0)),
}
#: Shortest stretch inside the envelope kept as a segment, s.
MIN_SEGMENT = 10.0
#: Smallest relative fall of the held-out score for which an effect is added.
MIN_GAIN = 0.05
#: Where no single effect pays, pairs of this many candidates (those with most evidence) are tried.
PAIR_WIDTH = 4

#: Effects a ladder (``diagnose``, ``improve``) tries only where asked by name (``--candidates``), and why not by
#: default.
ON_REQUEST: dict[str, str] = {
    "drift_resistance": (
        "tried only where named (--candidates): its forcing -v r* is (2.55)'s r*^2 times gamma1* wherever the drift "
        "has settled, so on the basin truth's zig-zags its residual evidence ranked it among the four strongest while "
        "its refit went to its null, and it crowded the pair that the ladder would add out of the pairs it tries "
        "(docs/results/free_running.md)"
    ),
}

__all__ = ["MIN_GAIN", "MIN_SEGMENT", "NUISANCE", "ON_REQUEST", "PAIR_WIDTH"]
