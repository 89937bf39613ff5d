"""``Controller.warm_up``: kernels loaded before the first tick, and nothing else changes."""

from __future__ import annotations

import numpy as np
import pytest

import virtual_actuators as va

FEET = ["left_foot", "right_foot"]
AXES = ("x", "z", "ry")


class CountingForce(va.ConstantForce):
    """A constant force that counts its evaluations."""

    def __init__(self, force) -> None:
        super().__init__(AXES, force)
        self.calls = 0

    def compute_wrench(self, position, velocity, time):
        self.calls += 1
        return super().compute_wrench(position, velocity, time)


def _controller():
    robot = va.load_robot("spring_flamingo")
    body = va.ParallelVirtualActuator(
        robot, "body", FEET, "world", axes=AXES, contact="flat",
        unactuated=["left_ankle", "right_ankle"], friction=0.6, min_normal=10.0,
    )  # fmt: skip
    double = va.ParallelVirtualActuator(
        robot, "body", FEET, "world", axes=AXES, contact="flat",
        unactuated=["left_ankle", "right_ankle"],
    )  # fmt: skip
    swing = va.VirtualActuator(robot, "right_foot", "body", "world", AXES)
    component = CountingForce([40.0, 110.0, 1.0])
    controller = va.Controller(robot, clip=False)
    controller.add("qp", body, [component], method="qp", yield_axes=("x",))
    controller.add("double", double, [component], yield_axes=("x",), friction=0.5)
    controller.add("swing", swing, [va.SpringDamper(AXES, 100.0, 5.0)])
    return robot, controller, component


def test_warm_up_changes_no_result_and_evaluates_no_component():
    robot, warmed, counted = _controller()
    _, cold, _ = _controller()
    warmed.warm_up(robot.neutral())
    assert counted.calls == 0
    rng = np.random.default_rng(2)
    for _ in range(15):  # the QP's warm start carries over from tick to tick: same answers
        q = robot.neutral()
        q[3:] += rng.uniform(-0.05, 0.05, robot.model.nq - 3)
        v = rng.normal(0.0, 0.1, robot.model.nv)
        for active in (("qp", "swing"), ("double",)):
            a = warmed.compute(q, v, 0.0, active)
            b = cold.compute(q, v, 0.0, active)
            np.testing.assert_array_equal(a.tau, b.tau)


def test_warm_up_at_a_singular_configuration_does_not_raise():
    robot, controller, _ = _controller()
    q = robot.neutral()
    for joint in ("left_knee", "right_knee"):  # straight legs: a singular double support
        q[robot.model.joints[robot.model.getJointId(joint)].idx_q] = 0.0
    controller.warm_up(q)


def test_warm_up_checks_q():
    robot, controller, _ = _controller()
    with pytest.raises(va.InvalidInputError, match="Configuration q"):
        controller.warm_up(np.zeros(2))
