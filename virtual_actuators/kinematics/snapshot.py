"""One kinematics pass per control tick, shared by every reader: [`Snapshot`][].

Computed lazily on the first read, by the compiled kernel or Pinocchio; a snapshot owns what it
computed, so snapshots of one robot can be used from several threads.
"""

from __future__ import annotations

import threading

import numpy as np
import pinocchio as pin

from ..exceptions import FrameNotFoundError, InvalidInputError
from .kernels import center_of_mass_of, placement_row, velocity_of_point
from .tree import KinematicTree, tree_of

_BACKENDS = ("auto", "compiled", "pinocchio")
_local = threading.local()


def thread_data(model: pin.Model) -> pin.Data:
    """The ``pinocchio.Data`` of ``model`` for the calling thread (one per model and thread)."""
    pool = getattr(_local, "pool", None)
    if pool is None:
        pool = _local.pool = {}
    entry = pool.get(id(model))
    if entry is None or entry[0] is not model:
        entry = pool[id(model)] = (model, pin.Data(model))
    return entry[1]


class Snapshot:
    """The kinematics of a robot at one configuration, computed once and shared.

    Args:
        robot: The robot (a [`Robot`][]).
        q: Configuration ``(model.nq,)``; the snapshot keeps a copy (`q`), so the
            caller may reuse its array.
        v: Velocity ``(model.nv,)``, needed only for velocities; copied likewise (`v`).
        backend: ``"auto"`` (the compiled kernel when it handles every joint of the model,
            else Pinocchio), ``"compiled"`` or ``"pinocchio"``.

    Attributes:
        q: The snapshot's own copy of the configuration (checked; near-unit quaternions
            normalised). Do not modify it: the kinematics were computed from it.
        v: Its own copy of the velocity, or None.

    Raises:
        InvalidInputError: Bad ``q``, ``v`` or ``backend``, or ``"compiled"`` for a model the
            kernel does not handle.

    Example:
        >>> snapshot = va.Snapshot(robot, q, v)          # once per tick
        >>> reading = leg.read(snapshot)                 # sensors, actuators, events share it
        >>> solution = body.solve(snapshot, wrench)
    """

    __slots__ = ("robot", "tree", "q", "v", "backend", "_joints", "_jacobian", "_frames", "_rows",
                 "_extra", "_velocities", "_frame_velocities", "_buffer")  # fmt: skip

    def __init__(
        self, robot: object, q: np.ndarray, v: np.ndarray | None = None, backend: str = "auto"
    ) -> None:
        tree: KinematicTree = tree_of(robot)
        if backend != "auto" and backend not in _BACKENDS:
            raise InvalidInputError(f"backend must be one of {_BACKENDS}, got {backend!r}.")
        if backend == "compiled" and not tree.compiled:
            reason = (
                f"joints {tree.unsupported}" if tree.unsupported
                else "the compiled core is not built (or VA_CORE=0)"
            )  # fmt: skip
            raise InvalidInputError(
                f"backend='compiled' is not available for model {tree.model.name!r}: {reason}."
            )
        self.robot = robot
        self.tree = tree
        # private copies: a driver that reuses its buffers cannot change q or v under us
        checked = tree.check_configuration(q)
        self.q = checked.copy() if checked is q or checked.base is not None else checked
        if v is not None:
            checked = tree.check_velocity(v)
            v = checked.copy() if checked is v or checked.base is not None else checked
        self.v = v
        if backend == "auto":
            backend = "compiled" if tree.compiled else "pinocchio"
        self.backend = backend
        self._joints = None
        self._jacobian = None
        self._frames = None
        # what the pass fills, then the frames outside the table (dicts made on first use)
        self._rows: dict[int, int] | None = None
        self._extra: dict[int, tuple[np.ndarray, np.ndarray]] | None = None
        self._velocities: dict[int, np.ndarray] | None = None
        self._frame_velocities: np.ndarray | None = None  # (rows, 3): the table's, with v
        self._buffer = None  # the core's pass: joints and velocities cut from it lazily

    def _run(self) -> None:
        if self.backend == "compiled":
            self._take(*self.tree.core_pass(self.q, self.v))
            return
        model = self.tree.model
        data = thread_data(model)
        pin.computeJointJacobians(model, data, self.q)
        pin.updateFramePlacements(model, data)
        self._jacobian = np.array(data.J).reshape(6, model.nv)  # (6,) when nv is 1
        rows, _, _ = self.tree.frame_tables
        frames = np.empty((len(rows), 12))
        for frame_id, row in rows.items():
            frames[row] = placement_row(data.oMf[frame_id])
        self._frames, self._rows = frames, rows
        self._joints = np.array([placement_row(m) for m in data.oMi])

    def _take(self, buffer: np.ndarray, frames: int, rows: dict[int, int]) -> None:
        """Keep the core's pass ``buffer``: Jacobian and frames now, the rest cut on first read."""
        at, nv = 12 * self.tree.njoints, self.tree.nv
        self._buffer, self._rows = buffer, rows
        self._jacobian = buffer[at : at + 6 * nv].reshape(6, nv)
        self._frames = buffer[at + 6 * nv : at + 6 * nv + 12 * frames].reshape(frames, 12)

    def _joint_table(self) -> np.ndarray:
        """``(njoints, 12)`` joint placements (the pass runs first if it has not)."""
        joints = self._joints
        if joints is None:
            if self._jacobian is None:
                self._run()
            joints = self._joints
            if joints is None:  # the core's pass: cut from its buffer on first use
                joints = self._joints = self._buffer[: 12 * self.tree.njoints].reshape(-1, 12)
        return joints

    def _velocity_table(self) -> np.ndarray | None:
        """``(rows, 3)`` the table's frame velocities, or None (after the pass; without ``v``)."""
        table = self._frame_velocities
        if table is None and self._buffer is not None:  # cut on first use
            start = 12 * self.tree.njoints + 6 * self.tree.nv + self._frames.size
            if self._buffer.shape[0] > start:
                table = self._frame_velocities = self._buffer[start:].reshape(-1, 3)
        return table

    @property
    def computed(self) -> bool:
        """Whether the kinematics pass ran (a reader asked for the Jacobian or placements)."""
        return self._jacobian is not None

    @property
    def jacobian_world(self) -> np.ndarray:
        """``(6, nv)`` world joint Jacobian, linear rows first (``data.J``; do not modify)."""
        if self._jacobian is None:
            self._run()
        return self._jacobian

    @property
    def frame_table(self) -> np.ndarray:
        """``(rows, 12)`` world placements of the frames the actuators read (do not modify).

        Row ``r``: a rotation (row-major, 9 entries) then a position [m].
        """
        if self._frames is None:
            self._run()
        return self._frames

    def _placement(self, frame_id: int) -> tuple[np.ndarray, np.ndarray]:
        if self._frames is None:
            self._run()
        row = self._rows.get(frame_id)
        if row is not None:
            entry = self._frames[row]
            return entry[:9].reshape(3, 3), entry[9:]
        extra = self._extra
        if extra is None:
            extra = self._extra = {}
        cached = extra.get(frame_id)
        if cached is None:
            frame = self.tree.model.frames[frame_id]
            joint = self._joint_table()[frame.parentJoint]
            rotation_j, position_j = joint[:9].reshape(3, 3), joint[9:]
            cached = (
                rotation_j @ frame.placement.rotation,
                rotation_j @ frame.placement.translation + position_j,
            )
            extra[frame_id] = cached
        return cached

    def _frame_id(self, frame: int | str) -> int:
        if isinstance(frame, str):
            return self.tree.frame_id(frame)
        model = self.tree.model
        if isinstance(frame, bool) or not isinstance(frame, (int, np.integer)):
            raise FrameNotFoundError(
                f"Frame must be a frame name (str) or id (int), got {type(frame).__name__}; "
                f"model {model.name!r} has {len(model.frames)} frames."
            )
        if not 0 <= int(frame) < len(model.frames):
            raise FrameNotFoundError(
                f"Frame id {frame} is out of range; model {model.name!r} has "
                f"{len(model.frames)} frames."
            )
        return int(frame)

    def placement(self, frame: int | str) -> tuple[np.ndarray, np.ndarray]:
        """``(rotation (3, 3), position (3,))`` of a frame in the world (views: do not modify).

        Raises:
            FrameNotFoundError: Unknown frame name or id.
        """
        return self._placement(self._frame_id(frame))

    def named_row(self, frame: object) -> int:
        """The row of a frame given by a tabled name in `frame_table`, else -1."""
        row = self.tree.name_rows.get(frame) if frame.__class__ is str else None
        if row is None:
            return -1
        if self._frames is None:
            self._run()
        return row if row < self._frames.shape[0] else -1

    def frame_position(self, frame: int | str) -> np.ndarray:
        """World position of a frame's origin [m] (a copy).

        Raises:
            FrameNotFoundError: Unknown frame.
        """
        row = self.named_row(frame)
        if row >= 0:  # a tabled frame by name: one row read (a tick's cost)
            return self._frames[row, 9:].copy()
        return self._placement(self._frame_id(frame))[1].copy()

    def frame_rotation(self, frame: int | str) -> np.ndarray:
        """World orientation of a frame, a 3x3 rotation matrix (a copy).

        Raises:
            FrameNotFoundError: Unknown frame.
        """
        return self._placement(self._frame_id(frame))[0].copy()

    def frame_velocity(self, frame: int | str) -> np.ndarray:
        """Linear velocity of a frame's origin in world axes [m/s].

        Raises:
            FrameNotFoundError: Unknown frame.
            InvalidInputError: The snapshot was built without ``v``.
        """
        if self.v is None:
            raise InvalidInputError("frame_velocity needs a snapshot built with v.")
        frame_id = self._frame_id(frame)
        if self._frames is None:
            self._run()
        table = self._velocity_table()  # the compiled pass computed the table's
        row = None if table is None else self._rows.get(frame_id)
        if row is not None:
            return table[row].copy()
        velocities = self._velocities
        if velocities is None:
            velocities = self._velocities = {}
        cached = velocities.get(frame_id)
        if cached is None:  # a frame the pass did not compute, or Pinocchio's pass
            x, y, z = self._placement(frame_id)[1].tolist()
            columns = self.tree.frame_columns(frame_id)
            cached = velocities[frame_id] = np.array(
                velocity_of_point(self.jacobian_world, self.v, columns, x, y, z)
            )
        return cached.copy()

    def center_of_mass(self) -> np.ndarray:
        """Centre of mass of the whole robot in the world [m], from this snapshot's kinematics.

        Returns:
            ``(3,)`` position [m] in world axes.

        Raises:
            InvalidInputError: The robot has no mass.
        """
        tree = self.tree
        if not tree.mass > 0.0:
            raise InvalidInputError(f"Robot {tree.model.name!r} has no mass: no centre of mass.")
        return np.array(center_of_mass_of(self._joint_table(), tree.masses, tree.levers))

    @classmethod
    def of_pass(
        cls, robot: object, q: np.ndarray, v: np.ndarray, buffer: np.ndarray, rows: dict[int, int]
    ) -> Snapshot:
        """The snapshot of a pass at ``q``, ``v`` the compiled core made already (a plan's tick).

        ``buffer``: joints, Jacobian, ``len(rows)`` frames and their velocities; ``rows``: frame
        id -> row of the pass's frame table.

        Raises:
            InvalidInputError: A bad ``q`` or ``v``.
        """
        snapshot = cls(robot, q, v)
        snapshot._take(buffer, len(rows), rows)
        return snapshot

    def __repr__(self) -> str:
        done = "computed" if self._jacobian is not None else "not computed yet"
        return (
            f"Snapshot(robot={getattr(self.robot, 'name', '?')!r}, backend={self.backend!r}, "
            f"velocity={'yes' if self.v is not None else 'no'}, {done})"
        )
