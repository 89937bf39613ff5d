"""The real-time path of a parallel actuator's solve: tables built once, one compiled call a tick.

Without the core, or when the core hands a tick back, `PartitionedSolver` decides with numpy. A
`BufferSolve` builds a request's [`Solution`][] straight from the core's output buffer.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...core import CORE, has
from ..methods import Request
from ..problem import DistributionProblem
from ..result import RawSolution, Solution, TickResult
from .reference import PartitionedSolver


def chain_table(
    problem: DistributionProblem, partitioner: PartitionedSolver | None = None
) -> tuple[np.ndarray, np.ndarray, list[int]]:
    """The kernels' per-chain integer table, the chains' signs and the table's block widths.

    Per chain a header (its columns, own constrained joints and ball axes; with ``partitioner``
    also its rank, natural rows, free entries and the start of those among the reduced unknowns),
    then its velocity columns, the positions of its constrained joints among them, its ball axes
    (0-2) and, with ``partitioner``, its CFS and its free entries: blocks of ``widths``.
    """
    groups, header = problem.groups, 3 if partitioner is None else 7
    widths = [max(len(c) for c in problem.kinematics.chain_columns),
              max(g.constrained.shape[1] for g in groups), 3]  # fmt: skip
    if partitioner is not None:
        widths += [max(g.num_constraints for g in groups), max(g.num_free for g in groups)]
    ints = np.zeros((problem.p, header + sum(widths)), np.int64)
    signs = np.zeros((problem.p, widths[0]))
    at = np.cumsum([header, *widths[:-1]]).tolist()  # each block's start
    start = 0
    for index, group in enumerate(groups):
        k, c, nb = group.columns.shape[1], group.constrained.shape[1], len(group.ball_axes)
        for j, chain in enumerate(group.chains):
            head = [k, c, nb]
            blocks = [group.columns[j], group.constrained[j], group.ball_axes]
            if partitioner is not None:
                head += [group.rank, group.num_constraints, group.num_free, start]
                blocks += [partitioner.cfs[index][j], partitioner.free_entries[index][j]]
                start += group.num_free
            ints[chain, :header] = head
            for begin, block in zip(at, blocks, strict=True):
                ints[chain, begin : begin + len(block)] = block
            signs[chain, :k] = group.signs[j]
    return ints, signs, widths


def spring_table(problem: DistributionProblem) -> np.ndarray:
    """The kernels' ``(nv, 5)`` table of the passive and limp joints.

    Per joint: spring stiffness, rest angle, q index (-1: no spring), 1 for a continuous joint,
    1 if actuated.
    """
    springs = np.zeros((problem.model.nv, 5))
    springs[:, 2] = -1.0
    springs[:, 4] = problem.actuated_mask
    for v, spring in problem.passive_v.items():
        springs[v, :4] = (spring.stiffness, spring.rest, spring.idx_q, float(spring.continuous))
    return springs


@dataclass(frozen=True)
class PackedMode:
    """The packed tables of one set of prescribed axes (``CompiledDistribution.mode_for``)."""

    mode: int  # 0 minimum norm, 1 partitioned, -1 numpy path
    sets: dict
    systems: tuple
    method: str
    packed: tuple  # (ints, floats): the kernel's declaration-time arguments, () for mode -1
    core: object  # the compiled core's Distribution of these tables, or None


class BufferSolve:
    """A request's [`Solution`][] built from the compiled core's output buffer (thread-safe).

    Built by [`Solution.from_tick`][] from the tick the general path would return.

    Args:
        distribution: The actuator's `CompiledDistribution`.
        mode: The request's packed tables (with the core's ``Distribution``).
        names: The actuator's reaction frames and axes, the request's free axes.
        floating: Whether the robot has a floating base (``base_effort``: ``tau[:6]``).
    """

    def __init__(
        self,
        distribution: CompiledDistribution,
        mode: PackedMode,
        names: tuple[tuple[str, ...], tuple[str, ...], tuple[str, ...]],
        floating: bool,
    ) -> None:
        self._core = mode.core
        #: the mode's packed tables (the core's Distribution arguments)
        self.packed = mode.packed
        self._kinematics = distribution.problem.kinematics.tree  # its core_tree grows with frames
        self._distribution, self._mode = distribution, mode
        self._max_row = distribution.max_row
        self._names, self._floating = names, floating

    def solution(
        self, out: np.ndarray, residual: float, scale: float, rounding: float, tol: float
    ) -> Solution:
        """The [`Solution`][] of the core's buffer ``out`` and norms, with tolerance ``tol``."""
        tick = self._distribution.tick_result(self._mode, (out, residual, scale, rounding, 0))
        return Solution.from_tick(tick, tol, *self._names, self._floating)

    def __repr__(self) -> str:
        shape, method = self._distribution.shape, self._mode.method
        return f"{type(self).__name__}(shape={shape}, method={method!r})"


