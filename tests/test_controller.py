"""The controller (components on actuators summed into joint efforts) against independent oracles.

Oracles: sensor positions from Pinocchio forward kinematics, velocities and Jacobians by central
finite differences of forward kinematics, Pinocchio's analytic frame Jacobians, the RNEA
external-force oracle of oracles.py (``tau = -rnea(q, 0, 0, fext)`` without gravity), and the
oracles.py' ``ReferenceDistribution`` (pinv of the distribution problem rebuilt from Pinocchio).
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
from oracles import (
    AXES,
    ReferenceDistribution,
    external_forces,
    random_configuration,
    rnea_torques,
    robot,
)

import virtual_actuators as va
from virtual_actuators.components import (
    Component,
    ConstantForce,
    Damper,
    DogtrackBunny,
    GrannyWalker,
    Spring,
    SpringDamper,
)
from virtual_actuators.control import Controller

UR5 = "ur5_robot"
TURKEY = "spring_turkey"
FLAMINGO = "spring_flamingo"
PLANAR = ("x", "z", "ry")
EPS = 1e-6  # finite-difference step


# -- independent kinematics ---------------------------------------------------------------------
def placement(model: pin.Model, q: np.ndarray, frame: str) -> pin.SE3:
    data = model.createData()
    pin.framesForwardKinematics(model, data, q)
    return data.oMf[model.getFrameId(frame)].copy()


def world_pose(model, q, frame) -> np.ndarray:
    """(p, log3(R)) of a frame in the world."""
    m = placement(model, q, frame)
    return np.concatenate((m.translation, pin.log3(m.rotation)))


def fd_twist(model, q, frame, dq) -> np.ndarray:
    """Central difference of the frame's world pose along ``dq``: (linear, angular) velocity."""
    mp = placement(model, pin.integrate(model, q, EPS * dq), frame)
    mm = placement(model, pin.integrate(model, q, -EPS * dq), frame)
    linear = (mp.translation - mm.translation) / (2 * EPS)
    angular = pin.log3(mp.rotation @ mm.rotation.T) / (2 * EPS)
    return np.concatenate((linear, angular))


def fd_jacobian(model, q, frame) -> np.ndarray:
    return np.column_stack([fd_twist(model, q, frame, e) for e in np.eye(model.nv)])


def analytic_jacobian(model, q, frame) -> np.ndarray:
    data = model.createData()
    return pin.computeFrameJacobian(
        model, data, q, model.getFrameId(frame), pin.ReferenceFrame.LOCAL_WORLD_ALIGNED
    )


def v_index(model, joint: str) -> int:
    return model.joints[model.getJointId(joint)].idx_v


def q_index(model, joint: str) -> int:
    return model.joints[model.getJointId(joint)].idx_q


def ur5_state(seed: int):
    rob = robot(UR5)
    rng = np.random.default_rng(seed)
    while True:
        q = rng.uniform(-2.0, 2.0, rob.model.nq)
        # stay away from the log3 cut at pi so that the rotation vector is smooth
        if np.linalg.norm(pin.log3(placement(rob.model, q, "tool0").rotation)) < 2.8:
            return q, rng.uniform(-1.0, 1.0, rob.model.nv), rng


# -- serial actuator on a fixed-base manipulator ------------------------------------------------
@pytest.mark.parametrize("seed", range(4))
def test_serial_spring_damper_gives_jt_f_with_f_by_hand(seed):
    rob = robot(UR5)
    model = rob.model
    q, v, rng = ur5_state(seed)
    k, b = rng.uniform(0, 300, 6), rng.uniform(0, 30, 6)
    x0, v0, f = rng.uniform(-0.5, 0.5, 6), rng.uniform(-0.5, 0.5, 6), rng.uniform(-5, 5, 6)
    arm = va.VirtualActuator(rob, "tool0", "world", "world", AXES)
    controller = Controller(rob, clip=False)
    controller.add(
        "arm",
        arm,
        [SpringDamper(AXES, stiffness=k, damping=b, setpoint=x0, velocity_setpoint=v0, force=f)],
    )
    out = controller.compute(q, v)

    position = world_pose(model, q, "tool0")
    velocity_fd = fd_twist(model, q, "tool0", v)
    jac_fd = fd_jacobian(model, q, "tool0")
    np.testing.assert_allclose(out.positions["arm"], position, rtol=0, atol=1e-12)
    np.testing.assert_allclose(out.velocities["arm"], velocity_fd, rtol=0, atol=1e-8)

    # the rotational set point is an orientation: the deflection is log(R_set R^T) in {O}
    deflection = x0 - position
    deflection[3:] = pin.log3(pin.exp3(x0[3:]) @ pin.exp3(position[3:]).T)
    force_fd = k * deflection + b * (v0 - velocity_fd) + f
    np.testing.assert_allclose(out.wrenches["arm"], force_fd, rtol=0, atol=1e-6)
    np.testing.assert_allclose(out.tau, jac_fd.T @ force_fd, rtol=0, atol=1e-6)

    # the same with Pinocchio's analytic Jacobian: tight
    jac = analytic_jacobian(model, q, "tool0")
    np.testing.assert_allclose(jac, jac_fd, rtol=0, atol=1e-8)
    force = k * deflection + b * (v0 - jac @ v) + f
    np.testing.assert_allclose(out.wrenches["arm"], force, rtol=0, atol=1e-10)
    np.testing.assert_allclose(out.tau, jac.T @ force, rtol=0, atol=1e-10)
    np.testing.assert_array_equal(out.produced["arm"], out.wrenches["arm"])


