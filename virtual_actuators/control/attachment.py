"""Attachments: an actuator, the components on it and the sensor they read, checked once."""

from __future__ import annotations

from collections.abc import Container, Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np

from ..actuators import ParallelVirtualActuator, VirtualActuator
from ..components.base import Component
from ..contacts import ContactSet, declare
from ..distribution.qp import check_weights
from ..exceptions import InvalidInputError
from ..kinematics.kernels import finite
from ..models.robot import Robot
from ..vocabulary.arguments import check_name, check_number, check_sequence, describe
from ..vocabulary.axes import WORLD, check_axes_subset
from .attachment_kernel import SpringTick

Actuator = VirtualActuator | ParallelVirtualActuator

#: ``Controller.add(method="qp", yield_axes=...)``: the yield axes' weight in the QP's
#: closest wrench (the other axes weigh 1), so an infeasible request gives way on them first
YIELD_WEIGHT = 1e-3


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

    @classmethod
    def declare(
        cls,
        robot: Robot,
        name: str,
        actuator: Actuator,
        components: Sequence[Component],
        sensor: VirtualActuator | None,
        free: Sequence[str],
        unilateral: Mapping[str, float] | None,
        yield_axes: Sequence[str],
        friction: float | None,
        min_normal: float,
        method: str,
        yield_weight: float | None,
        taken: Container[str],
    ) -> Attachment:
        """An attachment from what [`Controller.add`][] is given, every argument checked.

        ``taken`` holds the names already used in the controller.

        Raises:
            InvalidInputError: As [`Controller.add`][].
            InvalidAxisError: As [`Controller.add`][].
        """
        check_name(name, "Controller.add: name")
        components = _parts(name, actuator, sensor, components)
        friction, min_normal = _limit_values(name, friction, min_normal, unilateral)
        free = _free(name, robot, actuator, free)
        sensor = _sensor(name, robot, actuator, sensor)
        indices = []
        for component in components:  # each component's axes among the actuator's
            check_axes_subset(component.axes, actuator.axes, f"{component.name} axes")
            indices.append(np.array([actuator.axes.index(a) for a in component.axes]))
        weights, yield_axes = _qp_yield(
            name, actuator, method, unilateral, yield_axes, friction, yield_weight
        )
        limits, yield_mask = _contact_limits(name, actuator, unilateral, yield_axes, friction)
        if name in taken:
            raise InvalidInputError(f"An attachment named {name!r} already exists.")
        method = _method(name, actuator, method)
        contacts = None
        if yield_mask is not None:  # the actuator's contacts with these limits
            declared = actuator.contacts
            contacts = declare(
                actuator.reactions,
                actuator.axes,
                declared.contact,
                friction,
                min_normal if friction is not None else 0.0,
                declared.normals,
                minima=limits,
            )
        return cls(
            name, actuator, sensor, components, free, indices, contacts, yield_mask, method, weights
        )

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


def _parts(name: str, actuator: object, sensor: object, components: object) -> list[Component]:
    """The actuator's and sensor's kinds; ``components`` as a list of components."""
    where = f"Attachment {name!r}"
    if not isinstance(actuator, (VirtualActuator, ParallelVirtualActuator)):
        raise InvalidInputError(
            f"{where}: actuator must be a va.VirtualActuator or va.ParallelVirtualActuator, "
            f"got {describe(actuator)}."
        )
    if sensor is not None and not isinstance(sensor, VirtualActuator):
        raise InvalidInputError(
            f"{where}: sensor must be a va.VirtualActuator or None, got {describe(sensor)}."
        )
    return list(
        check_sequence(
            components, f"{where}: components", "va.Component", Component, single=Component
        )
    )


def _limit_values(
    name: str, friction: object, min_normal: object, unilateral: object
) -> tuple[float | None, float]:
    """``(friction, min_normal)`` checked, and ``unilateral``'s kind (a dict or None)."""
    where = f"Attachment {name!r}"
    if friction is not None:
        friction = check_number(friction, f"{where}: friction", positive=True)
    min_normal = check_number(min_normal, f"{where}: min_normal [N]", minimum=0.0)
    if unilateral is not None and not isinstance(unilateral, Mapping):
        raise InvalidInputError(
            f"{where}: unilateral must be a dict {{axis: minimum [N]}}, got {describe(unilateral)}."
        )
    return friction, min_normal


