"""Relative kinematics of an action frame {B} with respect to reaction frames {A_i}, in {O}.

VAC eq. 1-7: the twist of {B} relative to {A_i} at {B}'s origin, both parts in {O}'s axes; its
transpose maps a wrench on {B} (moment about {B}'s origin, in {O}) to joint torques like the
pair "+wrench on {B}, -wrench on {A_i}".
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from .. import core
from ..exceptions import InvalidInputError
from ..vocabulary.axes import axis_rows
from .snapshot import Snapshot
from .tree import tree_of


def to_reference(rotation_o: np.ndarray, position_b: np.ndarray) -> np.ndarray:
    """``(6, 6)``: world twists to {B}'s origin in {O}: ``R_O^T (v - skew(p_B) w), R_O^T w``."""
    x, y, z = position_b
    transform = np.zeros((6, 6))
    transform[:3, :3] = transform[3:, 3:] = rotation_o.T
    transform[:3, 3:] = rotation_o.T @ np.array(((0.0, z, -y), (-z, 0.0, x), (y, -x, 0.0)))
    return transform


def rotation_log(rotation: np.ndarray) -> np.ndarray:
    """Rotation vector ``log(R)`` of a 3x3 rotation matrix [rad] (angle in ``[0, pi]``).

    Near ``pi`` the axis comes from the symmetric part, its sign from the skew part; near 0 a
    series keeps full precision.
    """
    cosine = min(max(0.5 * (np.trace(rotation) - 1.0), -1.0), 1.0)
    theta = math.acos(cosine)
    skew_part = np.array(  # vee(R - R^T) = 2 sin(theta) axis
        (rotation[2, 1] - rotation[1, 2], rotation[0, 2] - rotation[2, 0],
         rotation[1, 0] - rotation[0, 1])
    )  # fmt: skip
    if theta < 1e-4:
        return 0.5 * (1.0 + theta * theta / 6.0) * skew_part  # theta / (2 sin theta)
    if math.pi - theta > 1e-3:
        return 0.5 * theta / math.sin(theta) * skew_part
    # near pi: (R + R^T) / 2 - cos I = (1 - cos) a a^T; take the largest diagonal entry
    k = int(np.argmax(np.diag(rotation)))
    scale = 1.0 - cosine
    a_k = math.sqrt(max(rotation[k, k] - cosine, 0.0) / scale)
    axis = 0.5 * (rotation[k] + rotation[:, k]) / (scale * a_k)
    axis[k] = a_k
    return (-theta if axis @ skew_part < 0.0 else theta) * axis


def relative_sensor(
    jacobian_world: np.ndarray,
    frames: np.ndarray,
    v: np.ndarray,
    axis_rows: np.ndarray,
    rows: np.ndarray,
    columns: np.ndarray,
    signs: np.ndarray,
) -> np.ndarray:
    """A serial actuator's Jacobian, position and velocity of {B} relative to {A} in {O}.

    Args:
        jacobian_world: ``(6, nv)`` world joint Jacobian.
        frames: ``(nf, 12)`` frame placements (rotation row by row, translation).
        v: ``(nv,)`` velocity (empty: no velocity).
        axis_rows: ``(n,)`` rows of the selected axes among ``x y z rx ry rz``.
        rows: ``(3,)`` rows of {B}, {O} and {A} in ``frames``.
        columns: velocity indices of the chain between {A} and {B}.
        signs: their +1 / -1.

    Returns:
        One buffer: ``jacobian (n, nv)``, ``position (n,)`` (translations ``R_O^T (p_B - p_A)``,
        rotations ``R_O^T R_A log(R_A^T R_B)``) and ``velocity (n,)`` (zero without ``v``).
    """
    b, o, a = (int(row) for row in rows)
    n, nv = axis_rows.shape[0], jacobian_world.shape[1]
    rotation_b, rotation_o, rotation_a = (frames[i, :9].reshape(3, 3) for i in (b, o, a))
    transform = to_reference(rotation_o, frames[b, 9:12])
    buffer = np.zeros(n * nv + 2 * n)
    jacobian = buffer[: n * nv].reshape(n, nv)
    jacobian[:, columns] = (transform[axis_rows] @ jacobian_world[:, columns]) * signs
    if v.shape[0]:
        buffer[n * nv + n :] = jacobian @ v
    pose = np.zeros(6)
    pose[:3] = rotation_o.T @ (frames[b, 9:12] - frames[a, 9:12])
    if axis_rows[n - 1] >= 3:  # a rotation axis: log of R_A^T R_B, expressed in {O}
        pose[3:] = rotation_o.T @ (rotation_a @ rotation_log(rotation_a.T @ rotation_b))
    buffer[n * nv : n * nv + n] = pose[axis_rows]
    return buffer


