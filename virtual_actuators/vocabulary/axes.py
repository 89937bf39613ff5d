"""Frame, joint and axis names, resolved once against a model; errors name the closest names."""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence, Set

import numpy as np
import pinocchio as pin

from ..exceptions import FrameNotFoundError, InvalidAxisError, JointNotFoundError, suggestion
from .arguments import describe

#: All axes a virtual actuator can act along, in their canonical order: forces along and moments
#: about the axes of the reference frame {O}.
AXES: tuple[str, ...] = ("x", "y", "z", "rx", "ry", "rz")


#: Name of the inertial frame (Pinocchio's ``universe`` frame).
WORLD = "world"


def resolve_frame(model: pin.Model, name: str, role: str = "frame") -> int:
    """Return the Pinocchio frame id of ``name`` (``"world"`` is the universe frame).

    ``role`` says what the frame is for in the message (``"action"``, ...).

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
    what = "frame" if role == "frame" else f"{role} frame"
    raise FrameNotFoundError(
        f"The {what} {name!r} is not in the model {model.name!r}. "
        + suggestion(name, names, "frames")
    )


def resolve_joint(model: pin.Model, name: str, role: str = "joint") -> int:
    """Return the Pinocchio joint id (>= 1) of ``name``; ``role`` is for the message.

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


def parse_axes(axes: Iterable[str] | str, what: str = "axes") -> tuple[str, ...]:
    """Check that ``axes`` (or one axis name) is a non-empty ordered subset of [`AXES`][].

    Raises:
        InvalidAxisError: For axes that are not a str or an ordered collection of str (None, a
            number, a set, a dict, bytes), an unknown, repeated or out-of-order axis, or no axis.
    """
    if isinstance(axes, str):
        axes = (str(axes),)
    elif isinstance(axes, (bytes, Mapping, Set)) or not isinstance(axes, Iterable):
        raise InvalidAxisError(
            f"{what} must be an axis name or an ordered sequence of axis names from {AXES}, "
            f"got {describe(axes)}."
        )
    else:  # entries that are str become plain str
        axes = tuple(str(a) if isinstance(a, str) else a for a in axes)
    if not axes:
        raise InvalidAxisError(f"At least one axis is needed in {what}; valid axes are {AXES}.")
    for axis in axes:
        if axis not in AXES:
            raise InvalidAxisError(
                f"Unknown axis {axis!r} in {what}; valid axes are {AXES}. "
                + suggestion(str(axis), AXES, "axes")
            )
    if len(set(axes)) != len(axes):
        raise InvalidAxisError(f"{what} {axes} name an axis twice.")
    order = [AXES.index(a) for a in axes]
    if order != sorted(order):
        expected = tuple(sorted(axes, key=AXES.index))
        raise InvalidAxisError(
            f"{what} {axes} are out of order: give them in the order {AXES}, i.e. {expected}."
        )
    return axes


def axis_rows(axes: Sequence[str]) -> np.ndarray:
    """Return the indices of ``axes`` among the six rows ``x y z rx ry rz`` of a spatial vector."""
    return np.array([AXES.index(a) for a in axes], dtype=int)


def check_axes_subset(requested: Iterable[str], axes: Sequence[str], what: str) -> tuple[str, ...]:
    """Check that every axis in ``requested`` (or one name) is one of ``axes``; in their order.

    Raises:
        InvalidAxisError: If ``requested`` is not a str or a collection of str, or an axis is
            not one of ``axes``.
    """
    if isinstance(requested, str):
        requested = (requested,)
    elif isinstance(requested, (bytes, Mapping)) or not isinstance(requested, Iterable):
        raise InvalidAxisError(
            f"{what} must be an axis name or a sequence of axis names among this actuator's "
            f"axes {tuple(axes)}, got {describe(requested)}."
        )
    requested = tuple(requested)
    for axis in requested:
        if not isinstance(axis, str) or axis not in axes:
            raise InvalidAxisError(
                f"{what} axis {axis!r} is not one of this actuator's axes {tuple(axes)}."
            )
    return tuple(a for a in axes if a in requested)
