"""Built-in human policies: passive, random, reach, and a scripted non-learned baseline.

None is trained, so each runs under any capability profile (``profile = None``): its actions
are the same, and the env maps them onto the profile's joint ranges.
"""

from __future__ import annotations

from typing import ClassVar

import numpy as np

from ..observation import observation_layout


class Passive:
    """Does nothing: the zero action holds the rest pose."""

    api_version: ClassVar[int] = 1
    robot: str | None = None
    ablation: str = "complete"
    actuation: str = "pd"
    profile: str | None = None

    def reset(self, seed: int | None = None) -> None:
        pass

    def act(self, observation: np.ndarray) -> np.ndarray:
        return np.zeros(11)


class Random:
    """Uniform random PD targets, redrawn every step."""

    api_version: ClassVar[int] = 1
    robot: str | None = None
    ablation: str = "complete"
    actuation: str = "pd"
    profile: str | None = None

    def __init__(self) -> None:
        self._rng = np.random.default_rng()

    def reset(self, seed: int | None = None) -> None:
        self._rng = np.random.default_rng(seed)

    def act(self, observation: np.ndarray) -> np.ndarray:
        return self._rng.uniform(-1.0, 1.0, 11)


class Reach:
    """Holds the right arm straight out ahead at shoulder height, whatever it perceives: what a
    robot strategy achieves on its own, by bringing the opening to a still, outstretched arm."""

    api_version: ClassVar[int] = 1
    robot: str | None = None
    ablation: str = "complete"
    actuation: str = "pd"
    profile: str | None = None

    def __init__(self) -> None:
        from ..scene.human import Human  # the body model, for its joint ranges only

        body = Human()
        self._action = body.action_for(body.outstretched())

    def reset(self, seed: int | None = None) -> None:
        pass

    def act(self, observation: np.ndarray) -> np.ndarray:
        return self._action.copy()


class Scripted:
    """A non-learned baseline: steers the fingertip with damped least squares on the arm's
    Jacobian (an internal body model) and backs off when the haptic forces grow.

    It first brings the hand under the way in, rises into line with the axis from its shoulder
    through the opening's centre (it assumes, as a person would, that the opening faces it),
    pushes along that axis with the wrist trailing, and once past the opening follows the task
    vector. It reads only the observation; the spine is left at rest, so the torso stays upright.
    """

    api_version: ClassVar[int] = 1
    robot: str | None = None
    ablation: str = "complete"
    actuation: str = "pd"
    profile: str | None = None
    step_size = 0.03  # m of fingertip motion asked for per policy step
    damping = 0.05  # m, of the damped least squares
    back_off_force = 20.0  # N: above this total haptic force the hand moves back
    approach_distance = 0.12  # m before the opening where the hand lines up
    aligned = 0.025  # m off the axis that counts as lined up
    rise = 0.2  # m: the hand comes up into the way in from this far below it
    # clavicle (2), shoulder elevation, middle, swing, elbow, wrist (2): arm raised forward
    reach_posture = np.array([0.0, 0.0, 0.2, 0.0, 1.2, 1.0, 0.0, 0.0])
    posture_gain = 0.1

    def __init__(self) -> None:
        from ..scene.human import Human  # the body model, used for kinematics only

        self._body = Human()
        self._arm = self._body.actuated_index[3:]  # clavicle, shoulder, elbow, wrist

    def reset(self, seed: int | None = None) -> None:
        pass

    def act(self, observation: np.ndarray) -> np.ndarray:
        obs = np.asarray(observation, dtype=float)
        layout = observation_layout(self.ablation)
        q = np.arctan2(obs[layout.sin_q], obs[layout.cos_q])
        tip_jac, wrist_jac = self._body.hand_jacobians(q)  # also poses the body model
        tip, wrist, _, shoulder = self._body.arm_chain(self._body.body_transforms())
        direction, lined_up = self._direction(obs, shoulder)
        dx = self._gain(obs) * self.step_size * direction
        jac = tip_jac[:, self._arm]
        if lined_up:  # the wrist trails the fingertip, so the hand points along the axis
            wrist_step = tip + dx - np.linalg.norm(tip - wrist) * direction - wrist
            wrist_step *= min(1.0, self.step_size / max(np.linalg.norm(wrist_step), 1e-9))
            jac = np.vstack([jac, wrist_jac[:, self._arm]])
            dx = np.concatenate([dx, wrist_step])
        pinv = jac.T @ np.linalg.inv(jac @ jac.T + self.damping**2 * np.eye(len(dx)))
        # in the task's null space, drift toward a reaching posture (elbow up, arm forward)
        posture = self.posture_gain * (self.reach_posture - q[self._arm])
        dq = pinv @ dx + (np.eye(len(self._arm)) - pinv @ jac) @ posture
        target = q.copy()
        target[self._arm] += dq
        return self._body.action_for(target)

    def _direction(self, obs: np.ndarray, shoulder: np.ndarray) -> tuple[np.ndarray, bool]:
        """Where the fingertip should go, and whether it is lined up on the way in."""
        layout = observation_layout(self.ablation)
        centroid, offset = obs[layout.centroid], obs[layout.tip_offset]
        axis = _unit(centroid - shoulder)
        along = offset @ axis
        tip = centroid + offset
        if np.linalg.norm(offset - along * axis) > self.aligned:  # off the axis: line up first
            entry = centroid - self.approach_distance * axis
            below = entry - np.array([0.0, 0.0, self.rise])
            if np.linalg.norm((tip - below)[:2]) > self.aligned and tip[2] < entry[2]:
                return _unit(below - tip), False  # under the way in, then up into it
            return _unit(entry - tip), False
        task = None if layout.task is None else _unit(obs[layout.task])
        if along > 0.0 and task is not None and task @ axis > 0.5:
            return task, True  # through the opening: the task vector leads on
        return axis, True

    def _gain(self, obs: np.ndarray) -> float:
        """+1 without haptic force, falling to -1 (moving back) at ``back_off_force``."""
        block = observation_layout(self.ablation).forces
        if block is None:
            return 1.0
        forces = obs[block].reshape(-1, 3)
        force = float(np.linalg.norm(forces.sum(axis=0)))
        return 1.0 - 2.0 * min(force / self.back_off_force, 1.0)


def _unit(v: np.ndarray) -> np.ndarray:
    return v / max(float(np.linalg.norm(v)), 1e-9)
