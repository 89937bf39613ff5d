"""The QP distribution at scale: both matrix paths, many random cases, warm starts, threads.

Oracles: Pinocchio (frame placements for the cones and soles, RNEA with external forces for the
torques), the partitioned minimum-norm solve (a different method: a KKT system, no QP), and the
numpy path of the QP itself (all force entries, natural rows as equalities) for the compiled path
(free coordinates, natural rows eliminated). Seeded numpy draws; a few seconds in all.
"""

from __future__ import annotations

import threading

import numpy as np
import pinocchio as pin
import pytest
from oracles import external_forces, requires_core, rnea_torques, zero_gravity_model
from test_qp import HEX_FEET, SOLO_FEET, TOL, _check_cone, _check_torques, _q, _weight

import virtual_actuators as va
from virtual_actuators.distribution.methods import Request

ALL_HEX_FEET = [f"foot_{i}" for i in range(1, 7)]
SOLES = {"left_sole_link": (0.1, 0.05), "right_sole_link": (0.1, 0.05)}


def _body(name: str, soles: bool = True, **kwargs) -> va.ParallelVirtualActuator:
    robot = va.load_robot(name)
    if name == "talos_reduced":
        return va.ParallelVirtualActuator(
            robot, "base_link", list(SOLES), "world", contact="flat",
            soles=SOLES if soles else None, **kwargs,
        )  # fmt: skip
    feet = SOLO_FEET if name == "solo12" else ALL_HEX_FEET
    action = "base_link" if name == "solo12" else "body"
    return va.ParallelVirtualActuator(robot, action, feet, "world", **kwargs)


def _numpy_request(keep: np.ndarray) -> Request:
    """The QP on its numpy path (the reference of the compiled one), every axis as given."""
    return Request("qp", (), keep, compiled=False)


def _request(robot: va.Robot, rng: np.random.Generator, spread: float) -> np.ndarray:
    weight = _weight(robot)
    return np.concatenate(
        (rng.normal(size=2) * weight * spread, [weight * rng.uniform(0.5, 1.5)],
         rng.normal(size=3) * weight * spread * 0.05)
    )  # fmt: skip


def _check_soles(body, q, sol, mu) -> None:
    """Centre of pressure inside each half-sole, yaw moment within mu min(half sizes) f_n."""
    model = body.robot.model
    data = model.createData()
    pin.framesForwardKinematics(model, data, q)
    p_b = data.oMf[model.getFrameId(body.action)].translation
    slack = TOL * max(np.abs(sol.forces).max(), 1.0)
    for name, wrench_i in zip(body.reactions, sol.forces, strict=True):
        half_length, half_width = SOLES[name]
        placement = data.oMf[model.getFrameId(name)]
        local_m = placement.rotation.T @ (wrench_i[3:] + np.cross(p_b - placement.translation,
                                                                  wrench_i[:3]))  # fmt: skip
        f_n = (placement.rotation.T @ wrench_i[:3])[2]
        assert abs(local_m[0]) <= half_width * f_n + slack
        assert abs(local_m[1]) <= half_length * f_n + slack
        assert abs(local_m[2]) <= mu * min(half_length, half_width) * f_n + slack


def _check_paths(body, q, wrench, sol) -> None:
    """The compiled path's answer against the numpy path's (a different formulation).

    A feasible request: the same forces to 1e-9 of the request (both end with the exact step
    on the active set, :mod:`virtual_actuators.distribution.qp.exact`). An infeasible one: the
    same closest wrench, residual and forces to 1e-8 of the request.
    """
    keep = np.ones(body.n, dtype=bool)
    tick = body.qp.solve(body.kinematics.snapshot(q), wrench, _numpy_request(keep))
    scale = max(np.abs(wrench).max(), 1.0)
    if sol.residual <= 1e-9 * scale:
        np.testing.assert_allclose(sol.forces, tick.raw.forces, rtol=0, atol=1e-9 * scale)
    else:
        _check_same_closest(sol, tick.raw.forces, tick.produced, tick.residual, scale)


def _check_same_closest(sol, forces, produced, residual, scale) -> None:
    """Two answers to one infeasible request: the same closest wrench and forces (1e-8)."""
    assert abs(sol.residual - residual) <= 1e-8 * scale
    np.testing.assert_allclose(sol.wrench, produced, rtol=0, atol=1e-8 * scale)
    np.testing.assert_allclose(sol.forces, forces, rtol=0, atol=1e-8 * scale)


CASES = [  # robot, friction, least normal force, torque limit on the actuated joints, cases
    ("solo12", 0.5, 1.0, 2.0, 200),
    ("hexapod", 0.6, 0.5, 1.2, 200),
    ("talos_reduced", 0.7, 20.0, 150.0, 100),
]


