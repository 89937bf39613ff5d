"""Attachments: an actuator, the components on it and the sensor they read, checked once."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..actuators import VirtualActuator
from ..components.base import Component
from ..contacts import ContactSet
from ..exceptions import InvalidInputError
from ..kinematics.kernels import finite
from ..vocabulary.arguments import describe
from .attachment_checks import Actuator
from .attachment_kernel import SpringTick


@dataclass(repr=False)
class Attachment:
    """An actuator, the components attached to it and the sensor they read.

    Attributes:
        name: Unique name in its controller.
        actuator: The serial or parallel virtual actuator that produces the wrench.
        sensor: Serial actuator whose position and velocity the components read.
        components: The virtual components.
        free: Axes left to the distribution (parallel actuators only).
        indices: For each component, the indices of its axes among the actuator's axes.
        contacts: The contacts whose rows the yield policy keeps, or None.
        yield_mask: ``(n,)`` the yield axes (None without contact limits).
        method: The distribution method.
        weights: ``method="qp"``: the per-axis weights passed to every solve (None: the
            actuator's own).
    """

    name: str
    actuator: Actuator
    sensor: VirtualActuator
    components: list[Component]
    free: tuple[str, ...] = ()
    indices: list[np.ndarray] = field(default_factory=list)
    contacts: ContactSet | None = None
    yield_mask: np.ndarray | None = None
    method: str = "partitioned"
    weights: np.ndarray | None = None

    def __post_init__(self) -> None:
        # each component's axes as a slice when contiguous (views instead of gathers per tick)
        self.slots = [_as_slice(index) for index in self.indices]
        # a parallel actuator's checked request (method, free axes, weights) for its solves
        plan = getattr(self.actuator, "plan", None)
        self.plan = plan(self.free, self.method, weights=self.weights) if plan else None
        #: the plan's one-call solve on the tick's snapshot (None: the general path's solve)
        self.snapshot_solve = None if plan is None else self.actuator.snapshot_solve(self.plan)
        # the contact rows' compiled tables (None: the rows are built with numpy)
        self.margins = self.contacts.compiled() if self.contacts is not None else None
        #: the spring-dampers' one-call sensing and wrench (and efforts or solve), or None
        self.spring_tick = SpringTick.of(
            self.actuator, self.sensor, self.components, self.slots, self.snapshot_solve
        )

    def wrench(self, position: np.ndarray, velocity: np.ndarray, time: float) -> np.ndarray:
        """Sum ``(n,)`` [N, N m] of the component wrenches on the actuator's axes, checked finite.

        Raises:
            InvalidInputError: A component returned the wrong number of entries, complex ones,
                or the sum is not finite.
        """
        components, n = self.components, len(self.actuator.axes)
        wrench = None
        if len(components) == 1 and self.slots[0] == slice(0, n):  # one on every axis
            wrench = components[0].compute_wrench(position, velocity, time)
            if not isinstance(wrench, np.ndarray) or wrench.shape != (n,) or wrench.dtype != float:
                wrench = None  # a scalar, list or other dtype: the general path below
        if wrench is None:
            wrench = np.zeros(n)
            for component, slot in zip(components, self.slots, strict=True):
                result = component.compute_wrench(position[slot], velocity[slot], time)
                try:
                    wrench[slot] += result  # complex entries: a TypeError (same_kind casting)
                except (TypeError, ValueError):
                    raise InvalidInputError(
                        f"Attachment {self.name!r}: component {component.name!r} returned "
                        f"{describe(result)}; expected {len(component.axes)} real numbers (its "
                        f"axes {component.axes})."
                    ) from None
        if not finite(wrench):
            raise InvalidInputError(
                f"Attachment {self.name!r}: a component returned a non-finite wrench {wrench}."
            )
        return wrench

    def __repr__(self) -> str:
        kind = type(self.actuator).__name__
        names = ", ".join(c.name for c in self.components)
        return f"Attachment({self.name!r}, {kind} on {self.actuator.action!r}, [{names}])"


def _as_slice(index: np.ndarray) -> slice | np.ndarray:
    """``index`` as a slice if it is a contiguous increasing run, else unchanged."""
    if index.size and np.array_equal(index, np.arange(index[0], index[0] + index.size)):
        return slice(int(index[0]), int(index[0]) + index.size)
    return index
