"""A state machine for gaits (VMC 2001, section 5, Fig. 5 and Table 1)."""

from __future__ import annotations

from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field

import numpy as np

from ..exceptions import InvalidInputError, suggestion
from ..vocabulary.arguments import check_name, check_names, check_sequence, describe
from .context import Context, Event


def _check_context(context: object) -> None:
    """Refuse anything but a [`Context`][virtual_actuators.Context] (an InvalidInputError)."""
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
        on_update: Called with the context at every tick in the state, before the controller.

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
            target = self._states[transition.target]
            self._exits[transition.source].append((transition.event, target))
        self._check(self.initial, "initial")
        self._order = list(self._states.values())
        #: the state's index, when it was entered [s], whether it started (1.0): an array a
        #: compiled plan keeps in its registers (`bind_position`)
        self._position = np.array([float(self.index[self.initial]), 0.0, 0.0])

    @property
    def current(self) -> State:
        """The current state."""
        return self._order[int(self._position.item(0))]

    @property
    def current_index(self) -> int:
        """The current state's index in `index` (the declaration order)."""
        return int(self._position.item(0))

    @property
    def entered_at(self) -> float:
        """When the current state was entered [s]."""
        return self._position.item(1)

    @property
    def started(self) -> bool:
        """Whether the machine has entered its first state."""
        return self._position.item(2) != 0.0

    def bind_position(self, view: np.ndarray) -> None:
        """Keep the machine's state in ``view`` (3 floats of a compiled plan's registers)."""
        view[:] = self._position
        self._position = view

    def _check(self, name: str, where: str) -> None:
        if not isinstance(name, str):
            raise InvalidInputError(f"{where}: a state name must be a str, got {describe(name)}.")
        if name not in self._states:
            raise InvalidInputError(
                f"{where}: unknown state {name!r}. {suggestion(name, self._states, 'states')}"
            )

    def exits(self, state: str) -> list[tuple[Event, State]]:
        """``(event, target)`` of each of a state's transitions, in declaration order."""
        self._check(state, "exits")
        return list(self._exits[state])

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
        self._position[2] = 1.0  # started
        self._enter(self.state(state or self.initial), context)
        return self.current

    def _enter(self, state: State, context: Context) -> None:
        self._position[:2] = self.index[state.name], context.time  # current, entered_at
        self.history.append((context.time, state.name))
        context.state, context.time_in_state = state.name, 0.0
        if state.on_enter is not None:
            state.on_enter(context)

    def update(self, context: Context) -> State:
        """Take the first transition whose event fires, then run the state's ``on_update``.

        Starts the machine on the first call if [`start`][] was not called.

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
