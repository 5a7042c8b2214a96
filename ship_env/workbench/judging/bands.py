"""Prediction bands: how sure the fitted model is where it predicts, from the jackknife fits.

Cross-validation fits the model once per run (or group) left out (:class:`~.validation.Fold`). Each
of those n fold models replays a run from its measured initial state (free replay: heading, rate
of turn, track); per sample, the band is the jackknife mean of those replays plus and minus their
jackknife standard deviation

    s = sqrt((n - 1) / n * sum_i (y_i - mean y)^2),

the jackknife estimate of the standard error of the all-run fit's prediction (the same formula
as the terms' jackknife errors, :meth:`~.validation.CrossValidation.jackknife_errors`). Every fold's
replay lies inside it (Cauchy-Schwarz: (y_i - mean y)^2 <= (n - 1)/n * sum_j (y_j - mean y)^2), and
it has no width where all folds agree. Every fold takes part for every run -- a held-out run and a
validation run alike: the band is that of the model fitted to all runs (for a held-out run, the fold
that left it out is only one of the n). A fold replay that leaves the model's validity is left out
of the band. All folds' replays of all runs run in one compiled batch.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from ship_env.workbench.fitting.replay import EAST, NORTH, Tasks, pack_runs, replay
from ship_env.workbench.judging.validation import Fold
from ship_env.workbench.logs.logs import Log

#: How the band is labelled in drawings.
BAND_LABEL = "jackknife band"


@dataclass(frozen=True)
class Band:
    """One run's jackknife band: per sample and output column (north, east, heading, rate of turn; the
    replay's columns, :data:`~.replay.NORTH`...), the jackknife mean and standard deviation of the fold
    replays, SI units.

    Attributes:
        centre: (samples, 4) the mean of the fold replays.
        spread: (samples, 4) their jackknife standard deviation.
        replays: the fold replays it is made of (those that stayed valid).
    """

    centre: np.ndarray
    spread: np.ndarray
    replays: int

    def low(self, column: int) -> np.ndarray:
        return self.centre[:, column] - self.spread[:, column]

    def high(self, column: int) -> np.ndarray:
        return self.centre[:, column] + self.spread[:, column]

    @property
    def radius(self) -> np.ndarray:
        """The position's jackknife standard deviation, sqrt(s_north^2 + s_east^2), m."""
        return np.hypot(self.spread[:, NORTH], self.spread[:, EAST])


def jackknife_band(replays: np.ndarray) -> Band:
    """The band of ``replays`` (fold, sample, column): jackknife mean and standard deviation over the folds."""
    count = replays.shape[0]
    if count == 0:
        return Band(np.full(replays.shape[1:], np.nan), np.full(replays.shape[1:], np.nan), 0)
    # Deviations from the first replay: folds that agree give no width at all, not rounding's.
    deviations = replays - replays[0]
    mean = deviations.mean(axis=0)
    spread = np.sqrt((count - 1) / count * np.sum((deviations - mean) ** 2, axis=0))
    return Band(replays[0] + mean, spread, count)


def jackknife_bands(folds: Sequence[Fold], logs: Sequence[Log], window: float | None = None) -> list[Band]:
    """Each run's band, every fold's model replaying every run (free replays) in one batch."""
    if not folds or not logs:
        return []
    setups = [fold.setup for fold in folds]
    runs = pack_runs(logs, setups[0].model, window)
    records = np.concatenate([setup.model.record for setup in setups])
    pairs = [(f, run) for f in range(len(folds)) for run in range(len(logs))]
    tasks = Tasks.build(
        record=[f for f, _ in pairs],
        run=[run for _, run in pairs],
        track=[False] * len(pairs),
        current=np.array([setups[f].current for f, _ in pairs]),
    )
    outputs, valid_samples = replay(runs, records, tasks)
    outputs = outputs.reshape(len(folds), len(logs), *outputs.shape[1:])
    # A fold whose replay of a run left the model's validity is left out of that run's band.
    valid = valid_samples.reshape(len(folds), len(logs)) >= np.array([log.samples for log in logs])
    bands = []
    for run, log in enumerate(logs):
        bands.append(jackknife_band(outputs[valid[:, run], run, : log.samples]))
    return bands


__all__ = ["BAND_LABEL", "Band", "jackknife_band", "jackknife_bands"]
