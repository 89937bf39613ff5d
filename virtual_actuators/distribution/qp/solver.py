"""Contact-aware distribution as a lexicographic quadratic program (``solve(q, w, method="qp")``).

The request exactly with the least force norm, else the closest wrench, under the inequalities
(the contacts' rows and the torque limits, named; docs/concepts.md, "Contacts as inequalities").
"""

from __future__ import annotations

import threading
from collections.abc import Mapping, Sequence
from typing import Any, NamedTuple

import numpy as np

from ...contacts import Constraint, ContactSet, TorqueLimits
from ...exceptions import ConstraintError, InvalidAxisError, InvalidInputError
from ...vocabulary.arguments import as_float_array, check_number, describe
from ..methods import Request
from ..problem import DistributionProblem
from ..result import RawSolution, TickResult, close_tick
from ..tolerances import ACTIVE_TOL, EPS_ABS, EXACT_TOL, INFINITY, TINY
from .compiled import Answer, CompiledQPMatrices
from .stages import BUDGET_EXHAUSTED, ITERATION_BUDGET, Budget, ProxStages, StageRows


class ContactLimits:
    """The inequalities of a parallel actuator's QP: its contacts' rows, then torque limits.

    Args:
        problem: The distribution problem.
        contacts: The actuator's contacts (`declare`).
        torque_limits: False (none), True (URDF effort limits) or ``(nv,)`` limits [N m, N].

    Raises:
        InvalidInputError: Bad torque limits.
    """

    def __init__(
        self,
        problem: DistributionProblem,
        contacts: ContactSet,
        torque_limits: bool | Sequence[float] | np.ndarray,
    ) -> None:
        self.contacts = contacts
        on_chain = np.zeros(problem.model.nv, dtype=bool)
        on_chain[np.concatenate(problem.kinematics.chain_columns)] = True
        limits = TorqueLimits(problem.model, torque_limits, on_chain, problem.actuated_mask)
        self.torque_limits = limits
        #: the declaration's tables for the compiled path
        self.tables = {**contacts.tables(), "limited_v": limits.limited_v, "limits": limits.limits}
        #: the inequality rows' names, in the order both paths build the rows
        self.row_names = [*contacts.names, *limits.names(problem.joint_name)]

    def rows(self, state: object, torque_map: np.ndarray) -> Constraint:
        """``lows <= G x <= uppers`` over ``x = forces.ravel()``, with a name per row.

        Args:
            state: The tick's kinematic state (rotations, offsets, Jacobian rows in {O}).
            torque_map: ``(nv, p n)`` joint torques of ``x``.
        """
        offsets = state.offsets_o() if self.contacts.sole_rows else None
        one_sided = self.contacts.rows(state.rotation_o, state.rotation_a, offsets)
        rows, low, upper = self.torque_limits.rows(torque_map)  # two-sided
        return Constraint(
            np.vstack((one_sided.G, rows)),
            np.concatenate((one_sided.lows, low)),
            np.concatenate((np.full(len(one_sided.lows), INFINITY), upper)),
            self.row_names,
        )


def torque_map(problem: DistributionProblem, jacobian_o: np.ndarray) -> np.ndarray:
    """``(nv, p n)``: the joint torques ``sum_i J_i^T F_i`` as a matrix over ``F.ravel()``."""
    p, n = problem.p, problem.n
    matrix = np.zeros((problem.model.nv, p * n))
    for group in problem.groups:
        columns = group.columns  # (g, k): each chain's velocity columns
        targets = group.chains[:, None, None] * n + np.arange(n)[None, None, :]
        share = jacobian_o[:, columns].transpose(1, 2, 0) * group.signs[:, :, None]  # (g, k, n)
        matrix[columns[:, :, None], targets] += share
    return matrix


