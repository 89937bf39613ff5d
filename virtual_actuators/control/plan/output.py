"""What a compiled tick computed: [`PlanOutput`][], read from the plan's registers on demand."""

from __future__ import annotations

from collections.abc import Mapping
from types import MappingProxyType

import numpy as np


class PlanOutput:
    """One compiled tick's output (see the module docstring).

    Args:
        compiled: The compiled machine.
        active: The names evaluated this tick.
        tau: The tick's efforts after the limp joints and the clip [N m or N].
        held: ``(nv,)`` bool, True where the effort rate limit held the effort back.
    """

    __slots__ = ("_cache", "_compiled", "active", "rate_limited", "tau", "tau_requested")

    #: A compiled tick has no failures (a failing tick is the Python machine's).
    failed: Mapping[str, str] = MappingProxyType({})
    failures: Mapping[str, object] = MappingProxyType({})

    def __init__(
        self, compiled: object, active: tuple[str, ...], tau: np.ndarray, held: np.ndarray
    ) -> None:
        self._compiled = compiled
        self.active = active
        self.tau = tau
        self.tau_requested = compiled.requested.copy()
        self.rate_limited = held
        self._cache: dict[str, dict] = {}

    @property
    def joint_names(self) -> tuple[str, ...]:
        """Names of the velocity entries."""
        return self._compiled.joint_names

    @property
    def saturated(self) -> np.ndarray:
        """``(nv,)`` True where the request exceeds the effort limit."""
        limits = self._compiled.machine.controller.effort_limits
        return np.abs(self.tau_requested) > limits

    def _readings(self, what: str) -> dict[str, np.ndarray]:
        cached = self._cache.get(what)
        if cached is None:
            compiled, key = self._compiled, (self.active, what)
            layout = compiled.layouts.get(key)
            if layout is None:  # each reading's span in one gather, once per active set
                entries = [(name, compiled.entry(name)) for name in self.active]
                entries = [(n, e) for n, e in entries if e.reports]  # a term has no wrench
                index = [getattr(e, what) + i for _, e in entries for i in range(e.n)]
                bounds = np.cumsum([0] + [e.n for _, e in entries]).tolist()
                spans = [(n, bounds[k], bounds[k + 1]) for k, (n, _) in enumerate(entries)]
                layout = compiled.layouts[key] = (np.array(index, dtype=np.intp), spans)
            index, spans = layout
            values = compiled.registers.take(index)  # a copy: the next tick leaves it alone
            cached = self._cache[what] = {name: values[a:b] for name, a, b in spans}
        return cached

    def wrench_of(self, name: str) -> np.ndarray | None:
        """The requested wrench of attachment ``name`` (a copy), None when it is not active."""
        cached = self._cache.get("wrench")
        if cached is not None:
            return cached.get(name)
        if name not in self.active:
            return None
        entry = self._compiled.entry(name)
        if not entry.reports:
            return None
        return self._compiled.registers[entry.wrench : entry.wrench + entry.n].copy()

    @property
    def wrenches(self) -> dict[str, np.ndarray]:
        """Requested wrench per active attachment, on its actuator's axes."""
        return self._readings("wrench")

    @property
    def produced(self) -> dict[str, np.ndarray]:
        """Wrench produced per active attachment."""
        return self._readings("produced")

    @property
    def positions(self) -> dict[str, np.ndarray]:
        """Sensor position per active attachment [m, rad]."""
        return self._readings("position")

    @property
    def velocities(self) -> dict[str, np.ndarray]:
        """Sensor velocity per active attachment [m/s, rad/s]."""
        return self._readings("velocity")

    @property
    def solutions(self) -> dict:
        """The distribution's solution per active parallel attachment."""
        cached = self._cache.get("solutions")
        if cached is None:
            cached = self._cache["solutions"] = {}
            for name in self.active:
                solution = self._compiled.entry(name).solved_solution()
                if solution is not None:
                    cached[name] = solution
        return cached

    @property
    def saturated_joints(self) -> list[str]:
        """Names of the velocity entries whose effort was clipped."""
        return [self.joint_names[i] for i in np.flatnonzero(self.saturated)]

    @property
    def rate_limited_joints(self) -> list[str]:
        """Names of the velocity entries the effort rate limit held back."""
        return [self.joint_names[i] for i in np.flatnonzero(self.rate_limited)]

    def __repr__(self) -> str:
        return (
            f"PlanOutput(active={self.active}, |tau|={np.linalg.norm(self.tau):.3g}, "
            f"saturated={self.saturated_joints})"
        )
