"""The contact-aware distribution (``method="qp"``) on real robots.

Properties: with no inequality active the QP answer is the partitioned minimum-norm one (the
equality-only problem has one least-norm answer); every declared inequality (friction pyramid,
least normal force, centre of pressure in the sole, torque limit) holds to 1e-8 at every answer;
the equalities (limp joints, point feet) hold and the torques are the RNEA of the chain forces;
the scaling rule of ``Controller.add(yield_axes=...)`` gives up force that the QP keeps.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
from oracles import chain_forces_world, external_forces, rnea_torques, zero_gravity_model

import virtual_actuators as va

SOLO_FEET = ["FL_FOOT", "FR_FOOT", "HL_FOOT", "HR_FOOT"]
HEX_FEET = ["foot_1", "foot_3", "foot_5", "foot_2"]
TOL = 1e-8


def _q(robot: va.Robot, rng: np.random.Generator, scale: float = 0.25) -> np.ndarray:
    model = robot.model
    step = rng.uniform(-scale, scale, model.nv)
    step[:6] = 0.0  # the body level: world z is the ground's normal
    return pin.integrate(model, robot.neutral(), step)


def _weight(robot: va.Robot) -> float:
    return pin.computeTotalMass(robot.model) * 9.81


def _check_cone(body, q, sol, mu, min_normal) -> None:
    """Each chain's force against the pyramid about world z (expressed in {O})."""
    force_world = chain_forces_world(body, q, sol.forces)  # rows: R_O f
    scale = max(np.abs(sol.forces).max(), 1.0)
    normal = force_world[:, 2]
    assert np.all(normal >= min_normal - TOL * scale), normal
    assert np.all(np.abs(force_world[:, 0]) <= mu * normal + TOL * scale)
    assert np.all(np.abs(force_world[:, 1]) <= mu * normal + TOL * scale)


def _check_torques(name, body, q, sol) -> None:
    model = zero_gravity_model(name)
    pairs = [
        (body.action, r, body.reference, body.axes, f)
        for r, f in zip(body.reactions, sol.forces, strict=True)
    ]
    tau = rnea_torques(model, q, external_forces(model, q, pairs))
    mask = body.problem.actuated_mask
    scale = max(np.abs(tau).max(), 1.0)
    np.testing.assert_allclose(sol.tau[mask], tau[mask], rtol=0, atol=TOL * scale)
    np.testing.assert_allclose(tau[~mask], 0.0, rtol=0, atol=TOL * scale)  # limp: J^T F = 0


def test_qp_equals_partitioned_minimum_norm_when_nothing_is_active():
    robot = va.load_robot("solo12")
    body = va.ParallelVirtualActuator(robot, "base_link", SOLO_FEET, "world", friction=1.0)
    rng = np.random.default_rng(14)
    weight, checked = _weight(robot), 0
    for _ in range(60):
        q = _q(robot, rng)
        wrench = np.concatenate(([0.0, 0.0, weight], rng.normal(size=3) * 0.2))
        wrench[:2] = rng.normal(size=2) * 0.5
        qp = body.solve(q, wrench, method="qp")
        if qp.active:
            continue
        ref = body.solve(q, wrench)
        scale = np.abs(ref.forces).max()
        np.testing.assert_allclose(qp.forces, ref.forces, rtol=0, atol=TOL * scale)
        np.testing.assert_allclose(
            qp.tau, ref.tau, rtol=0, atol=TOL * max(np.abs(ref.tau).max(), 1)
        )
        assert qp.method == "qp" and qp.solver == "qp" and qp.residual <= TOL * weight
        checked += 1
    assert checked >= 40


