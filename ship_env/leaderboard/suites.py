"""The leaderboard's fixed, seeded suites of episodes.

A :class:`Suite` is one table of the leaderboard: an environment with its keyword arguments, a
:class:`Condition` (how the sailed ship differs from the one the controllers were designed for)
and a tuple of seeded :class:`Episode` s. The same suite gives the same episodes every time: each
episode's seed and reset options are fixed here.

- **CourseChange**: course changes to starboard and to port, in calm water, in wind and current,
  and in wind, current and waves (one suite each).
- **TrackFollow**: the reference tracks T1..T6 in the thesis's wind and current (Table 6.2).
- **Robustness**: the same suites on a ship whose K*, tau* are off by a factor 2 from the values
  the controllers were designed for (``yaw.gain`` and ``yaw.time_constant`` scaled), or that sails
  at half its service speed (:data:`CONDITIONS`; at half speed a track may take twice as long).
  The environment sails that ship as its ``ship_variation`` option would draw it
  (:meth:`Condition.ship_variation`): the design ship's environment, whose observations keep the
  design ship's scales (a learned policy is not told the changed K*, as no autopilot is).
- **Fitted uncertainty** (:data:`FITTED_UNCERTAINTY`), on a fitted preset only (one whose K*, tau*
  carry standard errors: written by ``ship-env fit/improve --preset``; on any other ship the
  condition is left out): the same suites, each episode on another ship drawn from the fit
  (``ship_variation="fitted"``, :mod:`ship_env.envs.variation`): K*, tau* from Gaussians with the
  preset's standard errors, inside their ranges. The ship is drawn from the episode's seed, so the
  dev and test suites (seeds 0.. and :data:`TEST_FIRST_SEED`..) sail different ships, the same ones
  every time: the controllers are ranked on the ships the logs allow, beside the fixed factors.

The named suites (:data:`SUITE_SPECS`) select on some episodes and report on others:

- ``dev`` (alias ``quick``), for screening and tuning: the thesis experiment's changes
  {15, 30, 45, 75, 105} deg (Table 6.1.a), the tracks from their first waypoint, each episode once,
  seeds 0.. (the sea, the initial heading, the instruments' noise);
- ``full``: the dev episodes and two more repetitions with other seeds (100.., 200..); the same
  magnitudes and starts, so it sharpens the dev verdicts and is no held-out set;
- ``test``, to report: magnitudes between and beside the thesis's (:data:`TEST_COURSE_CHANGES_DEG`,
  sailed by no screen and drawn by no training: the environments draw the thesis's five), once
  each with seeds from :data:`TEST_FIRST_SEED` (other initial headings, seas and noise), and the
  tracks from a start 1 to 1.6 nm before one of their turns (``start="before_turn"``: the leg and
  the distance drawn from the test seed) where every screen sailed them from the first waypoint.
- ``unseen`` (:class:`UnseenSuiteSpec`): the dev episodes on a ship whose
  equations differ from every controller's design and training model: shipmmg's MMG KVLCC2
  (:mod:`ship_env.model.mmg_kvlcc2`) through the external-dynamics protocol
  (:mod:`ship_env.model.external`), the autopilots designed from the ``kvlcc2`` preset fitted to it.

Every spec but ``unseen`` sails :data:`DEFAULT_SHIP` unless its ``ship`` names another (a preset name
or a ship YAML, such as a fitted preset): the environments then sail that ship, the classic autopilots
are designed from its values, and the robustness conditions scale its K*, tau* and speed.

A ship whose preset is sailed by a fitted MMG model (its ``dynamics:`` block, written by ``ship-env fit-mmg --preset``
or chosen by ``fit``/``improve --preset``) sails what that model can: the nominal ship (the robustness conditions
scale ship_env's own model, which does not sail it) and its fitted uncertainty (ships drawn from the model's
jackknife) in calm water (the model has no wind or wave forces), TrackFollow included (``disturbance="calm"``, the
task then named "TrackFollow calm"); each suite left out is named with why (:meth:`SuiteSpec.left_out`).

Seeds: episode k of a suite's r-th repetition has seed ``first_seed + SEED_STRIDE * r + k``, so the
dev suite's episodes are the first repetition of the full suite's.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from functools import cache
from typing import Any

import gymnasium as gym

import ship_env  # noqa: F401  (registers the environments)
from ship_env.envs.tracks import THESIS_COURSE_CHANGES_DEG, TRACK_IDS
from ship_env.envs.variation import FITTED, draws_ships
from ship_env.model import load_ship

COURSE_CHANGE = "ship_env/CourseChange-v0"
TRACK_FOLLOW = "ship_env/TrackFollow-v0"
#: CourseChange's disturbance levels, one suite each.
COURSE_CHANGE_DISTURBANCES = ("calm", "wind_current", "wind_current_waves")
#: The seed distance between repetitions of a suite's episodes.
SEED_STRIDE = 100
#: The test suite's course-change magnitudes, deg: between and beside the thesis's five, none of them.
TEST_COURSE_CHANGES_DEG = (10.0, 20.0, 40.0, 60.0, 90.0, 120.0)
#: The test suite's first seed: its episodes' seeds lie far above any dev or full seed.
TEST_FIRST_SEED = 10_000
#: TrackFollow's start from the first waypoint (the thesis's run of the whole track).
FIRST_WAYPOINT = "first_waypoint"
#: The ship the environments sail without a ``ship`` keyword.
DEFAULT_SHIP = "container_226m"


@cache
def ship_name(ship: str) -> str:
    """The name of the ship ``ship`` (a preset name or a ship YAML path) as the tables print it:
    its preset's ``name``."""
    return load_ship(ship).name


