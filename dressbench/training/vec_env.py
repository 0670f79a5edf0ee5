"""Envs on every core: N envs stepped by N - 1 worker processes and the training process itself.

SB3's ``SubprocVecEnv`` with one worker per core leaves the training process waiting while the
workers step, and puts N + 1 processes on N cores; here the training process steps env 0 while
the workers step the rest, so N envs keep N cores busy (docs/benchmark.md). Each env is built
and seeded as in ``SubprocVecEnv``: the same seeds give the same episodes.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

import gymnasium as gym
import numpy as np
from stable_baselines3.common.vec_env import DummyVecEnv, SubprocVecEnv, VecEnv
from stable_baselines3.common.vec_env.base_vec_env import VecEnvIndices, VecEnvStepReturn


class SharedCoreVecEnv(VecEnv):
    """Env 0 in this process (a ``DummyVecEnv``), envs 1..N-1 in worker processes (a
    ``SubprocVecEnv``); a step sends the workers their actions, steps env 0, then collects."""

    def __init__(self, env_fns: Sequence[Callable[[], gym.Env]], start_method: str = "spawn"):
        if len(env_fns) < 2:
            raise ValueError(f"SharedCoreVecEnv needs 2 envs or more, got {len(env_fns)}")
        self.workers = SubprocVecEnv(list(env_fns[1:]), start_method=start_method)
        self.local = DummyVecEnv([env_fns[0]])
        super().__init__(len(env_fns), self.local.observation_space, self.local.action_space)

    def _parts(self) -> tuple[tuple[VecEnv, slice], tuple[VecEnv, slice]]:
        return (self.local, slice(0, 1)), (self.workers, slice(1, self.num_envs))

    def reset(self):
        for part, span in self._parts():
            part._seeds, part._options = self._seeds[span], self._options[span]
        observations = [part.reset() for part, _ in self._parts()]
        self._reset_seeds()
        self._reset_options()
        self.reset_infos = [*self.local.reset_infos, *self.workers.reset_infos]
        return np.concatenate(observations)

    def step_async(self, actions: np.ndarray) -> None:
        self.workers.step_async(actions[1:])
        self.local.step_async(actions[:1])

    def step_wait(self) -> VecEnvStepReturn:
        mine, theirs = self.local.step_wait(), self.workers.step_wait()  # env 0 first
        self.reset_infos = [*self.local.reset_infos, *self.workers.reset_infos]
        observations, rewards, dones = (np.concatenate([mine[i], theirs[i]]) for i in range(3))
        return observations, rewards, dones, [*mine[3], *theirs[3]]

    def close(self) -> None:
        self.workers.close()
        self.local.close()

    def get_images(self) -> Sequence[np.ndarray | None]:
        return [*self.local.get_images(), *self.workers.get_images()]

    def get_attr(self, attr_name: str, indices: VecEnvIndices = None) -> list[Any]:
        return self._each("get_attr", indices, attr_name)

    def set_attr(self, attr_name: str, value: Any, indices: VecEnvIndices = None) -> None:
        self._each("set_attr", indices, attr_name, value)

    def env_method(self, method_name: str, *method_args, indices: VecEnvIndices = None,
                   **method_kwargs) -> list[Any]:  # fmt: skip
        return self._each("env_method", indices, method_name, *method_args, **method_kwargs)

    def env_is_wrapped(self, wrapper_class: type[gym.Wrapper],
                       indices: VecEnvIndices = None) -> list[bool]:  # fmt: skip
        return self._each("env_is_wrapped", indices, wrapper_class)

    def _each(self, method: str, indices: VecEnvIndices, *args, **kwargs) -> list[Any]:
        """``method`` of the part that holds each of ``indices``, results in their order."""
        results = []
        for index in self._get_indices(indices):
            part, first = (self.local, 0) if index == 0 else (self.workers, 1)
            answer = getattr(part, method)(*args, indices=[index - first], **kwargs)
            results.extend(answer or [None])
        return results
