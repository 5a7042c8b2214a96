"""What every ship-steering task shares: the ship model, the rudder, the step, the instruments, the action.

:class:`ShipTask` is the base of the course-change, track-following and course-keeping tasks. It
builds the ship model from a preset, sets the rudder limit delta_max that action +-1 orders, the
control step, the instruments' noise and position-fix interval (:mod:`ship_env.envs.sensors`),
turns actions into ordered rudder angles, continuous or discrete, and varies the ship from episode
to episode if asked (:mod:`ship_env.envs.variation`).
"""

from __future__ import annotations

import dataclasses
import functools
import math
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from gymnasium import spaces

from ship_env.envs.checks import check_choice, check_number, check_whole_number
from ship_env.envs.envelope import envelope_limits
from ship_env.envs.sensors import sensors_record
from ship_env.envs.ship_scales import ship_scales
from ship_env.envs.uniform_box import UniformBox
from ship_env.envs.variation import FITTED, FittedShipVariation, ShipFactors, ShipVariation, sailed_conditions
from ship_env.model import Conditions, ShipModel, Simulator, load_ship
from ship_env.model.external import DynamicsSource, ExternalSimulator, dynamics_factory, preset_dynamics
from ship_env.model.mmg_fitted import MmgFitted
from ship_env.model.mmg_record import MmgRecord

#: ``action_type``: a Box(-1, 1, (1,)) fraction of delta_max, or one of ``rudder_levels`` angles.
ACTION_TYPES = ("continuous", "discrete")
#: The effects that sail the waves: the HF yaw the compass sees (Fig. 2.13) and the sea's yaw moment
#: (2.89-2.91). The preset's defaults take them on where an episode brings waves (:meth:`ShipTask.model_for`).
WAVE_EFFECTS = ("wave_filter", "wave_spectrum")
#: The keywords that change what a policy observes or how often it acts (the tasks' observation options
#: and decision interval): a policy trained with them steers only an environment made with the same (a
#: leaderboard sails it so).
OBSERVATION_KEYWORDS = ("observation_history", "track_preview", "decision_interval", "observe_design_speed")


def observation_keywords(env_kwargs: Mapping[str, Any]) -> dict[str, Any]:
    """The :data:`OBSERVATION_KEYWORDS` among an environment's keyword arguments."""
    return {key: value for key, value in env_kwargs.items() if key in OBSERVATION_KEYWORDS}


@dataclass(frozen=True)
class TaskScenario:
    """What every task's episode has; a task's scenario adds its own fields (positional after these).

    Attributes:
        disturbance: the level it was drawn at (``"calm"``, ``"thesis"``, ...), or ``"custom"``
            (conditions given at reset).
        conditions: wind, current, waves and speed for the simulator.
        seed: the simulator's seed for the episode (its gusts, wave yaw, sea and sensor noise).
        ship: the ship's K*, tau*, speed and weather factors when ``ship_variation`` drew them
            (:class:`~ship_env.envs.variation.ShipFactors`), else ``None`` (the preset's ship).
    """

    disturbance: str
    conditions: Conditions
    seed: int
    ship: ShipFactors | None = field(default=None, kw_only=True)


