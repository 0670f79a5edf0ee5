"""Built-in human policies: passive, random, and a scripted non-learned baseline."""

from __future__ import annotations

from typing import ClassVar

import numpy as np

from ..observation import N_DOFS, N_SENSORS


class Passive:
    """Does nothing: the zero action holds the rest pose."""

    api_version: ClassVar[int] = 1
    robot: str | None = None
    ablation: str = "complete"

    def reset(self, seed: int | None = None) -> None:
        pass

    def act(self, observation: np.ndarray) -> np.ndarray:
        return np.zeros(11)


class Random:
    """Uniform random PD targets, redrawn every step."""

    api_version: ClassVar[int] = 1
    robot: str | None = None
    ablation: str = "complete"

    def __init__(self) -> None:
        self._rng = np.random.default_rng()

    def reset(self, seed: int | None = None) -> None:
        self._rng = np.random.default_rng(seed)

    def act(self, observation: np.ndarray) -> np.ndarray:
        return self._rng.uniform(-1.0, 1.0, 11)


class Scripted:
    """A non-learned baseline: steers the fingertip with damped least squares on the arm's
    Jacobian (an internal body model) and backs off when the haptic forces grow.

    Its direction is the task vector, except before any contact, where the task vector points
    straight at the opening's centre and would hit the rim: there it first lines the hand up
    on the axis from its shoulder through the opening (it assumes, as a person would, that the
    opening faces it), then pushes along that axis. It reads only the observation; the spine is
    left at rest, so the torso stays upright.
    """

    api_version: ClassVar[int] = 1
    robot: str | None = None
    ablation: str = "complete"
    step_size = 0.03  # m of fingertip motion asked for per policy step
    damping = 0.05  # m, of the damped least squares
    back_off_force = 20.0  # N: above this total haptic force the hand moves back
    approach_distance = 0.12  # m before the opening where the hand lines up
    aligned = 0.025  # m off the axis that counts as lined up

    def __init__(self) -> None:
        from ..scene.human import Human  # the body model, used for kinematics only

        self._body = Human()
        self._arm = self._body.actuated_index[3:]  # clavicle, shoulder, elbow, wrist

    def reset(self, seed: int | None = None) -> None:
        pass

    def act(self, observation: np.ndarray) -> np.ndarray:
        obs = np.asarray(observation, dtype=float)
        q = np.arctan2(obs[N_DOFS : 2 * N_DOFS], obs[:N_DOFS])
        jac = self._body.fingertip_jacobian(q)[:, self._arm]  # also poses the body model
        shoulder = self._body.arm_chain(self._body.body_transforms())[3]
        direction = self._direction(obs, shoulder)
        dx = self._gain(obs) * self.step_size * direction
        dq = jac.T @ np.linalg.solve(jac @ jac.T + self.damping**2 * np.eye(3), dx)
        target = q.copy()
        target[self._arm] += dq
        return self._body.action_for(target)

    def _direction(self, obs: np.ndarray, shoulder: np.ndarray) -> np.ndarray:
        feature = 3 * N_DOFS
        centroid, offset = obs[feature : feature + 3], obs[feature + 3 : feature + 6]
        axis = _unit(centroid - shoulder)
        along = offset @ axis
        lined_up = np.linalg.norm(offset - along * axis) <= self.aligned
        task = None if self.ablation == "no_task" else _unit(obs[-3:])
        if task is not None and task @ _unit(-offset) < 0.999 and not lined_up:
            return task  # touching the gown off the axis: follow the task vector
        if along < 0.0 and not lined_up:
            return _unit(centroid - self.approach_distance * axis - (centroid + offset))
        return axis

    def _gain(self, obs: np.ndarray) -> float:
        """+1 without haptic force, falling to -1 (moving back) at ``back_off_force``."""
        if self.ablation == "no_haptics":
            return 1.0
        start = 3 * N_DOFS + 6
        forces = obs[start : start + 3 * N_SENSORS].reshape(-1, 3)
        force = float(np.linalg.norm(forces.sum(axis=0)))
        return 1.0 - 2.0 * min(force / self.back_off_force, 1.0)


def _unit(v: np.ndarray) -> np.ndarray:
    return v / max(float(np.linalg.norm(v)), 1e-9)