@pytest.mark.parametrize("seed", range(4))
def test_serial_torques_match_the_rnea_external_force_oracle(seed):
    rob = robot(UR5)
    q, v, rng = ur5_state(10 + seed)
    arm = va.VirtualActuator(rob, "tool0", "world", "world", AXES)
    controller = Controller(rob, clip=False)
    controller.add("arm", arm, [Spring(AXES, rng.uniform(0, 300, 6)), Damper(AXES, 20.0)])
    out = controller.compute(q, v)
    fext = external_forces(rob.model, q, [("tool0", "world", "world", AXES, out.wrenches["arm"])])
    np.testing.assert_allclose(out.tau, rnea_torques(UR5, q, fext), rtol=0, atol=1e-9)


def test_components_on_axis_subsets_are_summed_in_place():
    rob = robot(UR5)
    q, v, _ = ur5_state(20)
    arm = va.VirtualActuator(rob, "tool0", "world", "world", AXES)
    controller = Controller(rob, clip=False)
    controller.add(
        "arm",
        arm,
        [ConstantForce(("x", "rz"), [1.0, 2.0]), ConstantForce(("z", "rz"), [3.0, 4.0])],
    )
    out = controller.compute(q, v)
    np.testing.assert_allclose(out.wrenches["arm"], [1.0, 0.0, 3.0, 0.0, 0.0, 6.0], atol=0)
    jac = analytic_jacobian(rob.model, q, "tool0")
    np.testing.assert_allclose(out.tau, jac.T @ out.wrenches["arm"], rtol=0, atol=1e-10)


def test_sensor_other_than_the_actuator():
    """Components read the sensor; the torques still come from the actuator's Jacobian."""
    rob = robot(UR5)
    model = rob.model
    q, v, _ = ur5_state(21)
    axes = ("x", "y", "z")
    actuator = va.VirtualActuator(rob, "tool0", "world", "world", axes)
    sensor = va.VirtualActuator(rob, "tool0", "shoulder_link", "world", axes)
    controller = Controller(rob, clip=False)
    controller.add("arm", actuator, [Spring(axes, 100.0, setpoint=[0.1, 0.2, 0.3])], sensor=sensor)
    out = controller.compute(q, v)
    position = (
        placement(model, q, "tool0").translation - placement(model, q, "shoulder_link").translation
    )
    np.testing.assert_allclose(out.positions["arm"], position, rtol=0, atol=1e-12)
    force = 100.0 * (np.array([0.1, 0.2, 0.3]) - position)
    jac = analytic_jacobian(model, q, "tool0")[:3]
    np.testing.assert_allclose(out.tau, jac.T @ force, rtol=0, atol=1e-10)


def _two_attachments(clip=False):
    rob = robot(UR5)
    controller = Controller(rob, clip=clip)
    tool = va.VirtualActuator(rob, "tool0", "world", "world", AXES)
    wrist = va.VirtualActuator(rob, "wrist_2_link", "shoulder_link", "world", ("x", "y", "z"))
    controller.add("tool", tool, [SpringDamper(AXES, 200.0, 10.0, setpoint=0.1)])
    controller.add("wrist", wrist, [Spring(("x", "y", "z"), 150.0), Damper(("x", "z"), 5.0)])
    return rob, controller


@pytest.mark.parametrize("seed", range(3))
def test_two_attachments_sum_linearly_and_match_rnea(seed):
    rob, controller = _two_attachments()
    q, v, _ = ur5_state(30 + seed)
    both = controller.compute(q, v)
    tool = controller.compute(q, v, active=["tool"])
    wrist = controller.compute(q, v, active=["wrist"])
    np.testing.assert_allclose(both.tau, tool.tau + wrist.tau, rtol=0, atol=1e-12)
    assert both.active == ("tool", "wrist")
    assert tool.active == ("tool",) and set(tool.wrenches) == {"tool"}
    assert set(wrist.positions) == {"wrist"} and set(wrist.velocities) == {"wrist"}
    pairs = [
        ("tool0", "world", "world", AXES, both.wrenches["tool"]),
        ("wrist_2_link", "shoulder_link", "world", ("x", "y", "z"), both.wrenches["wrist"]),
    ]
    fext = external_forces(rob.model, q, pairs)
    np.testing.assert_allclose(both.tau, rnea_torques(UR5, q, fext), rtol=0, atol=1e-9)
    # the wrist actuator spans shoulder_link -> wrist_2_link: no torque at the base or last wrist
    np.testing.assert_array_equal(wrist.tau[[0, 5]], [0.0, 0.0])


