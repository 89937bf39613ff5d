"""Contact-aware distribution as a quadratic program (``solve(q, w, method="qp")``).

The natural and design constraints stay equalities; the contacts add inequalities:

- a **friction pyramid** at each chain: with ``n`` the contact normal (world z unless one is given
  per reaction, expressed in {O}) and ``t1, t2`` two tangents, ``n . f >= min_normal`` and
  ``|t_k . f| <= mu n . f`` (four faces: an inner pyramid of the cone, exact along ``t1``, ``t2``);
- a **centre of pressure inside the sole** for flat contacts given a sole ``(half_length,
  half_width)``: the moment about the reaction frame's origin, in that frame, satisfies
  ``|m_x| <= half_width f_n`` and ``|m_y| <= half_length f_n``, and the yaw moment
  ``|m_z| <= mu min(half_length, half_width) f_n`` (a conservative contact wrench cone);
- **torque limits** ``|tau_j| <= limit_j`` at the actuated joints (the URDF effort limits, or an
  array).

Objective, on a problem scaled to ``|w| ~ 1``: first the request exactly with the least force
norm, ``min |F|^2`` subject to ``sum_i F_i = w`` on the prescribed axes (the usual case: one
solve, and with no inequality active exactly the partitioned minimum-norm answer); if that has no
solution, the closest feasible wrench, ``min |sum_i F_i - w|^2 + DELTA |F|^2``, and
``sol.residual`` reports the miss. Solved by ProxQP (proxsuite, dense), warm-started from the
previous solve of the same thread.
"""

from __future__ import annotations

import threading

import numpy as np

from ..exceptions import ConstraintError, InvalidInputError
from .linalg import ROUNDING, stable_norm
from .partitioner import RawSolution
from .problem import DistributionProblem
from .qp_compiled import CompiledQPMatrices
from .qp_kernel_answer import finish, violation
from .qp_limits import INFINITY, ContactLimits, kinds, torque_map

#: Weight of the force norm against the miss when the request is infeasible (scaled problem).
DELTA = 1e-6
#: An answer that misses a row by more than this (scaled) is not feasible.
FEASIBILITY_TOL = 1e-8
#: ProxQP's absolute accuracy on the scaled problem.
EPS_ABS = 1e-10
#: ProxQP's iteration budget (outer and inner): a tick never waits on a degenerate problem.
MAX_ITER = 300
#: A multiplier above this (scaled) marks its inequality active.
ACTIVE_TOL = 1e-9


