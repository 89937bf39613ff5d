"""An attachment's declaration-time checks: what ``Controller.add`` is given, checked once."""

from __future__ import annotations

from collections.abc import Container, Mapping, Sequence

import numpy as np

from ..actuators import ParallelVirtualActuator, VirtualActuator
from ..components.base import Component
from ..contacts import declare
from ..distribution.qp import check_weights
from ..exceptions import InvalidInputError
from ..models.robot import Robot
from ..vocabulary.arguments import check_name, check_number, check_sequence, describe
from ..vocabulary.axes import WORLD, check_axes_subset

Actuator = VirtualActuator | ParallelVirtualActuator

#: ``Controller.add(method="qp", yield_axes=...)``: the yield axes' weight in the QP's
#: closest wrench (the other axes weigh 1), so an infeasible request gives way on them first
YIELD_WEIGHT = 1e-3
_QP_LIMITS = (
    "with method='qp' the contact limits are the actuator's own (friction, min_normal, "
    "torque_limits); leave out unilateral and friction."
)


def attachment_fields(
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
) -> dict[str, object]:
    """An [`Attachment`][virtual_actuators.control.attachment.Attachment]'s fields, checked.

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
    method = _method(name, actuator, method, bool(limits) or friction is not None)
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
    return dict(
        name=name, actuator=actuator, sensor=sensor, components=components, free=free,
        indices=indices, contacts=contacts, yield_mask=yield_mask, method=method, weights=weights,
    )  # fmt: skip


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
    """``(weights, yield axes left to the scaling rule)``: the QP's yield weights, or none.

    With ``method="qp"`` on a parallel actuator, ``(n,)`` weights that make ``yield_axes`` give
    way first (None without yield axes) and ``()``; otherwise ``(None, yield_axes)``.
    """
    if method != "qp" or not isinstance(actuator, ParallelVirtualActuator):
        if yield_weight is not None:
            raise InvalidInputError(
                f"Attachment {name!r}: yield_weight goes with method='qp' (a parallel actuator)."
            )
        return None, yield_axes
    if unilateral or friction is not None:
        raise InvalidInputError(f"Attachment {name!r}: {_QP_LIMITS}")
    yielded = check_axes_subset(yield_axes, actuator.axes, "yield_axes")
    weight = YIELD_WEIGHT if yield_weight is None else yield_weight
    weight = check_number(weight, f"Attachment {name!r}: yield_weight", positive=True)
    if not yielded:
        return None, ()
    return check_weights(dict.fromkeys(yielded, weight), actuator.axes), ()


def _method(name: str, actuator: Actuator, method: object, limited: bool) -> str:
    """``method`` checked against the actuator's solvers (a serial one has none)."""
    if method == "partitioned":
        return method
    methods = list(getattr(actuator, "methods", ()))
    if method not in methods:
        raise InvalidInputError(
            f"Attachment {name!r}: method must be one of {methods or ['partitioned']} for "
            f"this actuator, got {describe(method)}."
        )
    if method == "qp" and limited:
        raise InvalidInputError(f"Attachment {name!r}: {_QP_LIMITS}")
    return str(method)
