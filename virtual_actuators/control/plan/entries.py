"""A lowered machine's attachments (`Attached`) and joint-space terms (`Term`)."""

from __future__ import annotations

import numpy as np

from ...actuators import ParallelVirtualActuator, VirtualActuator
from ...components.base import Component, has_traced_path
from ...components.gravity import GravityCompensation
from ...distribution.result import Solution
from ...exceptions import TraceError
from ..failures import run_attachment
from ..tick import TickSums
from .builder import Program
from .lower import GRAVITY, JOINTS, PARTITIONED, PYTHON, SERIAL, SOLVER, Lowering, Slots


def attachment_kind(attachment: object) -> str | None:
    """Why an attachment's distribution is a Python piece, or None (the core maps it)."""
    actuator = attachment.actuator
    if isinstance(actuator, VirtualActuator):
        if type(actuator) is not VirtualActuator or actuator is not attachment.sensor:
            return "a serial actuator read through another sensor"
        return None
    if attachment.method == "qp":  # a parallel actuator (Controller.add refuses other kinds)
        qp = actuator.backends.get("qp")
        if attachment.yield_mask is not None or qp is None:
            return "a QP with a yield policy"
        return None if qp.plan_tables(attachment.plan) is not None else "a numpy QP"
    if attachment.snapshot_solve is None:
        return f"a {attachment.method!r} distribution (the controller's)"
    if attachment.yield_mask is not None and attachment.margins is None:
        return "a yield policy on sole rows"
    return None


class Entry:
    """One lowered attachment or joint-space term: its registers and how the core runs it."""

    reports = True  # its wrench and readings are in the tick's output (an attachment's are)

    def __init__(self, compiled: object, name: str, n: int) -> None:
        self.compiled, self.name, self.n = compiled, name, n
        builder = compiled.lowering.builder
        self.position, self.velocity, self.wrench, self.produced = (
            builder.allocate(n) for _ in range(4)
        )
        self.programs: list[int] = []
        self.resets: list[int] = []
        self.mapping = SERIAL
        self.efforts_program = -1
        self.solution = None  # the last Python piece's Solution (parallel attachments)

    def read(self, base: int, program: Program, index: np.ndarray | None = None) -> tuple:
        """Registers ``base + index`` (all ``n`` by default), read now as traced values."""
        rows = range(self.n) if index is None else np.asarray(index).reshape(-1).tolist()
        return tuple(program.read(base + i) for i in rows)

    def component(self, component: object, index: np.ndarray, alone: bool) -> None:
        """The wrench and reset programs of one component on axes ``index``."""
        lowering = self.compiled.lowering
        what = f"{self.name}: {getattr(component, 'name', type(component).__name__)}"
        axes = np.asarray(index).reshape(-1).tolist()
        slots = component.plan_slots() if has_traced_path(component) else None
        if slots is not None:
            layout = lowering.keep(component, slots)

            def wrench(program: Program) -> None:
                traced = component.traced_wrench(
                    Slots(program, layout), self.read(self.position, program, axes),
                    self.read(self.velocity, program, axes), program.read(0),
                )  # fmt: skip
                for k, value in zip(axes, traced, strict=True):
                    total = value if alone else program.read(self.wrench + k) + value
                    program.store(self.wrench + k, total)

            def reset(program: Program) -> None:
                component.traced_reset(
                    Slots(program, layout), self.read(self.position, program, axes),
                    program.read(0),
                )  # fmt: skip

            start = len(lowering.builder.programs)
            try:
                programs = [lowering.trace(wrench).index, lowering.trace(reset).index]
                self.programs.append(programs[0])
                self.resets.append(programs[1])
                return
            except TraceError as error:  # both traces' programs go (the wrench's, if it traced)
                del lowering.builder.programs[start:]
                reason = str(error)
        else:
            reason = "a Python component (no traced formula)"
        at = np.array(axes)

        def python_wrench() -> None:
            registers, time = self.compiled.registers, self.compiled.time
            position, velocity = registers[self.position + at], registers[self.velocity + at]
            wrench = np.asarray(component.compute_wrench(position, velocity, time), dtype=float)
            registers[self.wrench + at] += wrench.reshape(-1)

        self.programs.append(lowering.python(what, reason, python_wrench).index)
        if type(component).reset is not Component.reset:

            def python_reset() -> None:
                component.reset(self.compiled.registers[self.position + at], self.compiled.time)

            piece = lowering.python(f"{what}: reset", reason, python_reset)
            self.resets.append(piece.index)

    def add_to(self, core: object, term: bool, rows, frames, columns, signs, q_rows) -> None:
        """Declare the entry's sensor rows (or joints), registers and programs to the core."""
        self.core_index = core.add_attachment(
            term, rows, frames, columns, signs, q_rows, self.position, self.velocity, self.wrench,
            self.produced, np.array(self.programs, dtype=np.int64),
            np.array(self.resets, dtype=np.int64), self.mapping, self.efforts_program,
        )  # fmt: skip

    def bind(self, core: object) -> None:
        """Take up the core's buffers of this entry (its efforts) once the machine is built."""
        self.efforts = core.efforts(self.core_index)
        self._core = core

    def solved_solution(self) -> object | None:
        """The solution of the last tick's distribution (parallel attachments), or None."""
        return None


