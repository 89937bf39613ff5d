"""The QP's iteration budget on a hexapod tripod tick whose request is infeasible.

The case (a walk's tick: foot_2 at its least normal force, the request out of reach) once took
the compiled path's closest-wrench stage hundreds of ProxQP iterations (all-zero torque-limit
rows of the swing legs). Now ProxQP's first iterates already name its active set, and the exact
step on it (:mod:`virtual_actuators.distribution.qp.exact`) gives the closest answer within any
budget. A six-footed tick whose first iterates do not gets the budget's error from ProxQP's
stages (with the core, DAQP's closest answer needs no ProxQP iteration). Oracles: the numpy
path at the default budget (all force entries, the natural rows as equalities) and Pinocchio
(cones and torques, :mod:`test_qp`'s checks).
"""

from __future__ import annotations

import numpy as np
import pytest
from test_qp import _check_cone, _check_torques

import virtual_actuators as va
from virtual_actuators.core import CORE
from virtual_actuators.distribution.qp import stages
from virtual_actuators.distribution.qp.stages import (
    BUDGET_EXHAUSTED,
    EXACT_MAX_ITER,
    ITERATION_BUDGET,
)

Q = np.array([
    0.0489807321130934, 8.321320886702836e-05, 0.13123437703349378, -0.00020307328887192913,
    0.0010454872149744687, 0.0003033877940163827, 0.9999993868365965, 0.45519862422871565,
    0.11399699021539496, 1.362549986184852, 0.13299581456968368, 0.0017792946265542068,
    -1.461384108400946, -0.4606241301933246, -0.12465021471968232, -1.3453297695540867,
    -0.13259165897053932, 0.0029840085336667803, 1.454649857645938, 0.4534060094917848,
    0.12629381432975637, 1.3421239857513863, 0.1328842174482038, 0.0007656170286639077,
    -1.4538524622763398,
])  # fmt: skip
WRENCH = np.array([14.911862290831055, -0.012327397182769362, 38.70712520384554,
                   0.7194712043266057, -0.4046624641272306, -0.6884717569081893])  # fmt: skip
MU = 0.5


@pytest.fixture(scope="module")
def tripod() -> va.ParallelVirtualActuator:
    robot = va.load_robot("hexapod")
    return va.ParallelVirtualActuator(
        robot, "body", ["foot_2", "foot_4", "foot_6"], "world", contact="point", friction=MU,
        min_normal=3.0, torque_limits=True,
    )  # fmt: skip


@pytest.fixture(scope="module")
def reference(tripod) -> va.Solution:
    tripod.qp.iteration_budget = ITERATION_BUDGET
    return tripod.solve(Q, WRENCH, method="qp", compiled=False)


def _check_feasible(body, sol) -> None:
    """Pyramids, torques (Pinocchio RNEA) and the URDF effort limits, to 1e-8 of the scale."""
    _check_cone(body, Q, sol, MU, min_normal=3.0)
    _check_torques("hexapod", body, Q, sol)
    mask = body.problem.actuated_mask
    limits = body.robot.model.effortLimit[mask]
    limited = limits < 1e30  # larger: unlimited (no row)
    scale = max(limits[limited].max(initial=0.0), 1.0)
    assert np.all(np.abs(sol.tau[mask][limited]) <= limits[limited] + 1e-8 * scale)


@pytest.mark.parametrize("compiled", [True, False])
def test_infeasible_tick_converges_within_budget(tripod, reference, compiled) -> None:
    """Both paths: the same closest wrench and forces, well inside the budget, nothing flagged."""
    tripod.qp.iteration_budget = ITERATION_BUDGET
    sol = tripod.solve(Q, WRENCH, method="qp", compiled=compiled)
    # stage 1 gives up at EXACT_MAX_ITER; stages 2 and 3 take a few tens at most
    assert tripod.qp.iterations <= EXACT_MAX_ITER + 40
    assert BUDGET_EXHAUSTED not in sol.active and BUDGET_EXHAUSTED not in reference.active
    assert "foot_2: normal >= 3 N" in sol.active
    assert sol.residual > 1e-3 * np.linalg.norm(WRENCH)  # infeasible: the closest wrench
    assert abs(sol.residual - reference.residual) <= 1e-9 * np.linalg.norm(WRENCH)
    np.testing.assert_allclose(sol.forces, reference.forces, atol=1e-7 * np.abs(WRENCH).max())
    _check_feasible(tripod, sol)