@dataclass(frozen=True)
class Metric:
    """A figure of a suite's table.

    Attributes:
        key: the episode metric (``info["metrics"]``, :mod:`ship_env.envs.metrics`).
        heading: the column's heading, with units.
        aggregate: how the episodes' values combine: ``"mean"``, ``"max"``, or ``"finite mean"``
            (the mean over the episodes where it is finite: a settling time is infinite when the
            ship never settled).
        digits: decimals shown in the markdown table.
    """

    key: str
    heading: str
    aggregate: str = "mean"
    digits: int = 1


#: The figures of each environment's tables; the first ranks the table (lower is better).
METRICS: dict[str, tuple[Metric, ...]] = {
    COURSE_CHANGE: (
        Metric("integrated_heading_error", "integrated abs heading error [deg s]"),
        Metric("overshoot", "overshoot [deg]", digits=2),
        Metric("settling_time", "settling time [s]", "finite mean"),
        Metric("rudder_travel", "rudder travel [deg]"),
    ),
    TRACK_FOLLOW: (
        Metric("rms_cross_track_error", "RMS track error [m]"),
        Metric("max_cross_track_error", "max track error [m]", "max"),
        Metric("rudder_travel", "rudder travel [deg]"),
    ),
}

#: What an episode's completion means per environment: CourseChange's ship settled within the
#: band (a finite settling time), TrackFollow's passed the last waypoint.
COMPLETION: dict[str, str] = {COURSE_CHANGE: "settled", TRACK_FOLLOW: "reached end"}


@dataclass(frozen=True)
class Condition:
    """How the sailed ship differs from the ship the controllers were designed for.

    Attributes:
        name: the condition as the tables name it.
        slug: its name on the command line.
        scales: model parameter -> factor applied to the nominal value (``{"yaw.gain": 0.5}``);
            empty for the nominal ship.
    """

    name: str
    slug: str
    scales: Mapping[str, float] = field(default_factory=dict)
    variation: str | None = None

    def ship_variation(self) -> dict[str, tuple[float, float]] | str:
        """The condition's ship as the environments' ``ship_variation``: its named draw
        (``"fitted"``), or its ranges (each a single value; :mod:`ship_env.envs.variation`): {}
        for the nominal ship."""
        if self.variation is not None:
            return self.variation
        return {VARIATION_KEYS[key]: (scale, scale) for key, scale in self.scales.items()}

    @property
    def varies(self) -> bool:
        """Whether the sailed ship differs from the design ship (a scale or a draw)."""
        return bool(self.scales) or self.variation is not None


