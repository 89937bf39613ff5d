"""One admissibility rule on every path: ``sol.admissible`` is False exactly when ``strict=True``
raises :class:`va.InadmissibleWrenchError`, for every method (partitioned, dense, qp) and both
matrix paths.

Oracles: the residual recomputed here from the produced and requested wrenches, the tolerance
bounded here from ``tol`` and the norms (``tol * max(|w|, |produced|)`` plus rounding), and a
direct argument on the inequalities (feet that push at least ``min_normal`` each cannot pull the
base down: ``sum f_z >= 4 min_normal``).
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
from test_qp import SOLO_FEET, _weight

import virtual_actuators as va

MU, MIN_NORMAL = 0.6, 1.0


def _check_rule(body, q, wrench, tol, method, compiled, free=()) -> va.Solution:
    """The rule, checked on one solve; returns the solution."""
    sol = body.solve(q, wrench, method=method, compiled=compiled, tol=tol, free=free)
    keep = np.array([a not in free for a in body.axes])
    miss = float(np.linalg.norm((sol.wrench - wrench)[keep]))
    size = max(float(np.linalg.norm(wrench[keep])), float(np.linalg.norm(sol.wrench[keep])))
    peak = max(float(np.abs(sol.forces).max()), size)
    assert sol.residual == pytest.approx(miss, rel=1e-9, abs=1e-12 * peak)
    # tol times the scale, plus the path's rounding (at most 1e-8 of the forces)
    assert tol * size <= sol.tolerance <= tol * size + 1e-8 * peak
    assert sol.admissible == (sol.residual <= sol.tolerance)
    if method == "qp":
        assert sol.method == "qp"
    else:
        assert (sol.method == "least-squares") == (not sol.admissible), sol.method
    if sol.admissible:
        strict = body.solve(q, wrench, method=method, compiled=compiled, tol=tol, free=free,
                            strict=True)  # fmt: skip
        np.testing.assert_array_equal(strict.forces, sol.forces)
    else:
        with pytest.raises(va.InadmissibleWrenchError) as info:
            body.solve(q, wrench, method=method, compiled=compiled, tol=tol, free=free,
                       strict=True)  # fmt: skip
        assert not info.value.solution.admissible
        np.testing.assert_array_equal(info.value.solution.forces, sol.forces)
    return sol


def test_the_qp_answer_to_a_pull_is_inadmissible():
    """The issue's case: solo12, friction 0.6, 1 N least normal force, a 20 N pull down. The feet
    push at least 4 N in all, so the residual is at least 24 N; the QP's answer is not
    admissible, on both matrix paths, and strict raises."""
    robot = va.load_robot("solo12")
    body = va.ParallelVirtualActuator(robot, "base_link", SOLO_FEET, "world", friction=MU,
                                      min_normal=MIN_NORMAL)  # fmt: skip
    wrench = np.array([0.0, 0.0, -20.0, 0.0, 0.0, 0.0])
    for compiled in (True, False):
        sol = _check_rule(body, robot.neutral(), wrench, 1e-6, "qp", compiled)
        assert not sol.admissible
        assert sol.residual >= 20.0 + 4 * MIN_NORMAL - 1e-8 * 20.0
        # the partitioned solve has no inequality: it pulls, and the request is admissible
        assert _check_rule(body, robot.neutral(), wrench, 1e-6, "partitioned", compiled).admissible


def _two_feet_requests(robot, q, rng) -> list[np.ndarray]:
    """Requests to two diagonal point feet: producible ones (sums of foot forces), the same
    pushed off the producible set by 1e-5 and 1e-2 of their size (the moment about the line
    through the feet), and random ones."""
    model = robot.model
    data = model.createData()
    pin.framesForwardKinematics(model, data, q)
    p_base = data.oMf[model.getFrameId("base_link")].translation
    feet = [data.oMf[model.getFrameId(f)].translation - p_base for f in ("FL_FOOT", "HR_FOOT")]
    line = (feet[1] - feet[0]) / np.linalg.norm(feet[1] - feet[0])
    weight = _weight(robot)
    out = []
    for _ in range(2):
        wrench = np.zeros(6)
        for lever in feet:
            force = np.array([*rng.normal(size=2) * 0.2 * weight, weight * rng.uniform(0.3, 0.7)])
            wrench += np.concatenate((force, np.cross(lever, force)))
        out.append(wrench)
        # a moment about the line through both feet: neither foot's force produces it
        push = np.concatenate(([0, 0, 0], line)) * np.linalg.norm(wrench)
        out += [wrench + fraction * push for fraction in (1e-5, 1e-2)]
    out.append(rng.normal(size=6) * weight)
    return out


@pytest.mark.parametrize("compiled", [True, False])
def test_every_method_and_path_follows_one_rule(compiled):
    """Four and two point feet, with and without cones, requests producible, nearly producible
    and not, loose and tight tolerances, free axes: partitioned, dense and qp all label the
    answer by ``residual <= tolerance``, and strict raises exactly when it is False."""
    robot = va.load_robot("solo12")
    rng = np.random.default_rng(4)
    q = pin.integrate(robot.model, robot.neutral(), np.r_[np.zeros(3), 0.2, -0.1, 0.6,
                                                           rng.uniform(-0.2, 0.2, 12)])  # fmt: skip
    two = va.ParallelVirtualActuator(robot, "base_link", ["FL_FOOT", "HR_FOOT"], "world",
                                     friction=MU, min_normal=MIN_NORMAL)  # fmt: skip
    four = va.ParallelVirtualActuator(robot, "base_link", SOLO_FEET, "world", friction=MU,
                                      min_normal=MIN_NORMAL)  # fmt: skip
    weight = _weight(robot)
    four_requests = [
        np.array([0.0, 0.0, weight, 0.1, -0.2, 0.05]),  # standing: admissible everywhere
        np.array([0.0, 0.0, -20.0, 0.0, 0.0, 0.0]),  # a pull: the QP cannot
        np.array([2.0 * weight, 0.0, weight, 0.0, 0.0, 0.0]),  # beyond the cones
    ]
    labels = {True: 0, False: 0}
    cases = [(four, w) for w in four_requests]
    cases += [(two, w) for w in _two_feet_requests(robot, q, rng)]
    for body, wrench in cases:
        for method in ("partitioned", "dense", "qp"):
            for tol in (1e-6, 1e-3, 0.0):
                sol = _check_rule(body, q, wrench, tol, method, compiled)
                labels[sol.admissible] += 1
        _check_rule(body, q, wrench, 1e-6, "qp", compiled, free=("rz",))
        _check_rule(body, q, wrench, 1e-6, "partitioned", compiled, free=("x", "rz"))
    assert labels[True] >= 20 and labels[False] >= 20  # both labels exercised


def test_interpolated_controller_solutions_follow_the_rule():
    """A controller's scaled request (unilateral minima, yield axes: the solution interpolated
    between two solves) is labelled by the same rule: produced, hence admissible."""
    robot = va.load_robot("solo12")
    weight = _weight(robot)
    body = va.ParallelVirtualActuator(robot, "base_link", SOLO_FEET, "world", min_normal=5.0)
    wrench = np.array([0.0, 0.0, weight, 0.5, 0.7, 0.0])
    controller = va.Controller(robot, clip=False)
    controller.add("body", body, [va.ConstantForce(body.axes, wrench)],
                   unilateral={"z": 5.0}, yield_axes=("rx", "ry"))  # fmt: skip
    sol = controller.compute(robot.neutral(), np.zeros(robot.model.nv)).solutions["body"]
    assert sol.wrench[4] < 0.99 * wrench[4]  # interpolated: the request was scaled
    miss = float(np.linalg.norm(sol.wrench - sol.requested))
    assert sol.residual == pytest.approx(miss, abs=1e-12 * weight)
    assert sol.admissible and sol.residual <= sol.tolerance
    assert sol.method in ("partitioned", "pseudo-inverse")
    assert 1e-6 * np.linalg.norm(sol.requested) <= sol.tolerance <= 1e-6 * 2 * weight
