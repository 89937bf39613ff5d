"""Lowering: a StateMachine and a Controller become one compiled machine's data.

What is traced, what runs as a Python piece and why: docs/reference/control.md.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from ...actuators import ParallelVirtualActuator, VirtualActuator
from ...components.gravity import GravityCompensation
from ...components.posture import Posture
from ...exceptions import TraceError
from ...kinematics.tree import tree_of
from ...vocabulary.traced import TRACING, Tracing, is_lowerable
from .builder import PlanBuilder, Program
from .memory import Memory
from .trace import TraceContext

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
        self.machine = machine
        self.controller = machine.controller
        self.robot = self.controller.robot
        self.tree = tree_of(self.robot)
        self.builder = PlanBuilder()
        self.pieces: list[tuple[str, str]] = []
        self.callbacks: list[Callable[[], object]] = []
        self.contacts: dict[str, list] = {}  # frame -> [register, required]
        self.slots: dict[int, dict[str, tuple[int, int]]] = {}
        self.owners: list[tuple[object, dict[str, tuple[int, int]]]] = []
        self.runtime = None  # the CompiledMachine, once built (the pieces read its views)

    # -- what the plan keeps ------------------------------------------------------------------
    def row(self, frame: str) -> int:
        """The frame table's row of ``frame`` (added to the table if need be)."""
        self.tree.frame_id(frame)
        return self.tree.name_rows[frame]

    def contact_register(self, frame: str, required: bool) -> int:
        """The register the tick writes ``frame``'s contact switch into."""
        entry = self.contacts.get(frame)
        if entry is None:
            register = self.builder.allocate(1)
            entry = self.contacts[frame] = [register, False]
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
        """Keep every `Memory` a hook can reach.

        Its owner's attributes (a method's), the variables it closes over and the globals it
        names (a function's).
        """
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

    # -- programs -----------------------------------------------------------------------------
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

    def hook(self, state: str, kind: str, hook: Callable | None) -> int:
        """The program of a state's ``on_enter`` or ``on_update`` hook (-1 for none)."""
        if hook is None:
            return -1
        what = f"state {state!r}: {kind}"
        if is_lowerable(hook):
            self.keep_memories(hook)
            try:
                return self.trace(lambda p: hook(TraceContext(self, p, state))).index
            except TraceError as error:
                self.builder.programs.pop()  # the failed trace's program
                reason = str(error)
        else:
            reason = "a Python hook (not marked lowerable)"
        return self.python(what, reason, lambda: hook(self.runtime.context())).index

    def exit(self, state: str, event: object) -> tuple[int, int]:
        """``(program, result register)`` of one of a state's exits."""
        result = self.builder.allocate(1)
        what = f"state {state!r}: the event {event!r}"
        if hasattr(event, "lower") or is_lowerable(event):
            if is_lowerable(event):
                self.keep_memories(event)

            def body(program: Program) -> None:
                program.store(result, TraceContext(self, program, state).event(event))

            try:
                return self.trace(body).index, result
            except TraceError as error:
                self.builder.programs.pop()
                reason = str(error)
        else:
            reason = "a Python event (a lambda or a function not marked lowerable)"

        def run() -> None:
            self.runtime.registers[result] = 1.0 if event(self.runtime.context()) else 0.0

        return self.python(what, reason, run).index, result


def attachment_kind(attachment: object) -> str | None:
    """Why an attachment's distribution is a Python piece, or None (the core maps it)."""
    actuator = attachment.actuator
    if isinstance(actuator, VirtualActuator):
        if type(actuator) is not VirtualActuator or actuator is not attachment.sensor:
            return "a serial actuator read through another sensor"
        return None
    if isinstance(actuator, ParallelVirtualActuator):
        if attachment.method == "qp":
            qp = actuator.backends.get("qp")
            if attachment.yield_mask is not None or qp is None:
                return "a QP with a yield policy"
            return None if qp.plan_tables(attachment.plan) is not None else "a numpy QP"
        if attachment.snapshot_solve is None:
            return f"a {attachment.method!r} distribution (the controller's)"
        if attachment.yield_mask is not None and attachment.margins is None:
            return "a yield policy on sole rows"
        return None
    return "an actuator of another kind"


def term_kind(term: object) -> str | None:
    """Why a joint-space term is a Python piece, or None (the core runs it)."""
    if isinstance(term, Posture) and term.null_space is None:
        return None
    if isinstance(term, GravityCompensation):
        return None  # the core's generalized gravity (mapping GRAVITY)
    return "a posture projected on a null space"
