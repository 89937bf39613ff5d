"""Common machinery of the gaits: a controller driven by a state machine, and a walk's record."""

from __future__ import annotations

import math
import os
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ..components.slots import slot
from ..control.controller import Controller, ControlOutput
from ..control.machine_controller import MachineController
from ..control.plan.compiled import CompiledMachine
from ..control.state_machine import StateMachine
from ..control.tick_rate import TickRate, bound_tick_rate
from ..exceptions import InvalidInputError
from ..models.robot import Robot

if TYPE_CHECKING:
    from ..simulation.simulator import Simulator
    from ..simulation.terrain import Terrain


def as_floats(values: object) -> tuple:
    """A tick's vector as a tuple: a traced one as it is, an array's entries as floats."""
    if isinstance(values, tuple):
        return values
    return tuple(np.asarray(values, dtype=float).tolist())


class SizedSlots:
    """A slotted component's mixin: slot ``name`` holds ``SIZES[name]`` numbers.

    Attributes:
        SIZES: The numbers per slot.
        GAINS: The slots whose numbers are >= 0.
        FINITE: Whether the numbers must be finite (else only not NaN).
    """

    SIZES: Mapping[str, int] = {}
    GAINS: tuple[str, ...] = ()
    FINITE = True

    def _sized(self, value: object, name: str) -> np.ndarray:
        """``value`` as slot ``name``'s numbers, never NaN (finite if `FINITE`, >= 0 in `GAINS`).

        Raises:
            InvalidInputError: Not ``SIZES[name]`` such numbers (naming the component and slot).
        """
        count, gains, finite = self.SIZES[name], name in self.GAINS, self.FINITE
        try:
            array = np.array(value, dtype=float).reshape(-1)
        except (TypeError, ValueError):
            array = np.full(count + 1, np.nan)
        bad = array.shape != (count,) or np.isnan(array).any() or (gains and (array < 0.0).any())
        if bad or (finite and not np.isfinite(array).all()):
            kind = ("finite numbers" if finite else "numbers") + (" >= 0" if gains else "")
            raise InvalidInputError(f"{self.name}: {name} must be {count} {kind}, got {value!r}.")
        return array


class SlotFormula:
    """A slotted component's mixin: one `_formula` is both its float and its traced wrench."""

    def _formula(self, slots: Mapping, position: Sequence, velocity: Sequence) -> list:
        """The wrench on the slots (floats or a plan's registers) and the readings."""
        raise NotImplementedError

    def compute_wrench(self, position: np.ndarray, velocity: np.ndarray, time: float) -> np.ndarray:
        """`_formula` on the slots' and the readings' floats."""
        slots = {name: getattr(self, f"_{name}").tolist() for name in self.SLOTS}
        position = np.asarray(position, dtype=float).tolist()
        return np.array(self._formula(slots, position, np.asarray(velocity, float).tolist()))

    def traced_wrench(self, slots, position: tuple, velocity: tuple, time: object) -> list:
        """`_formula` on a plan's traced slots and readings."""
        return self._formula(slots, position, velocity)


def sized_slot(name: str, doc: str, scalar: bool = False) -> property:
    """The property of a `SizedSlots` slot (``scalar``: its one number read as a float)."""
    vector = slot(name, "_sized")
    read = (lambda self: vector.fget(self)[0]) if scalar else vector.fget
    return property(read, vector.fset, doc=doc)


