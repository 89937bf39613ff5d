"""Python's garbage collector around a control loop: no collection inside a tick.

CPython's collector runs whenever enough container objects were allocated, wherever that
happens: inside a controller's tick it adds its pause to that tick. Measured on figure 7 of
``benchmarks/bench_realtime.py`` before this policy: young (generation 1) collections of
0.5-1.2 ms inside ticks, one of 2.6 ms, because they walked the objects the set-up had left in
the young generations (robots, declarations, warm-up results).

The control loops ([`run`][] and the walks' runner) therefore apply a
[`LoopCollector`][] policy, ``gc_policy=``:

- ``"between-ticks"`` (the default): before the first tick, a full collection, then
  `gc.freeze` (everything the set-up made moves to the permanent generation: later
  collections no longer walk it) and the automatic collector is disabled. Between two ticks
  (after the efforts are written, in the loop's slack), [`LoopCollector.between_ticks`][]
  collects the young generation when as many objects were allocated as would have triggered
  CPython's own collection (``gc.get_threshold()[0]``), and generation 1 every
  ``gc.get_threshold()[1]`` of those, as CPython does. Generation 2 never runs during the loop:
  garbage cycles that survive two young collections wait until the loop ends. When the loop
  ends (however it ends) the collector is restored: unfrozen (if it was not frozen before) and
  enabled again if it was. The automatic collector is process-wide: other threads of the
  process see it disabled while the loop runs (their young garbage is still collected between
  ticks).
- ``"python"``: leave the collector alone (CPython's automatic collections, inside ticks too).
"""

from __future__ import annotations

import gc

from ..exceptions import InvalidInputError

#: The garbage-collection policies of the control loops (see the module's text).
GC_POLICIES = ("between-ticks", "python")


def check_gc_policy(policy: object, where: str) -> str:
    """``policy`` if it is one of [`GC_POLICIES`][].

    Raises:
        InvalidInputError: Anything else (naming ``where`` and the valid policies).
    """
    if not isinstance(policy, str) or policy not in GC_POLICIES:
        raise InvalidInputError(
            f"{where}: gc_policy must be one of {GC_POLICIES}, got {policy!r}."
        )
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
        # (a threshold of 0: the user turned automatic collections off, and so do we)
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


__all__ = ["GC_POLICIES", "LoopCollector", "check_gc_policy"]
