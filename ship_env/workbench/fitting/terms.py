"""What a fit may estimate: model parameters and the steady current, with their ranges and scales.

A *term* is one estimated number: a model parameter keyed ``effect.parameter`` (``yaw.gain``), as
:class:`~ship_env.model.ShipModel` keys them, or a component of a steady current over all runs,
``current.north`` / ``current.east`` in m/s (the current effect's speed and direction are
conditions of a run, not parameters of the ship). Each term has a range, a scale (its typical size:
the fitter works in units of it) and, where one exists, the null value at which its effect
vanishes (an offset of 0, a slipstream coefficient of 0) and the material size its effect declares
for this ship (``Parameter.material``: the smallest departure from null that means something).

Each effect names the terms fitted when it is added (``DEFAULT_TERMS``; an effect registered from
outside ``ship_env`` has all its parameters fitted, in their declared ranges, with the declared
null value; see :func:`effect_terms`); the parameters left out keep the preset's value (e.g. the
propeller diameter, the hull's cross-flow drag). Effects that output-error fitting cannot estimate
(random disturbances) and effects the logs cannot show (a speed loss where no log measures the speed)
are excluded with the reason (:func:`why_not_fitted`).

**Speed is a fitted output.** Where a log measures the speed, the replay predicts it
(:mod:`.replay`): a fit to such logs sails with the speed loss on (:func:`with_speed_output`) and
fits its terms K_u* and tau_u* (2.55; beta3 of H_u, 2.39, with ``--free speed_loss.cubic``: it shows
only where u* is large, a hard-over turn or a start from rest). Where no log measures it, the speed-loss terms
are not fitted (:func:`default_terms` with the logs): the fit cannot know the speed loss, and keeps
the starting model's (:func:`not_identified` says so in words).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, replace

import numpy as np

from ship_env.model import EFFECTS, PRINCIPAL, ShipModel
from ship_env.model.declarations import Parameter
from ship_env.model.effects.current import STEADY_COMPONENT
from ship_env.workbench.fitting.replay import INPUTS, ReplayModel
from ship_env.workbench.logs.logs import CALM_AIR_DEVIATIONS, Log

CURRENT_TERMS = ("current.north", "current.east")

#: The terms fitted when an effect is in the model.
DEFAULT_TERMS: dict[str, tuple[str, ...]] = {
    "yaw": ("yaw.gain", "yaw.time_constant"),
    "norrbin": ("norrbin.cubic", "norrbin.odd_quadratic"),
    "hull_crossflow": ("hull_crossflow.coefficient",),
    "propeller_astern": ("propeller_astern.rudder_inflow", "propeller_astern.walk"),
    "asymmetry": ("asymmetry.side_force", "asymmetry.quadratic"),
    "speed_loss": ("speed_loss.gain", "speed_loss.time_constant"),
    "turning_resistance": ("turning_resistance.speed_exponent",),
    "rudder_drag": ("rudder_drag.drag_coefficient",),
    "sway": ("sway.linear",),
    "sway_lag": ("sway_lag.time_constant", "sway_lag.coupling"),
    "drift_resistance": ("drift_resistance.gain",),
    "steering_machine": ("steering_machine.rudder_rate",),
    "rudder_offset": ("rudder_offset.angle",),
    "propeller_slipstream": ("propeller_slipstream.coefficient",),
    "current": CURRENT_TERMS,
    "wind_moment": ("wind_moment.yaw_coefficient", "wind_moment.beam_coefficient"),
    "wind_drift": ("wind_drift.force_ratio",),
}

#: Effects output-error fitting leaves alone, and why.
NOT_FITTED: dict[str, str] = {
    "kinematics": "required; has no parameters",
    "gusts": "a random disturbance: output error cannot fit it (the filters in baselines/ estimate it)",
    "wave_filter": "a random disturbance: output error cannot fit it (the filters in baselines/ estimate it)",
    "wave_spectrum": "a random sea: output error cannot fit it",
}


def reverses_propeller(log: Log) -> bool:
    """Whether the log's propeller turns astern (n < 0) at some sample."""
    return log.propeller_rate is not None and not bool(np.all(log.propeller_rate >= 0.0))


