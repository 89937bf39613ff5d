"""Where the parts of one kinematics pass lie in the compiled core's buffer (``Tree.compute``)."""

from __future__ import annotations

from typing import NamedTuple

import numpy as np


class Kinematics(NamedTuple):
    """What one pass of the compiled kernel computes (views of one buffer: do not modify).

    Attributes:
        joints: ``(njoints, 12)`` joint placements in the world (rotation row by row, position).
        jacobian: ``(6, nv)`` world joint Jacobian (Pinocchio's ``data.J``).
        frames: ``(rows, 12)`` placements of the frames computed at every tick.
        velocities: ``(rows, 3)`` linear velocities of their origins, or None without ``v``.
        rows: Frame id -> row of ``frames``.
    """

    joints: np.ndarray
    jacobian: np.ndarray
    frames: np.ndarray
    velocities: np.ndarray | None
    rows: dict[int, int]


class BufferLayout(NamedTuple):
    """Where the parts of one pass lie in the kernel's buffer, for one frame table.

    Attributes:
        core_tree: The compiled core's ``Tree`` it describes.
        joints: Slice of the joint placements, ``(njoints, 12)`` once reshaped.
        joints_shape: ``(njoints, 12)``.
        jacobian: Slice of the world joint Jacobian.
        jacobian_shape: ``(6, nv)``.
        frames: Slice of the frame placements; the frames' velocities follow it (with ``v``).
        frames_shape: ``(rows, 12)``.
    """

    core_tree: object
    joints: slice
    joints_shape: tuple[int, int]
    jacobian: slice
    jacobian_shape: tuple[int, int]
    frames: slice
    frames_shape: tuple[int, int]

    def velocities(self, buffer: np.ndarray) -> np.ndarray | None:
        """The ``(rows, 3)`` frame velocities of ``buffer``, or None (a pass without ``v``)."""
        end = self.frames.stop
        return buffer[end:].reshape(self.frames_shape[0], 3) if buffer.shape[0] > end else None

    def cut(self, buffer: np.ndarray, rows: dict[int, int]) -> Kinematics:
        """The `Kinematics` of ``buffer`` (views of it), with frame rows ``rows``."""
        return Kinematics(
            buffer[self.joints].reshape(self.joints_shape),
            buffer[self.jacobian].reshape(self.jacobian_shape),
            buffer[self.frames].reshape(self.frames_shape),
            self.velocities(buffer),
            rows,
        )


def buffer_layout(core_tree: object, njoints: int, nv: int, nf: int) -> BufferLayout:
    """The `BufferLayout` of a pass.

    Args:
        core_tree: The compiled core's ``Tree`` the layout describes.
        njoints: The model's number of joints (the universe included).
        nv: The model's velocity dimension.
        nf: The number of rows of the frame table.
    """
    at = njoints * 12
    jacobian_end = at + 6 * nv
    return BufferLayout(
        core_tree, slice(0, at), (njoints, 12), slice(at, jacobian_end), (6, nv),
        slice(jacobian_end, jacobian_end + nf * 12), (nf, 12),
    )  # fmt: skip


__all__ = ["BufferLayout", "Kinematics", "buffer_layout"]