class Attached(Entry):
    """An attachment: a serial sensor, its components, its distribution."""

    def __init__(self, compiled: object, name: str, attachment, lowering: Lowering):
        super().__init__(compiled, name, len(attachment.sensor.axes))
        self.attachment = attachment
        single = len(attachment.components) == 1
        for component, index in zip(attachment.components, attachment.indices, strict=True):
            alone = single and len(np.asarray(index).reshape(-1)) == self.n
            self.component(component, index, alone)
        why, actuator = attachment_kind(attachment), attachment.actuator
        qp = why is None and attachment.method == "qp"  # the core's step, the rest in Python
        self.qp = actuator.backends["qp"] if qp else None
        if qp or (why is None and isinstance(actuator, ParallelVirtualActuator)):
            self.mapping = SOLVER if qp else PARTITIONED
            why = "a QP tick whose active set changed" if qp else "a tick the core hands on"
        elif why is not None:
            self.mapping = PYTHON
        if self.mapping != SERIAL:
            piece = lowering.python(f"{name}: distribution", why, self._python_distribution)
            self.efforts_program = piece.index
            if self.mapping != PYTHON:
                lowering.pieces.pop()  # only the rare ticks: not a piece of every tick

    def _python_distribution(self) -> None:
        """The attachment's distribution of the plan's wrench, in Python (failure policy)."""
        compiled, attachment = self.compiled, self.attachment
        controller = compiled.machine.controller
        registers = compiled.registers
        sums = TickSums()
        wrench = registers[self.wrench : self.wrench + self.n].copy()
        run_attachment(
            _Fixed(attachment, wrench), compiled.snapshot(), compiled.time, sums,
            controller.on_failure, controller.effort_limits,
        )  # fmt: skip
        self.efforts[:] = 0.0 if sums.tau is None else sums.tau
        produced = sums.produced.get(self.name)
        if produced is not None:
            registers[self.produced : self.produced + self.n] = produced
        self.solution = sums.solutions.get(self.name)
        if self.qp is not None:  # the warm start the Python stages certified, for the core
            self._guess = self.qp.plan_tables(attachment.plan).slot.active
            self._core.set_guess(self.core_index, self._guess)

    def solved_solution(self) -> object | None:
        """The solution of the last tick's distribution (parallel attachments), or None."""
        if self.mapping == SOLVER:
            out, active, count, norms = self._core.qp_answer(self.core_index)
            if count < 0:  # the Python piece solved it
                return self.solution
            tick = self.qp.answer_tick(out.copy(), norms, active[:count].copy())
            actuator, request = self.attachment.actuator, self.attachment.plan
            return Solution.from_tick(
                tick, 1e-6, actuator.reactions, actuator.axes, request.free,
                bool(actuator.robot.floating_base),
            )  # fmt: skip
        if self.mapping == PARTITIONED:
            residual, scale, rounding, status = self._core.solved(self.core_index)
            if status == 0:
                out = self._core.out(self.core_index).copy()
                return self.attachment.snapshot_solve.solution(out, residual, scale, rounding, 1e-6)
        return self.solution

    def declare(self, core: object) -> None:
        """Declare the attachment to the core: its sensor, programs and distribution."""
        tables = self.attachment.sensor.kinematics.sensor_tables
        self.add_to(core, False, *tables, np.zeros(0, np.int64))
        if self.mapping == SOLVER:
            core_qp, work, keep, weights, tolerances, slot = self.qp.plan_tables(
                self.attachment.plan
            )
            self._work = work  # its buffer is the core's scratch: kept alive here
            q = self.compiled.robot.neutral()
            core.set_qp(
                self.core_index, core_qp, q, work.buffer, work.layout, work.kept, keep, weights,
                tolerances,
            )  # fmt: skip
            self._guess = slot.active
            core.set_guess(self.core_index, slot.active)
        if self.mapping == PARTITIONED:
            ints, floats = self.attachment.snapshot_solve.packed
            core.set_distribution(self.core_index, ints, floats)
            if self.attachment.yield_mask is not None:
                points, axis_rows, minima_axes, lows = self.attachment.margins
                core.set_yield(
                    self.core_index, np.asarray(self.attachment.yield_mask, dtype=np.int64),
                    np.asarray(self.attachment.actuator.kinematics.orientation_rows, np.int64),
                    np.ascontiguousarray(points, dtype=float).reshape(-1, 7),
                    np.asarray(axis_rows, dtype=np.int64),
                    np.asarray(minima_axes, dtype=np.int64), np.asarray(lows, dtype=float),
                )  # fmt: skip


