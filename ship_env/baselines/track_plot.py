"""Drawing a predicted track against the sailed one (thesis Figs. 3.12, 6.7.b)."""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
from matplotlib.axes import Axes

from ship_env.baselines.track_predictor import PredictedTrack


def plot_track_prediction(
    axes: Axes,
    sailed: np.ndarray,
    predictions: Mapping[str, PredictedTrack],
    reference: np.ndarray | None = None,
) -> Axes:
    """Draw on ``axes``, north up and east to the right, in metres, equal scales.

    Args:
        axes: matplotlib axes.
        sailed: (N, 2) north, east positions the ship sailed (the actual track x_s).
        predictions: labelled predicted tracks (e.g. ``{"x_0 initial": ..., "x_p adapted": ...}``).
        reference: (K, 2) north, east points of a reference track, if any.

    Returns:
        ``axes``.
    """
    if reference is not None:
        axes.plot(reference[:, 1], reference[:, 0], color="0.6", linewidth=1.0, label="reference track")
    axes.plot(sailed[:, 1], sailed[:, 0], color="black", linewidth=1.5, label="sailed")
    for label, track in predictions.items():
        axes.plot(track.east, track.north, linestyle="--", linewidth=1.2, label=label)
    axes.set_xlabel("east (m)")
    axes.set_ylabel("north (m)")
    axes.set_aspect("equal", adjustable="datalim")
    axes.legend(loc="best")
    return axes