def test_no_active_attachment_gives_zero():
    _, controller = _two_attachments()
    q, v, _ = ur5_state(40)
    out = controller.compute(q, v, active=())
    np.testing.assert_array_equal(out.tau, np.zeros(6))
    assert out.active == () and out.wrenches == {} and out.failed == {}


def test_limp_joints_get_zero_effort_and_others_are_unchanged():
    rob, controller = _two_attachments()
    q, v, _ = ur5_state(41)
    full = controller.compute(q, v)
    limp = controller.joint_indices(["elbow_joint", "wrist_3_joint"])
    np.testing.assert_array_equal(limp, [v_index(rob.model, "elbow_joint"), 5])
    out = controller.compute(q, v, limp=limp)
    expected = full.tau.copy()
    expected[limp] = 0.0
    np.testing.assert_array_equal(out.tau, expected)
    np.testing.assert_array_equal(out.tau_requested, expected)


def test_joint_indices_unknown_joint():
    _, controller = _two_attachments()
    with pytest.raises(va.JointNotFoundError, match="elbow_joint"):
        controller.joint_indices(["elbow"])


def test_clipping_to_urdf_effort_limits():
    rob = robot(UR5)
    model = rob.model
    q, v, _ = ur5_state(50)
    controller = Controller(rob)  # clip=True by default
    arm = va.VirtualActuator(rob, "tool0", "world", "world", AXES)
    force = np.array([300.0, -200.0, 400.0, 30.0, -20.0, 25.0])
    controller.add("arm", arm, [ConstantForce(AXES, force)])
    out = controller.compute(q, v)
    requested = analytic_jacobian(model, q, "tool0").T @ force
    limit = np.asarray(model.effortLimit)
    np.testing.assert_allclose(out.tau_requested, requested, rtol=0, atol=1e-10)
    saturated = np.abs(requested) > limit
    assert saturated.any() and not saturated.all()
    np.testing.assert_array_equal(out.saturated, saturated)
    np.testing.assert_allclose(out.tau, np.clip(requested, -limit, limit), rtol=0, atol=1e-10)
    assert np.all(np.abs(out.tau) <= limit)
    names = [model.names[j] for j in range(1, model.njoints)]
    assert out.saturated_joints == [n for n, s in zip(names, saturated, strict=True) if s]
    np.testing.assert_array_equal(controller.effort_limits, limit)


def test_effort_limits_are_assigned_checked_and_read_only():
    rob = robot(UR5)
    q, v, _ = ur5_state(52)
    controller = Controller(rob)
    arm = va.VirtualActuator(rob, "tool0", "world", "world", AXES)
    force = np.array([300.0, -200.0, 400.0, 30.0, -20.0, 25.0])
    controller.add("arm", arm, [ConstantForce(AXES, force)])
    with pytest.raises(ValueError):
        controller.effort_limits[0] = 1.0  # read-only: an in-place edit would go unseen
    controller.effort_limits = np.full(6, 5.0)
    out = controller.compute(q, v)
    np.testing.assert_allclose(out.tau, np.clip(out.tau_requested, -5.0, 5.0), rtol=0, atol=0)
    np.testing.assert_array_equal(out.saturated, np.abs(out.tau_requested) > 5.0)
    for bad in (np.full(5, 1.0), [1.0, 2.0, 3.0, 4.0, 5.0, -1.0], np.full(6, np.nan), "inf"):
        with pytest.raises(va.InvalidInputError, match="effort_limits"):
            controller.effort_limits = bad


class _Returns(Component):
    """A component returning a fixed object (to test how the controller takes it)."""

    def __init__(self, axes, value):
        super().__init__(axes)
        self.value = value

    def compute_wrench(self, position, velocity, time):
        return self.value


@pytest.mark.parametrize(
    ("value", "expected"),
    [
        (2.0, [2.0, 2.0, 2.0]),  # a scalar on every axis
        ([1, 2, 3], [1.0, 2.0, 3.0]),  # a list of ints
        (np.array([1, 2, 3], dtype=np.int32), [1.0, 2.0, 3.0]),
        (np.array([1.5, 2.5, 3.5]), [1.5, 2.5, 3.5]),
    ],
)
def test_component_results_of_any_numeric_form_are_summed(value, expected):
    rob = robot(UR5)
    q, v, _ = ur5_state(53)
    controller = Controller(rob, clip=False)
    arm = va.VirtualActuator(rob, "tool0", "world", "world", ("x", "y", "z"))
    controller.add("arm", arm, [_Returns(("x", "y", "z"), value)])
    out = controller.compute(q, v)
    np.testing.assert_array_equal(out.wrenches["arm"], expected)
    np.testing.assert_allclose(out.tau, arm.jacobian(q).T @ np.array(expected), atol=1e-12)


@pytest.mark.parametrize("value", [np.ones(2), "x", None, [np.nan, 0.0, 0.0]])
def test_component_returning_a_bad_wrench_is_a_typed_error(value):
    rob = robot(UR5)
    q, v, _ = ur5_state(54)
    controller = Controller(rob)
    arm = va.VirtualActuator(rob, "tool0", "world", "world", ("x", "y", "z"))
    controller.add("arm", arm, [_Returns(("x", "y", "z"), value)])
    with pytest.raises(va.InvalidInputError, match="arm"):
        controller.compute(q, v)


