"""``ParallelVirtualActuator.producible`` against an oracle built from Pinocchio directly.

The oracle shares no code with the library: the wrench a set of ground contacts can exert on a
floating base is the span of the base rows of the stacked contact Jacobians transposed
(``J_c^T f``, Pinocchio's generalized force on the free flyer: a wrench in the base frame about
its origin), turned into world axes. Point contacts contribute the linear rows of their
Jacobian, flat ones all six. ``give_way`` is checked on its stated properties.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

import virtual_actuators as va
from virtual_actuators.actuators.producible import give_way, moment_directions

FEET = ("FL_FOOT", "FR_FOOT", "HL_FOOT", "HR_FOOT")
AXES = ("x", "y", "z", "rx", "ry", "rz")


@pytest.fixture(scope="module")
def solo():
    return va.load_robot("solo12")


def _configuration(robot, seed):
    rng = np.random.default_rng(seed)
    q = robot.neutral()
    q[7:] += rng.uniform(-0.3, 0.3, robot.model.nv - 6)
    q[3:7] = pin.Quaternion(pin.rpy.rpyToMatrix(*rng.uniform(-0.3, 0.3, 3))).coeffs()
    return q


def _oracle(robot, q, feet, kinds, axes):
    """Orthonormal basis of the world-axes base wrenches the contacts can exert (SVD)."""
    model, data = robot.model, robot.model.createData()
    pin.computeJointJacobians(model, data, q)
    pin.updateFramePlacements(model, data)
    columns = []
    for foot, kind in zip(feet, kinds, strict=True):
        jacobian = pin.getFrameJacobian(
            model, data, model.getFrameId(foot), pin.ReferenceFrame.LOCAL_WORLD_ALIGNED
        )
        rows = jacobian[:3] if kind == "point" else jacobian
        columns.append(rows[:, :6].T)  # generalized force on the free flyer (base frame)
    stacked = np.hstack(columns)
    rotation = data.oMi[1].rotation
    world = np.zeros((6, 6))
    world[:3, :3] = world[3:, 3:] = rotation
    stacked = (world @ stacked)[[AXES.index(a) for a in axes]]
    u, s, _ = np.linalg.svd(stacked, full_matrices=False)
    return u[:, s > 1e-9 * s[0]]


def _projector(basis):
    return basis @ basis.T


@pytest.mark.parametrize(
    ("feet", "rank"),
    [(FEET[:1], 3), (("FL_FOOT", "HR_FOOT"), 5), (("FL_FOOT", "FR_FOOT"), 5), (FEET[:3], 6),
     (FEET, 6)],
)
def test_point_feet_match_the_oracle(solo, feet, rank):
    body = va.ParallelVirtualActuator(solo, "base_link", list(feet), "world", contact="point")
    for seed in range(3):
        q = _configuration(solo, seed)
        basis = body.producible(q)
        oracle = _oracle(solo, q, feet, ["point"] * len(feet), AXES)
        assert basis.shape == (6, rank) == oracle.shape
        assert np.allclose(basis.T @ basis, np.eye(rank), atol=1e-10)
        assert np.allclose(_projector(basis), _projector(oracle), atol=1e-8)


def test_two_point_feet_cannot_turn_about_the_line_between_them(solo):
    feet = ["FL_FOOT", "HR_FOOT"]
    body = va.ParallelVirtualActuator(solo, "base_link", feet, "world", contact="point")
    q = _configuration(solo, 4)
    snapshot = va.Snapshot(solo, q)
    basis = body.producible(snapshot)
    line = snapshot.frame_position(feet[1]) - snapshot.frame_position(feet[0])
    line /= np.linalg.norm(line)
    couple = np.r_[np.zeros(3), line]
    assert np.linalg.norm(couple - basis @ (basis.T @ couple)) > 0.5  # mostly unproducible
    # a pure force through either foot and the couples about the other axes are producible
    base = snapshot.frame_position("base_link")
    force = np.array([3.0, -1.0, 20.0])
    lever = snapshot.frame_position(feet[0]) - base
    through_foot = np.r_[force, np.cross(lever, force)]
    assert np.allclose(basis @ (basis.T @ through_foot), through_foot, atol=1e-9)
    # give_way: moments change only along the line, the forces stay exact
    wrench = np.array([5.0, 2.0, 25.0, 0.4, -0.3, 0.2])
    produced = give_way(basis, wrench, moment_directions(AXES))
    assert np.allclose(basis @ (basis.T @ produced), produced, atol=1e-9)
    change = produced - wrench
    assert np.allclose(change[:3], 0.0, atol=1e-12)
    assert np.allclose(np.cross(change[3:], line), 0.0, atol=1e-9)
    # and the distribution then meets it exactly
    solution = body.solve(q, produced)
    assert solution.residual < 1e-6 * np.linalg.norm(produced)


def test_one_point_foot_produces_only_a_force_and_moments_follow(solo):
    body = va.ParallelVirtualActuator(solo, "base_link", ["FL_FOOT"], "world", contact="point")
    q = _configuration(solo, 5)
    basis = body.producible(q)
    wrench = np.array([1.0, 2.0, 30.0, 0.5, 0.5, 0.5])
    produced = give_way(basis, wrench, moment_directions(AXES))
    assert np.allclose(produced[:3], wrench[:3], atol=1e-12)
    assert np.allclose(basis @ (basis.T @ produced), produced, atol=1e-9)


def test_flat_feet_match_the_oracle():
    robot = va.load_robot("talos")  # six-joint legs: one sole produces any wrench
    q = _configuration(robot, 6)
    for feet in (["left_sole_link"], ["left_sole_link", "right_sole_link"]):
        body = va.ParallelVirtualActuator(robot, "base_link", feet, "world", contact="flat")
        oracle = _oracle(robot, q, feet, ["flat"] * len(feet), AXES)
        assert body.producible(q).shape == oracle.shape == (6, 6)
    mixed = va.ParallelVirtualActuator(
        robot, "base_link", ["left_sole_link"], "world", contact={"left_sole_link": "point"}
    )
    oracle = _oracle(robot, q, ["left_sole_link"], ["point"], AXES)
    assert np.allclose(_projector(mixed.producible(q)), _projector(oracle), atol=1e-8)


def test_axis_subsets_match_the_oracle():
    robot = va.load_robot("solo12")
    q = _configuration(robot, 6)
    axes = ("x", "y", "z", "rz")
    feet = ["FL_FOOT", "HR_FOOT"]
    body = va.ParallelVirtualActuator(robot, "base_link", feet, "world", axes, contact="point")
    basis = body.producible(q)
    # the point contacts' moments on the unselected axes are free: project the oracle's span
    oracle = _oracle(robot, q, feet, ["point"] * 2, AXES)
    rows = [AXES.index(a) for a in axes]
    u, s, _ = np.linalg.svd(oracle[rows], full_matrices=False)
    expected = u[:, s > 1e-9 * s[0]]
    assert np.allclose(_projector(basis), _projector(expected), atol=1e-8)


def test_give_way_leaves_producible_requests_alone(solo):
    body = va.ParallelVirtualActuator(solo, "base_link", list(FEET), "world", contact="point")
    basis = body.producible(solo.neutral())
    wrench = np.array([1.0, -2.0, 24.0, 0.1, 0.2, -0.3])
    assert np.array_equal(give_way(basis, wrench, moment_directions(AXES)), wrench)


def test_yielding_the_horizontal_force_keeps_height_and_attitude_exact(solo):
    """Two point feet, forces x, y yielding: the centre of mass's pendulum force, moments kept."""
    from virtual_actuators.actuators.producible import producible_directions

    feet = ["FL_FOOT", "HR_FOOT"]
    body = va.ParallelVirtualActuator(solo, "base_link", feet, "world", contact="point")
    q = _configuration(solo, 7)
    directions = producible_directions(body.kinematics, body.problem, q)
    assert np.allclose(directions.producible, body.producible(q))
    assert np.allclose(directions.producible.T @ directions.missing, 0.0, atol=1e-12)
    wrench = np.array([5.0, 2.0, 25.0, 0.4, -0.3, 0.2])
    horizontal = np.eye(6)[:, :2]
    produced = give_way(directions.producible, wrench, horizontal, directions.missing)
    assert np.allclose(produced[2:], wrench[2:], atol=1e-12)  # z and every moment exact
    basis = directions.producible
    assert np.allclose(basis @ (basis.T @ produced), produced, atol=1e-9)
    assert np.allclose(give_way(basis, wrench, horizontal), produced, atol=1e-9)
    assert body.solve(q, produced).residual < 1e-6 * np.linalg.norm(produced)


def test_the_actuator_gives_way_on_request(solo):
    feet = ["FL_FOOT", "HR_FOOT"]
    body = va.ParallelVirtualActuator(solo, "base_link", feet, "world", contact="point")
    q = _configuration(solo, 8)
    wrench = np.array([5.0, 2.0, 25.0, 0.4, -0.3, 0.2])
    request = body.give_way(q, wrench)  # the horizontal force yields
    assert np.allclose(request[2:], wrench[2:], atol=1e-12)
    assert body.solve(q, request).residual < 1e-6 * np.linalg.norm(request)
    moments = body.give_way(q, wrench, axes=("rx", "ry", "rz"))
    assert np.allclose(moments[:3], wrench[:3], atol=1e-12)
    assert body.solve(q, moments).residual < 1e-6 * np.linalg.norm(moments)
    with pytest.raises(va.InvalidAxisError):
        body.give_way(q, wrench, axes=("w",))