#: Effects that act only where a run meets a condition -- elsewhere their contributions return what
#: they are given (see the effect's module) -- and whether a log meets it at some sample.
ACTS_ONLY_WHERE: dict[str, Callable[[Log], bool]] = {"propeller_astern": reverses_propeller}


def acts_on(effect: str, logs: Sequence[Log]) -> bool:
    """Whether an effect can act on the logs: False for one of ``ACTS_ONLY_WHERE`` whose condition no log
    meets (its terms then move no replay of these logs)."""
    meets = ACTS_ONLY_WHERE.get(effect)
    return meets is None or any(meets(log) for log in logs)


@dataclass(frozen=True)
class TermRule:
    """Range, null value and smallest scale of a term, in SI units."""

    lower: float
    upper: float
    null: float | None = None
    smallest_scale: float = 1.0


_DEG = math.pi / 180.0
_RULES: dict[str, TermRule] = {
    "yaw.gain": TermRule(0.01, 50.0),
    "yaw.time_constant": TermRule(0.01, 100.0),
    "yaw.linear": TermRule(-5.0, 5.0),
    "propeller_astern.rudder_inflow": TermRule(0.0, 10.0, 0.0, 0.05),
    "propeller_astern.walk": TermRule(-1.0, 1.0, 0.0, 0.001),
    "asymmetry.side_force": TermRule(-1.0, 1.0, 0.0, 0.001),
    "asymmetry.constant": TermRule(-2.0, 2.0, 0.0, 0.01),
    "asymmetry.quadratic": TermRule(-5.0, 5.0, 0.0, 0.1),
    "norrbin.cubic": TermRule(0.0, 100.0, 0.0, 0.5),
    "norrbin.odd_quadratic": TermRule(-100.0, 100.0, 0.0, 0.5),
    "hull_crossflow.coefficient": TermRule(0.0, 100.0, 0.0, 0.5),
    "speed_loss.gain": TermRule(0.0, 20.0, 0.0, 0.3),
    "speed_loss.time_constant": TermRule(0.05, 100.0),
    "speed_loss.cubic": TermRule(0.0, 100.0, 0.0, 1.0),
    "turning_resistance.speed_exponent": TermRule(0.0, 4.0, 0.0, 0.3),
    "rudder_drag.drag_coefficient": TermRule(0.0, 20.0, 0.0, 0.3),
    "sway.linear": TermRule(-3.0, 3.0, 0.0, 0.1),
    "sway.cubic": TermRule(-3.0, 3.0, 0.0, 0.1),
    "sway_lag.time_constant": TermRule(1e-3, 20.0, None, 0.1),
    "sway_lag.coupling": TermRule(-50.0, 50.0, 0.0, 0.1),
    "drift_resistance.gain": TermRule(0.0, 20.0, 0.0, 0.3),
    "steering_machine.rudder_rate": TermRule(0.2 * _DEG, 500.0 * _DEG, None, 1.0 * _DEG),
    "rudder_offset.angle": TermRule(-20.0 * _DEG, 20.0 * _DEG, 0.0, 1.0 * _DEG),
    "propeller_slipstream.coefficient": TermRule(0.0, 10.0, 0.0, 0.05),
    "wind_moment.yaw_coefficient": TermRule(-math.inf, math.inf, 0.0, 0.0),
    "wind_moment.beam_coefficient": TermRule(-math.inf, math.inf, 0.0, 0.0),
    "wind_moment.surge_coefficient": TermRule(-math.inf, math.inf, 0.0, 0.0),
    "wind_drift.force_ratio": TermRule(0.0, math.inf, 0.0, 1e-4),
    "wind_drift.lift_slope": TermRule(1e-3, 100.0, None, 0.1),
    "wind_drift.crossflow_drag": TermRule(1e-3, 100.0, None, 0.1),
    "current.north": TermRule(-math.inf, math.inf, 0.0, 0.0),
    "current.east": TermRule(-math.inf, math.inf, 0.0, 0.0),
}


