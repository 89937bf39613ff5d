"""The QP's lexicographic stages (the request exactly, else the closest wrench): ProxQP, DAQP."""

from __future__ import annotations

import functools
import threading
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
from proxsuite import proxqp

from ... import core
from ...exceptions import ConstraintError
from ..tolerances import ACTIVE_TOL, CLOSEST_EPS_ABS, CONFLICT_SHARE, EPS_ABS, FEASIBILITY_TOL
from .exact import exact_answer

#: ProxQP (outer) iterations of one solve, all stages together
ITERATION_BUDGET = 300
#: Stage 1's ProxQP iterations, at most (and half the budget)
EXACT_MAX_ITER = 120
#: The conflict check's ProxQP iterations, at most; it runs only when twice as many are left
CONFLICT_MAX_ITER = 40
#: DAQP's active-set iterations of a stage, at most
DAQP_MAX_ITER = 200
#: DAQP's exit flag of a problem with no feasible point.
DAQP_INFEASIBLE = -1
#: DAQP's closest wrench: ``|x|^2 / 2 + sum_a omega_a (A x - w)_a^2 / (2 eps max omega)``
DAQP_CLOSEST_EPS = 1e-8
#: ProxQP's inner (semismooth Newton) steps per outer iteration, at most.
MAX_ITER_IN = 30
#: In ``sol.active`` when the iteration budget ran out before the last stage converged.
BUDGET_EXHAUSTED = "iteration budget exhausted"

#: DAQP in the compiled core (stage 1 from cold; the closest wrench), or None: ProxQP alone.
DAQP_LEAST_NORM = core.kernel("daqp_least_norm", None)
DAQP_CLOSEST = core.kernel("daqp_closest", None)


@functools.cache
def _identity(size: int) -> np.ndarray:
    """``np.eye(size)``, made once per size (ProxQP copies it)."""
    return np.eye(size)


@dataclass(slots=True)
class Budget:
    """ProxQP (outer) iterations one solve has left (``left``), all stages together."""

    left: int

    def charge(self, used: int) -> None:
        """Take ``used`` iterations off (never below zero)."""
        self.left -= min(used, self.left)


@dataclass(slots=True)
class ProxSlot:
    """One ProxQP workspace of this thread."""

    qp: object = None  # the proxqp.dense.QP, made when ProxQP first runs on this slot
    fresh: bool = True  # until a solve succeeded (and after a failure): start from init
    active: np.ndarray | None = None  # the last certified answer's inequality multipliers


class StageRows(NamedTuple):
    """The scaled rows of one solve, shared by its stages."""

    equality: np.ndarray  # the ``design`` rows that always hold, then the request's rows
    equality_rhs: np.ndarray  # the request's part rewritten in place by the closest stages
    design: int
    inequality: np.ndarray
    lows: np.ndarray
    uppers: np.ndarray


class StageAnswer(NamedTuple):
    """What `ProxStages.solve` hands back: the (scaled) answer, its inequality multipliers."""

    x: np.ndarray
    multipliers: np.ndarray
    exhausted: bool  # the budget ran out first (x: the feasible point of least miss found)


