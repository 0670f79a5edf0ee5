"""What a Ray task does on its node before its work: look for trained humans where the driver
does, and check that the plugins it needs are installed there.

A plugin installed on the driver but not on a worker would otherwise fail deep in the task,
with a message about an unknown name that does not say where; here it is one line naming the
plugin and the node.
"""

from __future__ import annotations

import os
import socket
from collections.abc import Iterable
from dataclasses import dataclass

from .backend import ClusterError

POLICIES_VARIABLE = "DRESSBENCH_POLICIES"
SHIPPED = ""  # stands for dressbench's shipped policy folder, wherever a node installed it


@dataclass(frozen=True)
class PolicyFolders:
    """The folders the driver looks for trained humans in (``plugins.policy_folders``), to be
    looked in on a worker too: each by its absolute path, and the shipped folder as the
    worker's own install has it."""

    folders: tuple[str, ...]

    @classmethod
    def of_driver(cls) -> PolicyFolders:
        """This process's folders."""
        from ..plugins.registry import policy_folders, shipped_policy_folder

        shipped = shipped_policy_folder().resolve()
        return cls(tuple(SHIPPED if f == shipped else str(f) for f in policy_folders()))

    def apply(self) -> None:
        """Make this process's registry look in these folders (re-read only on a change)."""
        from ..plugins import refresh
        from ..plugins.registry import shipped_policy_folder

        value = os.pathsep.join(f or str(shipped_policy_folder()) for f in self.folders)
        if os.environ.get(POLICIES_VARIABLE) != value:
            os.environ[POLICIES_VARIABLE] = value
            refresh()


def require_plugins(robots: Iterable[str] = (), humans: Iterable[str] = ()) -> None:
    """A ClusterError naming the first of these plugins that is missing or broken on this node."""
    from ..plugins import human_plugins, refresh, robot_plugins

    for noun, names, plugins in (
        ("robot", robots, robot_plugins),
        ("human", humans, human_plugins),
    ):
        for name in names:
            if name not in plugins():
                refresh()  # installed, or a policy file written, since this worker last looked
            plugin = plugins().get(name)
            if plugin is None:
                raise ClusterError(
                    f"{noun} plugin {name!r} is not installed on Ray node {node()}: "
                    "install it on every node, as on the driver"
                )
            if not plugin.ok:
                raise ClusterError(
                    f"{noun} plugin {name!r} is broken on Ray node {node()}: {plugin.error}"
                )


def node() -> str:
    """This node, for messages: ``host (IP)``."""
    import ray

    return f"{socket.gethostname()} ({ray.util.get_node_ip_address()})"
