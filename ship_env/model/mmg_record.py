"""What a fitted MMG model holds (:class:`MmgRecord`), read from the document ``ship-env fit-mmg`` writes: a file of
its own, or a ship preset's ``dynamics:`` block (:mod:`ship_env.model.ship`).

:mod:`ship_env.model.mmg_fitted` reads the file, writes the document and sails the model; this module holds only
what a preset needs to read the block, so that the presets do not depend on the external-dynamics protocol.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from ship_env.model.mmg_form import INFLOW_TERMS, SURGE_TERMS, SWAY_TERMS, YAW_TERMS, MmgForm, RigidBody
from ship_env.model.operating_point import COVERAGE_QUANTITIES, FittedRanges

#: The file's ``kind``: what reads it.
KIND = "mmg_3dof"
#: The rigid body's fields in the file (:class:`~ship_env.model.mmg_form.RigidBody`'s).
BODY_FIELDS = ("length", "breadth", "draught", "block_coefficient", "centre_of_gravity", "gyration")
#: The force coefficients' sections in the file and their names.
SECTIONS = {"inflow": INFLOW_TERMS, "surge": SURGE_TERMS, "sway": SWAY_TERMS, "yaw": YAW_TERMS}


@dataclass(frozen=True)
class MmgRecord:
    """What a fitted MMG file gives to sail the ship.

    Attributes:
        form: the model.
        rudder_rate: the steering machine's rate, rad/s.
        rudder_limit: the hard-over angle, rad.
        propeller_rate: the runs' propeller rate, rps (median): the ship's unless one is ordered.
        service_speed: the runs' straight-course speed, m/s (sets the integration step).
        source: the file.
        folds: the models fitted with each run left out (the jackknife), for the spread of what they predict.
        coverage: the ranges the runs covered, by :data:`~ship_env.model.operating_point.COVERAGE_QUANTITIES`
            key ("rate" r* = L |r| / u, "drift", "rudder" in rad, "speed" in m/s): (low or None, high).
    """

    form: MmgForm
    rudder_rate: float
    rudder_limit: float
    propeller_rate: float
    service_speed: float
    source: str = ""
    folds: tuple[MmgForm, ...] = ()
    coverage: Mapping[str, tuple[float | None, float]] = field(default_factory=dict)

    def fold_records(self) -> list[MmgRecord]:
        """Each fold's model, sailed as this one (no folds of its own)."""
        return [replace(self, form=fold, folds=()) for fold in self.folds]

    def check_drawable(self) -> None:
        """``ValueError`` where :meth:`drawn` cannot draw a ship: the fit's jackknife has fewer than two folds."""
        if len(self.folds) < 2:
            raise ValueError(
                f"{self.source or 'the fitted MMG model'}: its jackknife has {len(self.folds)} folds; ships are drawn "
                "from two or more (fit it with three or more runs, without --no-jackknife)"
            )

    def drawn(self, rng: np.random.Generator) -> MmgRecord:
        """A ship drawn from the fit's uncertainty: its coefficients moved by one fold's jackknife deviation,
        theta_hat + sqrt(n - 1) (theta_k - mean_j theta_j), with k drawn uniformly from the n folds (no folds of its
        own). Over the folds the draws' covariance is the jackknife's, (n - 1) / n sum_k (theta_k - mean)(theta_k -
        mean)^T, the coefficients' correlations kept; ``ValueError`` without two folds (:meth:`check_drawable`)."""
        self.check_drawable()
        count = len(self.folds)
        k = int(rng.integers(count))

        def moved(name: str) -> np.ndarray:
            folds = np.array([getattr(fold, name) for fold in self.folds])
            return getattr(self.form, name) + math.sqrt(count - 1) * (folds[k] - folds.mean(axis=0))

        form = MmgForm(self.form.body, *(moved(name) for name in SECTIONS))
        return replace(self, form=form, folds=())

    def fitted_ranges(self) -> FittedRanges | None:
        """The runs' ranges as a preset's (:class:`~ship_env.model.operating_point.FittedRanges`); None without."""
        return FittedRanges(self.source, dict(self.coverage), propeller=False) if self.coverage else None


def _number(section: Mapping[str, Any], key: str, where: str) -> float:
    entry = section.get(key) if isinstance(section, Mapping) else None
    value = entry.get("value") if isinstance(entry, Mapping) else entry
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise ValueError(f"{where}.{key}: expected a finite number (or a mapping with one as 'value'), got {entry!r}")
    return float(value)


def mmg_record(document: object, where: str) -> MmgRecord:
    """The fitted model in ``document`` (a file's, or a preset's ``dynamics:`` block), ``where`` naming it in
    errors and as its :attr:`MmgRecord.source`; ``ValueError`` naming the field where one is missing or wrong."""
    if not isinstance(document, Mapping) or document.get("kind") != KIND:
        found = document.get("kind") if isinstance(document, Mapping) else type(document).__name__
        raise ValueError(f"{where}: kind: expected {KIND!r} (a model written by ship-env fit-mmg), got {found!r}")
    body_section = document.get("rigid_body") or {}
    body = RigidBody(*(_number(body_section, name, f"{where}: rigid_body") for name in BODY_FIELDS))
    form = MmgForm(
        body,
        *(
            np.array([_number(document.get(section) or {}, name, f"{where}: {section}") for name in names])
            for section, names in SECTIONS.items()
        ),
    )
    folds = tuple(
        MmgForm(
            body,
            *(
                np.array(_numbers(fold, section, len(names), f"{where}: jackknife.folds[{k}]"))
                for section, names in SECTIONS.items()
            ),
        )
        for k, fold in enumerate((document.get("jackknife") or {}).get("folds") or [])
    )
    coverage = {}
    for quantity, entry in (document.get("coverage") or {}).items():
        place = f"{where}: coverage.{quantity}"
        if quantity not in COVERAGE_QUANTITIES or not isinstance(entry, Mapping):
            raise ValueError(f"{place}: expected one of {sorted(COVERAGE_QUANTITIES)} with 'low' and 'high'")
        low = None if entry.get("low") is None else _number(entry, "low", place)
        coverage[quantity] = (low, _number(entry, "high", place))
    sailing = document.get("sailing") or {}
    place = f"{where}: sailing"
    return MmgRecord(
        form,
        math.radians(_number(sailing, "rudder_rate_deg_s", place)),
        math.radians(_number(sailing, "rudder_limit_deg", place)),
        _number(sailing, "propeller_rate", place),
        _number(sailing, "service_speed", place),
        where,
        folds,
        coverage,
    )


def _numbers(section: Mapping[str, Any], key: str, count: int, where: str) -> list[float]:
    values = section.get(key) if isinstance(section, Mapping) else None
    if not isinstance(values, list) or len(values) != count:
        raise ValueError(f"{where}.{key}: expected a list of {count} numbers, got {values!r}")
    return [_number({"value": value}, "value", f"{where}.{key}") for value in values]


__all__ = ["BODY_FIELDS", "KIND", "SECTIONS", "MmgRecord", "mmg_record"]
