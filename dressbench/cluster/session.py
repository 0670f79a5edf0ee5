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
AUTH_MODE = "RAY_AUTH_MODE"  # Ray's switch of token authentication ("token", "disabled")


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
    local = {"num_cpus": cpus or os.cpu_count() or 1, "include_dashboard": False}
    try:
        ray.init(
            address=address, logging_level=logging.WARNING, **(local if address is None else {})
        )
    except (ConnectionError, RuntimeError, ValueError) as error:
        raise ClusterError(
            f"cannot connect to Ray at {address}: {first_line(error)}{_auth_hint(address)}"
        ) from None
    try:
        yield ray
    finally:
        ray.shutdown()


def _auth_hint(address: str | None) -> str:
    """What to try when joining by address failed and Ray's token authentication is not on
    here: Ray turns it on by itself only for a cluster it finds (auto), never for an address."""
    if address in (None, "auto") or AUTH_MODE in os.environ:
        return ""
    return f" (if the cluster uses token authentication, set {AUTH_MODE}=token and its token here)"


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
