"""A request's [`Solution`][] built straight from the compiled core's output buffer."""

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
    """A request's [`Solution`][] built from the compiled core's output buffer (thread-safe).

    The same [`Solution`][], bit for bit, as [`Solution.from_tick`][] of the general path's tick.

    Args:
        mode: The request's packed tables (with the core's ``Distribution``).
        tree: The robot's ``KinematicTree``.
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


__all__ = ["BufferSolve", "ConfigurationSolve", "PackedMode", "SnapshotSolve"]
