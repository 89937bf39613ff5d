"""``va.Posture``: a joint-space spring-damper on named joints, alone and in a controller."""

from __future__ import annotations

import numpy as np
import pytest

import virtual_actuators as va
from virtual_actuators.components.gains import body_gains, gains, joint_gains
from virtual_actuators.simulation import Simulator

ARM = ["arm_left_1_joint", "arm_left_2_joint", "arm_left_4_joint", "head_1_joint"]


@pytest.fixture(scope="module")
def talos():
    return va.load_robot("talos")


def _index(robot, joint):
    model = robot.model
    data = model.joints[model.getJointId(joint)]
    return data.idx_q, data.idx_v


def test_torques_by_hand(talos):
    stiffness = [100.0, 80.0, 60.0, 10.0]
    posture = va.Posture(ARM, stiffness, 5.0, {"arm_left_4_joint": -1.0}, robot=talos)
    rng = np.random.default_rng(3)
    q0 = talos.neutral()
    posture.reset(q0)  # joints without a setpoint hold this pose
    q = q0.copy()
    v = rng.normal(size=talos.model.nv)
    for joint in ARM:
        q[_index(talos, joint)[0]] += rng.uniform(-0.3, 0.3)
    tau = posture.torques(q, v)
    expected = np.zeros(talos.model.nv)
    for k, joint in enumerate(ARM):
        iq, iv = _index(talos, joint)
        target = -1.0 if joint == "arm_left_4_joint" else q0[iq]
        expected[iv] = stiffness[k] * (target - q[iq]) - 5.0 * v[iv]
    assert np.array_equal(np.flatnonzero(tau), np.flatnonzero(expected))
    assert np.allclose(tau, expected, rtol=1e-14, atol=1e-12)


def test_in_a_controller_like_an_attachment(talos):
    controller = va.Controller(talos, clip=False)
    posture = controller.add("arms", va.Posture(ARM, 50.0, 2.0))
    body = va.VirtualActuator(talos, "torso_2_link", "world", axes=("z",))
    controller.add("torso", body, [va.ConstantForce("z", 30.0)])
    q, v = talos.neutral(), np.full(talos.model.nv, 0.1)
    controller.reset(["arms"], q, 0.0)  # holds q
    out = controller.compute(q, v)
    torso = controller.compute(q, v, active=["torso"]).tau
    arms = controller.compute(q, v, active="arms").tau
    assert np.allclose(arms, posture.torques(q, v))
    assert np.allclose(out.tau, torso + arms)
    assert out.active == ("torso", "arms")
    for joint in ARM:
        assert arms[_index(talos, joint)[1]] == pytest.approx(-2.0 * 0.1)
    with pytest.raises(va.InvalidInputError, match="taken"):
        controller.add("arms", va.Posture(ARM, 1.0, 1.0))


def test_unknown_joint_names_the_closest(talos):
    controller = va.Controller(talos)
    with pytest.raises(va.JointNotFoundError, match="arm_left_1_joint"):
        controller.add("arms", va.Posture(["arm_left_1_jont"], 1.0, 1.0))
    with pytest.raises(va.InvalidInputError, match="stiffness"):
        va.Posture(ARM, [1.0, 2.0], 1.0)
    with pytest.raises(va.InvalidInputError, match="damping"):
        va.Posture(ARM, 1.0, -1.0)
    with pytest.raises(va.InvalidInputError, match="not one of its joints"):
        va.Posture(ARM, 1.0, 1.0, {"arm_right_1_joint": 0.0})
    with pytest.raises(va.InvalidInputError, match="not bound"):
        va.Posture(ARM, 1.0, 1.0).torques(talos.neutral(), np.zeros(talos.model.nv))
    with pytest.raises(va.JointNotFoundError, match="degrees of freedom"):
        va.Posture(["root_joint"], 1.0, 1.0, robot=talos)


def test_null_space_leaves_the_end_effector_alone():
    panda = va.load_robot("panda")
    hand = va.VirtualActuator(panda, "panda_link8", "world")
    joints = [f"panda_joint{i}" for i in range(1, 8)]
    posture = va.Posture(joints, 20.0, 0.0, 0.0, robot=panda, null_space=hand)
    q = panda.neutral() + 0.3
    free = va.Posture(joints, 20.0, 0.0, 0.0, robot=panda).torques(q, np.zeros(panda.model.nv))
    tau = posture.torques(q, np.zeros(panda.model.nv))
    jacobian = hand.jacobian(va.Snapshot(panda, q))
    assert np.linalg.norm(tau) > 1e-3 * np.linalg.norm(free)  # something is left
    # no end-effector wrench: tau is orthogonal to every J^T F
    assert np.abs(jacobian @ tau).max() < 1e-9 * np.linalg.norm(free)


def test_holds_an_arm_in_mujoco():
    robot = va.load_robot("ur5")
    joints = [name for name in robot.joint_names]
    target = robot.neutral() + np.array([0.3, -0.4, 0.5, -0.2, 0.3, 0.1])
    controller = va.Controller(robot)
    # gains in physical units: each joint's inertia, 3 Hz, critically damped
    stiffness, damping = joint_gains(robot, joints, 2 * np.pi * 3.0, 1.0, target)
    controller.add("hold", va.Posture(joints, stiffness, damping, target))
    gravity = va.GravityCompensation(robot)
    simulator = Simulator(robot, collisions="none")
    for _ in range(2000):  # 2 s
        q, v = simulator.q, simulator.v
        simulator.step(controller.compute(q, v).tau + gravity.torques(q))
    assert np.abs(simulator.q - target).max() < 1e-3
    assert np.abs(simulator.v).max() < 1e-3


def test_gains_in_physical_units():
    stiffness, damping = gains([2.0, 0.5], 10.0, 0.7)
    assert np.allclose(stiffness, [200.0, 50.0]) and np.allclose(damping, [28.0, 7.0])
    for name in ("solo12", "talos"):
        robot = va.load_robot(name)
        k, d = body_gains(robot, 8.0, 1.0, ("z", "ry"))
        assert k[0] == pytest.approx(robot.mass * 64.0)
        # the same frequency on robots 40x apart in mass: sqrt(k / m) is the frequency
        assert np.sqrt(k[0] / robot.mass) == pytest.approx(8.0)
        assert d[1] / (2.0 * np.sqrt(k[1] * k[1] / 64.0)) == pytest.approx(1.0)
    with pytest.raises(va.InvalidInputError, match="frequency"):
        gains(1.0, 0.0)
    with pytest.raises(va.JointNotFoundError, match="wrist_1_joint"):
        joint_gains(va.load_robot("ur5"), ["wrist_1_jiont"], 10.0)