@dataclass(frozen=True)
class Term:
    """One estimated number.

    Attributes:
        key: ``effect.parameter``, a principal particular, or ``current.north`` / ``current.east``.
        unit: its SI unit.
        description: what it is.
        scale: its typical size; the fitter estimates value / scale.
        lower, upper: its range.
        null: the value at which its effect vanishes, or None.
        material: the smallest departure from ``null`` that means something physically, in ``unit``
            for this ship (its effect's declared ``Parameter.material``), or None.
    """

    key: str
    unit: str
    description: str
    scale: float
    lower: float
    upper: float
    null: float | None
    material: float | None = None

    @property
    def effect(self) -> str:
        return self.key.partition(".")[0]

    @property
    def is_condition(self) -> bool:
        return self.key in CURRENT_TERMS

    def record_field(self) -> str:
        """The field of the compiled parameter record that holds it."""
        effect, _, name = self.key.partition(".")
        return EFFECTS[effect].field_name(name) if name else effect


def effect_terms(effect: str) -> tuple[str, ...]:
    """The terms fitted when ``effect`` is added: ``DEFAULT_TERMS``, or every parameter of an effect from outside."""
    if effect in DEFAULT_TERMS or EFFECTS.entry(effect).builtin:
        return DEFAULT_TERMS.get(effect, ())
    return tuple(f"{effect}.{parameter.name}" for parameter in EFFECTS[effect].parameters)


def _rule(key: str, minimum: float, maximum: float) -> TermRule:
    """A term's fit rule: ``_RULES``, else its declared range and null, scaled by a hundredth of the range."""
    if key in _RULES:
        return _RULES[key]
    effect_name, _, name = key.partition(".")
    declared = {parameter.name: parameter for parameter in EFFECTS[effect_name].parameters} if name else {}
    null = declared[name].null if name in declared else None
    span = maximum - minimum
    return TermRule(minimum, maximum, null, span / 100.0 if math.isfinite(span) and span > 0.0 else 1.0)


def _declaration(key: str) -> Parameter:
    """The declaration of a model parameter, a principal particular or a steady current's component."""
    if key in CURRENT_TERMS:
        towards = key.split(".")[1]
        description = f"steady current towards the {towards}, the same in every run"
        return replace(STEADY_COMPONENT, name=towards, description=description)
    principal = {parameter.name: parameter for parameter in PRINCIPAL}
    effect_name, _, name = key.partition(".")
    if not name and key in principal:
        parameter = principal[key]
    else:
        effect = EFFECTS.get(effect_name)
        by_name = {parameter.name: parameter for parameter in effect.parameters} if effect else {}
        if name not in by_name:
            raise ValueError(
                f"fit: unknown term {key!r}; use 'effect.parameter' (e.g. 'yaw.gain'), a principal particular, "
                f"or {' / '.join(CURRENT_TERMS)}"
            )
        parameter = by_name[name]
    return parameter


def value_of(setup: ReplayModel, key: str) -> float:
    """A term's value in a replay model."""
    if key == "current.north":
        return setup.current_north
    if key == "current.east":
        return setup.current_east
    return setup.model.parameter(key)


def make_term(key: str, setup: ReplayModel) -> Term:
    """The term ``key`` with its range and a scale fitted to the model's value and the ship's size."""
    declared = _declaration(key)
    minimum, maximum = declared.minimum, declared.maximum
    rule = _rule(key, minimum, maximum)
    natural = {
        # A yaw acceleration from a wind of ten times the ship's speed comparable to (u/L)^2.
        "wind_moment.yaw_coefficient": 1.0 / (100.0 * setup.model.length**2),
        "wind_moment.beam_coefficient": 1.0 / (100.0 * setup.model.length**2),
        "wind_moment.surge_coefficient": 1.0 / (100.0 * setup.model.length**2),
        "current.north": 0.1 * setup.model.service_speed,
        "current.east": 0.1 * setup.model.service_speed,
    }.get(key, rule.smallest_scale)
    try:
        value = abs(value_of(setup, key))
    except KeyError:
        value = 0.0
    return Term(
        key=key,
        unit=declared.unit,
        description=declared.description,
        scale=max(value, natural, 1e-12),
        lower=max(rule.lower, minimum),
        upper=min(rule.upper, maximum),
        null=rule.null,
        material=declared.material_size(setup.model.length, setup.model.service_speed),
    )


