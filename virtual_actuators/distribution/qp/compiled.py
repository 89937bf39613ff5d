"""The QP distribution's per-tick matrices through the compiled core: tables built once.

The core's reduced QP (``src/core/qp.hpp``) is in the chains' free coordinates: per chain
``F_i = x0_i + N_i z_i``, ``N_i`` orthonormal.
"""

from __future__ import annotations

import threading
from typing import NamedTuple

import numpy as np

from ...core import CORE, has
from ..partitioned.compiled import chain_table, spring_table
from ..problem import DistributionProblem
from ..tolerances import ACTIVE_TOL, EPS_ABS, EXACT_TOL


class Answer(NamedTuple):
    """The core's read-out of a solved reduced QP: the tick's buffer and norms, the active rows."""

    out: np.ndarray
    residual: float
    scale: float
    rounding: float
    active: np.ndarray


class Workspace:
    """One thread's buffer for one set of prescribed axes, and its arrays (views, reused).

    ``buffer``, written by the core's ``QP.reduced``, holds the null-space bases ``N`` ``(p n,
    d)``, the particular forces ``x0`` ``(p n,)``, the QP's rows (``equality`` ``(s + k, d)``,
    its ``design_rows`` design rows first, ``equality_rhs``, ``inequality`` ``(m, d)``, ``lows``,
    ``uppers``: right-hand sides and bounds scaled), the torque map ``(nv, d)``, the torques of
    ``x0`` and the springs' torques; ``layout``: their offsets, then ``d``, ``s + k``, ``m``, ``s``.
    """

    def __init__(self, p_n: int, nv: int, free: int, design: int, kept: np.ndarray,
                 rows_in: int) -> None:  # fmt: skip
        rows_eq = design + len(kept)
        sizes = (p_n * free, p_n, rows_eq * free, rows_eq, rows_in * free, rows_in, rows_in,
                 nv * free, nv, nv)  # fmt: skip
        offsets = np.concatenate(([0], np.cumsum(sizes))).tolist()
        self.layout = np.array([*offsets[:-1], free, rows_eq, rows_in, design], dtype=np.int64)
        self.buffer = np.zeros(int(offsets[-1]))
        self.kept = kept
        self.design_rows = design
        self.pn, self.nv = p_n, nv
        equality, self.equality_rhs, inequality, self.lows, self.uppers = (
            self.buffer[offsets[i] : offsets[i + 1]] for i in range(2, 7)
        )
        self.equality = equality.reshape((rows_eq, free))
        self.inequality = inequality.reshape((rows_in, free))
        self.active = np.empty(rows_in, dtype=np.int64)  # the read-out's active rows
        self.scale = 1.0

    def violation(self, z: np.ndarray, equalities: int) -> float:
        """How far ``z`` misses this workspace's rows (the core's ``qp_violation``)."""
        return CORE.qp_violation(self.buffer, self.layout, self.pn, self.nv, z, equalities)

    def finish(
        self, z: np.ndarray, multipliers: np.ndarray, wrench: np.ndarray, keep: np.ndarray
    ) -> Answer:
        """The answer ``z`` read out on this workspace's tick (the core's ``qp_read_out``)."""
        out = np.zeros(self.pn + 2 * self.nv + 2 * len(wrench))
        active = np.empty(len(multipliers), dtype=np.int64)
        count, norms = CORE.qp_read_out(
            self.buffer, self.layout, self.pn, self.nv, z, multipliers, self.scale, wrench,
            keep, ACTIVE_TOL, EPS_ABS, out, active,
        )  # fmt: skip
        return Answer(out, *norms, active[:count].copy())


