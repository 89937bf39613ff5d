"""Gravity compensation against independent oracles: RNEA, the potential energy's gradient by
finite differences, and MuJoCo physics holding an arm still."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

import virtual_actuators as va
from virtual_actuators.components.gravity import GravityCompensation


def _potential(robot: va.Robot, q: np.ndarray, joints: list[int]) -> float:
    """Gravity potential of the bodies of ``joints`` [J], from the joint placements only."""
    model = robot.model
    data = pin.Data(model)
    pin.forwardKinematics(model, data, q)
    gravity = model.gravity.linear
    total = 0.0
    for j in joints:
        inertia = model.inertias[j]
        com_world = data.oMi[j].act(inertia.lever)
        total -= inertia.mass * float(gravity @ com_world)
    return total


def _fd_gravity(robot: va.Robot, q: np.ndarray, joints: list[int], h: float = 1e-6) -> np.ndarray:
    model = robot.model
    out = np.zeros(model.nv)
    for k in range(model.nv):
        step = np.zeros(model.nv)
        step[k] = h
        plus = _potential(robot, pin.integrate(model, q, step), joints)
        minus = _potential(robot, pin.integrate(model, q, -step), joints)
        out[k] = (plus - minus) / (2 * h)
    return out


def _joint_of(model: pin.Model, name: str) -> int:
    if name in model.names:
        return model.getJointId(name)
    return model.frames[model.getFrameId(name)].parentJoint


@pytest.mark.parametrize("name", ["ur5_robot", "panda", "solo12", "talos_reduced"])
def test_all_links_equal_rnea_at_rest(name):
    robot = va.load_robot(name)
    model = robot.model
    gravity = GravityCompensation(robot)
    for _ in range(5):
        q = pin.randomConfiguration(model, -np.ones(model.nq), np.ones(model.nq))
        oracle = pin.rnea(model, pin.Data(model), q, np.zeros(model.nv), np.zeros(model.nv))
        ours = gravity.torques(q)
        scale = max(1.0, np.abs(oracle).max())
        assert np.allclose(ours, oracle, rtol=0.0, atol=1e-10 * scale)
    assert gravity.mass == pytest.approx(robot.mass)


@pytest.mark.parametrize(
    ("name", "links"),
    [("ur5_robot", ["forearm_link", "wrist_3_link"]), ("solo12", ["FL_LOWER_LEG", "HR_HFE"])],
)
def test_some_links_equal_the_potential_gradient(name, links):
    robot = va.load_robot(name)
    model = robot.model
    gravity = GravityCompensation(robot, links)
    joints = sorted({_joint_of(model, n) for n in links})
    rng = np.random.default_rng(1)
    for _ in range(3):
        q = pin.randomConfiguration(model, -np.ones(model.nq), np.ones(model.nq))
        q[:3] = rng.normal(size=3) if robot.floating_base else q[:3]
        oracle = _fd_gravity(robot, q, joints)
        ours = gravity.torques(q)
        assert np.allclose(ours, oracle, rtol=0.0, atol=1e-6 * max(1.0, np.abs(oracle).max()))
    # linear in the selection: the parts add up to the whole
    rest = [model.names[j] for j in range(1, model.njoints) if j not in joints]
    q = robot.neutral()
    total = gravity.torques(q) + GravityCompensation(robot, rest).torques(q)
    assert np.allclose(total, GravityCompensation(robot).torques(q), atol=1e-10)


def test_reads_the_snapshot_and_rejects_bad_input():
    robot = va.load_robot("ur5_robot")
    gravity = GravityCompensation(robot)
    q = robot.neutral()
    assert np.array_equal(gravity.torques(va.Snapshot(robot, q)), gravity.torques(q))
    with pytest.raises(va.FrameNotFoundError, match="forearm_link"):
        GravityCompensation(robot, ["forearm_lnk"])
    with pytest.raises(va.InvalidInputError):
        GravityCompensation(robot, [3])
    with pytest.raises(va.InvalidInputError):
        gravity.torques(np.zeros(3))
    with pytest.raises(va.InvalidInputError):
        gravity.torques(va.Snapshot(va.load_robot("solo12"), va.load_robot("solo12").neutral()))
    assert "ur5_robot" in repr(gravity)


@pytest.mark.slow
def test_holds_an_arm_still_in_mujoco():
    from virtual_actuators.simulation import Simulator

    robot = va.load_robot("ur5_robot")
    q0 = robot.q(shoulder_lift_joint=-0.9, elbow_joint=1.2, wrist_1_joint=-0.7)
    simulator = Simulator(robot)
    simulator.reset(q0)
    gravity = GravityCompensation(robot)
    for _ in range(2000):  # 2 s
        simulator.step(gravity.torques(simulator.q))
    drift = np.abs(simulator.q - q0).max()
    assert drift < 1e-9  # [rad]: the MuJoCo model is built from the same Pinocchio model
    # without compensation it falls
    simulator.reset(q0)
    for _ in range(300):
        simulator.step(np.zeros(robot.model.nv))
    assert np.abs(simulator.q - q0).max() > 0.05
