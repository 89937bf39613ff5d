"""The real-time path of a parallel actuator's solve: tables built once, one compiled call a tick.

Without the core, or when the core hands a tick back, `PartitionedSolver` decides with numpy. A
`BufferSolve` builds a request's [`Solution`][] straight from the core's output buffer.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from ...core import CORE, has
from ..methods import Request
from ..problem import DistributionProblem
from ..result import RawSolution, Solution, TickResult, buffer_slices, label, tolerance
from .reference import PartitionedSolver

#: entries of the chain table's per-chain header
HEADER = 7


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
    keep: np.ndarray  # int64 mask
    plan: np.ndarray
    sets: dict
    systems: tuple
    method: str
    packed: tuple = ()  # (ints, floats): the kernel's declaration-time arguments
    core: object = None  # the compiled core's Distribution of these tables, or None


class BufferSolve:
    """A request's [`Solution`][] built from the compiled core's output buffer (thread-safe).

    The same [`Solution`][], bit for bit, as [`Solution.from_tick`][] of the general path's tick.

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
        self._max_row = distribution.max_row
        self._shape = distribution.shape
        self._method, self._sets, self._systems = mode.method, mode.sets, mode.systems
        self._names = names
        self._floating = floating
        #: forces, tau, the springs' torques, produced, requested: the buffer's slices
        self._forces, self._tau, self._passive, self._produced, self._requested = buffer_slices(
            *self._shape, distribution.problem.model.nv
        )

    def solution(
        self, out: np.ndarray, residual: float, scale: float, rounding: float, tol: float
    ) -> Solution:
        """The [`Solution`][] of the core's buffer ``out`` and norms, with tolerance ``tol``."""
        tau = out[self._tau]
        limit = tolerance(tol, scale, rounding)
        reactions, axes, free = self._names
        return Solution(  # positional, as Solution.from_tick builds it
            tau,
            out[self._forces].reshape(self._shape),
            out[self._produced],
            self._sets,
            residual,
            label(self._method, residual <= limit),
            out[self._requested],
            reactions,
            axes,
            free,
            out[self._passive],
            tau[:6].copy() if self._floating else np.zeros(0),
            "partitioned",
            self._systems,
            True,
            (),
            limit,
        )

    def __repr__(self) -> str:
        return f"{type(self).__name__}(shape={self._shape}, method={self._method!r})"


