"""Joining Ray for the ``--backend ray`` commands (``ship-env train --seeds``, ``ship-env leaderboard``).

:func:`ray_session` joins the Ray cluster this process already initialised, or starts one for the
duration of the command: a local one (``ray.init()``) by default, or the cluster at an address
(``--ray-address``: ``host:port`` of its head, ``ray://host:port`` of its client server, or
``auto``). An address where nothing answers is reported at once, naming it, rather than after
Ray's own connection time-out.
"""

from __future__ import annotations

import argparse
import socket
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from types import ModuleType
from typing import Any

#: Seconds to wait for a Ray head to accept a connection before giving up on its address.
CONNECT_TIMEOUT_S = 5.0


class RayUnavailable(RuntimeError):
    """Ray is not installed, or nothing answers at the address given; the message names it."""


def _import_ray() -> ModuleType:
    try:
        import ray
    except ImportError:
        raise RayUnavailable("the ray backend needs Ray: pip install 'ship-env[ray]'") from None
    return ray


def check_address(address: str) -> None:
    """``RayUnavailable`` naming ``address`` unless it is ``auto`` or a ``[ray://]host:port`` that answers."""
    if address == "auto":
        return
    host, _, port = address.removeprefix("ray://").rpartition(":")
    if not host or not port.isdigit():
        raise RayUnavailable(f"Ray address {address!r}: expected host:port, ray://host:port or auto")
    try:
        socket.create_connection((host, int(port)), timeout=CONNECT_TIMEOUT_S).close()
    except OSError as error:
        raise RayUnavailable(f"Ray address {address!r}: no Ray cluster answers there ({error})") from None


def add_backend_arguments(parser: argparse.ArgumentParser, backends: Sequence[str], help: str) -> None:
    """``--backend`` (``local`` by default; ``help`` says what each does) and ``--ray-address``."""
    parser.add_argument("--backend", choices=backends, default="local", help=f"{help} (default: %(default)s)")
    parser.add_argument(
        "--ray-address",
        default=None,
        metavar="ADDRESS",
        help="the Ray cluster to run on (host:port, ray://host:port or auto; default: a local Ray)",
    )


def check_backend(backend: str, address: str | None) -> None:
    """``RayUnavailable`` if an address is given for a backend other than Ray."""
    if address is not None and backend != "ray":
        raise RayUnavailable(f"{address!r} needs --backend ray")


@contextmanager
def ray_session(address: str | None = None) -> Iterator[ModuleType]:
    """Ray, initialised: the session already open in this process (``address`` must then be ``None``),
    or one opened here and shut down on leaving (the cluster at ``address``, or a local one)."""
    ray = _import_ray()
    if ray.is_initialized():
        if address is not None:
            raise RayUnavailable(f"Ray address {address!r}: this process has already joined another Ray session")
        yield ray
        return
    if address is not None:
        check_address(address)
    try:
        ray.init(address=address, include_dashboard=False, log_to_driver=False)
    except ConnectionError as error:
        raise RayUnavailable(f"Ray address {address!r}: cannot join the cluster there ({error})") from None
    try:
        yield ray
    finally:
        ray.shutdown()


def run_as_tasks(
    function: Callable[..., Any],
    arguments: Sequence[tuple[Any, ...]],
    on_done: Callable[[int, Any], object],
    address: str | None = None,
    num_cpus: int = 1,
) -> list[Any]:
    """``function(*arguments[i])`` as one Ray task each (in :func:`ray_session` ``address``), each
    task holding ``num_cpus``; ``on_done(i, result)`` as each finishes; the results in ``arguments``' order."""
    with ray_session(address) as ray:
        remote = ray.remote(num_cpus=num_cpus)(function)
        pending = {remote.remote(*task_arguments): index for index, task_arguments in enumerate(arguments)}
        results: list[Any] = [None] * len(arguments)
        while pending:
            (done,), _ = ray.wait(list(pending), num_returns=1)
            index = pending.pop(done)
            results[index] = ray.get(done)
            on_done(index, results[index])
    return results
