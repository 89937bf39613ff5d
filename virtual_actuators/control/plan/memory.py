"""A gait's memory: named floats it carries from tick to tick (a compiled plan's registers)."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from ...exceptions import InvalidInputError, TraceError
from ...vocabulary.arguments import check_number
from ...vocabulary.traced import TRACING, traced_store


class Memory:
    """Named floats and tuples of floats a gait carries from tick to tick.

    Args:
        **fields: Each field's initial value: a float, or a tuple of floats.

    Raises:
        InvalidInputError: A value that is not a finite float or a tuple of them.
    """

    __slots__ = ("_layout", "_values")

    def __init__(self, **fields: float | Sequence[float]) -> None:
        layout, values = {}, []
        for name, value in fields.items():
            entries = tuple(value) if isinstance(value, (tuple, list)) else (value,)
            layout[name] = (len(values), len(entries), isinstance(value, (tuple, list)))
            values.extend(_finite(entries, name))
        object.__setattr__(self, "_layout", layout)
        object.__setattr__(self, "_values", np.array(values, dtype=float))

    def __getattr__(self, name: str) -> object:
        layout = object.__getattribute__(self, "_layout")
        if name not in layout:
            raise AttributeError(f"Memory has no field {name!r} (its fields: {list(layout)}).")
        offset, size, many = layout[name]
        tracing = TRACING.get()
        where = None if tracing is None else tracing.slot(self, "values")
        if where is not None:  # a traced hook reads the plan's register (a copy of it now)
            values = tuple(tracing.program.read(where[0] + offset + i) for i in range(size))
        else:
            values = tuple(self._values[offset : offset + size].tolist())
        return values if many else values[0]

    def __setattr__(self, name: str, value: object) -> None:
        layout = self._layout
        if name not in layout:
            raise InvalidInputError(f"Memory has no field {name!r} (its fields: {list(layout)}).")
        offset, size, many = layout[name]
        entries = tuple(value) if many else (value,)
        if len(entries) != size:
            raise InvalidInputError(f"Memory.{name} holds {size} values, got {len(entries)}.")
        try:  # a traced hook writes the plan's registers
            if traced_store(self, "values", entries, offset):
                return
        except TraceError:  # a traced value, and no trace keeping this memory
            message = f"Memory.{name}: a traced value outside a plan's trace."
            raise InvalidInputError(message) from None
        self._values[offset : offset + size] = _finite(entries, name)

    @property
    def fields(self) -> dict[str, object]:
        """Every field's value now."""
        return {name: getattr(self, name) for name in self._layout}

    def plan_slots(self) -> dict[str, np.ndarray]:
        """The array a compiled plan keeps (one slot, ``values``)."""
        return {"values": self._values}

    def bind_slots(self, views: dict[str, np.ndarray]) -> None:
        """Keep the memory in a compiled plan's registers (``views["values"]``)."""
        object.__setattr__(self, "_values", views["values"])

    def __repr__(self) -> str:
        return f"Memory({', '.join(f'{k}={v!r}' for k, v in self.fields.items())})"


def _finite(entries: tuple, name: str) -> list[float]:
    """``entries`` as floats, each a finite real number (a bool is not one)."""
    return [check_number(entry, f"Memory.{name}") for entry in entries]
