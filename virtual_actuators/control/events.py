"""Events for [`Transition`][]: factories of callables of the tick's [`Context`][]."""

from __future__ import annotations

import functools
from collections.abc import Callable
from dataclasses import dataclass

from ..exceptions import InvalidAxisError, InvalidInputError
from ..vocabulary.arguments import check_flag, check_name, check_number, describe
from ..vocabulary.axes import AXES
from ..vocabulary.scalar import logical_and, logical_not, logical_or
from .context import POSITION_COLUMNS, Context, Event


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


@dataclass(slots=True, repr=False, eq=False)
class After:
    """Fires once the current state has lasted ``seconds`` (`after`)."""

    seconds: float

    def __call__(self, context: Context) -> bool:
        """Whether the event fires at this tick (a traced value on a lowering's context)."""
        return context.time_in_state >= self.seconds

    lower = __call__  # the same read traces

    def __repr__(self) -> str:
        return f"after({self.seconds:g})"


@dataclass(slots=True, repr=False, eq=False)
class AheadOf:
    """Fires when ``frame`` is more than ``distance`` ahead of ``reference`` (`ahead_of`)."""

    frame: str
    reference: str
    distance: float
    axis: str

    def __post_init__(self) -> None:
        axis = self.axis  # a world axis x, y or z
        if not isinstance(axis, str) or axis not in POSITION_COLUMNS:
            raise InvalidAxisError(f"Event axis must be one of x, y, z (of {AXES}), got {axis!r}.")

    def __call__(self, context: Context) -> bool:
        """Whether the event fires at this tick (a traced value on a lowering's context)."""
        difference = context.frame_coordinate(self.frame, self.axis) - context.frame_coordinate(
            self.reference, self.axis
        )
        return difference > self.distance

    lower = __call__  # the same reads trace

    def __repr__(self) -> str:
        return f"ahead_of({self.frame!r}, {self.reference!r}, {self.distance:g}, {self.axis!r})"


@dataclass(slots=True, repr=False, eq=False)
class Contact:
    """Fires when the contact switches of ``frames`` are closed, all or any (`contact`)."""

    frames: tuple[str, ...]
    require_all: bool

    def __call__(self, context: Context) -> bool:
        """Whether the event fires at this tick."""
        wanted = self.require_all  # all(...) / any(...) without a generator (per tick)
        for frame in self.frames:
            if context.in_contact(frame) != wanted:
                return not wanted
        return wanted

    def lower(self, trace: object) -> object:
        """The event as a traced value (each frame's switch a register the tick writes)."""
        combine = logical_and if self.require_all else logical_or
        return functools.reduce(combine, (trace.contact(f, required=True) for f in self.frames))

    def __repr__(self) -> str:
        return f"contact({', '.join(map(repr, self.frames))}, require_all={self.require_all})"


@dataclass(slots=True, repr=False, eq=False)
class NoContact:
    """Fires when none of the contact switches of ``frames`` is closed (`no_contact`)."""

    frames: tuple[str, ...]

    def __call__(self, context: Context) -> bool:
        """Whether the event fires at this tick."""
        return not any(context.in_contact(f) for f in self.frames)

    def lower(self, trace: object) -> object:
        """The event as a traced value."""
        return logical_not(Contact(self.frames, require_all=False).lower(trace))

    def __repr__(self) -> str:
        return f"no_contact({', '.join(map(repr, self.frames))})"


@dataclass(slots=True, repr=False, eq=False)
class Combined:
    """Fires when any (or all) of ``events`` fire (`any_of`, `all_of`)."""

    events: tuple[Event, ...]
    require_all: bool

    def __call__(self, context: Context) -> bool:
        """Whether the event fires at this tick."""
        wanted = self.require_all  # all(...) / any(...) without a generator (per tick)
        for each in self.events:
            if bool(each(context)) != wanted:
                return not wanted
        return wanted

    def lower(self, trace: object) -> object:
        """The event as a traced value (every event evaluated: they have no side effect)."""
        combine = logical_and if self.require_all else logical_or
        return functools.reduce(combine, map(trace.event, self.events))

    def __repr__(self) -> str:
        kind = "all_of" if self.require_all else "any_of"
        return f"{kind}({', '.join(map(repr, self.events))})"


def after(seconds: float) -> Event:
    """Fires once the current state has lasted ``seconds`` (a timer, e.g. the buffer states).

    Raises:
        InvalidInputError: ``seconds`` is not a finite real number >= 0.
    """
    return After(check_number(seconds, "after(): seconds", minimum=0.0))


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
    return AheadOf(frame, reference, distance, axis)


def contact(*frames: str, require_all: bool = True) -> Event:
    """Fires when the contact switches of ``frames`` are closed (all of them, or any).

    Raises:
        InvalidInputError: No frame given, a frame that is not a str, or ``require_all`` that
            is not a bool.
    """
    frames = _frames(frames, "contact()")
    return Contact(frames, check_flag(require_all, "contact(): require_all"))


def no_contact(*frames: str) -> Event:
    """Fires when none of the contact switches of ``frames`` is closed.

    Raises:
        InvalidInputError: No frame given, or a frame that is not a str.
    """
    return NoContact(_frames(frames, "no_contact()"))


def any_of(*events: Event) -> Event:
    """Fires when any of ``events`` fires.

    Raises:
        InvalidInputError: No event given, or one that is not callable.
    """
    return Combined(_events(events, "any_of()"), require_all=False)


def all_of(*events: Event) -> Event:
    """Fires when all of ``events`` fire.

    Raises:
        InvalidInputError: No event given, or one that is not callable.
    """
    return Combined(_events(events, "all_of()"), require_all=True)


def when(predicate: Callable[[Context], bool]) -> Event:
    """Wrap any callable of the context as an event (a plan traces it, or calls it).

    Raises:
        InvalidInputError: ``predicate`` is not callable.
    """
    if not callable(predicate):
        raise InvalidInputError(
            f"when(): predicate must be a callable of the Context, got {describe(predicate)}."
        )
    return predicate