@requires_core
@pytest.mark.parametrize(("name", "mu", "min_normal", "limit", "count"), CASES)
def test_inequalities_hold_and_both_paths_agree(name, mu, min_normal, limit, count):
    """Hundreds of random requests pressing on cones, least normal forces and torque limits:
    every answer meets them to 1e-8 (Pinocchio oracle), its torques are the RNEA of its forces,
    and the compiled path (free coordinates) gives the numpy path's answer (all entries)."""
    robot = va.load_robot(name)
    limits = np.full(robot.model.nv, np.inf)
    limits[6:] = limit
    body = _body(name, friction=mu, min_normal=min_normal, torque_limits=limits)
    assert body.qp.matrices.applicable
    rng = np.random.default_rng(len(name))
    keep = np.ones(body.n, dtype=bool)
    solved = active = 0
    for _ in range(count):
        q = _q(robot, rng, scale=0.05 if name == "talos_reduced" else 0.25)
        wrench = _request(robot, rng, 0.4)
        try:
            sol = body.solve(q, wrench, method="qp")
        except va.ConstraintError as error:  # the least normal force and the limits clash
            assert "torque" in str(error)
            with pytest.raises(va.ConstraintError):
                body.qp.solve(body.kinematics.snapshot(q), wrench, _numpy_request(keep))
            continue
        solved += 1
        active += bool(sol.active)
        _check_cone(body, q, sol, mu, min_normal)
        if name == "talos_reduced":
            _check_soles(body, q, sol, mu)
        tau_scale = max(np.abs(sol.tau).max(), 1.0)
        assert np.all(np.abs(sol.tau) <= limits + TOL * tau_scale)
        _check_torques(name, body, q, sol)
        _check_paths(body, q, wrench, sol)
    assert solved >= 0.8 * count and active >= 0.2 * count  # the requests do press


@pytest.mark.parametrize(("name", "spread"), [("solo12", 0.05), ("hexapod", 0.05),
                                              ("talos_reduced", 0.01)])  # fmt: skip
def test_qp_is_the_minimum_norm_answer_when_nothing_is_active(name, spread):
    """With no active inequality, the QP's answer is the partitioned minimum-norm one (talos
    without soles: the least-norm answer loads the soles' roll moments beyond a real sole)."""
    robot = va.load_robot(name)
    body = _body(name, soles=False, friction=1.0)
    rng = np.random.default_rng(5)
    checked = 0
    for _ in range(150):
        q = _q(robot, rng, scale=0.05 if name == "talos_reduced" else 0.25)
        wrench = _request(robot, rng, spread)
        qp = body.solve(q, wrench, method="qp")
        if qp.active:
            continue
        ref = body.solve(q, wrench)
        assert ref.method in ("pseudo-inverse", "partitioned")
        scale = np.abs(ref.forces).max()
        np.testing.assert_allclose(qp.forces, ref.forces, rtol=0, atol=TOL * scale)
        tau_scale = max(np.abs(ref.tau).max(), 1.0)
        np.testing.assert_allclose(qp.tau, ref.tau, rtol=0, atol=TOL * tau_scale)
        checked += 1
    assert checked >= 100


def test_passive_springs_and_limp_joints_with_the_qp():
    """A spring at one ankle and a limp joint at the other (talos on its soles): the torques at
    those joints are the spring's and zero (RNEA of the chain forces), the cones and soles
    hold, and both paths agree."""
    robot = va.load_robot("talos_reduced")
    body = _body(
        "talos_reduced", friction=0.7, min_normal=10.0, unactuated=["leg_left_6_joint"],
        passive={"leg_right_6_joint": (40.0, 0.05)},
    )  # fmt: skip
    model = robot.model
    spring_v = model.joints[model.getJointId("leg_right_6_joint")].idx_v
    spring_q = model.joints[model.getJointId("leg_right_6_joint")].idx_q
    limp_v = model.joints[model.getJointId("leg_left_6_joint")].idx_v
    model_0g = zero_gravity_model("talos_reduced")
    rng = np.random.default_rng(11)
    for _ in range(60):
        q = _q(robot, rng, scale=0.05)
        wrench = _request(robot, rng, 0.01)
        sol = body.solve(q, wrench, method="qp")
        _check_cone(body, q, sol, 0.7, 10.0)
        _check_soles(body, q, sol, 0.7)
        pairs = [(body.action, r, body.reference, body.axes, f)
                 for r, f in zip(body.reactions, sol.forces, strict=True)]  # fmt: skip
        tau = rnea_torques(model_0g, q, external_forces(model_0g, q, pairs))
        tau_scale = max(np.abs(tau).max(), 1.0)
        mask = body.problem.actuated_mask
        np.testing.assert_allclose(sol.tau[mask], tau[mask], rtol=0, atol=TOL * tau_scale)
        spring = -40.0 * (q[spring_q] - 0.05)
        assert sol.tau_passive[spring_v] == pytest.approx(spring, rel=1e-12)
        assert tau[spring_v] == pytest.approx(spring, abs=TOL * tau_scale)  # J^T F = spring
        assert abs(tau[limp_v]) <= TOL * tau_scale  # J^T F = 0 at the limp joint
        _check_paths(body, q, wrench, sol)


