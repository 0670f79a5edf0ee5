"""Training a human model for a robot strategy with stable-baselines3 (TRPO by default).

A run lives in ``out/NAME/``: atomic checkpoints (the SB3 model and the observation
normalisation, local training state), TensorBoard and CSV logs, and ``run.json`` with the
configuration, seeds and result. Re-running the same call resumes from the last checkpoint. The
finished model is exported to ``policies/NAME.{safetensors,json}``: plain weights that load
without unpickling anything.
"""

from __future__ import annotations

import json
import math
import os
import shutil
import time
from collections.abc import Iterable
from dataclasses import fields, replace
from pathlib import Path

import numpy as np
import torch
from stable_baselines3 import PPO
from stable_baselines3.common.callbacks import CallbackList
from stable_baselines3.common.logger import configure
from stable_baselines3.common.vec_env import DummyVecEnv, VecEnv, VecNormalize

from ..files import write_csv, write_json
from ..observation import NEWTONS
from ..policy_file import TrainedPolicy
from ..provenance import git_commit, versions
from .callbacks import Checkpoints, CurriculumLevels, Progress, StopAt, Warmup
from .config import TrainConfig, option_changes
from .curriculum import NearStarts
from .init import parent_policy, parent_record, start_from
from .lock import run_lock
from .summary import learning_table, training_seconds, write_learning_table
from .tear import TornGown
from .vec_env import SharedCoreVecEnv
from .warmup import DeformationShare
from .wrappers import ScaledHaptics

CHECKPOINT = "checkpoint"  # stem of the model and normalisation files in a run folder
# what a resumed run may change: how long it trains, on how many processes, how often it saves;
# every other setting shaped what its checkpoint learned, so it goes on as run.json records it
RESUMABLE = frozenset(
    {"timesteps", "hours", "envs", "envs_per_process", "checkpoint_every", "name"}
)


def train(config: TrainConfig | None = None, *, progress: bool = True, **options) -> Path:
    """Train (or resume) a human model and export it; returns the policy's JSON path."""
    config = replace(config or TrainConfig(), **options)
    return TrainingRun(config).run(progress=progress)


def train_config(recipe: str | None = None, *, resume: bool = False, **options) -> TrainConfig:
    """The run that ``dressbench train`` makes of its options (``option_changes``) on ``recipe``
    (None: the default one). With ``resume``, a run folder with a checkpoint goes on as its
    run.json records it, but for the settings these options change (every one, given a
    ``recipe``)."""
    changes = option_changes(**options)
    config = TrainConfig.preset(recipe or "default", **changes)
    if not resume:
        return config
    return continued_config(config, {f.name for f in fields(TrainConfig)} if recipe else changes)


def recorded_config(folder: Path | str) -> TrainConfig:
    """The settings a run folder's run.json records, training on in that folder."""
    folder = Path(folder)
    try:
        config = TrainConfig.from_dict(_record(folder))
    except ValueError as error:
        raise ValueError(f"{folder}/run.json: {error}; it cannot resume that run") from None
    return replace(config, out=str(folder.parent))


def continued_config(config: TrainConfig, given: Iterable[str]) -> TrainConfig:
    """The settings that resume ``config``'s run: the recorded ones, with the fields named in
    ``given`` and the policies folder as ``config`` has them (the command line's way: an option
    left out continues as recorded); ``config`` itself when there is no checkpoint to resume."""
    folder = Path(config.out) / config.run_name
    if not _resumable(folder):
        return config
    changes = {name: getattr(config, name) for name in {*given, "policies"}}
    return replace(recorded_config(folder), **changes)


def _resumable(folder: Path) -> bool:
    """Whether a run folder holds a checkpoint and the run.json of the settings it learned on."""
    return (folder / f"{CHECKPOINT}.zip").exists() and (folder / "run.json").exists()


def _record(folder: Path) -> dict:
    """The settings a run folder's run.json records (``TrainConfig.record()``)."""
    return _record_of(folder)["config"]


def _record_of(folder: Path) -> dict:
    """A run folder's run.json."""
    return json.loads((folder / "run.json").read_text())


class TrainingStopped(KeyboardInterrupt):
    """Training was interrupted; its checkpoint was saved at the step it stopped at."""

    def __init__(self, folder: Path, steps: int) -> None:
        super().__init__(f"training stopped at {steps:,} steps; its checkpoint in {folder} is "
                         f"saved: run the same command again to resume, or with --timesteps "
                         f"{steps} to export the policy as it is")  # fmt: skip
        self.steps = steps


