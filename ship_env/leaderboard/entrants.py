"""The controllers on the leaderboard: the classic baselines of :mod:`ship_env.baselines.presys` and SB3 policies.

An :class:`Entrant` names a controller and the environment it steers, and builds a fresh one for
every episode (so an episode's result does not depend on the episodes sailed before it, nor on
how the episodes are split between workers). Entrants hold names and paths only: they travel to
Ray workers as they are.

Classic controllers are designed for the nominal ship: they are built from a
:class:`DesignedTask`, the sailed task with the nominal model in place of the sailed one.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from functools import cache, partial
from pathlib import Path
from typing import Any

from gymnasium import spaces

from ship_env.baselines.controller import Controller, SB3Controller
from ship_env.baselines.presys import (
    indirect_adaptive_controller,
    mrac_controller,
    pd_controller,
    track_follow_controller,
)
from ship_env.envs.task import ShipTask
from ship_env.leaderboard.suites import COURSE_CHANGE, TRACK_FOLLOW
from ship_env.model import ShipModel
from ship_env.rl.policy_file import PolicyFileError, read_policy_file
from ship_env.rl.shipped import shipped_policies

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
def _policy(path: Path) -> Any:
    """The policy network of a policy file, loaded once per process."""
    return read_policy_file(path).policy()


@dataclass(frozen=True)
class Entrant:
    """A controller on the leaderboard.

    Attributes:
        name: its name in the tables (unique).
        env_id: the environment it steers.
        kind: ``"classic"`` or ``"learned"``.
        policy_path: the policy file of a learned entrant.
    """

    name: str
    env_id: str
    kind: str = "classic"
    policy_path: Path | None = None

    def build(self, task: DesignedTask) -> Controller:
        """A fresh controller for one episode of ``task``."""
        if self.policy_path is not None:
            return SB3Controller(_policy(self.policy_path))
        return CLASSIC_BUILDERS[self.env_id][self.name](task)


def classic_entrants(env_ids: Sequence[str]) -> list[Entrant]:
    """The classic baselines of the environments ``env_ids``."""
    return [Entrant(name, env_id) for env_id in env_ids for name in CLASSIC_BUILDERS.get(env_id, {})]


def policy_entrants(
    paths: Sequence[Path], env_spaces: Mapping[str, tuple[spaces.Space, spaces.Space]], shipped: bool = True
) -> list[Entrant]:
    """Learned entrants: the shipped policies (if ``shipped``) and the policy files ``paths``.

    A policy sails the environment its metadata names, or without metadata every environment of
    ``env_spaces`` (env id -> observation and action space) whose spaces it matches. A shipped
    policy for an environment the leaderboard does not sail is left out; ``PolicyFileError`` names
    a given file that fits none of them (another environment, other spaces).
    """
    shipped_files = [read_policy_file(path) for path in (shipped_policies() if shipped else [])]
    labelled = [(policy_file, "shipped") for policy_file in shipped_files if policy_file.env_id in env_spaces]
    labelled += [(read_policy_file(path), str(path)) for path in paths]
    entrants = []
    for policy_file, label in labelled:
        if policy_file.env_id is not None:
            if policy_file.env_id not in env_spaces:
                raise PolicyFileError(
                    f"policy file {policy_file.path}: it was trained on {policy_file.env_id}; the leaderboard "
                    f"sails {', '.join(env_spaces)}"
                )
            policy_file.check(policy_file.env_id, *env_spaces[policy_file.env_id])
            fitting = [policy_file.env_id]
        else:
            reasons = {env_id: policy_file.mismatch(env_id, *pair) for env_id, pair in env_spaces.items()}
            fitting = [env_id for env_id, reason in reasons.items() if reason is None]
            if not fitting:
                raise PolicyFileError(f"policy file {policy_file.path}: " + "; ".join(map(str, reasons.values())))
        entrants += [
            Entrant(f"{policy_file.algo} ({label})", env_id, "learned", policy_file.path) for env_id in fitting
        ]
    return entrants
