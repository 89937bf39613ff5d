"""The seed's walking components (VMC 2001, section 5, Figs. 6 and 7)."""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from ..exceptions import InvalidAxisError, InvalidInputError
from ..vocabulary.arguments import as_float_array, check_number
from ..vocabulary.axes import parse_axes
from ..vocabulary.traced import TRACING, traced_store
from .springs import SpringDamper, Vector


def _entry(values: np.ndarray | tuple, index: int) -> object:
    """Entry ``index`` of a parameter: a float of its array, or its traced value."""
    return values[index] if isinstance(values, tuple) else values.item(index)


class GrannyWalker(SpringDamper):
    """Spring-dampers on body height and pitch, plus the weight as a feed-forward force.

    Args:
        height: Height set point of the action frame [m] (along the actuator's z).
        stiffness: ``(k_z [N/m], k_pitch [N m/rad])``.
        damping: ``(b_z [N s/m], b_pitch [N m s/rad])``.
        pitch: Pitch set point [rad].
        weight: Constant upward force [N], e.g. total mass times g.
        axes: The height axis and the pitch axis (``("z", "ry")`` for a planar robot in x-z).
        name: Label used in reports.

    Raises:
        InvalidAxisError: ``axes`` is not one translation followed by one rotation.
        InvalidInputError: ``height``, ``pitch`` or ``weight`` is not a finite real number, or
            a bad ``stiffness`` or ``damping`` (shape, value, or a negative entry).
    """

    def __init__(
        self,
        height: float,
        stiffness: Vector,
        damping: Vector,
        pitch: float = 0.0,
        weight: float = 0.0,
        axes: Sequence[str] = ("z", "ry"),
        name: str | None = None,
    ) -> None:
        height = check_number(height, "GrannyWalker: height [m]")
        pitch = check_number(pitch, "GrannyWalker: pitch [rad]")
        weight = check_number(weight, "GrannyWalker: weight [N]")
        parsed = parse_axes(axes, "GrannyWalker: axes")
        if len(parsed) != 2 or parsed[0].startswith("r") or not parsed[1].startswith("r"):
            raise InvalidAxisError(
                f"GrannyWalker axes must be a height axis then a pitch axis such as "
                f"('z', 'ry'), got {tuple(axes)}."
            )
        super().__init__(
            parsed, stiffness, damping, setpoint=(height, pitch), force=(weight, 0.0), name=name
        )

    height = property(
        lambda self: _entry(self._traced("setpoint"), 0),
        lambda self, value: self._set_entry(0, value, "height [m]"),
    )
    """Height set point [m]."""
    pitch = property(
        lambda self: _entry(self._traced("setpoint"), 1),
        lambda self, value: self._set_entry(1, value, "pitch [rad]"),
    )
    """Pitch set point [rad]."""

    def _set_entry(self, index: int, value: float, what: str) -> None:
        if TRACING.get() is not None and traced_store(self, "setpoint", (value,), offset=index):
            return
        value = check_number(value, f"{self.name}: {what}")
        setpoint = self._setpoint.copy()  # a new array, as the setpoint setter makes
        setpoint[index] = value
        self._assign("_setpoint", setpoint)


