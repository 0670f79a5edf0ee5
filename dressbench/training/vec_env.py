"""Envs on every core: the training process steps a group of envs while worker processes, one
per other core, step a group each.

SB3's ``SubprocVecEnv`` with one worker per core leaves the training process waiting while the
workers step, and puts N + 1 processes on N cores; here the training process steps its own
group while the workers step theirs, so N processes keep N cores busy (docs/benchmark.md).
Groups of more than one env (``per_process``) share each vector step's fixed costs (the
policy's forward pass, the round trip to a worker) among more env steps. Each env is built and
seeded as in ``SubprocVecEnv``: the same seeds give the same episodes.
"""

from __future__ import annotations

import multiprocessing as mp
from collections.abc import Callable, Sequence
from typing import Any

import gymnasium as gym
import numpy as np
from stable_baselines3.common.vec_env import DummyVecEnv, VecEnv
from stable_baselines3.common.vec_env.base_vec_env import (
    CloudpickleWrapper,
    VecEnvIndices,
    VecEnvStepReturn,
)

EnvFactory = Callable[[], gym.Env]


class SharedCoreVecEnv(VecEnv):
    """N envs in groups of ``per_process``: the first group in this process (a ``DummyVecEnv``),
    each other group in a worker process (``WorkerVecEnv``); a step sends the workers their
    actions, steps this process's group, then collects."""

    def __init__(
        self, env_fns: Sequence[EnvFactory], per_process: int = 1, start_method: str = "spawn"
    ) -> None:
        if len(env_fns) <= per_process:
            raise ValueError(
                f"SharedCoreVecEnv needs 2 groups of {per_process} envs or more, got "
                f"{len(env_fns)} envs"
            )
        starts = range(0, len(env_fns), per_process)
        groups = [list(env_fns[i : i + per_process]) for i in starts]
        self.parts: list[VecEnv] = [DummyVecEnv(groups[0])]
        try:
            for group in groups[1:]:
                self.parts.append(WorkerVecEnv(group, start_method))
        except BaseException:  # one group's envs could not be built: end the others
            self.close()
            raise
        self.local = self.parts[0]
        # each part with its envs' places in the vector
        self.spans = [
            (part, slice(i, i + part.num_envs)) for part, i in zip(self.parts, starts, strict=True)
        ]
        super().__init__(len(env_fns), self.local.observation_space, self.local.action_space)

    def reset(self):
        for part, span in self.spans:
            part._seeds, part._options = self._seeds[span], self._options[span]
        observations = [part.reset() for part in self.parts]
        self._reset_seeds()
        self._reset_options()
        self.reset_infos = [info for part in self.parts for info in part.reset_infos]
        return np.concatenate(observations)

    def step_async(self, actions: np.ndarray) -> None:
        for part, span in self.spans[1:]:
            part.step_async(actions[span])
        self.local.step_async(actions[self.spans[0][1]])

    def step_wait(self) -> VecEnvStepReturn:
        results = [part.step_wait() for part in self.parts]  # this process's group first
        self.reset_infos = [info for part in self.parts for info in part.reset_infos]
        observations, rewards, dones = (np.concatenate([r[i] for r in results]) for i in range(3))
        return observations, rewards, dones, [info for r in results for info in r[3]]

    def close(self) -> None:
        for part in self.parts:
            part.close()

    def get_images(self) -> Sequence[np.ndarray | None]:
        return [image for part in self.parts for image in part.get_images()]

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
            part, span = next((part, span) for part, span in self.spans if index < span.stop)
            answer = getattr(part, method)(*args, indices=[index - span.start], **kwargs)
            results.extend(answer or [None])
        return results


