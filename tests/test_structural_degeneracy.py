"""Joints and directions the selected axes cannot reach, and ill-conditioned eliminations.

Each test builds the case on a real robot, states what the answer must be (a dropped limp row,
a rejected spring, a direction left unproduced, a dense re-solve) and checks it against the
RNEA oracle or the dense reference (eq. 10-11).
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
from oracles import external_forces, rnea_torques

import virtual_actuators as va

AXES = ("x", "y", "z", "rx", "ry", "rz")


def _q(robot: va.Robot, seed: int, scale: float = 0.4) -> np.ndarray:
    """The robot's standing pose moved by a seeded random tangent step."""
    model = robot.model
    step = np.random.default_rng(seed).uniform(-scale, scale, model.nv)
    return pin.normalize(model, pin.integrate(model, robot.neutral(), step))


def _rnea(robot: va.Robot, q, body: va.ParallelVirtualActuator, forces) -> np.ndarray:
    """``-rnea(q, 0, 0, fext)`` without gravity for +F_i on {B} and -F_i on {A_i}."""
    model = pin.Model(robot.model)
    model.gravity.linear[:] = 0.0
    pairs = [
        (body.action, r, body.reference, body.axes, f)
        for r, f in zip(body.reactions, forces, strict=True)
    ]
    return rnea_torques(model, q, external_forces(model, q, pairs))


def test_limp_joint_no_selected_axis_loads_is_dropped_not_kept():
    """The turkey's hip sits at the body's origin: an x force there loads no hip. The limp hip
    constrains nothing, so the partitioned answer is the dense one (exact), not a residual."""
    robot = va.load_robot("spring_turkey")
    body = va.ParallelVirtualActuator(
        robot,
        "body",
        ["left_foot", "right_foot"],
        "body",
        ("x",),
        "point",
        unactuated=["right_hip"],
        passive={"left_knee": (0.5, -0.6)},
    )
    hip = robot.model.joints[robot.model.getJointId("right_hip")].idx_v
    assert hip in body.problem.vacuous_v
    for seed in range(5):
        q = _q(robot, seed)
        wrench = np.array([3.0 + seed])
        sol = body.solve(q, wrench)
        dense = body.solve(q, wrench, method="dense")
        assert sol.method != "least-squares" and sol.residual <= 1e-9 * abs(wrench[0])
        np.testing.assert_allclose(sol.wrench, wrench, rtol=1e-12)
        assert sol.tau[hip] == 0.0
        assert sol.residual <= dense.residual + 1e-9 * abs(wrench[0])


@pytest.mark.parametrize(
    ("name", "action", "reactions", "axes", "spring"),
    [
        ("hexapod", "body", ["foot_1", "foot_2", "foot_3", "foot_4"], ("x",), "hip2_2"),
        (
            "hyq_no_sensors",
            "base_link",
            ["rh_foot", "lh_foot", "rf_foot", "lf_foot"],
            ("y",),
            "lh_haa_joint",
        ),
    ],
)
def test_spring_no_selected_axis_loads_is_rejected_when_declared(
    name, action, reactions, axes, spring
):
    robot = va.load_robot(name)
    with pytest.raises(va.ConstraintError, match=f"passive joint '{spring}'") as error:
        va.ParallelVirtualActuator(
            robot, action, reactions, action, axes, "point", passive={spring: (5.0, 0.3)}
        )
    assert str(list(axes)) in str(error.value)
    # a limp joint there is fine: it constrains nothing
    body = va.ParallelVirtualActuator(
        robot, action, reactions, action, axes, "point", unactuated=[spring]
    )
    q = _q(robot, 3)
    sol = body.solve(q, np.ones(len(axes)))
    assert sol.residual <= 1e-9


def test_direction_below_1e9_of_the_strongest_is_not_credited():
    """hyq's front-left leg on (x, y, ry) with a flat foot: the HAA joint's ry lever is URDF
    rounding (1e-12 relative). The leg cannot exert that direction: nothing is put on it, and
    the torques are the RNEA of the forces it does exert."""
    robot = va.load_robot("hyq_no_sensors")
    body = va.ParallelVirtualActuator(
        robot, "base_link", ["lf_foot"], "base_link", ("x", "y", "ry"), "flat"
    )
    q = _q(robot, 1)
    sol = body.solve(q, np.array([0.0, 5.0, 1.0]))
    dense = body.solve(q, np.array([0.0, 5.0, 1.0]), method="dense")
    np.testing.assert_allclose(sol.forces, dense.forces, rtol=0, atol=1e-9)
    np.testing.assert_allclose(sol.tau, _rnea(robot, q, body, sol.forces), rtol=0, atol=1e-9)
    assert body.problem.groups[0].rank == 2  # the leg's three joints span two directions


def test_ill_conditioned_elimination_is_resolved_by_the_dense_reference():
    """talos on four reactions with limp and passive arm and leg joints, at a pose where
    |F| ~ 5e5 for |w| = 100: the partitioned elimination lost the limp rows (torques 1e-7 |F|).
    Every path must keep the limp joints torque-free to 1e-10 |F|, like the dense reference."""
    robot = va.load_robot("talos_reduced")
    model = robot.model
    limp = ["arm_right_7_joint", "arm_right_2_joint"]
    body = va.ParallelVirtualActuator(
        robot,
        "base_link",
        ["left_sole_link", "gripper_left_base_link", "gripper_right_base_link", "right_sole_link"],
        "base_link",
        AXES,
        "point",
        unactuated=limp,
        passive={"leg_left_2_joint": (50.0, 0.3), "arm_right_3_joint": (50.0, 0.3)},
    )
    limp_v = [model.joints[model.getJointId(j)].idx_v for j in limp]
    q = _q(robot, 627, scale=0.25)
    direction = np.random.default_rng(3793556).normal(size=6)
    wrench = direction / np.linalg.norm(direction) * 100.0
    dense = body.solve(q, wrench, method="dense")
    assert np.abs(dense.forces).max() > 1e5  # the ill-conditioned pose
    for kwargs in ({}, {"compiled": False}):
        sol = body.solve(q, wrench, **kwargs)
        tau = _rnea(robot, q, body, sol.forces)
        scale = np.abs(sol.forces).max()
        assert np.abs(tau[limp_v]).max() <= 1e-10 * scale
        assert sol.residual <= dense.residual + 1e-9 * scale
