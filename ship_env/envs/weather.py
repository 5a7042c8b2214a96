"""The wind, current and waves an episode is sailed in, drawn at a disturbance level.

Shared by the course-change and course-keeping tasks (:class:`WeatherTask`). Directions follow the simulator's
conventions (:class:`~ship_env.model.Conditions`): the wind and the waves come *from* their
direction, the current sets *towards* its direction; angles in radians clockwise from north.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

from ship_env.envs.checks import check_choice, check_range
from ship_env.envs.ship_scales import ShipScales
from ship_env.envs.task import WAVE_EFFECTS, ShipTask
from ship_env.model import Conditions

#: Disturbance levels; ``"random"`` draws one of them per episode.
DISTURBANCES = ("calm", "wind_current", "wind_current_waves")
RANDOM_DISTURBANCE = "random"
#: The level reported for an episode whose conditions were given in ``reset(options=...)``.
CUSTOM_DISTURBANCE = "custom"
#: Still water and air, shared by every calm episode (``Conditions`` is frozen).
CALM = Conditions()

#: Waves come from within this angle of the wind's direction (assumed: a wind sea).
WAVE_SPREAD = math.radians(30.0)

#: Uniform numbers :meth:`WeatherRanges.conditions` reads, whatever the level.
WEATHER_DRAWS = 7

#: The effects that sail each condition a reset option can bring: where the model has none of them (and
#: does not take them on, as the preset's defaults take on the waves'), the option is refused
#: (:func:`check_sailed`).
SAILING_EFFECTS = {
    "wind_speed": ("wind_moment", "wind_drift"),
    "current_speed": ("current",),
    "wave_height": WAVE_EFFECTS,
}
#: The conditions an episode at each level can have (``"random"``: any level's).
LEVEL_CONDITIONS = {
    "calm": (),
    "wind_current": ("wind_speed", "current_speed"),
    "wind_current_waves": ("wind_speed", "current_speed", "wave_height"),
    RANDOM_DISTURBANCE: ("wind_speed", "current_speed", "wave_height"),
}


def _within(bounds: tuple[float, float], fraction: float) -> float:
    return bounds[0] + (bounds[1] - bounds[0]) * fraction


def _times(bounds: tuple[float, float], factor: float) -> tuple[float, float]:
    return bounds[0] * factor, bounds[1] * factor


def has_waves(disturbance: str) -> bool:
    """Whether episodes at this level (or drawn from it) can have waves."""
    return disturbance in ("wind_current_waves", RANDOM_DISTURBANCE)


@dataclass(frozen=True)
class WeatherRanges:
    """The ranges the weather is drawn from, uniformly.

    Attributes:
        wind_speed_range, current_speed_range: m/s.
        wave_height_range: significant wave height H_s, m.
        wave_period_range: peak period T_p, s.
    """

    wind_speed_range: tuple[float, float] = (5.0, 10.0)
    current_speed_range: tuple[float, float] = (0.5, 1.5)
    wave_height_range: tuple[float, float] = (1.0, 4.0)
    wave_period_range: tuple[float, float] = (6.0, 10.0)

    def __post_init__(self) -> None:
        for name in ("wind_speed_range", "current_speed_range", "wave_height_range"):
            object.__setattr__(self, name, check_range(name, getattr(self, name)))
        object.__setattr__(self, "wave_period_range", check_range("wave_period_range", self.wave_period_range, 1e-3))

    def scaled(self, scales: ShipScales) -> WeatherRanges:
        """These ranges (drawn for the reference ship) in the scales of another ship
        (:mod:`ship_env.envs.ship_scales`): wind and current speeds in units of its speed U (the
        wind's and the current's forces and set then stand to the hull's as on the reference ship),
        wave heights in its length L, wave periods in sqrt(L) (the waves' lengths, g T^2 / (2 pi), in
        proportion to L)."""
        wave_period = math.sqrt(scales.length)
        return WeatherRanges(
            _times(self.wind_speed_range, scales.speed),
            _times(self.current_speed_range, scales.speed),
            _times(self.wave_height_range, scales.length),
            _times(self.wave_period_range, wave_period),
        )

    def conditions(self, disturbance: str, draws: Sequence[float]) -> Conditions:
        """The weather of a level (one of ``DISTURBANCES``) from ``WEATHER_DRAWS`` uniforms in [0, 1).

        Wind speed and current speed uniform in their ranges, the wind from and the current towards
        uniform directions; at ``"wind_current_waves"`` waves of uniform H_s and T_p from the
        wind's direction +-30 deg. ``"calm"`` is still water and air.
        """
        if disturbance == "calm":
            return CALM
        wind_direction = 2.0 * math.pi * draws[1]
        weather = {
            "wind_speed": _within(self.wind_speed_range, draws[0]),
            "wind_direction": wind_direction,
            "current_speed": _within(self.current_speed_range, draws[2]),
            "current_direction": 2.0 * math.pi * draws[3],
        }
        if disturbance == "wind_current_waves":
            weather["wave_height"] = _within(self.wave_height_range, draws[4])
            weather["wave_period"] = _within(self.wave_period_range, draws[5])
            weather["wave_direction"] = (wind_direction + WAVE_SPREAD * (2.0 * draws[6] - 1.0)) % (2.0 * math.pi)
        return Conditions(**weather)


def check_sailed(option: str, conditions: Sequence[str], task: ShipTask) -> None:
    """``ValueError`` where a reset ``option`` brings one of the ``conditions`` (names in
    ``SAILING_EFFECTS``) that none of the ``task``'s model's effects sails and the model does not take
    on (the waves' effects, which the preset's defaults take on: ``ShipTask.model_for``), naming the
    condition, the effects and the constructor argument that sails it (``effects``). A ship simulated
    outside ship_env (``sailing_model`` None) sails the conditions itself: nothing is checked."""
    model = task.sailing_model
    if model is None:
        return
    for name in conditions:
        effects = SAILING_EFFECTS[name]
        if any(model.has(effect) for effect in effects) or (name == "wave_height" and task.adds_wave_effects):
            continue
        raise ValueError(
            f"{option}: its {name} is sailed by {' or '.join(effects)}, none of them among the effects the "
            "environment was made with, so it would do nothing; make the environment with effects including them"
        )


def check_conditions(name: str, conditions: object, task: ShipTask) -> Conditions:
    """``conditions`` given in ``reset(options=...)``, checked: a ``Conditions`` with a positive
    service speed, whose wind, current and waves the ``task``'s model sails (:func:`check_sailed`)."""
    if not isinstance(conditions, Conditions):
        raise TypeError(f"{name}: expected a Conditions, got {conditions!r}")
    if conditions.service_speed is not None and conditions.service_speed <= 0.0:
        raise ValueError(f"{name}.service_speed: must be positive, got {conditions.service_speed!r}")
    for condition in SAILING_EFFECTS:
        value = getattr(conditions, condition)
        if value > 0.0:
            check_sailed(f"{name}.{condition} = {value!r}", [condition], task)
    return conditions


class WeatherTask(ShipTask):
    """A task sailed in weather drawn at a disturbance level: its options and its weather draw.

    Args:
        disturbance: ``"calm"``, ``"wind_current"``, ``"wind_current_waves"`` or ``"random"``
            (one of the three per episode).
        wind_speed_range, current_speed_range: m/s, drawn uniformly; ``None`` (default): 5 to 10
            m/s and 0.5 to 1.5 m/s on the 226 m container ship at 19 kn, in units of the ship's speed
            on another (:meth:`WeatherRanges.scaled`).
        wave_height_range, wave_period_range: significant height (m) and peak period (s); ``None``
            (default): 1 to 4 m and 6 to 10 s on the container ship, in units of the ship's length
            and its square root on another.
        **ship_options: the keywords every task shares (:class:`~ship_env.envs.task.ShipTask`);
            ``effects=None`` takes the preset's defaults, plus ``wave_filter`` and
            ``wave_spectrum`` when ``disturbance`` can bring waves, or from the first episode a
            reset option brings waves to (``ShipTask.model_for``). With ``effects`` given, an option
            that brings weather none of them sails is refused (:func:`check_sailed`).
    """

    def __init__(
        self,
        *,
        disturbance: str,
        wind_speed_range: tuple[float, float] | None = None,
        current_speed_range: tuple[float, float] | None = None,
        wave_height_range: tuple[float, float] | None = None,
        wave_period_range: tuple[float, float] | None = None,
        **ship_options: Any,
    ) -> None:
        self.disturbance = check_choice("disturbance", disturbance, (*DISTURBANCES, RANDOM_DISTURBANCE))
        given = {
            "wind_speed_range": wind_speed_range,
            "current_speed_range": current_speed_range,
            "wave_height_range": wave_height_range,
            "wave_period_range": wave_period_range,
        }
        super().__init__(extra_effects=WAVE_EFFECTS if has_waves(disturbance) else (), **ship_options)
        ship_ranges = vars(WeatherRanges().scaled(self.scales))
        #: The ranges the weather is drawn from: those given, the others the reference's in this ship's scales.
        self.weather = WeatherRanges(
            **{name: ship_ranges[name] if bounds is None else bounds for name, bounds in given.items()}
        )

    def draw_weather(
        self, level_draw: float, weather_draws: Sequence[float], options: Mapping[str, Any]
    ) -> tuple[str, Conditions]:
        """An episode's disturbance level and conditions: the level uniform over ``DISTURBANCES``
        (if ``"random"``) from ``level_draw``, the weather from ``WEATHER_DRAWS`` uniforms
        (:meth:`WeatherRanges.conditions`); ``options`` may pin the ``disturbance`` or give the
        ``conditions`` (reported as ``"custom"``), not both; ``ValueError`` where they bring weather
        the model does not sail (:func:`check_sailed`)."""
        if "conditions" in options:
            if "disturbance" in options:
                raise ValueError(
                    "options: 'disturbance' and 'conditions' together; the conditions are sailed as given "
                    "(reported as 'custom'): give one of them"
                )
            conditions = check_conditions("options['conditions']", options["conditions"], self)
            return CUSTOM_DISTURBANCE, conditions
        disturbance = options.get("disturbance", self.disturbance)
        if "disturbance" in options:
            check_choice("options['disturbance']", disturbance, (*DISTURBANCES, RANDOM_DISTURBANCE))
            option = f"options['disturbance'] = {disturbance!r}"
            check_sailed(option, LEVEL_CONDITIONS[disturbance], self)
        if disturbance == RANDOM_DISTURBANCE:
            disturbance = DISTURBANCES[int(level_draw * len(DISTURBANCES))]
        return disturbance, self.weather.conditions(disturbance, weather_draws)
