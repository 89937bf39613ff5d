"""Springs, dampers, constant forces and inertances on the axes of a virtual actuator (VMC 3)."""

from __future__ import annotations

import functools
import math
from collections.abc import Callable, Sequence

import numpy as np

from ..exceptions import InvalidInputError, TraceError
from ..vocabulary.arguments import check_number
from ..vocabulary.scalar import maximum, minimum
from .base import Component
from .gains import Gains
from .orientation import deflection, rotation_axes
from .slots import Slotted, slot

Vector = float | Sequence[float] | np.ndarray
_FLOAT64 = np.dtype(np.float64)


def spring_damper(
    parameters: dict[str, Sequence], position: Sequence, velocity: Sequence, rotations: object
) -> list:
    """``min(max(k d + b (v0 - v), -limit), limit) + f`` per axis, ``d`` the deflection.

    On floats or traced values alike (``parameters``: the `SLOTS` by name, one value per axis).
    """
    bent = deflection(list(parameters["setpoint"]), list(position), rotations)
    k, b = parameters["stiffness"], parameters["damping"]
    v0, f, limit = parameters["velocity_setpoint"], parameters["force"], parameters["limit"]
    return [
        minimum(maximum(k[i] * bent[i] + b[i] * (v0[i] - velocity[i]), -limit[i]), limit[i]) + f[i]
        for i in range(len(bent))
    ]


class SpringDamper(Slotted, Component):
    """A spring and a damper in parallel on each axis, plus an optional constant force.

    Args:
        axes: Axes the component acts on.
        stiffness: Per axis or scalar, >= 0 [N/m or N m/rad].
        damping: Per axis or scalar, >= 0 [N s/m or N m s/rad].
        setpoint: Rest position [m or rad]; on rotational axes a rotation vector in {O}'s
            axes, the orientation ``exp(setpoint)``.
        velocity_setpoint: Velocity the damper pulls toward [m/s or rad/s] (angular velocity
            in {O}'s axes on rotational axes).
        force: Constant force added (a feed-forward, e.g. the weight) [N or N m].
        limit: Largest magnitude of the spring-damper's output per axis before ``force`` is
            added [N or N m].
        name: Label used in reports.

    Raises:
        InvalidAxisError: Bad axes.
        InvalidInputError: A parameter is not a real number or one per axis (None, a str, a
            dict, a bool, a complex number), has the wrong shape, is not finite, or a stiffness,
            damping or limit is negative; ``name`` is neither None nor a str.
    """

    def __init__(
        self,
        axes: Sequence[str],
        stiffness: Vector = 0.0,
        damping: Vector = 0.0,
        setpoint: Vector = 0.0,
        velocity_setpoint: Vector = 0.0,
        force: Vector = 0.0,
        limit: Vector = np.inf,
        name: str | None = None,
    ) -> None:
        super().__init__(axes, name)
        self._shape = (len(self.axes),)
        self._rotations = rotation_axes(self.axes)  # None: translations only
        self.stiffness = stiffness
        self.damping = damping
        self.setpoint = setpoint
        self.velocity_setpoint = velocity_setpoint
        self.force = force
        self.limit = limit

    stiffness = slot("stiffness", "_non_negative")
    """Spring constants [N/m or N m/rad]."""
    damping = slot("damping", "_non_negative")
    """Damping constants [N s/m or N m s/rad]."""
    setpoint = slot("setpoint")
    """Spring rest positions [m or rad] (rotational axes: a rotation vector in {O})."""
    velocity_setpoint = slot("velocity_setpoint")
    """Velocities the dampers pull toward [m/s or rad/s]."""
    force = slot("force")
    """Constant feed-forward force [N or N m]."""
    limit = slot("limit", "_check_limit")
    """Saturation of the spring-damper output per axis [N or N m] (``inf``: none)."""

    def _check_limit(self, value: Vector, what: str) -> np.ndarray:
        array = self._non_negative(value, what, allow_inf=True)
        self._limited = bool(np.isfinite(array).any())
        return array

    #: The parameters a compiled plan keeps in its registers, in this order.
    SLOTS = ("stiffness", "damping", "setpoint", "velocity_setpoint", "force", "limit")

    def traced_wrench(self, slots, position: tuple, velocity: tuple, time: object) -> list:
        """The wrench of `spring_damper` on traced parameters and readings (a plan's ops)."""
        return spring_damper(slots, position, velocity, self._rotations)

    def linear_gains(self) -> Gains:
        """The stiffness and damping per axis."""
        return Gains(self._stiffness.copy(), self._damping.copy())

    def scale_gains(self, factor: np.ndarray) -> None:
        """Multiply the stiffness and damping of each axis by ``factor``.

        Raises:
            InvalidInputError: ``factor`` is not one number >= 0 per axis.
        """
        factor = self._non_negative(factor, "gain factor")
        self.stiffness = self._stiffness * factor
        self.damping = self._damping * factor

    def compute_wrench(self, position: np.ndarray, velocity: np.ndarray, time: float) -> np.ndarray:
        """``clip(k deflection + b (v0 - v), -limit, limit) + f`` per axis."""
        if (
            position.__class__ is np.ndarray
            and velocity.__class__ is np.ndarray
            and position.dtype is _FLOAT64
            and velocity.dtype is _FLOAT64
            and position.shape == self._shape
            and velocity.shape == self._shape
        ):
            floats = {name: getattr(self, f"_{name}").tolist() for name in SpringDamper.SLOTS}
            return np.array(  # entry by entry on floats: the same bits, faster
                spring_damper(floats, position.tolist(), velocity.tolist(), self._rotations)
            )
        wrench = self._stiffness * self._deflection(position) + self._damping * (
            self._velocity_setpoint - velocity
        )
        if self._limited:
            wrench = np.minimum(np.maximum(wrench, -self._limit), self._limit)
        return wrench + self._force

    def _deflection(self, position: np.ndarray) -> np.ndarray:
        """``setpoint - position``, the orientation's deflection on rotational axes [m, rad]."""
        bent = self._setpoint - position
        if self._rotations is not None and bent.shape == self._shape:
            position = np.asarray(position, dtype=float).tolist()
            bent = np.array(deflection(self._setpoint.tolist(), position, self._rotations))
        return bent

    def _parameters(self) -> str:
        fmt = functools.partial(np.array2string, precision=4, separator=", ")
        return (
            f"stiffness={fmt(self._stiffness)}, damping={fmt(self._damping)}, "
            f"setpoint={fmt(self._setpoint)}"
        )


