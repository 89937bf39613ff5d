"""An attachment's declaration-time checks: what ``Controller.add`` is given, checked once."""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np

from ..actuators import ParallelVirtualActuator, VirtualActuator
from ..components.base import Component
from ..distribution.qp import check_weights
from ..exceptions import InvalidInputError
from ..models.robot import Robot
from ..vocabulary.arguments import check_number, check_sequence, describe
from ..vocabulary.axes import WORLD, check_axes_subset

Actuator = VirtualActuator | ParallelVirtualActuator

#: ``Controller.add(method="qp", yield_axes=...)``: the yield axes' weight in the QP's
#: closest wrench (the other axes weigh 1), so an infeasible request gives way on them first
YIELD_WEIGHT = 1e-3
_QP_LIMITS = (
    "with method='qp' the contact limits are the actuator's own (friction, min_normal, "
    "torque_limits); leave out unilateral and friction."
)


def check_parts(name: str, actuator: object, sensor: object, components: object) -> list[Component]:
    """The actuator's and sensor's kinds; ``components`` as a list of components.

    Raises:
        InvalidInputError: The actuator or sensor is not a virtual actuator (a sensor: serial,
            or None), or a component is not a [`Component`][].
    """
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


def check_limit_values(
    name: str, friction: object, min_normal: object, unilateral: object
) -> tuple[float | None, float]:
    """``(friction, min_normal)`` checked, and ``unilateral``'s kind (a dict or None).

    Raises:
        InvalidInputError: ``friction`` not None or a finite number > 0, ``min_normal`` not a
            finite number >= 0, or ``unilateral`` not a dict.
    """
    where = f"Attachment {name!r}"
    if friction is not None:
        friction = check_number(friction, f"{where}: friction", positive=True)
    min_normal = check_number(min_normal, f"{where}: min_normal [N]", minimum=0.0)
    if unilateral is not None and not isinstance(unilateral, Mapping):
        raise InvalidInputError(
            f"{where}: unilateral must be a dict {{axis: minimum [N]}}, got {describe(unilateral)}."
        )
    return friction, min_normal


def check_free(name: str, robot: Robot, actuator: Actuator, free: Sequence[str]) -> tuple[str, ...]:
    """The actuator's robot, and the free axes (a parallel actuator's only), in its order.

    Raises:
        InvalidInputError: The actuator is for another robot, or free axes on a serial one.
        InvalidAxisError: ``free`` names an axis the actuator lacks.
    """
    if actuator.robot.model is not robot.model:
        raise InvalidInputError(f"Attachment {name!r}: the actuator is for another robot.")
    free_axes = check_axes_subset(free, actuator.axes, "free")
    if free_axes and isinstance(actuator, VirtualActuator):
        raise InvalidInputError(
            f"Attachment {name!r}: free axes need a ParallelVirtualActuator; a serial "
            "actuator produces every axis."
        )
    return free_axes


def sensor_of(
    name: str, robot: Robot, actuator: Actuator, sensor: VirtualActuator | None
) -> VirtualActuator:
    """The attachment's sensor: ``sensor``, else a serial actuator itself, else world to {B}.

    Raises:
        InvalidInputError: The sensor is for another robot, or its axes differ from the
            actuator's.
    """
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


def component_indices(components: list[Component], axes: tuple[str, ...]) -> list[np.ndarray]:
    """For each component, the indices of its axes among the actuator's ``axes``.

    Raises:
        InvalidAxisError: A component acts on an axis the actuator does not have.
    """
    indices = []
    for component in components:
        check_axes_subset(component.axes, axes, f"{component.name} axes")
        indices.append(np.array([axes.index(a) for a in component.axes]))
    return indices


def check_contact_limits(
    name: str,
    actuator: Actuator,
    unilateral: Mapping[str, float] | None,
    yield_axes: Sequence[str],
    friction: float | None,
) -> tuple[dict[int, float], np.ndarray | None]:
    """An attachment's contact limits as ``({axis index: minimum}, yield mask or None)``.

    Raises:
        InvalidInputError: Limits without yield axes or the reverse, limits on a serial
            actuator, a cone without force axes, or a minimum that is not a finite number.
        InvalidAxisError: ``unilateral`` or ``yield_axes`` name an axis the actuator lacks.
    """
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


def check_qp_yield(
    name: str,
    actuator: Actuator,
    method: object,
    unilateral: Mapping[str, float] | None,
    yield_axes: Sequence[str],
    friction: float | None,
    yield_weight: float | None,
) -> tuple[np.ndarray | None, Sequence[str]]:
    """``method="qp"``: the closest-wrench weights that make ``yield_axes`` give way first.

    Returns:
        ``(weights, yield axes left to the scaling rule)``: with ``method="qp"`` on a parallel
        actuator, ``(n,)`` weights (None without yield axes) and ``()``; otherwise
        ``(None, yield_axes)``.

    Raises:
        InvalidInputError: With ``method="qp"``, ``unilateral`` or ``friction`` given;
            ``yield_weight`` without ``method="qp"`` or not a finite number > 0.
        InvalidAxisError: ``yield_axes`` names an axis the actuator lacks.
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


def check_method(name: str, actuator: Actuator, method: object, limited: bool) -> str:
    """``method`` checked against the actuator's solvers (a serial one has none).

    Raises:
        InvalidInputError: A method the actuator does not have, or ``method="qp"`` with the
            attachment's own contact limits (``limited``).
    """
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
