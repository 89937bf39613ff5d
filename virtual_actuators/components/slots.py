"""A component's parameters as a compiled plan's slots: arrays it keeps, traced when lowered."""

from __future__ import annotations

import numpy as np

from ..vocabulary.traced import TRACING, traced_read, traced_store


class Slotted:
    """The slots half of a component (a mixin): `SLOTS` arrays held as ``_name``."""

    #: The parameters a compiled plan keeps in its registers, in this order.
    SLOTS: tuple[str, ...] = ()
    _bound = False  # the parameters are a plan's registers (bind_slots)

    def _traced(self, name: str) -> np.ndarray | tuple:
        """Parameter ``name``: its array, or its traced values while a plan traces a hook."""
        if TRACING.get() is not None:
            traced = traced_read(self, name)
            if traced is not None:
                return traced
        return getattr(self, f"_{name}")

    def _store_traced(self, name: str, value: object) -> bool:
        """Store ``value`` into the plan's slot while a hook is traced (True: done)."""
        if TRACING.get() is None:
            return False
        size = getattr(self, f"_{name}").size
        values = tuple(value) if isinstance(value, (tuple, list)) else (value,) * size
        return traced_store(self, name, values)

    def _assign(self, name: str, array: np.ndarray) -> None:
        """Set a parameter array: replaced, or written in place once bound to a plan."""
        if self._bound:
            getattr(self, name)[:] = array
        else:
            setattr(self, name, array)

    def plan_slots(self) -> dict[str, np.ndarray]:
        """The arrays a compiled plan keeps (`SLOTS`), by name."""
        return {name: getattr(self, f"_{name}") for name in self.SLOTS}

    def bind_slots(self, views: dict[str, np.ndarray]) -> None:
        """Keep the parameters in a compiled plan's registers: ``views`` become the arrays."""
        for name, view in views.items():
            setattr(self, f"_{name}", view)
        self._bound = True


def slot(name: str, check: str = "_per_axis") -> property:
    """The property of parameter ``name``, set through the method ``check(value, name)``.

    Read: its array, or its traced values while a plan traces a hook; set: the plan's slot
    while traced, else the checked array (written in place once bound to a plan).
    """

    def read(self: Slotted) -> np.ndarray | tuple:
        return self._traced(name)

    def write(self: Slotted, value: object) -> None:
        if not self._store_traced(name, value):
            self._assign(f"_{name}", getattr(self, check)(value, name))

    return property(read, write)
