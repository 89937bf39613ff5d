"""The real-time path of a parallel actuator's solve: tables built once, one compiled call a tick.

Without the core, or when the core hands a tick back, `PartitionedSolver` decides with numpy.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from ...core import CORE, has
from ..methods import Request
from ..problem import DistributionProblem
from ..result import RawSolution, TickResult
from . import kernel_tables
from .buffer_solve import BufferSolve, ConfigurationSolve, PackedMode, SnapshotSolve
from .reference import PartitionedSolver


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
class _Tables:
    chain_ints: np.ndarray
    chain_signs: np.ndarray
    layout: np.ndarray


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
        #: the chain tables: the partitioner's sets never change after its __init__
        self._tables = self._build_tables()
        self._modes: dict[bytes, PackedMode] = {}

    def _build_tables(self) -> _Tables:
        problem, partitioner = self.problem, self.partitioner
        p = problem.p
        kin = problem.kinematics
        width_k = max(len(c) for c in kin.chain_columns)
        width_c = max(g.constrained.shape[1] for g in problem.groups)
        width_l = max(g.num_constraints for g in problem.groups)
        width_d = max(g.num_free for g in problem.groups)
        header = kernel_tables.HEADER
        ints = np.zeros((p, header + width_k + width_c + 3 + width_l + width_d), dtype=np.int64)
        chain_signs = np.zeros((p, width_k))
        start = 0
        for group, cfs, free in zip(
            problem.groups, partitioner.cfs, partitioner.free_entries, strict=True
        ):
            for j, chain in enumerate(group.chains):
                k = group.columns.shape[1]
                c = group.constrained.shape[1]
                nb = len(group.ball_axes)
                row = ints[chain]
                row[:header] = (k, c, nb, group.rank, group.num_constraints, group.num_free, start)
                start += group.num_free
                at = header
                row[at : at + k] = group.columns[j]
                chain_signs[chain, :k] = group.signs[j]
                at += width_k
                row[at : at + c] = group.constrained[j]
                at += width_c
                row[at : at + nb] = group.ball_axes
                at += 3
                row[at : at + group.num_constraints] = cfs[j]
                at += width_l
                row[at : at + group.num_free] = free[j]
        layout = np.array([width_k, width_c, width_l, width_d], dtype=np.int64)
        return _Tables(ints, chain_signs, layout)

    def mode_for(self, keep: np.ndarray) -> PackedMode:
        """The packed tables of the set of prescribed axes ``keep`` (built on first use)."""
        mode = self._modes.get(keep.tobytes())
        if mode is None:  # once per set of free axes (two threads may both build it: same mode)
            mode = self._mode(keep)
        return mode

    def _mode(self, keep: np.ndarray) -> PackedMode:
        problem, partitioner = self.problem, self.partitioner
        m, s, k = partitioner.num_free_entries, problem.num_hard, int(keep.sum())
        keep_int = keep.astype(np.int64)
        cfs_systems = tuple(
            ("CFS", g.num_constraints, g.size) for g in problem.groups if g.num_constraints
        )
        if k + s < m:
            sets = partitioner.reported_sets(keep)
            systems = cfs_systems + (("KKT", k + s, 1),)
            mode = PackedMode(0, keep_int, np.zeros(0, np.int64), sets, systems, "pseudo-inverse")
        elif k + s == m and not problem.structurally_singular(keep):
            plan = partitioner.square_plan(keep)
            labels = partitioner.labels()
            sets = {
                "MFS": [labels[i] for i in plan.mfs],
                "RFS": [labels[i] for i in plan.rfs],
                "CFS": partitioner.labels(partitioner.cfs),
            }
            systems = cfs_systems
            if len(plan.rfs) and plan.gain is None:
                systems += (("RFS", len(plan.rfs), 1),)
            systems += (("MFS", len(plan.mfs), 1),)
            order = np.concatenate((plan.rfs, plan.mfs)).astype(np.int64)
            mode = PackedMode(1, keep_int, order, sets, systems, "partitioned")
        else:
            mode = PackedMode(-1, keep_int, np.zeros(0, np.int64), {}, (), "")
        if mode.mode >= 0:
            tables = self._tables
            packed = kernel_tables.pack_arguments(
                mode.mode,
                mode.keep,
                self.axis_rows,
                self.frame_rows,
                tables.chain_ints,
                tables.chain_signs,
                self.springs,
                self.const_rows,
                self.const_rhs,
                self.torque_rows,
                self.torque_signs,
                mode.plan,
                tables.layout,
            )
            core = CORE.Distribution(*packed, problem.model.nv) if has("Distribution") else None
            mode = dataclasses.replace(mode, packed=packed, core=core)
        self._modes[keep.tobytes()] = mode
        return mode

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

    def configuration_solve(
        self, request: Request, reactions: tuple[str, ...], axes: tuple[str, ...], floating: bool
    ) -> ConfigurationSolve | None:
        """The `ConfigurationSolve` of a checked request, or None without the core."""
        if self.problem.kinematics.tree.core_tree is None:
            return None
        return self.buffer_solve(ConfigurationSolve, request, reactions, axes, floating)

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
        tree, nv = self.problem.kinematics.tree, self.problem.model.nv
        return kind(mode, tree, self.max_row, self.shape, nv, reactions, axes, request.free,
                    floating)  # fmt: skip

    def solve(self, snapshot: object, wrench: np.ndarray, request: Request) -> TickResult | None:
        """Distribute ``wrench`` at a snapshot, or None to hand the tick to the numpy path.

        Returns:
            The tick's result (``tau`` zero at limp and passive joints), or None.
        """
        if not request.compiled:
            return None
        mode = self.mode_for(request.keep)
        if mode.mode < 0:
            return None
        tick = None
        core = mode.core
        if core is not None and not snapshot.computed and snapshot.backend == "compiled":
            tree = snapshot.tree.core_tree  # a snapshot of q alone: kinematics + distribution
            if tree.nf > self.max_row:
                tick = core.tick(tree, snapshot.q, wrench)
        if tick is None:
            frames = snapshot.frame_table
            if frames.shape[0] <= self.max_row:
                return None  # frames required after this snapshot ran: the numpy path reads them
            if core is None:
                return None  # no compiled core: the numpy path
            tick = core.solve(snapshot.jacobian_world, frames, snapshot.q, wrench)
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


__all__ = ["BufferSolve", "CompiledDistribution", "ConfigurationSolve", "SnapshotSolve"]
