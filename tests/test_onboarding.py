"""Onboarding a robot nobody here built: feet by structure, a standing pose, on the ground."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

import virtual_actuators as va
from virtual_actuators.components.gains import joint_gains
from virtual_actuators.models.feet import find_feet
from virtual_actuators.models.standing import leg_joints, standing_pose
from virtual_actuators.simulation import Simulator


@pytest.fixture(scope="module")
def paw_robot(tmp_path_factory):
    """solo12 with feet named ``*_paw`` (and their joints ``*_tip``), without its SRDF."""
    text = va.load_robot("solo12").urdf_string.replace("_FOOT", "_paw").replace("_ANKLE", "_tip")
    path = tmp_path_factory.mktemp("paws") / "solo_paws.urdf"
    path.write_text(text)
    return va.load_robot(path)


def test_feet_found_by_structure(paw_robot):
    feet = find_feet(paw_robot)
    assert feet.source == "structure"
    assert sorted(feet.feet) == ["FL_paw", "FR_paw", "HL_paw", "HR_paw"]


def test_structure_agrees_with_names_and_srdf():
    from virtual_actuators.models.feet import structural_feet

    for name in ("go2", "anymal", "hyq", "laikago", "hexapod"):
        robot = va.load_robot(name)
        assert sorted(structural_feet(robot)) == sorted(find_feet(robot).feet), name


def _placements(robot, q):
    data = robot.model.createData()
    pin.framesForwardKinematics(robot.model, data, q)
    return data


@pytest.mark.parametrize("name", ["g1", "paw"])
def test_standing_pose_without_srdf(name, paw_robot):
    robot = paw_robot if name == "paw" else va.load_robot(name)
    assert robot.default_pose is None
    q = standing_pose(robot)
    model = robot.model
    assert np.all(q >= model.lowerPositionLimit - 1e-12)
    assert np.all(q <= model.upperPositionLimit + 1e-12)
    feet = find_feet(robot).feet
    data = _placements(robot, q)
    heights = [data.oMf[model.getFrameId(f)].translation[2] for f in feet]
    assert np.allclose(heights, 0.0, atol=1e-6)  # feet level, the lowest at z = 0
    middle = np.mean([data.oMf[model.getFrameId(f)].translation[:2] for f in feet], axis=0)
    assert np.linalg.norm(robot.center_of_mass(q)[:2] - middle) < 0.03  # CoM over the feet
    for foot in feet:
        frame = model.getFrameId(foot)
        joints = leg_joints(model, frame)
        jacobian = pin.computeFrameJacobian(
            model, data, q, frame, pin.ReferenceFrame.LOCAL_WORLD_ALIGNED
        )[:3, [model.joints[j].idx_v for j in joints]]
        # bent knees: the leg can push the foot vertically (a straight leg cannot)
        assert np.linalg.svd(jacobian, compute_uv=False)[2] > 0.02, foot
        if len(joints) >= 6:  # flat soles stay flat
            assert np.allclose(data.oMf[frame].rotation, np.eye(3), atol=1e-6)


def test_g1_standing_pose_is_above_ground_and_bent():
    robot = va.load_robot("g1")
    neutral = _placements(robot, robot.neutral())
    foot = robot.model.getFrameId("left_ankle_roll_link")
    assert neutral.oMf[foot].translation[2] < -0.7  # the URDF's neutral: feet underground
    q = standing_pose(robot)
    assert 0.5 < q[2] < 0.8
    knee = robot.model.joints[robot.model.getJointId("left_knee_joint")].idx_q
    assert q[knee] > 0.3


def test_standing_pose_keeps_the_srdf_pose():
    robot = va.load_robot("go2")
    assert np.array_equal(standing_pose(robot), robot.neutral())


def test_standing_pose_bad_input():
    with pytest.raises(va.InvalidInputError, match="fixed base"):
        standing_pose(va.load_robot("ur5"))
    with pytest.raises(va.InvalidInputError, match="height_ratio"):
        standing_pose(va.load_robot("g1"), height_ratio=2.0)
    with pytest.raises(va.FrameNotFoundError, match="left_ankle_roll_link"):
        standing_pose(va.load_robot("g1"), feet=["left_ankle_rol_link", "right_ankle_roll_link"])


@pytest.mark.parametrize("name", ["g1", "solo12"])
def test_simulator_starts_on_the_ground(name):
    robot = va.load_robot(name)
    simulator = Simulator(robot)
    q = simulator.q
    assert simulator.data.ncon > 0  # touching
    depth = min(simulator.data.contact.dist) if simulator.data.ncon else 0.0
    assert depth > -1e-6  # and not inside the ground
    # zero torque: the robot settles (no launch), its base stays low
    for _ in range(200):
        simulator.step(np.zeros(robot.model.nv))
    assert simulator.q[2] <= q[2] + 1e-3
    assert np.abs(simulator.v[:3]).max() < 3.0


def test_on_ground_moves_any_pose():
    robot = va.load_robot("g1")
    simulator = Simulator(robot)
    q = standing_pose(robot)
    for offset in (-0.3, 0.0, 0.4):
        lifted = q.copy()
        lifted[2] += offset
        placed = simulator.on_ground(lifted)
        assert np.array_equal(placed[3:], q[3:])
        assert abs(placed[2] - simulator.on_ground(q)[2]) < 1e-9
    with pytest.raises(va.InvalidInputError, match="floating base"):
        Simulator(va.load_robot("ur5")).on_ground(va.load_robot("ur5").neutral())


def test_sole_frames_read_their_links_geometry():
    robot = va.load_robot("talos")
    simulator = Simulator(robot)
    joints = [name for name in robot.joint_names if name != "root_joint"]
    stiffness, damping = joint_gains(robot, joints, 2 * np.pi * 5.0)
    controller = va.Controller(robot)
    controller.add("hold", va.Posture(joints, stiffness, damping, robot.neutral()[7:]))
    for _ in range(300):  # a rigid statue for 0.3 s
        simulator.step(controller.compute(simulator.q, simulator.v).tau)
    soles = simulator.contact_forces(["left_sole_link", "right_sole_link"])
    assert np.all(soles[:, 2] > 0.2 * robot.mass * 9.81)  # both soles carry weight
    assert soles[:, 2].sum() == pytest.approx(robot.mass * 9.81, rel=0.05)
    assert np.allclose(soles[0], simulator.contact_force("leg_left_6_link"))
    with pytest.raises(va.FrameNotFoundError, match="no collision geometry"):
        simulator.contact_force("universe")


def test_implausible_effort_limits_reported_and_set():
    from virtual_actuators.models.efforts import implausible_effort_limits, set_effort_limits

    robot = va.load_robot("solo12")
    found = implausible_effort_limits(robot)
    assert len(found) == 12 and set(found.values()) == {1000.0}  # 1000 N m on a 2.5 kg robot
    for name in ("go2", "talos", "g1", "anymal", "ur5"):  # real limits pass
        assert implausible_effort_limits(va.load_robot(name)) == {}, name
    set_effort_limits(robot, 2.7)
    assert implausible_effort_limits(robot) == {}
    set_effort_limits(robot, {"FL_KFE": 3.0})
    assert va.Controller(robot).effort_limits[6 + 2] == 3.0  # what controllers clip to
    assert Simulator(robot).model.actuator_ctrlrange[2].tolist() == [-3.0, 3.0]  # and motors
    with pytest.raises(va.JointNotFoundError, match="FL_KFE"):
        set_effort_limits(robot, {"FL_KEF": 3.0})
    with pytest.raises(va.InvalidInputError, match="FL_HAA"):
        set_effort_limits(robot, {"FL_HAA": -1.0})


BOX_FOOT = """<robot name="boxfoot">
  <link name="shin"><inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01"
    ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="foot"><inertial><mass value="0.5"/><inertia ixx="0.001" iyy="0.001" izz="0.001"
    ixy="0" ixz="0" iyz="0"/></inertial>
    <collision><origin xyz="0.03 -0.01 -0.02" rpy="0 0 0"/>
      <geometry><box size="0.2 0.08 0.04"/></geometry></collision>
    <collision><origin xyz="0 0 0.05"/><geometry><sphere radius="0.02"/></geometry></collision>
  </link>
  <link name="sole"/>
  <joint name="ankle" type="revolute"><parent link="shin"/><child link="foot"/>
    <axis xyz="0 1 0"/><limit lower="-1" upper="1" effort="10" velocity="1"/></joint>
  <joint name="sole_fixed" type="fixed"><parent link="foot"/><child link="sole"/>
    <origin xyz="0 0 -0.04"/></joint>
</robot>
"""


def test_sole_from_a_box(tmp_path):
    from virtual_actuators.models.soles import find_sole

    path = tmp_path / "boxfoot.urdf"
    path.write_text(BOX_FOOT)
    robot = va.load_robot(path, floating_base=False)
    sole = find_sole(robot, "sole")  # the box's bottom: x in [-0.07, 0.13], y in [-0.05, 0.03]
    assert sole.height == pytest.approx(0.0, abs=1e-12)
    assert np.allclose(sole.lower, (-0.07, -0.05)) and np.allclose(sole.upper, (0.13, 0.03))
    assert (sole.half_length, sole.half_width) == pytest.approx((0.07, 0.03))
    assert sole.centre == pytest.approx((0.03, -0.01))
    assert find_sole(robot, "foot").height == pytest.approx(-0.04)
    with pytest.raises(va.FrameNotFoundError, match="no collision geometry"):
        find_sole(robot, "shin")
    talos = find_sole(va.load_robot("talos"), "left_sole_link")  # a mesh
    assert 0.09 < talos.half_length < 0.12 and 0.05 < talos.half_width < 0.08
