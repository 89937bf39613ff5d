"""The QP's accuracy contract (``method="qp"``): exact answers, the same whatever came before,
and inequalities that cannot hold named.

Properties: every answer (compiled and numpy paths, the request met or the closest wrench) is
within 1e-8 of ``max(|w|, the active bounds)`` of the true optimum, for requests from 1e-6 to
1e6, with torque limits that never bind and with limits that do; with every axis free a 1 N
least normal force gives exactly 1 N; answers depend on the arguments alone (to 1e-9 |w|); a
declaration whose inequalities cannot hold together raises ``ConstraintError`` at once, naming
rows that conflict.

Oracle (no library code): the QP is rebuilt here from Pinocchio (the chains' natural rows of
:class:`oracles.ReferenceDistribution`, pyramids about world z, torque rows from the relative
Jacobians); a proxsuite QP written here (tolerance 1e-13) names its active set, and numpy solves
the problem on that set exactly (SVD: the least-norm answer, or the weighted least squares on the
null space of the active rows and then the least norm); the answer is accepted only when the
KKT conditions hold: every row met, each active row's multiplier of the right sign
(stationarity by ``lstsq``). The named conflicting rows are checked by a feasibility QP written
here on those rows alone.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
from oracles import ReferenceDistribution
from proxsuite import proxqp

import virtual_actuators as va
from virtual_actuators.core import CORE
from virtual_actuators.distribution.qp.stages import CONFLICT_MAX_ITER, EXACT_MAX_ITER

SIX = ("x", "y", "z", "rx", "ry", "rz")
SOLO_FEET = ["FL_FOOT", "FR_FOOT", "HL_FOOT", "HR_FOOT"]
HEX_FEET = [f"foot_{i}" for i in range(1, 7)]
#: the contract: every answer to this fraction of max(|w|, the active bounds)
ACCURACY = 1e-8
#: the oracle's KKT tolerance, on its problem scaled to ~1
KKT_TOL = 1e-10


class ExactQP:
    """The QP of a point-footed body over all ``p x 6`` force entries, solved exactly here."""

    def __init__(self, robot, action, feet, mu, min_normal, limits):
        self.robot, self.mu, self.min_normal = robot, mu, min_normal
        self.limits = limits  # (nv,) [N m] or None
        self.reference = ReferenceDistribution(robot, action, feet, "world", SIX, "point")
        self.p = len(feet)

    def rows(self, q, wrench, free=()):
        """``(hard, hard_rhs, request, request_rhs, C, lows, uppers)`` over ``F.ravel()``."""
        hard, hard_rhs, request, request_rhs = self.reference.system(q, wrench, free)
        p, n = self.p, 6
        rows, lows, uppers = [], [], []
        for i in range(p):  # world z pyramid: f_z >= min_normal, |f_x|, |f_y| <= mu f_z
            for vector, low in (
                ((0.0, 0.0, 1.0), self.min_normal),
                ((1.0, 0.0, self.mu), 0.0), ((-1.0, 0.0, self.mu), 0.0),
                ((0.0, 1.0, self.mu), 0.0), ((0.0, -1.0, self.mu), 0.0),
            ):  # fmt: skip
                row = np.zeros(p * n)
                row[i * n : i * n + 3] = vector
                rows.append(row)
                lows.append(low)
                uppers.append(np.inf)
        if self.limits is not None:  # tau_v = sum_i J_i[:, v] . F_i (sign: bounds symmetric)
            jacobians = self.reference.chain_jacobians(q)
            for v in range(6, self.robot.model.nv):
                rows.append(np.concatenate([jac[:, v] for jac in jacobians]))
                lows.append(-self.limits[v])
                uppers.append(self.limits[v])
        return (hard, hard_rhs, request, request_rhs, np.array(rows), np.array(lows),
                np.array(uppers))  # fmt: skip

    def solve(self, q, wrench, free=()):
        """``(forces (p, 6), produced wrench on the prescribed axes, scale of the bounds met)``."""
        hard, hard_rhs, request, target, rows, lows, uppers = self.rows(q, wrench, free)
        scale = max(np.abs(target).max(initial=0.0), self.min_normal, 1e-300)
        hard_rhs, target = hard_rhs / scale, target / scale
        lows, uppers = lows / scale, uppers / scale
        size = hard.shape[1]
        equality = np.vstack((hard, request))
        first = _proxsuite(np.eye(size), np.zeros(size), equality,
                           np.concatenate((hard_rhs, target)), rows, lows, uppers)  # fmt: skip
        guesses = [(first.x.copy(), first.z.copy())]
        if first.info.status != proxqp.QPSolverOutput.PROXQP_SOLVED:
            # the closest wrench (unit weights), then the least norm at it
            closest = _proxsuite(request.T @ request, -(request.T @ target), hard, hard_rhs,
                                 rows, lows, uppers)  # fmt: skip
            reached = request @ closest.x
            last = _proxsuite(np.eye(size), np.zeros(size), equality,
                              np.concatenate((hard_rhs, reached)), rows, lows, uppers)  # fmt: skip
            held = np.abs(closest.z) > 1e-9  # bounding the miss: active at every closest answer
            guesses = [(last.x.copy(), np.where(held, closest.z, last.z)),
                       (closest.x.copy(), closest.z.copy())]  # fmt: skip
        for x_guess, z_guess in guesses:
            values = rows @ x_guess
            for at_low, at_up in (
                (z_guess < -1e-9, z_guess > 1e-9),
                (values - lows <= 1e-9, uppers - values <= 1e-9),
            ):
                x = _certified(hard, hard_rhs, request, target, rows, lows, uppers, at_low, at_up)
                if x is not None:
                    active = np.concatenate((lows[at_low], uppers[at_up]))
                    bound = scale * float(np.abs(active).max(initial=0.0))
                    return x.reshape(self.p, 6) * scale, request @ x * scale, bound
        raise AssertionError("the oracle could not certify an answer")


def _proxsuite(hessian, gradient, equality, equality_rhs, rows, lows, uppers):
    qp = proxqp.dense.QP(hessian.shape[0], len(equality_rhs), len(lows))
    qp.settings.eps_abs = 1e-13
    qp.settings.eps_rel = 0.0
    qp.settings.max_iter = 20000
    qp.settings.check_duality_gap = True
    qp.settings.eps_duality_gap_abs = 1e-13
    qp.settings.eps_duality_gap_rel = 0.0
    qp.settings.verbose = False
    qp.init(hessian, gradient, equality, equality_rhs, rows, np.maximum(lows, -1e20),
            np.minimum(uppers, 1e20))  # fmt: skip
    qp.solve()
    return qp.results


def _pinv_solve(matrix, rhs):
    return np.linalg.pinv(matrix, rcond=1e-12) @ rhs


def _certified(hard, hard_rhs, request, target, rows, lows, uppers, at_low, at_up):
    """The exact answer with ``at_low``/``at_up`` rows at their bounds, or None if not KKT.

    On the null space ``N`` of the fixed rows ``M`` (hard and active): ``x = x_p + N u``,
    ``u`` the least-norm least-squares fit of the request (the request met when it can be; the
    least norm since ``x_p`` is orthogonal to ``N``). Multipliers: ``grad = M^T lam`` of the
    miss, ``x = [M; request]^T nu`` of the norm; an active row needs ``lam`` of the right sign,
    or ``nu`` where it does not bound the miss (``lam = 0``).
    """
    fixed = np.vstack((hard, rows[at_low], rows[at_up]))
    fixed_rhs = np.concatenate((hard_rhs, lows[at_low], uppers[at_up]))
    _, singular, vt = np.linalg.svd(fixed)
    rank = int(np.sum(singular > 1e-10 * singular[0]))
    null = vt[rank:].T
    particular = _pinv_solve(fixed, fixed_rhs)
    x = particular + null @ _pinv_solve(request @ null, target - request @ particular)
    sides = np.concatenate((np.zeros(len(hard_rhs)), -np.ones(at_low.sum()), np.ones(at_up.sum())))
    miss = request.T @ (request @ x - target)
    lam = np.linalg.lstsq(fixed.T, miss, rcond=None)[0]
    both = np.vstack((fixed, request))
    nu = np.linalg.lstsq(both.T, x, rcond=None)[0]
    values = rows @ x
    stationary = (np.abs(fixed.T @ lam - miss).max(initial=0.0) <= KKT_TOL
                  and np.abs(both.T @ nu - x).max() <= KKT_TOL)  # fmt: skip
    signs = np.where(np.abs(lam) > KKT_TOL, sides * lam, sides * nu[: len(fixed_rhs)])
    feasible = (
        np.abs(fixed @ x - fixed_rhs).max() <= KKT_TOL
        and np.all(values >= lows - KKT_TOL)
        and np.all(values <= uppers + KKT_TOL)
    )
    return x if stationary and feasible and np.all(signs <= KKT_TOL) else None


def _q(robot, rng, scale=0.25):
    step = np.r_[np.zeros(6), rng.uniform(-scale, scale, robot.model.nv - 6)]
    return pin.integrate(robot.model, robot.neutral(), step)


def _check(sol, oracle, q, wrench, free=()):
    """The library's answer against the oracle's: forces and wrench to ACCURACY."""
    forces, produced, bound = oracle.solve(q, wrench, free)
    keep = [a not in free for a in SIX]
    size = max(np.abs(wrench[keep]).max(initial=0.0), bound)
    np.testing.assert_allclose(sol.forces, forces, rtol=0, atol=ACCURACY * size)
    np.testing.assert_allclose(sol.wrench[keep], produced, rtol=0, atol=ACCURACY * size)
    return np.abs(sol.forces - forces).max() / size


@pytest.fixture(scope="module")
def solo():
    return va.load_robot("solo12")


#: a request that presses two feet against their pyramids (mu 0.6) and is met
PRESSING = np.array([9.0, -2.0, 25.0, 1.2, -0.8, 0.3])


@pytest.mark.parametrize("compiled", [True, False])
@pytest.mark.parametrize("limited", [False, True])
def test_answers_are_exact_from_1e_minus_6_to_1e6(solo, compiled, limited):
    """Requests scaled by 1e-6..1e6, with no torque limits and with the URDF's 1000 N m ones
    (binding from 1e4 x on: then the closest wrench): every answer is the oracle's to
    1e-8 of max(|w|, the active bounds), on either path."""
    body = va.ParallelVirtualActuator(solo, "base_link", SOLO_FEET, "world", friction=0.6,
                                      torque_limits=limited)  # fmt: skip
    limits = solo.model.effortLimit.copy() if limited else None
    oracle = ExactQP(solo, "base_link", SOLO_FEET, 0.6, 0.0, limits)
    q = _q(solo, np.random.default_rng(1))
    for exponent in range(-6, 7):
        wrench = PRESSING * 10.0**exponent
        sol = body.solve(q, wrench, method="qp", compiled=compiled)
        if not limited or exponent <= 3:  # 1000 N m does not bind there: the request is met
            assert any("friction" in name for name in sol.active)
            assert not any("torque" in name for name in sol.active)
            assert sol.residual <= 1e-12 * np.abs(wrench).max()
        else:
            assert any("torque" in name for name in sol.active)
        _check(sol, oracle, q, wrench)


@pytest.mark.parametrize(("name", "action", "feet", "limit"), [
    ("solo12", "base_link", SOLO_FEET, 1.0), ("hexapod", "body", HEX_FEET, 1.2),
])  # fmt: skip
def test_binding_limits_and_closest_wrenches_are_exact(name, action, feet, limit):
    """Random requests pressing on pyramids, least normal forces and torque limits that bind
    (a third cannot be met: the closest wrench): both paths give the oracle's answer."""
    robot = va.load_robot(name)
    limits = np.full(robot.model.nv, np.inf)
    limits[6:] = limit
    body = va.ParallelVirtualActuator(robot, action, feet, "world", friction=0.5,
                                      min_normal=1.0, torque_limits=limits)  # fmt: skip
    oracle = ExactQP(robot, action, feet, 0.5, 1.0, limits)
    rng = np.random.default_rng(3)
    weight = pin.computeTotalMass(robot.model) * 9.81
    kinds = {"met": 0, "closest": 0, "torque": 0}
    for _ in range(12):
        q = _q(robot, rng)
        wrench = np.concatenate((rng.normal(size=2) * weight * 0.4,
                                 [weight * rng.uniform(0.5, 1.5)],
                                 rng.normal(size=3) * weight * 0.02))  # fmt: skip
        for compiled in (True, False):
            sol = body.solve(q, wrench, method="qp", compiled=compiled)
            _check(sol, oracle, q, wrench)
        kinds["met" if sol.residual <= 1e-9 * weight else "closest"] += 1
        kinds["torque"] += any("torque" in a for a in sol.active)
    assert min(kinds.values()) >= 2, kinds


