"""A 3-DOF MMG-form model identified from logs (``ship-env fit-mmg``), sailed behind the external-dynamics protocol.

``ship-env fit-mmg LOGS --ship PRESET -o hull.yaml`` fits the MMG standard's hull, propeller and rudder forces
(:mod:`ship_env.model.mmg_form`) to measured runs by inverse dynamics
(:mod:`ship_env.workbench.fitting.inverse_dynamics`) and writes them to a YAML file. :class:`MmgFitted` sails that file
wherever ship_env takes external dynamics (:mod:`ship_env.model.external`)::

    import gymnasium as gym

    env = gym.make("ship_env/CourseChange-v0", ship="kvlcc2_model.yaml", dynamics="hull.yaml")

and ``ship-env manoeuvre --ship PRESET --dynamics hull.yaml`` sails it through the standard manoeuvres.

The file holds what the model needs to sail (:func:`read_mmg`): the rigid body, the force coefficients, the
steering machine's rate and limit, and the runs' propeller rate, at which the ship sails unless a rate is
ordered; and what it does not need, for the reader: the coefficients' standard errors, the runs it was fitted
to and the ranges of v', r', speed and rudder they covered (a manoeuvre beyond them extrapolates the
polynomials). The model has no wind or wave forces: a reset in wind or waves raises ``ValueError``; a current
carries the ship over the ground.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np
import yaml

from ship_env.model.external import ShipMotion
from ship_env.model.mmg_form import MmgForm, rk4_step
from ship_env.model.mmg_record import BODY_FIELDS, KIND, SECTIONS, MmgRecord, mmg_record
from ship_env.model.simulator import Conditions

#: The longest integration step, in ship lengths sailed at the runs' speed (L / U).
MAX_STEP_LENGTHS = 0.1
#: The fastest a sailed ship may go, in times its runs' speed: beyond it the polynomials have diverged.
FASTEST = 5.0


def read_mmg(path: str | Path) -> MmgRecord:
    """The fitted model in ``path``; ``ValueError`` naming the file and the field where one is missing or wrong."""
    path = Path(path)
    try:
        document = yaml.safe_load(path.read_text())
    except OSError as error:
        raise ValueError(f"dynamics: cannot read {str(path)!r}: {error.strerror}") from None
    return mmg_record(document, str(path))


def mmg_document(record: MmgRecord, errors: Mapping[str, float], about: Mapping[str, Any]) -> dict[str, Any]:
    """The YAML document of ``record`` (what :func:`read_mmg` reads), each coefficient with its standard error
    from ``errors`` (by name, where given), after ``about`` (provenance, coverage: written as given)."""
    body = record.form.body

    def entries(names: tuple[str, ...], values: np.ndarray) -> dict[str, Any]:
        return {
            name: {"value": float(value), **({"std_error": float(errors[name])} if name in errors else {})}
            for name, value in zip(names, values, strict=True)
        }

    def arrays(form: MmgForm) -> dict[str, np.ndarray]:
        return {"inflow": form.inflow, "surge": form.surge, "sway": form.sway, "yaw": form.yaw}

    return {
        "kind": KIND,
        **about,
        "rigid_body": {name: float(getattr(body, name)) for name in BODY_FIELDS},
        "sailing": {
            "rudder_rate_deg_s": math.degrees(record.rudder_rate),
            "rudder_limit_deg": math.degrees(record.rudder_limit),
            "propeller_rate": record.propeller_rate,
            "service_speed": record.service_speed,
        },
        **{section: entries(names, arrays(record.form)[section]) for section, names in SECTIONS.items()},
        "coverage": {quantity: {"low": low, "high": high} for quantity, (low, high) in record.coverage.items()},
        "jackknife": {
            "about": "the fits with each run left out, in the runs' order: the spread of what they predict",
            "folds": [
                {key: [float(x) for x in values] for key, values in arrays(fold).items()} for fold in record.folds
            ],
        },
    }


class MmgFitted:
    """A fitted MMG-form ship (:class:`~ship_env.model.external.ShipDynamics`), integrated by RK4.

    Args:
        source: the file ``ship-env fit-mmg`` wrote, or its :class:`MmgRecord`.
        draw: each reset sails a ship drawn from the fit's uncertainty, from the reset's seed
            (:meth:`MmgRecord.drawn`; the environments' ``ship_variation="fitted"``).

    Each step moves the rudder towards the order at the steering machine's rate (linearly over the step) and
    integrates the equations of motion in sub-steps of at most :data:`MAX_STEP_LENGTHS` ship lengths; a state
    that is not finite raises ``FloatingPointError`` (the ship left the model's validity).
    """

    def __init__(self, source: str | Path | MmgRecord, draw: bool = False) -> None:
        self.record = source if isinstance(source, MmgRecord) else read_mmg(source)
        #: Whether each reset sails a ship drawn from the fit's uncertainty (:meth:`MmgRecord.drawn`, from the seed).
        self.draw = draw
        #: The model the episode sails: the record's, or the reset's draw.
        self.sailed = self.record
        self.state = np.zeros(6)
        self.rudder = 0.0
        self._current = (0.0, 0.0)

    def reset(self, start: ShipMotion, conditions: Conditions, seed: int) -> None:
        """Start at ``start``; ``ValueError`` in wind or waves, which the model has no forces for."""
        if conditions.wind_speed > 0.0 or conditions.wave_height > 0.0:
            raise ValueError(
                f"conditions: the fitted MMG model {self.record.source} has no wind or wave forces (wind "
                f"{conditions.wind_speed} m/s, H_s {conditions.wave_height} m); sail it in calm water or a current"
            )
        self._current = (
            conditions.current_speed * math.cos(conditions.current_direction),
            conditions.current_speed * math.sin(conditions.current_direction),
        )
        #: u, v, r, north, east, heading.
        sway = -start.speed * math.tan(start.drift)
        self.state = np.array([start.speed, sway, start.rate_of_turn, start.north, start.east, start.heading])
        self.rudder = start.rudder
        self.sailed = self.record.drawn(np.random.default_rng(seed)) if self.draw else self.record

    def step(self, rudder_order: float, propeller_rate: float | None, dt: float) -> ShipMotion:
        """Sail ``dt`` s: the rudder towards ``rudder_order``, the propeller at ``propeller_rate`` (``None``: the
        runs' rate)."""
        record = self.sailed
        order = min(max(rudder_order, -record.rudder_limit), record.rudder_limit)
        largest = record.rudder_rate * dt
        rudder = self.rudder + min(max(order - self.rudder, -largest), largest)
        rate = record.propeller_rate if propeller_rate is None else propeller_rate
        substeps = max(1, math.ceil(dt * record.service_speed / (MAX_STEP_LENGTHS * record.form.body.length)))
        state = self.state
        with np.errstate(all="ignore"):  # a state that overflows is refused below, by name
            for k in range(substeps):
                start = self.rudder + (rudder - self.rudder) * k / substeps
                end = self.rudder + (rudder - self.rudder) * (k + 1) / substeps
                state = rk4_step(state, start, end, rate, record.form, dt / substeps)
        if not (
            np.all(np.isfinite(state)) and 0.0 < state[0] and math.hypot(*state[:2]) < FASTEST * record.service_speed
        ):
            u, v, r = self.state[:3]
            named = f" {record.source}" if record.source else ""
            raise FloatingPointError(
                f"the fitted MMG model{named} left its validity: from u {u:.4g} m/s, v {v:.4g} m/s, r {r:.4g} rad/s "
                f"the next step is not a ship going ahead below {FASTEST:g} times its runs' speed"
            )
        state[3] += self._current[0] * dt
        state[4] += self._current[1] * dt
        self.state, self.rudder = state, rudder
        u, v, r, north, east, heading = state.tolist()
        return ShipMotion(heading, r, north, east, u, math.atan2(-v, u), rudder)


__all__ = ["KIND", "MmgFitted", "MmgRecord", "mmg_document", "mmg_record", "read_mmg"]
