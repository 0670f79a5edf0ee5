"""Configuration of an environment as dataclasses: the scene, the reward, the task."""

from __future__ import annotations

from dataclasses import dataclass, field, fields, replace

from .checks import check_gown_vertices, check_horizon
from .metrics import deformation_limit
from .observation import check_ablation
from .scene.clock import POLICY_DT
from .scene.world import SceneConfig


@dataclass(frozen=True)
class RewardConfig:
    """r = progress * r_p + deformation * r_d + geodesic * r_g + upright * r_u (paper §III-B).

    The deformation threshold and scale are calibrated for dressbench's cloth: see
    docs/reward.md for the measurement behind them.
    """

    progress: float = 5.0
    deformation: float = 6.0
    geodesic: float = 2.0
    upright: float = 1.0
    deformation_threshold: float = 1.0  # the paper: 15; see docs/reward.md
    deformation_scale: float = 1.5  # the paper: 0.7

    @property
    def limit(self) -> float:
        """The deformation threshold: the area ratio at which r_d reaches -0.1 (2.02 with these
        numbers, 14.9 with the paper's), what "low deformation" is read against."""
        return deformation_limit(self.deformation_threshold, self.deformation_scale)


@dataclass(frozen=True)
class EnvConfig:
    """Everything an environment needs besides the robot strategy."""

    ablation: str = "complete"  # "complete", "no_haptics" or "no_task"
    horizon: int = 400  # policy steps per episode (16 s)
    gown_vertices: int = 2000  # the gown's resolution
    device: str = "cpu"  # Warp device for the cloth
    reward: RewardConfig = field(default_factory=RewardConfig)
    scene: SceneConfig = field(default_factory=SceneConfig)

    def __post_init__(self) -> None:
        check_ablation(self.ablation)
        step = self.scene.dt * self.scene.frame_skip
        if abs(step - POLICY_DT) > 1e-9:
            raise ValueError(
                f"the policy step is {POLICY_DT} s, which robot strategies and humans act on: "
                f"dt x frame_skip = {self.scene.dt} x {self.scene.frame_skip} = {step:.4g} s"
            )
        check_horizon(self.horizon)
        check_gown_vertices(self.gown_vertices)

    def scene_config(self) -> SceneConfig:
        """The scene settings with this config's resolution and device applied."""
        gown = replace(self.scene.gown, target_vertices=self.gown_vertices)
        return replace(self.scene, gown=gown, device=self.device)

    @classmethod
    def build(cls, config: EnvConfig | None = None, **overrides) -> EnvConfig:
        """A config from keyword overrides, with a clear error for an unknown option."""
        base = config or cls()
        names = {f.name for f in fields(cls)}
        unknown = sorted(set(overrides) - names)
        if unknown:
            raise TypeError(
                f"unknown option(s) {', '.join(unknown)}: choose from {', '.join(sorted(names))}"
            )
        return replace(base, **overrides)
