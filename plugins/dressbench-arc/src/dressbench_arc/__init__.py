"""dressbench-arc: an example plugin package with one robot strategy, one human policy and one
capability profile.

dressbench finds them through the entry points in ``pyproject.toml`` (as ``arc``,
``follow_task`` and ``stiff_elbow``) and imports ``robot``, ``human`` or ``profile`` only when it
needs them, so this file imports nothing.
"""
