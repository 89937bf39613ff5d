"""The solvers of a parallel actuator by name: a checked request, and each method's backends."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Protocol

import numpy as np

from .result import TickResult


@dataclass(frozen=True, slots=True, eq=False)
class Request:
    """How to solve, checked once (``ParallelVirtualActuator.plan``), then reused per tick.

    Attributes:
        method: ``"partitioned"``, ``"dense"`` or ``"qp"`` (a key of `METHODS`).
        free: The axes left to the solver.
        keep: ``(n,)`` bool, the prescribed axes.
        compiled: Use the compiled kernels where they apply.
        weights: ``method="qp"``: checked closest-wrench weights per axis; None: declared.
    """

    method: str
    free: tuple[str, ...]
    keep: np.ndarray
    compiled: bool = True
    weights: np.ndarray | None = None


class Backend(Protocol):
    """One way to solve a tick."""

    def solve(self, snapshot: object, wrench: np.ndarray, request: Request) -> TickResult | None:
        """The tick's result, or None to hand the tick to the method's next backend.

        The last backend of a method always answers, or raises.
        """


#: Each method's backends, tried in order: the compiled partitioned kernel hands the ticks it
#: cannot decide to the numpy reference, which hands those it cannot to the dense solver
METHODS: dict[str, tuple[str, ...]] = {
    "partitioned": ("compiled", "reference", "dense"),
    "dense": ("dense",),
    "qp": ("qp",),
}


def dispatch(
    backends: Mapping[str, Backend], snapshot: object, wrench: np.ndarray, request: Request
) -> TickResult:
    """The first answer of the request's method's backends (by name in ``backends``), in order.

    Raises:
        SingularConfigurationError: No distribution can be solved at this configuration.
        ConstraintError: Constraints that contradict each other here.
        RuntimeError: Every backend handed the tick on (a bug).
    """
    for name in METHODS[request.method]:
        tick = backends[name].solve(snapshot, wrench, request)
        if tick is not None:
            return tick
    raise RuntimeError(f"No backend of method {request.method!r} answered.")
