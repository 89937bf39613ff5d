"""Controller(on_failure=...): one policy for every per-attachment failure; compute()'s argument
checks; a Snapshot owns its q and v (issue 24, items 7, 9, 11, 14)."""

from __future__ import annotations

import warnings

import numpy as np
import pinocchio as pin
import pytest
from oracles import requires_core, robot

import virtual_actuators as va
from virtual_actuators.control import Controller

SOLO = robot("solo12")
FEET = ["FL_FOOT", "FR_FOOT", "HL_FOOT", "HR_FOOT"]
QP_TORQUE_LIMITS = np.r_[np.zeros(6), np.full(12, 3.0)]  # [N m] no 60 N per foot within these
REQUEST = np.array([1.0, -2.0, 25.0, 0.1, -0.2, 0.05])  # [N, N m] on the body


def infeasible_qp_controller(on_failure=None, **options) -> tuple[Controller, object]:
    """solo12 whose body QP cannot be solved: 60 N per foot needs more than 3 N m per joint."""
    body = va.ParallelVirtualActuator(
        SOLO, "base_link", FEET, friction=0.8, min_normal=60.0, torque_limits=QP_TORQUE_LIMITS
    )
    controller = Controller(SOLO, on_failure=on_failure, **options)
    controller.add("body", body, [va.ConstantForce(body.axes, REQUEST)], method="qp")
    return controller, body


def solo_state():
    q = SOLO.neutral()
    return q, np.zeros(SOLO.model.nv)


def test_the_qp_is_infeasible_and_raise_raises_it():
    controller, body = infeasible_qp_controller("raise")
    q, v = solo_state()
    with pytest.raises(va.ConstraintError):
        body.solve(q, REQUEST, method="qp")
    with pytest.raises(va.ConstraintError):
        controller.compute(q, v)


def test_fallback_is_the_partitioned_answer_clipped_to_the_effort_limits():
    controller, body = infeasible_qp_controller("fallback")
    limits = np.r_[np.full(6, np.inf), np.full(12, 0.3)]  # [N m] some joints clip
    controller.effort_limits = limits
    q, v = solo_state()
    out = controller.compute(q, v)
    oracle = body.solve(q, REQUEST, method="partitioned")  # the same request, non-strict
    expected = np.clip(oracle.tau, -limits, limits)
    assert (np.abs(oracle.tau) > limits).any()  # the clip binds
    np.testing.assert_allclose(out.tau, expected, rtol=0, atol=1e-12 * np.abs(oracle.tau).max())
    failure = out.failures["body"]
    assert (failure.reason, failure.error, failure.action) == (
        "constraint",
        "ConstraintError",
        "fallback",
    )
    assert failure.fallback_error is None and "cannot hold together" in failure.message
    assert out.failed == {}
    assert out.solutions["body"].solver == "partitioned"
    np.testing.assert_allclose(out.produced["body"], oracle.wrench, rtol=0, atol=1e-12)
    np.testing.assert_array_equal(out.wrenches["body"], REQUEST)
    assert "fallback=['body']" in repr(out)


def test_skip_drops_the_attachment_and_reports_it():
    controller, _ = infeasible_qp_controller("skip")
    q, v = solo_state()
    out = controller.compute(q, v)
    assert not out.tau.any()
    assert out.failures["body"].action == "skip" and out.failures["body"].reason == "constraint"
    assert "cannot hold together" in out.failed["body"] and "normal >= 60 N" in out.failed["body"]
    assert "body" not in out.solutions and "body" not in out.produced


def test_on_singular_is_the_former_name_of_on_failure():
    # the case: on_singular="skip" used to let a contact QP's ConstraintError out
    controller, _ = infeasible_qp_controller(None, on_singular="skip")
    q, v = solo_state()
    assert controller.on_failure == "skip"
    assert not controller.compute(q, v).tau.any()
    assert Controller(SOLO).on_failure == "raise"
    assert Controller(SOLO, on_singular="skip", on_failure="skip").on_failure == "skip"
    with pytest.raises(va.InvalidInputError, match="on_singular is the former name"):
        Controller(SOLO, on_singular="skip", on_failure="fallback")
    for bad in ("ignore", 1, ["skip"]):
        with pytest.raises(va.InvalidInputError, match="on_failure must be one of"):
            Controller(SOLO, on_failure=bad)