def test_no_clipping_when_clip_false():
    rob = robot(UR5)
    model = rob.model
    q, v, _ = ur5_state(51)
    controller = Controller(rob, clip=False)
    arm = va.VirtualActuator(rob, "tool0", "world", "world", AXES)
    force = np.array([300.0, -200.0, 400.0, 30.0, -20.0, 25.0])
    controller.add("arm", arm, [ConstantForce(AXES, force)])
    out = controller.compute(q, v)
    requested = analytic_jacobian(model, q, "tool0").T @ force
    assert np.any(np.abs(requested) > model.effortLimit)
    np.testing.assert_allclose(out.tau, requested, rtol=0, atol=1e-10)
    np.testing.assert_array_equal(out.tau, out.tau_requested)


def test_joints_without_a_positive_finite_limit_are_never_clipped():
    rob = va.load_robot(UR5)  # a private copy: its limits are edited below
    model = rob.model
    model.effortLimit[0] = 0.0
    model.effortLimit[1] = np.inf
    q, v, _ = ur5_state(52)
    controller = Controller(rob)
    arm = va.VirtualActuator(rob, "tool0", "world", "world", AXES)
    force = np.array([3000.0, -2000.0, 4000.0, 300.0, -200.0, 250.0])
    controller.add("arm", arm, [ConstantForce(AXES, force)])
    out = controller.compute(q, v)
    requested = analytic_jacobian(model, q, "tool0").T @ force
    assert np.all(np.abs(requested[2:]) > model.effortLimit[2:])
    np.testing.assert_allclose(out.tau[:2], requested[:2], rtol=0, atol=1e-10)
    np.testing.assert_allclose(out.tau[2:], np.sign(requested[2:]) * model.effortLimit[2:], atol=0)
    np.testing.assert_array_equal(out.saturated, [False, False, True, True, True, True])


def test_panda_fingers_and_arm_clip_independently():
    rob = robot("panda")
    model = rob.model
    q = rob.neutral()
    controller = Controller(rob)
    hand = va.VirtualActuator(rob, "panda_leftfinger", "panda_rightfinger", "world", AXES)
    controller.add("hand", hand, [ConstantForce(AXES, [1e4, 0, 0, 0, 0, 0])])
    out = controller.compute(q, np.zeros(model.nv))
    limit = np.asarray(model.effortLimit)
    np.testing.assert_allclose(out.tau, np.clip(out.tau_requested, -limit, limit), atol=0)
    np.testing.assert_array_equal(out.saturated, np.abs(out.tau_requested) > limit)


# -- parallel actuators on the planar bipeds ----------------------------------------------------
def turkey_double():
    rob = robot(TURKEY)
    return rob, va.ParallelVirtualActuator(
        rob,
        "body",
        ["left_foot", "right_foot"],
        "world",
        PLANAR,
        contact="point",
        design=[va.EqualTorque("left_hip", "right_hip")],
    )


def turkey_state(seed: int):
    rob = robot(TURKEY)
    model = rob.model
    rng = np.random.default_rng(seed)
    q = rob.neutral() + rng.uniform(-0.08, 0.08, model.nq)
    q[q_index(model, "boom_x")] += rng.uniform(-1.0, 1.0)
    return q, rng.uniform(-0.5, 0.5, model.nv), rng


@pytest.mark.parametrize("seed", range(4))
def test_double_support_torque_is_the_distribution_of_the_components_wrench(seed):
    rob, double = turkey_double()
    model = rob.model
    q, v, rng = turkey_state(60 + seed)
    granny = GrannyWalker(
        0.5, stiffness=(1500.0, 200.0), damping=(150.0, 20.0), pitch=0.05, weight=98.1
    )
    bunny = DogtrackBunny(speed=0.5, damping=80.0, stiffness=10.0, limit=60.0)
    controller = Controller(rob, clip=False)
    controller.add("double", double, [granny, bunny])
    x0, t0, t = rng.uniform(-1, 1), 0.3, 0.8
    bunny.reset(np.array([x0]), t0)
    out = controller.compute(q, v, time=t)

    bx, bz, bp = (q_index(model, j) for j in ("boom_x", "boom_z", "boom_pitch"))
    vx, vz, vp = (v_index(model, j) for j in ("boom_x", "boom_z", "boom_pitch"))
    # the default sensor of a parallel actuator: the body relative to the world
    np.testing.assert_allclose(out.positions["double"], q[[bx, bz, bp]], rtol=0, atol=1e-12)
    np.testing.assert_allclose(out.velocities["double"], v[[vx, vz, vp]], rtol=0, atol=1e-12)

    bunny_x = x0 + 0.5 * (t - t0)
    wrench = np.array(
        [
            np.clip(80.0 * (0.5 - v[vx]) + 10.0 * (bunny_x - q[bx]), -60.0, 60.0),
            1500.0 * (0.5 - q[bz]) + 150.0 * (0.0 - v[vz]) + 98.1,
            200.0 * (0.05 - q[bp]) + 20.0 * (0.0 - v[vp]),
        ]
    )
    np.testing.assert_allclose(out.wrenches["double"], wrench, rtol=0, atol=1e-10)
    solution = double.solve(q, wrench)
    np.testing.assert_allclose(out.tau, solution.tau, rtol=0, atol=1e-9)
    np.testing.assert_allclose(out.produced["double"], wrench, rtol=0, atol=1e-9)
    np.testing.assert_allclose(out.solutions["double"].forces, solution.forces, atol=1e-9)
    # EqualTorque and an independent check of the efforts: RNEA with each chain's share
    assert out.tau[v_index(model, "left_hip")] == pytest.approx(
        out.tau[v_index(model, "right_hip")], abs=1e-9
    )
    reference = ReferenceDistribution(
        rob,
        "body",
        ["left_foot", "right_foot"],
        "world",
        PLANAR,
        "point",
        design=[va.EqualTorque("left_hip", "right_hip")],
    )
    forces = reference.solve(q, wrench)
    np.testing.assert_allclose(out.solutions["double"].forces, forces, rtol=0, atol=1e-9)
    pairs = [
        ("body", f"{s}_foot", "world", PLANAR, forces[i]) for i, s in enumerate(("left", "right"))
    ]
    np.testing.assert_allclose(
        out.tau, rnea_torques(TURKEY, q, external_forces(model, q, pairs)), rtol=0, atol=1e-9
    )