def test_warm_start_gives_the_cold_start_answer():
    """Ticks warm-started from each other against the same ticks from fresh workspaces."""
    robot = va.load_robot("solo12")
    warm = _body("solo12", friction=0.5, min_normal=1.0, torque_limits=True)
    cold = _body("solo12", friction=0.5, min_normal=1.0, torque_limits=True)
    rng = np.random.default_rng(2)
    base_q = _q(robot, rng)
    exact = closest = 0
    for _ in range(100):
        q = pin.integrate(robot.model, base_q, np.r_[np.zeros(6), rng.normal(size=12) * 0.01])
        wrench = _request(robot, rng, 0.2)
        hot = warm.solve(q, wrench, method="qp")
        cold.qp.reset()  # drop this thread's ProxQP workspaces: a cold start
        fresh = cold.solve(q, wrench, method="qp")
        scale = max(np.abs(wrench).max(), 1.0)
        if fresh.residual <= 1e-9 * scale:
            np.testing.assert_allclose(hot.forces, fresh.forces, rtol=0, atol=1e-9 * scale)
            exact += 1
        else:
            _check_same_closest(hot, fresh.forces, fresh.wrench, fresh.residual, scale)
            closest += 1
    assert exact >= 50 and closest >= 10


def test_a_walk_of_nearby_ticks_reuses_the_active_set_without_proxqp():
    """Slowly changing ticks (some with a friction face active): after the first, ProxQP does
    not run (no iteration used) and every answer is the cold start's."""
    robot = va.load_robot("solo12")
    warm = _body("solo12", friction=0.5, min_normal=1.0, torque_limits=True)
    cold = _body("solo12", friction=0.5, min_normal=1.0, torque_limits=True)
    rng = np.random.default_rng(7)
    q, weight = _q(robot, rng), _weight(robot)
    wrench = np.array([0.45 * weight, 0.1 * weight, weight, 0.0, 0.0, 0.02 * weight])
    skipped = held = 0
    for tick in range(60):
        q = pin.integrate(robot.model, q, np.r_[np.zeros(6), rng.normal(size=12) * 1e-3])
        wrench = wrench + rng.normal(size=6) * 1e-3 * weight
        hot = warm.solve(q, wrench, method="qp")
        cold.qp.reset()
        fresh = cold.solve(q, wrench, method="qp")
        assert fresh.residual <= 1e-9 * weight  # feasible: the request exactly
        np.testing.assert_allclose(hot.forces, fresh.forces, rtol=0, atol=1e-9 * weight)
        assert hot.active == fresh.active
        skipped += tick > 0 and warm.qp.iterations == 0
        held += tick > 0 and warm.qp.iterations == 0 and bool(hot.active)
    assert skipped >= 55 and held >= 10


def test_the_qp_from_two_threads_at_once():
    """Two threads solving different ticks on one actuator get the single-thread answers."""
    robot = va.load_robot("hexapod")
    body = _body("hexapod", friction=0.6, min_normal=0.5, torque_limits=True)
    rng = np.random.default_rng(4)
    ticks = [(_q(robot, rng), _request(robot, rng, 0.3)) for _ in range(200)]
    expected = [body.solve(q, w, method="qp") for q, w in ticks]
    weight = _weight(robot)
    results: dict[int, list] = {0: [], 1: []}
    errors: list[BaseException] = []
    barrier = threading.Barrier(2)

    def run(worker: int) -> None:
        try:
            barrier.wait()
            for _ in range(3):
                for q, w in ticks[worker::2]:
                    results[worker].append(body.solve(q, w, method="qp"))
        except BaseException as error:  # noqa: BLE001 - reported by the main thread
            errors.append(error)

    threads = [threading.Thread(target=run, args=(k,)) for k in range(2)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    assert not errors
    for worker in range(2):
        mine = expected[worker::2] * 3
        assert len(results[worker]) == len(mine)
        for got, want in zip(results[worker], mine, strict=True):
            assert got.method == "qp"
            if want.residual <= 1e-9 * weight:
                np.testing.assert_allclose(got.forces, want.forces, rtol=0, atol=1e-9 * weight)
            else:
                _check_same_closest(got, want.forces, want.wrench, want.residual, weight)


def test_the_numpy_path_takes_declarations_the_kernel_does_not():
    """A joint shared by every chain (talos's limp waist under a torso action frame) makes a
    coupling row that depends on q: the kernel does not apply, numpy builds every tick, and the
    answer meets the coupling row (zero waist torque, RNEA oracle) and the cones."""
    robot = va.load_robot("talos_reduced")
    body = va.ParallelVirtualActuator(
        robot, "torso_2_link", list(SOLES), "world", contact="flat", friction=0.7,
        min_normal=10.0, unactuated=["torso_1_joint"],
    )  # fmt: skip
    assert not body.qp.matrices.applicable and body.problem.coupled_v
    rng = np.random.default_rng(8)
    for _ in range(20):
        q = _q(robot, rng, scale=0.05)
        wrench = _request(robot, rng, 0.01)
        sol = body.solve(q, wrench, method="qp")
        _check_cone(body, q, sol, 0.7, 10.0)
        _check_torques("talos_reduced", body, q, sol)
    assert HEX_FEET[0] == "foot_1"
