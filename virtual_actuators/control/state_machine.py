"""A state machine for gaits (VMC 2001, section 5, Fig. 5 and Table 1).

Each [`State`][] names the controller attachments (actuators with their components) it uses,
the chains in support and the joints left limp. [`Transition`][] objects move between states
on events: callables of the tick's [`Context`][] returning a bool (see
[`virtual_actuators.control.events`][virtual_actuators.events] for body-over-foot, contact and timer
events). All
declarations are built once; changing state only swaps which precomputed attachments are
evaluated, so a transition costs nothing at run time.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np

from ..exceptions import InvalidAxisError, InvalidInputError, suggestion
from ..kinematics.snapshot import Snapshot
from ..models.robot import Robot
from ..vocabulary.arguments import (
    check_name,
    check_names,
    check_number,
    check_robot,
    check_sequence,
    describe,
)

#: A world axis's column in a row of a snapshot's frame table (rotation, then position).
POSITION_COLUMNS = {"x": 9, "y": 10, "z": 11}


def table_entry(snapshot: Snapshot, frame: object, column: int) -> float | None:
    """Entry ``column`` of a frame's row in the snapshot's frame table, None if not tabled.

    A tabled frame is read in one table entry (a tick's cost); callers fall back on the
    snapshot's general reads for the others.
    """
    row = snapshot.tree.name_rows.get(frame) if frame.__class__ is str else None
    if row is not None:
        table = snapshot.frame_table
        if row < table.shape[0]:
            return table.item(row, column)
    return None


class Context:
    """What events see at one tick: state, time, contacts and frame positions on demand.

    Frame reads go through the tick's [`Snapshot`][], the same kinematics
    pass that the controller's actuators and sensors read: events add no kinematics of their
    own.

    Args:
        robot: The robot (frame names are resolved against its model).
        q: Configuration ``(nq,)``.
        v: Velocity ``(nv,)``.
        time: Controller time [s].
        contacts: Contact switches by frame name (e.g. ``{"left_heel": True}``).
        time_in_state: Seconds since the current state was entered (the machine fills it).
        snapshot: The tick's snapshot of ``(q, v)``; built from ``q`` and ``v`` when None.

    Raises:
        InvalidInputError: ``robot`` is not a robot; ``time`` or ``time_in_state`` is not a
            finite number; ``contacts`` is not a dict; ``snapshot`` is not a
            [`Snapshot`][] of ``robot``; bad ``q`` or ``v`` (when no
            snapshot is given).

    """

    def __init__(
        self,
        robot: Robot,
        q: np.ndarray,
        v: np.ndarray,
        time: float,
        contacts: Mapping[str, bool] | None = None,
        time_in_state: float = 0.0,
        *,
        snapshot: Snapshot | None = None,
    ) -> None:
        # the per-tick case: a Snapshot of this robot's model (which proves the robot one)
        known = isinstance(snapshot, Snapshot) and snapshot.tree.model is getattr(
            robot, "model", None
        )
        if not known:
            check_robot(robot, "Context")
        time = check_number(time, "Context: time [s]")
        time_in_state = check_number(time_in_state, "Context: time_in_state [s]")
        if contacts is not None and not isinstance(contacts, Mapping):
            raise InvalidInputError(
                f"Context: contacts must be a dict {{frame: bool}} or None, got "
                f"{describe(contacts)}."
            )
        if snapshot is None:
            snapshot = Snapshot(robot, q, v)
        elif not known and (
            not isinstance(snapshot, Snapshot) or snapshot.tree.model is not robot.model
        ):
            raise InvalidInputError(
                f"Context: snapshot must be a va.Snapshot of the context's robot or None, got "
                f"{describe(snapshot)}."
            )
        self.robot = robot
        self.snapshot = snapshot
        # the snapshot's reads directly (a tick's cost: no second call per read)
        self.frame_position = snapshot.frame_position
        self.frame_velocity = snapshot.frame_velocity
        self.frame_rotation = snapshot.frame_rotation
        self.q, self.v, self.time = snapshot.q, snapshot.v, float(time)
        self.contacts = dict(contacts or {})
        self.time_in_state = time_in_state
        self.state: str | None = None

    @classmethod
    def of_tick(
        cls, robot: Robot, snapshot: Snapshot, time: float, contacts: Mapping[str, bool] | None
    ) -> Context:
        """The context of a tick whose snapshot (of ``robot``, with ``v``) is built already.

        The same context as ``Context(robot, snapshot.q, snapshot.v, time, contacts,
        snapshot=snapshot)``, with the checks a float time and a dict (or no) contacts pass
        skipped (a tick's cost); anything else goes through the constructor's checks.

        Raises:
            InvalidInputError: As the constructor.

        """
        if (
            time.__class__ is not float
            or not math.isfinite(time)
            or not (contacts is None or contacts.__class__ is dict)
            or snapshot.__class__ is not Snapshot
            or snapshot.tree.model is not getattr(robot, "model", None)
        ):
            return cls(robot, snapshot.q, snapshot.v, time, contacts, snapshot=snapshot)
        context = cls.__new__(cls)
        context.robot = robot
        context.snapshot = snapshot
        context.frame_position = snapshot.frame_position
        context.frame_velocity = snapshot.frame_velocity
        context.frame_rotation = snapshot.frame_rotation
        context.q, context.v, context.time = snapshot.q, snapshot.v, time
        context.contacts = {} if contacts is None else contacts.copy()
        context.time_in_state = 0.0
        context.state = None
        return context

    def frame_position(self, frame: str) -> np.ndarray:
        """World position of a frame [m] (from the tick's snapshot).

        Raises:
            FrameNotFoundError: Unknown frame (with close matches).

        """
        return self.snapshot.frame_position(frame)

    def frame_rotation(self, frame: str) -> np.ndarray:
        """World orientation of a frame, a 3x3 rotation matrix.

        Raises:
            FrameNotFoundError: Unknown frame (with close matches).

        """
        return self.snapshot.frame_rotation(frame)

    def frame_pitch(self, frame: str) -> float:
        """Rotation of a frame about the world y axis [rad] (planar robots in x-z).

        Raises:
            FrameNotFoundError: Unknown frame (with close matches).

        """
        snapshot = self.snapshot
        sine = table_entry(snapshot, frame, 2)  # a tabled frame: its rotation's row 0
        if sine is not None:
            return math.atan2(sine, table_entry(snapshot, frame, 0))
        rotation = snapshot.placement(frame)[0]
        return math.atan2(rotation.item(0, 2), rotation.item(0, 0))

    def frame_coordinate(self, frame: str, axis: str) -> float:
        """One world coordinate of a frame's origin [m], a float.

        The entry of [`frame_position`][] along ``axis``, read without making an array (a
        tabled frame: one entry of the snapshot's frame table).

        Args:
            frame: Frame name.
            axis: ``"x"``, ``"y"`` or ``"z"``.

        Raises:
            InvalidAxisError: ``axis`` is not x, y or z.
            FrameNotFoundError: Unknown frame (with close matches).

        """
        column = POSITION_COLUMNS.get(axis) if axis.__class__ is str else None
        if column is None:
            raise InvalidAxisError(
                f"Context.frame_coordinate: axis must be 'x', 'y' or 'z', got {axis!r}."
            )
        value = table_entry(self.snapshot, frame, column)
        if value is not None:
            return value
        return self.frame_position(frame).item(column - 9)

    def frame_velocity(self, frame: str) -> np.ndarray:
        """Linear velocity of a frame's origin in world axes [m/s].

        Raises:
            FrameNotFoundError: Unknown frame (with close matches).

        """
        return self.snapshot.frame_velocity(frame)

    def in_contact(self, frame: str) -> bool:
        """The contact switch of ``frame``.

        Raises:
            InvalidInputError: No switch reported for that frame.

        """
        try:
            return bool(self.contacts[frame])
        except (KeyError, TypeError):  # TypeError: an unhashable frame
            hint = (
                suggestion(str(frame), self.contacts, "contact switches")
                if self.contacts
                else "This context was given no contact switches (Context(..., contacts=...))."
            )
            raise InvalidInputError(f"No contact switch for {frame!r}. {hint}") from None

    def __repr__(self) -> str:
        return f"Context(time={self.time:.4f}, state={self.state!r}, contacts={self.contacts})"


Event = Callable[[Context], bool]


def _check_context(context: object) -> None:
    if not isinstance(context, Context):
        raise InvalidInputError(
            f"context must be a va.Context (the tick's state, time and contacts), got "
            f"{describe(context)}."
        )


@dataclass(repr=False)
class State:
    """One state of a gait.

    Attributes:
        name: Unique name.
        active: Names of the controller attachments evaluated in this state.
        support: Frames in support (for reports and viewers).
        limp: Joints whose effort is zero in this state (e.g. a swing leg falling freely).
        on_enter: Called with the context when the state is entered.
        on_update: Called with the context at every tick spent in the state, before the
            controller runs (e.g. to move set points).

    Raises:
        InvalidInputError: ``name`` is not a str; ``active``, ``support`` or ``limp`` is not a
            name or a sequence of names; ``on_enter`` or ``on_update`` is not callable.

    """

    name: str
    active: tuple[str, ...] = ()
    support: tuple[str, ...] = ()
    limp: tuple[str, ...] = ()
    on_enter: Callable[[Context], None] | None = None
    on_update: Callable[[Context], None] | None = None

    def __post_init__(self) -> None:
        check_name(self.name, "State: name")
        where = f"State {self.name!r}"
        self.active = check_names(self.active, f"{where}: active")
        self.support = check_names(self.support, f"{where}: support")
        self.limp = check_names(self.limp, f"{where}: limp", ordered=False)
        for hook in ("on_enter", "on_update"):
            value = getattr(self, hook)
            if value is not None and not callable(value):
                raise InvalidInputError(
                    f"{where}: {hook} must be a callable of the Context or None, got "
                    f"{describe(value)}."
                )

    def __repr__(self) -> str:
        return f"State({self.name!r}, active={self.active}, support={self.support})"


@dataclass(repr=False)
class Transition:
    """Go from ``source`` to ``target`` when ``event(context)`` is true.

    Attributes:
        source: Name of the state the transition leaves.
        target: Name of the state it enters.
        event: Callable of the [`Context`][] returning a bool.
        label: Text for reports (the seed's Table 1 "trigger event").

    Raises:
        InvalidInputError: ``source``, ``target`` or ``label`` is not a str, or ``event`` is not
            callable.

    """

    source: str
    target: str
    event: Event
    label: str = ""

    def __post_init__(self) -> None:
        check_name(self.source, "Transition: source (a state name)")
        check_name(self.target, "Transition: target (a state name)")
        check_name(self.label, "Transition: label")
        if not callable(self.event):
            raise InvalidInputError(
                f"Transition {self.source!r} -> {self.target!r}: event must be a callable of "
                f"the Context returning a bool (see va.events), got {describe(self.event)}."
            )

    def __repr__(self) -> str:
        label = f", {self.label!r}" if self.label else ""
        return f"Transition({self.source!r} -> {self.target!r}{label})"


@dataclass
class StateMachine:
    """States and transitions; at most one transition per tick, tried in declaration order.

    Args:
        states: The states (unique names).
        transitions: The transitions between them.
        initial: Name of the initial state.

    Raises:
        InvalidInputError: ``states`` or ``transitions`` is not a sequence of [`State`][] or
            [`Transition`][]; ``initial`` is not a str; repeated state names, or a transition
            or ``initial`` naming an unknown state.

    """

    states: Sequence[State]
    transitions: Sequence[Transition]
    initial: str
    history: list[tuple[float, str]] = field(default_factory=list)

    def __post_init__(self) -> None:
        self.states = check_sequence(self.states, "StateMachine: states", "va.State", State)
        self.transitions = check_sequence(
            self.transitions, "StateMachine: transitions", "va.Transition", Transition
        )
        check_name(self.initial, "StateMachine: initial (a state name)")
        self._states = {}
        for state in self.states:
            if state.name in self._states:
                raise InvalidInputError(f"State {state.name!r} is declared twice.")
            self._states[state.name] = state
        self.index = {name: i for i, name in enumerate(self._states)}
        # per state, its transitions' events and target states, in declaration order
        self._exits: dict[str, list[tuple[Event, State]]] = {name: [] for name in self._states}
        for transition in self.transitions:
            for end in (transition.source, transition.target):
                self._check(end, f"transition {transition}")
            exit_ = (transition.event, self._states[transition.target])
            self._exits[transition.source].append(exit_)
        self._check(self.initial, "initial")
        self.current: State = self._states[self.initial]
        self.entered_at = 0.0  # [s]
        self.started = False

    def _check(self, name: str, where: str) -> None:
        if not isinstance(name, str):
            raise InvalidInputError(f"{where}: a state name must be a str, got {describe(name)}.")
        if name not in self._states:
            raise InvalidInputError(
                f"{where}: unknown state {name!r}. {suggestion(name, self._states, 'states')}"
            )

    @property
    def names(self) -> list[str]:
        """State names in declaration order (their index is `index`)."""
        return list(self._states)

    def state(self, name: str) -> State:
        """The state called ``name``.

        Raises:
            InvalidInputError: Unknown name.

        """
        self._check(name, "state")
        return self._states[name]

    def start(self, context: Context, state: str | None = None) -> State:
        """Enter the initial state (or ``state``) at ``context.time``.

        Raises:
            InvalidInputError: ``context`` is not a [`Context`][], or an unknown state.

        """
        _check_context(context)
        if state is not None:
            self._check(state, "start: state")
        self.history.clear()
        self.started = True
        self._enter(self.state(state or self.initial), context)
        return self.current

    def _enter(self, state: State, context: Context) -> None:
        self.current = state
        self.entered_at = context.time
        self.history.append((context.time, state.name))
        context.state, context.time_in_state = state.name, 0.0
        if state.on_enter is not None:
            state.on_enter(context)

    def update(self, context: Context) -> State:
        """Take the first transition whose event fires, then run the state's ``on_update``.

        Starts the machine on the first call if [`start`][] was not called.

        Returns:
            The current state after the update.

        Raises:
            InvalidInputError: ``context`` is not a [`Context`][].

        """
        if context.__class__ is not Context:  # the tick's case skips the check
            _check_context(context)
        if not self.started:
            self.start(context)
        context.state = name = self.current.name
        context.time_in_state = context.time - self.entered_at
        for event, target in self._exits[name]:
            if event(context):
                self._enter(target, context)
                break
        current = self.current
        if current.on_update is not None:
            current.on_update(context)
        return current

    def steps_into(self, names: Iterable[str]) -> int:
        """How many times the machine entered any of ``names`` (e.g. single-support states)."""
        wanted = set(names)
        return sum(1 for _, name in self.history if name in wanted)

    def __repr__(self) -> str:
        return (
            f"StateMachine(states={self.names}, transitions={len(self.transitions)}, "
            f"current={self.current.name!r})"
        )