@pytest.mark.parametrize(
    ("name", "action", "feet", "mu"),
    [("solo12", "base_link", SOLO_FEET, 0.4), ("hexapod", "body", HEX_FEET, 0.5)],
)
def test_cones_and_torque_limits_hold_on_random_requests(name, action, feet, mu):
    robot = va.load_robot(name)
    limits = np.full(robot.model.nv, np.inf)
    limits[6:] = 0.6 if name == "hexapod" else 1.5
    body = va.ParallelVirtualActuator(
        robot, action, feet, "world", friction=mu, min_normal=0.5, torque_limits=limits
    )
    rng = np.random.default_rng(7)
    weight, active, refused = _weight(robot), 0, 0
    for _ in range(80):
        q = _q(robot, rng)
        wrench = np.concatenate(
            (rng.normal(size=2) * weight * 0.5, [weight * rng.uniform(0.5, 1.5)],
             rng.normal(size=3) * 0.5)
        )  # fmt: skip
        try:
            sol = body.solve(q, wrench, method="qp")
        except va.ConstraintError as error:  # min_normal and the limits cannot both hold
            assert "torque" in str(error)
            refused += 1
            continue
        _check_cone(body, q, sol, mu, 0.5)
        scale = max(np.abs(sol.tau).max(), 1.0)
        assert np.all(np.abs(sol.tau) <= limits + TOL * scale)
        _check_torques(name, body, q, sol)
        np.testing.assert_allclose(sol.residual, np.linalg.norm(sol.wrench - wrench), atol=1e-9)
        active += bool(sol.active)
    assert active >= 20  # the requests do press on the limits
    assert refused <= 8


def test_infeasible_request_degrades_to_the_closest_feasible_one():
    robot = va.load_robot("solo12")
    body = va.ParallelVirtualActuator(robot, "base_link", SOLO_FEET, "world", friction=0.6)
    q = robot.neutral()
    weight = _weight(robot)
    wrench = np.array([weight, 0.0, weight, 0.0, 0.0, 0.0])  # |f_x| = f_z > mu f_z
    sol = body.solve(q, wrench, method="qp")
    assert sol.method == "qp" and sol.residual > 0.1 * weight
    assert any("friction" in name for name in sol.active)
    assert sol.wrench[0] == pytest.approx(0.6 * sol.wrench[2], rel=1e-6)  # the cone's edge
    with pytest.raises(va.InadmissibleWrenchError):
        body.solve(q, wrench, method="qp", strict=True)


def test_limp_joints_and_flat_soles_with_the_qp():
    """talos on its soles, a limp arm joint off the chains' way: the centre of pressure stays in
    the 0.1 x 0.05 m half-sole and the yaw moment within mu min(half sizes) f_n."""
    robot = va.load_robot("talos_reduced")
    soles = {"left_sole_link": (0.1, 0.05), "right_sole_link": (0.1, 0.05)}
    body = va.ParallelVirtualActuator(
        robot, "base_link", list(soles), "world", contact="flat", friction=0.7,
        min_normal=5.0, soles=soles, unactuated=["leg_left_6_joint"],
    )  # fmt: skip
    model = robot.model
    data = model.createData()
    rng = np.random.default_rng(3)
    weight = _weight(robot)
    for _ in range(30):
        q = _q(robot, rng, scale=0.05)
        wrench = np.concatenate(([0, 0, weight], rng.normal(size=3) * 40.0))
        sol = body.solve(q, wrench, method="qp")
        _check_cone(body, q, sol, 0.7, 5.0)
        _check_torques("talos_reduced", body, q, sol)
        pin.framesForwardKinematics(model, data, q)
        p_b = data.oMf[model.getFrameId("base_link")].translation
        for (name, (half_length, half_width)), wrench_i in zip(
            soles.items(), sol.forces, strict=True
        ):
            placement = data.oMf[model.getFrameId(name)]
            moment_a = wrench_i[3:] + np.cross(p_b - placement.translation, wrench_i[:3])
            local_m = placement.rotation.T @ moment_a
            f_n = (placement.rotation.T @ wrench_i[:3])[2]
            slack = TOL * max(np.abs(sol.forces).max(), 1.0)
            assert abs(local_m[0]) <= half_width * f_n + slack
            assert abs(local_m[1]) <= half_length * f_n + slack
            assert abs(local_m[2]) <= 0.7 * half_width * f_n + slack


