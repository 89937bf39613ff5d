"""Relative kinematics of an action frame {B} with respect to reaction frames {A_i}, in {O}.

VAC eq. 1-7: the twist of {B} relative to {A_i} at {B}'s origin, both parts in {O}'s axes; its
transpose maps a wrench on {B} (moment about {B}'s origin, in {O}) to joint torques like the
pair "+wrench on {B}, -wrench on {A_i}".
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
import pinocchio as pin

from ..exceptions import InvalidInputError
from ..vocabulary.axes import AXES, axis_rows
from .sensor_kernels import sensor
from .snapshot import Snapshot
from .tree import tree_of


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


class Sensed(NamedTuple):
    """A serial actuator's reading (`RelativeKinematics.sense`).

    Attributes:
        jacobian: ``(n, nv)`` twist of {B} relative to {A} at {B}'s origin, in {O}.
        position: ``(n,)`` pose of {B} relative to {A} on the selected axes.
        velocity: ``(n,)`` ``jacobian @ v``, or None when not asked for.
    """

    jacobian: np.ndarray
    position: np.ndarray
    velocity: np.ndarray | None


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
        model = robot.model
        self.robot = robot
        self.model = model
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
        self._axis_rows = np.asarray(self.rows, dtype=np.int64)
        #: Rows of {O} then of every {A_i} in the snapshot's frame table (compiled readers).
        self.orientation_rows = np.array([self._row_o, *self._rows_a.tolist()], dtype=np.int64)
        self.orientation_rows_end = int(self.orientation_rows.max()) + 1  # table rows read
        self._rows_end = max(self.orientation_rows_end, self._row_b + 1)  # compute() reads
        self._sensor_rows = np.array([self._row_b, self._row_o, self._rows_a[0]], dtype=np.int64)
        self._sensor_rows_end = int(self._sensor_rows.max()) + 1  # frame rows the sensor reads
        action_joint = model.frames[self.action_id].parentJoint
        #: per chain, velocity indices between {A_i} and {B}, and +1 on {B}'s side of the
        #: path, -1 on {A_i}'s side (shared ancestors and other branches cancel)
        self.chain_columns: list[np.ndarray] = []
        self.chain_signs: list[np.ndarray] = []
        for r in self.reaction_ids:
            columns, signs = self._path(model, action_joint, model.frames[int(r)].parentJoint)
            self.chain_columns.append(columns)
            self.chain_signs.append(signs)

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

    def check_configuration(self, q: np.ndarray) -> np.ndarray:
        """Return ``q`` checked (see `KinematicTree.check_configuration`)."""
        return self.tree.check_configuration(q)

    def check_velocity(self, v: np.ndarray) -> np.ndarray:
        """Return ``v`` checked (see `KinematicTree.check_velocity`)."""
        return self.tree.check_velocity(v)

    def compute(self, state: np.ndarray | Snapshot) -> KinematicState:
        """Return the Jacobian rows in {O} and the frames' placements at a snapshot (or ``q``).

        Args:
            state: A [`Snapshot`][], or a configuration ``(model.nq,)``.

        Returns:
            The `KinematicState`.
        """
        snapshot = self.snapshot(state)
        jacobian_world = snapshot.jacobian_world
        frames = snapshot.frame_table
        if frames.shape[0] < self._rows_end:
            frames = self._frames_of(snapshot)  # frames required after that snapshot ran
        position_b = frames[self._row_b, 9:]
        rotation_o = frames[self._row_o, :9].reshape(3, 3)
        # the point at {B}'s origin moves at v + w x p_B = v - skew(p_B) w: one (n, 6) map
        x, y, z = position_b
        transform = np.zeros((6, 6))
        transform[:3, :3] = transform[3:, 3:] = rotation_o.T
        transform[:3, 3:] = rotation_o.T @ np.array(((0.0, z, -y), (-z, 0.0, x), (y, -x, 0.0)))
        reactions = frames[self._rows_a]
        return KinematicState(
            jacobian_o=transform[self.rows] @ jacobian_world,
            rotation_o=rotation_o,
            position_b=position_b,
            position_a=reactions[:, 9:],
            rotation_a=reactions[:, :9].reshape(-1, 3, 3),
            snapshot=snapshot,
        )

    def rotations(self, state: np.ndarray | Snapshot) -> tuple[np.ndarray, np.ndarray]:
        """World orientations of {O} and of every {A_i}, without any Jacobian.

        Args:
            state: A [`Snapshot`][] or a configuration ``(model.nq,)``.

        Returns:
            ``(rotation_o (3, 3), rotation_a (p, 3, 3))`` (views: do not modify).

        Raises:
            InvalidInputError: A bad ``q``, or a snapshot of another robot.
        """
        snapshot = self.snapshot(state)
        frames = snapshot.frame_table
        if frames.shape[0] < self.orientation_rows_end:
            frames = self._frames_of(snapshot)
        return frames[self._row_o, :9].reshape(3, 3), frames[self._rows_a, :9].reshape(-1, 3, 3)

    def sense(self, state: np.ndarray | Snapshot, velocity: bool = False) -> Sensed:
        """A serial actuator's reading in one compiled call: Jacobian, position, velocity.

        Args:
            state: A [`Snapshot`][] (with ``v`` if ``velocity``) or ``q``.
            velocity: Also compute ``jacobian @ v``.

        Returns:
            The `Sensed` reading of chain 0.

        Raises:
            InvalidInputError: A bad ``q``, a snapshot of another robot, or no velocity.
        """
        snapshot = self.snapshot(state, need_velocity=velocity)
        jacobian_world = snapshot.jacobian_world
        frames = snapshot.frame_table
        if frames.shape[0] < self._sensor_rows_end:
            frames = self._frames_of(snapshot)
        buffer = sensor(
            jacobian_world,
            frames,
            snapshot.v if velocity else _NO_VELOCITY,
            self._axis_rows,
            self._sensor_rows,
            self.chain_columns[0],
            self.chain_signs[0],
        )
        n, nv = self._axis_rows.shape[0], jacobian_world.shape[1]
        jacobian = buffer[: n * nv].reshape(n, nv)
        position = buffer[n * nv : n * nv + n]
        return Sensed(jacobian, position, buffer[n * nv + n :] if velocity else None)

    def _frames_of(self, snapshot: Snapshot) -> np.ndarray:
        rows = {self._row_b: self.action_id, self._row_o: self.reference_id}
        rows.update(zip(self._rows_a.tolist(), self.reaction_ids.tolist(), strict=True))
        frames = np.zeros((max(rows) + 1, 12))
        for row, frame_id in rows.items():
            rotation, position = snapshot.placement(frame_id)
            frames[row, :9], frames[row, 9:] = rotation.ravel(), position
        return frames

    def __repr__(self) -> str:
        names = [self.model.frames[int(r)].name for r in self.reaction_ids]
        return (
            f"RelativeKinematics(action={self.model.frames[self.action_id].name!r}, "
            f"reactions={names}, reference={self.model.frames[self.reference_id].name!r}, "
            f"axes={self.axes})"
        )


def skew(vector: np.ndarray) -> np.ndarray:
    """Return the ``(..., 3, 3)`` cross-product matrices of ``(..., 3)`` vectors."""
    vector = np.asarray(vector)
    out = np.zeros(vector.shape[:-1] + (3, 3))
    x, y, z = vector[..., 0], vector[..., 1], vector[..., 2]
    out[..., 0, 1], out[..., 0, 2] = -z, y
    out[..., 1, 0], out[..., 1, 2] = z, -x
    out[..., 2, 0], out[..., 2, 1] = -y, x
    return out


__all__ = ["AXES", "KinematicState", "RelativeKinematics", "Sensed", "skew"]
