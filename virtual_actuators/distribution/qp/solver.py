"""Contact-aware distribution as a quadratic program (``solve(q, w, method="qp")``).

The natural and design constraints stay equalities; the contacts add inequalities:
- a **friction pyramid** at each chain: with ``n`` the contact normal (world z; or a world vector
  given per reaction; or, ``"frame"``, the reaction frame's z axis at this tick) and ``t1, t2``
  two tangents fixed in the world (``t1 = n x e`` normalised, ``e`` the world x axis, or y when
  ``|n_x| >= 0.9``; ``t2 = n x t1``: world y and -x about world z), ``n . f >= min_normal`` and
  ``|t_k . f| <= mu n . f`` (four faces: the pyramid circumscribing the cone, exact along
  ``t1``, ``t2``, up to ``sqrt(2) mu`` on the diagonals between them). The pyramid is built in
  world axes and then turned into {O}'s: it is the contact's, and the same physical request
  gives the same forces whatever frame {O} the wrench is written in;
- a **centre of pressure inside the sole** for flat contacts given a sole ``(half_length,
  half_width)``: the moment about the reaction frame's origin, in that frame, satisfies
  ``|m_x| <= half_width f_n`` and ``|m_y| <= half_length f_n``, and the yaw moment
  ``|m_z| <= mu min(half_length, half_width) f_n`` (a conservative contact wrench cone);
- **torque limits** ``|tau_j| <= limit_j`` at the actuated joints that a chain moves (the URDF
  effort limits, or an array).

Objective, lexicographic, on the problem divided by its scale (the largest of the request, the
spring torques, the least normal force and the constant design right-hand sides; not the torque
limits, which may lie far from every answer):

1. the request exactly with the least force norm, ``min |F|^2`` subject to ``sum_i F_i = w`` on
   the prescribed axes (the usual case: one solve, and with no inequality active exactly the
   partitioned minimum-norm answer);
2. if that has no solution, the closest reachable wrench in the weighted least-squares sense,
   ``min sum_a weight_a (sum_i F_ia - w_a)^2`` subject to the other rows (a convex QP whose
   Hessian is singular in ``F``; its wrench ``A F*`` is unique because the weights are > 0, its
   forces need not be);
3. the least force norm that produces that wrench exactly, ``min |F|^2`` subject to
   ``sum_i F_i = A F*`` and the inequalities whose multipliers stage 2 found nonzero held as
   equalities (they hold at every closest answer, so the feasible set is unchanged, but without
   them ProxQP meets the rows only at the cones' edges); ``sol.residual`` reports the miss.

No stage mixes the miss and the force norm in one objective. Solved by ProxQP (proxsuite,
dense): stage 1 warm-started from the previous solve of the same thread, stages 2 and 3 (only on
infeasible requests) from cold, to ``CLOSEST_EPS_ABS`` with ProxQP's duality-gap check. With
the compiled core, stage 1 runs first in DAQP (a dense dual active-set solver built into the
core) from cold, at most ``DAQP_MAX_ITER`` iterations; when DAQP finds the request infeasible,
stages 2 and 3 run in DAQP too (from cold, at most ``DAQP_MAX_ITER`` iterations, the closest
wrench regularised by a little of the least norm: ``DAQP_CLOSEST_EPS``), and stage 1 does not
run in ProxQP. ProxQP runs only when the exact step does not certify DAQP's answer (ProxQP
remains the reference: ``VA_CORE=0``).
**Exact answers.** ProxQP stops at an absolute accuracy, from a start that depends on the
thread's previous solve. Its multipliers name the active inequalities, and on that active set
`exact_step` computes stage 1's answer (or stages 2 and 3 at once) by linear
algebra, kept only when the KKT conditions hold to ``EXACT_TOL`` of the scale (every row met,
every active row's multiplier of the right sign; up to ``EXACT_STEPS`` corrections of the active
set, else ProxQP's answer stands). An answer is then the optimum to rounding: within 1e-8 of
``max(|w|, the active bounds)`` for requests from 1e-6 to 1e6, and the same, to 1e-9 ``|w|``,
whatever was solved before (warm or cold start, any thread). When stage 1 fails, its last
iterate mostly names the closest answer's active set already: certified there, that answer ends
the solve (stages 2 and 3 run only when it is not).
Before ProxQP, the thread's last certified active set is tried on the tick's rows: certified,
it gives the same answer (the KKT conditions name one optimum) by linear algebra alone (a compiled
plan runs that step in the core: `plan_tables`).

**Rows that cannot hold.** When stage 1 fails, the other rows are checked first (`conflict`:
the least squared shift of the inequalities' bounds that lets them hold with the equalities):
if they cannot hold together, ``ConstraintError`` names them (each foot's least normal force and
the knees' torque limits, say); the iteration-budget error is kept for a solve that did not
converge.

Worst case: at most ``ITERATION_BUDGET`` ProxQP (outer) iterations over the stages, each of
at most ``MAX_ITER_IN`` inner steps (stage 1 at most ``EXACT_MAX_ITER`` and half the budget, the
rows' check ``CONFLICT_MAX_ITER``); with the core, before them, two DAQP solves at most.
When the budget runs out: the exact answer on the last feasible iterate's active set if it is
certified, else that iterate (meeting every row to ``FEASIBILITY_TOL``) with its residual and
``BUDGET_EXHAUSTED`` in ``sol.active``; ``ConstraintError`` if none was feasible.
"""