class Spring(SpringDamper):
    """A spring: ``stiffness * deflection``, or any force law of the deflection.

    Args:
        axes: Axes the spring acts on.
        stiffness: [N/m or N m/rad], >= 0 (a linear spring); None with ``law``.
        setpoint: Rest position [m or rad].
        name: Label used in reports.
        law: ``law(deflection) -> force`` on the spring's axes [m or rad] -> [N or N m], e.g.
            ``lambda d: 2000 * d**3``; one finite number per axis (or a scalar). With a law,
            ``stiffness`` is not used.

    Raises:
        InvalidAxisError: Bad axes.
        InvalidInputError: Bad parameter shape or value; both or neither of ``stiffness`` and
            ``law`` given; ``law`` not callable; (per tick) a law that returns the wrong
            number of values, complex values or a non-finite one.
    """

    def __init__(
        self,
        axes: Sequence[str],
        stiffness: Vector | None = None,
        setpoint: Vector = 0.0,
        name: str | None = None,
        law: Callable[[np.ndarray], Vector] | None = None,
    ) -> None:
        if (stiffness is None) == (law is None):
            raise InvalidInputError(
                f"{name or 'Spring'}: give a stiffness (a linear spring) or a law (a callable "
                "of the deflection), exactly one of them."
            )
        if law is not None and not callable(law):
            raise InvalidInputError(
                f"{name or 'Spring'}: law must be a callable of the deflection, got "
                f"{type(law).__name__}."
            )
        super().__init__(
            axes, stiffness=0.0 if law is not None else stiffness, setpoint=setpoint, name=name
        )
        self.law = law

    def compute_wrench(self, position: np.ndarray, velocity: np.ndarray, time: float) -> np.ndarray:
        """The linear spring's force, or ``law(deflection)`` ([`SpringDamper`][])."""
        if self.law is None:
            return SpringDamper.compute_wrench(self, position, velocity, time)
        result = self.law(self._deflection(np.asarray(position, dtype=float)))
        try:
            values = np.asarray(result)
            if values.dtype.kind == "c":  # a cast to float would drop the imaginary part
                raise TypeError
            force = np.broadcast_to(values.astype(float), self._shape).copy()
        except (TypeError, ValueError):
            raise InvalidInputError(
                f"{self.name}: law returned {result!r}; expected {len(self.axes)} numbers (axes "
                f"{self.axes}) or one, real and finite."
            ) from None
        if not np.all(np.isfinite(force)):
            raise InvalidInputError(f"{self.name}: law returned a non-finite force {force}.")
        return force

    def linear_gains(self) -> Gains | None:
        """The linear spring's gains; None with a law (not a linear element)."""
        return SpringDamper.linear_gains(self) if self.law is None else None

    def traced_wrench(self, slots, position: tuple, velocity: tuple, time: object) -> list:
        """The linear spring's wrench on traced values (a law is not lowered).

        Raises:
            TraceError: The spring has a law.
        """
        if self.law is not None:
            raise TraceError(f"{self.name}: a spring's law is Python: it is not lowered.")
        return SpringDamper.traced_wrench(self, slots, position, velocity, time)

    def _parameters(self) -> str:
        if self.law is None:
            return super()._parameters()
        law = getattr(self.law, "__name__", type(self.law).__name__)
        return f"law={law}, setpoint={self._setpoint.tolist()}"