@pytest.mark.parametrize("compiled", [True, False])
@pytest.mark.parametrize("limited", [False, True])
def test_every_axis_free_gives_the_least_normal_force_exactly(solo, compiled, limited):
    """Nothing requested, every foot pushing at least 1 N: each pushes exactly 1 N (the least
    norm), also beside 1000 N m torque limits."""
    body = va.ParallelVirtualActuator(solo, "base_link", SOLO_FEET, "world", friction=0.6,
                                      min_normal=1.0, torque_limits=limited)  # fmt: skip
    q = _q(solo, np.random.default_rng(2))
    sol = body.solve(q, np.zeros(6), free=SIX, method="qp", compiled=compiled)
    np.testing.assert_allclose(sol.forces[:, 2], 1.0, rtol=0, atol=ACCURACY)
    limits = solo.model.effortLimit.copy() if limited else None
    _check(sol, ExactQP(solo, "base_link", SOLO_FEET, 0.6, 1.0, limits), q, np.zeros(6), SIX)


@pytest.mark.parametrize("compiled", [True, False])
def test_answers_do_not_depend_on_what_was_solved_before(solo, compiled):
    """The same ticks (met and closest, 1000 N m limits and 1 N least normal forces) solved in
    order, in reverse on a fresh actuator, and again shuffled on the used one: the same answers
    to 1e-9 |w|; and A, B, A on one actuator gives A's answer twice."""
    def body():
        return va.ParallelVirtualActuator(solo, "base_link", SOLO_FEET, "world", friction=0.5,
                                          min_normal=1.0, torque_limits=True)  # fmt: skip

    rng = np.random.default_rng(6)
    ticks = []
    for _ in range(30):
        wrench = np.concatenate((rng.normal(size=2) * 12.0, [rng.uniform(10.0, 40.0)],
                                 rng.normal(size=3) * 0.6))  # fmt: skip
        ticks.append((_q(solo, rng, 0.1), wrench * 10.0 ** rng.uniform(-4, 2)))
    used, fresh = body(), body()
    first = [used.solve(q, w, method="qp", compiled=compiled) for q, w in ticks]
    reverse = [fresh.solve(q, w, method="qp", compiled=compiled) for q, w in ticks[::-1]][::-1]
    order = rng.permutation(len(ticks))
    again = dict(zip(order, [used.solve(*ticks[i], method="qp", compiled=compiled)
                             for i in order], strict=True))  # fmt: skip
    closest = 0
    for i, (_, wrench) in enumerate(ticks):
        size = np.abs(wrench).max()
        for other in (reverse[i], again[i]):
            np.testing.assert_allclose(other.forces, first[i].forces, rtol=0, atol=1e-9 * size)
        closest += first[i].residual > 1e-9 * size
    assert 3 <= closest <= 27  # both stages are exercised
    (q_a, w_a), (q_b, w_b) = ticks[0], ticks[1]
    one = body()
    a1 = one.solve(q_a, w_a, method="qp", compiled=compiled)
    one.solve(q_b, w_b, method="qp", compiled=compiled)
    a2 = one.solve(q_a, w_a, method="qp", compiled=compiled)
    np.testing.assert_allclose(a2.forces, a1.forces, rtol=0, atol=1e-9 * np.abs(w_a).max())
    np.testing.assert_allclose(a1.forces, first[0].forces, rtol=0, atol=1e-9 * np.abs(w_a).max())