class TrainingRun:
    """The files of one run in ``out/NAME/`` and the steps that produce them."""

    def __init__(self, config: TrainConfig) -> None:
        self.config = config
        self.folder = Path(config.out) / config.run_name
        self.model_path = self.folder / f"{CHECKPOINT}.zip"
        self.norm_path = self.folder / f"{CHECKPOINT}-normalization.pkl"
        self.state_path = self.folder / "checkpoint.json"
        self.learned_before = 0.0  # learning seconds of the sessions before this one
        self.parent: TrainedPolicy | None = None  # the human a fresh run starts from
        self.curriculum: CurriculumLevels | None = None
        if config.curriculum is not None:
            reach = self._saved_state().get("curriculum_reach", config.curriculum.first_reach)
            self.curriculum = CurriculumLevels(config.curriculum, reach)

    def _saved_state(self) -> dict:
        """The last checkpoint's marker (steps, seed, curriculum level), or {} before one."""
        return json.loads(self.state_path.read_text()) if self.state_path.exists() else {}

    # ----------------------------------------------------------------------------- run
    def run(self, progress: bool = True) -> Path:
        """Train to ``timesteps`` (resuming a checkpoint if there is one) and export.

        Bad input fails before the run folder is made (``TrainConfig.check``); a run that this
        call started fails before its first checkpoint leaves no folder behind. The run's lock
        (``lock.run_lock``) is held throughout: another process training it is refused.
        """
        self.config.check()
        torch.set_num_threads(1)  # a second thread does not speed these small updates up
        created = not self.folder.exists()
        self.folder.mkdir(parents=True, exist_ok=True)
        with run_lock(self.folder):
            try:
                self._check_resumable()
                if self.config.init and not self.model_path.exists():
                    self.parent = parent_policy(self.config)
                return self._run(progress)
            except Exception:
                if created and not self.model_path.exists():
                    shutil.rmtree(self.folder, ignore_errors=True)
                raise

    def _check_resumable(self) -> None:
        """A checkpoint goes on only with the settings it was trained on (but ``RESUMABLE``):
        else one line names what differs, before anything is written."""
        if not _resumable(self.folder):
            return
        if changed := _differences(_record(self.folder), self.config.record()):
            raise ValueError(f"{self.folder} holds a run trained with {'; '.join(changed)}: "
                             f"resume it with the settings its run.json records (options left "
                             f"out, or recorded_config(folder)), or start it fresh")  # fmt: skip

    def _run(self, progress: bool) -> Path:
        run_json = {"config": self.config.record(), "versions": versions()}
        if self.parent is not None:
            run_json["parent"] = parent_record(self.parent)
        elif self.config.init:  # resumed: as its first session recorded it
            run_json["parent"] = _record_of(self.folder)["parent"]
        write_json(self.folder / "run.json", run_json)
        venv = self._envs()
        try:
            model, done = self._model(venv)
            remaining = max(self.config.timesteps - done, 0)
            self.learned_before = self._learned_seconds()
            seconds = self.config.budget_seconds - self.learned_before
            if remaining and seconds > 0.0:
                self._archive_progress(done)
                model.set_logger(configure(str(self.folder / "logs"), ["csv", "tensorboard"]))
                total = self.config.timesteps
                steps = [Checkpoints(self.save_checkpoint, self.config.checkpoint_every),
                         StopAt(total, seconds), Progress(done, total, progress)]  # fmt: skip
                if self.curriculum is not None:
                    steps.append(self.curriculum)
                if self.config.warmup is not None:
                    steps.append(Warmup(self.config.warmup))
                callbacks = CallbackList(steps)
                try:
                    model.learn(remaining, callback=callbacks, reset_num_timesteps=done == 0)
                except KeyboardInterrupt:  # Ctrl-C (or SIGTERM in the CLI): keep every update
                    self.save_checkpoint(model)
                    raise TrainingStopped(self.folder, int(model.num_timesteps)) from None
                self.save_checkpoint(model)
            steps = int(model.num_timesteps)
            run_json["result"] = self._summarize(steps)
            write_json(self.folder / "run.json", run_json)
            return self.export(model, run_json.get("parent"))
        finally:
            try:
                venv.close()
            except (BrokenPipeError, EOFError):  # workers a terminal's Ctrl-C already stopped
                pass

    def _envs(self) -> VecNormalize:
        cfg = self.config
        venv = training_envs(cfg)
        venv.seed(self._episode_seed())
        if self.norm_path.exists():
            return VecNormalize.load(str(self.norm_path), venv)
        return VecNormalize(venv, norm_obs=True, norm_reward=True, gamma=cfg.gamma,
                            epsilon=cfg.norm_epsilon)  # fmt: skip

    def _episode_seed(self) -> int:
        """The seed of the envs' episode stream: the run's seed from the start, and after a
        resume one drawn from (seed, steps done), so a continued run neither repeats the
        episodes it trained on nor depends on where it is resumed."""
        done = self._saved_state().get("timesteps", 0)
        if not done:
            return self.config.seed
        return int(np.random.SeedSequence([self.config.seed, done]).generate_state(1)[0])

    def _learned_seconds(self) -> float:
        """Wall seconds of learning up to the last checkpoint, over all the run's sessions: as
        the checkpoint records them, or (one saved before they were recorded) as its CSV logs
        do, to the last update logged before it."""
        state = self._saved_state()
        if "training_seconds" in state or not state.get("timesteps"):
            return float(state.get("training_seconds", 0.0))
        try:
            return training_seconds(learning_table(self.folder, until=state["timesteps"]))
        except FileNotFoundError:  # a checkpoint saved before the first logged update
            return 0.0

    def _model(self, venv: VecNormalize):
        """A fresh learner, or the checkpointed one and how many steps it has done; a run may
        be resumed with another number of envs (a machine with more or fewer cores), and its
        updates keep their size."""
        algorithm = _algorithm(self.config.algo)
        if self.model_path.exists():
            model = algorithm.load(str(self.model_path), env=venv, device="cpu",
                                   n_steps=self.config.rollout_steps)  # fmt: skip
            torch.manual_seed(self._episode_seed())  # the actions' noise continues seeded too
            return model, int(model.num_timesteps)
        cfg = self.config
        kwargs = {
            "n_steps": cfg.rollout_steps,
            "gamma": cfg.gamma,
            "gae_lambda": cfg.gae_lambda,
            "seed": cfg.seed,
            "device": "cpu",
            "policy_kwargs": {
                "net_arch": {"pi": [64, 64], "vf": [64, 64]},
                "activation_fn": torch.nn.Tanh,
                "log_std_init": math.log(cfg.action_std),
            },
        }
        if cfg.algo == "trpo":
            kwargs |= {"target_kl": cfg.target_kl, "batch_size": 128}
        else:
            kwargs |= {"batch_size": 256, "n_epochs": 10}
        model = algorithm("MlpPolicy", venv, **kwargs)
        if self.parent is not None:
            start_from(model, venv, self.parent)
        return model, 0

    # ----------------------------------------------------------------------------- files
    def _archive_progress(self, done: int) -> None:
        """Move an earlier session's CSV log into progress-history.csv: SB3 rewrites the file.

        Rows past the checkpoint are dropped, since those steps are trained again.
        """
        log = self.folder / "logs" / "progress.csv"
        if not log.exists() or log.stat().st_size == 0:
            return
        write_csv(log.with_name("progress-history.csv"), learning_table(self.folder, until=done))
        log.unlink()

    def save_checkpoint(self, model) -> None:
        """Model, normalisation, then the marker: a kill at any point leaves a usable set."""
        tmp_model = self.folder / f"{CHECKPOINT}.tmp.zip"
        model.save(str(tmp_model))
        tmp_norm = self.folder / f"{CHECKPOINT}-normalization.tmp.pkl"
        model.get_vec_normalize_env().save(str(tmp_norm))
        os.replace(tmp_norm, self.norm_path)
        os.replace(tmp_model, self.model_path)
        learned = self.learned_before + (time.time_ns() - model.start_time) / 1e9
        state = {"timesteps": int(model.num_timesteps), "seed": self.config.seed,
                 "training_seconds": round(learned, 1)}  # fmt: skip
        if self.curriculum is not None:
            state["curriculum_reach"] = self.curriculum.reach
        write_json(self.state_path, state)

    def _summarize(self, steps: int) -> dict[str, float]:
        """Write the learning summary (if an update has been logged) and return the run's steps,
        learning wall time over all its sessions, and environment steps per second."""
        result: dict[str, float] = {"steps": steps}
        try:
            table = learning_table(self.folder, until=steps)
        except FileNotFoundError:  # stopped before its first update: nothing learned to draw
            return result
        write_learning_table(table, self.folder.name, self.folder)
        seconds = self._learned_seconds()
        return result | {"training_seconds": round(seconds, 1),
                         "env_steps_per_second": round(steps / max(seconds, 1e-9), 1)}  # fmt: skip

    def export(self, model, parent: dict | None = None) -> Path:
        """The finished policy as safetensors + JSON in the policies folder, with the record of
        the ``parent`` it started from, if any; plugins are discovered again on next use, so
        that this process finds it by name."""
        from ..plugins import refresh, robot_plugin
        from ..plugins.contract import trains_generalists
        from .export import save_policy

        cfg = self.config
        Path(cfg.policies).mkdir(parents=True, exist_ok=True)
        generalist = trains_generalists(robot_plugin(cfg.robot).factory)
        metadata = {
            "name": cfg.run_name,
            "robot": None if generalist else cfg.robot,  # a generalist is meant for any
            "ablation": cfg.ablation,
            "actuation": cfg.actuation,
            "profile": cfg.profile,
            "haptics": cfg.haptics,
            "algorithm": cfg.algo,
            "seed": cfg.seed,
            "steps": int(model.num_timesteps),
            "versions": versions(),
            "git_commit": git_commit(),
            "config": cfg.record(),
        }
        if parent is not None:
            metadata["parent"] = parent
        norm = model.get_vec_normalize_env()
        _, json_path = save_policy(Path(cfg.policies) / cfg.run_name, model, norm.obs_rms, metadata,
                                   clip_obs=norm.clip_obs, epsilon=norm.epsilon)  # fmt: skip
        refresh()
        return Path(json_path)


