"""Common machinery of the gaits: a controller driven by a state machine, and a walk's record.

A `Gait` owns a [`Controller`][] (actuators and components,
declared once) and a [`StateMachine`][] whose states select which
attachments run. `Gait.compute` is the whole per-tick control law: update the machine on
the tick's [`Context`][], reset the components of attachments that
just became active, evaluate the active ones and return the joint efforts. A `Walk` is
what a gait's folder registers (its ``walk.py``): the robot, the defaults, the closed loop that
runs it and how its result is plotted; `registry` collects them.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..control.context import Context
from ..control.controller import Controller, ControlOutput
from ..control.machine_controller import MachineController
from ..control.plan.compiled import CompiledMachine
from ..control.state_machine import Event, StateMachine
from ..control.tick_rate import TickRate, bound_tick_rate
from ..exceptions import InvalidInputError
from ..models.robot import Robot
from ..vocabulary.scalar import logical_and
from ..vocabulary.traced import lowerable
from .planar import SIDES


class Gait:
    """A controller and a state machine stepped together.

    Subclasses build `controller` and `machine` in their constructor and call
    `_finish` at the end.

    Attributes:
        robot: The robot.
        controller: Actuators and components.
        machine: States and transitions.
        wiring: The [`MachineController`][] of the two (the tick).
        step_states: States whose entries count as steps (single support).
        contact_frames: Frames whose contact switches the gait reads.
        foot_contacts: Contact frames per support frame (see `support_contacts`).
        last: The last [`ControlOutput`][].
    """

    step_states: tuple[str, ...] = ()
    contact_frames: tuple[str, ...] = ()
    #: The contact frames that make up each support frame whose geoms are elsewhere (a flat
    #: foot's heel and toe); a support frame not listed is its own contact frame.
    foot_contacts: Mapping[str, tuple[str, ...]] = {}

    def __init__(self, robot: Robot) -> None:
        self.robot = robot
        self.controller = Controller(robot, clip=True, on_singular="skip")
        self.machine: StateMachine | None = None
        self.wiring: MachineController | None = None
        self.last: ControlOutput | None = None

    def _finish(self, machine: StateMachine) -> None:
        self.machine = machine
        self.wiring = MachineController(self.controller, machine)

    def _bound_gains(self, control_rate: float) -> list[TickRate]:
        """Bound the derived gains' per-tick rate in every state (`bound_tick_rate`).

        Judged at `initial_configuration`, each state's support held, for a controller run at
        ``control_rate`` [Hz]; returns each state's `TickRate` before the bound.
        """
        states = [(state.active, state.support) for state in self.machine.states]
        q = self.initial_configuration()
        return bound_tick_rate(self.controller, q, states, 1.0 / control_rate)

    def _front_is(self, side: str, event: Event) -> Event:
        """``event``, but only while ``side`` is the front foot (``self.memory.front``: 0 left).

        Traced by a compiled plan (``event`` an event object); on floats in Python.
        """
        if not hasattr(getattr(self, "memory", None), "front"):  # a gait keeping `front` itself
            return lambda context: self.front == side and event(context)
        index = float(SIDES.index(side))

        @lowerable
        def front_is(context: Context) -> object:
            if isinstance(context, Context):
                return self.memory.front == index and event(context)
            return logical_and(self.memory.front == index, context.event(event))

        return front_is

    def initial_configuration(self) -> np.ndarray:
        """Where a simulation of this gait starts (default: the robot's standing pose)."""
        return self.robot.neutral()

    def nominal_height(self) -> float:
        """Nominal hip height above level ground [m] (the gait's ``height`` or ``hip_height``)."""
        parameters = getattr(self, "parameters", None)
        if hasattr(parameters, "hip_height"):
            return float(parameters.hip_height(0.0))
        return float(parameters.height)

    def support_contacts(self) -> list[tuple[str, ...]]:
        """Per foot in support in the current state, the contact frames that make it up."""
        contacts = self.foot_contacts
        return [contacts.get(foot, (foot,)) for foot in self.machine.current.support]

    @property
    def state(self) -> str:
        """Name of the current state."""
        return self.machine.current.name

    def compute(
        self,
        q: np.ndarray,
        v: np.ndarray,
        time: float,
        contacts: Mapping[str, bool] | None = None,
    ) -> ControlOutput:
        """One control tick: [`MachineController.compute`][] of `wiring`.

        The gait is lowered into the compiled core on its first tick, or in `warm_up` (its
        components and memory are the plan's registers from then on); without the core, or a
        gait the lowering refuses, the tick runs in Python.

        Args:
            q: Configuration ``(nq,)`` (Pinocchio convention).
            v: Velocity ``(nv,)``.
            time: Controller time [s].
            contacts: Contact switches by frame name (only the gaits that use switches need them).

        Returns:
            The [`ControlOutput`][] (its ``tau`` goes to the motors).
        """
        self.last = self.wiring.compute(q, v, time, contacts)
        return self.last

    def warm_up(self, q: np.ndarray) -> None:
        """Lower the gait (if it has not been) and warm its controller up, before a timed loop.

        Raises:
            InvalidInputError: A bad ``q``.
        """
        self.wiring.warm_up(q)

    @property
    def compiled(self) -> CompiledMachine | None:
        """The compiled machine the ticks run on (None: Python, or not lowered yet)."""
        return self.wiring.compiled

    def __repr__(self) -> str:
        return f"{type(self).__name__}(robot={self.robot.name!r}, state={self.state!r})"


#: The bound of every walk's desired speed [m/s]. It is absolute: ``force_speed=True`` (command
#: line: ``--force-speed``) lifts a walk's supported range, never this bound. No walk here walks
#: faster: the fastest, go2's trot, was measured up to it (``gaits.legged.speeds``).
MAX_SPEED = 1.5

#: Why a speed beyond `MAX_SPEED` is refused (ends the messages that refuse one).
BEYOND_MAX_SPEED = (
    f"{MAX_SPEED:g} m/s bounds every walk's desired speed, and force_speed does not lift it (it "
    "lifts only a walk's supported range): no walk here walks faster (the fastest, go2's trot, "
    f"was measured up to {MAX_SPEED:g} m/s)"
)


def check_speed_bound(speed: object, zero: bool = True) -> None:
    """Refuse a desired speed beyond `MAX_SPEED` or below zero (``zero``: 0 allowed).

    Raises:
        InvalidInputError: Not a finite number, or outside ``[0, MAX_SPEED]`` (``(0,
            MAX_SPEED]`` without ``zero``); beyond the bound, the message says it is absolute,
            and why.
    """
    number = isinstance(speed, (int, float)) and not isinstance(speed, bool)
    if not (number and math.isfinite(speed)) or speed < 0.0 or (speed == 0.0 and not zero) or (
        speed > MAX_SPEED
    ):
        bracket = "[" if zero else "("
        raise InvalidInputError(
            f"speed must be in {bracket}0, {MAX_SPEED:g}] m/s, got {speed!r}"
            + (f": {BEYOND_MAX_SPEED}." if number and speed > MAX_SPEED else ".")
        )


#: The ways a gait's double support can share the body's wrench (``distribution=``).
DISTRIBUTIONS = ("partitioned", "qp")


def check_distribution(distribution: object) -> bool:
    """Whether ``distribution`` asks for the QP (checked: one of `DISTRIBUTIONS`).

    Raises:
        InvalidInputError: Any other value.
    """
    if distribution not in DISTRIBUTIONS:
        raise InvalidInputError(
            f"distribution must be one of {DISTRIBUTIONS}, got {distribution!r}."
        )
    return distribution == "qp"


def describe_options(options: Mapping[str, Any]) -> str:
    """`` (robot 'go2', gait 'pace', track)`` for the options given, or ``""``."""
    named = [
        key if value is True else f"{key} {value!r}"
        for key, value in options.items()
        if value not in (None, False)
    ]
    return f" ({', '.join(named)})" if named else ""


@dataclass(frozen=True, slots=True)
class Walk:
    """How to run one of the walks (a gait folder's registration, see ``WALKS``).

    Attributes:
        name: Demo name on the command line.
        robot: Robot name for [`load_robot`][].
        run: The walk's own start: ``run(request)`` with the
            [`WalkRequest`][virtual_actuators.gaits.registered.WalkRequest] that
            [`run_registered`][virtual_actuators.gaits.registered.run_registered] resolved from
            `run_walk`'s arguments (duration and terrain resolved, parameters of the walk's
            type); it builds the episode, runs it under ``drive`` and returns the result.
        parameters: The gait's parameters dataclass.
        terrain: Default terrain (a [`parse`][virtual_actuators.simulation.Terrain.parse] spec).
        duration: Default simulated time [s].
        plot: Draws a result: ``plot(result, path, window)`` returns the path written.
        description: One line for the command-line help.
        make_gait: Builds the gait from the robot, the desired speed and the parameters (the
            planar bipeds; None when ``run`` builds its own).
        push: Start-up push on the body: force along x [N] for ``push_time`` seconds.
        push_time: [s].
        options: The walk's own keyword options of ``run`` (and command-line options).
        plot_window: Whether ``plot`` draws a time window (``--window``).
        force_scale: Viewer arrow length per newton [m/N].
        viewer_robot: Loads the robot the viewer draws from the options (None: ``robot``).
        speeds: The supported desired speeds ``(low, high)`` [m/s]: the ends walk without
            falling in runs of the walk's default duration (None: the walk takes no speed).
        speeds_for: The supported speeds from the walk's options (the legged walk's depend
            on ``robot`` and ``gait``); None: `speeds` whatever the options.
        nominal_speed: The gait's own desired speed [m/s], or a function of the walk's options
            returning it (the hexapod's is slower with the pendulum); None: the walk takes no
            speed. A run given no speed walks at `default_speed`: this, moved into the
            supported range.
    """

    name: str
    robot: str
    run: Callable[..., Any]
    parameters: type
    terrain: str
    duration: float
    plot: Callable[..., Any]
    description: str
    make_gait: Callable[..., Gait] | None = None
    push: float = 0.0
    push_time: float = 0.0
    options: tuple[str, ...] = ()
    plot_window: bool = False
    force_scale: float = 1 / 250
    viewer_robot: Callable[..., Robot] | None = None
    speeds: tuple[float, float] | None = None
    speeds_for: Callable[..., tuple[float, float]] | None = None
    nominal_speed: float | Callable[..., float] | None = None

    def speed_range(self, **options: Any) -> tuple[float, float] | None:
        """The supported desired speeds ``(low, high)`` [m/s] with these options, or None."""
        return self.speeds if self.speeds_for is None else self.speeds_for(**options)

    def default_speed(self, **options: Any) -> float | None:
        """The desired speed [m/s] of a run given none: always one of the supported speeds.

        The rule: the gait's own speed (`nominal_speed` with these options) when
        `speed_range` holds it, else the nearer end of that range (each end is measured to walk,
        see `speeds`); the nominal speed as it is when the options have no range (a robot the
        legged trot was not measured on). E.g. the legged walk's nominal 0.4 m/s trots solo12 at
        0.4 m/s, but walks it (``gait="walk"``, 0.05 to 0.2 m/s) at 0.2 m/s.

        Returns:
            The speed, or None for a walk that takes no speed (it stands).
        """
        nominal = self.nominal_speed
        if callable(nominal):
            nominal = nominal(**options)
        supported = self.speed_range(**options)
        if nominal is None or supported is None:
            return nominal
        low, high = supported
        return min(max(float(nominal), low), high)

    def check_speed(
        self, speed: float | None, *, forced_by: str = "force_speed=True", **options: Any
    ) -> None:
        """Refuse a desired speed outside `speed_range` (None: the walk's default).

        Args:
            speed: The desired speed [m/s].
            forced_by: How the caller runs it anyway, which the message offers (the command
                line: ``"--force-speed"``).
            **options: The walk's options that select its range.

        Raises:
            InvalidInputError: ``speed`` is outside the supported range (its message names it).
        """
        supported = self.speed_range(**options)
        if supported is None or not isinstance(speed, (int, float)):
            return  # None: the walk's default; not a number: the walk's own check refuses it
        low, high = supported
        if not low - 1e-9 <= speed <= high + 1e-9:
            raise InvalidInputError(
                f"{self.name}{describe_options(options)} walks at desired speeds from {low:g} "
                f"to {high:g} m/s, got {speed:g} m/s: give a speed in that range, or "
                f"{forced_by} to run it anyway."
            )
