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


@pytest.mark.parametrize("name", ["ur5_robot", "panda", "talos_reduced"])
def test_controller_gravity_term_equals_pinocchio_generalized_gravity(name):
    """``controller.add("gravity", GravityCompensation(robot))``: tau is g(q), before clipping."""
    robot = va.load_robot(name)
    model = robot.model
    controller = va.Controller(robot, clip=False)
    term = GravityCompensation(robot)
    assert controller.add("gravity", term) is term
    rng = np.random.default_rng(3)
    for _ in range(5):
        q = pin.randomConfiguration(model, -np.ones(model.nq), np.ones(model.nq))
        v = rng.normal(size=model.nv)
        oracle = pin.computeGeneralizedGravity(model, pin.Data(model), q)
        out = controller.compute(q, v)
        scale = max(1.0, np.abs(oracle).max())
        assert np.allclose(out.tau, oracle, rtol=0.0, atol=1e-10 * scale)
        assert np.allclose(out.tau_requested, oracle, rtol=0.0, atol=1e-10 * scale)
        assert np.allclose(controller.compute(q, v, active=()).tau, 0.0)  # active= drops it


def test_controller_gravity_term_adds_to_a_spring_and_some_links_only():
    """A spring's J^T F plus the gravity of some links: Pinocchio's Jacobian and gravity of a
    model whose other bodies weigh nothing."""
    robot = va.load_robot("ur5_robot")
    model = robot.model
    q = np.array([0.3, -1.2, 1.5, -1.9, -1.5, 0.4])
    tool = va.VirtualActuator(robot, action="tool0", reaction="world", reference="world",
                              axes=("x", "y", "z"))
    setpoint = tool.position(q) + np.array([0.02, -0.01, 0.03])
    controller = va.Controller(robot, clip=False)
    controller.add("tool", tool, [va.Spring(tool.axes, 500.0, setpoint=setpoint)])
    controller.add("gravity", GravityCompensation(robot, links=["forearm_link", "wrist_1_link"]))
    controller.reset(["gravity", "tool"], q, 0.0)  # a term without state resets
    light = model.copy()
    kept = {model.getJointId("elbow_joint"), model.getJointId("wrist_1_joint")}
    for j in range(model.njoints):
        if j not in kept:
            light.inertias[j] = pin.Inertia.Zero()
    data = model.createData()
    pin.framesForwardKinematics(model, data, q)
    jacobian = pin.computeFrameJacobian(
        model, data, q, model.getFrameId("tool0"), pin.LOCAL_WORLD_ALIGNED
    )[:3]
    force = 500.0 * (setpoint - data.oMf[model.getFrameId("tool0")].translation)
    oracle = jacobian.T @ force + pin.computeGeneralizedGravity(light, light.createData(), q)
    tau = controller.compute(q, np.zeros(model.nv)).tau
    assert np.allclose(tau, oracle, rtol=0.0, atol=1e-10 * np.abs(oracle).max())
    assert np.abs(pin.computeGeneralizedGravity(light, light.createData(), q)).max() > 1.0


def test_controller_gravity_term_bad_uses():
    ur5, panda = va.load_robot("ur5_robot"), va.load_robot("panda")
    controller = va.Controller(ur5)
    with pytest.raises(va.InvalidInputError, match="'panda'.*make one per robot"):
        controller.add("gravity", GravityCompensation(panda))
    tool = va.VirtualActuator(ur5, action="tool0", reaction="world")
    with pytest.raises(va.InvalidInputError, match="takes no components"):
        controller.add("gravity", GravityCompensation(ur5), [va.Damper(tool.axes, 1.0)])
    controller.add("gravity", GravityCompensation(ur5))
    with pytest.raises(va.InvalidInputError, match="not taken"):
        controller.add("gravity", GravityCompensation(ur5))


def test_gravity_compensation_holds_the_arm_in_mujoco_through_va_run():
    """The term inside va.run, no wrapper: the UR5 stays put in MuJoCo (its own physics)."""
    from virtual_actuators.simulation import MujocoHardware, Simulator

    robot = va.load_robot("ur5_robot")
    q0 = np.array([0.3, -1.2, 1.5, -1.9, -1.5, 0.4])
    controller = va.Controller(robot)
    controller.add("gravity", GravityCompensation(robot))
    simulator = Simulator(robot)
    simulator.reset(q0)
    hardware = MujocoHardware(simulator)
    va.run(controller, hardware.read_state, hardware.write_effort, robot=robot, rate_hz=1000,
           realtime=False, should_stop=lambda: simulator.time >= 1.0)
    assert np.abs(simulator.q - q0).max() < 1e-3  # [rad]; unheld, the arm falls by ~1 rad
    simulator.reset(q0)
    for _ in range(1000):
        simulator.step(np.zeros(robot.model.nv))
    assert np.abs(simulator.q - q0).max() > 0.1


def test_efforts_on_some_joints_only_are_the_potentials_gradient_there():
    """``joints=``: an arm's bodies held by its own joints, the rest of the robot untouched."""
    robot = va.load_robot("anymal_kinova")
    model = robot.model
    arm = [model.names[j] for j in range(2, model.njoints) if "j2s6s200" in model.names[j]]
    term = GravityCompensation(robot, links=arm, joints=arm)
    q = robot.neutral()
    columns = [model.joints[model.getJointId(j)].idx_v for j in arm]
    expected = _fd_gravity(robot, q, [model.getJointId(j) for j in arm])
    tau = term.torques(q)
    assert np.allclose(tau[columns], expected[columns], atol=1e-6 * max(1.0, abs(expected).max()))
    others = np.setdiff1d(np.arange(model.nv), columns)
    assert not tau[others].any() and abs(expected[others]).max() > 1.0  # the legs carry it
    with pytest.raises(va.JointNotFoundError, match="j2s6s200_joint_1"):
        GravityCompensation(robot, joints=["j2s6s200_joint1"])