def single_leg(name: str, side: str = "left"):
    rob = robot(name)
    if name == TURKEY:
        return rob, va.ParallelVirtualActuator(
            rob, "body", [f"{side}_foot"], "world", PLANAR, contact="point"
        )
    return rob, va.ParallelVirtualActuator(
        rob,
        "body",
        [f"{side}_foot"],
        "world",
        PLANAR,
        contact="flat",
        unactuated=[f"{side}_ankle"],
    )


@pytest.mark.parametrize("name", [TURKEY, FLAMINGO])
@pytest.mark.parametrize("seed", range(3))
def test_free_x_on_one_leg_produces_z_and_pitch_exactly_with_no_foot_moment(name, seed):
    rob, leg = single_leg(name)
    model = rob.model
    rng = np.random.default_rng(70 + seed)
    q = rob.neutral() + rng.uniform(-0.08, 0.08, model.nq)
    v = rng.uniform(-0.5, 0.5, model.nv)
    controller = Controller(rob, clip=False)
    granny = GrannyWalker(0.5, (1500.0, 200.0), (150.0, 20.0), pitch=0.02, weight=100.0)
    push = ConstantForce(("x",), 25.0)  # ignored: x is free
    controller.add("stance", leg, [granny, push], free=("x",))
    out = controller.compute(q, v)
    request = out.wrenches["stance"]
    produced = out.produced["stance"]
    np.testing.assert_allclose(produced[1:], request[1:], rtol=0, atol=1e-9)

    # zero moment about the foot point (or limp ankle): my + d_z fx - d_x fz = 0, d = body - foot
    d = placement(model, q, "body").translation - placement(model, q, "left_foot").translation
    fz, my = request[1], request[2]
    fx = (d[0] * fz - my) / d[2]
    assert produced[0] == pytest.approx(fx, abs=1e-9)
    assert out.solutions["stance"].free == ("x",)

    fext = external_forces(model, q, [("body", "left_foot", "world", PLANAR, produced)])
    np.testing.assert_allclose(out.tau, rnea_torques(name, q, fext), rtol=0, atol=1e-9)
    untouched = [j for j in model.names[1:] if not j.startswith("left_") or j == "left_ankle"]
    for joint in untouched:
        assert out.tau[v_index(model, joint)] == 0.0, joint


def _unilateral_controller(minimum: float, fx: float):
    rob, double = turkey_double()
    controller = Controller(rob, clip=False)
    controller.add(
        "double",
        double,
        [ConstantForce(PLANAR, [fx, 100.0, 2.0])],
        unilateral={"z": minimum},
        yield_axes=("x",),
    )
    reference = ReferenceDistribution(
        rob,
        "body",
        ["left_foot", "right_foot"],
        "world",
        PLANAR,
        "point",
        design=[va.EqualTorque("left_hip", "right_hip")],
    )
    return rob, double, controller, reference


@pytest.mark.parametrize("fx", [50.0, -60.0, 200.0])
def test_unilateral_scales_the_yield_axis_until_the_smallest_share_meets_the_minimum(fx):
    rob, double, controller, reference = _unilateral_controller(10.0, fx)
    q, v = rob.neutral(), np.zeros(rob.model.nv)
    request = np.array([fx, 100.0, 2.0])
    full = reference.solve(q, request)
    assert full[:, 1].min() < 10.0  # the request would make a foot pull
    base = reference.solve(q, np.array([0.0, 100.0, 2.0]))
    assert base[:, 1].min() > 10.0
    # z shares are linear in the scale: base + a (full - base); the largest feasible a
    slope = full[:, 1] - base[:, 1]
    alpha = min((10.0 - base[i, 1]) / slope[i] for i in range(2) if full[i, 1] < 10.0)
    out = controller.compute(q, v)
    produced = out.produced["double"]
    np.testing.assert_allclose(produced, [alpha * fx, 100.0, 2.0], rtol=0, atol=1e-9)
    forces = out.solutions["double"].forces
    assert forces[:, 1].min() == pytest.approx(10.0, abs=1e-9)
    np.testing.assert_allclose(forces, reference.solve(q, produced), rtol=0, atol=1e-9)
    np.testing.assert_allclose(out.tau, double.solve(q, produced).tau, rtol=0, atol=1e-9)
    np.testing.assert_array_equal(out.wrenches["double"], request)  # the request is reported


