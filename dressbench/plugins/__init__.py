"""Robot strategies, human policies and capability profiles that dressbench finds through entry
points.

Importing this package is cheap: no entry point is read and no plugin is imported until one of
the registry functions is first called.
"""

from dressbench.plugins.protocols import (
    HUMAN_API_VERSION,
    HUMAN_GROUP,
    PROFILE_API_VERSION,
    PROFILE_GROUP,
    ROBOT_API_VERSION,
    ROBOT_GROUP,
    TYPICAL_PROFILE,
    CapabilityProfile,
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
    load_profile,
    load_robot,
    profile_plugin,
    profile_plugins,
    refresh,
    robot_plugin,
    robot_plugins,
)

__all__ = [
    "HUMAN_API_VERSION",
    "HUMAN_GROUP",
    "PROFILE_API_VERSION",
    "PROFILE_GROUP",
    "ROBOT_API_VERSION",
    "ROBOT_GROUP",
    "TYPICAL_PROFILE",
    "BrokenPluginError",
    "CapabilityProfile",
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
    "load_profile",
    "load_robot",
    "profile_plugin",
    "profile_plugins",
    "refresh",
    "robot_plugin",
    "robot_plugins",
]