def _differences(recorded: dict, given: dict, prefix: str = "") -> list[str]:
    """``"key recorded (now given)"`` for each setting both records hold that differs, nested
    ones as ``part.key``; the ``RESUMABLE`` ones may differ."""
    found = []
    for key in sorted(recorded.keys() & given.keys()):
        was, now, name = recorded[key], given[key], prefix + key
        if isinstance(was, dict) and isinstance(now, dict):
            found += _differences(was, now, f"{name}.")
        elif was != now and name not in RESUMABLE:
            found.append(f"{name} {was} (now {now})")
    return found


def training_envs(config: TrainConfig) -> VecEnv:
    """The run's ``n_envs`` training envs (before normalisation): all in this process, or a
    group here and a group in each spawned worker (``SharedCoreVecEnv``)."""
    factories = [_EnvFactory(config, rank) for rank in range(config.n_envs)]
    if config.processes == 1:
        return DummyVecEnv(factories)
    return SharedCoreVecEnv(factories, per_process=config.envs_per_process, start_method="spawn")


class _EnvFactory:
    """Builds one training env in a worker process (picklable, so it works with spawn)."""

    def __init__(self, config: TrainConfig, rank: int) -> None:
        self.config = config
        self.rank = rank

    def __call__(self):
        from stable_baselines3.common.monitor import Monitor

        from ..factory import make_human_env

        cfg = self.config
        env = make_human_env(cfg.robot, ablation=cfg.ablation, gown_vertices=cfg.gown_vertices,
                             horizon=cfg.horizon, actuation=cfg.actuation,
                             profile=cfg.profile)  # fmt: skip
        if cfg.haptics != NEWTONS:
            env = ScaledHaptics(env, cfg.ablation, cfg.haptics)
        keywords = ("arm_progress", "max_deformation", "sim_failure")
        if cfg.warmup is not None:
            env = DeformationShare(env, cfg.warmup.share(0))
        if cfg.tear_limit is not None:
            env = TornGown(env, cfg.tear_limit)
            keywords += ("torn",)
        if cfg.curriculum is not None:
            env = NearStarts(env, cfg.curriculum, seed=cfg.seed * 1000 + self.rank)
            keywords += ("near_start",)
        return Monitor(env, info_keywords=keywords)


def _algorithm(name: str):
    if name == "trpo":
        from sb3_contrib import TRPO

        return TRPO
    return PPO