def test_a_failed_fallback_leaves_the_attachment_at_zero():
    rob = robot("spring_turkey")
    model = rob.model
    leg = va.ParallelVirtualActuator(rob, "body", ["left_foot"], "world", ("x", "z", "ry"))
    q = rob.neutral()
    knee = model.joints[model.getJointId("left_knee")].idx_q
    q[knee] = 0.0  # a straight knee: the leg's distribution is singular
    swing = va.VirtualActuator(rob, "right_foot", "world", "world", ("x", "z"))
    controller = Controller(rob, clip=False, on_failure="fallback")
    controller.add("stance", leg, [va.ConstantForce(("z", "ry"), (200.0, 1.0))], free=("x",))
    controller.add("swing", swing, [va.ConstantForce(("x", "z"), (3.0, -4.0))])
    v = np.zeros(model.nv)
    with pytest.raises(va.SingularConfigurationError):
        leg.solve(q, np.array([0.0, 200.0, 1.0]), free=("x",))
    out = controller.compute(q, v)
    failure = out.failures["stance"]
    assert (failure.reason, failure.action) == ("singular", "skip")
    assert failure.fallback_error.startswith("fallback failed: SingularConfigurationError")
    assert "stance" in out.failed
    # the swing leg's J^T F from Pinocchio alone
    data = pin.Data(model)
    pin.computeJointJacobians(model, data, q)
    pin.updateFramePlacements(model, data)
    frame = model.getFrameId("right_foot")
    jacobian = pin.getFrameJacobian(model, data, frame, pin.LOCAL_WORLD_ALIGNED)[[0, 2]]
    np.testing.assert_allclose(out.tau, jacobian.T @ np.array([3.0, -4.0]), rtol=0, atol=1e-12)


class Returns(va.Component):
    """A component that returns ``value`` (or raises it) on every axis it is given."""

    def __init__(self, axes, value):
        super().__init__(axes)
        self.value = value

    def compute_wrench(self, position, velocity, time):
        if isinstance(self.value, BaseException):
            raise self.value
        return self.value


UR5 = robot("ur5_robot")
UR5_Q = np.array([0.3, -1.0, 1.3, -0.8, 0.4, 0.2])


def ur5_controller(on_failure, value):
    tool = va.VirtualActuator(UR5, "tool0", "world", "world", ("x", "y", "z"))
    wrist = va.VirtualActuator(UR5, "wrist_1_link", "world", "world", ("z",))
    controller = Controller(UR5, clip=False, on_failure=on_failure)
    controller.add("tool", tool, [Returns(("x", "y", "z"), value)])
    controller.add("wrist", wrist, [va.ConstantForce(("z",), 5.0)])
    return controller, wrist


def wrist_oracle() -> np.ndarray:
    """J^T F of 5 N along world z at wrist_1_link, from Pinocchio."""
    model = UR5.model
    data = pin.Data(model)
    pin.computeJointJacobians(model, data, UR5_Q)
    pin.updateFramePlacements(model, data)
    frame = model.getFrameId("wrist_1_link")
    jacobian = pin.getFrameJacobian(model, data, frame, pin.LOCAL_WORLD_ALIGNED)
    return jacobian[2] * 5.0


@pytest.mark.parametrize(
    ("value", "raised", "error"),
    [
        (np.array([1.0, np.nan, 0.0]), va.InvalidInputError, "InvalidInputError"),
        (np.array([1.0, 2.0]), va.InvalidInputError, "InvalidInputError"),
        (np.array([1.0 + 1e-3j, 0.0, 0.0]), va.InvalidInputError, "InvalidInputError"),
        (ZeroDivisionError("empty tank"), ZeroDivisionError, "ZeroDivisionError"),
    ],
)
def test_a_component_that_gives_no_wrench(value, raised, error):
    v = np.zeros(6)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no ComplexWarning: complex wrenches are refused
        with pytest.raises(raised):
            ur5_controller("raise", value)[0].compute(UR5_Q, v)
        for policy in ("skip", "fallback"):
            out = ur5_controller(policy, value)[0].compute(UR5_Q, v)
            failure = out.failures["tool"]
            assert (failure.reason, failure.error, failure.action) == ("wrench", error, "skip")
            if policy == "fallback":
                assert failure.fallback_error == "no fallback: the components gave no wrench"
            np.testing.assert_allclose(out.tau, wrist_oracle(), rtol=0, atol=1e-12)