def measures_speed(logs: Sequence[Log]) -> bool:
    """Whether some log has a speed channel (the replay then predicts the speed, :mod:`.replay`)."""
    return any(log.speed is not None for log in logs)


def default_terms(effects: Sequence[str], logs: Sequence[Log] | None = None) -> list[str]:
    """The terms fitted by default for a set of effects, in the order of ``EFFECTS``; with ``logs`` of which
    none measures the speed, without the speed loss's, and with ``logs`` in calm air (:func:`in_calm_air`), without
    the wind effects' (the logs do not identify them)."""
    unidentified = [] if logs is None or measures_speed(logs) else ["speed_loss"]
    if logs is not None and in_calm_air(logs):
        unidentified += WIND_EFFECTS
    return [key for name in EFFECTS if name in effects and name not in unidentified for key in effect_terms(name)]


def with_speed_output(setup: ReplayModel, logs: Sequence[Log]) -> ReplayModel:
    """The model a fit to ``logs`` sails: with the speed loss on where a log measures the speed, so that the
    replay's speed is the model's own prediction (2.55, 2.53), not the ship's service speed held throughout."""
    if not measures_speed(logs) or setup.model.has("speed_loss"):
        return setup
    return replace(setup, model=setup.model.with_effects("speed_loss"))


def not_identified(model: ShipModel, logs: Sequence[Log]) -> list[str]:
    """What a fit of ``model`` to ``logs`` cannot know, in words (empty where it can know all its effects)."""
    words = []
    if not measures_speed(logs):
        kept = (
            "its speed loss is on with the starting preset's values"
            if model.has("speed_loss")
            else "it sails at constant speed (the speed loss is off)"
        )
        words.append(f"speed loss: no log measures the speed, so the fit does not identify the speed loss; {kept}")
    blowing = [name for name in WIND_EFFECTS if model.has(name)]
    if blowing and in_calm_air(logs):
        words.append(
            f"{', '.join(blowing)}: {calm_air_words(logs)}; the fit holds their terms at the starting preset's values"
        )
    sailed = sailing_model(model, logs)
    if sailed.has("steering_machine") and not model.has("steering_machine"):
        rate = math.degrees(sailed.parameter("steering_machine.rudder_rate"))
        words.append(
            "steering machine: every log records the actual rudder, which the fit takes as an input, so the fit "
            f"does not identify the steering machine; the preset keeps the starting preset's (rudder rate {rate:.3g} "
            "deg/s) to sail rudder orders"
        )
    return words


def records_actual_rudder(logs: Sequence[Log]) -> bool:
    """Whether every log records the rudder's actual angle (the steering machine's output), not its order."""
    return all(log.rudder_kind == "actual" for log in logs)


def propeller_rates(logs: Sequence[Log]) -> np.ndarray | None:
    """Every sample of the logs' propeller rate, rps, in one array; None where no log measures it."""
    rates = [log.propeller_rate for log in logs if log.propeller_rate is not None]
    return np.concatenate(rates) if rates else None


def sailing_model(model: ShipModel, logs: Sequence[Log]) -> ShipModel:
    """The fitted model as the ship its preset sails: at the logs' operating point (the median of their propeller
    rate as its service condition, where they measure it, as the preset's ``service_conditions``) and with the
    starting preset's steering machine where every log records the actual rudder (the replay takes it as an
    input, so the fit leaves the machine out, but a preset ordered to put the rudder over must move it at the
    machine's rate). It sails without the starting preset's coverage check: its values are a new fit, whose ranges
    the preset it writes records (:meth:`~ship_env.model.ShipModel.without_coverage_check`)."""
    machine = "steering_machine"
    effects = model.effects
    if machine in model.ship.enabled and not model.has(machine) and records_actual_rudder(logs):
        effects = (*effects, machine)
    rates = propeller_rates(logs)
    ship = model.ship
    if rates is not None:
        ship = replace(ship, service_conditions={**ship.service_conditions, "propeller_rate": float(np.median(rates))})
    if ship is not model.ship or effects != model.effects:
        model = ShipModel(ship, effects, model.overrides)
    return model.without_coverage_check()


