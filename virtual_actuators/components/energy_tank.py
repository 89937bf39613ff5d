"""An energy tank that keeps any component passive, its work checked exactly (in integers)."""

from __future__ import annotations

import math
import sys

import numpy as np

from ..exceptions import InvalidInputError
from ..vocabulary.arguments import check_number, describe
from .base import Component

#: The floats' relative rounding step.
_EPSILON = sys.float_info.epsilon


class EnergyTank(Component):
    """Wrap a component so that it never injects more energy than its tank holds.

    Args:
        component: The component to keep passive.
        capacity: Largest energy in the tank [J] (dissipated energy beyond it is lost).
        initial: Energy at the start [J] (None: ``capacity``).
        name: Label used in reports (None: ``tank(<component name>)``).

    Attributes:
        energy: Energy left in the tank [J].
        injected: Energy the component injected so far [J].
        dissipated: Energy it dissipated so far [J].

    Raises:
        InvalidInputError: ``component`` is not a [`Component`][], or ``capacity`` /
            ``initial`` is negative or not finite, or ``initial > capacity``.
    """

    def __init__(
        self,
        component: Component,
        capacity: float,
        initial: float | None = None,
        name: str | None = None,
    ) -> None:
        if not isinstance(component, Component):
            raise InvalidInputError(
                f"EnergyTank: component must be a va.Component, got {describe(component)}."
            )
        super().__init__(component.axes, name or f"tank({component.name})")
        self.component = component
        self.capacity = check_number(capacity, f"{self.name}: capacity [J]", minimum=0.0)
        start = self.capacity if initial is None else initial
        self.energy = check_number(start, f"{self.name}: initial [J]", minimum=0.0)
        if self.energy > self.capacity:
            raise InvalidInputError(
                f"{self.name}: initial energy {self.energy} J exceeds the capacity "
                f"{self.capacity} J."
            )
        self.injected = 0.0
        self.dissipated = 0.0
        self._last_time: float | None = None

    def reset(self, position: np.ndarray, time: float) -> None:
        """Reset the wrapped component; the tank keeps its energy."""
        self.component.reset(position, time)
        self._last_time = None

    def compute_wrench(self, position: np.ndarray, velocity: np.ndarray, time: float) -> np.ndarray:
        """The wrapped component's wrench, without its injecting part once the tank is empty.

        A non-finite wrench is returned as it is (the controller refuses it).

        Raises:
            InvalidInputError: If ``velocity`` does not have one entry per axis, or holds NaN or
                an infinity.
        """
        wrench = np.array(self.component.compute_wrench(position, velocity, time), dtype=float)
        values = np.asarray(velocity, dtype=float).reshape(-1).tolist()  # a few plain floats
        if len(values) != wrench.size:
            raise InvalidInputError(
                f"{self.name}: velocity has {len(values)} entries, expected one per axis "
                f"{self.axes}."
            )
        dt = 0.0 if self._last_time is None else max(time - self._last_time, 0.0)
        self._last_time = time
        if not all(map(math.isfinite, values)):
            raise InvalidInputError(f"{self.name}: velocity must be finite, got {values}.")
        forces = wrench.tolist()
        if not any(values) or not all(map(math.isfinite, forces)):
            return wrench  # no motion, no work; or a wrench the controller refuses
        power = _dot(forces, values)  # [W], exact
        allowed = _Allowance(0.0 if dt == 0.0 else self.energy, dt)
        if power[0] > 0 and not allowed.admits(power):
            # only what is left may be injected (nothing on a first tick): remove the excess
            forces = allowed.enforce(forces, values)
            work = self.energy if allowed.energy > 0.0 else 0.0  # [J], the tank empties
        else:
            work = _to_float(*_times(power, dt))  # [J], > 0: injected into the robot
        if work > 0.0:
            self.injected += work
            self.energy = max(self.energy - work, 0.0)
        else:
            self.dissipated -= work
            self.energy = min(self.energy - work, self.capacity)
        return np.array(forces)

    def _parameters(self) -> str:
        return (
            f"component={self.component.name!r}, energy={self.energy:.4g} J, "
            f"capacity={self.capacity:.4g} J"
        )


