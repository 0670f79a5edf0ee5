"""Robot strategies and human policies that dressbench finds through entry points.

Importing this package is cheap: no entry point is read and no plugin is imported until one of
the registry functions is first called.
"""

from dressbench.plugins.protocols import (
    HUMAN_API_VERSION,
    HUMAN_GROUP,
    ROBOT_API_VERSION,
    ROBOT_GROUP,
    HumanPolicy,
    RobotStrategy,
)
from dressbench.plugins.registry import (
    BrokenPluginError,
    Plugin,
    PluginError,
    UnknownPluginError,
    all_plugins,
    human_plugin,
    human_plugins,
    human_providers,
    load_human,
    load_robot,
    refresh,
    robot_plugin,
    robot_plugins,
)

__all__ = [
    "HUMAN_API_VERSION",
    "HUMAN_GROUP",
    "ROBOT_API_VERSION",
    "ROBOT_GROUP",
    "BrokenPluginError",
    "HumanPolicy",
    "Plugin",
    "PluginError",
    "RobotStrategy",
    "UnknownPluginError",
    "all_plugins",
    "human_plugin",
    "human_plugins",
    "human_providers",
    "load_human",
    "load_robot",
    "refresh",
    "robot_plugin",
    "robot_plugins",
]
