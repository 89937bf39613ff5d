"""Traced numbers: what a gait's hooks and a component's formula are lowered through.

Given [`Sym`][] values, a hook written with plain arithmetic and `scalar` records its operations
into a compiled plan's program; what cannot be traced (a Python ``if`` on a traced value, a numpy
call) raises `TraceError` and stays a Python callback.
"""

from __future__ import annotations

import contextvars
from collections.abc import Callable, Sequence

from ..exceptions import TraceError


def _operator(name: str, swapped: bool = False) -> Callable[[Sym, object], Sym]:
    """The method that appends the binary op ``name`` (``swapped``: the operands reversed)."""

    def method(self: Sym, other: object) -> Sym:
        if swapped:
            return self.program.binary(name, other, self)
        return self.program.binary(name, self, other)

    return method


class Sym:
    """A traced float: register ``index`` of a program's blackboard.

    Arithmetic, comparisons and `scalar`'s functions on it append ops to ``program``;
    ``bool()`` and ``float()`` refuse (the value is only known when the plan runs).
    """

    __slots__ = ("index", "program")

    def __init__(self, program: object, index: int) -> None:
        self.program = program
        self.index = index

    # arithmetic (Python's operand order: the same IEEE operations as on floats)
    __add__ = _operator("add")
    __radd__ = _operator("add", swapped=True)
    __sub__ = _operator("sub")
    __rsub__ = _operator("sub", swapped=True)
    __mul__ = _operator("mul")
    __rmul__ = _operator("mul", swapped=True)
    __truediv__ = _operator("div")
    __rtruediv__ = _operator("div", swapped=True)

    def __neg__(self) -> Sym:
        return self.program.unary("neg", self)

    def __pos__(self) -> Sym:
        return self

    def __abs__(self) -> Sym:
        return self.program.unary("abs", self)

    def __pow__(self, exponent: object) -> Sym:
        if exponent == 2:
            return self.program.binary("mul", self, self)
        if exponent == 0.5:
            return self.program.unary("sqrt", self)
        raise TraceError(f"Sym ** {exponent!r}: only squares and square roots are lowered.")

    # comparisons give 1.0 or 0.0
    __lt__ = _operator("lt")
    __le__ = _operator("le")
    __gt__ = _operator("lt", swapped=True)
    __ge__ = _operator("le", swapped=True)
    __eq__ = _operator("eq")  # type: ignore[assignment]
    __ne__ = _operator("ne")  # type: ignore[assignment]

    def __bool__(self) -> bool:
        raise TraceError(
            "a Python `if`, `and`, `or`, `min` or `max` on a traced value: its result is only "
            "known when the plan runs. Write it with virtual_actuators.vocabulary.scalar "
            "(select, minimum, maximum, clip)."
        )

    def __float__(self) -> float:
        raise TraceError("float() of a traced value: keep it in the plan's arithmetic.")

    __index__ = __int__ = __float__

    def __array__(self, *args: object, **kwargs: object) -> object:
        raise TraceError("numpy on a traced value: write the arithmetic with floats and tuples.")

    def __repr__(self) -> str:
        return f"Sym(r{self.index})"

    __hash__ = object.__hash__


def is_traced(*values: object) -> bool:
    """Whether any of ``values`` (or an entry of a sequence among them) is a `Sym`."""
    for value in values:
        if isinstance(value, Sym):
            return True
        if isinstance(value, (tuple, list)) and any(isinstance(v, Sym) for v in value):
            return True
    return False


class Tracing:
    """What a traced hook writes to: its ``program``, the plan's ``slots`` (of each owner kept).

    ``slots``: ``id(owner) -> {name: (register, size)}`` (parameters, a gait's `Memory`).
    """

    def __init__(self, program: object, slots: dict[int, dict[str, tuple[int, int]]]) -> None:
        self.program = program
        self.slots = slots

    def slot(self, owner: object, name: str) -> tuple[int, int] | None:
        """``(register, size)`` of ``owner``'s slot ``name`` in the plan, or None."""
        return self.slots.get(id(owner), {}).get(name)


#: The tracing in progress (None: hooks run on floats).
TRACING: contextvars.ContextVar[Tracing | None] = contextvars.ContextVar("TRACING", default=None)


def traced_read(owner: object, name: str) -> tuple | None:
    """``owner``'s slot ``name`` as traced values when a trace is running and keeps it."""
    tracing = TRACING.get()
    where = None if tracing is None else tracing.slot(owner, name)
    if where is None:
        return None
    register, size = where
    return tuple(tracing.program.read(register + i) for i in range(size))


def traced_store(owner: object, name: str, values: Sequence, offset: int = 0) -> bool:
    """Store ``values`` into ``owner``'s slot ``name`` (from ``offset``) in the running trace.

    Returns:
        False when no trace keeps that slot (the caller sets it on floats).

    Raises:
        TraceError: A traced value, with no trace keeping the slot.
    """
    tracing = TRACING.get()
    where = None if tracing is None else tracing.slot(owner, name)
    if where is None:
        if is_traced(*values):
            raise TraceError(f"a traced value written to {name!r}, which the plan does not keep.")
        return False
    register, size = where
    if offset + len(values) > size:
        raise TraceError(f"{name!r} holds {size} values, {offset + len(values)} written.")
    for i, value in enumerate(values):
        tracing.program.store(register + offset + i, value)
    return True


def lowerable(function: Callable) -> Callable:
    """Mark a hook or predicate as written to be traced (`scalar` math, `Memory` state, tuples).

    A compiled plan traces a marked callable into its ops; an unmarked one (a user's lambda)
    runs as a Python piece of the tick.
    """
    function.__va_lowerable__ = True
    return function


def is_lowerable(function: object) -> bool:
    """Whether ``function`` (or a bound method's function) is marked by `lowerable`."""
    return bool(getattr(getattr(function, "__func__", function), "__va_lowerable__", False))
