"""Ship variation: a different ship every episode, for policies that must hold up off the nominal one.

The environments sail the ship of their preset (the *nominal* ship, the one the classic
autopilots are designed for). With ``ship_variation`` each episode sails a ship drawn around it:

- ``yaw``: K* and tau* together as multiples of the preset's (2.54), drawn log-uniformly (a ship
  that answers its rudder more strongly also takes longer to stop turning: the leaderboard's
  robustness conditions scale both);
- ``yaw_gain``, ``yaw_time_constant``: K* and tau* each once more, log-uniformly and independently;
- ``speed``: the service speed U0 as a fraction of the preset's, uniformly;
- ``disturbance``: the wind speed, current speed and significant wave height of the episode's
  weather as multiples of those drawn, uniformly.

``ship_variation=True`` takes :data:`DEFAULT_SHIP_VARIATION`: K*, tau* together x0.5 .. x2 (the
leaderboard's robustness conditions are the ends: both halved, both doubled), each apart x0.8 ..
x1.25 more, speed 0.5 .. 1.0 U0, weather x0.5 .. x1.5. A mapping gives the ranges ``{"yaw": [0.5,
2.0], ...}``; a key left out stays nominal. The draws come from the environment's generator after
the task's own, so with ``ship_variation`` off (the default) an id's episodes are what they always
were, and with it on a seed gives the same task episode (course change, weather, track) on the ship
drawn.

``ship_variation="fitted"`` (:data:`FITTED`) draws the ship from its fit instead: a preset written
by ``ship-env fit/improve --preset`` carries each fitted value theta_hat with its standard error s
(the larger of the Jacobian's and the jackknife's, :mod:`ship_env.workbench.reporting.presets`), and each
episode's K* and tau* are drawn (:class:`FittedShipVariation`)

    theta ~ N(theta_hat, s^2) truncated to [theta_min, theta_max],

independently for K* and tau*, with theta_min, theta_max the parameter's declared range (K* >= 0,
tau* >= 1e-6: ``ship_env.model.effects.yaw``) and truncation by redrawing: a draw outside the range
is drawn again, so the ships keep the Gaussian's shape inside the range. Clipping would instead
pile the tail's probability onto the bound (a ship with K* = 0 exactly, no rudder at all, or
tau* = 1e-6); where the bound lies more than 3 s from theta_hat the redraws change the spread by
under 1 %. The preset records neither the fold (jackknife) models nor the covariance of the
terms, so the draws are independent: a fit that trades K* against tau* (their errors correlated)
draws ships somewhat wider than its data allow along the trade. The other fitted terms (the wind
moment, the sway, Norrbin's terms) sail at their fitted values: the ships of one vector
environment can differ only in K* and tau* (the per-ship factors below). A preset without standard
errors for K* and tau* (a built-in one) is refused, naming the option and the preset.

The ships of one vector environment differ at once: K* and tau* reach the simulator as per-ship
:class:`~ship_env.model.Conditions` (``yaw_gain_factor``, ``yaw_time_constant_factor``), not as the
model's parameters.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from ship_env.envs.checks import check_range
from ship_env.model import EFFECTS, Conditions, Ship, ShipModel

#: The varied quantities and the ranges ``ship_variation=True`` draws them from.
DEFAULT_SHIP_VARIATION: dict[str, tuple[float, float]] = {
    "yaw": (0.5, 2.0),
    "yaw_gain": (0.8, 1.25),
    "yaw_time_constant": (0.8, 1.25),
    "speed": (0.5, 1.0),
    "disturbance": (0.5, 1.5),
}
#: Uniform numbers a varied episode draws, one per quantity.
VARIATION_DRAWS = len(DEFAULT_SHIP_VARIATION)
#: The smallest factor a range may hold: a ship with no rudder effect, no inertia or no speed has no model.
_SMALLEST_FACTOR = {"yaw": 1e-3, "yaw_gain": 1e-3, "yaw_time_constant": 1e-3, "speed": 1e-3, "disturbance": 0.0}
#: The factors drawn log-uniformly (the others uniformly).
_LOG_UNIFORM = ("yaw", "yaw_gain", "yaw_time_constant")


@dataclass(frozen=True)
class ShipFactors:
    """The ship an episode sails, as multiples of the nominal one (all 1 for the nominal ship).

    Attributes:
        yaw_gain: K* / the preset's K*.
        yaw_time_constant: tau* / the preset's tau*.
        speed: U0 / the preset's service speed.
        disturbance: the wind speed, current speed and wave height / those of the task's draw.
    """

    yaw_gain: float = 1.0
    yaw_time_constant: float = 1.0
    speed: float = 1.0
    disturbance: float = 1.0


#: The nominal ship.
NOMINAL_SHIP = ShipFactors()


class ShipVariation:
    """The ranges ships are drawn from; ``ValueError`` naming the key and value for a bad range.

    Args:
        ranges: ``True`` (:data:`DEFAULT_SHIP_VARIATION`), or quantity -> (low, high) with
            0 < low <= high (``disturbance`` may start at 0: still water and air); a quantity
            left out stays nominal (1, 1).
    """

    def __init__(self, ranges: bool | Mapping[str, Sequence[float]]) -> None:
        if ranges is True:
            ranges = DEFAULT_SHIP_VARIATION
        if not isinstance(ranges, Mapping):
            raise TypeError(f"ship_variation: expected true or a mapping of ranges, got {ranges!r}")
        unknown = sorted(set(ranges) - set(DEFAULT_SHIP_VARIATION))
        if unknown:
            raise ValueError(f"ship_variation: unknown keys {unknown}; known: {', '.join(DEFAULT_SHIP_VARIATION)}")
        self.ranges = {
            name: check_range(f"ship_variation[{name!r}]", ranges.get(name, (1.0, 1.0)), _SMALLEST_FACTOR[name])
            for name in DEFAULT_SHIP_VARIATION
        }

    def draw(self, rng: np.random.Generator) -> ShipFactors:
        """A ship from ``VARIATION_DRAWS`` uniforms of ``rng``: the yaw factors log-uniform, speed and
        weather uniform; K* = yaw * yaw_gain, tau* = yaw * yaw_time_constant."""
        draws = rng.random(VARIATION_DRAWS).tolist()
        factors = {}
        for (name, (low, high)), draw in zip(self.ranges.items(), draws, strict=True):
            if name in _LOG_UNIFORM:
                factors[name] = math.exp(math.log(low) + (math.log(high) - math.log(low)) * draw)
            else:
                factors[name] = low + (high - low) * draw
        yaw = factors.pop("yaw")
        return ShipFactors(
            **{
                **factors,
                "yaw_gain": yaw * factors["yaw_gain"],
                "yaw_time_constant": yaw * factors["yaw_time_constant"],
            }
        )


#: ``ship_variation="fitted"``: each episode's K*, tau* drawn from the preset's fit (:class:`FittedShipVariation`).
FITTED = "fitted"
#: The fitted terms ``ship_variation="fitted"`` draws, and the :class:`ShipFactors` field each sails as.
FITTED_TERMS = {"yaw.gain": "yaw_gain", "yaw.time_constant": "yaw_time_constant"}
#: Draws of one term before a range that keeps refusing them is reported (each falls inside the range
#: with probability at least one half while the fitted value lies inside it).
MAXIMUM_REDRAWS = 100
#: Largest standard error, as a fraction of its fitted value, of a term drawn from: beyond it the fit does not
#: determine the term's size (the Gaussian puts over 2 % of its ships at or below zero, and the redraws pile
#: ships without rudder or yaw inertia against the bound), so no ship is drawn from it.
UNDETERMINED_SHARE = 0.5


def draws_fitted(preset: Ship) -> bool:
    """Whether ``preset`` gives a standard error for each of :data:`FITTED_TERMS`, each at most
    :data:`UNDETERMINED_SHARE` of its value (``ship_variation="fitted"`` can draw from it)."""
    return all(preset.std_errors.get(key) is not None for key in FITTED_TERMS) and not undetermined_terms(preset)


def draws_ships(preset: Ship) -> bool:
    """Whether ``ship_variation="fitted"`` draws ships from ``preset`` as it sails by default: from its fitted MMG
    model's jackknife (two or more folds) where its ``dynamics:`` block sails it
    (:meth:`~ship_env.model.mmg_record.MmgRecord.drawn`), else from its effects' standard errors
    (:func:`draws_fitted`)."""
    if preset.dynamics is not None:
        return len(preset.dynamics.folds) >= 2
    return draws_fitted(preset)


def undetermined_terms(preset: Ship) -> list[str]:
    """The drawn terms whose standard error exceeds :data:`UNDETERMINED_SHARE` of their value, in words."""
    words = []
    for key in FITTED_TERMS:
        error = preset.std_errors.get(key)
        effect, _, name = key.partition(".")
        value = preset.values.get(effect, {}).get(name)
        if error is not None and value is not None and error > UNDETERMINED_SHARE * abs(value):
            words.append(f"{key} {value:.4g} +- {error:.2g}")
    return words


class FittedShipVariation:
    """Ships drawn from a fitted preset's uncertainty (``ship_variation="fitted"``; the module docstring).

    Args:
        model: the environment's model of a preset written by ``ship-env fit/improve --preset``; the
            draws centre on its K* and tau* (the fitted values, unless ``ship_parameters`` set others).

    Raises:
        ValueError: the preset gives no standard error for K* or tau* (a built-in preset, or a fit
            that did not determine them), or one over :data:`UNDETERMINED_SHARE` of its value, naming
            the option, the preset and the terms.
    """

    def __init__(self, model: ShipModel) -> None:
        errors = model.ship.std_errors
        undetermined = undetermined_terms(model.ship)
        if undetermined:
            raise ValueError(
                f"ship_variation={FITTED!r}: the preset {model.ship.name!r} ({model.ship.path or model.ship.name}) "
                f"does not determine {', '.join(undetermined)} (a standard error over {UNDETERMINED_SHARE:g} of the "
                "value): ships drawn from it would include ones without rudder or yaw inertia"
            )
        if not draws_fitted(model.ship):
            lacking = [key for key in FITTED_TERMS if errors.get(key) is None]
            where = model.ship.path or model.ship.name
            raise ValueError(
                f"ship_variation={FITTED!r}: the preset {model.ship.name!r} ({where}) gives no standard error "
                f"(std_error) for {', '.join(lacking)}; only a preset written by `ship-env fit --preset` or "
                "`ship-env improve --preset` with those terms fitted does (fixed factors: ship_variation=True "
                "or a mapping of ranges)"
            )
        declared = {f"{name}.{p.name}": p for name, effect in EFFECTS.items() for p in effect.parameters}
        #: Per term: the fitted value theta_hat, its standard error s and its declared range.
        self.values = {key: model.parameter(key) for key in FITTED_TERMS}
        self.std_errors = {key: float(errors[key] or 0.0) for key in FITTED_TERMS}
        self.ranges = {key: (declared[key].minimum, declared[key].maximum) for key in FITTED_TERMS}

    def draw_term(self, key: str, rng: np.random.Generator) -> float:
        """One term drawn from N(theta_hat, s^2), redrawn until inside its declared range."""
        low, high = self.ranges[key]
        for _ in range(MAXIMUM_REDRAWS):
            value = float(rng.normal(self.values[key], self.std_errors[key]))
            if low <= value <= high:
                return value
        raise ValueError(
            f"ship_variation={FITTED!r}: {key} {self.values[key]!r} +- {self.std_errors[key]!r} drew no value "
            f"inside its range [{low}, {high}] in {MAXIMUM_REDRAWS} draws"
        )

    def draw(self, rng: np.random.Generator) -> ShipFactors:
        """A ship from ``rng``: K*, then tau*, each as a multiple of the model's (speed and weather nominal)."""
        return ShipFactors(
            **{field: self.draw_term(key, rng) / self.values[key] for key, field in FITTED_TERMS.items()}
        )


def sailed_conditions(conditions: Conditions, ship: ShipFactors, service_speed: float) -> Conditions:
    """``conditions`` for the ship ``ship``: its K*, tau* factors, its speed (a fraction of
    ``service_speed`` unless the conditions name one), the weather scaled by its disturbance factor."""
    speed = service_speed if conditions.service_speed is None else conditions.service_speed
    return dataclasses.replace(
        conditions,
        service_speed=speed * ship.speed,
        wind_speed=conditions.wind_speed * ship.disturbance,
        current_speed=conditions.current_speed * ship.disturbance,
        wave_height=conditions.wave_height * ship.disturbance,
        yaw_gain_factor=ship.yaw_gain,
        yaw_time_constant_factor=ship.yaw_time_constant,
    )