def test_unilateral_leaves_a_feasible_request_untouched():
    rob, double, controller, reference = _unilateral_controller(10.0, 8.0)
    q, v = rob.neutral(), np.zeros(rob.model.nv)
    request = np.array([8.0, 100.0, 2.0])
    assert reference.solve(q, request)[:, 1].min() > 10.0
    out = controller.compute(q, v)
    np.testing.assert_allclose(out.produced["double"], request, rtol=0, atol=1e-9)
    np.testing.assert_allclose(out.tau, double.solve(q, request).tau, rtol=0, atol=1e-12)


def _singular_setup(on_singular: str):
    rob, leg = single_leg(TURKEY)
    model = rob.model
    q = rob.neutral()
    q[q_index(model, "left_knee")] = 0.0  # straight knee
    controller = Controller(rob, clip=False, on_singular=on_singular)
    controller.add("stance", leg, [GrannyWalker(0.5, (1500.0, 200.0), (0, 0))], free=("x",))
    swing = va.VirtualActuator(rob, "right_foot", "body", "world", ("x", "z"))
    controller.add("swing", swing, [Spring(("x", "z"), 100.0, setpoint=(0.1, -0.4))])
    return rob, controller, q, swing


def test_singular_parallel_attachment_is_skipped_and_reported():
    rob, controller, q, swing = _singular_setup("skip")
    v = np.zeros(rob.model.nv)
    out = controller.compute(q, v)
    assert set(out.failed) == {"stance"}
    assert "singular" in out.failed["stance"]
    assert "stance" not in out.solutions and "stance" not in out.produced
    assert "failed=['stance']" in repr(out)
    position = swing.position(q)
    np.testing.assert_allclose(
        out.tau, swing.torques(q, 100.0 * (np.array([0.1, -0.4]) - position)), atol=1e-12
    )
    alone = controller.compute(q, v, active=["stance"])
    np.testing.assert_array_equal(alone.tau, np.zeros(rob.model.nv))


def test_singular_parallel_attachment_raises_by_default():
    rob, controller, q, _ = _singular_setup("raise")
    with pytest.raises(va.SingularConfigurationError):
        controller.compute(q, np.zeros(rob.model.nv))
    assert Controller(rob).on_failure == "raise"


# -- errors ------------------------------------------------------------------------------------
def test_bad_on_singular():
    with pytest.raises(va.InvalidInputError, match="on_singular"):
        Controller(robot(UR5), on_singular="ignore")


def test_duplicate_attachment_name():
    rob = robot(UR5)
    controller = Controller(rob)
    arm = va.VirtualActuator(rob, "tool0", "world", "world", AXES)
    controller.add("arm", arm, [Spring(AXES, 1.0)])
    with pytest.raises(va.InvalidInputError, match="'arm'"):
        controller.add("arm", arm, [])
    assert len(controller.attachments) == 1


def test_component_axis_not_in_actuator_axes():
    rob = robot(UR5)
    controller = Controller(rob)
    arm = va.VirtualActuator(rob, "tool0", "world", "world", ("x", "y", "z"))
    with pytest.raises(va.InvalidAxisError, match="'rz'"):
        controller.add("arm", arm, [Spring(("x", "rz"), 1.0)])
    assert "arm" not in controller.attachments


def test_free_axes_on_a_serial_actuator():
    rob = robot(UR5)
    arm = va.VirtualActuator(rob, "tool0", "world", "world", AXES)
    with pytest.raises(va.InvalidInputError, match="ParallelVirtualActuator"):
        Controller(rob).add("arm", arm, [], free=("x",))


def test_free_axis_not_in_parallel_actuator_axes():
    rob, double = turkey_double()
    with pytest.raises(va.InvalidAxisError):
        Controller(rob).add("double", double, [], free=("y",))


def test_unilateral_needs_a_parallel_actuator_and_yield_axes():
    rob, double = turkey_double()
    swing = va.VirtualActuator(rob, "left_foot", "body", "world", ("x", "z"))
    with pytest.raises(va.InvalidInputError):
        Controller(rob).add("swing", swing, [], unilateral={"z": 1.0}, yield_axes=("x",))
    with pytest.raises(va.InvalidInputError):
        Controller(rob).add("double", double, [], unilateral={"z": 1.0})
    with pytest.raises(va.InvalidInputError):
        Controller(rob).add("double", double, [], yield_axes=("x",))
    with pytest.raises(va.InvalidAxisError):
        Controller(rob).add("double", double, [], unilateral={"y": 1.0}, yield_axes=("x",))