class WorkerVecEnv(VecEnv):
    """A group of envs stepped one after another in a spawned worker process: the parent's view
    of a ``DummyVecEnv`` there. An exception in the worker is raised again here."""

    def __init__(self, env_fns: Sequence[EnvFactory], start_method: str = "spawn") -> None:
        context = mp.get_context(start_method)
        self.remote, worker_remote = context.Pipe()
        factories = CloudpickleWrapper(list(env_fns))
        self.process = context.Process(target=_serve, args=(worker_remote, self.remote, factories),
                                       daemon=True)  # fmt: skip
        self.process.start()
        worker_remote.close()
        self.closed = False
        try:
            spaces = self._call("spaces")
        except BaseException:  # the envs could not be built there: the worker has ended
            self.process.join()
            raise
        super().__init__(len(env_fns), *spaces)

    def _call(self, command: str, *data: Any) -> Any:
        self.remote.send((command, data))
        return self._answer()

    def _answer(self) -> Any:
        failed, answer = self.remote.recv()
        if failed:
            raise answer
        return answer

    def reset(self):
        observations, self.reset_infos = self._call("reset", self._seeds, self._options)
        self._reset_seeds()
        self._reset_options()
        return observations

    def step_async(self, actions: np.ndarray) -> None:
        self.remote.send(("step", (actions,)))

    def step_wait(self) -> VecEnvStepReturn:
        *result, self.reset_infos = self._answer()
        return tuple(result)

    def close(self) -> None:
        if self.closed:
            return
        self.closed = True
        try:
            self.remote.send(("close", ()))
        except (BrokenPipeError, EOFError):  # the worker is already gone
            pass
        self.process.join()
        self.remote.close()

    def get_images(self) -> Sequence[np.ndarray | None]:
        return self._call("get_images")

    def get_attr(self, attr_name: str, indices: VecEnvIndices = None) -> list[Any]:
        return self._call("get_attr", attr_name, indices)

    def set_attr(self, attr_name: str, value: Any, indices: VecEnvIndices = None) -> None:
        self._call("set_attr", attr_name, value, indices)

    def env_method(self, method_name: str, *method_args, indices: VecEnvIndices = None,
                   **method_kwargs) -> list[Any]:  # fmt: skip
        return self._call("env_method", method_name, *method_args, indices, method_kwargs)

    def env_is_wrapped(self, wrapper_class: type[gym.Wrapper],
                       indices: VecEnvIndices = None) -> list[bool]:  # fmt: skip
        return self._call("env_is_wrapped", wrapper_class, indices)


def _serve(remote, parent_remote, factories: CloudpickleWrapper) -> None:
    """A worker's loop: build the group's envs, answer the parent's commands until "close"."""
    parent_remote.close()
    try:
        venv = DummyVecEnv(factories.var)
    except Exception as error:  # the parent raises it again
        _send_error(remote, error)
        remote.close()
        return
    try:
        while True:
            command, data = remote.recv()
            if command == "close":
                break
            try:
                answer = _run(venv, command, data)
            except Exception as error:  # the parent raises it again
                _send_error(remote, error)
            else:
                remote.send((False, answer))
    except (EOFError, KeyboardInterrupt):  # the parent is gone, or the run is interrupted
        pass
    finally:
        venv.close()
        remote.close()


def _send_error(remote, error: Exception) -> None:
    """The error itself if it pickles, else a RuntimeError that names it."""
    try:
        remote.send((True, error))
    except Exception:  # e.g. it holds a handle
        remote.send((True, RuntimeError(f"{type(error).__name__}: {error}")))


def _run(venv: DummyVecEnv, command: str, data: tuple) -> Any:
    """One command of the parent on the worker's envs."""
    if command == "spaces":
        return venv.observation_space, venv.action_space
    if command == "step":
        venv.step_async(*data)
        return (*venv.step_wait(), venv.reset_infos)
    if command == "reset":
        venv._seeds, venv._options = data
        return venv.reset(), venv.reset_infos
    if command == "env_method":
        name, *args, indices, kwargs = data
        return venv.env_method(name, *args, indices=indices, **kwargs)
    if command == "get_images":
        return venv.get_images()
    *args, indices = data
    return getattr(venv, command)(*args, indices=indices)  # get_attr, set_attr, env_is_wrapped
