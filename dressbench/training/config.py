"""What a training run is: ``TrainConfig``, its checks, and the named recipes."""

from __future__ import annotations

import dataclasses
import math
import os
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

from ..checks import (
    check_folder,
    check_int,
    check_name,
    check_positive,
    check_seed,
)
from ..config import ANY_PROCESSES, AT_LEAST_ONE, EnvConfig, check_options, option, option_like
from ..factory import DEFAULT_ROBOT
from ..observation import HAPTIC_SCALES
from ..plugins.protocols import TYPICAL_PROFILE
from ..scene.actuation import ACTUATIONS
from .curriculum import CurriculumConfig
from .tear import TearConfig
from .warmup import WarmupConfig

ALGORITHMS = ("trpo", "ppo")
RECIPES = ("default", "fine-gown", "paper")
# the training gown: half the evaluation's resolution, so a step costs about two thirds; what a
# human learns on it carries over (docs/experiments/2026-12-05-coarse-training-gown.md)
TRAINING_GOWN_VERTICES = 1000


@dataclass(frozen=True)
class TrainConfig:
    """One training run: what to train for, how, and where it goes. ``TrainConfig.preset``
    gives the named recipes (docs/training.md)."""

    # which preset these settings came from (a label for run.json)
    recipe: str = option("default", "fine-gown: the default trained on the evaluation's gown; "
                         "paper: TRPO, torques = action x 10 N m, 50k batches, the evaluation's "
                         "gown.", choices=RECIPES)  # fmt: skip
    robot: str = option(DEFAULT_ROBOT, "Robot strategy to train for.")
    algo: str = option("trpo", "The paper's TRPO, or PPO.", choices=ALGORITHMS)
    ablation: str = option_like(EnvConfig, "ablation", EnvConfig.ablation)
    # the body it learns in; the trained policy declares it, and is run with it everywhere
    profile: str = option_like(EnvConfig, "profile", EnvConfig.profile)
    # the warm-up's end, then as many steps on the whole reward
    timesteps: int = option(1_000_000, "Environment steps.", AT_LEAST_ONE)
    # a budget of learning time in hours, summed over the run's sessions as run.json counts
    # it: training stops where it runs out, short of ``timesteps``, and exports; None: none
    hours: float | None = option(None, "Stop and export once the run has learned this long, "
                                 "its sessions summed (default: no budget).",
                                 check_positive)  # fmt: skip
    envs: int = option(0, "Parallel env processes (default: one per core).", ANY_PROCESSES)
    # envs each process steps one after another (vec_env.py)
    envs_per_process: int = option(1, "Envs each env process steps one after another.",
                                   AT_LEAST_ONE)  # fmt: skip
    seed: int = option(0, "Training seed.", check_seed)
    gown_vertices: int = option_like(EnvConfig, "gown_vertices", TRAINING_GOWN_VERTICES,
                                     help="The training gown's resolution, in vertices (an "
                                     "evaluation plays its own).")  # fmt: skip
    horizon: int = option_like(EnvConfig, "horizon", EnvConfig.horizon)
    # the paper's 50k-sample batches would give a 1M-step run only 20 updates
    samples_per_update: int = option(4096, "Samples per update.", AT_LEAST_ONE)
    gamma: float = 0.995
    gae_lambda: float = 0.95
    target_kl: float = 0.01
    # the initial std of the policy's Gaussian actions; with "delta" actions the noise
    # random-walks the PD targets, so SB3's default of 1 carries a near start away, while 0.3
    # explores too little from rest once the curriculum is over (docs/training.md)
    action_std: float = option(0.5, "Initial std of the policy's actions.", check_positive)
    # the human's action: PD targets ("pd"), moves of them ("delta": a zero action holds the
    # pose, so a near start of the curriculum stays near), or torques; the trained policy
    # declares it, and every env that runs the policy takes it from there
    actuation: str = option("delta", "What an action drives: PD targets, moves of them, "
                            "torques.", choices=ACTUATIONS)  # fmt: skip
    haptics: str = option("log", "How the policy reads contact forces: log scale, or the "
                          "paper's newtons.", choices=HAPTIC_SCALES)  # fmt: skip
    # added to each feature's running variance when normalising (VecNormalize's epsilon): a
    # floor of 0.32 on the std, so a feature that barely varied (an untouched sensor, a still
    # joint) is not blown up to the clip at its first change; SB3's default is 1e-8
    norm_epsilon: float = 0.1
    checkpoint_every: int = 20_000  # environment steps between checkpoints
    # near starts that widen (training/curriculum.py); None: every episode starts at rest
    curriculum: CurriculumConfig | None = option(
        CurriculumConfig(), "Start some episodes with the hand near the opening."
    )
    # r_d left out, then brought in to its full weight (training/warmup.py); None: from step 0
    warmup: WarmupConfig | None = option(
        WarmupConfig(), "Bring the deformation term in after the first steps."
    )
    # episodes end where the gown's max area ratio passes a limit, once r_d has its full weight
    # (training/tear.py); None: never
    tear: TearConfig | None = option(
        TearConfig(), "End training episodes where the gown's max area ratio passes this."
    )
    out: str = option("runs", "Folder of training runs.", check_folder)
    policies: str = option("policies", "Where models go (a folder dressbench finds humans in).",
                           check_folder)  # fmt: skip
    name: str = option("", "Run and policy name (default ROBOT-ABLATION-ALGO-sSEED, "
                       "ROBOT-ABLATION-PROFILE-ALGO-sSEED for a profile not typical).",
                       check_name)  # fmt: skip
    # a trained human to start from (training/init.py): with one, the recipe's curriculum and
    # warm-up are off (a capable human needs neither), unless asked for
    init: str | None = option(None, "Start from this trained human's weights and observation "
                              "normalisation (a human's name); then no curriculum or warm-up "
                              "unless asked for.", check_name)  # fmt: skip

    def __post_init__(self) -> None:
        check_options(self, skip=("out", "policies"))  # the folders: by check(), before a run
        check_int(self.checkpoint_every, "checkpoint_every", 1)
        check_positive(self.norm_epsilon, "norm_epsilon")

    def check(self) -> None:
        """What a run needs besides its numbers, checked before anything is written: the robot
        strategy loads (else a ``PluginError``) and passes one reset and one act in a small env,
        the capability profile passes its check, the env options are valid, ``out`` and
        ``policies`` are folders that exist or can be created, no other process trains the run
        (``lock.check_unlocked``), and no human but the run's own earlier policy has its name
        (else a ``ValueError``)."""
        from ..plugins import robot_plugin
        from ..preflight import profile_problem, robot_problem
        from .lock import check_unlocked

        plugin = robot_plugin(self.robot)
        EnvConfig(ablation=self.ablation, profile=self.profile, gown_vertices=self.gown_vertices,
                  horizon=self.horizon)  # fmt: skip
        problem = profile_problem(self.profile)
        if problem:
            raise ValueError(f"capability profile {self.profile!r} cannot be trained in: "
                             f"{problem}")  # fmt: skip
        check_folder(self.out, "out")
        check_folder(self.policies, "policies")
        check_unlocked(Path(self.out) / self.run_name)
        self._check_name_free()
        problem = robot_problem(plugin)
        if problem:
            raise ValueError(f"robot plugin {self.robot!r} from {plugin.origin} cannot be trained "
                             f"for: {problem}")  # fmt: skip

    def _check_name_free(self) -> None:
        """Refuse a name another human plugin or policy file provides: the policy would not be
        the one its name runs. The policy file this run exports to is its own (a re-run)."""
        from ..plugins import human_providers
        from ..policy_file import JSON_SUFFIX

        own = (Path(self.policies) / f"{self.run_name}{JSON_SUFFIX}").resolve()
        for plugin in human_providers(self.run_name):
            if not (plugin.from_policy_file and Path(plugin.value).resolve() == own):
                raise ValueError(f"name {self.run_name!r} is taken: human plugin "
                                 f"{self.run_name!r} from {plugin.source} provides it; train "
                                 f"under another name (--name)")  # fmt: skip

    @classmethod
    def preset(cls, recipe: str = "default", **changes) -> TrainConfig:
        """A named recipe with ``changes`` on top. "fine-gown" is the default trained on the
        evaluation's gown (the default until the coarse training gown). "paper" is Clegg et al.'s
        published setting: TRPO, torque = action x 10 N m, 50,000-sample batches, forces in
        newtons, actions of std 1 at first, no curriculum, the whole reward from the first step,
        on the evaluation's gown. A run that starts from a trained human (``init``) has no
        curriculum or warm-up unless ``changes`` give them."""
        if recipe not in RECIPES:
            raise ValueError(f"unknown recipe {recipe!r}: choose one of {', '.join(RECIPES)}")
        base = {"recipe": recipe}
        if recipe in ("fine-gown", "paper"):
            base |= {"gown_vertices": EnvConfig.gown_vertices}
        if changes.get("init"):
            base |= {"curriculum": None, "warmup": None}
        if recipe == "paper":
            base |= {"algo": "trpo", "actuation": "torque", "samples_per_update": 50_000,
                     "haptics": "newtons", "norm_epsilon": 1e-8, "action_std": 1.0,
                     "curriculum": None, "warmup": None, "tear": None}  # fmt: skip
        return cls(**(base | changes))

    @property
    def tear_limit(self) -> TearConfig | None:
        """The tear limit that applies: none for ``no_haptics``, whose reward has no r_d."""
        return None if self.ablation == "no_haptics" else self.tear

    def record(self) -> dict:
        """What the run is, as run.json and the policy file record it: every field but the
        folders it was written to (``out``, ``policies``), so a run folder moved elsewhere
        holds no path of the machine it came from; the tear limit is the one that applies."""
        fields = {k: v for k, v in asdict(self).items() if k not in ("out", "policies")}
        return fields | {"tear": asdict(self.tear_limit) if self.tear_limit else None}

    @classmethod
    def from_dict(cls, fields: dict) -> TrainConfig:
        """The config of ``dataclasses.asdict(config)`` or ``record()`` (as in run.json), nested
        parts included; a record's folders are the defaults."""
        known = {field.name for field in dataclasses.fields(cls)}
        if unknown := sorted(fields.keys() - known):
            raise ValueError(f"settings this dressbench does not know: {', '.join(unknown)}")
        nested = {"curriculum": CurriculumConfig, "warmup": WarmupConfig, "tear": TearConfig}
        parts = {key: kind(**fields[key]) for key, kind in nested.items() if fields.get(key)}
        return cls(**(fields | parts))

    @property
    def budget_seconds(self) -> float:
        """The ``hours`` budget in seconds (inf: none)."""
        return math.inf if self.hours is None else self.hours * 3600.0

    @property
    def run_name(self) -> str:
        """``name``, else one made of the settings (the profile only when it is not typical, so
        that the names of runs made before profiles stay theirs)."""
        profile = "" if self.profile == TYPICAL_PROFILE else f"-{self.profile}"
        return self.name or f"{self.robot}-{self.ablation}{profile}-{self.algo}-s{self.seed}"

    @property
    def processes(self) -> int:
        return self.envs or os.cpu_count() or 1

    @property
    def n_envs(self) -> int:
        return self.processes * self.envs_per_process

    @property
    def rollout_steps(self) -> int:
        """Steps each env takes per update: the update's samples shared among the envs."""
        return max(self.samples_per_update // self.n_envs, 64)


def option_changes(
    curriculum: bool | None = None,
    warmup: bool | None = None,
    tear_limit: float | None = None,
    no_tear_limit: bool = False,
    **fields: Any,
) -> dict[str, Any]:
    """The ``TrainConfig`` fields that options set, as the command line gives them: a field
    None keeps the recipe's; ``curriculum`` and ``warmup`` turn those parts on (as configured
    by default) or off; ``tear_limit`` sets the tear limit, ``no_tear_limit`` takes it away."""
    if tear_limit is not None and no_tear_limit:
        raise ValueError("tear_limit and no_tear_limit exclude each other")
    changes = {key: value for key, value in fields.items() if value is not None}
    if curriculum is not None:
        changes["curriculum"] = CurriculumConfig() if curriculum else None
    if warmup is not None:
        changes["warmup"] = WarmupConfig() if warmup else None
    if tear_limit is not None or no_tear_limit:
        changes["tear"] = None if no_tear_limit else TearConfig(tear_limit)
    return changes
