"""Frame and axis names: resolved once, checked, with helpful errors."""

from __future__ import annotations

from collections.abc import Iterable, Sequence

import numpy as np
import pinocchio as pin

from ..exceptions import FrameNotFoundError, InvalidAxisError, JointNotFoundError, suggestion

#: All axes a virtual actuator can act along, in their canonical order: forces along and moments
#: about the axes of the reference frame {O}.
AXES: tuple[str, ...] = ("x", "y", "z", "rx", "ry", "rz")

#: Name of the inertial frame (Pinocchio's ``universe`` frame).
WORLD = "world"


def resolve_frame(model: pin.Model, name: str, role: str = "frame") -> int:
    """Return the Pinocchio frame id of ``name`` (``"world"`` is the universe frame).

    Args:
        model: The Pinocchio model.
        name: Frame name in the model (a link, a joint or a fixed frame), or ``"world"``.
        role: What the frame is for, used in the error message (``"action"``, ...).

    Returns:
        The frame id.

    Raises:
        FrameNotFoundError: If no frame has that name; the message lists the closest names.

    """
    if not isinstance(name, str):
        raise FrameNotFoundError(f"The {role} frame must be a frame name (str), got {name!r}.")
    if name in (WORLD, "universe"):
        return 0
    if model.existFrame(name):
        return int(model.getFrameId(name))
    names = [WORLD] + [f.name for f in model.frames][1:]
    raise FrameNotFoundError(
        f"The {role} frame {name!r} is not in the model {model.name!r}. "
        + suggestion(name, names, "frames")
    )


def resolve_joint(model: pin.Model, name: str, role: str = "joint") -> int:
    """Return the Pinocchio joint id of ``name``.

    Args:
        model: The Pinocchio model.
        name: Joint name in the model.
        role: What the joint is for, used in the error message.

    Returns:
        The joint id (>= 1).

    Raises:
        JointNotFoundError: If no joint with degrees of freedom has that name.

    """
    names = list(model.names)[1:]
    if isinstance(name, str) and name in names:
        return int(model.getJointId(name))
    raise JointNotFoundError(
        f"The {role} {name!r} is not a joint of the model {model.name!r}. "
        + suggestion(str(name), names, "joints")
    )


def parse_axes(axes: Iterable[str] | str) -> tuple[str, ...]:
    """Check that ``axes`` is a non-empty ordered subset of :data:`AXES`.

    Args:
        axes: Axis names, e.g. ``("x", "z", "ry")``.

    Returns:
        The axes as a tuple.

    Raises:
        InvalidAxisError: For an unknown, repeated or out-of-order axis, or no axis at all.

    """
    if isinstance(axes, str):
        axes = (axes,)
    axes = tuple(axes)
    if not axes:
        raise InvalidAxisError(f"At least one axis is needed; valid axes are {AXES}.")
    for axis in axes:
        if axis not in AXES:
            raise InvalidAxisError(
                f"Unknown axis {axis!r}; valid axes are {AXES}. "
                + suggestion(str(axis), AXES, "axes")
            )
    if len(set(axes)) != len(axes):
        raise InvalidAxisError(f"Axes {axes} name an axis twice.")
    order = [AXES.index(a) for a in axes]
    if order != sorted(order):
        expected = tuple(sorted(axes, key=AXES.index))
        raise InvalidAxisError(
            f"Axes {axes} are out of order: give them in the order {AXES}, i.e. {expected}."
        )
    return axes


def axis_rows(axes: Sequence[str]) -> np.ndarray:
    """Return the indices of ``axes`` among the six rows ``x y z rx ry rz`` of a spatial vector."""
    return np.array([AXES.index(a) for a in axes], dtype=int)


def check_axes_subset(requested: Iterable[str], axes: Sequence[str], what: str) -> tuple[str, ...]:
    """Check that every axis in ``requested`` is one of the actuator's ``axes``.

    Args:
        requested: Axis names given by the user (e.g. ``free=("x",)``).
        axes: The actuator's axes.
        what: What the names are for, used in the error message.

    Returns:
        The requested axes, in the actuator's order.

    Raises:
        InvalidAxisError: If an axis is not one of ``axes``.

    """
    if isinstance(requested, str):
        requested = (requested,)
    requested = tuple(requested)
    for axis in requested:
        if axis not in axes:
            raise InvalidAxisError(
                f"{what} axis {axis!r} is not one of this actuator's axes {tuple(axes)}."
            )
    return tuple(a for a in axes if a in requested)