from __future__ import annotations

import threading

import numpy as np

from ...exceptions import ConstraintError, InvalidInputError
from ..methods import Request
from ..problem import DistributionProblem
from ..result import RawSolution, TickResult, close_tick
from ..tolerances import ACTIVE_TOL, EPS_ABS, EXACT_TOL, INFINITY
from .buffer import Answer
from .compiled import CompiledQPMatrices
from .limits import ContactLimits, kinds, torque_map
from .stage_types import Budget, PlanTables, StageRows
from .stages import BUDGET_EXHAUSTED, ITERATION_BUDGET, ProxStages
from .weights import check_weights


class QPDistribution:
    """The QP distribution of one parallel actuator (one ProxQP workspace per thread).

    Each tick's matrices come from the compiled kernel in the chains' free coordinates when the
    declaration allows it (`compiled`: ``F = x0 + N z``, the natural rows eliminated,
    ``|F|^2 = |x0|^2 + |z|^2``), else from numpy over all ``p n`` force entries with the natural
    rows as equalities; both are the same convex program with one answer.

    Args:
        problem: The distribution problem.
        limits: The inequalities.
        weights: Per-axis weights of the closest-wrench stage (`weights.check_weights`:
            a dict by axis name or an array over the axes); None for 1 on every axis.

    Raises:
        InvalidInputError: proxsuite is not installed; bad ``weights``.
        InvalidAxisError: ``weights`` names an axis the actuator lacks.
    """

    def __init__(
        self, problem: DistributionProblem, limits: ContactLimits, weights: object = None
    ) -> None:
        try:
            from proxsuite import proxqp
        except ImportError as error:  # pragma: no cover - proxsuite is a dependency
            raise InvalidInputError(
                "method='qp' needs proxsuite (pip install proxsuite)."
            ) from error
        self._proxqp = proxqp
        self.problem = problem
        self.limits = limits
        #: the closest-wrench stage's weight per axis (read-only)
        self.weights = check_weights({} if weights is None else weights, problem.axes)
        self._local = threading.local()
        #: this thread's ProxQP workspaces and the stages run on them
        self.stages = ProxStages(proxqp, limits.row_names(), problem.reactions)
        #: ProxQP iterations one solve may use, all stages together (:data:`ITERATION_BUDGET`)
        self.iteration_budget = ITERATION_BUDGET
        #: per set of prescribed axes: the rows summing the chains' forces on them
        self._selects: dict[bytes, np.ndarray] = {}
        #: the active rows' names by their indices' bytes (the sets recur tick after tick)
        self._active_names: dict[bytes, tuple[str, ...]] = {}
        #: the part of the scale that the declaration fixes: the least normal force and the
        #: constant right-hand sides (not the torque limits: a limit that does not bind would
        #: set the accuracy of every answer below it)
        self._static_scale = max(
            limits.min_normal if limits.normal_row else 0.0,
            float(np.abs(problem.constant_rhs).max(initial=0.0)),
        )
        self.matrices = CompiledQPMatrices(
            problem, **limits.tables, static_scale=self._static_scale,
            rows_in=len(limits.row_names()),
        )  # fmt: skip

    @property
    def iterations(self) -> int:
        """ProxQP iterations (outer) of this thread's last solve, all stages together."""
        return getattr(self._local, "iterations", 0)

    def reset(self) -> None:
        """Drop this thread's ProxQP workspaces and count: the next solve starts cold."""
        self._local.__dict__.clear()
        self.stages.reset()

    def _refuse(self, exhausted: bool = False) -> ConstraintError:
        names = self.limits.row_names()
        if exhausted:
            return ConstraintError(
                f"No distribution over the chains to {list(self.problem.reactions)} meeting "
                f"every constraint was found within the iteration budget "
                f"({self.iteration_budget} ProxQP iterations; raise `qp.iteration_budget`)."
            )
        return ConstraintError(
            f"No distribution over the chains to {list(self.problem.reactions)} meets every "
            "constraint at this configuration: the natural and design equalities and the "
            f"inequalities ({', '.join(sorted(set(kinds(names))))}) cannot all hold (e.g. "
            "min_normal with tight torque limits)."
        )

    def solve(self, snapshot: object, wrench: np.ndarray, request: Request) -> TickResult:
        """Distribute ``wrench`` with the QP at a snapshot (the ``"qp"`` backend).

        Args:
            snapshot: The tick's [`Snapshot`][].
            wrench: ``(n,)`` requested wrench.
            request: The prescribed axes (``keep``); ``compiled``: build the matrices with the
                compiled kernel when it applies (False: with numpy over all force entries, the
                reference); ``weights``: ``(n,)`` checked per-axis weights of the
                closest-wrench stage for this solve (`weights.check_weights`), None: the
                declaration's.

        Returns:
            The `TickResult`, like the other
            paths: ``raw.method == "qp"``, ``raw.active`` the names of the active inequalities.

        Raises:
            ConstraintError: No distribution meets the equalities and the inequalities here
                (the message names the inequalities that conflict when they cannot hold
                whatever the request), or none was found within ``iteration_budget`` ProxQP
                iterations.
        """
        keep = request.keep
        weights = self._weights(request)
        tried = request.compiled and self.matrices.applicable
        if tried:  # most ticks of a walk: the last certified active set, one compiled call
            tick = self._again(snapshot, wrench, keep, weights)
            if tick is not None:
                self._local.iterations = 0
                return tick
        budget = Budget(max(int(self.iteration_budget), 1))
        try:
            return self._solve(snapshot, wrench, keep, request.compiled, weights, budget)
        finally:
            self._local.iterations = max(int(self.iteration_budget), 1) - budget.left

    def plan_tables(self, request: Request) -> PlanTables | None:
        """What a compiled plan runs ``request`` with on the last certified active set, or None.

        Returns:
            The `PlanTables` (the slot's ``active`` None before the first certified answer);
            None: no compiled path.
        """
        if not request.compiled or self.matrices.core is None or not self.matrices.applicable:
            return None
        work, slot = self._hot(request.keep)
        tolerances = np.array([ACTIVE_TOL, EXACT_TOL, EPS_ABS])
        keep = np.asarray(request.keep, dtype=np.int64)
        return PlanTables(self.matrices.core, work, keep, self._weights(request), tolerances, slot)

    def answer_tick(self, out: np.ndarray, norms: tuple, active: np.ndarray) -> TickResult:
        """The `TickResult` of an answer the core read out (``out``, its norms, active rows)."""
        return self._tick(Answer(out, *norms, active), False)

    def _weights(self, request: Request) -> np.ndarray:
        """The request rows' weights of ``request`` (this thread's last, kept)."""
        hot = getattr(self._local, "request", None)  # this thread's last request and weights
        if hot is None or hot[0] is not request:
            weights = (self.weights if request.weights is None else request.weights)
            hot = self._local.request = (request, weights[request.keep])
        return hot[1]

    def solve_configuration(
        self, q: np.ndarray, wrench: np.ndarray, request: Request
    ) -> TickResult | None:
        """`solve` at a checked configuration in one compiled call, or None.

        The compiled core's kinematics and `_again` in one call (the same kernels, hence
        the same bits, as `solve` on a snapshot of ``q``); None when the core does not
        apply or the last certified active set does not hold (the caller builds the snapshot
        and calls `solve`).
        """
        matrices, tree = self.matrices, self.problem.kinematics.tree.core_tree
        if not request.compiled or matrices.core is None or tree is None:
            return None
        work, slot = self._hot(request.keep)
        if slot.active is None:
            return None
        answer = matrices.again(q, wrench, request.keep, work, self._weights(request),
                                slot.active, tree)  # fmt: skip
        if answer is None:
            return None
        self._local.iterations = 0
        return self._tick(answer, False)

    def _solve(self, snapshot, wrench, keep, compiled, weights, budget):
        """`solve` with its checked weights and its `Budget`, once `_again` answered None."""
        work = None
        if compiled and self.matrices.applicable:
            work = self.matrices.build(snapshot, wrench, keep)
        if work is None:
            return self._solve_numpy(snapshot, wrench, keep, weights, budget)
        rows = StageRows(work.equality, work.equality_rhs, work.design_rows, work.inequality,
                         work.lows, work.uppers)  # fmt: skip
        results = self.stages.solve("free", rows, work.violation, weights, budget)
        if results is None:  # the reference decides (and raises) what the fast path cannot
            return self._solve_numpy(snapshot, wrench, keep, weights, budget)
        answer = work.finish(results.x, results.multipliers, wrench, keep)
        return self._tick(answer, results.exhausted)

    def _again(self, snapshot, wrench, keep, weights) -> TickResult | None:
        """The tick on the last certified answer's active set, in one compiled call, or None.

        The core's ``again`` builds the matrices, certifies that active set on them and
        reads the answer out: the first try of `stages.ProxStages.solve` without its
        Python (most ticks of a walk). None: no certified answer yet in this thread's
        workspace, an active set that changed, or matrices that need the numpy path; the
        stages decide then.
        """
        work, slot = self._hot(keep)
        if slot.active is None:
            return None
        answer = self.matrices.again(snapshot, wrench, keep, work, weights, slot.active)
        return None if answer is None else self._tick(answer, False)

    def _hot(self, keep: np.ndarray) -> tuple:
        """This thread's workspace for ``keep`` and the stage-1 slot of the same sizes."""
        hot = getattr(self._local, "workspace", None)  # for the last prescribed axes
        if hot is None or hot[0] is not keep:
            work = self.matrices.workspace(keep)
            slot = self.stages.exact_slot(
                "free", work.equality.shape[1], len(work.equality_rhs), len(work.lows)
            )
            hot = self._local.workspace = (keep, work, slot)
        return hot[1], hot[2]

    def _tick(self, answer: Answer, exhausted: bool) -> TickResult:
        """The `TickResult` of a read-out answer (``exhausted``: the budget ran out)."""
        p, n = self.problem.p, self.problem.n
        key = answer.active.tobytes()
        active = self._active_names.get(key)
        if active is None:
            names = self.limits.row_names()
            active = tuple([names[i] for i in answer.active.tolist()])
            if len(self._active_names) >= 256:
                self._active_names.clear()
            self._active_names[key] = active
        if exhausted:
            active += (BUDGET_EXHAUSTED,)
        raw = RawSolution(
            forces=answer.out[: p * n].reshape(p, n), method="qp", solver="qp", active=active
        )
        # compiled=False: the matrices are compiled, the solve is ProxQP's (as before)
        return TickResult.from_buffer(
            raw, answer.out, answer.residual, answer.scale, answer.rounding, compiled=False
        )

    def _solve_numpy(
        self,
        snapshot: object,
        wrench: np.ndarray,
        keep: np.ndarray,
        weights: np.ndarray,
        budget: Budget,
    ) -> TickResult:
        """`solve` with numpy over all ``p n`` force entries, natural rows as equalities.

        Raises:
            ConstraintError: No distribution meets the rows, or none was found before the
                iteration budget ran out.
        """
        if budget.left == 0:
            raise self._refuse(exhausted=True)
        problem = self.problem
        p, n = problem.p, problem.n
        ev = problem.evaluate(snapshot, check_singular=False)
        natural, natural_rhs = problem.block_natural(ev)
        hard = ev.hard_rows.reshape(len(ev.hard_rhs), p * n)
        select = self._select(keep)
        equality = np.vstack((natural, hard, select))
        equality_rhs = np.concatenate((natural_rhs, ev.hard_rhs, wrench[keep]))
        tmap = torque_map(problem, ev.state.jacobian_o)
        limits = self.limits.rows(ev.state, tmap)
        inequality, lows, uppers = limits.G, limits.lows, limits.uppers
        # scale: the request, spring torques and bounds to ~1 (homogeneous answers)
        scale = max(
            float(np.abs(wrench[keep]).max(initial=0.0)),
            float(np.abs(ev.passive_torque).max(initial=0.0)),
            self._static_scale,
            1e-300,
        )

        equality_rhs = equality_rhs / scale
        lows, uppers = np.maximum(lows / scale, -INFINITY), np.minimum(uppers / scale, INFINITY)

        def miss(x: np.ndarray, rows: int) -> float:
            slack = float(np.abs(equality[:rows] @ x - equality_rhs[:rows]).max(initial=0.0))
            if len(lows):
                values = inequality @ x
                slack = max(slack, float(np.max(lows - values)), float(np.max(values - uppers)))
            return slack if np.all(np.isfinite(x)) else np.inf

        rows = StageRows(equality, equality_rhs, len(equality_rhs) - len(select), inequality,
                         lows, uppers)  # fmt: skip
        results = self.stages.solve("forces", rows, miss, weights, budget)
        if results is None:
            raise self._refuse(exhausted=budget.left == 0)
        names = self.limits.row_names()
        x = results.x * scale
        active = tuple(names[i] for i in np.flatnonzero(np.abs(results.multipliers) > ACTIVE_TOL))
        active += (BUDGET_EXHAUSTED,) if results.exhausted else ()
        raw = RawSolution(forces=x.reshape(p, n), method="qp", solver="qp", active=active)
        return close_tick(
            raw,
            wrench,
            keep,
            lambda forces: tmap @ forces.ravel(),
            problem.actuated_mask,
            ev.passive_torque,
            accuracy=EPS_ABS * 10 * scale,
        )

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