def _least_shift(oracle, q, rows_kept):
    """The least squared shift of the kept inequalities' bounds that lets them hold with the
    natural rows (a proxsuite QP written here over the forces and one shift per row)."""
    hard, hard_rhs, _, _, rows, lows, uppers = oracle.rows(q, np.zeros(6), SIX)
    rows, lows, uppers = rows[rows_kept], lows[rows_kept], uppers[rows_kept]
    size, m = hard.shape[1], len(lows)
    hessian = np.zeros((size + m, size + m))
    hessian[size:, size:] = np.eye(m)
    result = _proxsuite(hessian, np.zeros(size + m), np.hstack((hard, np.zeros((len(hard), m)))),
                        hard_rhs, np.hstack((rows, np.eye(m))), lows / 1000.0,
                        uppers / 1000.0)  # fmt: skip
    assert result.info.status == proxqp.QPSolverOutput.PROXQP_SOLVED
    return float(np.abs(result.x[size:]).max(initial=0.0)) * 1000.0


@pytest.mark.parametrize("compiled", [True, False])
def test_inequalities_that_cannot_hold_are_named_at_once(compiled):
    """1000 N per foot on the hexapod, whose joints hold 5 N m: a ConstraintError naming rows
    that conflict (each foot's least normal force, knee torque limits), found within the first
    stage's iterations and the check's (not the budget: 100,000 changes nothing), also with
    every axis free (no request row). The oracle:
    the named rows alone cannot hold (their least shift is ~N), the least normal forces alone
    can (no torque limits: a shift of 0)."""
    robot = va.load_robot("hexapod")
    body = va.ParallelVirtualActuator(robot, "body", HEX_FEET, "world", friction=0.6,
                                      min_normal=1000.0, torque_limits=True)  # fmt: skip
    q = robot.neutral()
    messages = []
    for budget in (300, 100_000):
        body.qp.iteration_budget = budget
        with pytest.raises(va.ConstraintError) as caught:
            body.solve(q, np.array([0.0, 0.0, 6000.0, 0.0, 0.0, 0.0]), method="qp",
                       compiled=compiled)  # fmt: skip
        assert body.qp.iterations <= EXACT_MAX_ITER + CONFLICT_MAX_ITER
        messages.append(str(caught.value))
    message = messages[0]
    assert messages[1] == message and "iteration budget" not in message
    with pytest.raises(va.ConstraintError) as caught:  # every axis free: no request row
        body.solve(q, np.zeros(6), free=SIX, method="qp", compiled=compiled)
    assert "foot_1: normal >= 1000 N" in str(caught.value)
    for i in range(1, 7):
        assert f"foot_{i}: normal >= 1000 N" in message
        assert f"torque knee_{i}: |tau| <= 5" in message
    # the oracle's rows: per foot its normal and four faces, then the joints' torques
    model = robot.model
    joints = [model.names[j] for j in range(1, model.njoints) if model.joints[j].idx_v >= 6]
    normal = [f"{foot}: normal >= 1000 N" in message for foot in HEX_FEET]
    faces = [f"{foot}: friction" in message for foot in HEX_FEET]  # all four faces if any
    named = [[n, f, f, f, f] for n, f in zip(normal, faces, strict=True)]
    named = np.array(sum(named, []) + [f"torque {j}: |tau|" in message for j in joints])
    oracle = ExactQP(robot, "body", HEX_FEET, 0.6, 1000.0, model.effortLimit.copy())
    assert _least_shift(oracle, q, named) > 1.0  # [N, N m]: those rows alone cannot hold
    normals_only = np.zeros(len(named), dtype=bool)
    normals_only[: 5 * len(HEX_FEET) : 5] = True
    assert _least_shift(oracle, q, normals_only) <= 1e-6