def test_a_bug_in_a_component_is_never_swallowed():
    with pytest.raises(TypeError, match="a bug"):
        ur5_controller("skip", TypeError("a bug"))[0].compute(UR5_Q, np.zeros(6))


def test_non_finite_efforts_from_a_finite_wrench_are_a_failure():
    def controller_of(policy):
        wrist = va.VirtualActuator(UR5, "wrist_1_link", "world", "world", ("z",))
        controller = Controller(UR5, clip=False, on_failure=policy)
        controller.add("tool", tool, [Returns(("rx", "ry", "rz"), huge)])
        controller.add("wrist", wrist, [va.ConstantForce(("z",), 5.0)])
        return controller

    tool = va.VirtualActuator(UR5, "tool0", "world", "world", ("rx", "ry", "rz"))
    jacobian = tool.jacobian(UR5_Q)
    column = np.abs(jacobian).sum(axis=0).argmax()
    huge = 1.7e308 * np.sign(jacobian[:, column])  # finite, but J^T F overflows
    with np.errstate(over="ignore"):
        assert not np.isfinite(jacobian.T @ huge).all()
        with pytest.raises(va.InvalidInputError, match="'tool': non-finite joint efforts"):
            controller_of("raise").compute(UR5_Q, np.zeros(6))
        for policy in ("skip", "fallback"):
            out = controller_of(policy).compute(UR5_Q, np.zeros(6))
            assert (out.failures["tool"].reason, out.failures["tool"].action) == ("effort", "skip")
            assert "tool" in out.failed and "tool" not in out.produced
            np.testing.assert_allclose(out.tau, wrist_oracle(), rtol=0, atol=1e-12)


def test_active_entries_that_are_not_names_are_typed_errors():
    controller, _ = ur5_controller("raise", np.zeros(3))
    for active, match in (([["tool"]], r"active\[0\]"), (["tool", 3], r"active\[1\]")):
        with pytest.raises(va.InvalidInputError, match=match):
            controller.compute(UR5_Q, np.zeros(6), active=active)
    with pytest.raises(va.InvalidInputError, match="twice"):
        controller.compute(UR5_Q, np.zeros(6), active=["tool", "tool"])


def test_a_velocity_beside_a_snapshot_must_be_the_snapshot_s():
    controller, _ = ur5_controller("raise", np.array([1.0, 2.0, 3.0]))
    v = np.linspace(-1.0, 1.0, 6)
    snapshot = va.Snapshot(UR5, UR5_Q, v)
    reference = controller.compute(snapshot).tau
    for same in (v.copy(), v.tolist(), snapshot.v):
        np.testing.assert_array_equal(controller.compute(snapshot, same).tau, reference)
    for other in (v + 1e-9, np.zeros(6), np.zeros(5), "v"):
        with pytest.raises(va.InvalidInputError, match="differs from the velocity"):
            controller.compute(snapshot, other)


@pytest.mark.parametrize("backend", [pytest.param("compiled", marks=requires_core), "pinocchio"])
def test_a_snapshot_owns_its_q_and_v(backend):
    model = SOLO.model
    q, v = SOLO.neutral(), np.linspace(-1.0, 1.0, model.nv)
    q_buffer, v_buffer = q.copy(), v.copy()
    snapshot = va.Snapshot(SOLO, q_buffer, v_buffer, backend=backend)
    q_buffer[:3] += 0.5  # the driver reuses its buffers for the next reading
    v_buffer[:] = 0.0
    np.testing.assert_array_equal(snapshot.q, q)
    np.testing.assert_array_equal(snapshot.v, v)
    data = pin.Data(model)
    pin.forwardKinematics(model, data, q, v)
    pin.updateFramePlacements(model, data)
    frame = model.getFrameId("FL_FOOT")
    np.testing.assert_allclose(
        snapshot.frame_position("FL_FOOT"), data.oMf[frame].translation, rtol=0, atol=1e-14
    )
    velocity = pin.getFrameVelocity(model, data, frame, pin.LOCAL_WORLD_ALIGNED).linear
    np.testing.assert_allclose(snapshot.frame_velocity("FL_FOOT"), velocity, rtol=0, atol=1e-13)
    # a buffer handed over as a view (array.array, memoryview) is copied too
    buffer = memoryview(bytearray(q.tobytes())).cast("d")
    viewed = va.Snapshot(SOLO, buffer, backend=backend)
    buffer[0] = 7.0
    assert viewed.q[0] == q[0]
