"""Lowering: a StateMachine and a Controller become one compiled machine's data.

A traced hook or event sees a [`TraceContext`][] (the tick's context as traced ops). What is
traced, what runs as a Python piece and why: docs/reference/control.md.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from ...exceptions import TraceError
from ...kinematics.tree import tree_of
from ...vocabulary.scalar import atan2
from ...vocabulary.traced import TRACING, Sym, Tracing, is_lowerable
from ..context import POSITION_COLUMNS
from .builder import TIME, TIME_IN_STATE, PlanBuilder, Program
from .memory import Memory

#: How an attachment's wrench becomes efforts (plan_machine.hpp's Mapping).
SERIAL, PARTITIONED, JOINTS, PYTHON, SOLVER, GRAVITY = 0, 1, 2, 3, 4, 5


class Slots:
    """One owner's slots: ``slots[name]`` reads (traced copies), ``slots.store(name, v)`` writes."""

    def __init__(self, program: Program, layout: dict[str, tuple[int, int]]) -> None:
        self._program, self._layout = program, layout

    def __getitem__(self, name: str) -> tuple:
        base, size = self._layout[name]
        return tuple(self._program.read(base + i) for i in range(size))

    def store(self, name: str, values: tuple) -> None:
        """Write ``values`` into slot ``name``."""
        base, size = self._layout[name]
        if len(values) != size:
            raise TraceError(f"slot {name!r} holds {size} values, {len(values)} stored.")
        for i, value in enumerate(values):
            self._program.store(base + i, value)


class Lowering:
    """A machine being lowered: its registers, programs, slots, frames and Python pieces.

    Args:
        machine: The [`MachineController`][virtual_actuators.MachineController].

    Attributes:
        builder: The registers and programs.
        pieces: ``(what, why)`` of each piece left to Python.
        callbacks: The Python pieces' callables (the plan's CALL ops run them by index).
    """

    def __init__(self, machine: object) -> None:
        self.robot = machine.controller.robot
        self.tree = tree_of(self.robot)
        self.builder = PlanBuilder()
        self.pieces: list[tuple[str, str]] = []
        self.callbacks: list[Callable[[], object]] = []
        self.contacts: dict[str, list] = {}  # frame -> [register, required]
        self.slots: dict[int, dict[str, tuple[int, int]]] = {}
        self.owners: list[tuple[object, dict[str, tuple[int, int]]]] = []
        self.runtime = None  # the CompiledMachine, once built (the pieces read its views)

    def row(self, frame: str) -> int:
        """The frame table's row of ``frame`` (added to the table if need be)."""
        self.tree.frame_id(frame)
        return self.tree.name_rows[frame]

    def contact_register(self, frame: str, required: bool) -> int:
        """The register the tick writes ``frame``'s contact switch into."""
        if frame not in self.contacts:
            self.contacts[frame] = [self.builder.allocate(1), False]
        entry = self.contacts[frame]
        entry[1] = entry[1] or required
        return entry[0]

    def keep(self, owner: object, slots: dict[str, np.ndarray]) -> dict[str, tuple[int, int]]:
        """Registers for ``owner``'s slots (once per owner), initialised from its arrays."""
        layout = self.slots.get(id(owner))
        if layout is None:
            layout = {}
            for name, array in slots.items():
                values = np.asarray(array, dtype=float).reshape(-1)
                layout[name] = (self.builder.allocate(values.size, values.tolist()), values.size)
            self.slots[id(owner)] = layout
            self.owners.append((owner, layout))
        return layout

    def keep_memories(self, function: object) -> None:
        """Keep every `Memory` a hook reaches: its owner's attributes, closure and globals."""
        owner = getattr(function, "__self__", None)
        values = list(vars(owner).values()) if hasattr(owner, "__dict__") else []
        plain = getattr(function, "__func__", function)
        for cell in getattr(plain, "__closure__", None) or ():
            try:
                values.append(cell.cell_contents)
            except ValueError:  # a variable not bound yet
                continue
        code, names = getattr(plain, "__code__", None), getattr(plain, "__globals__", {})
        values += [names[name] for name in getattr(code, "co_names", ()) if name in names]
        for value in values:
            if isinstance(value, Memory):
                self.keep(value, value.plan_slots())

    def trace(self, body: Callable[[Program], None]) -> Program:
        """A program made by ``body`` under tracing (the plan's slots readable and writable).

        Raises:
            TraceError: What ``body`` cannot trace (the caller makes it a Python piece).
        """
        program = self.builder.program()
        token = TRACING.set(Tracing(program, self.slots))
        try:
            body(program)
        finally:
            TRACING.reset(token)
        return program

    def python(self, what: str, why: str, callback: Callable[[], object]) -> Program:
        """A program of one CALL op that runs ``callback`` (a Python piece of the tick)."""
        self.pieces.append((what, why))
        self.callbacks.append(callback)
        program = self.builder.program()
        program.ops.append((self.builder.codes["call"], 0, len(self.callbacks) - 1, 0, 0))
        return program

    def piece(self, what: str, body: Callable | None, why: str, run: Callable[[], object]) -> int:
        """The program ``body`` traces, else the piece ``run`` (``why``, or the trace's error)."""
        if body is not None:
            try:
                return self.trace(body).index
            except TraceError as error:
                self.builder.programs.pop()  # the failed trace's program
                why = str(error)
        return self.python(what, why, run).index

    def hook(self, state: str, kind: str, hook: Callable | None) -> int:
        """The program of a state's ``on_enter`` or ``on_update`` hook (-1 for none)."""
        if hook is None:
            return -1
        traced = is_lowerable(hook)
        if traced:
            self.keep_memories(hook)

        def body(program: Program) -> None:
            hook(TraceContext(self, program, state))

        what, why = f"state {state!r}: {kind}", "a Python hook (not marked lowerable)"
        return self.piece(what, body if traced else None, why, lambda: hook(self.runtime.context()))

    def exit(self, state: str, event: object) -> tuple[int, int]:
        """``(program, result register)`` of one of a state's exits."""
        result = self.builder.allocate(1)
        if is_lowerable(event):
            self.keep_memories(event)

        def body(program: Program) -> None:
            program.store(result, TraceContext(self, program, state).event(event))

        def run() -> None:
            self.runtime.registers[result] = 1.0 if event(self.runtime.context()) else 0.0

        traced = hasattr(event, "lower") or is_lowerable(event)
        what = f"state {state!r}: the event {event!r}"
        why = "a Python event (a lambda or a function not marked lowerable)"
        return self.piece(what, body if traced else None, why, run), result


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

    def contact(self, frame: str, required: bool = True) -> Sym:
        """The contact switch of ``frame`` (1.0 closed, 0.0 open), a register the tick writes."""
        return self.program.read(self._lowering.contact_register(frame, required))

    in_contact = contact  # a required switch

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