def test_two_stance_feet_at_nearly_the_same_height_give_the_least_norm_answer(solo):
    """Two diagonal feet (a trot's stance) whose heights differ by 1e-11..1e-7 m: their request
    rows miss one direction (the moment about the line through the feet), and in the axes'
    order they are nearly dependent before the last row completes them. Requests that the feet
    produce (a first answer's wrench) give the oracle's least-norm answer to 1e-12 |w|, with no
    ProxQP iteration when the core is built (the exact step certifies DAQP's answer)."""
    feet = ["FL_FOOT", "HR_FOOT"]
    body = va.ParallelVirtualActuator(solo, "base_link", feet, "world", contact="point",
                                      friction=0.6)  # fmt: skip
    oracle = ExactQP(solo, "base_link", feet, 0.6, 0.0, None)
    knee = solo.model.joints[solo.model.getJointId("HR_KFE")].idx_q
    rng = np.random.default_rng(1)
    for angle in np.concatenate([np.logspace(-10, -6, 9), -np.logspace(-10, -6, 9)]):
        q = solo.neutral()
        q[knee] += angle  # the hind foot's height moves by ~0.1 angle [m]
        for _ in range(3):
            wrench = np.array([0.0, 0.0, 20.0, 0.0, 0.0, 0.0]) + rng.normal(scale=2.0, size=6)
            request = body.solve(q, wrench, method="qp").wrench.copy()
            body.qp.reset()
            sol = body.solve(q, request, method="qp")
            assert CORE is None or body.qp.iterations == 0
            forces, _, _ = oracle.solve(q, request)
            size = np.abs(request).max()
            np.testing.assert_allclose(sol.forces, forces, rtol=0, atol=1e-12 * size)
            assert sol.residual <= 1e-12 * size