def test_sensor_axes_must_match_actuator_axes():
    rob = robot(UR5)
    arm = va.VirtualActuator(rob, "tool0", "world", "world", ("x", "y", "z"))
    sensor = va.VirtualActuator(rob, "tool0", "world", "world", ("x", "y"))
    with pytest.raises(va.InvalidInputError, match="axes"):
        Controller(rob).add("arm", arm, [], sensor=sensor)


def test_actuator_or_sensor_from_another_robot():
    ur5, panda = robot(UR5), robot("panda")
    arm = va.VirtualActuator(ur5, "tool0", "world", "world", AXES)
    with pytest.raises(va.InvalidInputError, match="another robot"):
        Controller(panda).add("arm", arm, [])
    panda_arm = va.VirtualActuator(panda, "panda_hand", "world", "world", AXES)
    with pytest.raises(va.InvalidInputError, match="another robot"):
        Controller(panda).add("arm", panda_arm, [], sensor=arm)


def test_unknown_active_name_lists_close_matches():
    _, controller = _two_attachments()
    q, v, _ = ur5_state(80)
    with pytest.raises(va.InvalidInputError, match="'tol'") as error:
        controller.compute(q, v, active=["tol"])
    assert "'tool'" in str(error.value)
    with pytest.raises(va.InvalidInputError, match="'wrist'"):
        controller.compute(q, v, active=["tool", "wirst"])


def test_reset_of_unknown_attachment_is_invalid_input():
    rob, controller = _two_attachments()
    with pytest.raises(va.InvalidInputError, match="wrist"):
        controller.reset(["wrists"], rob.neutral(), 0.0)


class _Broken(Component):
    def __init__(self) -> None:
        super().__init__(("z",), name="broken")

    def compute_wrench(self, position, velocity, time):
        return np.array([np.nan])


def test_non_finite_component_output():
    rob = robot(UR5)
    controller = Controller(rob)
    controller.add("arm", va.VirtualActuator(rob, "tool0", "world", "world", AXES), [_Broken()])
    q, v, _ = ur5_state(81)
    with pytest.raises(va.InvalidInputError, match="non-finite"):
        controller.compute(q, v)


def test_bad_configuration_and_velocity():
    rob, controller = _two_attachments()
    q, v, _ = ur5_state(82)
    with pytest.raises(va.InvalidInputError):
        controller.compute(q[:-1], v)
    with pytest.raises(va.InvalidInputError):
        controller.compute(q, np.full(6, np.nan))


# -- reset hooks and reports --------------------------------------------------------------------
def test_reset_puts_the_bunny_at_the_body():
    rob, double = turkey_double()
    bunny = DogtrackBunny(speed=0.5, damping=80.0)
    controller = Controller(rob)
    controller.add("double", double, [GrannyWalker(0.5, (1.0, 1.0), (1.0, 1.0)), bunny])
    q = rob.neutral()
    q[q_index(rob.model, "boom_x")] = 1.7
    controller.reset(["double"], q, 2.5)
    assert bunny.start_position == pytest.approx(1.7, abs=1e-12)
    assert bunny.start_time == 2.5


def test_reprs():
    rob, controller = _two_attachments()
    text = repr(controller)
    assert "ur5" in text and "'tool'" in text and "'wrist'" in text
    assert "Attachment('tool', VirtualActuator on 'tool0'" in repr(controller.attachments["tool"])
    q, v, _ = ur5_state(90)
    assert repr(controller.compute(q, v)).startswith("ControlOutput(active=('tool', 'wrist')")


# -- the virtual sensor -------------------------------------------------------------------------
@pytest.mark.parametrize(
    ("name", "action", "reaction", "reference", "axes"),
    [
        (UR5, "tool0", "world", "world", AXES),
        (UR5, "tool0", "shoulder_link", "wrist_1_link", ("x", "z", "ry", "rz")),
        (TURKEY, "left_foot", "body", "world", ("x", "z")),
        ("solo12", "base_link", "FL_FOOT", "world", ("x", "y", "z")),
        ("solo12", "FR_FOOT", "world", "base_link", AXES),
    ],
)
def test_read_equals_position_velocity_jacobian(name, action, reaction, reference, axes):
    rob = robot(name)
    actuator = va.VirtualActuator(rob, action, reaction, reference, axes)
    rng = np.random.default_rng(5)
    for _ in range(3):
        q = random_configuration(rob, rng)
        v = rng.uniform(-1.0, 1.0, rob.model.nv)
        reading = actuator.read(q, v)
        np.testing.assert_allclose(reading.position, actuator.position(q), rtol=0, atol=1e-14)
        np.testing.assert_allclose(reading.velocity, actuator.velocity(q, v), rtol=0, atol=1e-13)
        np.testing.assert_allclose(reading.jacobian, actuator.jacobian(q), rtol=0, atol=1e-14)
        assert reading.jacobian.shape == (len(axes), rob.model.nv)
    assert repr(reading).startswith("ActuatorReading(position=")


def test_read_validates_inputs():
    rob = robot(UR5)
    actuator = va.VirtualActuator(rob, "tool0", "world", "world", AXES)
    with pytest.raises(va.InvalidInputError):
        actuator.read(np.zeros(5), np.zeros(6))
    with pytest.raises(va.InvalidInputError):
        actuator.read(np.zeros(6), np.zeros(7))


