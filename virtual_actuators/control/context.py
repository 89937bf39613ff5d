"""The tick's context of a gait's state machine, read by its events and state callbacks."""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping

import numpy as np

from ..exceptions import InvalidAxisError, InvalidInputError, suggestion
from ..kinematics.snapshot import Snapshot
from ..models.robot import Robot
from ..vocabulary.arguments import check_number, check_robot, describe

#: A world axis's column in a row of a snapshot's frame table (rotation, then position).
POSITION_COLUMNS = {"x": 9, "y": 10, "z": 11}


def table_entry(snapshot: Snapshot, frame: object, column: int) -> float | None:
    """Entry ``column`` of a frame's row in the snapshot's frame table, None if not tabled."""
    row = snapshot.named_row(frame)
    return snapshot.frame_table.item(row, column) if row >= 0 else None


class Context:
    """What events see at one tick: state, time, contacts and frame positions on demand.

    Args:
        robot: The robot (frame names are resolved against its model).
        q: Configuration ``(nq,)``.
        v: Velocity ``(nv,)``.
        time: Controller time [s].
        contacts: Contact switches by frame name (e.g. ``{"left_heel": True}``).
        time_in_state: Seconds since the current state was entered [s].
        snapshot: The tick's snapshot of ``(q, v)``; built from ``q`` and ``v`` when None.

    Attributes:
        frame_position: ``frame_position(frame)``, the world position of a frame [m].
        frame_rotation: ``frame_rotation(frame)``, its world orientation (a 3x3 rotation).
        frame_velocity: ``frame_velocity(frame)``, its origin's linear velocity in world axes
            [m/s]. The three are the tick's [`Snapshot`][]'s reads, no kinematics of their own
            (an unknown frame raises its FrameNotFoundError, with close matches).

    Raises:
        InvalidInputError: ``robot`` is not a robot; ``time`` or ``time_in_state`` is not a
            finite number; ``contacts`` is not a dict; ``snapshot`` is not a [`Snapshot`][] of
            ``robot``; bad ``q`` or ``v`` (when no snapshot is given).
    """

    def __init__(
        self,
        robot: Robot,
        q: np.ndarray,
        v: np.ndarray,
        time: float,
        contacts: Mapping[str, bool] | None = None,
        time_in_state: float = 0.0,
        *,
        snapshot: Snapshot | None = None,
    ) -> None:
        # the per-tick case: a Snapshot of this robot's model (which proves the robot one)
        known = isinstance(snapshot, Snapshot) and snapshot.tree.model is getattr(
            robot, "model", None
        )
        if not known:
            check_robot(robot, "Context")
        time = check_number(time, "Context: time [s]")
        time_in_state = check_number(time_in_state, "Context: time_in_state [s]")
        if contacts is not None and not isinstance(contacts, Mapping):
            raise InvalidInputError(
                f"Context: contacts must be a dict {{frame: bool}} or None, got "
                f"{describe(contacts)}."
            )
        if snapshot is None:
            snapshot = Snapshot(robot, q, v)
        elif not known:  # not a Snapshot, or one of another robot
            raise InvalidInputError(
                f"Context: snapshot must be a va.Snapshot of the context's robot or None, got "
                f"{describe(snapshot)}."
            )
        self._fill(robot, snapshot, float(time), dict(contacts or {}), time_in_state)

    def _fill(
        self, robot: Robot, snapshot: Snapshot, time: float, contacts: dict, time_in_state: float
    ) -> None:
        self.robot = robot
        self.snapshot = snapshot
        # the snapshot's reads themselves (a tick's cost: no second call per read)
        self.frame_position = snapshot.frame_position
        self.frame_velocity = snapshot.frame_velocity
        self.frame_rotation = snapshot.frame_rotation
        self.q, self.v, self.time = snapshot.q, snapshot.v, time
        self.contacts = contacts
        self.time_in_state = time_in_state
        self.state: str | None = None

    @classmethod
    def of_tick(
        cls, robot: Robot, snapshot: Snapshot, time: float, contacts: Mapping[str, bool] | None
    ) -> Context:
        """The context of a tick whose snapshot (of ``robot``, with ``v``) is built already.

        Skips the checks a float time and a dict (or no) contacts pass (a tick's cost).

        Raises:
            InvalidInputError: As the constructor.
        """
        if (
            time.__class__ is not float
            or not math.isfinite(time)
            or not (contacts is None or contacts.__class__ is dict)
            or snapshot.__class__ is not Snapshot
            or snapshot.tree.model is not getattr(robot, "model", None)
        ):
            return cls(robot, snapshot.q, snapshot.v, time, contacts, snapshot=snapshot)
        context = cls.__new__(cls)
        context._fill(robot, snapshot, time, {} if contacts is None else contacts.copy(), 0.0)
        return context

    def placement(self, frame: str) -> tuple[np.ndarray, np.ndarray]:
        """``(rotation, position)`` of a frame in the world (views of the tick's snapshot).

        Raises:
            FrameNotFoundError: Unknown frame (with close matches).
        """
        return self.snapshot.placement(frame)

    def center_of_mass(self) -> np.ndarray:
        """The robot's centre of mass in the world [m] (from the tick's snapshot).

        Raises:
            InvalidInputError: The robot has no mass.
        """
        return self.snapshot.center_of_mass()

    def frame_pitch(self, frame: str) -> float:
        """Rotation of a frame about the world y axis [rad] (planar robots in x-z).

        Raises:
            FrameNotFoundError: Unknown frame (with close matches).
        """
        snapshot = self.snapshot
        sine = table_entry(snapshot, frame, 2)  # a tabled frame: its rotation's row 0
        if sine is not None:
            return math.atan2(sine, table_entry(snapshot, frame, 0))
        rotation = snapshot.placement(frame)[0]
        return math.atan2(rotation.item(0, 2), rotation.item(0, 0))

    def frame_coordinate(self, frame: str, axis: str) -> float:
        """One world coordinate [m] of a frame's origin (`frame_position` along ``axis``).

        Args:
            frame: Frame name.
            axis: ``"x"``, ``"y"`` or ``"z"``.

        Raises:
            InvalidAxisError: ``axis`` is not x, y or z.
            FrameNotFoundError: Unknown frame (with close matches).
        """
        column = POSITION_COLUMNS.get(axis) if axis.__class__ is str else None
        if column is None:
            raise InvalidAxisError(
                f"Context.frame_coordinate: axis must be 'x', 'y' or 'z', got {axis!r}."
            )
        value = table_entry(self.snapshot, frame, column)
        if value is not None:
            return value
        return self.frame_position(frame).item(column - 9)

    def in_contact(self, frame: str) -> bool:
        """The contact switch of ``frame``.

        Raises:
            InvalidInputError: No switch reported for that frame.
        """
        try:
            return bool(self.contacts[frame])
        except (KeyError, TypeError):  # TypeError: an unhashable frame
            hint = (
                suggestion(str(frame), self.contacts, "contact switches")
                if self.contacts
                else "This context was given no contact switches (Context(..., contacts=...))."
            )
            raise InvalidInputError(f"No contact switch for {frame!r}. {hint}") from None

    def __repr__(self) -> str:
        return f"Context(time={self.time:.4f}, state={self.state!r}, contacts={self.contacts})"


Event = Callable[[Context], bool]
