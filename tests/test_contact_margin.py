"""The compiled feasibility check of the contact limits against forward-kinematics oracles.

``least_margin`` decides, without building the constraint rows, whether a tick's distribution
already meets the friction cones and unilateral minima (the usual tick). It must equal the
smallest margin of an oracle (cones about world z, or with ``normals="frames"`` about the soles'
axes from Pinocchio's placements), and the rows' own margins. When a
request must be scaled, ``largest_scale`` (compiled ratio test) must agree with the numpy ratio
test on the rows and with a bisection on the oracle margins, and the interpolated solution must
equal a solve of the scaled request.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
from oracles import requires_core, robot

import virtual_actuators as va
from virtual_actuators.components import ConstantForce
from virtual_actuators.control import Controller
from virtual_actuators.control.failures import (
    constraint_rows,
    enforce_unilateral,
    interpolate,
    largest_scale,
    least_margin,
    ratio_test,
)

PLANAR = ("x", "z", "ry")
ANKLES = ["left_ankle", "right_ankle"]


def _flamingo(
    mu: float | None, min_normal: float, unilateral: dict | None = None, normals=None
):
    rob = robot("spring_flamingo")
    double = va.ParallelVirtualActuator(
        rob, "body", ["left_foot", "right_foot"], "world", PLANAR, contact="flat",
        unactuated=ANKLES, normals=normals,
    )  # fmt: skip
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


def _oracle_margins(
    rob: va.Robot, q: np.ndarray, forces: np.ndarray, mu, min_normal, frames: bool = False
):
    """``mu n -+ t`` per foot (and the normal minus its minimum when > 0).

    About world z with the world's x and y as tangents by default; about the soles' axes from
    Pinocchio's placements with ``frames`` (``normals="frames"``).
    """
    model = rob.model
    data = model.createData()
    pin.framesForwardKinematics(model, data, q)
    margins = []
    for chain, foot in enumerate(("left_foot", "right_foot")):
        rotation = data.oMf[model.getFrameId(foot)].rotation if frames else np.eye(3)
        force_world = np.array([forces[chain, 0], 0.0, forces[chain, 1]])
        normal = rotation[:, 2] @ force_world
        t1, t2 = rotation[:, 0] @ force_world, rotation[:, 1] @ force_world
        margins += [normal - min_normal] if min_normal > 0.0 else []
        margins += [mu * normal - t1, mu * normal + t1, mu * normal - t2, mu * normal + t2]
    return np.array(margins)


@requires_core
@pytest.mark.parametrize("normals", [None, "frames"])
@pytest.mark.parametrize("seed", range(6))
def test_least_margin_equals_the_forward_kinematics_cone_margins(seed, normals):
    rng = np.random.default_rng(seed)
    mu, min_normal = rng.uniform(0.2, 1.2), rng.uniform(0.0, 20.0) * (seed % 3 > 0)
    rob, attachment = _flamingo(mu, min_normal, normals=normals)
    for _ in range(40):
        q = _tilted(rob, rng)
        snapshot = va.Snapshot(rob, q, np.zeros(rob.model.nv))
        forces = rng.normal(0.0, 60.0, (2, 3)) + [0.0, 50.0, 0.0]
        frames = normals == "frames"
        expected = _oracle_margins(rob, q, forces, mu, min_normal, frames).min()
        margin = least_margin(attachment, snapshot, forces)
        assert margin == pytest.approx(expected, rel=1e-12, abs=1e-10 * np.abs(forces).max())
        rows, lows = constraint_rows(attachment, snapshot)
        assert margin == pytest.approx((rows @ forces.ravel() - lows).min(), abs=1e-9)


@requires_core
def test_least_margin_of_unilateral_minima_is_the_least_share_above_its_floor():
    rng = np.random.default_rng(7)
    rob, attachment = _flamingo(None, 0.0, unilateral={"z": 12.0})
    snapshot = va.Snapshot(rob, _tilted(rob, rng), np.zeros(rob.model.nv))
    for _ in range(50):
        forces = rng.normal(0.0, 40.0, (2, 3))
        margin = least_margin(attachment, snapshot, forces)
        assert margin == pytest.approx((forces[:, 1] - 12.0).min(), rel=1e-12, abs=1e-12)


@pytest.mark.parametrize("seed", range(4))
def test_largest_scale_equals_the_ratio_test_and_a_bisection_on_the_oracle(seed):
    rng = np.random.default_rng(100 + seed)
    mu, min_normal = rng.uniform(0.3, 1.0), rng.uniform(0.0, 15.0)
    rob, attachment = _flamingo(mu, min_normal, normals="frames" if seed % 2 else None)
    frames = seed % 2 == 1
    checked = 0
    for _ in range(60):
        q = _tilted(rob, rng)
        snapshot = va.Snapshot(rob, q, np.zeros(rob.model.nv))
        base = rng.normal(0.0, 20.0, (2, 3)) + [0.0, 80.0, 0.0]  # inside the cones, mostly
        full = base + rng.normal(0.0, 80.0, (2, 3))
        alpha = largest_scale(attachment, snapshot, full, base)
        rows, lows = constraint_rows(attachment, snapshot)
        reference = ratio_test(rows @ full.ravel(), rows @ base.ravel(), lows)
        assert alpha == pytest.approx(reference, rel=1e-12, abs=1e-12)
        assert 0.0 <= alpha <= 1.0

        def feasible(a, q=q, full=full, base=base):
            shares = base + a * (full - base)
            margins = _oracle_margins(rob, q, shares, mu, min_normal, frames)
            return margins.min() >= 0.0

        if not feasible(0.0) or feasible(1.0):
            continue  # the bisection below needs a feasible base and an infeasible full
        low, high = 0.0, 1.0  # the feasible set in alpha is an interval from 0
        for _ in range(60):
            middle = 0.5 * (low + high)
            low, high = (middle, high) if feasible(middle) else (low, middle)
        assert alpha == pytest.approx(low, abs=1e-9)
        checked += 1
    assert checked >= 10


def test_ratio_test_is_zero_when_a_condition_cannot_be_met():
    lows = np.array([1.0, 0.0])
    assert ratio_test(np.array([0.5, 3.0]), np.array([0.5, 2.0]), lows) == 0.0  # flat, short
    assert ratio_test(np.array([2.0, -1.0]), np.array([2.0, 1.0]), lows) == 0.5
    assert ratio_test(np.array([3.0, 2.0]), np.array([-1.0, 1.0]), lows) == 1.0  # the end meets


@pytest.mark.parametrize("seed", range(3))
def test_interpolated_solution_equals_a_solve_of_the_scaled_request(seed):
    rng = np.random.default_rng(200 + seed)
    rob, attachment = _flamingo(0.6, 5.0)
    actuator = attachment.actuator
    for _ in range(20):
        snapshot = va.Snapshot(rob, _tilted(rob, rng), np.zeros(rob.model.nv))
        request = rng.normal(0.0, 60.0, 3) + [0.0, 150.0, 0.0]
        base = np.where(attachment.yield_mask, 0.0, request)
        start = actuator.solve(snapshot, base, attachment.free)
        end = actuator.solve(snapshot, request, attachment.free)
        alpha = rng.uniform(0.0, 1.0)
        blend = interpolate(start, end, alpha)
        direct = actuator.solve(snapshot, base + alpha * (request - base), attachment.free)
        scale = np.abs(direct.forces).max() + np.abs(direct.tau).max()
        for name in ("forces", "tau", "wrench", "requested", "base_effort"):
            np.testing.assert_allclose(
                getattr(blend, name), getattr(direct, name), rtol=0, atol=1e-11 * scale
            )
        assert blend.residual == pytest.approx(direct.residual, abs=1e-9 * scale)
        assert blend.method == direct.method
        assert blend.reactions == direct.reactions and blend.free == direct.free


def test_enforce_unilateral_answers_the_scaled_request_on_the_cone_boundary():
    rng = np.random.default_rng(11)
    rob, attachment = _flamingo(0.5, 10.0)
    actuator = attachment.actuator
    scaled = 0
    for _ in range(40):
        q = _tilted(rob, rng)
        snapshot = va.Snapshot(rob, q, np.zeros(rob.model.nv))
        request = np.array([rng.uniform(-300.0, 300.0), rng.uniform(100.0, 300.0), 0.0])
        full = actuator.solve(snapshot, request, attachment.free)
        answer = enforce_unilateral(attachment, snapshot, request, full)
        margins = _oracle_margins(rob, q, answer.forces, 0.5, 10.0)
        base_margins = _oracle_margins(
            rob, q, actuator.solve(snapshot, request * [0.0, 1.0, 1.0]).forces, 0.5, 10.0
        )
        if answer is full or base_margins.min() < 0.0:
            continue  # feasible as asked, or not even the base is (then the base is answered)
        scaled += 1
        scale = np.abs(answer.forces).max()
        assert margins.min() == pytest.approx(0.0, abs=1e-9 * scale)  # on the boundary
        direct = actuator.solve(snapshot, answer.requested, attachment.free)
        np.testing.assert_allclose(answer.tau, direct.tau, rtol=0, atol=1e-10 * scale)
        assert answer.requested[1:] == pytest.approx(request[1:], abs=1e-12 * scale)
    assert scaled >= 5
