"""The human: 22 DOF of which 11 are actuated, capsules and sensors on the body, stable PD
control toward absolute targets, and the paper's torque mapping as an option."""

import numpy as np
import pytest

from dressbench.scene.human import Human, HumanConfig


@pytest.fixture(scope="module")
def human() -> Human:
    return Human()


def no_wrench(human: Human) -> tuple[np.ndarray, np.ndarray]:
    z = np.zeros((len(human.body_names), 3))
    return z, z


def test_the_body_has_22_dofs_11_actuated_spine_and_right_arm(human):
    assert human.skeleton.getNumDofs() == 22
    actuated = [human.skeleton.getDof(int(i)).getName() for i in human.actuated_index]
    assert len(actuated) == 11
    assert actuated == [
        "spine_bend", "spine_flexion", "spine_twist",
        "clavicle_r_elevation", "clavicle_r_protraction",
        "shoulder_r_elevation", "shoulder_r_middle", "shoulder_r_swing",
        "elbow_r_flexion", "wrist_r_flexion", "wrist_r_deviation",
    ]  # fmt: skip


def test_rest_pose_lies_inside_the_joint_ranges(human):
    assert (human.lower <= human.rest).all() and (human.rest <= human.upper).all()
    assert (human.lower < human.upper).all()


def test_adult_proportions(human):
    tip, wrist, elbow, shoulder = human.arm_chain(human.body_transforms())
    human.reset(np.zeros(22))  # T-pose: the arm lies straight along -y
    tip, wrist, elbow, shoulder = human.arm_chain(human.body_transforms())
    assert np.linalg.norm(elbow - shoulder) == pytest.approx(0.30)
    assert np.linalg.norm(wrist - elbow) == pytest.approx(0.26)
    assert np.linalg.norm(tip - wrist) == pytest.approx(0.18)
    assert shoulder[1] < 0 and tip[1] < shoulder[1]  # the right arm is on the -y side
    human.reset()


def test_sensors_lie_on_the_capsule_axes(human):
    T = human.body_transforms()
    caps = human.capsules(T)
    sensors = human.sensors(T)
    assert sensors.shape == (22, 3)
    for s, body in zip(sensors, human.sensor_body, strict=True):
        own = caps[human.capsule_body == body]
        a, b = own[:, 0], own[:, 1]
        t = np.clip(((s - a) * (b - a)).sum(1) / ((b - a) ** 2).sum(1), 0, 1)
        assert np.linalg.norm(s - (a + t[:, None] * (b - a)), axis=1).min() < 0.02


def test_zero_action_holds_the_rest_pose(human):
    human.reset()
    human.set_action(np.zeros(11))
    for _ in range(200):
        human.step(*no_wrench(human))
    assert np.abs(human.q - human.rest).max() < 1e-3


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_random_targets_stay_stable(human, seed):
    human.reset()
    rng = np.random.default_rng(seed)
    for k in range(1500):  # 15 s of random targets, held 0.4 s each
        if k % 40 == 0:
            human.set_action(rng.uniform(-1, 1, 11))
        human.step(*no_wrench(human))
        assert human.is_finite() and np.abs(human.dq).max() < 50.0


def test_a_reach_target_is_tracked(human):
    human.reset()
    q = human.rest.copy()
    q[8:12] = [0.0, 0.0, np.pi / 2, 0.0]  # right arm straight ahead
    human.set_action(human.action_for(q))
    for _ in range(100):
        human.step(*no_wrench(human))
    assert np.abs(human.q - q)[human.actuated_index].max() < 0.05
    tip, *_, shoulder = human.arm_chain(human.body_transforms())
    np.testing.assert_allclose(tip - shoulder, [0.74, 0.0, 0.0], atol=0.05)


def test_action_for_inverts_the_target_mapping(human):
    q = human.rest.copy()
    q[human.actuated_index] = human.lower[human.actuated_index] * 0.3 + 0.1
    human.set_action(human.action_for(q))
    np.testing.assert_allclose(human.target[human.actuated_index], q[human.actuated_index])


def test_the_papers_torque_mapping_is_available():
    human = Human(HumanConfig(actuation="torque"))
    human.set_action(np.full(11, 0.5))
    human.step(*no_wrench(human))
    np.testing.assert_allclose(human.torque[human.actuated_index], 5.0)  # 0.5 x 10 N m
    with pytest.raises(ValueError, match="actuation"):
        Human(HumanConfig(actuation="muscles"))


def test_an_external_force_moves_the_body(human):
    human.reset()
    forces, torques = no_wrench(human)
    forces = forces.copy()
    forces[human.body_names.index("hand_r")] = [0.0, 0.0, 40.0]
    for _ in range(20):
        human.step(forces, torques)
    tip_z = human.arm_chain(human.body_transforms())[0, 2]
    human.reset()
    rest_z = human.arm_chain(human.body_transforms())[0, 2]
    assert tip_z > rest_z + 0.01


def test_a_delta_action_moves_the_pd_target_and_doing_nothing_holds_the_start_pose():
    held = {}
    for actuation in ("delta", "pd"):
        human = Human(HumanConfig(actuation=actuation))
        pose = human.outstretched()
        human.reset(pose)
        still = np.zeros((len(human.body_names), 3))
        for _ in range(25):  # one second of zero actions, 4 frames each
            human.set_action(np.zeros(human.N_ACTIONS))
            for _ in range(4):
                human.step(still, still)
        held[actuation] = np.abs(human.q - pose).max()
    assert held["delta"] < 0.05 and held["pd"] > 1.0  # an absolute zero target is rest
    human = Human(HumanConfig(actuation="delta"))
    before = human.target.copy()
    human.set_action(np.ones(human.N_ACTIONS))
    moved = (human.target - before)[human.actuated_index]
    room = (human.upper - before)[human.actuated_index]
    assert np.allclose(moved, np.minimum(human.delta_step, room))  # 0.12 rad, or to the limit