#: `relative_sensor` as the library calls it: the compiled core's when it is built.
sensor = core.kernel("relative_sensor", relative_sensor)


@dataclass(frozen=True)
class KinematicState:
    """What `RelativeKinematics.compute` returns for one configuration.

    Attributes:
        jacobian_o: ``(n, nv)`` rows ``axes`` of the world joint Jacobian shifted to {B}'s
            origin and rotated into {O}; chain ``i``'s columns times ``chain_signs[i]``.
        rotation_o: ``(3, 3)`` orientation of {O} in the world.
        position_b: ``(3,)`` position of {B}'s origin in the world [m].
        position_a: ``(p, 3)`` positions of the reaction frames' origins in the world [m].
        rotation_a: ``(p, 3, 3)`` orientations of the reaction frames in the world.
        snapshot: The [`Snapshot`][] this was computed from.
    """

    jacobian_o: np.ndarray
    rotation_o: np.ndarray
    position_b: np.ndarray
    position_a: np.ndarray
    rotation_a: np.ndarray
    snapshot: Snapshot

    def offsets_o(self) -> np.ndarray:
        """Return ``(p, 3)`` vectors from each {A_i}'s origin to {B}'s origin, in {O} [m]."""
        return (self.position_b[None, :] - self.position_a) @ self.rotation_o


_NO_VELOCITY = np.zeros(0)