class DogtrackBunny(SpringDamper):
    """A set point running at the desired speed, pulling the body through a damper (and spring).

    ``force = damping (speed - velocity) + stiffness (bunny - position)`` with the bunny at
    ``start + speed (time - start_time)``; [`reset`][] puts the bunny back at the body.

    Args:
        speed: Desired speed [m/s] along ``axis``.
        damping: [N s/m], >= 0.
        stiffness: [N/m], >= 0 (the seed uses a damper only).
        limit: Largest force the bunny applies [N] (``inf``: none).
        axis: Axis of travel.
        name: Label used in reports.

    Raises:
        InvalidAxisError: Bad axis.
        InvalidInputError: ``speed`` is not a finite real number, or a bad ``damping``,
            ``stiffness`` or ``limit`` (not a real number, NaN, negative).
    """

    def __init__(
        self,
        speed: float,
        damping: float,
        stiffness: float = 0.0,
        limit: float = np.inf,
        axis: str = "x",
        name: str | None = None,
    ) -> None:
        super().__init__((axis,), stiffness, damping, limit=limit, name=name)
        self.speed = speed
        self._start = np.zeros(2)  # where and when the bunny started [m, s]

    #: The parameters a compiled plan keeps: the spring-damper's and the start.
    SLOTS = (*SpringDamper.SLOTS, "start")

    start_position = property(
        lambda self: self._start.item(0),
        lambda self, value: self._set_start(0, value, "start_position [m]"),
    )
    """Where the bunny started [m]."""
    start_time = property(
        lambda self: self._start.item(1),
        lambda self, value: self._set_start(1, value, "start_time [s]"),
    )
    """When the bunny started [s]."""

    def _set_start(self, index: int, value: float, what: str) -> None:
        self._start[index] = check_number(value, f"{self.name}: {what}")

    @property
    def speed(self) -> float:
        """Desired speed [m/s]."""
        return _entry(self._traced("velocity_setpoint"), 0)

    @speed.setter
    def speed(self, value: float) -> None:
        self.velocity_setpoint = check_number(value, f"{self.name}: speed [m/s]")

    def position_at(self, time: float) -> float:
        """Where the bunny is at ``time`` [m]."""
        if TRACING.get() is None:  # the arrays themselves (a tick's record reads it)
            start = self._start
            return start.item(0) + self._velocity_setpoint.item(0) * (time - start.item(1))
        return self.start_position + self.speed * (time - self.start_time)

    def reset(self, position: np.ndarray, time: float) -> None:
        """Put the bunny at ``position`` [m] (one number) at ``time`` [s].

        Raises:
            InvalidInputError: ``position`` is not one finite real number, or ``time`` is not a
                finite real number.
        """
        time = check_number(time, f"{self.name}: time [s]")
        values = as_float_array(position, f"{self.name}: position", "one real number [m]")
        if values.size != 1 or not math.isfinite(float(values.reshape(-1)[0])):
            raise InvalidInputError(
                f"{self.name}: position must be one finite real number [m], got {values}."
            )
        self.start_position = float(values.reshape(-1)[0])
        self.start_time = time

    def traced_wrench(self, slots, position: tuple, velocity: tuple, time: object) -> list:
        """`compute_wrench` on a plan's traced values: the set point moved, then the formula."""
        (start, started), (speed,) = slots["start"], slots["velocity_setpoint"]
        slots.store("setpoint", (start + speed * (time - started),))
        return super().traced_wrench(slots, position, velocity, time)

    def traced_reset(self, slots, position: tuple, time: object) -> None:
        """`reset` on a plan's traced values."""
        slots.store("start", (position[0], time))

    def compute_wrench(self, position: np.ndarray, velocity: np.ndarray, time: float) -> np.ndarray:
        """Damper toward the bunny's speed plus spring toward its position."""
        self.setpoint = self.position_at(time)
        return super().compute_wrench(position, velocity, time)


class SwingLegLinkage(SpringDamper):
    """Spring-dampers that place the swing foot relative to the body.

    On a serial actuator from the body to the swing foot; the gait moves its set points every
    tick with [`place`][].

    Args:
        stiffness: Per axis or scalar [N/m].
        damping: Per axis or scalar [N s/m].
        axes: Axes of the foot's placement (``("x", "z")`` for a planar robot).
        setpoint: Initial foot position relative to the body [m].
        name: Label used in reports.

    Raises:
        InvalidAxisError: Bad axes.
        InvalidInputError: Bad parameter shape or value.
    """

    def __init__(
        self,
        stiffness: Vector,
        damping: Vector,
        axes: Sequence[str] = ("x", "z"),
        setpoint: Vector = 0.0,
        name: str | None = None,
    ) -> None:
        super().__init__(axes, stiffness, damping, setpoint=setpoint, name=name)

    def place(self, setpoint: Vector, velocity_setpoint: Vector = 0.0) -> None:
        """Move the foot's set point [m] and its velocity [m/s].

        Raises:
            InvalidInputError: A value is not a real number or one per axis, or not finite.
        """
        self.setpoint = setpoint
        self.velocity_setpoint = velocity_setpoint
