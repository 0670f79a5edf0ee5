"""StiffElbow: a capability profile whose right elbow bends at most a right angle."""

from __future__ import annotations

from dataclasses import replace
from typing import ClassVar

import numpy as np
from dressbench.plugins.profiles import BodyLimits, dof_indices


class StiffElbow:
    """A right elbow that bends at most ``max_flexion`` (as with a flexion contracture), the
    rest of the body typical and no involuntary motion."""

    api_version: ClassVar[int] = 1
    max_flexion = np.pi / 2  # rad; the typical elbow bends to 2.6 rad

    def body(self, typical: BodyLimits) -> BodyLimits:
        """The typical body with the right elbow's upper limit lowered to ``max_flexion``."""
        upper = typical.upper.copy()
        elbow = dof_indices(("elbow_r_flexion",))
        upper[elbow] = np.minimum(upper[elbow], self.max_flexion)
        return replace(typical, upper=upper)

    def involuntary(self, rng: np.random.Generator, frames: int, dt: float) -> None:
        """No involuntary motion."""
        return None