def replay_inputs(logs: Sequence[Log]) -> list[str]:
    """What a fit to ``logs`` takes from them as an input (:data:`~.replay.INPUTS` the logs have), and how it
    takes the speed: the service speed and the initial speed where measured, else the service speed only."""
    present = {
        "rudder": True,
        "propeller_rate": any(log.propeller_rate is not None for log in logs),
        "wind_speed": any(log.has_wind for log in logs),
        "wind_direction": any(log.has_wind for log in logs),
    }
    inputs = [name for name in INPUTS if present[name]]
    if measures_speed(logs):
        inputs.append("speed: each run's service speed U0 and initial speed only (the speed is predicted)")
    else:
        inputs.append("service speed: each run's U0, held (no speed channel: the speed is not predicted)")
    return inputs


def with_values(setup: ReplayModel, values: Mapping[str, float]) -> ReplayModel:
    """The replay model with some terms set (checked against the parameters' declared ranges)."""
    parameters = {key: value for key, value in values.items() if key not in CURRENT_TERMS}
    return ReplayModel(
        model=setup.model.with_parameters(parameters) if parameters else setup.model,
        current_north=float(values.get("current.north", setup.current_north)),
        current_east=float(values.get("current.east", setup.current_east)),
    )


def write_record(record: np.ndarray, terms: Sequence[Term], values: np.ndarray) -> None:
    """Write the model terms' values into a copy of a parameter record (fast, unchecked)."""
    for term, value in zip(terms, values, strict=True):
        if not term.is_condition:
            record[0][term.record_field()] = value


#: The effects the true wind drives, which calm air leaves nothing to fit (:func:`why_not_fitted`).
WIND_EFFECTS = ("wind_moment", "wind_drift")


def in_calm_air(logs: Sequence[Log]) -> bool:
    """Whether no log's true wind stands out of its anemometer's noise (:attr:`~.Log.has_wind_beyond_noise`; a
    log without a wind channel has none): the wind effects would be fitted on the ship's own motion."""
    return not any(log.has_wind_beyond_noise for log in logs)


def calm_air_words(logs: Sequence[Log]) -> str:
    """Why the logs are calm air, in words."""
    medians = [float(np.median(log.wind_speed)) for log in logs if log.wind_speed is not None]
    largest = max(medians, default=0.0)
    return (
        f"calm air: no log's true wind (median at most {largest:.3g} m/s) stands out of its anemometer's noise "
        f"by {CALM_AIR_DEVIATIONS:g} deviations, so a wind effect would be fitted on the ship's own motion"
    )


def why_not_fitted(effect: str, model: ShipModel, logs: Sequence[Log]) -> str | None:
    """Why an effect cannot be added and fitted with these logs, or None if it can."""
    if effect in NOT_FITTED:
        return NOT_FITTED[effect]
    speedless = not measures_speed(logs)
    checks = {
        "speed_loss": (
            speedless,
            "no log measures the speed: the speed loss is not identified (the preset keeps its values)",
        ),
        "rudder_drag": (speedless, "no log measures the speed: the rudder's drag shows only in the speed"),
        "drift_resistance": (
            speedless or not model.has("sway"),
            "no log measures the speed: the drift's resistance shows only in the speed"
            if speedless
            else "the model has no sway: the drift's resistance is forced by the drift",
        ),
        "steering_machine": (records_actual_rudder(logs), "every log records the actual rudder"),
        "propeller_slipstream": (any(log.propeller_rate is None for log in logs), "a log has no propeller rate"),
        "wind_moment": (any(not log.has_wind for log in logs), "a log has no wind"),
        "wind_drift": (not all(log.has_wind and log.has_position for log in logs), "a log has no wind or no position"),
        "sway": (not all(log.has_position for log in logs), "a log has no position: sway shows only in the track"),
        "current": (
            not all(log.has_position for log in logs),
            "a log has no position: current shows only in the track",
        ),
    }
    failed, reason = checks.get(effect, (False, ""))
    if not failed and effect in WIND_EFFECTS and in_calm_air(logs):
        failed, reason = True, calm_air_words(logs)
    if failed:
        return reason
    try:
        model.with_effects(effect)
    except ValueError as error:
        return f"the ship preset cannot turn it on: {error}"
    return None
