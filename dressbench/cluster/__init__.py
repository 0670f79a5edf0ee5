"""Running dressbench's tasks (rollouts, trainings) on a Ray cluster instead of this machine.

Importing this package never imports Ray: ``Backend`` and ``ClusterError`` are plain Python, and
Ray loads only when a session starts (``session.ray_session``). See docs/cluster.md.
"""

from __future__ import annotations

from .backend import BACKENDS, Backend, ClusterError

__all__ = ["BACKENDS", "Backend", "ClusterError"]
