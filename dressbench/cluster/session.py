"""Connecting to Ray: start a local instance or join a cluster, and leave it as it was found.

Ray's own failures are slow or long: joining an address nobody listens on waits for minutes,
and a missing ``ray`` is an ImportError. Here each is a ``ClusterError`` of one line, fast.
"""

from __future__ import annotations

import logging
import os
import socket
from collections.abc import Iterator
from contextlib import contextmanager
from types import ModuleType

from .backend import ClusterError, first_line

REACH_TIMEOUT = 5.0  # s to open a TCP connection to a cluster's address before giving up


def import_ray() -> ModuleType:
    """The ``ray`` module, or a ClusterError saying how to install it."""
    try:
        import ray
    except ImportError as error:
        raise ClusterError(
            "the ray backend needs Ray: pip install 'dressbench[ray]' (on every node)"
        ) from error
    return ray


@contextmanager
def ray_session(address: str | None, cpus: int | None = None) -> Iterator[ModuleType]:
    """Ray, connected, for the block; yields the ``ray`` module.

    If this process has already initialised Ray (``ray.init`` by the caller, as the tests do),
    that instance is used as it is and left running. Otherwise ``address`` None starts a local
    instance of ``cpus`` CPUs (default: every core) and ``auto``, ``HOST:PORT`` or
    ``ray://HOST:PORT`` joins a cluster; the block's end shuts the connection (and a local
    instance) down.
    """
    ray = import_ray()
    if ray.is_initialized():
        yield ray
        return
    if address is not None and address != "auto":
        _check_reachable(address)
    options = {"num_cpus": cpus or os.cpu_count() or 1} if address is None else {}
    try:
        ray.init(address=address, include_dashboard=False, logging_level=logging.WARNING,
                 **options)  # fmt: skip
    except (ConnectionError, RuntimeError, ValueError) as error:
        raise ClusterError(f"cannot connect to Ray at {address}: {first_line(error)}") from None
    try:
        yield ray
    finally:
        ray.shutdown()


def _check_reachable(address: str) -> None:
    """A ClusterError unless something accepts TCP connections at ``address`` within
    ``REACH_TIMEOUT`` (Ray itself would wait for minutes)."""
    host, port = address.removeprefix("ray://").rsplit(":", 1)
    try:
        socket.create_connection((host, int(port)), timeout=REACH_TIMEOUT).close()
    except OSError as error:
        raise ClusterError(
            f"cannot reach a Ray cluster at {address}: {error.strerror or error} "
            f"(start one with `ray start --head`, or give its address)"
        ) from None
