"""The base class of virtual components (VMC 2001, section 3): a sensor reading to a wrench."""

from __future__ import annotations

import math
from abc import ABC, abstractmethod
from collections.abc import Sequence

import numpy as np

from ..exceptions import InvalidInputError, TraceError
from ..vocabulary.arguments import as_float_array, check_name
from ..vocabulary.axes import parse_axes
from .gains import Gains

_REALS = frozenset((float, int, np.float64))  # list entries taken without conversion checks


class Component(ABC):
    """A virtual component acting on some axes of a virtual actuator.

    Args:
        axes: Ordered subset of ``("x", "y", "z", "rx", "ry", "rz")``, or one axis name.
        name: Label used in reports; defaults to the class name.

    Raises:
        InvalidAxisError: Bad axes.
        InvalidInputError: ``name`` is neither None nor a str.
    """

    def __init__(self, axes: Sequence[str], name: str | None = None) -> None:
        if name is not None:
            check_name(name, f"{type(self).__name__}: name")
        self.axes: tuple[str, ...] = parse_axes(axes, f"{type(self).__name__}: axes")
        self.name = name or type(self).__name__

    @abstractmethod
    def compute_wrench(self, position: np.ndarray, velocity: np.ndarray, time: float) -> np.ndarray:
        """Wrench on the action frame from the sensor reading on this component's axes.

        Args:
            position: Pose of {B} relative to {A} along ``self.axes`` [m, rad] (a rotation
                vector in {O}'s axes on rotational axes).
            velocity: Its rate [m/s, rad/s] (the angular velocity in {O}'s axes).
            time: Controller time [s].

        Returns:
            ``(len(self.axes),)`` forces [N] and moments [N m].
        """

    def plan_slots(self) -> dict[str, np.ndarray] | None:
        """The arrays a compiled plan keeps for this component, by name, or None (default).

        A component that returns slots implements `bind_slots` and `traced_wrench` (and
        `traced_reset` if it has a `reset`); None runs it as a Python piece.
        """
        return None

    def bind_slots(self, views: dict[str, np.ndarray]) -> None:
        """Keep the `plan_slots` in a compiled plan's registers (``views`` become the arrays).

        Raises:
            TraceError: The component has no slots (the default).
        """
        raise TraceError(f"{self.name}: {type(self).__name__} keeps no slots in a plan.")

    def traced_wrench(self, slots: object, position: tuple, velocity: tuple, time: object) -> list:
        """`compute_wrench` on traced values (a compiled plan's ops).

        Raises:
            TraceError: The component is not lowered (the default).
        """
        raise TraceError(f"{self.name}: {type(self).__name__} is not lowered into a plan.")

    def traced_reset(self, slots: object, position: tuple, time: object) -> None:  # noqa: B027
        """`reset` on traced values (default: nothing, as `reset`)."""

    def linear_gains(self) -> Gains | None:
        """The stiffness and damping per axis of a linear spring-damper, or None (default).

        A component that returns gains must implement [`scale_gains`][].
        """
        return None

    def scale_gains(self, factor: np.ndarray) -> None:
        """Multiply the stiffness and damping of each axis by ``factor`` (``(len(axes),)``).

        Raises:
            InvalidInputError: The component has no linear gains (``linear_gains()`` is None).
        """
        raise InvalidInputError(f"{self.name}: {type(self).__name__} has no gains to scale.")

    def reset(self, position: np.ndarray, time: float) -> None:  # noqa: B027 (optional hook)
        """Hook called when the component becomes active (a state is entered). Default: nothing.

        Args:
            position: Sensor reading on ``self.axes`` at activation [m, rad].
            time: Controller time [s].
        """

    def _per_axis(
        self, value: float | Sequence[float] | np.ndarray, what: str, allow_inf: bool = False
    ) -> np.ndarray:
        """Broadcast a scalar or per-axis parameter to ``(len(axes),)`` finite floats (a copy).

        Raises:
            InvalidInputError: ``value`` is not a real number or one per axis (None, a str, a
                dict, a bool, a complex number), or is NaN (or infinite unless ``allow_inf``).
        """
        try:
            fast = self._per_axis_fast(value, allow_inf)
            if fast is not None:
                return fast
            expected = f"a real number or one real number per axis {self.axes}"
            array = as_float_array(value, f"{self.name}: {what}", expected, copy=True)
        except OverflowError:  # an int beyond any float
            raise InvalidInputError(
                f"{self.name}: {what} holds a number too large for a float: {value!r:.80}."
            ) from None
        if array.ndim == 0:
            array = np.full(len(self.axes), float(array))
        if array.shape != (len(self.axes),):
            raise InvalidInputError(
                f"{self.name}: {what} must be a scalar or have one entry per axis "
                f"{self.axes}, got shape {array.shape}."
            )
        if np.isnan(array).any() or not (allow_inf or np.isfinite(array).all()):
            raise InvalidInputError(f"{self.name}: {what} must be finite, got {array}.")
        return array

    def _non_negative(self, value: object, what: str, allow_inf: bool = False) -> np.ndarray:
        """`_per_axis`, each entry >= 0 (an InvalidInputError naming ``what`` otherwise)."""
        array = self._per_axis(value, what, allow_inf)
        if np.any(array < 0.0):
            raise InvalidInputError(f"{self.name}: {what} must be >= 0, got {array}.")
        return array

    def _per_axis_fast(self, value: object, allow_inf: bool) -> np.ndarray | None:
        """`_per_axis` for the values a gait assigns every tick, or None for the rest.

        A plain float, a list or tuple of plain floats or ints, or a float64 array of the right
        shape whose sum is finite (not NaN, with ``allow_inf``) is taken as it is.
        """
        kind, size = type(value), len(self.axes)
        if kind is float or kind is int:
            number = float(value)
            if math.isfinite(number) or (allow_inf and number == number):
                return np.array((number,) * size)  # np.full costs twice as much
            return None
        if kind is tuple or kind is list:
            if len(value) != size or not _REALS.issuperset(map(type, value)):
                return None
            array = np.array(value, dtype=float)
            total = sum(value)  # NaN or inf if an entry is (or on overflow)
        elif kind is np.ndarray and value.dtype == np.float64 and value.shape == (size,):
            array = value.copy()
            total = sum(array.tolist())
        else:
            return None
        if math.isfinite(total) or (allow_inf and not np.isnan(array).any()):
            return array
        return None

    def _parameters(self) -> str:
        return ""

    def __repr__(self) -> str:
        extra = self._parameters()
        return f"{type(self).__name__}(axes={self.axes}{', ' + extra if extra else ''})"


def has_traced_path(component: object) -> bool:
    """Whether a compiled plan can trace ``component`` (its formula and its reset).

    A subclass that overrides only the Python method is not traced with its parent's formula.
    """
    if getattr(component, "plan_slots", lambda: None)() is None:
        return False
    for python, traced in (("compute_wrench", "traced_wrench"), ("reset", "traced_reset")):
        for klass in type(component).__mro__:
            if python in klass.__dict__:
                if traced not in klass.__dict__ and klass is not Component:
                    return False
                break
    return True