class Damper(SpringDamper):
    """A linear damper: ``damping (velocity_setpoint - velocity)``.

    Args:
        axes: Axes the damper acts on.
        damping: [N s/m or N m s/rad], >= 0.
        velocity_setpoint: Velocity of the damper's other end [m/s or rad/s].
        name: Label used in reports.

    Raises:
        InvalidAxisError: Bad axes.
        InvalidInputError: Bad parameter shape or value.
    """

    def __init__(
        self,
        axes: Sequence[str],
        damping: Vector,
        velocity_setpoint: Vector = 0.0,
        name: str | None = None,
    ) -> None:
        super().__init__(axes, damping=damping, velocity_setpoint=velocity_setpoint, name=name)


class ConstantForce(SpringDamper):
    """A constant wrench (a thruster, or a feed-forward such as the robot's weight).

    Args:
        axes: Axes the force acts on.
        force: [N or N m].
        name: Label used in reports.

    Raises:
        InvalidAxisError: Bad axes.
        InvalidInputError: Bad parameter shape or value.
    """

    def __init__(self, axes: Sequence[str], force: Vector, name: str | None = None) -> None:
        super().__init__(axes, force=force, name=name)


class Inertance(Component):
    """``wrench = -inertance * filtered d(velocity)/dt`` on each axis.

    Args:
        axes: Axes the component acts on.
        inertance: Per axis or scalar, >= 0 [kg or kg m^2].
        time_constant: Of the low-pass filter on the acceleration [s] (0: raw differences).
        name: Label used in reports.

    Raises:
        InvalidAxisError: Bad axes.
        InvalidInputError: A negative or non-finite inertance or time constant.

    Note:
        Keeps the last velocity and acceleration: one instance per controller, called once per
        tick with increasing times; [`reset`][] forgets them.
    """

    def __init__(
        self,
        axes: Sequence[str],
        inertance: float | Sequence[float] | np.ndarray,
        time_constant: float = 0.005,
        name: str | None = None,
    ) -> None:
        super().__init__(axes, name)
        self.inertance = self._non_negative(inertance, "inertance")
        self.time_constant = check_number(
            time_constant, f"{self.name}: time_constant [s]", minimum=0.0
        )
        self._last: tuple[float, np.ndarray] | None = None
        self.acceleration = np.zeros(len(self.axes))  # filtered estimate [m/s^2 or rad/s^2]

    def reset(self, position: np.ndarray, time: float) -> None:
        """Forget the velocity history (the next tick starts a new estimate)."""
        self._last = None
        self.acceleration = np.zeros(len(self.axes))

    def compute_wrench(self, position: np.ndarray, velocity: np.ndarray, time: float) -> np.ndarray:
        """``-inertance * acceleration``, the acceleration filtered from velocity differences."""
        velocity = np.array(velocity, dtype=float)
        if self._last is not None:
            last_time, last_velocity = self._last
            dt = time - last_time
            if dt > 0.0:
                raw = (velocity - last_velocity) / dt
                blend = 1.0 if self.time_constant == 0.0 else -math.expm1(-dt / self.time_constant)
                self.acceleration = self.acceleration + blend * (raw - self.acceleration)
        if self._last is None or time > self._last[0]:
            self._last = (time, velocity)
        return -self.inertance * self.acceleration

    def _parameters(self) -> str:
        return f"inertance={self.inertance.tolist()}, time_constant={self.time_constant}"
