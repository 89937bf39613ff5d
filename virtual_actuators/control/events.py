"""Events for [`Transition`][]: small factories.

Each returns a callable of the tick's [`Context`][].
Combine them with [`any_of`][] and [`all_of`][], or write a lambda.
"""

from __future__ import annotations

from collections.abc import Callable

from ..exceptions import InvalidAxisError, InvalidInputError
from ..vocabulary.arguments import check_flag, check_name, check_number, describe
from ..vocabulary.axes import AXES
from .context import POSITION_COLUMNS, Context, Event, table_entry

_AXIS_INDEX = {"x": 0, "y": 1, "z": 2}


def _axis(axis: str) -> int:
    if not isinstance(axis, str) or axis not in _AXIS_INDEX:
        raise InvalidAxisError(f"Event axis must be one of x, y, z (of {AXES}), got {axis!r}.")
    return _AXIS_INDEX[axis]


def _frames(frames: tuple, where: str) -> tuple[str, ...]:
    if not frames:
        raise InvalidInputError(f"{where} needs at least one frame name.")
    for frame in frames:
        check_name(frame, f"{where}: frames (each a frame name; pass them as separate arguments)")
    return frames


def _events(events: tuple, where: str) -> tuple[Event, ...]:
    if not events:
        raise InvalidInputError(f"{where} needs at least one event.")
    for i, event in enumerate(events):
        if not callable(event):
            raise InvalidInputError(
                f"{where}: events[{i}] must be a callable of the Context, got {describe(event)}."
            )
    return events


def after(seconds: float) -> Event:
    """Fires once the current state has lasted ``seconds`` (a timer, e.g. the buffer states).

    Raises:
        InvalidInputError: ``seconds`` is not a finite real number >= 0.

    """
    seconds = check_number(seconds, "after(): seconds", minimum=0.0)
    return lambda context: context.time_in_state >= seconds


def ahead_of(frame: str, reference: str, distance: float, axis: str = "x") -> Event:
    """Fires when ``frame`` is more than ``distance`` ahead of ``reference`` along a world axis.

    ``ahead_of("body", "left_foot", -0.03)`` is the seed's "body nearly over left foot";
    ``ahead_of("body", "left_foot", 0.12)`` its "body away from left foot".

    Raises:
        InvalidInputError: ``frame`` or ``reference`` is not a str, or ``distance`` is not a
            finite real number.
        InvalidAxisError: ``axis`` is not x, y or z.

    """
    check_name(frame, "ahead_of(): frame")
    check_name(reference, "ahead_of(): reference")
    distance = check_number(distance, "ahead_of(): distance [m]")
    index = _axis(axis)
    column = POSITION_COLUMNS[axis]  # the position's entry in a row of the snapshot's frame table

    def event(context: Context) -> bool:
        snapshot = context.snapshot  # tabled frames: two entries of the table (a tick's cost)
        position = table_entry(snapshot, frame, column)
        reference_position = table_entry(snapshot, reference, column)
        if position is not None and reference_position is not None:
            return position - reference_position > distance
        return (
            context.frame_position(frame)[index] - context.frame_position(reference)[index]
            > distance
        )

    return event


def contact(*frames: str, require_all: bool = True) -> Event:
    """Fires when the contact switches of ``frames`` are closed (all of them, or any).

    Raises:
        InvalidInputError: No frame given, a frame that is not a str, or ``require_all`` that
            is not a bool.

    """
    frames = _frames(frames, "contact()")
    if check_flag(require_all, "contact(): require_all"):

        def event(context: Context) -> bool:  # all(...) without a generator (per tick)
            switches = context.contacts
            for frame in frames:
                switch = switches.get(frame)
                if not (context.in_contact(frame) if switch is None else switch):
                    return False
            return True

    else:

        def event(context: Context) -> bool:  # any(...) without a generator (per tick)
            switches = context.contacts
            for frame in frames:
                switch = switches.get(frame)
                if context.in_contact(frame) if switch is None else switch:
                    return True
            return False

    return event


def no_contact(*frames: str) -> Event:
    """Fires when none of the contact switches of ``frames`` is closed.

    Raises:
        InvalidInputError: No frame given, or a frame that is not a str.

    """
    frames = _frames(frames, "no_contact()")
    return lambda context: not any(context.in_contact(f) for f in frames)


def any_of(*events: Event) -> Event:
    """Fires when any of ``events`` fires.

    Raises:
        InvalidInputError: No event given, or one that is not callable.

    """
    events = _events(events, "any_of()")

    def event(context: Context) -> bool:  # any(...) without a generator (per tick)
        for each in events:
            if each(context):
                return True
        return False

    return event


def all_of(*events: Event) -> Event:
    """Fires when all of ``events`` fire.

    Raises:
        InvalidInputError: No event given, or one that is not callable.

    """
    events = _events(events, "all_of()")

    def event(context: Context) -> bool:  # all(...) without a generator (per tick)
        for each in events:
            if not each(context):
                return False
        return True

    return event


def when(predicate: Callable[[Context], bool]) -> Event:
    """Wrap any callable of the context as an event (for symmetry in declarations).

    Raises:
        InvalidInputError: ``predicate`` is not callable.

    """
    if not callable(predicate):
        raise InvalidInputError(
            f"when(): predicate must be a callable of the Context, got {describe(predicate)}."
        )
    return predicate
