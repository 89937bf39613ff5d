"""The plan's registers ([`PlanBuilder`][]) and programs ([`Program`][]: the core's ops)."""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from ...core import CORE
from ...vocabulary.traced import Sym, TraceError

#: Registers every plan has: the tick's time and the time spent in the current state [s], then
#: the machine's state (its index, when it was entered [s], whether it started), from MACHINE.
TIME, TIME_IN_STATE, MACHINE = 0, 1, 2


class PlanBuilder:
    """The registers of a plan being lowered, and its programs.

    Attributes:
        registers: Initial value of every register.
        programs: The programs, in the order they were made (their index is their id).

    Raises:
        TraceError: The compiled core is not built (or has no plan, ``_core.PLAN_OPS``).
    """

    def __init__(self) -> None:
        table = getattr(CORE, "PLAN_OPS", None)
        if table is None:
            raise TraceError("the compiled core is not built (or has no plan): nothing to lower.")
        self.codes = dict(table)  # the core's op codes by name
        self.registers: list[float] = [0.0] * 5  # TIME, TIME_IN_STATE, the machine's 3
        self.programs: list[Program] = []
        self._constants: dict[str, int] = {}

    def allocate(self, size: int, initial: float | Sequence[float] = 0.0) -> int:
        """``size`` new registers (their first index) set to ``initial``, one or ``size`` values."""
        base = len(self.registers)
        values = [initial] * size if isinstance(initial, (int, float)) else initial
        self.registers.extend(float(v) for v in values)
        return base

    def constant(self, value: float) -> int:
        """The register holding ``value`` (one per distinct bit pattern)."""
        value = float(value)
        key = value.hex()  # one register per bit pattern (NaN is refused before)
        index = self._constants.get(key)
        if index is None:
            index = self._constants[key] = self.allocate(1, value)
        return index

    def program(self) -> Program:
        """A new, empty program."""
        program = Program(self, len(self.programs))
        self.programs.append(program)
        return program

    def assemble(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``(registers, ops, bounds)``: initial registers, ops and programs' spans.

        Every op is ``(code, out, a, b, c)``; a program is ``[start, stop)`` of the ops.
        """
        rows, bounds = [], []
        for program in self.programs:
            bounds.append((len(rows), len(rows) + len(program.ops)))
            rows.extend(program.ops)
        ops, registers = np.array(rows, dtype=np.int64).reshape(-1, 5), np.array(self.registers)
        return registers, ops, np.array(bounds, dtype=np.int64).reshape(-1, 2)


class Program:
    """Ops appended in order (``index``: its id); a traced value is the register an op writes."""

    def __init__(self, builder: PlanBuilder, index: int) -> None:
        self.builder = builder
        self.index = index
        self.ops: list[tuple[int, int, int, int, int]] = []

    def register(self, value: object) -> int:
        """The register of ``value``: a traced value's, or a constant's.

        Raises:
            TraceError: Not a number (a str, an array...), or a value of another plan.
        """
        if isinstance(value, Sym):
            if value.program.builder is not self.builder:
                raise TraceError("a traced value of another plan.")
            return value.index
        if isinstance(value, bool) or not isinstance(value, int | float | np.floating | np.integer):
            raise TraceError(f"a {type(value).__name__} where the plan needs a number.")
        if math.isnan(value):
            raise TraceError("NaN in a declaration constant.")
        return self.builder.constant(value)

    def emit(self, name: str, a: int = 0, b: int = 0, c: int = 0) -> Sym:
        """Append op ``name`` on registers (or immediates) ``a, b, c``; its result."""
        out = self.builder.allocate(1)
        self.ops.append((self.builder.codes[name], out, a, b, c))
        return Sym(self, out)

    def unary(self, name: str, a: object) -> Sym:
        """``name(a)``."""
        return self.emit(name, self.register(a))

    def binary(self, name: str, a: object, b: object) -> Sym:
        """``a name b``."""
        return self.emit(name, self.register(a), self.register(b))

    def select(self, condition: object, a: object, b: object) -> Sym:
        """``a if condition != 0 else b``."""
        return self.emit("select", self.register(condition), self.register(a), self.register(b))

    def read(self, register: int) -> Sym:
        """The value register ``register`` holds now (a copy: later stores do not change it)."""
        return self.emit("copy", register)

    def store(self, register: int, value: object) -> None:
        """Write ``value`` into register ``register`` (a declared slot)."""
        self.ops.append((self.builder.codes["store"], register, self.register(value), 0, 0))

    def center_of_mass(self) -> tuple[Sym, Sym, Sym]:
        """The robot's centre of mass in the world [m], three registers one op writes."""
        out = self.builder.allocate(3)
        self.ops.append((self.builder.codes["center_of_mass"], out, 0, 0, 0))
        return Sym(self, out), Sym(self, out + 1), Sym(self, out + 2)
