"""A request's [`Solution`][] built straight from the compiled core's output buffer.

`BufferSolve` reads once what the declaration and the request fix;
`ConfigurationSolve` answers ``solve(q, wrench)``'s default request with one compiled call
that also checks the arguments, `SnapshotSolve` a controller's request on the tick's snapshot.
Both are made by ``CompiledDistribution.buffer_solve`` (``compiled.py``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..result import Solution, buffer_slices, label, tolerance


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
    """A request's [`Solution`][] built straight from the compiled core's output buffer.

    What the declaration and the request fix (the mode's sets and systems, the buffer's layout,
    the names) is read once, so that the answer is the same [`Solution`][], bit for bit, as
    [`Solution.from_tick`][] of the general path's tick. Holds no per-call state: threads may
    share it. `ConfigurationSolve` (from ``q``) and `SnapshotSolve` (on a snapshot) call
    the core and build their answer with `solution`.

    Args:
        mode: The request's packed tables (with the core's ``Distribution``).
        tree: The robot's ``KinematicTree`` (its ``core_tree`` grows with its frames).
        max_row: The largest frame row the tables read.
        shape: ``(p, n)`` the chains' forces.
        nv: The robot's velocity size.
        reactions: The actuator's reaction frames.
        axes: Its axes.
        free: The request's free axes.
        floating: Whether the robot has a floating base (``base_effort``: ``tau[:6]``).
    """

    def __init__(
        self,
        mode: PackedMode,
        tree: object,
        max_row: int,
        shape: tuple[int, int],
        nv: int,
        reactions: tuple[str, ...],
        axes: tuple[str, ...],
        free: tuple[str, ...],
        floating: bool,
    ) -> None:
        self._core = mode.core
        #: the mode's packed tables (the core's Distribution arguments)
        self.packed = mode.packed
        self._kinematics = tree  # its core_tree grows with frames
        self._max_row = max_row
        self._shape = shape
        self._method, self._sets, self._systems = mode.method, mode.sets, mode.systems
        self._names = (reactions, axes, free)
        self._floating = floating
        #: forces, tau, the springs' torques, produced, requested: the buffer's slices
        self._forces, self._tau, self._passive, self._produced, self._requested = buffer_slices(
            *self._shape, nv
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
    """One request's solve from unchecked ``q`` and wrench: one compiled call, then the solution.

    The compiled core's ``Distribution.checked_tick`` checks the arguments (what
    ``KinematicTree.check_configuration`` and ``wrench_array`` accept unchanged), runs the
    kinematics and the distribution, and hands back (None here) whatever it does not decide: an
    argument the Python checks must judge (to raise their typed error, or to normalise ``q``),
    or a tick for the numpy path. Arguments as `BufferSolve`'s.
    """

    def __call__(self, q: object, wrench: object, tol: float) -> Solution | None:
        """The solution of ``wrench`` at ``q`` with tolerance ``tol`` (checked), or None.

        None: ``q`` or ``wrench`` is not what the checks accept unchanged, or the kernel hands
        the tick on; the caller then solves on the general path.
        """
        out, residual, scale, rounding, status, _, _ = self._core.checked_tick(
            self._kinematics.core_tree, q, wrench
        )
        if status:
            return None
        return self.solution(out, residual, scale, rounding, tol)


class SnapshotSolve(BufferSolve):
    """One request's solve on a computed snapshot: the core's one call, then the solution.

    The controller's per-tick distribution (a checked request and a finite float wrench, as
    ``ParallelVirtualActuator.solve_checked`` takes them): the same call of the core's
    ``Distribution.solve`` as `CompiledDistribution.solve` on that snapshot, without the
    dispatch, the `TickResult` and the tables' look-up. Arguments as `BufferSolve`'s.
    """

    def __call__(self, snapshot: object, wrench: np.ndarray, tol: float = 1e-6) -> Solution | None:
        """The solution of ``wrench`` at ``snapshot`` with tolerance ``tol``, or None.

        None: the snapshot's kinematics have not run (the general path then runs them with the
        distribution in one call), its frame table lacks the distribution's rows, or the kernel
        hands the tick on; the caller then solves on the general path.
        """
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


__all__ = ["BufferSolve", "ConfigurationSolve", "PackedMode", "SnapshotSolve"]