class Gait:
    """A controller and a state machine stepped together (subclasses call `_finish`).

    Attributes:
        robot: The robot.
        controller: Actuators and components.
        machine: States and transitions.
        wiring: The [`MachineController`][] of the two (the tick).
        step_states: States whose entries count as steps (single support).
        contact_frames: Frames whose contact switches the gait reads.
        foot_contacts: Contact frames per support frame (see `support_contacts`).
    """

    step_states: tuple[str, ...] = ()
    contact_frames: tuple[str, ...] = ()
    foot_contacts: Mapping[str, tuple[str, ...]] = {}

    def __init__(self, robot: Robot) -> None:
        self.robot = robot
        self.controller = Controller(robot, clip=True, on_singular="skip")
        self.machine: StateMachine | None = None
        self.wiring: MachineController | None = None

    def _finish(self, machine: StateMachine) -> None:
        self.machine = machine
        self.wiring = MachineController(self.controller, machine)

    def _bound_gains(self, control_rate: float) -> list[TickRate]:
        """Bound every state's per-tick gain rate at ``control_rate`` [Hz]; the rates before."""
        states = [(state.active, state.support) for state in self.machine.states]
        q = self.initial_configuration()
        return bound_tick_rate(self.controller, q, states, 1.0 / control_rate)

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
        """One control tick (compiled on the first tick or in `warm_up`, else Python).

        Args:
            q: Configuration ``(nq,)`` (Pinocchio convention).
            v: Velocity ``(nv,)``.
            time: Controller time [s].
            contacts: Contact switches by frame name.

        Returns:
            The [`ControlOutput`][] (its ``tau`` goes to the motors).
        """
        return self.wiring.compute(q, v, time, contacts)

    @property
    def last(self) -> ControlOutput | None:
        """The last tick's output (None before the first)."""
        return None if self.wiring is None else self.wiring.last

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


#: The absolute bound of every walk's desired speed [m/s] (``force_speed`` does not lift it).
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
            MAX_SPEED]`` without ``zero``).
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


@dataclass(frozen=True, slots=True)
class Walk:
    """How to run one of the walks (a gait folder's registration, see ``WALKS``).

    Attributes:
        name: Demo name on the command line.
        robot: Robot name for [`load_robot`][].
        run: ``run(request)`` with the resolved `WalkRequest`; returns the result.
        parameters: The gait's parameters dataclass.
        duration: Default simulated time [s].
        draw: A result's matplotlib figure: ``draw(result, window)`` (see `plot`).
        description: One line for the command-line help.
        terrain: Default terrain (a [`parse`][virtual_actuators.simulation.Terrain.parse] spec).
        gait: The gait's class, which a planar walk builds (None: ``run`` builds the gait).
        push: Start-up push on the body: force along x [N] for ``push_time`` seconds.
        push_time: [s].
        options: The walk's own keyword options of ``run`` (and command-line options).
        plot_window: Whether ``draw`` draws a time window (``--window``).
        force_scale: Viewer arrow length per newton [m/N].
        viewer_robot: Loads the robot the viewer draws from the options (None: ``robot``).
        speeds: The supported desired speeds ``(low, high)`` [m/s], or a function of the options
            returning them (None: the walk takes no speed).
        nominal_speed: The gait's own desired speed [m/s], or a function of the options
            returning it (None: the walk takes no speed).
    """

    name: str
    robot: str
    run: Callable[..., Any]
    parameters: type
    duration: float
    draw: Callable[..., Any]
    description: str
    terrain: str = "flat"
    gait: type[Gait] | None = None
    push: float = 0.0
    push_time: float = 0.0
    options: tuple[str, ...] = ()
    plot_window: bool = False
    force_scale: float = 1 / 250
    viewer_robot: Callable[..., Robot] | None = None
    speeds: tuple[float, float] | Callable[..., tuple[float, float] | None] | None = None
    nominal_speed: float | Callable[..., float] | None = None

    def plot(self, result: Any, path: str | os.PathLike[str], window: Any = None) -> Path:
        """Draw ``result`` (`draw`; ``window``: ``(t0, t1)`` simulated seconds or None) to a PNG.

        A walk on the estimate also gets ``STEM-estimate.png`` beside it: the estimated against
        the true velocity and height (`draw_estimate`).

        Returns:
            The path written (the walk's figure).
        """
        from ..experiments.estimation_score import draw_estimate
        from ..experiments.plot_panels import save_figure

        path = save_figure(self.draw(result, window), path)
        estimation = getattr(result, "estimation", None)
        if estimation is not None:
            save_figure(draw_estimate(estimation), path.with_name(f"{path.stem}-estimate.png"))
        return path

    def speed_range(self, **options: Any) -> tuple[float, float] | None:
        """The supported desired speeds ``(low, high)`` [m/s] with these options, or None."""
        return self.speeds(**options) if callable(self.speeds) else self.speeds

    def default_speed(self, **options: Any) -> float | None:
        """The desired speed [m/s] of a run given none: `nominal_speed` clipped to `speed_range`.

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
            forced_by: How the caller runs it anyway, which the message offers.
            **options: The walk's options that select its range.

        Raises:
            InvalidInputError: ``speed`` is outside the supported range (its message names it).
        """
        supported = self.speed_range(**options)
        if supported is None or not isinstance(speed, (int, float)):
            return  # None: the walk's default; not a number: the walk's own check refuses it
        low, high = supported
        if not low - 1e-9 <= speed <= high + 1e-9:
            given = {k: v for k, v in options.items() if v not in (None, False)}
            named = ", ".join(k if v is True else f"{k} {v!r}" for k, v in given.items())
            raise InvalidInputError(  # named: " (robot 'go2', gait 'pace', track)" or ""
                f"{self.name}{f' ({named})' if named else ''} walks at desired speeds from {low:g} "
                f"to {high:g} m/s, got {speed:g} m/s: give a speed in that range, or "
                f"{forced_by} to run it anyway."
            )