def test_the_qp_keeps_force_that_the_scaling_rule_gives_up():
    """Controller.add(unilateral=..., yield_axes=...) scales the whole request on the yield
    axes until every foot pushes; the QP moves the load between feet and keeps all of it."""
    robot = va.load_robot("solo12")
    q = robot.neutral()
    weight = _weight(robot)
    minimum = 5.0  # [N] every foot keeps pushing at least this much
    body = va.ParallelVirtualActuator(robot, "base_link", SOLO_FEET, "world", min_normal=minimum)
    wrench = np.array([0.0, 0.0, weight, 0.5, 0.7, 0.0])  # roll and pitch unload the front right
    controller = va.Controller(robot, clip=False)
    controller.add("body", body, [va.ConstantForce(body.axes, wrench)],
                   unilateral={"z": minimum}, yield_axes=("rx", "ry"))  # fmt: skip
    scaled = controller.compute(q, np.zeros(robot.model.nv)).produced["body"]
    sol = body.solve(q, wrench, method="qp")
    assert scaled[4] < 0.99 * wrench[4]  # the scaling rule gave up moment
    assert sol.residual <= 1e-6 * weight  # the QP produced all of it
    assert np.all(sol.forces[:, 2] >= minimum - 1e-8 * weight)  # every foot still pushes


def test_bad_qp_arguments_are_typed_errors():
    robot = va.load_robot("solo12")
    make = lambda **kw: va.ParallelVirtualActuator(robot, "base_link", SOLO_FEET, **kw)  # noqa: E731
    for kwargs, match in (
        ({"friction": -1.0}, "friction"),
        ({"friction": "a"}, "friction"),
        ({"min_normal": -1.0}, "min_normal"),
        ({"torque_limits": np.ones(3)}, "torque_limits"),
        ({"normals": {"FL_FOOT": (0, 0, 0)}}, "normals"),
        ({"normals": {"nope": (0, 0, 1)}}, "nope"),
        ({"soles": {"FL_FOOT": (0.1, 0.05)}}, "point contact"),
    ):
        with pytest.raises(va.VirtualActuatorError, match=match):
            make(**kwargs)
    body = make()
    with pytest.raises(va.InvalidInputError, match="qp"):
        body.solve(robot.neutral(), np.zeros(6), method="quadratic")


def test_controller_attachment_with_the_qp():
    robot = va.load_robot("solo12")
    q, v = robot.neutral(), np.zeros(robot.model.nv)
    weight = _weight(robot)
    body = va.ParallelVirtualActuator(
        robot, "base_link", SOLO_FEET, "world", friction=0.6, min_normal=1.0
    )
    wrench = np.array([weight, 0.0, weight, 0.0, 0.0, 0.0])
    controller = va.Controller(robot, clip=False)
    controller.add("body", body, [va.ConstantForce(body.axes, wrench)], method="qp")
    out = controller.compute(q, v)
    sol = out.solutions["body"]
    assert sol.method == "qp" and any("friction" in a for a in sol.active)
    np.testing.assert_allclose(out.tau, sol.tau)
    np.testing.assert_allclose(out.produced["body"], sol.wrench)
    with pytest.raises(va.InvalidInputError, match="method"):
        controller.add("other", body, method="simplex")
    with pytest.raises(va.InvalidInputError, match="unilateral"):
        controller.add("limits", body, method="qp", unilateral={"z": 0.0}, yield_axes=("z",))


def test_every_method_reports_the_three_sets():
    # API: sol.sets is {"MFS": [...], "RFS": [...], "CFS": [...]}; empty for the QP and dense
    robot = va.load_robot("solo12")
    body = va.ParallelVirtualActuator(robot, "base_link", SOLO_FEET, "world", friction=0.6)
    wrench = np.array([0.0, 0.0, _weight(robot), 0.0, 0.0, 0.0])
    for method in ("qp", "dense"):
        sets = body.solve(robot.neutral(), wrench, method=method).sets
        assert sets == {"MFS": [], "RFS": [], "CFS": []}, method
    assert set(body.solve(robot.neutral(), wrench).sets) == {"MFS", "RFS", "CFS"}
