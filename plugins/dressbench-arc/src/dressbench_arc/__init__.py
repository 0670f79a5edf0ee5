"""dressbench-arc: an example plugin package with one robot strategy and one human policy.

dressbench finds them through the entry points in ``pyproject.toml`` (as ``arc`` and
``follow_task``) and imports ``robot`` or ``human`` only when it needs them, so this file
imports nothing.
"""
