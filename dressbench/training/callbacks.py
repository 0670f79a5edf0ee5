"""The callbacks of a training run: checkpoints, where it stops, its progress bar and logs, the
curriculum's levels and the deformation term's warm-up."""

from __future__ import annotations

import math
import time
from collections import deque
from collections.abc import Callable

import numpy as np
from stable_baselines3.common.base_class import BaseAlgorithm
from stable_baselines3.common.callbacks import BaseCallback
from tqdm import tqdm

from ..metrics import STAGE_DEPTHS
from .curriculum import CurriculumConfig
from .warmup import WarmupConfig


class Checkpoints(BaseCallback):
    """Call ``save(model)`` every ``every`` environment steps."""

    def __init__(self, save: Callable[[BaseAlgorithm], None], every: int) -> None:
        super().__init__()
        self.save = save
        self.every = every
        self.last = 0

    def _on_training_start(self) -> None:
        self.last = self.num_timesteps  # a resumed run's checkpoint is where it starts

    def _on_step(self) -> bool:
        if self.num_timesteps - self.last >= self.every:
            self.save(self.model)
            self.last = self.num_timesteps
        return True


class StopAt(BaseCallback):
    """End training at ``timesteps`` as given (SB3 alone rounds up to whole rollouts), or at the
    step where this session has learned for ``seconds`` (SB3's clock: since learning began)."""

    def __init__(self, timesteps: int, seconds: float = math.inf) -> None:
        super().__init__()
        self.timesteps = timesteps
        self.seconds = seconds

    def _on_step(self) -> bool:
        buffer = self.model.rollout_buffer  # this step is added to it after the callbacks
        completes_a_rollout = buffer.pos + 1 == buffer.buffer_size
        learned = (time.time_ns() - self.model.start_time) / 1e9
        going = self.num_timesteps < self.timesteps and learned < self.seconds
        return going or completes_a_rollout


class Progress(BaseCallback):
    """A progress bar with steps, rate, ETA and the recent mean final arm progress."""

    def __init__(self, done: int, total: int, enabled: bool) -> None:
        super().__init__()
        self.done, self.total, self.enabled = done, total, enabled
        self.recent: deque[tuple[float, float, float]] = deque(maxlen=20)
        self.rest_starts: deque[float] = deque(maxlen=20)  # progress of episodes begun at rest
        self.torn: deque[float] = deque(maxlen=20)  # episodes a tear limit ended

    def _on_training_start(self) -> None:
        self.bar = tqdm(total=self.total, initial=self.done, unit="step", disable=not self.enabled,
                        dynamic_ncols=True, desc="training", mininterval=2.0)  # fmt: skip

    def _on_step(self) -> bool:
        self.bar.update(self.training_env.num_envs)
        for info in self.locals.get("infos", []):
            if "episode" in info:
                episode = info["episode"]
                scores = ("arm_progress", "max_deformation", "sim_failure")
                self.recent.append(tuple(float(episode[score]) for score in scores))
                if episode.get("near_start", 0.0) == 0.0:
                    self.rest_starts.append(float(episode["arm_progress"]))
                if "torn" in episode:
                    self.torn.append(float(episode["torn"]))
        if self.torn:
            self.logger.record("rollout/torn_rate", np.mean(self.torn))
        if self.rest_starts:
            progress = np.asarray(self.rest_starts)
            self.logger.record("rollout/rest_start_arm_progress", progress.mean())
            for stage in ("hand_in", "past_elbow"):  # the shares the evaluation reports
                rate = float(np.mean(progress >= STAGE_DEPTHS[stage]))
                self.logger.record(f"rollout/rest_start_{stage}_rate", rate)
        if self.recent:
            progress, deformation, failures = np.mean(self.recent, axis=0)
            self.bar.set_postfix(arm_progress=f"{progress:.3f}", refresh=False)
            self.logger.record("rollout/final_arm_progress", progress)
            self.logger.record("rollout/max_deformation", deformation)
            self.logger.record("rollout/sim_failure_rate", failures)
        return True

    def _on_training_end(self) -> None:
        self.bar.close()


class CurriculumLevels(BaseCallback):
    """Widens the near starts when the policy gets the hand in from most of them: the recent
    near starts of training (``judge="training"``), or its mean actions on a few trial near
    starts every ``judge_every`` steps (``judge="mean"``)."""

    def __init__(self, config: CurriculumConfig, reach: float) -> None:
        super().__init__()
        self.config = config
        self.reach = reach
        self.recent: deque[bool] = deque(maxlen=config.window)
        self.judged = 0  # steps done at the last judgement (or the start)

    def _on_training_start(self) -> None:
        self.training_env.env_method("set_reach", self.reach)
        self.judged = self.num_timesteps

    def _on_step(self) -> bool:
        for info in self.locals.get("infos", []):
            episode = info.get("episode")
            if episode is not None and episode["near_start"] > 0.0:
                self.recent.append(episode["arm_progress"] >= self.config.hand_in)
        full = len(self.recent) == self.recent.maxlen
        if self.config.judge == "training" and full:
            self._promote_if(float(np.mean(self.recent)))
        self.logger.record("curriculum/reach", self.reach)
        if self.recent:
            self.logger.record("curriculum/hand_in_rate", float(np.mean(self.recent)))
        return True

    def _on_rollout_end(self) -> None:
        """Judge between rollouts, once their returns are computed, while the curriculum runs."""
        cfg = self.config
        due = self.num_timesteps - self.judged >= cfg.judge_every
        if cfg.judge != "mean" or not due or self.reach > cfg.last_reach:
            return
        self.judged = self.num_timesteps
        rate = float(np.mean(self._trials()))
        self._promote_if(rate)
        self.logger.record("curriculum/trial_hand_in_rate", rate)
        self.logger.record("curriculum/reach", self.reach)

    def _promote_if(self, rate: float) -> None:
        if rate >= self.config.promote_at:
            self.reach += self.config.step
            self.recent.clear()
            self.training_env.env_method("set_reach", self.reach)

    def _trials(self) -> list[bool]:
        """Whether the hand got in, for ``trials`` near starts played with the policy's mean
        actions on the training envs (their normalization frozen); the envs then start afresh,
        their unfinished episodes cut (as at a rollout's end, their returns are already taken)."""
        venv, model = self.training_env, self.model
        learning, venv.training = venv.training, False
        venv.env_method("set_trials", True)
        observation, results = venv.reset(), []
        try:
            while len(results) < self.config.trials:
                action, _ = model.predict(observation, deterministic=True)
                observation, _, dones, infos = venv.step(action)
                ended = [info["episode"] for done, info in zip(dones, infos, strict=True) if done]
                results += [episode["arm_progress"] >= self.config.hand_in for episode in ended]
        finally:
            venv.env_method("set_trials", False)
            venv.training = learning
            model._last_obs = venv.reset()
            model._last_episode_starts = np.ones(venv.num_envs, dtype=bool)
        return results[: self.config.trials]


class Warmup(BaseCallback):
    """Sets the training envs' deformation share at the start of each rollout, from the steps
    done so far (a resumed run picks up where its checkpoint was), and logs it."""

    def __init__(self, config: WarmupConfig) -> None:
        super().__init__()
        self.config = config

    def _on_rollout_start(self) -> None:
        share = self.config.share(self.num_timesteps)
        self.training_env.env_method("set_share", share)
        self.logger.record("warmup/deformation_share", share)

    def _on_step(self) -> bool:
        return True