#: Most corrections of a wrench whose part along the velocity is removed
_CORRECTIONS = 60

Dyadic = tuple[int, int]  # n * 2**k, exactly


def _dyadic(value: float) -> Dyadic:
    """A finite float as ``(n, k)``: ``value == n * 2**k`` exactly."""
    numerator, denominator = value.as_integer_ratio()  # the denominator is a power of two
    return numerator, 1 - denominator.bit_length()


def _dot(a: list[float], b: list[float]) -> Dyadic:
    """``sum(a[i] * b[i])`` of finite floats, exactly."""
    terms = [
        (n1 * n2, k1 + k2)
        for (n1, k1), (n2, k2) in ((_dyadic(x), _dyadic(y)) for x, y in zip(a, b, strict=True))
        if n1 and n2
    ]
    if not terms:
        return 0, 0
    low = min(k for _, k in terms)
    return sum(n << (k - low) for n, k in terms), low


def _times(value: Dyadic, factor: float) -> Dyadic:
    """``value * factor`` exactly."""
    n, k = _dyadic(factor)
    return value[0] * n, value[1] + k


def _to_float(n: int, k: int) -> float:
    """``n * 2**k`` as a float (to rounding): an infinity past the float range, 0 below it."""
    shift = max(abs(n).bit_length() - 62, 0)  # 62 bits round to a float's 53
    mantissa = float(abs(n) >> shift)
    return _ldexp(-mantissa if n < 0 else mantissa, k + shift)


def _ldexp(mantissa: float, exponent: int) -> float:
    """``mantissa * 2**exponent``: an infinity beyond the float range, 0 below it."""
    try:
        return math.ldexp(mantissa, exponent)
    except OverflowError:
        return math.copysign(math.inf, mantissa)


class _Allowance:
    """What a tank holding ``energy`` [J] lets a wrench inject over a tick of ``dt`` [s].

    The work may reach ``energy`` (none when the tank is empty or ``dt == 0``), compared exactly.
    """

    def __init__(self, energy: float, dt: float) -> None:
        self.energy = energy if dt > 0.0 else 0.0
        self.dt = dt

    def admits(self, power: Dyadic) -> bool:
        """Whether a power [W] is within the allowance (exactly)."""
        if self.energy == 0.0:
            return power[0] <= 0
        (work, k), (energy, j) = _times(power, self.dt), _dyadic(self.energy)
        low = min(k, j)
        return work << (k - low) <= energy << (j - low)

    def enforce(self, forces: list[float], values: list[float]) -> list[float]:
        """``forces`` less the least multiple of the velocity found that `admits` them.

        Projected in floats on the velocity scaled by a power of two, then corrected with a
        doubling margin until the exact check admits it; zero if none does.
        """
        scale = math.frexp(max(map(abs, values)))[1]
        unit = [math.ldexp(v, -scale) for v in values]  # the velocity / 2**scale
        norm = math.fsum(u * u for u in unit)  # in [0.25, len)
        largest = max(range(len(unit)), key=lambda i: abs(unit[i]))
        target = 0.0  # the power allowed, in the scaled velocity's units
        if self.energy > 0.0:
            (me, ee), (md, ed) = math.frexp(self.energy), math.frexp(self.dt)
            target = _ldexp(me / md, ee - ed - scale)
        margin = 0.0
        for _ in range(_CORRECTIONS):
            along = _to_float(*_dot(forces, unit))
            size = len(unit) * max(abs(f * u) for f, u in zip(forces, unit, strict=True))
            margin = max(2.0 * margin, _EPSILON * size)  # what rounding may have left, or more
            step = (max(along - target, 0.0) + margin) / norm
            moved = [f - step * u for f, u in zip(forces, unit, strict=True)]
            if moved == forces:  # the step is below the wrench's rounding: one unit in the last
                moved[largest] = math.nextafter(
                    forces[largest], -math.copysign(math.inf, unit[largest])
                )
            if not all(map(math.isfinite, moved)):
                break
            forces = moved
            if self.admits(_dot(forces, values)):
                return forces
        return [0.0] * len(forces)
