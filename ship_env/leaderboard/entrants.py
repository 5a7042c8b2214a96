"""The controllers on the leaderboard: the classic baselines of :mod:`ship_env.baselines.presys` and SB3 policies.

An :class:`Entrant` names a controller and the environment it steers, and builds a fresh one for
every episode (so an episode's result does not depend on the episodes sailed before it, nor on
how the episodes are split between workers). Entrants hold names and paths only: they travel to
Ray workers as they are.

Classic controllers are designed for the nominal ship: they are built from a
:class:`DesignedTask`, the sailed task with the nominal model in place of the sailed one. On a
board sailing another ship (``ship-env leaderboard --ship``) that is the given ship's model, so the
autopilots are designed from its own K*, tau*, length and speed (:func:`check_design_ship` refuses a
ship that lacks one). A learned entrant trained on another ship than the board's says so in its name.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from functools import cache, partial
from pathlib import Path
from typing import Any

import gymnasium as gym
from gymnasium import spaces

from ship_env.baselines.controller import Controller, SB3Controller
from ship_env.baselines.presys import (
    indirect_adaptive_controller,
    mrac_controller,
    pd_controller,
    track_follow_controller,
)
from ship_env.envs.task import ShipTask, observation_keywords
from ship_env.leaderboard.suites import COURSE_CHANGE, DEFAULT_SHIP, TRACK_FOLLOW, ship_name
from ship_env.model import Ship, ShipModel, load_ship
from ship_env.rl.policy_file import PolicyFile, PolicyFileError, read_policy_file, seed_models
from ship_env.rl.shipped import shipped_entrants

#: The classic baselines per environment: name -> builder from the task (:mod:`ship_env.baselines.presys`).
CLASSIC_BUILDERS: dict[str, dict[str, Callable[[Any], Controller]]] = {
    COURSE_CHANGE: {
        "PD, fixed gains": partial(pd_controller, schedule="fixed"),
        "PD, gain-scheduled": pd_controller,
        "indirect adaptive PD": indirect_adaptive_controller,
        "MRAC": mrac_controller,
    },
    TRACK_FOLLOW: {"predictor course changer": track_follow_controller},
}


#: The ship's values the classic autopilots are designed from (:mod:`ship_env.baselines.presys`):
#: K*, tau* (every autopilot) and the rudder rate (the predictor course changer).
DESIGN_PARAMETERS = ("yaw.gain", "yaw.time_constant", "steering_machine.rudder_rate")


def check_design_ship(ship: str) -> Ship:
    """The ship ``ship`` (a preset name or a ship YAML path) checked for what the classic autopilots
    are designed from (:data:`DESIGN_PARAMETERS`); ``ValueError`` naming the file and the field it lacks."""
    preset = load_ship(ship)
    model = ShipModel(preset)
    for key in DESIGN_PARAMETERS:
        try:
            model.parameter(key)
        except KeyError:
            effect, _, name = key.partition(".")
            raise ValueError(
                f"{preset.path or ship}: effects.{effect}.{name}: missing; the classic autopilots are designed from it"
            ) from None
    return preset


def _same_ship(first: Ship, second: Ship) -> bool:
    """Whether two presets describe the same ship: the same particulars, effects on and values."""
    return (first.principal, first.values, first.enabled) == (second.principal, second.values, second.enabled)


def trained_elsewhere(policy_file: PolicyFile, board_ship: str) -> str | None:
    """The ship a policy was trained on (its metadata's ``ship`` keyword: a preset's name, or the
    file as recorded where it cannot be read here) when it is not ``board_ship``; ``None`` when it
    is the same ship or the policy has no metadata."""
    if policy_file.metadata is None:
        return None
    trained = str(policy_file.metadata.env_kwargs.get("ship", DEFAULT_SHIP))
    try:
        trained_ship = load_ship(trained)
    except (OSError, TypeError, ValueError):
        return trained
    if _same_ship(trained_ship, load_ship(board_ship)):
        return None
    return trained_ship.name if trained_ship.name != ship_name(board_ship) else trained


class DesignedTask:
    """The sailed task as the controllers' designer knows it: its rudder limit, step, instruments
    and charts (reference tracks), but the nominal ship's model.

    Args:
        sailed: the task of the environment sailed.
        model: the ship model the controllers are designed for.
    """

    def __init__(self, sailed: ShipTask, model: ShipModel) -> None:
        self._sailed = sailed
        self.model = model

    def __getattr__(self, name: str) -> Any:
        return getattr(self._sailed, name)


@cache
def _policy(path: Path, trust_policy_code: bool) -> Any:
    """The policy network of a policy file, loaded once per process (:func:`read_policy_file`)."""
    return read_policy_file(path, trust_policy_code).policy()


@dataclass(frozen=True)
class Entrant:
    """A controller on the leaderboard.

    Attributes:
        name: its name in the tables (unique).
        env_id: the environment it steers.
        kind: ``"classic"`` or ``"learned"``.
        policies: a learned entrant's policy files, one per training seed.
        training_seeds: their training seeds (from their metadata; without it, their positions).
        observation_kwargs: the observation options they were trained with (``track_preview``,
            ...), given to the environments they sail, as (keyword, value) pairs.
        trust_policy_code: read its policy files by unpickling them, running any code they carry.
    """

    name: str
    env_id: str
    kind: str = "classic"
    policies: tuple[Path, ...] = ()
    training_seeds: tuple[int, ...] = ()
    observation_kwargs: tuple[tuple[str, Any], ...] = ()
    trust_policy_code: bool = False

    @property
    def runs(self) -> int:
        """The runs it sails each episode with: one per training seed, one for a classic autopilot."""
        return max(1, len(self.policies))

    def build(self, task: DesignedTask, run: int = 0) -> Controller:
        """A fresh controller for one episode of ``task`` (a learned entrant's ``run``-th seed)."""
        if self.policies:
            return SB3Controller(_policy(self.policies[run], self.trust_policy_code))
        return CLASSIC_BUILDERS[self.env_id][self.name](task)


def classic_entrants(env_ids: Sequence[str]) -> list[Entrant]:
    """The classic baselines of the environments ``env_ids``."""
    return [Entrant(name, env_id) for env_id in env_ids for name in CLASSIC_BUILDERS.get(env_id, {})]


def _training_seeds(policy_files: Sequence[PolicyFile]) -> tuple[int, ...]:
    """The files' training seeds from their metadata; their positions where one has none or two share one."""
    seeds = [policy_file.metadata.seed for policy_file in policy_files if policy_file.metadata is not None]
    if len(set(seeds)) < len(policy_files):
        return tuple(range(len(policy_files)))
    return tuple(seeds)


def policy_entrants(
    paths: Sequence[Path],
    env_spaces: Mapping[str, tuple[spaces.Space, spaces.Space]],
    shipped: bool = True,
    trust_policy_code: bool = False,
    ship: str = DEFAULT_SHIP,
) -> list[Entrant]:
    """Learned entrants: the shipped policies (if ``shipped``) and the policies at ``paths``.

    The shipped policies sailed are those trained on the board's ``ship`` and those trained on the
    tasks' own ship, :data:`DEFAULT_SHIP` (sailing any other ship zero-shot); a shipped policy trained
    on a third ship (e.g. ``ppo_esso_osaka_model``, on the identified Esso Osaka model) sails only
    that ship's board.

    Each path (and each shipped entrant's folder) is one entrant: a policy file, a training run's
    folder, or a folder of one run per training seed (``seed<S>/``, as ``ship-env train --seeds``
    writes them). A policy sails the environment its metadata names (with the observation options
    it was trained with: its spaces are then that environment's with them), or without metadata every
    environment of ``env_spaces`` (env id -> observation and action space) whose spaces it
    matches. A shipped entrant for an environment the leaderboard does not sail is left out;
    ``PolicyFileError`` names a given file that fits none of them (another environment, other
    spaces), whose seeds were trained on different environments, or that cannot be read without
    running its code. With ``trust_policy_code`` the files at ``paths`` are read by unpickling them,
    which runs any code they carry; the shipped ones are always read without. An entrant trained on
    another ship than ``ship``, the board's (:func:`trained_elsewhere`), is named
    ``"<algo> (<label>, trained on <that ship>)"``; the observation options it was trained with are
    kept, its ship is not: it sails the board's.
    """
    labelled = []
    for folder in shipped_entrants() if shipped else []:
        files = [read_policy_file(path) for path in seed_models(folder)]
        elsewhere = trained_elsewhere(files[0], ship)
        if files[0].env_id in env_spaces and elsewhere in (None, ship_name(DEFAULT_SHIP)):
            labelled.append((files, "shipped", False, elsewhere))
    for path in paths:
        files = [read_policy_file(model, trust_policy_code) for model in seed_models(path)]
        labelled.append((files, str(path), trust_policy_code, trained_elsewhere(files[0], ship)))
    entrants = []
    for files, label, trusted, elsewhere in labelled:
        first = files[0]
        if len({policy_file.env_id for policy_file in files}) > 1:
            raise PolicyFileError(
                f"policy files {label}: the seeds were trained on different environments "
                f"({', '.join(sorted(str(policy_file.env_id) for policy_file in files))})"
            )
        if first.env_id is not None:
            if first.env_id not in env_spaces:
                raise PolicyFileError(
                    f"policy file {first.path}: it was trained on {first.env_id}; the leaderboard "
                    f"sails {', '.join(env_spaces)}"
                )
            fitting = [first.env_id]
        else:
            reasons = {env_id: first.mismatch(env_id, *pair) for env_id, pair in env_spaces.items()}
            fitting = [env_id for env_id, reason in reasons.items() if reason is None]
            if not fitting:
                raise PolicyFileError(f"policy file {first.path}: " + "; ".join(map(str, reasons.values())))
        observation_kwargs = observation_keywords(first.metadata.env_kwargs) if first.metadata else {}
        for env_id in fitting:
            pair = env_spaces[env_id]
            if observation_kwargs:
                env = gym.make(env_id, ship=ship, **observation_kwargs)
                pair = (env.observation_space, env.action_space)
                env.close()
            for policy_file in files:
                policy_file.check(env_id, *pair)
        policies = tuple(policy_file.path for policy_file in files)
        observed = tuple(sorted(observation_kwargs.items()))
        name = f"{first.algo} ({label})" if elsewhere is None else f"{first.algo} ({label}, trained on {elsewhere})"
        entrants += [
            Entrant(name, env_id, "learned", policies, _training_seeds(files), observed, trusted) for env_id in fitting
        ]
    return entrants