class RelativeKinematics:
    """Jacobians and virtual sensors of {B} relative to each {A_i}, expressed in {O} (thread-safe).

    Args:
        robot: The robot.
        action_id: Frame id of {B}.
        reaction_ids: Frame ids of the {A_i}.
        reference_id: Frame id of {O}.
        axes: Selected axes (an ordered subset of [`AXES`][]).
    """

    def __init__(
        self,
        robot: object,
        action_id: int,
        reaction_ids: Sequence[int],
        reference_id: int,
        axes: Sequence[str],
    ) -> None:
        model = self.model = robot.model
        self.robot = robot
        self.tree = tree_of(robot)
        self.action_id = int(action_id)
        self.reaction_ids = np.array(reaction_ids, dtype=int)
        self.reference_id = int(reference_id)
        self.axes = tuple(axes)
        self.rows = axis_rows(self.axes)
        self.nq, self.nv = model.nq, model.nv
        self.tree.require([self.action_id, self.reference_id, *self.reaction_ids.tolist()])
        frame_rows = self.tree.frame_tables[0]  # rows never move once assigned
        self._row_b = frame_rows[self.action_id]
        self._row_o = frame_rows[self.reference_id]
        self._rows_a = np.array([frame_rows[int(r)] for r in self.reaction_ids], dtype=int)
        #: Rows of {B}, {O}, then every {A_i} in the snapshot's frame table (compiled readers).
        self.frame_rows = np.array([self._row_b, self._row_o, *self._rows_a.tolist()], np.int64)
        #: Rows of {O} then of every {A_i} in the snapshot's frame table (compiled readers).
        self.orientation_rows = self.frame_rows[1:]
        self.orientation_rows_end = int(self.orientation_rows.max()) + 1  # table rows read
        self._rows_end = int(self.frame_rows.max()) + 1  # compute() reads
        joint_b, reactions = model.frames[self.action_id].parentJoint, self.reaction_ids.tolist()
        #: per chain, velocity indices between {A_i} and {B}, and +1 on {B}'s side of the
        #: path, -1 on {A_i}'s side (shared ancestors and other branches cancel)
        paths = [self._path(model, joint_b, model.frames[r].parentJoint) for r in reactions]
        self.chain_columns: list[np.ndarray] = [columns for columns, _ in paths]
        self.chain_signs: list[np.ndarray] = [signs for _, signs in paths]
        #: Chain 0's sensor tables (`sensor`'s arguments after ``v``): the axes' rows, the rows
        #: of {B}, {O} and {A} in the frame table, the chain's velocity indices and signs.
        self.sensor_tables = (
            np.asarray(self.rows, dtype=np.int64), self.frame_rows[:3].copy(),
            self.chain_columns[0], self.chain_signs[0],
        )  # fmt: skip
        self.sensor_rows_end = int(self.frame_rows[:3].max()) + 1  # frame rows the sensor reads

    @staticmethod
    def _path(model: pin.Model, joint_b: int, joint_a: int) -> tuple[np.ndarray, np.ndarray]:
        support_b = set(model.supports[joint_b])
        support_a = set(model.supports[joint_a])
        columns, signs = [], []
        for joint_id, sign in sorted(
            [(j, 1.0) for j in support_b - support_a] + [(j, -1.0) for j in support_a - support_b]
        ):
            joint = model.joints[joint_id]
            columns.extend(range(joint.idx_v, joint.idx_v + joint.nv))
            signs.extend([sign] * joint.nv)
        order = np.argsort(columns, kind="stable")
        return np.array(columns, dtype=int)[order], np.array(signs, dtype=float)[order]

    def snapshot(self, state: np.ndarray | Snapshot, need_velocity: bool = False) -> Snapshot:
        """Return ``state`` if it is a snapshot of this robot, else a new snapshot of ``q``.

        Raises:
            InvalidInputError: A snapshot of another robot, or a bad ``q`` or ``v``.
        """
        if isinstance(state, Snapshot):
            if state.tree is not self.tree:
                raise InvalidInputError(
                    f"The snapshot is of robot {getattr(state.robot, 'name', '?')!r}; this "
                    f"actuator belongs to {getattr(self.robot, 'name', '?')!r}."
                )
            if need_velocity and state.v is None:
                raise InvalidInputError("This call needs a velocity: build the snapshot with v.")
            return state
        return Snapshot(self.robot, state)

    def _frames(self, snapshot: Snapshot, end: int) -> np.ndarray:
        """The snapshot's frame table; this actuator's rows alone if it has fewer than ``end``."""
        frames = snapshot.frame_table
        if frames.shape[0] >= end:
            return frames
        rows = {self._row_b: self.action_id, self._row_o: self.reference_id}
        rows.update(zip(self._rows_a.tolist(), self.reaction_ids.tolist(), strict=True))
        frames = np.zeros((max(rows) + 1, 12))
        for row, frame_id in rows.items():
            rotation, position = snapshot.placement(frame_id)
            frames[row, :9], frames[row, 9:] = rotation.ravel(), position
        return frames

    def compute(self, state: np.ndarray | Snapshot) -> KinematicState:
        """The `KinematicState` (Jacobian rows in {O}, placements) at a [`Snapshot`][] or ``q``."""
        snapshot = self.snapshot(state)
        frames = self._frames(snapshot, self._rows_end)
        position_b = frames[self._row_b, 9:]
        rotation_o = frames[self._row_o, :9].reshape(3, 3)
        reactions = frames[self._rows_a]
        return KinematicState(
            jacobian_o=to_reference(rotation_o, position_b)[self.rows] @ snapshot.jacobian_world,
            rotation_o=rotation_o,
            position_b=position_b,
            position_a=reactions[:, 9:],
            rotation_a=reactions[:, :9].reshape(-1, 3, 3),
            snapshot=snapshot,
        )

    def rotations(self, state: np.ndarray | Snapshot) -> tuple[np.ndarray, np.ndarray]:
        """World orientations ``(rotation_o (3, 3), rotation_a (p, 3, 3))``, without any Jacobian.

        ``state``: a [`Snapshot`][] or ``q``; the rotations are views (do not modify).

        Raises:
            InvalidInputError: A bad ``q``, or a snapshot of another robot.
        """
        frames = self._frames(self.snapshot(state), self.orientation_rows_end)
        return frames[self._row_o, :9].reshape(3, 3), frames[self._rows_a, :9].reshape(-1, 3, 3)

    def sense(
        self, state: np.ndarray | Snapshot, velocity: bool = False
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray | None]:
        """Chain 0's reading in one compiled call, at a [`Snapshot`][] (with ``v``) or ``q``.

        Returns:
            ``(jacobian, position, velocity)``: the ``(n, nv)`` twist of {B} relative to {A} at
            {B}'s origin in {O}, the ``(n,)`` pose of {B} relative to {A} on the selected axes,
            and ``jacobian @ v`` if ``velocity`` (else None).

        Raises:
            InvalidInputError: A bad ``q``, a snapshot of another robot, or no velocity.
        """
        snapshot = self.snapshot(state, need_velocity=velocity)
        jacobian_world = snapshot.jacobian_world
        frames = self._frames(snapshot, self.sensor_rows_end)
        v = snapshot.v if velocity else _NO_VELOCITY
        buffer = sensor(jacobian_world, frames, v, *self.sensor_tables)
        n, nv = len(self.axes), jacobian_world.shape[1]
        jacobian = buffer[: n * nv].reshape(n, nv)
        position = buffer[n * nv : n * nv + n]
        return jacobian, position, buffer[n * nv + n :] if velocity else None

    def __repr__(self) -> str:
        names = [self.model.frames[int(r)].name for r in self.reaction_ids]
        return (
            f"RelativeKinematics(action={self.model.frames[self.action_id].name!r}, "
            f"reactions={names}, reference={self.model.frames[self.reference_id].name!r}, "
            f"axes={self.axes})"
        )