class ConfigurationSolve(BufferSolve):
    """One request's solve from unchecked ``q`` and wrench: the core checks them, in one call."""

    def __call__(self, q: object, wrench: object, tol: float) -> Solution | None:
        """The solution of ``wrench`` at ``q`` (tolerance ``tol``), or None for the general path."""
        out, residual, scale, rounding, status, _, _ = self._core.checked_tick(
            self._kinematics.core_tree, q, wrench
        )
        return None if status else self.solution(out, residual, scale, rounding, tol)


class SnapshotSolve(BufferSolve):
    """One request's solve on a computed snapshot: the core's one call, then the solution."""

    def __call__(self, snapshot: object, wrench: np.ndarray, tol: float = 1e-6) -> Solution | None:
        """The solution of ``wrench`` at ``snapshot`` (tolerance ``tol``), or None."""
        if not snapshot.computed:
            return None
        frames = snapshot.frame_table
        if frames.shape[0] <= self._max_row:
            return None
        out, residual, scale, rounding, status, _, _ = self._core.solve(
            snapshot.jacobian_world, frames, snapshot.q, wrench
        )
        return None if status else self.solution(out, residual, scale, rounding, tol)


class CompiledDistribution:
    """Per-tick distribution of one parallel actuator through the compiled kernel.

    Args:
        problem: The declaration's structure.
        partitioner: The numpy solver whose sets (and fallbacks) the kernel follows.
    """

    def __init__(self, problem: DistributionProblem, partitioner: PartitionedSolver) -> None:
        self.problem = problem
        self.partitioner = partitioner
        kin = problem.kinematics
        self.axis_rows = np.asarray(kin.rows, dtype=np.int64)
        self.frame_rows = kin.frame_rows
        #: the largest frame-table row the distribution reads
        self.max_row = int(self.frame_rows.max())
        #: the shape of the forces, ``(p, n)``
        self.shape = (problem.p, len(self.axis_rows))
        self.springs = spring_table(problem)
        torque = [(v, -1, 0) for v in problem.coupled_v]
        torque += [(int(a), int(b), 1) for a, b in problem.torque_pairs]
        self.torque_rows = np.array(torque, dtype=np.int64).reshape(-1, 3)
        # the chain signs at joints a and b (none at b = -1)
        at_a, at_b = (problem.signs[:, self.torque_rows[:, i]].T for i in (0, 1))
        self.torque_signs = np.stack((at_a, at_b), axis=1)
        self._modes: dict[bytes, PackedMode] = {}
        # the chain tables (the partitioner's sets never change after its __init__)
        self.chain_ints, self.chain_signs, widths = chain_table(problem, partitioner)
        #: the chain table's block widths but the ball axes': K, C, L, D
        self.layout = np.array(widths[:2] + widths[3:], dtype=np.int64)

    def mode_for(self, keep: np.ndarray) -> PackedMode:
        """The packed tables of the set of prescribed axes ``keep`` (built on first use)."""
        mode = self._modes.get(keep.tobytes())
        if mode is not None:  # once per set of free axes (two threads may both build it: same)
            return mode
        problem, partitioner = self.problem, self.partitioner
        m, s, k = partitioner.num_free_entries, problem.num_hard, int(keep.sum())
        systems, plan = partitioner.cfs_systems, np.zeros(0, np.int64)
        if k + s < m:
            systems += (("KKT", k + s, 1),)
            code, sets, method = 0, partitioner.reported_sets(keep), "pseudo-inverse"
        elif k + s == m and not problem.structurally_singular(keep):
            square = partitioner.square_plan
            if len(square.rfs) and square.gain is None:
                systems += (("RFS", len(square.rfs), 1),)
            systems += (("MFS", len(square.mfs), 1),)
            plan = np.concatenate((square.rfs, square.mfs)).astype(np.int64)
            code, sets, method = 1, partitioner.sets(square.mfs, square.rfs), "partitioned"
        else:
            code, sets, systems, method = -1, {}, (), ""
        packed, core = (), None
        if code >= 0:
            packed = self._pack(code, keep.astype(np.int64), plan)
            core = CORE.Distribution(*packed, problem.model.nv) if has("Distribution") else None
        mode = self._modes[keep.tobytes()] = PackedMode(code, sets, systems, method, packed, core)
        return mode

    def _pack(self, mode: int, keep: np.ndarray, plan: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``Distribution``'s declaration-time arguments as one integer and one float array.

        The integers: a header (``mode``, n, p, the chain table's width, torque rows, plan length,
        chain columns, velocity indices, constant rows), then ``keep`` (1 at prescribed axes),
        the axis rows, the frame rows ({B}, {O}, each {A_i}), the chain table, the torque rows
        (joint a, joint b or -1, kind: 0 a shared limp or passive joint, ahead of the constant
        rows, 1 equal torques, after them), ``plan`` (mode 1: the RFS then the MFS) and the
        layout; the floats: the chain signs, the `spring_table`, the constant design rows and
        right-hand sides, the torque rows' chain signs at joints a and b.
        """
        ints = (keep, self.axis_rows, self.frame_rows, self.chain_ints, self.torque_rows, plan,
                self.layout)  # fmt: skip
        rows, rhs = self.problem.constant_rows, self.problem.constant_rhs
        header = [mode, len(keep), *self.chain_ints.shape, len(self.torque_rows), len(plan),
                  self.chain_signs.shape[1], len(self.springs), len(rows)]  # fmt: skip
        floats = (self.chain_signs, self.springs, rows, rhs, self.torque_signs)
        ints = [np.array(header, np.int64), *(np.ravel(a).astype(np.int64) for a in ints)]
        return np.concatenate(ints), np.concatenate([np.ravel(a).astype(float) for a in floats])

    def solve_configuration(
        self, q: np.ndarray, wrench: np.ndarray, request: Request
    ) -> TickResult | None:
        """Kinematics and distribution of a checked configuration in one call, or None."""
        mode, tree = self._core_mode(request), self.problem.kinematics.tree.core_tree
        if mode is None or tree is None or tree.nf <= self.max_row:
            return None
        return self.tick_result(mode, mode.core.tick(tree, q, wrench))

    def buffer_solve(
        self,
        kind: type[BufferSolve],
        request: Request,
        reactions: tuple[str, ...],
        axes: tuple[str, ...],
        floating: bool,
    ) -> BufferSolve | None:
        """A `BufferSolve` of ``kind`` for a checked request, or None off the compiled path."""
        mode = self._core_mode(request)
        return None if mode is None else kind(self, mode, (reactions, axes, request.free), floating)

    def solve(self, snapshot: object, wrench: np.ndarray, request: Request) -> TickResult | None:
        """Distribute ``wrench`` at a snapshot, or None to hand the tick to the numpy path."""
        mode = self._core_mode(request)
        if mode is None:  # the numpy path
            return None
        tree = snapshot.tree.core_tree
        if not snapshot.computed and snapshot.backend == "compiled" and tree.nf > self.max_row:
            return self.tick_result(mode, mode.core.tick(tree, snapshot.q, wrench))  # q alone: both
        frames = snapshot.frame_table
        if frames.shape[0] <= self.max_row:
            return None  # frames required after this snapshot ran: the numpy path reads them
        tick = mode.core.solve(snapshot.jacobian_world, frames, snapshot.q, wrench)
        return self.tick_result(mode, tick)

    def _core_mode(self, request: Request) -> PackedMode | None:
        """The request's packed tables if the core solves it (compiled, partitioned), else None."""
        if not request.compiled or request.method != "partitioned":
            return None
        mode = self.mode_for(request.keep)
        return None if mode.core is None else mode

    def tick_result(self, mode: PackedMode, tick: tuple) -> TickResult | None:
        """The `TickResult` of the core's ``tick`` or ``solve`` output, or None if handed on."""
        out, residual, scale, rounding, status = tick[:5]
        if status:
            return None
        forces = out[: self.shape[0] * self.shape[1]].reshape(self.shape)
        raw = RawSolution(forces, mode.method, mode.sets, mode.systems)
        return TickResult.from_buffer(raw, out, residual, scale, rounding, compiled=True)
