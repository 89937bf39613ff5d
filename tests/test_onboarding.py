"""Onboarding a robot nobody here built: feet by structure, a standing pose, on the ground."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

import virtual_actuators as va
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