def check_weights(weights: object, axes: Sequence[str]) -> np.ndarray:
    """``weights`` as a read-only ``(n,)`` array of finite numbers > 0 over ``axes``.

    Args:
        weights: ``{axis: weight}`` (the axes not named keep 1), or ``n`` numbers over ``axes``.
        axes: The actuator's axes.

    Raises:
        InvalidAxisError: A key of the dict is not one of ``axes``.
        InvalidInputError: A weight that is not a finite number > 0 (the message names its
            axis), an array of the wrong length, or neither a dict nor numbers.
    """
    axes = tuple(axes)
    if not isinstance(weights, Mapping):  # n numbers: checked by axis as a dict's values
        expected = f"{len(axes)} numbers > 0 (one per axis {axes}) or a dict {{axis: weight}}"
        values = as_float_array(weights, "weights", expected).reshape(-1)
        if values.shape != (len(axes),):
            raise InvalidInputError(f"weights must be {expected}, got {describe(weights)}.")
        weights = dict(zip(axes, values.tolist(), strict=True))
    out = np.ones(len(axes))
    for axis, value in weights.items():
        if not isinstance(axis, str) or axis not in axes:
            raise InvalidAxisError(
                f"weights names axis {axis!r}, not one of this actuator's axes {axes}."
            )
        out[axes.index(axis)] = check_number(value, f"weights[{axis!r}]", positive=True)
    out.setflags(write=False)
    return out


class PlanTables(NamedTuple):
    """What a compiled plan runs a request with on the last certified active set."""

    core: Any  # the core's ``QP``
    workspace: Any  # this thread's workspace (its buffer the core's scratch)
    keep: np.ndarray  # the kept request rows, 0/1 integers
    weights: np.ndarray  # the kept rows' weights
    tolerances: np.ndarray  # (active, exact, accuracy)
    slot: Any  # the slot whose ``active`` is the warm start