#: Each scaled parameter's key in the environments' ``ship_variation`` ranges.
VARIATION_KEYS = {"yaw.gain": "yaw_gain", "yaw.time_constant": "yaw_time_constant", "service_speed": "speed"}


NOMINAL = Condition("nominal", "nominal")
#: The robustness conditions: the ship's K*, tau* half or twice the design values, half speed.
K_TAU_HALF = Condition("K*, tau* x0.5", "k-tau-half", {"yaw.gain": 0.5, "yaw.time_constant": 0.5})
K_TAU_DOUBLE = Condition("K*, tau* x2", "k-tau-double", {"yaw.gain": 2.0, "yaw.time_constant": 2.0})
HALF_SPEED = Condition("half speed", "half-speed", {"service_speed": 0.5})
#: Each episode on a ship drawn from a fitted preset's standard errors (sailed on fitted presets only).
FITTED_UNCERTAINTY = Condition("fitted uncertainty", "fitted-uncertainty", variation=FITTED)
CONDITIONS = (NOMINAL, K_TAU_HALF, K_TAU_DOUBLE, HALF_SPEED, FITTED_UNCERTAINTY)


def sails_condition(condition: Condition, ship: str) -> bool:
    """Whether ``condition`` can be sailed on ``ship``: :data:`FITTED_UNCERTAINTY` on a fitted preset only, and on a
    ship sailed by its preset's fitted MMG model (:func:`sailed_by_fitted_model`) the nominal ship and, where the
    model has a jackknife, ships drawn from it."""
    preset = load_ship(ship)
    if preset.dynamics is not None and condition.varies:  # its ships are drawn from the model's jackknife only
        return condition.variation == FITTED and draws_ships(preset)
    return condition.variation != FITTED or draws_ships(preset)


def sailed_by_fitted_model(ship: str) -> str:
    """Where ``ship``'s preset is sailed by a fitted MMG model (its ``dynamics:`` block), the model's name in the
    left-out lines; else ""."""
    record = load_ship(ship).dynamics
    return "" if record is None else f"the fitted MMG model of {ship_name(ship)} (its preset's dynamics block)"


@dataclass(frozen=True)
class Episode:
    """One seeded episode: ``env.reset(seed=seed, options=options)``.

    Attributes:
        seed: the reset's seed (the sea, the initial heading, the instruments' noise).
        options: the reset's options (the course change or the track).
        label: the episode as the tables and plots name it (``"+45 deg"``, ``"T3"``).
    """

    seed: int
    options: Mapping[str, Any]
    label: str


@dataclass(frozen=True)
class Suite:
    """One table of the leaderboard.

    Attributes:
        task: the task's name in the tables (``"CourseChange calm"``).
        env_id: the environment sailed.
        env_kwargs: its keyword arguments (before the condition's ship parameters).
        condition: how the sailed ship differs from the design.
        episodes: the seeded episodes.
    """

    task: str
    env_id: str
    env_kwargs: Mapping[str, Any]
    condition: Condition
    episodes: tuple[Episode, ...]

    @property
    def name(self) -> str:
        """``"<task> | <condition>"``, unique on a leaderboard."""
        return f"{self.task} | {self.condition.name}"

    @property
    def ship(self) -> str:
        """The ship sailed: the ``ship`` keyword (a preset name or a YAML path), else :data:`DEFAULT_SHIP`."""
        return str(self.env_kwargs.get("ship", DEFAULT_SHIP))

    @property
    def ship_name(self) -> str:
        """The name of the ship sailed (:func:`ship_name`)."""
        return ship_name(self.ship)

    @property
    def metrics(self) -> tuple[Metric, ...]:
        """The figures of this suite's table; the first ranks it."""
        return METRICS[self.env_id]


def track_env_kwargs(condition: Condition) -> dict[str, Any]:
    """TrackFollow's keywords in ``condition``: a slower ship gets proportionally longer to sail the
    track (the registration's time limit is for the service speed)."""
    speed = condition.scales.get("service_speed", 1.0)
    if speed == 1.0:
        return {}
    registered_steps = gym.spec(TRACK_FOLLOW).max_episode_steps
    assert registered_steps is not None, f"{TRACK_FOLLOW} is registered with a time limit"
    return {"max_episode_steps": math.ceil(registered_steps / speed)}


