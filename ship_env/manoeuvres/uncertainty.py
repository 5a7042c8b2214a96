"""The fit's uncertainty in a fitted preset's manoeuvres: its figures sailed by each jackknife fold.

``ship-env fit|improve --preset`` records in the preset's ``fitted.jackknife`` the terms fitted with each run (or
group of runs) left out, the folds of its leave-one-out cross-validation. Each fold is a ship the runs could as
well have given; sailing all n of them through a manoeuvre and taking the jackknife standard error of each figure,

    s = sqrt((n - 1) / n * sum_i (x_i - mean x)^2)

(the formula of the terms' own jackknife errors, applied to a figure x that depends on them), says how sure the
fit is of that figure: what its runs leave open, not what its model form lacks. Beyond the runs' coverage (a
hard-over turn fitted on zig-zags) the preset warns that it extrapolates; this band is how far its own data
would move the figure there.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from ship_env.manoeuvres.results import Figure
from ship_env.model import ShipModel


def fold_models(model: ShipModel) -> list[ShipModel]:
    """``model`` with each jackknife fold's terms in place of the fitted ones: one ship per fold recorded in its
    preset's ``fitted.jackknife`` (none for a preset that was not fitted, or was fitted before they were recorded).

    A term of an effect ``model`` leaves out (``--effects``) is not sailed.

    Raises:
        ValueError: a record whose terms and values do not match, naming the preset and the field.
    """
    record = (model.ship.fitted or {}).get("jackknife")
    if not record:
        return []
    where = model.ship.path or model.ship.name
    terms = record.get("terms")
    folds = record.get("values")
    if not isinstance(terms, list) or not isinstance(folds, list) or any(len(fold) != len(terms) for fold in folds):
        raise ValueError(f"{where}: fitted.jackknife needs 'terms' and per fold as many 'values'; got {record!r}")
    sailed = [i for i, key in enumerate(terms) if "." not in key or model.has(key.partition(".")[0])]
    return [model.with_parameters({terms[i]: float(fold[i]) for i in sailed}) for fold in folds]


def jackknife_error(values: Sequence[float] | np.ndarray) -> float:
    """sqrt((n - 1) / n * sum_i (x_i - mean x)^2) over the folds' ``values``; NaN where any is NaN (a fold that did
    not reach the figure) or fewer than two are given."""
    array = np.asarray(values, dtype=float)
    if len(array) < 2 or not np.all(np.isfinite(array)):
        return math.nan
    return float(math.sqrt((len(array) - 1) / len(array) * np.sum((array - array.mean()) ** 2)))


def figure_errors(figures_per_fold: Sequence[Sequence[Figure]]) -> dict[str, float]:
    """Per numeric figure (by its key), the :func:`jackknife_error` of its values over the folds' figures."""
    values: dict[str, list[float]] = {}
    for figures in figures_per_fold:
        for figure in figures:
            if not isinstance(figure.value, str):
                values.setdefault(figure.key, []).append(figure.value)
    return {key: jackknife_error(numbers) for key, numbers in values.items()}


__all__ = ["figure_errors", "fold_models", "jackknife_error"]