class Term(Entry):
    """A joint-space term (a posture, a gravity compensation): its joints are its axes."""

    reports = False

    def __init__(self, compiled: object, name: str, term, lowering: Lowering):
        if isinstance(term, GravityCompensation):  # the core's generalized gravity
            columns = term.columns.tolist()
            super().__init__(compiled, name, len(columns))
            self.term, self.columns, self.q_rows = term, columns, [0] * len(columns)
            self.mapping = GRAVITY
            return
        super().__init__(compiled, name, len(term.joints))  # a posture, bound to the robot
        self.term, self.columns, self.q_rows = term, term.v_rows.tolist(), term.q_rows.tolist()
        why = None if term.null_space is None else "a posture projected on a null space"
        self.mapping = JOINTS if why is None else PYTHON
        if why is None:
            layout = lowering.keep(term, term.plan_slots())

            def torques(program: Program) -> None:
                traced = term.traced_torques(
                    Slots(program, layout), self.read(self.position, program),
                    self.read(self.velocity, program),
                )  # fmt: skip
                for k, value in enumerate(traced):
                    program.store(self.wrench + k, value)

            def reset(program: Program) -> None:
                term.traced_reset(Slots(program, layout), self.read(self.position, program))

            self.programs.append(lowering.trace(torques).index)
            self.resets.append(lowering.trace(reset).index)
        else:
            self.efforts_program = lowering.python(name, why, self._python_torques).index

    def _python_torques(self) -> None:
        self.efforts[:] = self.term.torques(self.compiled.snapshot())

    def declare(self, core: object) -> None:
        """Declare the term to the core: its joints and programs."""
        none = np.zeros(0, dtype=np.int64)
        columns = np.asarray(self.columns, dtype=np.int64)
        self.add_to(core, True, none, none, columns, np.zeros(0), np.asarray(self.q_rows, np.int64))
        if self.mapping == GRAVITY:
            inertias = self.term.model.inertias
            core.set_gravity(
                self.core_index, np.array([inertia.mass for inertia in inertias]),
                np.array([inertia.lever for inertia in inertias]).reshape(-1, 3),
                np.array(self.term.model.gravity.linear, dtype=float),
            )  # fmt: skip


class _Fixed:
    """An attachment whose components are replaced by the plan's wrench (its distribution)."""

    def __init__(self, attachment: object, wrench: np.ndarray) -> None:
        self._attachment, self._wrench = attachment, wrench
        self.spring_tick = None

    def wrench(self, position: np.ndarray, velocity: np.ndarray, time: float) -> np.ndarray:
        return self._wrench

    def __getattr__(self, name: str) -> object:
        return getattr(self._attachment, name)