def course_change_episodes(angles_deg: tuple[float, ...], repetitions: int, first_seed: int = 0) -> tuple[Episode, ...]:
    """Each change to starboard and to port, ``repetitions`` times with other seeds."""
    signed = [sign * angle for angle in angles_deg for sign in (1.0, -1.0)]
    return tuple(
        Episode(first_seed + SEED_STRIDE * repetition + k, {"course_change_deg": change}, f"{change:+g} deg")
        for repetition in range(repetitions)
        for k, change in enumerate(signed)
    )


def track_episodes(tracks: tuple[str, ...], repetitions: int, first_seed: int = 0) -> tuple[Episode, ...]:
    """Each track ``repetitions`` times with other seeds (gusts, instrument noise, a ``before_turn`` start)."""
    return tuple(
        Episode(first_seed + SEED_STRIDE * repetition + k, {"track": track}, track)
        for repetition in range(repetitions)
        for k, track in enumerate(tracks)
    )


@dataclass(frozen=True)
class SuiteSpec:
    """What ``--suite`` chooses: the episodes per task and the conditions they are sailed in.

    Attributes:
        course_changes_deg: the CourseChange magnitudes sailed (each to both sides).
        repetitions: how often each episode is sailed, with other seeds.
        tracks: the TrackFollow tracks.
        conditions: the ship conditions (:data:`FITTED_UNCERTAINTY` left out on a ship that is not a
            fitted preset).
        course_change_disturbances: the CourseChange disturbance levels, one suite each.
        first_seed: the seed of the first episode (:data:`SEED_STRIDE` apart per repetition).
        track_start: TrackFollow's ``start`` (:data:`~ship_env.envs.track_follow_task.STARTS`).
        ship: the ship sailed and designed for, a preset name or a ship YAML path; ``None``: the
            environments' own, :data:`DEFAULT_SHIP` (no ``ship`` keyword given).
    """

    course_changes_deg: tuple[float, ...] = THESIS_COURSE_CHANGES_DEG
    repetitions: int = 1
    tracks: tuple[str, ...] = TRACK_IDS
    conditions: tuple[Condition, ...] = CONDITIONS
    course_change_disturbances: tuple[str, ...] = COURSE_CHANGE_DISTURBANCES
    first_seed: int = 0
    track_start: str = FIRST_WAYPOINT
    ship: str | None = None

    def left_out(self) -> list[str]:
        """A line per condition and disturbance of this spec that its ship cannot sail, saying why (the fitted
        uncertainty on a ship that is no fitted preset is said by the command, which knows what the user asked)."""
        sailed_ship = DEFAULT_SHIP if self.ship is None else self.ship
        model = sailed_by_fitted_model(sailed_ship)
        if not model:
            return []
        lines = [
            f"the {condition.name} condition: it scales or draws ship_env's model of the ship, and {model} sails it"
            for condition in self.conditions
            if condition.varies and not sails_condition(condition, sailed_ship)
        ]
        calm_air = [level for level in self.course_change_disturbances if level != "calm"]
        if calm_air:
            lines.append(f"CourseChange {', '.join(calm_air)}: {model} has no wind or wave forces")
        if self.tracks:
            lines.append(
                f"TrackFollow in the thesis's wind and current: {model} has no wind forces (sailed calm instead)"
            )
        return lines

    def suites(self) -> list[Suite]:
        """The suites, condition by condition: CourseChange per disturbance, then TrackFollow (what a ship sailed by
        its preset's fitted MMG model cannot sail left out, :meth:`left_out`)."""
        course_changes = course_change_episodes(self.course_changes_deg, self.repetitions, self.first_seed)
        tracks = track_episodes(self.tracks, self.repetitions, self.first_seed)
        start = {} if self.track_start == FIRST_WAYPOINT else {"start": self.track_start}
        ship = {} if self.ship is None else {"ship": self.ship}
        suites = []
        sailed_ship = DEFAULT_SHIP if self.ship is None else self.ship
        calm_only = bool(sailed_by_fitted_model(sailed_ship))
        disturbances = [d for d in self.course_change_disturbances if not calm_only or d == "calm"]
        track_task, calm = ("TrackFollow calm", {"disturbance": "calm"}) if calm_only else ("TrackFollow", {})
        for condition in self.conditions:
            if not sails_condition(condition, sailed_ship):
                continue
            for disturbance in disturbances:
                suites.append(
                    Suite(
                        f"CourseChange {disturbance}",
                        COURSE_CHANGE,
                        {**ship, "disturbance": disturbance},
                        condition,
                        course_changes,
                    )
                )
            if tracks:
                track_kwargs = {**ship, **track_env_kwargs(condition), **start, **calm}
                suites.append(Suite(track_task, TRACK_FOLLOW, track_kwargs, condition, tracks))
        return suites


