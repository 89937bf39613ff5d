"""What a traced hook or event sees: [`TraceContext`][], the tick's context as traced ops."""

from __future__ import annotations

from ...exceptions import TraceError
from ...vocabulary.scalar import atan2
from ...vocabulary.traced import Sym, is_lowerable
from ..context import POSITION_COLUMNS
from .builder import TIME, TIME_IN_STATE, Program


class _Switches:
    """The contact switches as traced values: ``get(frame, default)`` and ``[frame]``."""

    def __init__(self, trace: TraceContext) -> None:
        self._trace = trace

    def get(self, frame: str, default: object = None) -> Sym:
        return self._trace.contact(frame, required=False)

    def __getitem__(self, frame: str) -> Sym:
        return self._trace.contact(frame, required=True)

    def __bool__(self) -> bool:
        return True  # a plan always has its switches (every frame a hook reads has one)


class _Entries:
    """``q`` or ``v`` as traced values by index."""

    def __init__(self, program: Program, op: str, size: int) -> None:
        self._program, self._op, self._size, self._cache = program, op, size, {}

    def __getitem__(self, index: int | slice) -> Sym | tuple:
        if isinstance(index, slice):
            return tuple(self[i] for i in range(*index.indices(self._size)))
        if index < 0:
            index += self._size
        if not 0 <= index < self._size:
            raise TraceError(f"index {index} outside ({self._size},).")
        cached = self._cache.get(index)
        if cached is None:
            cached = self._cache[index] = self._program.emit(self._op, index)
        return cached

    def __len__(self) -> int:
        return self._size


class TraceContext:
    """The traced reads of a tick's [`Context`][virtual_actuators.Context] for ``state``'s hooks.

    The reads go to ``program``; ``lowering`` has the plan's frame rows and contact registers.
    """

    def __init__(self, lowering: object, program: Program, state: str) -> None:
        self._lowering = lowering
        self.program = program
        self.state = state
        self.robot = lowering.robot
        self.snapshot = self  # the snapshot's reads are the context's
        self._frames: dict[tuple[int, int], Sym] = {}
        self._com: tuple | None = None
        model = lowering.robot.model
        self.q = _Entries(program, "q", model.nq)
        self.v = _Entries(program, "v", model.nv)
        self.contacts = _Switches(self)
        self.time = program.read(TIME)
        self.time_in_state = program.read(TIME_IN_STATE)

    # -- frames -------------------------------------------------------------------------------
    def _entry(self, frame: str, column: int) -> Sym:
        """Entry ``column`` (0-8 the rotation row by row, 9-11 the position) of a frame's row."""
        row = self._lowering.row(frame)
        key = (row, column)
        entry = self._frames.get(key)
        if entry is None:
            entry = self._frames[key] = self.program.emit("frame", row, column)
        return entry

    def frame_coordinate(self, frame: str, axis: str) -> Sym:
        """One world coordinate of a frame's origin [m]."""
        return self._entry(frame, POSITION_COLUMNS[axis])

    def frame_position(self, frame: str) -> tuple:
        """World position of a frame [m]."""
        return tuple(self._entry(frame, 9 + i) for i in range(3))

    def frame_rotation(self, frame: str) -> tuple:
        """World orientation of a frame, rows of a rotation matrix."""
        return tuple(tuple(self._entry(frame, 3 * r + c) for c in range(3)) for r in range(3))

    def placement(self, frame: str) -> tuple:
        """``(rotation, position)`` of a frame in the world."""
        return self.frame_rotation(frame), self.frame_position(frame)

    def frame_velocity(self, frame: str) -> tuple:
        """Linear velocity of a frame's origin in world axes [m/s]."""
        row = self._lowering.row(frame)
        return tuple(self.program.emit("frame_velocity", row, axis) for axis in range(3))

    def frame_pitch(self, frame: str) -> Sym:
        """Rotation of a frame about the world y axis [rad] (planar robots in x-z)."""
        return atan2(self._entry(frame, 2), self._entry(frame, 0))

    # -- switches and events ------------------------------------------------------------------
    def contact(self, frame: str, required: bool = True) -> Sym:
        """The contact switch of ``frame`` (1.0 closed, 0.0 open), a register the tick writes."""
        return self.program.read(self._lowering.contact_register(frame, required))

    def in_contact(self, frame: str) -> Sym:
        """The contact switch of ``frame``."""
        return self.contact(frame, required=True)

    def event(self, event: object) -> object:
        """An event's value: lowered (an event object), traced (a `lowerable` predicate).

        Raises:
            TraceError: A predicate that is not lowerable (the caller makes it a Python piece).
        """
        lower = getattr(event, "lower", None)
        if lower is not None:
            return lower(self)
        if is_lowerable(event):
            return event(self)
        raise TraceError(f"the event {event!r} is Python (not marked lowerable).")

    def center_of_mass(self) -> tuple:
        """The robot's centre of mass in the world [m] (one op, read once per trace).

        Raises:
            TraceError: The robot has no mass (the Python tick raises its typed error).
        """
        if self._com is None:
            if not self._lowering.tree.mass > 0.0:
                raise TraceError("the robot has no mass: no centre of mass.")
            self._com = self.program.center_of_mass()
        return self._com