def test_repeated_active_name_is_rejected():
    robot = va.load_robot("ur5_robot")
    controller = va.Controller(robot)
    actuator = va.VirtualActuator(robot, "tool0", "world", "world", ("x", "y", "z"))
    controller.add("tool", actuator, [va.Spring(("x", "y", "z"), 10.0)])
    q, v = robot.neutral(), np.zeros(robot.model.nv)
    with pytest.raises(va.InvalidInputError, match="twice"):
        controller.compute(q, v, active=["tool", "tool"])


def _flamingo_cone(mu: float, min_normal: float, fx: float, tilt: float, normals=None):
    """Flamingo double support (limp ankles, flat feet) with both soles pitched by ``tilt``."""
    rob = robot(FLAMINGO)
    ankles = ["left_ankle", "right_ankle"]
    double = va.ParallelVirtualActuator(
        rob, "body", ["left_foot", "right_foot"], "world", PLANAR, contact="flat",
        unactuated=ankles, normals=normals,
    )  # fmt: skip
    controller = Controller(rob, clip=False)
    controller.add(
        "double",
        double,
        [ConstantForce(PLANAR, [fx, 110.0, 1.0])],
        yield_axes=("x",),
        friction=mu,
        min_normal=min_normal,
    )
    q = rob.neutral()
    for ankle in ankles:
        q[q_index(rob.model, ankle)] += tilt
    reference = ReferenceDistribution(
        rob, "body", ["left_foot", "right_foot"], "world", PLANAR, "flat", unactuated=ankles
    )
    return rob, controller, reference, q


def _cone_margins(model, q, forces, mu, min_normal, frames=False) -> np.ndarray:
    """Normal minus its minimum, and mu * normal -+ tangential, per foot.

    About world z (tangent world x) by default; about the soles' axes from their FK with
    ``frames`` (the actuator's ``normals="frames"``).
    """
    margins = []
    for chain, foot in enumerate(("left_foot", "right_foot")):
        rotation = placement(model, q, foot).rotation if frames else np.eye(3)
        force_world = np.array([forces[chain, 0], 0.0, forces[chain, 1]])
        normal, tangent = rotation[:, 2] @ force_world, rotation[:, 0] @ force_world
        margins += [normal - min_normal, mu * normal - tangent, mu * normal + tangent]
    return np.array(margins)


@pytest.mark.parametrize("normals", [None, "frames"])
@pytest.mark.parametrize(("fx", "tilt"), [(80.0, 0.0), (-90.0, 0.0), (60.0, 0.25), (-50.0, -0.3)])
def test_friction_cone_scales_the_yield_axis_to_the_largest_feasible_request(fx, tilt, normals):
    mu, min_normal = 0.4, 10.0
    rob, controller, reference, q = _flamingo_cone(mu, min_normal, fx, tilt, normals)
    frames = normals == "frames"

    def margins_of(forces):
        return _cone_margins(rob.model, q, forces, mu, min_normal, frames)

    request = np.array([fx, 110.0, 1.0])
    assert margins_of(reference.solve(q, request)).min() < 0.0
    base = np.array([0.0, 110.0, 1.0])
    assert margins_of(reference.solve(q, base)).min() > 0.0

    def feasible(alpha: float) -> bool:
        forces = reference.solve(q, np.array([alpha * fx, 110.0, 1.0]))
        return margins_of(forces).min() >= -1e-12

    low, high = 0.0, 1.0  # bisection on the independent distribution (a convex set of alphas)
    for _ in range(60):
        middle = 0.5 * (low + high)
        low, high = (middle, high) if feasible(middle) else (low, middle)
    out = controller.compute(q, np.zeros(rob.model.nv))
    produced = out.produced["double"]
    assert produced[0] == pytest.approx(low * fx, abs=1e-8)
    np.testing.assert_allclose(produced[1:], [110.0, 1.0], rtol=0, atol=1e-9)
    margins = margins_of(out.solutions["double"].forces)
    assert margins.min() == pytest.approx(0.0, abs=1e-8)  # one condition is active


def test_friction_cone_leaves_a_feasible_request_untouched():
    rob, controller, reference, q = _flamingo_cone(0.8, 5.0, 3.0, 0.1)
    out = controller.compute(q, np.zeros(rob.model.nv))
    np.testing.assert_allclose(out.produced["double"], [3.0, 110.0, 1.0], rtol=0, atol=1e-9)


def test_friction_cone_arguments_are_checked():
    rob, double = turkey_double()
    for mu in (0.0, -1.0, float("nan"), float("inf")):
        with pytest.raises(va.InvalidInputError, match="friction"):
            Controller(rob).add("double", double, [], friction=mu, yield_axes=("x",))
    with pytest.raises(va.InvalidInputError, match="min_normal"):
        Controller(rob).add("double", double, [], friction=0.5, min_normal=-1.0, yield_axes=("x",))
    with pytest.raises(va.InvalidInputError, match="yield_axes"):
        Controller(rob).add("double", double, [], friction=0.5)