@pytest.mark.parametrize("compiled", [True, False])
@pytest.mark.parametrize("budget", [1, 2, 8, 16])
def test_small_budgets_still_give_the_exact_closest_answer(tripod, reference, compiled, budget):
    """A budget far below the stages' needs: the answer certified exact on the active set of
    ProxQP's first iterates, the reference's to 1e-9 |w|, unflagged, within the budget."""
    tripod.qp.iteration_budget = budget
    try:
        sol = tripod.solve(Q, WRENCH, method="qp", compiled=compiled)
    finally:
        used = tripod.qp.iterations
        tripod.qp.iteration_budget = ITERATION_BUDGET
    assert used <= budget
    assert BUDGET_EXHAUSTED not in sol.active
    _check_feasible(tripod, sol)
    scale = np.abs(WRENCH).max()
    np.testing.assert_allclose(sol.forces, reference.forces, rtol=0, atol=1e-9 * scale)
    assert abs(sol.residual - reference.residual) <= 1e-9 * scale


#: a six-footed tick (URDF limits, 5 N m) that ProxQP's first iterates do not solve
SIX_Q = np.array([
    0.0, 0.0, 0.13, 0.0, 0.0, 0.0, 1.0, 0.089591, 0.185044, 1.334288, 0.197724, 0.186098,
    -1.71137, 0.103748, -0.2494, -1.468947, -0.031666, -0.148374, 1.3831, 0.153108, -0.091774,
    1.295148, 0.099256, -0.025728, -1.321159,
])  # fmt: skip
SIX_WRENCH = np.array([-45.565527, 6.206623, 79.817656, 0.06283, 0.082929, -3.779286])


@pytest.mark.parametrize("compiled", [True, False])
def test_budget_without_feasible_point_raises(compiled, monkeypatch) -> None:
    """ProxQP's stages alone (without DAQP, as without the core) and too few iterations to
    reach any feasible point: a typed error naming the budget (the default budget reaches the
    closest wrench). With the core, DAQP's closest answer needs no ProxQP iteration: that
    answer, to 1e-9 |w|, within any budget."""
    robot = va.load_robot("hexapod")
    body = va.ParallelVirtualActuator(
        robot, "body", [f"foot_{i}" for i in range(1, 7)], "world", friction=0.5,
        min_normal=1.0, torque_limits=True,
    )  # fmt: skip
    with_daqp = None
    if CORE is not None:
        body.qp.iteration_budget = 2
        with_daqp = body.solve(SIX_Q, SIX_WRENCH, method="qp", compiled=compiled)
        assert body.qp.iterations == 0
    monkeypatch.setattr(stages, "DAQP_LEAST_NORM", None)
    body.qp.iteration_budget = 2
    with pytest.raises(va.exceptions.ConstraintError, match="iteration budget"):
        body.solve(SIX_Q, SIX_WRENCH, method="qp", compiled=compiled)
    assert body.qp.iterations <= 2
    body.qp.iteration_budget = ITERATION_BUDGET
    sol = body.solve(SIX_Q, SIX_WRENCH, method="qp", compiled=compiled)
    assert sol.residual > 1e-3 * np.linalg.norm(SIX_WRENCH)
    if with_daqp is not None:
        scale = np.abs(SIX_WRENCH).max()
        np.testing.assert_allclose(with_daqp.forces, sol.forces, rtol=0, atol=1e-9 * scale)
        assert abs(with_daqp.residual - sol.residual) <= 1e-9 * scale
