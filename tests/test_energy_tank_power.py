"""The energy tank's power at extreme magnitudes, in exact rational arithmetic (issue 35).

An empty tank (or any tank on its first tick, whose duration is unknown) lets through no power:
the exact ``wrench . velocity`` of what it returns is never positive, for any finite velocity
and wrench, from subnormal to near the float range (|v| = 1e160 once let 4e144 W through, the
rounding of a projection). A tank that pays lets through at most the energy it held.
"""

from __future__ import annotations

import math
import warnings
from fractions import Fraction

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

import virtual_actuators as va
from virtual_actuators.components.energy_tank import EnergyTank


class Constant(va.Component):
    """A constant wrench on ``n`` axes."""

    AXES = ("x", "y", "z", "rx", "ry", "rz")

    def __init__(self, wrench: list[float]) -> None:
        super().__init__(self.AXES[: len(wrench)])
        self.wrench = np.array(wrench, dtype=float)

    def compute_wrench(self, position, velocity, time):
        return self.wrench.copy()


def exact_power(wrench: np.ndarray, velocity: list[float]) -> Fraction:
    """``wrench . velocity`` [W] without rounding."""
    return sum(
        (Fraction(w) * Fraction(v) for w, v in zip(wrench.tolist(), velocity, strict=True)),
        start=Fraction(0),
    )


def signed(mantissa: float, exponent: int) -> float:
    """``mantissa * 10**exponent`` (down to subnormal sizes, 1e-320)."""
    return (
        mantissa * 1e-300 * 10.0 ** (exponent + 300)
        if exponent < -300
        else mantissa * 10.0**exponent
    )


#: Finite floats of either sign from 1e-320 to 1e307, and zero.
MAGNITUDES = st.one_of(
    st.just(0.0), st.builds(signed, st.floats(-9.99, 9.99), st.integers(-320, 306))
)

VECTORS = st.integers(1, 6).flatmap(
    lambda n: st.tuples(*[st.lists(MAGNITUDES, min_size=n, max_size=n)] * 2)
)


@settings(max_examples=300, deadline=None)
@given(VECTORS, st.sampled_from([0.0, 1e-300, 1e-3, 1.0, 1e300]), st.sampled_from([1e-3, 1e-9]))
def test_the_tank_never_lets_through_power_it_does_not_hold(vectors, initial, dt):
    velocity, wrench = vectors
    tank = EnergyTank(Constant(wrench), capacity=max(initial, 1.0), initial=initial)
    for tick in range(3):
        held = tank.energy
        with warnings.catch_warnings():
            warnings.simplefilter("error")  # no overflow, underflow or invalid-value warning
            out = tank.compute_wrench(np.zeros(len(wrench)), np.array(velocity), tick * dt)
        assert np.all(np.isfinite(out))
        assert 0.0 <= tank.energy <= tank.capacity
        power = exact_power(out, velocity)
        if tick == 0 or held == 0.0:
            assert power <= 0, (tick, float(power))  # nothing on a first tick or from empty
        else:
            assert power * Fraction(dt) <= Fraction(held), (tick, float(power), held)


def test_the_issues_case_at_1e160():
    """|v| = 1e160 and an empty tank: the returned wrench injects no power (was 4e144 W)."""
    rng = np.random.default_rng(0)
    for _ in range(200):
        velocity = (1e160 * rng.standard_normal(3)).tolist()
        tank = EnergyTank(Constant(rng.standard_normal(3).tolist()), capacity=1.0, initial=0.0)
        for tick in range(2):
            out = tank.compute_wrench(np.zeros(3), np.array(velocity), tick * 1e-3)
            assert exact_power(out, velocity) <= 0
            assert math.isfinite(float(out @ np.array(velocity)))
