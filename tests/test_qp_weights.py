"""Per-axis weights of the QP's closest wrench: which axes give way when a request cannot be met.

The flamingo in double support (flat feet, limp ankles, friction 0.6, every foot pushing at
least 10 N) asked for more forward force than its feet can give. Oracle: the lexicographic
answer (z and pitch kept exactly, the most forward force that allows) by enumerating the
vertices of the feasible polygon, a linear program written with Pinocchio (RNEA with external
forces for the limp ankles) and numpy only. A small weight on x must approach it, by about the
weight; equal weights give up z and pitch too.
"""

from __future__ import annotations

import itertools

import numpy as np
import pinocchio as pin
import pytest
from oracles import external_forces, rnea_torques, zero_gravity_model

import virtual_actuators as va

FEET = ["left_foot", "right_foot"]
AXES = ("x", "z", "ry")
MU, MIN_NORMAL = 0.6, 10.0  # [-], [N]


def _body(**kwargs) -> va.ParallelVirtualActuator:
    return va.ParallelVirtualActuator(
        va.load_robot("spring_flamingo"), "body", FEET, "world", axes=AXES, contact="flat",
        unactuated=["left_ankle", "right_ankle"], friction=MU, min_normal=MIN_NORMAL, **kwargs,
    )  # fmt: skip


def _ankle_rows(q: np.ndarray) -> np.ndarray:
    """``(2, 6)``: the limp ankles' torques over ``(F_left, F_right)`` (RNEA, unit forces)."""
    model = zero_gravity_model("spring_flamingo")
    ankles = [model.joints[model.getJointId(f"{side}_ankle")].idx_v for side in ("left", "right")]
    rows = np.zeros((2, 6))
    for column in range(6):
        forces = np.zeros((2, 3))
        forces[divmod(column, 3)] = 1.0
        pairs = [("body", foot, "world", AXES, f) for foot, f in zip(FEET, forces, strict=True)]
        rows[:, column] = rnea_torques(model, q, external_forces(model, q, pairs))[ankles]
    return rows


def _most_forward_force(q: np.ndarray, fz: float, fry: float) -> float:
    """The largest total x force with z and pitch exactly ``fz``, ``fry`` (vertex enumeration).

    Unknowns ``(f_x, f_z, m_y)`` per foot; equalities: limp ankles, total z, total pitch;
    inequalities: ``f_z >= MIN_NORMAL`` and ``|f_x| <= MU f_z`` per foot.
    """
    equality = np.vstack((_ankle_rows(q), [[0, 1, 0, 0, 1, 0], [0, 0, 1, 0, 0, 1]]))
    equality_rhs = np.array([0.0, 0.0, fz, fry])
    inequality, lows = [], []  # rows @ u >= low
    for foot in range(2):
        fx, fz_row = np.eye(6)[3 * foot], np.eye(6)[3 * foot + 1]
        inequality += [fz_row, MU * fz_row - fx, MU * fz_row + fx]
        lows += [MIN_NORMAL, 0.0, 0.0]
    inequality, lows = np.array(inequality), np.array(lows)
    best = -np.inf
    for pair in itertools.combinations(range(len(lows)), 2):
        system = np.vstack((equality, inequality[list(pair)]))
        if abs(np.linalg.det(system)) < 1e-9:
            continue
        u = np.linalg.solve(system, np.concatenate((equality_rhs, lows[list(pair)])))
        if np.all(inequality @ u >= lows - 1e-9):
            best = max(best, u[0] + u[3])
    assert np.isfinite(best)
    return best


def _check_feasible(q: np.ndarray, sol: va.Solution) -> None:
    scale = max(np.abs(sol.forces).max(), 1.0)
    fx, fz = sol.forces[:, 0], sol.forces[:, 1]
    assert np.all(fz >= MIN_NORMAL - 1e-8 * scale)
    assert np.all(np.abs(fx) <= MU * fz + 1e-8 * scale)
    np.testing.assert_allclose(_ankle_rows(q) @ sol.forces.ravel(), 0.0, atol=1e-8 * scale)


def _requests(robot: va.Robot) -> list[np.ndarray]:
    weight = pin.computeTotalMass(robot.model) * 9.81
    pairs = ((0.3, 0.0), (0.8, 0.0), (0.5, 5.0), (0.6, -4.0))  # (x / weight, pitch [N m])
    return [np.array([fx * weight, weight, fry]) for fx, fry in pairs]


@pytest.mark.parametrize("weight", [1e-3, 1e-6])
def test_a_small_weight_on_x_gives_up_x_first(weight):
    """x weighted ``weight``: z and pitch within about ``weight`` times the x miss of the
    request, x within as much of the most forward force that keeps them exactly (oracle); the
    same request with equal weights gives up z and pitch by a tenth of the x miss or more."""
    body = _body()
    robot = body.robot
    q = robot.neutral()
    for wrench in _requests(robot):
        best_x = _most_forward_force(q, wrench[1], wrench[2])
        assert best_x < wrench[0] - 1.0  # the request's x cannot be met with z and pitch kept
        sol = body.solve(q, wrench, method="qp", weights={"x": weight})
        _check_feasible(q, sol)
        miss = sol.wrench - wrench
        assert sol.method == "qp" and sol.residual == pytest.approx(np.linalg.norm(miss))
        assert np.all(np.abs(miss[1:]) <= 5 * weight * abs(miss[0])), miss
        assert abs(sol.wrench[0] - best_x) <= 5 * weight * abs(miss[0]) + 1e-8 * wrench[1]
        equal = body.solve(q, wrench, method="qp")
        _check_feasible(q, equal)
        gave_up = np.abs(equal.wrench - wrench)
        assert np.all(gave_up[1:] >= 0.1 * gave_up[0]), gave_up  # z and pitch given up too
        assert equal.residual < sol.residual  # the unweighted miss is the smaller one