#: The named suites (the module's docstring): ``dev`` sails every episode once in every condition (the
#: nominal ship, its K*, tau* halved and doubled, half speed, and on a fitted preset its fitted
#: uncertainty), ``full`` three times, ``test`` once
#: on held-out magnitudes, seeds and track starts; ``quick`` is ``dev`` by its former name.
DEV = SuiteSpec()
SUITE_SPECS: dict[str, SuiteSpec] = {
    "dev": DEV,
    "quick": DEV,
    "full": SuiteSpec(repetitions=3),
    "test": SuiteSpec(
        course_changes_deg=TEST_COURSE_CHANGES_DEG, first_seed=TEST_FIRST_SEED, track_start="before_turn"
    ),
}


# -- unseen physics ----------------------------------------------------------------------------------
#: The ship of the unseen-physics suite: shipmmg's MMG model of KVLCC2 (:mod:`ship_env.model.mmg_kvlcc2`),
#: equations no controller was designed or trained on; the autopilots are designed from the ``kvlcc2``
#: preset, whose De Keizer coefficients are fitted to it.
MMG_KVLCC2 = Condition("MMG KVLCC2 (unseen physics)", "mmg-kvlcc2")
#: The environments' keywords that sail it: the preset is what the bridge knows, the MMG model the motion.
MMG_KVLCC2_ENV_KWARGS: Mapping[str, Any] = {"ship": "kvlcc2", "dynamics": "ship_env.model.mmg_kvlcc2:MmgKvlcc2"}


@dataclass(frozen=True)
class UnseenSuiteSpec(SuiteSpec):
    """The unseen-physics suites: every controller on the MMG KVLCC2 at its service speed (15.5 kn).

    CourseChange in calm water and in wind and current (``course_change_disturbances``; the MMG
    model has no wave forces), and TrackFollow in the thesis's wind and current. The tasks take their
    scales from the ship (:mod:`ship_env.envs.ship_scales`): the tracks in proportion to 320 m, the
    control step 1 s in units of L / U (1.69 s), so the registered episode lengths hold.
    The episodes (seeds, changes, tracks) are the other suites'; ``conditions`` is not used (the
    ship is :data:`MMG_KVLCC2`), nor may ``ship`` be given.
    """

    course_change_disturbances: tuple[str, ...] = ("calm", "wind_current")

    def suites(self) -> list[Suite]:
        """CourseChange per disturbance level, then TrackFollow, on the MMG KVLCC2."""
        if self.ship is not None:
            raise ValueError(f"ship {self.ship}: the unseen suite sails its own ship, the MMG KVLCC2")
        if "wind_current_waves" in self.course_change_disturbances:
            raise ValueError("disturbances: the MMG KVLCC2 has no wave forces; sail calm or wind_current")
        course_changes = course_change_episodes(self.course_changes_deg, self.repetitions)
        suites = [
            Suite(
                f"CourseChange {level}",
                COURSE_CHANGE,
                {**MMG_KVLCC2_ENV_KWARGS, "disturbance": level},
                MMG_KVLCC2,
                course_changes,
            )
            for level in self.course_change_disturbances
        ]
        if self.tracks:
            tracks = track_episodes(self.tracks, self.repetitions)
            suites.append(Suite("TrackFollow", TRACK_FOLLOW, dict(MMG_KVLCC2_ENV_KWARGS), MMG_KVLCC2, tracks))
        return suites


SUITE_SPECS["unseen"] = UnseenSuiteSpec()
