"""Events for :class:`~virtual_actuators.control.state_machine.Transition`: small factories.

Each returns a callable of the tick's :class:`~virtual_actuators.control.state_machine.Context`.
Combine them with :func:`any_of` and :func:`all_of`, or write a lambda.
"""

from __future__ import annotations

from collections.abc import Callable

from ..declaration.frames import AXES
from ..exceptions import InvalidAxisError, InvalidInputError
from .state_machine import Context, Event

_AXIS_INDEX = {"x": 0, "y": 1, "z": 2}


def _axis(axis: str) -> int:
    if axis not in _AXIS_INDEX:
        raise InvalidAxisError(f"Event axis must be one of x, y, z (of {AXES}), got {axis!r}.")
    return _AXIS_INDEX[axis]


def after(seconds: float) -> Event:
    """Fires once the current state has lasted ``seconds`` (a timer, e.g. the buffer states).

    Raises:
        InvalidInputError: Negative or non-finite ``seconds``.

    """
    if not seconds >= 0.0 or seconds == float("inf"):
        raise InvalidInputError(f"after(): seconds must be finite and >= 0, got {seconds}.")
    return lambda context: context.time_in_state >= seconds


def ahead_of(frame: str, reference: str, distance: float, axis: str = "x") -> Event:
    """Fires when ``frame`` is more than ``distance`` ahead of ``reference`` along a world axis.

    ``ahead_of("body", "left_foot", -0.03)`` is the seed's "body nearly over left foot";
    ``ahead_of("body", "left_foot", 0.12)`` its "body away from left foot".

    Raises:
        InvalidAxisError: ``axis`` is not x, y or z.

    """
    index = _axis(axis)
    return lambda context: (
        context.frame_position(frame)[index] - context.frame_position(reference)[index] > distance
    )


def contact(*frames: str, require_all: bool = True) -> Event:
    """Fires when the contact switches of ``frames`` are closed (all of them, or any).

    Raises:
        InvalidInputError: No frame given.

    """
    if not frames:
        raise InvalidInputError("contact() needs at least one frame name.")
    combine = all if require_all else any
    return lambda context: combine(context.in_contact(f) for f in frames)


def no_contact(*frames: str) -> Event:
    """Fires when none of the contact switches of ``frames`` is closed.

    Raises:
        InvalidInputError: No frame given.

    """
    if not frames:
        raise InvalidInputError("no_contact() needs at least one frame name.")
    return lambda context: not any(context.in_contact(f) for f in frames)


def any_of(*events: Event) -> Event:
    """Fires when any of ``events`` fires."""
    return lambda context: any(event(context) for event in events)


def all_of(*events: Event) -> Event:
    """Fires when all of ``events`` fire."""
    return lambda context: all(event(context) for event in events)


def when(predicate: Callable[[Context], bool]) -> Event:
    """Wrap any callable of the context as an event (for symmetry in declarations)."""
    return predicate