class QPDistribution:
    """The QP distribution of one parallel actuator (one ProxQP workspace per thread).

    Args:
        problem: The distribution problem.
        limits: The inequalities.
        weights: Per-axis weights of the closest-wrench stage (a dict by axis name or an array over
            the axes); None for 1 on every axis.

    Raises:
        InvalidInputError: Bad ``weights``.
        InvalidAxisError: ``weights`` names an axis the actuator lacks.
    """

    def __init__(
        self, problem: DistributionProblem, limits: ContactLimits, weights: object = None
    ) -> None:
        self.problem = problem
        self.limits = limits
        #: the closest-wrench stage's weight per axis (read-only)
        self.weights = check_weights({} if weights is None else weights, problem.axes)
        self._local = threading.local()
        #: this thread's ProxQP workspaces and the stages run on them
        self.stages = ProxStages(limits.row_names, problem.reactions)
        #: ProxQP iterations one solve may use, all stages together
        self.iteration_budget = ITERATION_BUDGET
        #: the active rows' names by their indices' bytes (the sets recur tick after tick)
        self._active_names: dict[bytes, tuple[str, ...]] = {}
        #: the scale's static part: the least normal force and constant right-hand sides
        self._static_scale = max(
            limits.contacts.min_normal if limits.contacts.normal_row else 0.0,
            float(np.abs(problem.constant_rhs).max(initial=0.0)),
        )
        self.matrices = CompiledQPMatrices(
            problem, limits.tables, self._static_scale, len(limits.row_names)
        )

    @property
    def iterations(self) -> int:
        """ProxQP iterations (outer) of this thread's last solve, all stages together."""
        return getattr(self._local, "iterations", 0)

    def reset(self) -> None:
        """Drop this thread's ProxQP workspaces and count: the next solve starts cold."""
        self._local.__dict__.clear()
        self.stages.reset()

    def _refuse(self, exhausted: bool = False) -> ConstraintError:
        if exhausted:
            return ConstraintError(
                f"No distribution over the chains to {list(self.problem.reactions)} meeting "
                f"every constraint was found within the iteration budget "
                f"({self.iteration_budget} ProxQP iterations; raise `qp.iteration_budget`)."
            )
        words = ("friction", "normal", "moment", "torque")  # the kinds of inequality
        kinds = {word for name in self.limits.row_names for word in words if word in name}
        return ConstraintError(
            f"No distribution over the chains to {list(self.problem.reactions)} meets every "
            "constraint at this configuration: the natural and design equalities and the "
            f"inequalities ({', '.join(sorted(kinds or ['none']))}) cannot all hold (e.g. "
            "min_normal with tight torque limits)."
        )

    def solve(self, snapshot: object, wrench: np.ndarray, request: Request) -> TickResult:
        """Distribute ``wrench`` with the QP at a snapshot.

        Args:
            snapshot: The tick's [`Snapshot`][].
            wrench: ``(n,)`` requested wrench.
            request: The prescribed axes, whether to use the compiled kernel, per-axis weights.

        Returns:
            The `TickResult`: ``raw.method == "qp"``, ``raw.active`` the active inequalities' names.

        Raises:
            ConstraintError: No distribution meets the equalities and the inequalities here (the
                message names the conflicting inequalities), or none was found within
                ``iteration_budget`` ProxQP iterations.
        """
        keep = request.keep
        weights = self._weights(request)
        if request.compiled and self.matrices.applicable:  # most ticks: one compiled call
            tick = self._again(snapshot, wrench, keep, weights)
            if tick is not None:
                return tick
        budget = Budget(max(int(self.iteration_budget), 1))
        try:
            return self._solve(snapshot, wrench, keep, request.compiled, weights, budget)
        finally:
            self._local.iterations = max(int(self.iteration_budget), 1) - budget.left

    def plan_tables(self, request: Request) -> PlanTables | None:
        """The tables a compiled plan runs ``request`` with, or None without a compiled path."""
        if not request.compiled or self.matrices.core is None:  # None unless applicable
            return None
        work, slot = self._hot(request.keep)
        tolerances = np.array([ACTIVE_TOL, EXACT_TOL, EPS_ABS])
        keep = np.asarray(request.keep, dtype=np.int64)
        return PlanTables(self.matrices.core, work, keep, self._weights(request), tolerances, slot)

    def answer_tick(self, out: np.ndarray, norms: tuple, active: np.ndarray) -> TickResult:
        """The `TickResult` of an answer the core read out."""
        return self._tick(Answer(out, *norms, active), False)

    def _weights(self, request: Request) -> np.ndarray:
        """The weights of ``request``'s rows (this thread's last, kept)."""
        hot = getattr(self._local, "request", None)  # this thread's last request and weights
        if hot is None or hot[0] is not request:
            weights = self.weights if request.weights is None else request.weights
            hot = self._local.request = (request, weights[request.keep])
        return hot[1]

    def solve_configuration(
        self, q: np.ndarray, wrench: np.ndarray, request: Request
    ) -> TickResult | None:
        """`solve` at a checked configuration in one compiled call, or None."""
        tree = self.problem.kinematics.tree.core_tree
        if not request.compiled or self.matrices.core is None or tree is None:
            return None
        return self._again(q, wrench, request.keep, self._weights(request), tree)

    def _solve(self, snapshot, wrench, keep, compiled, weights, budget):
        """`solve` once `_again` answered None."""
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

    def _again(self, snapshot, wrench, keep, weights, tree=None) -> TickResult | None:
        """The tick on the last certified active set, in one compiled call (no ProxQP), or None.

        ``snapshot`` is a checked configuration when ``tree`` is the core's ``Tree``.
        """
        work, slot = self._hot(keep)
        if slot.active is None:
            return None
        answer = self.matrices.again(snapshot, wrench, keep, work, weights, slot.active, tree)
        if answer is None:
            return None
        self._local.iterations = 0
        return self._tick(answer, False)

    def _hot(self, keep: np.ndarray) -> tuple:
        """This thread's workspace for ``keep`` and the stage-1 slot of the same sizes."""
        hot = getattr(self._local, "workspace", None)  # for the last prescribed axes
        if hot is None or hot[0] is not keep:
            work = self.matrices.workspace(keep)
            sizes = (work.equality.shape[1], len(work.equality_rhs), len(work.lows))
            slot = self.stages.slot(("free", "exact", *sizes))
            hot = self._local.workspace = (keep, work, slot)
        return hot[1], hot[2]

    def _tick(self, answer: Answer, exhausted: bool) -> TickResult:
        """The `TickResult` of a read-out answer (``exhausted``: the budget ran out)."""
        p, n = self.problem.p, self.problem.n
        forces = answer.out[: p * n].reshape(p, n)
        active = self._active(answer.active, exhausted)
        raw = RawSolution(forces, method="qp", solver="qp", active=active)
        return TickResult.from_buffer(
            raw, answer.out, answer.residual, answer.scale, answer.rounding, compiled=False
        )

    def _active(self, rows: np.ndarray, exhausted: bool) -> tuple[str, ...]:
        """The names of the active inequality ``rows``, then `BUDGET_EXHAUSTED` if ``exhausted``."""
        key = rows.tobytes()
        active = self._active_names.get(key)
        if active is None:
            names = self.limits.row_names
            active = tuple([names[i] for i in rows.tolist()])
            if len(self._active_names) >= 256:
                self._active_names.clear()
            self._active_names[key] = active
        return (*active, BUDGET_EXHAUSTED) if exhausted else active

    def _solve_numpy(
        self,
        snapshot: object,
        wrench: np.ndarray,
        keep: np.ndarray,
        weights: np.ndarray,
        budget: Budget,
    ) -> TickResult:
        """`solve` with numpy over all ``p n`` force entries, natural rows as equalities."""
        if budget.left == 0:
            raise self._refuse(exhausted=True)
        problem = self.problem
        p, n = problem.p, problem.n
        ev = problem.evaluate(snapshot, check_singular=False)
        exact, exact_rhs = problem.exact_rows(ev)
        equality = np.vstack((exact, problem.sum_rows(keep)))
        equality_rhs = np.concatenate((exact_rhs, wrench[keep]))
        tmap = torque_map(problem, ev.state.jacobian_o)
        limits = self.limits.rows(ev.state, tmap)
        inequality, lows, uppers = limits.G, limits.lows, limits.uppers
        # scale: the request, spring torques and bounds to ~1 (homogeneous answers)
        scale = max(
            float(np.abs(wrench[keep]).max(initial=0.0)),
            float(np.abs(ev.passive_torque).max(initial=0.0)),
            self._static_scale,
            TINY,
        )

        equality_rhs = equality_rhs / scale
        with np.errstate(over="ignore"):  # an open bound over a tiny scale: clipped to INFINITY
            lows, uppers = np.maximum(lows / scale, -INFINITY), np.minimum(uppers / scale, INFINITY)

        def miss(x: np.ndarray, rows: int) -> float:
            slack = float(np.abs(equality[:rows] @ x - equality_rhs[:rows]).max(initial=0.0))
            if len(lows):
                values = inequality @ x
                slack = max(slack, float(np.max(lows - values)), float(np.max(values - uppers)))
            return slack if np.all(np.isfinite(x)) else np.inf

        rows = StageRows(equality, equality_rhs, len(exact_rhs), inequality, lows, uppers)
        results = self.stages.solve("forces", rows, miss, weights, budget)
        if results is None:
            raise self._refuse(exhausted=budget.left == 0)
        x = results.x * scale
        rows = np.flatnonzero(np.abs(results.multipliers) > ACTIVE_TOL)
        active = self._active(rows, results.exhausted)
        raw = RawSolution(x.reshape(p, n), method="qp", solver="qp", active=active)
        return close_tick(
            raw,
            wrench,
            keep,
            lambda forces: tmap @ forces.ravel(),
            problem.actuated_mask,
            ev.passive_torque,
            accuracy=EPS_ABS * 10 * scale,
        )