class ConfigurationSolve(BufferSolve):
    """One request's solve from unchecked ``q`` and wrench: the core checks them, in one call."""

    def __call__(self, q: object, wrench: object, tol: float) -> Solution | None:
        """The solution of ``wrench`` at ``q`` (tolerance ``tol``), or None for the general path."""
        out, residual, scale, rounding, status, _, _ = self._core.checked_tick(
            self._kinematics.core_tree, q, wrench
        )
        if status:
            return None
        return self.solution(out, residual, scale, rounding, tol)


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
        if status:
            return None
        return self.solution(out, residual, scale, rounding, tol)


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
        self.const_rows = np.ascontiguousarray(problem.constant_rows, dtype=float)
        self.const_rhs = np.ascontiguousarray(problem.constant_rhs, dtype=float)
        torque = [(v, -1, 0) for v in problem.coupled_v]
        torque += [(int(a), int(b), 1) for a, b in problem.torque_pairs]
        self.torque_rows = np.array(torque, dtype=np.int64).reshape(-1, 3)
        signs = np.zeros((len(torque), 2, problem.p))
        for t, (a, b, _) in enumerate(torque):
            signs[t, 0] = problem.signs_at([a])[:, 0]
            if b >= 0:
                signs[t, 1] = problem.signs_at([b])[:, 0]
        self.torque_signs = signs
        self._modes: dict[bytes, PackedMode] = {}
        # the chain tables (the partitioner's sets never change after its __init__): per chain
        # a header of HEADER (its columns, own constrained joints, ball axes, rank, natural rows,
        # free entries, start of its free entries in the reduced unknowns), then its velocity
        # columns, the positions of its constrained joints among them, its ball axes (0-2), its
        # CFS and its free entries, in blocks of widths K, C, 3, L, D (``layout``: K, C, L, D)
        groups = problem.groups
        width_k = max(len(c) for c in kin.chain_columns)
        width_c = max(g.constrained.shape[1] for g in groups)
        width_l = max(g.num_constraints for g in groups)
        width_d = max(g.num_free for g in groups)
        self.layout = np.array([width_k, width_c, width_l, width_d], dtype=np.int64)
        self.chain_ints = np.zeros((problem.p, HEADER + int(self.layout.sum()) + 3), np.int64)
        self.chain_signs = np.zeros((problem.p, width_k))
        at = np.cumsum([HEADER, width_k, width_c, 3, width_l]).tolist()  # each block's start
        start = 0
        for group, cfs, free in zip(groups, partitioner.cfs, partitioner.free_entries, strict=True):
            k, c, nb = group.columns.shape[1], group.constrained.shape[1], len(group.ball_axes)
            for j, chain in enumerate(group.chains):
                row = self.chain_ints[chain]
                row[:HEADER] = (k, c, nb, group.rank, group.num_constraints, group.num_free, start)
                start += group.num_free
                row[at[0] : at[0] + k] = group.columns[j]
                row[at[1] : at[1] + c] = group.constrained[j]
                row[at[2] : at[2] + nb] = group.ball_axes
                row[at[3] : at[3] + group.num_constraints] = cfs[j]
                row[at[4] : at[4] + group.num_free] = free[j]
                self.chain_signs[chain, :k] = group.signs[j]

    def mode_for(self, keep: np.ndarray) -> PackedMode:
        """The packed tables of the set of prescribed axes ``keep`` (built on first use)."""
        mode = self._modes.get(keep.tobytes())
        if mode is not None:  # once per set of free axes (two threads may both build it: same)
            return mode
        problem, partitioner = self.problem, self.partitioner
        m, s, k = partitioner.num_free_entries, problem.num_hard, int(keep.sum())
        keep_int, systems = keep.astype(np.int64), partitioner.cfs_systems
        if k + s < m:
            systems += (("KKT", k + s, 1),)
            sets = partitioner.reported_sets(keep)
            mode = PackedMode(0, keep_int, np.zeros(0, np.int64), sets, systems, "pseudo-inverse")
        elif k + s == m and not problem.structurally_singular(keep):
            plan = partitioner.square_plan(keep)
            if len(plan.rfs) and plan.gain is None:
                systems += (("RFS", len(plan.rfs), 1),)
            systems += (("MFS", len(plan.mfs), 1),)
            order = np.concatenate((plan.rfs, plan.mfs)).astype(np.int64)
            sets = partitioner.sets(plan.mfs, plan.rfs)
            mode = PackedMode(1, keep_int, order, sets, systems, "partitioned")
        else:
            mode = PackedMode(-1, keep_int, np.zeros(0, np.int64), {}, (), "")
        if mode.mode >= 0:
            packed = self._pack(mode.mode, keep_int, mode.plan)
            core = CORE.Distribution(*packed, problem.model.nv) if has("Distribution") else None
            mode = dataclasses.replace(mode, packed=packed, core=core)
        self._modes[keep.tobytes()] = mode
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
        header = [mode, len(keep), *self.chain_ints.shape, len(self.torque_rows), len(plan),
                  self.chain_signs.shape[1], len(self.springs), len(self.const_rows)]  # fmt: skip
        floats = (self.chain_signs, self.springs, self.const_rows, self.const_rhs,
                  self.torque_signs)  # fmt: skip
        ints = [np.array(header, np.int64), *(np.ravel(a).astype(np.int64) for a in ints)]
        return np.concatenate(ints), np.concatenate([np.ravel(a).astype(float) for a in floats])

    def solve_configuration(
        self, q: np.ndarray, wrench: np.ndarray, request: Request
    ) -> TickResult | None:
        """Kinematics and distribution of a checked configuration in one call, or None."""
        if not request.compiled or request.method != "partitioned":
            return None
        mode = self.mode_for(request.keep)
        core, tree = mode.core, self.problem.kinematics.tree.core_tree
        if core is None or tree is None or tree.nf <= self.max_row:
            return None
        return self._tick(mode, core.tick(tree, q, wrench))

    def buffer_solve(
        self,
        kind: type[BufferSolve],
        request: Request,
        reactions: tuple[str, ...],
        axes: tuple[str, ...],
        floating: bool,
    ) -> BufferSolve | None:
        """A `BufferSolve` of ``kind`` for a checked request, or None off the compiled path."""
        if not request.compiled or request.method != "partitioned":
            return None
        mode = self.mode_for(request.keep)
        if mode.core is None:
            return None
        return kind(self, mode, (reactions, axes, request.free), floating)

    def solve(self, snapshot: object, wrench: np.ndarray, request: Request) -> TickResult | None:
        """Distribute ``wrench`` at a snapshot, or None to hand the tick to the numpy path.

        Returns:
            The tick's result (``tau`` zero at limp and passive joints), or None.
        """
        mode = self.mode_for(request.keep) if request.compiled else None
        if mode is None or mode.core is None:  # no compiled core or mode: the numpy path
            return None
        tree = snapshot.tree.core_tree
        if not snapshot.computed and snapshot.backend == "compiled" and tree.nf > self.max_row:
            return self._tick(mode, mode.core.tick(tree, snapshot.q, wrench))  # q alone: both
        frames = snapshot.frame_table
        if frames.shape[0] <= self.max_row:
            return None  # frames required after this snapshot ran: the numpy path reads them
        tick = mode.core.solve(snapshot.jacobian_world, frames, snapshot.q, wrench)
        return self._tick(mode, tick)

    def _tick(self, mode: PackedMode, tick: tuple) -> TickResult | None:
        """The `TickResult` of the core's ``tick`` or ``solve`` output, or None if handed on."""
        out, residual, scale, rounding, status = tick[:5]
        if status:
            return None
        forces = out[: self.shape[0] * self.shape[1]].reshape(self.shape)
        raw = RawSolution(forces, mode.method, mode.sets, mode.systems)
        return TickResult.from_buffer(raw, out, residual, scale, rounding, compiled=True)

    def __repr__(self) -> str:
        return f"CompiledDistribution(p={self.problem.p}, n={self.problem.n})"


__all__ = [
    "BufferSolve",
    "CompiledDistribution",
    "ConfigurationSolve",
    "PackedMode",
    "SnapshotSolve",
    "spring_table",
]