class CompiledQPMatrices:
    """Per-tick QP matrices of one parallel actuator, from tables built at declaration.

    Args:
        problem: The distribution problem.
        tables: `ContactLimits.tables`: ``normals_world`` ``(p, 3)`` unit contact normals in the
            world; ``frame_normals`` ``(p,)`` 1 where the normal is the reaction frame's z axis
            (each tick); ``cone`` ``(3,)``: friction (< 0 for none), least normal force [N], 1 to
            keep the normal row (0: no pyramid rows at all when friction < 0); ``soles``
            ``(p, 3)``: 1 for a sole, its half length and half width [m]; ``limited_v`` ``(t,)``
            velocity indices of the torque-limited joints and ``limits`` ``(t,)`` their limits
            [N m, N].
        static_scale: The declaration's part of the tick's scale.
        rows_in: Number of inequality rows.
    """

    def __init__(
        self,
        problem: DistributionProblem,
        tables: dict[str, np.ndarray],
        static_scale: float,
        rows_in: int,
    ) -> None:
        self.problem = problem
        self.rows_in = rows_in
        self._local = threading.local()
        kin = problem.kinematics
        self._max_row = int(kin.frame_rows.max())
        #: whether the compiled path can build this declaration's ticks: with the core, every
        #: chain's columns ``[J_i, ball_i]`` independent and no configuration-dependent hard row
        self.applicable = (
            has("QP")
            and all(g.rank == g.columns.shape[1] + len(g.ball_axes) for g in problem.groups)
            and not problem.coupled_v
            and not len(problem.torque_pairs)
        )
        #: the compiled core's QP (these tables, copied into C++), or None: the numpy path
        self.core = None
        if not self.applicable:
            return
        ints, signs, _ = chain_table(problem)
        self.core = CORE.QP(
            np.asarray(kin.rows, dtype=np.int64), kin.frame_rows, ints, signs,
            spring_table(problem), problem.constant_rows, problem.constant_rhs,
            np.ascontiguousarray(tables["normals_world"], dtype=float),
            np.asarray(tables["frame_normals"], dtype=np.int64),
            np.array([*np.asarray(tables["cone"], dtype=float), static_scale]),
            np.ascontiguousarray(tables["soles"], dtype=float),
            np.asarray(tables["limited_v"], dtype=np.int64),
            np.asarray(tables["limits"], dtype=float),
        )  # fmt: skip

    def workspace(self, keep: np.ndarray) -> Workspace:
        """This thread's workspace for these prescribed axes (made once)."""
        cache = getattr(self._local, "workspaces", None)
        if cache is None:
            cache = self._local.workspaces = {}
        key = keep.tobytes()
        workspace = cache.get(key)
        if workspace is None:
            problem = self.problem
            free = sum(g.size * (g.columns.shape[1] - g.constrained.shape[1])
                       for g in problem.groups)  # fmt: skip
            workspace = cache[key] = Workspace(
                problem.p * problem.n, problem.model.nv, free, len(problem.constant_rhs),
                np.flatnonzero(keep).astype(np.int64), self.rows_in,
            )  # fmt: skip
        return workspace

    def build(self, snapshot: object, wrench: np.ndarray, keep: np.ndarray) -> Workspace | None:
        """The tick's reduced QP in this thread's workspace, or None to build it with numpy.

        Args:
            snapshot: The tick's [`Snapshot`][].
            wrench: ``(n,)`` requested wrench.
            keep: ``(n,)`` bool, the prescribed axes.
        """
        workspace = self.workspace(keep)
        frames = snapshot.frame_table
        if frames.shape[0] <= self._max_row:  # frames required after the snapshot ran
            return None
        status, _, scale = self.core.reduced(
            snapshot.jacobian_world, frames, snapshot.q, wrench, workspace.kept,
            workspace.buffer, workspace.layout,
        )  # fmt: skip
        if status:
            return None
        workspace.scale = scale
        return workspace

    def again(
        self,
        snapshot: object,
        wrench: np.ndarray,
        keep: np.ndarray,
        workspace: Workspace,
        weights: np.ndarray,
        guess: np.ndarray,
        tree: object = None,
    ) -> Answer | None:
        """The core's ``again`` on this tick: the answer on the last certified active set, or None.

        ``snapshot`` is a configuration when ``tree`` is the core's ``Tree``; ``workspace`` is this
        thread's for ``keep``; ``guess``, the last certified answer's inequality multipliers, is
        replaced in place by this answer's when it is certified. None: the exact step did not
        certify the active set, the matrices need the numpy path or the snapshot lacks a frame.
        """
        out = np.zeros(workspace.pn + 2 * workspace.nv + 2 * len(wrench))  # the tick's own
        active = workspace.active
        tail = (workspace.kept, workspace.buffer, workspace.layout, keep, weights, guess,
                ACTIVE_TOL, EXACT_TOL, EPS_ABS, out, active)  # fmt: skip
        if tree is not None:
            if tree.nf <= self._max_row:
                return None
            count, norms = self.core.again_tick(tree, snapshot, wrench, *tail)
        else:
            frames = snapshot.frame_table  # the snapshot's arrays straight in (a tick's cost)
            if frames.shape[0] <= self._max_row:
                return None
            count, norms = self.core.again(
                snapshot.jacobian_world, frames, snapshot.q, wrench, *tail
            )
        return None if count < 0 else Answer(out, *norms, active[:count].copy())
