"""The compiled feasibility check of the contact limits against forward-kinematics oracles.

``least_margin`` decides, without building the constraint rows, whether a tick's distribution
already meets the friction cones and unilateral minima (the usual tick). It must equal the
smallest margin computed from Pinocchio's sole orientations, and the rows' own margins.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
from oracles import robot

import virtual_actuators as va
from virtual_actuators.components import ConstantForce
from virtual_actuators.control import Controller
from virtual_actuators.control.contact_limits import constraint_rows, least_margin

PLANAR = ("x", "z", "ry")
ANKLES = ["left_ankle", "right_ankle"]


def _flamingo(mu: float | None, min_normal: float, unilateral: dict | None = None):
    rob = robot("spring_flamingo")
    double = va.ParallelVirtualActuator(
        rob, "body", ["left_foot", "right_foot"], "world", PLANAR, contact="flat", unactuated=ANKLES
    )
    controller = Controller(rob, clip=False)
    limits = {"friction": mu, "min_normal": min_normal} if mu is not None else {}
    controller.add(
        "double",
        double,
        [ConstantForce(PLANAR, [0.0, 100.0, 0.0])],
        yield_axes=("x",),
        unilateral=unilateral or {},
        **limits,
    )
    return rob, controller.attachments["double"]


def _tilted(rob: va.Robot, rng: np.random.Generator) -> np.ndarray:
    q = rob.neutral()
    for joint in [*ANKLES, "boom_pitch"]:
        q[rob.model.joints[rob.model.getJointId(joint)].idx_q] += rng.uniform(-0.4, 0.4)
    return q


def _oracle_margins(rob: va.Robot, q: np.ndarray, forces: np.ndarray, mu, min_normal):
    """Normal minus its minimum and ``mu n -+ t`` per sole, from Pinocchio's placements."""
    model = rob.model
    data = model.createData()
    pin.framesForwardKinematics(model, data, q)
    margins = []
    for chain, foot in enumerate(("left_foot", "right_foot")):
        rotation = data.oMf[model.getFrameId(foot)].rotation  # sole axes in the world
        force_world = np.array([forces[chain, 0], 0.0, forces[chain, 1]])
        normal = rotation[:, 2] @ force_world
        t1, t2 = rotation[:, 0] @ force_world, rotation[:, 1] @ force_world
        margins += [normal - min_normal, mu * normal - t1, mu * normal + t1]
        margins += [mu * normal - t2, mu * normal + t2]
    return np.array(margins)


@pytest.mark.parametrize("seed", range(6))
def test_least_margin_equals_the_forward_kinematics_cone_margins(seed):
    rng = np.random.default_rng(seed)
    mu, min_normal = rng.uniform(0.2, 1.2), rng.uniform(0.0, 20.0)
    rob, attachment = _flamingo(mu, min_normal)
    for _ in range(40):
        q = _tilted(rob, rng)
        snapshot = va.Snapshot(rob, q, np.zeros(rob.model.nv))
        forces = rng.normal(0.0, 60.0, (2, 3)) + [0.0, 50.0, 0.0]
        expected = _oracle_margins(rob, q, forces, mu, min_normal).min()
        margin = least_margin(attachment, snapshot, forces)
        assert margin == pytest.approx(expected, rel=1e-12, abs=1e-10 * np.abs(forces).max())
        rows, lows = constraint_rows(attachment, snapshot)
        assert margin == pytest.approx((rows @ forces.ravel() - lows).min(), abs=1e-9)


def test_least_margin_of_unilateral_minima_is_the_least_share_above_its_floor():
    rng = np.random.default_rng(7)
    rob, attachment = _flamingo(None, 0.0, unilateral={"z": 12.0})
    snapshot = va.Snapshot(rob, _tilted(rob, rng), np.zeros(rob.model.nv))
    for _ in range(50):
        forces = rng.normal(0.0, 40.0, (2, 3))
        margin = least_margin(attachment, snapshot, forces)
        assert margin == pytest.approx((forces[:, 1] - 12.0).min(), rel=1e-12, abs=1e-12)
