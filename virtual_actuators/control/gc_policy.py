"""Python's garbage collector around a control loop: no collection inside a tick."""

from __future__ import annotations

import gc

from ..exceptions import InvalidInputError

#: The garbage-collection policies of the control loops
GC_POLICIES = ("between-ticks", "python")


def check_gc_policy(policy: object, where: str) -> str:
    """``policy`` if it is one of [`GC_POLICIES`][].

    Raises:
        InvalidInputError: Anything else (naming ``where`` and the valid policies).
    """
    if not isinstance(policy, str) or policy not in GC_POLICIES:
        raise InvalidInputError(f"{where}: gc_policy must be one of {GC_POLICIES}, got {policy!r}.")
    return policy


class LoopCollector:
    """The garbage collector's policy for one control loop (a context manager).

    Args:
        policy: One of [`GC_POLICIES`][].

    Attributes:
        collections: Collections run between ticks, per generation ``[0, 1, 2]``.

    Raises:
        InvalidInputError: An unknown ``policy``.

    Example:
        >>> with LoopCollector("between-ticks") as collector:
        ...     while running:
        ...         tick()
        ...         collector.between_ticks()
    """

    __slots__ = ("_enabled", "_every", "_froze", "_runs", "_young", "active", "collections")

    def __init__(self, policy: str = "between-ticks") -> None:
        self.active = check_gc_policy(policy, "LoopCollector") == "between-ticks"
        self.collections = [0, 0, 0]
        self._froze = self._enabled = False
        self._young = self._every = self._runs = 0

    def __enter__(self) -> LoopCollector:
        if self.active:
            self._enabled = gc.isenabled()
            gc.disable()
            gc.collect()
            self._froze = gc.get_freeze_count() == 0  # someone else's freeze is left alone
            gc.freeze()
            self._young, self._every = gc.get_threshold()[:2]
        return self

    def between_ticks(self) -> None:
        """Collect the young generations when CPython would have (call it between ticks)."""
        if not self.active or self._young <= 0 or gc.get_count()[0] < self._young:
            return
        self._runs += 1
        generation = 1 if self._every > 0 and self._runs % self._every == 0 else 0
        self.collections[generation] += 1
        gc.collect(generation)

    def __exit__(self, *exc: object) -> None:
        if self.active:
            if self._froze:
                gc.unfreeze()
            if self._enabled:
                gc.enable()