class QPDistribution:
    """The QP distribution of one parallel actuator (one ProxQP workspace per thread).

    Each tick's matrices come from the compiled kernel in the chains' free coordinates when the
    declaration allows it (:mod:`.qp_compiled`: ``F = x0 + N z``, the natural rows eliminated,
    ``|F|^2 = |x0|^2 + |z|^2``), else from numpy over all ``p n`` force entries with the natural
    rows as equalities; both are the same convex program with one answer.

    Args:
        problem: The distribution problem.
        limits: The inequalities.

    Raises:
        InvalidInputError: proxsuite is not installed.

    """

    def __init__(self, problem: DistributionProblem, limits: ContactLimits) -> None:
        try:
            from proxsuite import proxqp
        except ImportError as error:  # pragma: no cover - proxsuite is a dependency
            raise InvalidInputError(
                "method='qp' needs proxsuite (pip install proxsuite)."
            ) from error
        self._proxqp = proxqp
        self.problem = problem
        self.limits = limits
        self._local = threading.local()
        self._identities: dict[int, np.ndarray] = {}
        #: per set of prescribed axes: the rows summing the chains' forces on them
        self._selects: dict[bytes, np.ndarray] = {}
        #: the part of the scale that the declaration fixes: least normal force, limits
        self._static_scale = max(
            limits.min_normal if limits.normal_row else 0.0,
            float(np.abs(limits.limits).max(initial=0.0)),
            float(np.abs(problem.constant_rhs).max(initial=0.0)),
        )
        self.matrices = CompiledQPMatrices(
            problem, **limits.tables, static_scale=self._static_scale,
            rows_in=len(limits.row_names()),
        )  # fmt: skip

    def _identity(self, size: int) -> np.ndarray:
        identity = self._identities.get(size)
        if identity is None:
            identity = self._identities[size] = np.eye(size)
        return identity

    def _workspace(self, key: tuple) -> list:
        cache = getattr(self._local, "qps", None)
        if cache is None:
            cache = self._local.qps = {}
        workspace = cache.get(key)
        if workspace is None:
            qp = self._proxqp.dense.QP(*key[2:])
            qp.settings.eps_abs = EPS_ABS
            qp.settings.eps_rel = 0.0
            qp.settings.max_iter = MAX_ITER
            qp.settings.max_iter_in = MAX_ITER
            qp.settings.verbose = False
            workspace = cache[key] = [qp, True]  # the workspace, and whether it needs init()
        return workspace

    def _run(self, key, objective, equality, equality_rhs, inequality, lows, uppers, miss):
        """Solve one QP in this thread's workspace (warm-started); None if it has no solution.

        The workspace of ``key`` (path, stage, sizes) lives between ticks: ``update`` (the
        objective only in the closest-wrench stage) and a warm start from the previous answer;
        ``init`` only the first time and after a failure. ``miss(x)`` is the largest violation
        of the rows ``x`` must meet.
        """
        proxqp = self._proxqp
        workspace = self._workspace(key)
        qp, fresh = workspace
        if fresh:
            qp.settings.initial_guess = proxqp.InitialGuess.EQUALITY_CONSTRAINED_INITIAL_GUESS
            qp.init(*objective, equality, equality_rhs, inequality, lows, uppers)
        elif key[1] != "closest":  # the objective (I, 0) never changes
            qp.update(None, None, equality, equality_rhs, inequality, lows, uppers)
        else:
            qp.update(*objective, equality, equality_rhs, inequality, lows, uppers)
        qp.solve()
        results = qp.results
        status = results.info.status
        # the closest wrench is an approximation anyway: a feasible answer out of iterations is
        # kept (the request exactly, never: it goes on to the closest wrench)
        if not (
            status == proxqp.QPSolverOutput.PROXQP_SOLVED
            or (key[1] == "closest" and status == proxqp.QPSolverOutput.PROXQP_MAX_ITER_REACHED)
        ):
            workspace[1] = True  # start the next solve afresh
            return None
        if fresh:  # only after a solve: there is a previous result to start from
            qp.settings.initial_guess = proxqp.InitialGuess.WARM_START_WITH_PREVIOUS_RESULT
            workspace[1] = False
        # ProxQP's answer meets the rows to EPS_ABS: an infeasible request can look solved
        if miss(results.x) > FEASIBILITY_TOL:
            return None
        return results

    def _stages(self, path, equality, equality_rhs, design, inequality, lows, uppers, miss):
        """The request exactly with the least norm, else the closest wrench (scaled rows).

        ``equality``: the ``design`` rows that always hold, then the request's rows;
        ``miss(x, rows)``: the largest violation of the first ``rows`` equality rows and the
        inequalities.
        """
        size = equality.shape[1]
        sizes = (size, len(equality_rhs), len(lows))
        results = self._run(
            (path, "exact", *sizes), (self._identity(size), np.zeros(size)), equality,
            equality_rhs, inequality, lows, uppers, lambda x: miss(x, len(equality_rhs)),
        )  # fmt: skip
        if results is not None:
            return results
        # infeasible: the closest wrench (its least-norm weight DELTA is too small to fix the
        # forces well), then the least force norm that produces that wrench exactly
        request, target = equality[design:], equality_rhs[design:]
        objective = (request.T @ request + DELTA * self._identity(size), -(request.T @ target))
        closest = self._run(
            (path, "closest", size, design, len(lows)), objective, equality[:design],
            equality_rhs[:design], inequality, lows, uppers, lambda x: miss(x, design),
        )  # fmt: skip
        if closest is None:
            return None
        answer = closest.x.copy()
        equality_rhs[design:] = request @ answer  # the reachable wrench (in place: miss reads it)
        reached = self._run(
            (path, "reached", *sizes), (self._identity(size), np.zeros(size)), equality,
            equality_rhs, inequality, lows, uppers, lambda x: miss(x, len(equality_rhs)),
        )  # fmt: skip
        return reached if reached is not None else closest

    def _refuse(self) -> ConstraintError:
        names = self.limits.row_names()
        return ConstraintError(
            f"No distribution over the chains to {list(self.problem.reactions)} meets every "
            "constraint at this configuration: the natural and design equalities and the "
            f"inequalities ({', '.join(sorted(set(kinds(names))))}) cannot all hold (e.g. "
            "min_normal with tight torque limits)."
        )

    def solve(
        self, snapshot: object, wrench: np.ndarray, keep: np.ndarray, compiled: bool = True
    ) -> tuple[RawSolution, tuple]:
        """Distribute ``wrench`` with the QP at a snapshot.

        Args:
            snapshot: The tick's :class:`~virtual_actuators.Snapshot`.
            wrench: ``(n,)`` requested wrench.
            keep: ``(n,)`` bool, the prescribed axes.
            compiled: Build the matrices with the compiled kernel when it applies (False: with
                numpy over all force entries, the reference).

        Returns:
            ``(raw solution, (tau, passive torques, produced, requested, residual, scale,
            rounding))`` like the other paths, ``raw.method == "qp"``, ``raw.active`` the names
            of the active inequalities.

        Raises:
            ConstraintError: No distribution meets the equalities and the inequalities here.

        """
        work = None
        if compiled and self.matrices.applicable:
            work = self.matrices.build(snapshot, wrench, keep)
        if work is None:
            return self._solve_numpy(snapshot, wrench, keep)
        buffer, layout, pn, nv = work.buffer, work.layout, work.pn, work.nv
        results = self._stages(
            "free", work.equality, work.equality_rhs, work.design_rows, work.inequality,
            work.lows, work.uppers,
            lambda z, rows: violation(buffer, layout, pn, nv, z, rows),
        )  # fmt: skip
        if results is None:  # the reference decides (and raises) what the fast path cannot
            return self._solve_numpy(snapshot, wrench, keep)
        out, residual, scale, rounding, active = finish(
            buffer, layout, pn, nv, results.x, results.z, work.scale, wrench, keep, ACTIVE_TOL,
            EPS_ABS,
        )  # fmt: skip
        names = self.limits.row_names()
        forces = out[:pn].reshape(self.problem.p, self.problem.n)
        raw = RawSolution(
            forces=forces, method="qp", solver="qp", active=tuple(names[i] for i in active)
        )
        n = len(wrench)
        tau, passive = out[pn : pn + nv], out[pn + nv : pn + 2 * nv]
        produced, requested = out[pn + 2 * nv : pn + 2 * nv + n], out[pn + 2 * nv + n :]
        return raw, (tau, passive, produced, requested, residual, scale, rounding)

    def _solve_numpy(
        self, snapshot: object, wrench: np.ndarray, keep: np.ndarray
    ) -> tuple[RawSolution, tuple]:
        """:meth:`solve` with numpy over all ``p n`` force entries, natural rows as equalities."""
        problem = self.problem
        p, n = problem.p, problem.n
        ev = problem.evaluate(snapshot, check_singular=False)
        natural, natural_rhs = problem.block_natural(ev)
        hard = ev.hard_rows.reshape(len(ev.hard_rhs), p * n)
        select = self._select(keep)
        equality = np.vstack((natural, hard, select))
        equality_rhs = np.concatenate((natural_rhs, ev.hard_rhs, wrench[keep]))
        tmap = torque_map(problem, ev.state.jacobian_o)
        inequality, lows, uppers = self.limits.rows(ev.state, tmap)[:3]
        # scale: the request, spring torques and bounds to ~1 (homogeneous answers)
        scale = max(
            float(np.abs(wrench[keep]).max(initial=0.0)),
            float(np.abs(ev.passive_torque).max(initial=0.0)),
            self._static_scale,
            1e-300,
        )

        equality_rhs = equality_rhs / scale
        lows, uppers = lows / scale, np.minimum(uppers / scale, INFINITY)

        def miss(x: np.ndarray, rows: int) -> float:
            slack = float(np.abs(equality[:rows] @ x - equality_rhs[:rows]).max(initial=0.0))
            if len(lows):
                values = inequality @ x
                slack = max(slack, float(np.max(lows - values)), float(np.max(values - uppers)))
            return slack if np.all(np.isfinite(x)) else np.inf

        results = self._stages(
            "forces", equality, equality_rhs, len(equality_rhs) - len(select), inequality,
            lows, uppers, miss,
        )  # fmt: skip
        if results is None:
            raise self._refuse()
        names = self.limits.row_names()
        x = np.array(results.x) * scale
        active = tuple(names[i] for i in np.flatnonzero(np.abs(results.z) > ACTIVE_TOL))
        forces = x.reshape(p, n)
        tau = np.where(problem.actuated_mask, tmap @ x, 0.0)
        produced = forces.sum(axis=0)
        residual = stable_norm((produced - wrench)[keep])
        request = stable_norm(wrench[keep])
        output = stable_norm(produced[keep])
        rounding = ROUNDING * float(np.abs(x).max(initial=0.0)) + EPS_ABS * 10 * scale
        requested = np.where(keep, wrench, produced)
        raw = RawSolution(forces=forces, method="qp", solver="qp", active=active)
        return raw, (tau, ev.passive_torque, produced, requested, residual,
                     max(request, output), rounding)  # fmt: skip

    def _select(self, keep: np.ndarray) -> np.ndarray:
        """``(k, p n)``: the rows summing the chains' forces on the prescribed axes."""
        select = self._selects.get(keep.tobytes())
        if select is None:
            p, n = self.problem.p, self.problem.n
            select = np.zeros((int(keep.sum()), p * n))
            for r, axis in enumerate(np.flatnonzero(keep)):
                select[r, axis::n] = 1.0
            self._selects[keep.tobytes()] = select
        return select


__all__ = ["ContactLimits", "QPDistribution", "torque_map"]
