"""The QP's stages on DAQP (built into the compiled core) against ProxQP, the reference.

Stage 1 is ``min |x|^2`` on the equality rows and the bounded rows. With the core, DAQP solves it
from cold and the exact step certifies its active set; without it (``VA_CORE=0``), ProxQP. An
infeasible request's closest wrench (stages 2 and 3) is solved by DAQP too, likewise. The
stage-1 problems are recorded from real solves (solo12 and the hexapod with friction pyramids,
requests feasible and not) and each is solved by DAQP and by a cold ProxQP solve: both must call
the same problems infeasible and give the same ``x`` to ProxQP's accuracy. Whole solves through
DAQP and through ProxQP (requests met and closest wrenches, unit and uneven weights) agree to the
QP's determinism bound, and DAQP's answers need no ProxQP iteration.
"""

from __future__ import annotations

import numpy as np
import pytest
from oracles import random_configuration

import virtual_actuators as va
from virtual_actuators.core import CORE
from virtual_actuators.distribution.qp import stages

pytestmark = pytest.mark.skipif(CORE is None, reason="virtual_actuators._core is not built")

ROBOTS = {
    "solo12": ("base_link", ["FL_FOOT", "FR_FOOT", "HL_FOOT", "HR_FOOT"]),
    "hexapod": ("body", [f"foot_{i}" for i in range(1, 7)]),
}


def _requests(robot, body, count, seed):
    rng = np.random.default_rng(seed)
    weight = 9.81 * sum(inertia.mass for inertia in robot.model.inertias)
    for k in range(count):
        wrench = np.zeros(body.n)
        wrench[2] = weight
        wrench += rng.normal(scale=(0.3 if k % 2 else 0.03) * weight, size=body.n)
        yield random_configuration(robot, rng, scale=0.1), wrench


def _solve(body, q, wrench):
    try:
        return body.solve(q, wrench, method="qp")
    except va.ConstraintError:
        return None


@pytest.mark.parametrize("name", sorted(ROBOTS))
def test_daqp_and_proxqp_agree_on_recorded_stage_one_problems(name, monkeypatch):
    from proxsuite import proxqp

    problems = []
    original = stages.ProxStages.solve

    def recording(self, path, rows, miss, weights, budget):
        problems.append(tuple(np.array(a) for a in (rows.equality, rows.equality_rhs,
                                                     rows.inequality, rows.lows, rows.uppers)))
        return original(self, path, rows, miss, weights, budget)  # fmt: skip

    monkeypatch.setattr(stages.ProxStages, "solve", recording)
    robot = va.load_robot(name)
    body = va.ParallelVirtualActuator(robot, *ROBOTS[name], "world", contact="point",
                                      friction=0.6)  # fmt: skip
    for q, wrench in _requests(robot, body, 80, 3):
        _solve(body, q, wrench)
    verdicts = {True: 0, False: 0}
    for equality, rhs, inequality, lows, uppers in problems:
        size = equality.shape[1]
        qp = proxqp.dense.QP(size, len(rhs), len(lows))
        qp.settings.eps_abs, qp.settings.eps_rel, qp.settings.verbose = 1e-10, 0.0, False
        qp.settings.max_iter = 1000
        qp.init(np.eye(size), np.zeros(size), equality, rhs, inequality, lows, uppers)
        qp.solve()
        x = qp.results.x
        values = inequality @ x
        miss = max(
            np.abs(equality @ x - rhs).max(initial=0.0), (lows - values).max(initial=0.0),
            (values - uppers).max(initial=0.0),
        )  # fmt: skip
        feasible = qp.results.info.status == proxqp.QPSolverOutput.PROXQP_SOLVED and miss <= 1e-8
        flag, daqp_x, multipliers, iterations = CORE.daqp_least_norm(
            equality, rhs, inequality, lows, uppers, stages.DAQP_MAX_ITER
        )
        assert (flag == 1) == feasible
        verdicts[feasible] += 1
        if feasible:
            assert iterations <= stages.DAQP_MAX_ITER
            assert np.abs(daqp_x - x).max() <= 1e-8
            values = inequality @ daqp_x
            assert np.abs(equality @ daqp_x - rhs).max(initial=0.0) <= 1e-9
            assert np.all(values >= lows - 1e-9) and np.all(values <= uppers + 1e-9)
            held = np.abs(multipliers) > 1e-9  # the active rows meet their bound
            at_bound = np.minimum(np.abs(values - lows), np.abs(values - uppers))
            assert np.all(at_bound[held] <= 1e-9)
    assert verdicts[True] > 10 and verdicts[False] > 10


#: the closest-wrench stage's weights of the declarations compared: unit, and uneven
WEIGHTS = {"unit": None, "uneven": {"x": 1e-3, "y": 0.1, "rz": 30.0}}


@pytest.mark.parametrize("weights", sorted(WEIGHTS))
@pytest.mark.parametrize("name", sorted(ROBOTS))
def test_solves_through_daqp_equal_solves_through_proxqp(name, weights, monkeypatch):
    """Requests met and not (the closest wrench): the same answers through DAQP as through
    ProxQP's stages alone, to 1e-9 |w|, and DAQP's need no ProxQP iteration."""
    robot = va.load_robot(name)
    answers = {}
    for path in ("daqp", "proxqp"):
        if path == "proxqp":
            monkeypatch.setattr(stages, "DAQP_LEAST_NORM", None)
        body = va.ParallelVirtualActuator(robot, *ROBOTS[name], "world", contact="point",
                                          friction=0.6, weights=WEIGHTS[weights])  # fmt: skip
        answers[path] = []
        for q, wrench in _requests(robot, body, 40, 4):
            body.qp.reset()  # a cold stage 1 every time: the solver decides, not the last tick
            answers[path].append((_solve(body, q, wrench), body.qp.iterations, wrench))
    iterations = {"daqp": [], "proxqp": []}
    closest = 0
    for (ours, used, wrench), (theirs, used_ref, _) in zip(*answers.values(), strict=True):
        assert (ours is None) == (theirs is None)
        if ours is None:
            continue
        scale = max(np.abs(wrench).max(), 1.0)
        assert np.abs(ours.forces - theirs.forces).max() <= 1e-9 * scale
        assert np.abs(ours.wrench - theirs.wrench).max() <= 1e-9 * scale
        assert ours.residual == pytest.approx(theirs.residual, rel=0, abs=1e-9 * scale)
        closest += ours.residual > 1e-9 * scale
        iterations["daqp"].append(used)
        iterations["proxqp"].append(used_ref)
    assert closest >= 10  # the closest-wrench stages are exercised
    assert iterations["daqp"] and max(iterations["daqp"]) == 0  # DAQP: no ProxQP iteration
    assert max(iterations["proxqp"]) > 0