@dataclass(frozen=True, slots=True)
class WalkRequest:
    """One walk's run as ``run_walk`` resolved it (what `Walk.run` receives).

    Attributes:
        walk: The walk.
        duration: Simulated time [s].
        speed: Desired speed [m/s], as given (None: the walk's default).
        terrain: A [`Terrain`][] or its spec (the walk's when none was given).
        progress: Show a tqdm progress bar.
        on_tick: Called after every physics step, or None.
        stop_on_fall: End the run 0.5 s after the first fallen tick.
        seed: None for the walk's nominal start; an int varies it.
        parameters: The gait's parameters (a ``walk.parameters``), or None for the gait's.
        distribution: ``"partitioned"`` or ``"qp"`` as given, or None.
        options: The walk's own options (``walk.options``).
    """

    walk: Walk
    duration: float
    speed: float | None
    terrain: str | Terrain
    progress: bool
    on_tick: Callable[[Simulator, Gait], None] | None
    stop_on_fall: bool
    seed: int | None
    parameters: object | None
    distribution: str | None
    options: Mapping[str, Any]

    @property
    def loop(self) -> tuple[bool, Callable[[Simulator, Gait], None] | None, bool]:
        """``(progress, on_tick, stop_on_fall)``: the loop's arguments, in a walk's order."""
        return self.progress, self.on_tick, self.stop_on_fall

    def run_with(self, run: Callable[..., Any], config: type) -> Any:
        """``run(config, parameters, *loop)``, ``config`` a walk's dataclass built from the request.

        The speed is the given one, else `Walk.default_speed`; the distribution the given one
        (into the parameters too), else the parameters', else ``"qp"``.

        Raises:
            InvalidInputError: What ``config`` or ``run`` raises (a bad option, speed, ...).
        """
        parameters, distribution = self.parameters, self.distribution
        if distribution is None:
            distribution = "qp" if parameters is None else parameters.distribution
        elif parameters is not None:
            parameters = replace(parameters, distribution=distribution)
        speed = self.walk.default_speed(**self.options) if self.speed is None else self.speed
        built = config(
            speed=speed, terrain=self.terrain, duration=self.duration, seed=self.seed,
            distribution=distribution, **self.options,
        )  # fmt: skip
        return run(built, parameters, *self.loop)
