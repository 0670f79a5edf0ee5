"""dressbench: a benchmark suite for robot-assisted dressing (Clegg et al., ICRA 2018).

Importing the package is cheap: the physics (DART, Warp) loads only when a scene is built.
"""

__version__ = "0.1.0"