class ProxStages:
    """This thread's ProxQP workspaces of one distribution, and the stages run on them.

    Args:
        row_names: The inequalities' names (for the conflict error).
        reactions: The reaction frames' names (for the conflict error).
    """

    def __init__(self, row_names: Sequence[str], reactions: Sequence[str]):
        self._row_names = row_names
        self._reactions = reactions
        self._local = threading.local()

    def reset(self) -> None:
        """Drop this thread's workspaces: the next solve starts cold."""
        self._local.__dict__.clear()

    def slot(self, key: tuple) -> ProxSlot:
        """This thread's workspace of ``key`` (family, stage, sizes), made on first use."""
        cache = self._local.__dict__.setdefault("qps", {})
        slot = cache.get(key)
        if slot is None:  # its ProxQP workspace is made when ProxQP first runs (_workspace)
            slot = cache[key] = ProxSlot()
        return slot

    def _workspace(self, key: tuple) -> object:
        """The ``proxqp.dense.QP`` of a slot, made on first use (most ticks never run ProxQP)."""
        slot = self.slot(key)
        if slot.qp is None:
            qp = proxqp.dense.QP(*key[2:])
            qp.settings.eps_abs = EPS_ABS if key[1] == "exact" else CLOSEST_EPS_ABS
            qp.settings.eps_rel = 0.0
            qp.settings.max_iter_in = MAX_ITER_IN
            qp.settings.verbose = False
            if key[1] != "exact":  # residuals alone can stop with inactive rows held
                qp.settings.check_duality_gap = True
                qp.settings.eps_duality_gap_abs = CLOSEST_EPS_ABS
                qp.settings.eps_duality_gap_rel = 0.0
            # feasible by construction: no heuristic infeasibility verdicts
            if key[1] in ("reached", "conflict"):
                qp.settings.eps_primal_inf = 0.0
            slot.qp = qp
        return slot.qp

    def _run(self, key, objective, equality, equality_rhs, rows, miss, budget: Budget):
        """Solve one QP in this thread's workspace; None if it has no solution.

        The exact stage warm-starts from the previous answer; the closest-wrench stages start cold
        (warm, ProxQP can stop with inactive rows held). ``miss(x)`` is the largest violation of the
        rows ``x`` must meet; ``budget`` is charged.
        """
        slot = self.slot(key)
        qp, fresh = self._workspace(key), slot.fresh
        warm = key[1] == "exact"
        qp.settings.max_iter = min(EXACT_MAX_ITER, (budget.left + 1) // 2) if warm else budget.left
        if key[1] == "conflict":
            qp.settings.max_iter = min(CONFLICT_MAX_ITER, budget.left)
        bounded = (rows.inequality, rows.lows, rows.uppers)
        if fresh or not warm:
            qp.settings.initial_guess = proxqp.InitialGuess.EQUALITY_CONSTRAINED_INITIAL_GUESS
            precondition = key[1] != "closest"
            qp.init(
                *objective, equality, equality_rhs, *bounded, compute_preconditioner=precondition
            )
        else:  # the objective (I, 0) never changes
            qp.update(None, None, equality, equality_rhs, *bounded)
        qp.solve()
        results = qp.results
        budget.charge(results.info.iter_ext)
        status = results.info.status
        # a feasible closest answer out of iterations is kept; the request exactly, never
        if not (
            status == proxqp.QPSolverOutput.PROXQP_SOLVED
            or (key[1] != "exact" and status == proxqp.QPSolverOutput.PROXQP_MAX_ITER_REACHED)
        ):
            slot.fresh = True  # start the next solve afresh
            return None
        if fresh and warm:  # only after a solve: there is a previous result to start from
            qp.settings.initial_guess = proxqp.InitialGuess.WARM_START_WITH_PREVIOUS_RESULT
            slot.fresh = False
        # ProxQP's answer meets the rows to EPS_ABS: an infeasible request can look solved
        if miss(results.x) > FEASIBILITY_TOL:
            return None
        return results

    def _exact(self, rows: StageRows, weights, x, guess, certify: bool) -> tuple:
        """`exact.exact_answer` on ``rows``: ``(certified, x, z)``."""
        return exact_answer(
            rows.equality, rows.equality_rhs, rows.design, weights, rows.inequality, rows.lows,
            rows.uppers, x, guess, certify, ACTIVE_TOL,
        )  # fmt: skip

    def solve(
        self, path: str, rows: StageRows, miss: Callable, weights, budget: Budget
    ) -> StageAnswer | None:
        """The request exactly with the least norm, else the closest wrench (scaled rows).

        The last certified active set is tried first, then DAQP (with the core), then ProxQP.
        ``path`` names the workspaces' family (``"free"`` or ``"forces"``); ``miss(x, rows)`` is
        the largest violation of the first ``rows`` equality rows and the inequalities;
        ``weights`` weigh the request rows in the closest-wrench stage; ``budget`` is charged.

        Returns:
            A `StageAnswer`, or None when no ``x`` meets the rows.

        Raises:
            ConstraintError: The rows other than the request cannot hold together (named).
        """
        equality, equality_rhs = rows.equality, rows.equality_rhs
        size = equality.shape[1]
        key = (path, "exact", size, len(equality_rhs), len(rows.lows))
        slot = self.slot(key)
        if slot.active is not None:  # the last answer's active set, certified again
            certified, x, z = self._exact(rows, weights, None, slot.active, True)
            if certified:
                slot.active = z
                return StageAnswer(x, z, False)
        if DAQP_LEAST_NORM is not None:  # DAQP from cold, its active set certified exact
            flag, x, guess, _ = DAQP_LEAST_NORM(
                equality, equality_rhs, rows.inequality, rows.lows, rows.uppers, DAQP_MAX_ITER
            )
            if flag == 1:
                certified, x, z = self._exact(rows, weights, x, guess, True)
                if certified:
                    slot.active = z
                    return StageAnswer(x, z, False)
            elif flag == DAQP_INFEASIBLE:  # no x meets the request: the closest wrench
                slot.active = None
                return self._closest_on_daqp(path, rows, miss, weights, budget)
        identity = (_identity(size), np.zeros(size))
        results = self._run(
            key, identity, equality, equality_rhs, rows,
            lambda x: miss(x, len(equality_rhs)), budget,
        )  # fmt: skip
        slot.active = None
        if results is not None:  # exact on its active set (the same whatever the start)
            certified, x, z = self._exact(rows, weights, results.x, results.z, True)
            slot.active = z if certified else None
            return StageAnswer(x, z, False)
        # stage 1's last iterate mostly names the closest answer's active set already
        last = slot.qp.results
        certified, x, z = self._exact(rows, weights, last.x, last.z, False)
        if certified:
            return StageAnswer(x, z, False)
        return self._closest(path, rows, miss, weights, budget, last)

    def _closest_on_daqp(
        self, path: str, rows: StageRows, miss: Callable, weights, budget: Budget
    ) -> StageAnswer | None:
        """The closest wrench of a request DAQP found infeasible, by `DAQP_CLOSEST_EPS`."""
        flag = 0  # no request row (every axis free): only the other rows, which cannot hold
        if rows.design < len(rows.equality_rhs):
            flag, x, guess, _ = DAQP_CLOSEST(
                rows.equality, rows.equality_rhs, rows.design, weights, rows.inequality,
                rows.lows, rows.uppers, DAQP_MAX_ITER, DAQP_CLOSEST_EPS,
            )  # fmt: skip
        if flag == 1:
            certified, x, z = self._exact(rows, weights, x, guess, False)
            if certified:
                return StageAnswer(x, z, False)
        return self._closest(path, rows, miss, weights, budget, None)

    def _check_conflict(self, path: str, rows: StageRows, budget: Budget) -> None:
        """Raise the named conflict when the rows other than the request cannot hold.

        The least squared shift ``s`` of the bounds that lets the rows hold with the design
        equalities, ``min |s|^2`` subject to ``D x = d``, ``lows <= C x + s <= uppers``, is 0 when
        they are consistent, else a Farkas certificate: the rows it moves cannot hold together.
        """
        design, size, m = rows.design, rows.equality.shape[1], len(rows.lows)
        hessian = np.zeros((size + m, size + m))
        hessian[size:, size:] = np.eye(m)
        equality = np.hstack((rows.equality[:design], np.zeros((design, m))))
        shifted_rows = rows._replace(inequality=np.hstack((rows.inequality, np.eye(m))))
        shifted = self._run(
            (path, "conflict", size + m, design, m), (hessian, np.zeros(size + m)), equality,
            rows.equality_rhs[:design], shifted_rows, lambda x: 0.0, budget,
        )  # fmt: skip
        if shifted is None or shifted.info.status != proxqp.QPSolverOutput.PROXQP_SOLVED:
            return
        shift = np.abs(shifted.x[size:])
        largest = float(shift.max(initial=0.0))
        if largest > FEASIBILITY_TOL:
            moved = np.flatnonzero(shift >= CONFLICT_SHARE * largest)
            rank = np.round(shift[moved] / largest, 6)  # equal shifts (a symmetric robot): in order
            names = [self._row_names[i] for i in moved[np.argsort(-rank, kind="stable")]]
            raise ConstraintError(
                f"No distribution over the chains to {list(self._reactions)} meets every "
                "constraint at this configuration, whatever the request: these inequalities "
                "cannot hold together with the natural and design equalities (furthest off first;"
                f" relax one of them): {'; '.join(names)}."
            )

    def _closest(
        self, path, rows: StageRows, miss, weights, budget: Budget, last
    ) -> StageAnswer | None:
        """Stages 2 and 3: the closest reachable wrench, then its least force norm.

        ``last``: stage 1's results (None when stage 1 did not run in ProxQP).
        """
        if budget.left >= 2 * CONFLICT_MAX_ITER:  # rows that cannot hold, whatever the request
            self._check_conflict(path, rows, budget)
        equality, equality_rhs, design = rows.equality, rows.equality_rhs, rows.design
        size = equality.shape[1]
        request, target = equality[design:], equality_rhs[design:].copy()
        weighted = request * weights[:, None]
        converged = proxqp.QPSolverOutput.PROXQP_SOLVED

        def exact(x: np.ndarray, guess: np.ndarray, exhausted: bool) -> StageAnswer:
            """The exact closest answer on the active set ``guess`` names, else ``x``."""
            equality_rhs[design:] = target  # the request (the exact step finds the wrench)
            certified, x, z = self._exact(rows, weights, x, guess, False)
            return StageAnswer(x, z, exhausted and not certified)

        if budget.left == 0:  # the exact stage's last iterate, when it meets the other rows
            if last is not None and miss(last.x, design) <= FEASIBILITY_TOL:
                return exact(last.x.copy(), last.z.copy(), True)
            return None
        closest = self._run(
            (path, "closest", size, design, len(rows.lows)), (request.T @ weighted,
            -(weighted.T @ target)), equality[:design], equality_rhs[:design], rows,
            lambda x: miss(x, design), budget,
        )  # fmt: skip
        if closest is None:
            return None
        answer, multipliers = closest.x.copy(), closest.z.copy()
        solved = closest.info.status == converged
        if budget.left == 0:  # out of iterations: stage 3 (the least norm) cannot run
            return exact(answer, multipliers, True)
        equality_rhs[design:] = request @ answer  # the reachable wrench (in place: miss reads it)
        # rows with a nonzero multiplier hold at every closest answer: held as equalities at
        # their values there, they make stage 3 well posed
        held = np.flatnonzero(np.abs(multipliers) > ACTIVE_TOL)
        tight = np.vstack((equality, rows.inequality[held]))
        bounds = tight[len(equality_rhs) :] @ answer
        reached = self._run(
            (path, "reached", size, len(tight), len(rows.lows)), (_identity(size),
            np.zeros(size)), tight, np.concatenate((equality_rhs, bounds)), rows,
            lambda x: miss(x, len(equality_rhs)), budget,
        )  # fmt: skip
        if reached is None:
            return exact(answer, multipliers, budget.left == 0)
        # the active set: stage 3's rows, and the held rows on stage 2's sides
        guess = reached.z.copy()
        guess[held] = multipliers[held]
        return exact(reached.x, guess, reached.info.status != converged or not solved)