class ShipTask:
    """The options every task shares; a task's other keywords come first in its own signature.

    Args:
        ship: a ship preset name (``configs/ships``) or a YAML path.
        ship_parameters: parameter overrides for the preset, ``{"yaw.gain": 1.2}`` (SI units).
        effects: the model's effects; ``None`` takes the preset's defaults plus ``extra_effects``, and
            ``WAVE_EFFECTS`` from the first episode whose conditions have waves (given at reset), which
            then sail every later episode too (:meth:`model_for`).
        extra_effects: effects the task adds to the preset's defaults (the waves' when it has waves).
        rudder_limit_deg: delta_max, the hard-over angle action +-1 orders, deg (it becomes the
            model's rudder limit).
        dt: the control step, s (one simulator step); ``None`` (default): the ship's, 1 s in units
            of L / U (:mod:`ship_env.envs.ship_scales`: 1 s for the 226 m container ship at 19 kn,
            0.36 s for a 3 m model at 0.35 m/s), so an episode's steps span the same manoeuvre on
            every ship.
        sensor_noise_scale: multiplies ``sensors.SENSOR_NOISE`` (itself in the ship's scales: the
            position's in ship lengths, the log's in U, the gyro's in U / L); 0 gives noise-free
            instruments.
        fix_interval: s between position fixes (held in between); 0 fixes at every step; ``None``
            (default): the task's ``reference_fix_interval`` in units of L / U.
        action_type: ``"continuous"`` (``Box(-1, 1, (1,))``, the ordered rudder as a fraction of
            delta_max, clipped to [-1, 1]) or ``"discrete"`` (``Discrete(rudder_levels)``: action k
            orders -delta_max + 2 k delta_max / (rudder_levels - 1)).
        rudder_levels: the number of rudder angles of the discrete action, at least 2 (odd
            numbers include amidships).
        ship_variation: ``None`` (default) sails the preset's ship every episode; ``True`` or a
            mapping of ranges draws each episode's ship (K*, tau*, service speed, weather
            strength; :mod:`ship_env.envs.variation`), recorded as the scenario's ``ship``;
            ``"fitted"`` draws K* and tau* from a fitted preset's standard errors (a Gaussian
            truncated to their ranges by redrawing; a preset without them is refused); on a preset
            sailed by its fitted MMG model (its ``dynamics:`` block) each episode's ship is drawn from
            that model's jackknife, from the episode's seed
            (:meth:`~ship_env.model.mmg_record.MmgRecord.drawn`).
        observation_history: how many past steps of the heading error, rate of turn and rudder
            observations (``history_observations``) follow the observation, newest first (0,
            default: none). A policy without memory can then tell how the ship answers its rudder.
        decision_interval: how many simulator steps (of ``dt``) one environment step holds the ordered
            rudder for (1, default: every step). The step's reward is the sum of the simulator steps'
            rewards, its observation the last one's; a ship whose episode terminates within the
            interval keeps the record of its terminal step. A policy then decides every
            ``decision_interval * dt`` s: the episode has that many times fewer decisions (a shorter
            horizon for its discount) and each decision's effect shows within the step.
            ``max_episode_steps`` counts environment steps (decisions).
        observe_design_speed: ``False`` (default): the speed observation is the log speed over the
            episode's own service speed (1 on a straight course at any service speed); ``True``: over
            the preset's, so a ship that sails slower than designed (``ship_variation``'s speed, or
            conditions given at reset) shows it, as the log shows a gain-scheduled autopilot.
        dynamics: ``None`` (default): the preset's own model sails it: ship_env's simulator of its effects, or
            the model its ``dynamics:`` block names (a fitted MMG model of ``ship-env fit-mmg``); ``"native"``:
            ship_env's simulator of its effects whatever the preset names; or a ship simulated outside ship_env
            (:mod:`ship_env.model.external`): an adapter, its class (one adapter per ship), its
            ``"module:attribute"`` import path, or a fitted MMG model's file. The preset then gives what the
            bridge knows of the ship (its length, speed, K*: the observations' scales) and the autopilots'
            design model; the adapter gives the motion.
        info_keys: the keys each step's information gives, among ``measurement``, ``state``,
            ``metrics``, ``envelope`` and the task's own (``ShipBatch.info``); ``None`` (default): all.
            ``()`` builds none: a learner that reads none of them steps faster (building the
            information is the larger part of a single environment's step). ``reset``'s
            ``scenario``, the keys the terminating step adds and the vector environment's
            ``diverged`` are there whatever it says.
    """

    #: s between position fixes on the reference ship when ``fix_interval`` is ``None`` (0: every step).
    reference_fix_interval: float = 0.0
    #: The observation's elements ``observation_history`` remembers (each task sets its own).
    history_observations: tuple[int, ...] = ()
    #: The task's observation space, its constants record and what its compiled update reads
    #: besides the simulator's and the batch's arrays (each task sets them).
    observation_space: spaces.Box
    parameters: np.ndarray
    kernel_arguments: tuple[np.ndarray, ...]

    def __init__(
        self,
        *,
        ship: str | Path = "container_226m",
        ship_parameters: Mapping[str, float] | None = None,
        effects: Sequence[str] | None = None,
        extra_effects: Sequence[str] = (),
        rudder_limit_deg: float = 20.0,
        dt: float | None = None,
        sensor_noise_scale: float = 1.0,
        fix_interval: float | None = None,
        action_type: str = "continuous",
        rudder_levels: int = 7,
        ship_variation: bool | str | Mapping[str, Sequence[float]] | None = None,
        observation_history: int = 0,
        decision_interval: int = 1,
        observe_design_speed: bool = False,
        dynamics: DynamicsSource | None = None,
        info_keys: Sequence[str] | None = None,
    ) -> None:
        self.rudder_limit = math.radians(check_number("rudder_limit_deg", rudder_limit_deg, 1e-3, 90.0))
        if dt is not None:
            check_number("dt", dt, 1e-6)
        if fix_interval is not None:
            check_number("fix_interval", fix_interval, 0.0)
        self.action_type = check_choice("action_type", action_type, ACTION_TYPES)
        levels = check_whole_number("rudder_levels", rudder_levels, 2)
        noise_scale = check_number("sensor_noise_scale", sensor_noise_scale, 0.0)
        self.variation: ShipVariation | FittedShipVariation | None = None
        if isinstance(ship_variation, str):
            if ship_variation != FITTED:
                raise ValueError(
                    f"ship_variation: expected true, {FITTED!r} or a mapping of ranges, got {ship_variation!r}"
                )
        elif ship_variation is not None and ship_variation is not False:
            self.variation = ShipVariation(ship_variation)
        self.observation_history = check_whole_number("observation_history", observation_history, 0)
        self.decision_interval = check_whole_number("decision_interval", decision_interval, 1)
        if not isinstance(observe_design_speed, bool):
            raise TypeError(f"observe_design_speed: expected true or false, got {observe_design_speed!r}")
        self.observe_design_speed = observe_design_speed
        keys = tuple(info_keys) if isinstance(info_keys, Iterable) and not isinstance(info_keys, str) else None
        if info_keys is not None and (keys is None or not all(isinstance(key, str) for key in keys)):
            raise ValueError(f"info_keys: expected a sequence of key names or None, got {info_keys!r}")
        #: The keys of each step's information (``None``: all), checked by the batch that builds it.
        self.info_keys = keys
        preset = load_ship(ship)
        presets_effects = effects is None
        if effects is None:
            effects = (*preset.enabled, *extra_effects)
        self.model = ShipModel(preset, effects, {**(ship_parameters or {}), "rudder_limit": self.rudder_limit})
        sailed_by = preset_dynamics(self.model, dynamics)
        #: Makes one external adapter per ship, or ``None`` for ship_env's own simulator.
        self.make_dynamics = None if sailed_by is None else dynamics_factory(sailed_by)
        #: Whether an episode that brings waves adds ``WAVE_EFFECTS`` to the model (:meth:`model_for`): its
        #: effects are the preset's defaults, sailed by ship_env's simulator.
        self.adds_wave_effects = presets_effects and sailed_by is None
        if ship_variation == FITTED and isinstance(sailed_by, MmgRecord):  # its adapters draw each episode's ship
            try:
                sailed_by.check_drawable()
            except ValueError as error:
                raise ValueError(f"ship_variation={FITTED!r}: {error}") from None
            self.make_dynamics = functools.partial(MmgFitted, sailed_by, draw=True)
        elif ship_variation == FITTED:
            self.variation = FittedShipVariation(self.model)
        #: The ship's length, speed and time over the reference ship's (:mod:`ship_env.envs.ship_scales`).
        self.scales = ship_scales(self.model)
        #: The model's validity envelope, as the compiled check reads it from :meth:`parameter_record`
        #: (:mod:`ship_env.envs.envelope`).
        self.envelope_limits = envelope_limits(self.model)
        self.dt = self.scales.dt if dt is None else float(dt)
        if fix_interval is None:
            fix_interval = self.reference_fix_interval * self.scales.time
        self.sensors = sensors_record(noise_scale, fix_interval, self.scales)
        #: K* delta_max / L: the linear model's steady rate of turn at full rudder per m/s of speed
        #: (6.4.4.2: r_ss = K* (U/L) delta_max, about 40 deg/min at 19 kn and 10 deg).
        self.full_rudder_rate_per_speed = self.model.parameter("yaw.gain") * self.rudder_limit / self.model.length

        if self.action_type == "continuous":
            self.action_space: spaces.Space = UniformBox(-1.0, 1.0, shape=(1,), dtype=np.float32)
            self._levels = np.zeros(0)
        else:
            self.action_space = spaces.Discrete(levels)
            self._levels = np.linspace(-1.0, 1.0, levels) * self.rudder_limit

    def simulator(self, num_ships: int) -> Simulator:
        """The simulator of ``num_ships`` ships stepped every ``dt``: ship_env's, or the external adapters'."""
        if self.make_dynamics is None:
            return Simulator(self.model, num_ships=num_ships, dt=self.dt)
        return ExternalSimulator(self.model, self.make_dynamics, num_ships=num_ships, dt=self.dt)

    def model_for(self, conditions: Iterable[Conditions]) -> ShipModel:
        """The model that sails episodes in ``conditions``: the task's, which takes on ``WAVE_EFFECTS`` (for
        these episodes and every later one, at the cost of the waves' computation each step; compiled
        then, if not cached) where one brings waves and the model has none of them, with
        ``adds_wave_effects``."""
        if (
            self.adds_wave_effects
            and not any(self.model.has(effect) for effect in WAVE_EFFECTS)
            and any(c.wave_height > 0.0 for c in conditions)
        ):
            self.model = self.model.with_effects(*WAVE_EFFECTS)
        return self.model

    @property
    def sailing_model(self) -> ShipModel | None:
        """The model whose effects sail the episodes' conditions: the task's, or ``None`` for a ship
        simulated outside ship_env (its adapter sails them)."""
        return self.model if self.make_dynamics is None else None

    def parameter_record(self, **values: float | bool) -> np.ndarray:
        """The task's constants as its compiled update reads them: one record with ``rudder_limit``
        (rad), ``full_rudder_rate_per_speed`` (K* delta_max / L) and ``observed_speed_scale`` (m/s:
        the preset's service speed with ``observe_design_speed``, else 0: the episode's own), the
        envelope's ``envelope_limits``, then ``values`` (float64, or bool for a flag). It is the
        first of the task's ``kernel_arguments``."""
        values = {
            "rudder_limit": self.rudder_limit,
            "full_rudder_rate_per_speed": self.full_rudder_rate_per_speed,
            "observed_speed_scale": self.model.service_speed if self.observe_design_speed else 0.0,
            **self.envelope_limits,
            **values,
        }
        dtype = np.dtype([(name, np.bool_ if isinstance(v, bool) else np.float64) for name, v in values.items()])
        record = np.zeros(1, dtype=dtype)
        for name, value in values.items():
            record[0][name] = value
        return record

    def observation_box(self, low: np.ndarray, high: np.ndarray) -> spaces.Box:
        """The observation space: the task's bounds, then ``observation_history`` copies of those of
        the remembered elements."""
        remembered = list(self.history_observations) * self.observation_history
        return spaces.Box(
            np.concatenate((low, low[remembered])), np.concatenate((high, high[remembered])), dtype=np.float32
        )

    # -- episodes --------------------------------------------------------------------------------
    def draw_scenario(self, rng: np.random.Generator, options: Mapping[str, Any] | None = None) -> Any:
        """Draw an episode from ``rng``: the task's (:meth:`draw_task_scenario`), then its ship.

        With ``ship_variation`` the ship is drawn after the task's numbers and sails the task's
        conditions (its K*, tau* and speed, the weather scaled); conditions given in ``options``
        are sailed as they are (the draw is made all the same, so one seed gives one sequence).
        """
        scenario = self.draw_task_scenario(rng, options)
        if self.variation is None:
            return scenario
        ship = self.variation.draw(rng)
        if options and "conditions" in options:
            return scenario
        conditions = sailed_conditions(scenario.conditions, ship, self.model.service_speed)
        return dataclasses.replace(scenario, conditions=conditions, ship=ship)

    def draw_task_scenario(self, rng: np.random.Generator, options: Mapping[str, Any] | None) -> Any:
        """The task's episode drawn from ``rng`` (the scenario dataclass of the task, with a ``ship`` field)."""
        raise NotImplementedError

    # -- actions ---------------------------------------------------------------------------------
    def rudder_order(self, action: object) -> float:
        """One environment's action as the ordered rudder angle, rad; ``ValueError`` if it is malformed."""
        if self.action_type == "continuous":
            fraction = math.nan
            if isinstance(action, np.ndarray) and action.ndim == 1 and action.size == 1 and action.dtype.kind == "f":
                fraction = action.item()  # the common action, read without a conversion
            if not math.isfinite(fraction):  # any other, converted and checked (it raises where malformed)
                fraction = self._continuous(action, (1,)).item()
            if not -1.0 <= fraction <= 1.0:  # clipped (a comparison costs less than min and max)
                fraction = math.copysign(1.0, fraction)
            return fraction * self.rudder_limit
        return float(self._levels[self._discrete(action, ())])

    def rudder_orders(self, actions: object, num_envs: int, out: np.ndarray) -> np.ndarray:
        """N environments' actions as ordered rudder angles, rad, written into ``out`` (N,)."""
        if self.action_type == "continuous":
            np.clip(self._continuous(actions, (num_envs, 1))[:, 0], -1.0, 1.0, out=out)
            out *= self.rudder_limit
        else:
            np.take(self._levels, self._discrete(actions, (num_envs,)), out=out)
        return out

    @staticmethod
    def _continuous(action: object, shape: tuple[int, ...]) -> np.ndarray:
        """The action as a float64 array of ``shape``; ``ValueError`` if it is not that or not finite."""
        try:
            array = np.asarray(action, dtype=np.float64)
        except (TypeError, ValueError):
            raise ValueError(f"action: expected an array of shape {shape} in [-1, 1], got {action!r}") from None
        if array.shape != shape:
            raise ValueError(f"action: expected shape {shape}, got {action!r} of shape {array.shape}")
        if not (math.isfinite(array.item()) if array.size == 1 else np.isfinite(array).all()):
            index = tuple(int(i) for i in np.argwhere(~np.isfinite(array))[0])
            raise ValueError(f"action{list(index)}: must be finite, got {float(array[index])} in action {action!r}")
        return array

    def _discrete(self, action: object, shape: tuple[int, ...]) -> np.ndarray:
        """The action as rudder-level indices of ``shape``; ``ValueError`` unless whole numbers in range."""
        array = np.asarray(action)
        count = len(self._levels)
        if array.shape != shape or not np.issubdtype(array.dtype, np.integer) or array.dtype == np.bool_:
            raise ValueError(f"action: expected integers of shape {shape} in [0, {count}), got {action!r}")
        if np.any((array < 0) | (array >= count)):
            raise ValueError(f"action: expected integers in [0, {count}), got {action!r}")
        return array

    def check_options(self, options: Mapping[str, Any] | None, known: frozenset[str]) -> dict[str, Any]:
        """``reset``'s options as a dict; ``ValueError`` naming unknown keys."""
        options = dict(options or {})
        unknown = sorted(set(options) - known)
        if unknown:
            raise ValueError(f"options: unknown keys {unknown}; known: {', '.join(sorted(known))}")
        return options