def _free(name: str, robot: Robot, actuator: Actuator, free: Sequence[str]) -> tuple[str, ...]:
    """The actuator's robot, and the free axes (a parallel actuator's only), in its order."""
    if actuator.robot.model is not robot.model:
        raise InvalidInputError(f"Attachment {name!r}: the actuator is for another robot.")
    free_axes = check_axes_subset(free, actuator.axes, "free")
    if free_axes and isinstance(actuator, VirtualActuator):
        raise InvalidInputError(
            f"Attachment {name!r}: free axes need a ParallelVirtualActuator; a serial "
            "actuator produces every axis."
        )
    return free_axes


def _sensor(
    name: str, robot: Robot, actuator: Actuator, sensor: VirtualActuator | None
) -> VirtualActuator:
    """The attachment's sensor: ``sensor``, else a serial actuator itself, else world to {B}."""
    if sensor is None:
        if isinstance(actuator, VirtualActuator):
            sensor = actuator
        else:
            sensor = VirtualActuator(
                robot, actuator.action, WORLD, actuator.reference, actuator.axes
            )
    if sensor.robot.model is not robot.model:
        raise InvalidInputError(f"Attachment {name!r}: the sensor is for another robot.")
    if sensor.axes != actuator.axes:
        raise InvalidInputError(
            f"Attachment {name!r}: sensor axes {sensor.axes} differ from the actuator's "
            f"{actuator.axes}."
        )
    return sensor


def _contact_limits(
    name: str,
    actuator: Actuator,
    unilateral: Mapping[str, float] | None,
    yield_axes: Sequence[str],
    friction: float | None,
) -> tuple[dict[int, float], np.ndarray | None]:
    """An attachment's contact limits as ``({axis index: minimum}, yield mask or None)``."""
    where = f"Attachment {name!r}"
    limits: dict[int, float] = {}
    yield_mask = None
    constrained = bool(unilateral) or friction is not None
    yielded = check_axes_subset(yield_axes, actuator.axes, "yield_axes")
    if constrained or yielded:
        if isinstance(actuator, VirtualActuator) or not constrained or not yielded:
            raise InvalidInputError(
                f"Attachment {name!r}: unilateral (or friction) and yield_axes go "
                "together, on a ParallelVirtualActuator."
            )
        if friction is not None and not {"x", "y", "z"} & set(actuator.axes):
            raise InvalidInputError(
                f"Attachment {name!r}: a friction cone needs force axes (x, y or z) among "
                f"{actuator.axes}."
            )
        for axis in check_axes_subset(tuple(unilateral or {}), actuator.axes, "unilateral"):
            limits[actuator.axes.index(axis)] = check_number(
                unilateral[axis], f"{where}: unilateral[{axis!r}]"
            )
        yield_mask = np.array([a in yielded for a in actuator.axes])
    return limits, yield_mask


def _qp_yield(
    name: str,
    actuator: Actuator,
    method: object,
    unilateral: Mapping[str, float] | None,
    yield_axes: Sequence[str],
    friction: float | None,
    yield_weight: float | None,
) -> tuple[np.ndarray | None, Sequence[str]]:
    """``(weights, yield axes left to the scaling rule)``: with ``method="qp"`` the QP's weights."""
    if method != "qp" or not isinstance(actuator, ParallelVirtualActuator):
        if yield_weight is not None:
            raise InvalidInputError(
                f"Attachment {name!r}: yield_weight goes with method='qp' (a parallel actuator)."
            )
        return None, yield_axes
    if unilateral or friction is not None:
        raise InvalidInputError(
            f"Attachment {name!r}: with method='qp' the contact limits are the actuator's own "
            "(friction, min_normal, torque_limits); leave out unilateral and friction."
        )
    yielded = check_axes_subset(yield_axes, actuator.axes, "yield_axes")
    weight = YIELD_WEIGHT if yield_weight is None else yield_weight
    weight = check_number(weight, f"Attachment {name!r}: yield_weight", positive=True)
    if not yielded:
        return None, ()
    return check_weights(dict.fromkeys(yielded, weight), actuator.axes), ()


def _method(name: str, actuator: Actuator, method: object) -> str:
    """``method`` checked against the actuator's solvers (a serial one has none)."""
    if method == "partitioned":
        return method
    methods = list(getattr(actuator, "methods", ()))
    if method not in methods:
        raise InvalidInputError(
            f"Attachment {name!r}: method must be one of {methods or ['partitioned']} for "
            f"this actuator, got {describe(method)}."
        )
    return str(method)
