"""Optional dependencies: the features that need an extra of ``pip install "ship-env[EXTRA]"``.

The core install (the simulator, the Gymnasium environments, the classic baselines, the measurement
workbench) needs none of them. The extras, as ``pyproject.toml`` declares them:

- ``rl``: torch, stable-baselines3, sb3-contrib and rl-zoo3, for ``ship-env train``, the learned
  policies (:mod:`ship_env.rl`) and the SB3 adapter (:mod:`ship_env.envs.sb3_adapter`);
- ``leaderboard``: ``rl``'s packages (it sails the shipped PPO policies) and rliable with arch for
  its intervals, for ``ship-env leaderboard``;
- ``ray``: Ray, for ``--backend ray``; ``bench``: shipmmg, the MMG KVLCC2 model (a second, independent
  simulator) for the benchmarks, the ``kvlcc2`` fit and the tests that sail it;
- ``dev``: all of these and the test, lint and documentation tools.

A feature calls :func:`require` before it imports them (or turns the ImportError into
:func:`missing_extra`), so a missing package ends with :class:`MissingExtra`, whose message names the
extra that installs it.
"""

from __future__ import annotations

import importlib


class MissingExtra(ImportError):
    """An optional dependency a feature needs is not installed; the message names the extra."""


def missing_extra(extra: str, feature: str, error: ImportError) -> MissingExtra:
    """The error for ``feature`` when importing one of ``extra``'s packages failed with ``error``."""
    return MissingExtra(
        f'{feature} needs {error.name or "a package"} ({error}); install it with pip install "ship-env[{extra}]"',
        name=error.name,
    )


def require(extra: str, feature: str, *modules: str) -> None:
    """Import each of ``modules``; at the first that fails, :func:`missing_extra` naming ``feature`` and ``extra``."""
    for module in modules:
        try:
            importlib.import_module(module)
        except ImportError as error:
            raise missing_extra(extra, feature, error) from error


__all__ = ["MissingExtra", "missing_extra", "require"]