def test_weights_by_dict_by_array_in_the_constructor_and_per_solve_agree():
    q = va.load_robot("spring_flamingo").neutral()
    wrench = _requests(va.load_robot("spring_flamingo"))[1]
    by_dict = _body(weights={"x": 1e-3}).solve(q, wrench, method="qp")
    by_array = _body(weights=[1e-3, 1.0, 1.0]).solve(q, wrench, method="qp")
    plain = _body()
    per_solve = plain.solve(q, wrench, method="qp", weights={"x": 1e-3})
    for other in (by_array, per_solve):
        np.testing.assert_allclose(other.forces, by_dict.forces, rtol=0, atol=1e-9 * wrench[1])
    np.testing.assert_array_equal(plain.qp.weights, np.ones(3))  # the override is per solve
    assert plain.solve(q, wrench, method="qp").residual < per_solve.residual


def test_a_controller_with_yield_axes_on_the_qp():
    """``Controller.add(method="qp", yield_axes=("x",))``: the solve with x weighted 1e-3 (or
    ``yield_weight``), the actuator unchanged."""
    body = _body()
    robot = body.robot
    q, v = robot.neutral(), np.zeros(robot.model.nv)
    wrench = _requests(robot)[1]
    controller = va.Controller(robot, clip=False)
    component = va.ConstantForce(AXES, wrench)
    controller.add("body", body, [component], method="qp", yield_axes=("x",))
    controller.add("tight", body, [component], method="qp", yield_axes="x", yield_weight=1e-6)
    controller.add("plain", body, [component], method="qp")
    out = controller.compute(q, v, active=("body",))
    expected = body.solve(q, wrench, method="qp", weights={"x": 1e-3})
    np.testing.assert_allclose(out.produced["body"], expected.wrench, rtol=0, atol=1e-9)
    np.testing.assert_allclose(out.tau, expected.tau, rtol=0, atol=1e-9)
    miss = out.produced["body"] - wrench
    assert np.all(np.abs(miss[1:]) <= 5e-3 * abs(miss[0]))
    tight = controller.compute(q, v, active=("tight",)).produced["tight"] - wrench
    assert np.all(np.abs(tight[1:]) <= 5e-6 * abs(tight[0]))
    plain = controller.compute(q, v, active=("plain",)).produced["plain"] - wrench
    assert np.all(np.abs(plain[1:]) >= 0.1 * abs(plain[0]))
    np.testing.assert_array_equal(body.qp.weights, np.ones(3))


def test_bad_weights_are_typed_errors():
    body = _body()
    q, wrench = body.robot.neutral(), np.array([10.0, 100.0, 0.0])
    for weights, error, match in (
        ({"y": 1.0}, va.InvalidAxisError, "'y'"),
        ({"x": 0.0}, va.InvalidInputError, r"weights\['x'\]"),
        ({"z": -1.0}, va.InvalidInputError, r"weights\['z'\]"),
        ({"ry": float("nan")}, va.InvalidInputError, r"weights\['ry'\]"),
        ({"x": float("inf")}, va.InvalidInputError, r"weights\['x'\]"),
        ({"x": "heavy"}, va.InvalidInputError, r"weights\['x'\]"),
        ({"x": True}, va.InvalidInputError, r"weights\['x'\]"),
        ([1.0, 1.0], va.InvalidInputError, "3 numbers"),
        ([1.0, -2.0, 1.0], va.InvalidInputError, r"weights\['z'\]"),
        ([1.0, 1.0, np.nan], va.InvalidInputError, r"weights\['ry'\]"),
        ("x", va.InvalidInputError, "dict"),
        (2.0, va.InvalidInputError, "dict"),
    ):
        with pytest.raises(error, match=match):
            _body(weights=weights)
        with pytest.raises(error, match=match):
            body.solve(q, wrench, method="qp", weights=weights)
    controller = va.Controller(body.robot)
    with pytest.raises(va.InvalidInputError, match="yield_weight"):
        controller.add("a", body, method="qp", yield_axes=("x",), yield_weight=0.0)
    with pytest.raises(va.InvalidInputError, match="yield_weight"):
        controller.add("b", body, yield_axes=("x",), unilateral={"z": 1.0}, yield_weight=1e-3)
    with pytest.raises(va.InvalidAxisError, match="yield_axes"):
        controller.add("c", body, method="qp", yield_axes=("y",))
    with pytest.raises(va.InvalidInputError, match="unilateral"):
        controller.add("d", body, method="qp", yield_axes=("x",), friction=0.5)
    assert not controller.attachments
