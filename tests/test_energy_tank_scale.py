"""The energy tank at every scale of the velocity: the oracle is the energy balance, in exact
rational arithmetic (:class:`fractions.Fraction`), of the wrenches the tank returns.

Properties, tick by tick, for velocities from subnormal (1e-320) to near the float range (1e300):
the tank's energy stays in ``[0, capacity]``; the exact work of the returned wrench never exceeds
the energy the tank held (nothing on a first tick, nothing once it is empty); over a run the
injected work never exceeds the initial energy plus the dissipated work; the tank never counts
less injected energy than the wrenches really injected; no warning and no exception on the way.
The only tolerance is the rounding of the returned wrench itself, ``1e-14 |w| |v| dt`` per tick
(zero for a velocity along an axis, where removing the wrench along it is exact).
"""

from __future__ import annotations

import math
import warnings
from fractions import Fraction

import numpy as np
import pytest

import virtual_actuators as va
from virtual_actuators.components.energy_tank import EnergyTank

DT = 1e-3  # [s]
SCALES = [1e-320, 1e-300, 1e-200, 1e-163, 1e-100, 1.0, 1e100, 1e154, 1e160, 1e200, 1e300]


class Push(va.Component):
    """A constant force on x y z: injects energy while the velocity has a part along it."""

    def __init__(self, force: np.ndarray) -> None:
        super().__init__(("x", "y", "z"))
        self.force = np.asarray(force, dtype=float)

    def compute_wrench(self, position, velocity, time):
        return self.force.copy()


def exact_work(wrench: np.ndarray, velocity: np.ndarray, dt: float) -> Fraction:
    """``wrench . velocity dt`` [J] without rounding."""
    pairs = zip(wrench.tolist(), velocity.tolist(), strict=True)
    products = (Fraction(w) * Fraction(v) for w, v in pairs)
    return sum(products, start=Fraction(0)) * Fraction(dt)


def direction_of(velocity: np.ndarray) -> np.ndarray:
    """The unit vector along ``velocity`` (scaled first: subnormal entries keep their ratio)."""
    unit = velocity / np.max(np.abs(velocity))
    return unit / np.linalg.norm(unit)


def rounding(wrench: np.ndarray, velocity: np.ndarray, dt: float, exact_axis: bool) -> Fraction:
    """What rounding may inject or leave uncounted over one tick [J].

    The returned wrench is rounded to 1e-14 of its size along the velocity (not at all when the
    velocity lies along an axis), and an energy is counted to the float's resolution (the least
    subnormal number, 5e-324 J: a tick's work below it rounds to 0 J or to 5e-324 J).
    """
    resolution = 2 * Fraction(math.ulp(0.0))
    if exact_axis:
        return resolution
    largest = float(np.max(np.abs(velocity)))
    speed = Fraction(largest) * Fraction(float(np.linalg.norm(velocity / largest)))
    size = Fraction(float(np.linalg.norm(wrench)))
    return Fraction(1e-14) * size * speed * Fraction(dt) + resolution


def run(tank: EnergyTank, velocities: list[np.ndarray], exact_axis: bool = False) -> dict:
    """Tick the tank along ``velocities``; check the per-tick properties; return the totals."""
    start = Fraction(tank.energy)
    injected, dissipated, slack = Fraction(0), Fraction(0), Fraction(0)
    for k, velocity in enumerate(velocities):
        held = tank.energy
        with warnings.catch_warnings():
            warnings.simplefilter("error")  # no overflow, underflow or invalid-value warning
            wrench = tank.compute_wrench(np.zeros(3), velocity, k * DT)
        assert np.all(np.isfinite(wrench))
        assert 0.0 <= tank.energy <= tank.capacity
        work = exact_work(wrench, velocity, DT)
        allowed = rounding(wrench, velocity, DT, exact_axis)
        if k == 0 or held == 0.0:
            assert work <= allowed, (k, float(work))  # nothing on a first tick or from empty
        assert work <= Fraction(held) * (1 + Fraction(1, 10**12)) + allowed, (k, float(work))
        slack += allowed
        if work > 0:
            injected += work
        else:
            dissipated -= work
        # over the run: never more than the start plus what was dissipated
        assert injected <= start + dissipated + start / 10**12 + slack
        # the tank never counts less than was injected
        assert Fraction(tank.injected) >= injected * (1 - Fraction(1, 10**12)) - slack
    return {"injected": injected, "dissipated": dissipated}


@pytest.mark.parametrize("scale", SCALES, ids=[f"{s:g}" for s in SCALES])
def test_an_empty_tank_injects_nothing_at_any_speed(scale: float) -> None:
    """Initial energy 0: a force with a part along the velocity keeps only its orthogonal part."""
    rng = np.random.default_rng(7)
    force = np.array([2.0, -1.0, 0.5])
    velocities = [scale * (np.array([1.0, 0.3, -0.2]) + 0.1 * rng.standard_normal(3))] * 6
    tank = EnergyTank(Push(force), capacity=1.0, initial=0.0)
    run(tank, velocities)
    assert tank.energy == 0.0
    # the part removed lies along the velocity: the orthogonal part is what it was
    wrench = tank.compute_wrench(np.zeros(3), velocities[0], 6 * DT)
    direction = direction_of(velocities[0])
    removed = force - wrench
    assert np.linalg.norm(np.cross(removed, direction)) <= 1e-14 * np.linalg.norm(force)
    assert float(removed @ direction) == pytest.approx(float(force @ direction), rel=1e-14)


@pytest.mark.parametrize("scale", SCALES, ids=[f"{s:g}" for s in SCALES])
def test_a_full_tank_pays_at_most_what_it_holds_along_an_axis(scale: float) -> None:
    """Velocity along x (exact arithmetic): at most the 1 J it holds, then nothing."""
    tank = EnergyTank(Push(np.array([3.0, 1.0, -2.0])), capacity=1.0)
    velocities = [np.array([scale, 0.0, 0.0])] * 8
    totals = run(tank, velocities, exact_axis=True)
    assert totals["injected"] <= 1 + Fraction(1, 10**12)
    work_per_tick = 3.0 * scale * DT
    if 7 * work_per_tick > 1.0:  # enough work to drain it: empty at the end
        assert tank.energy == 0.0
    else:  # too little: every tick's work was paid, and counted
        assert float(totals["injected"]) == pytest.approx(7 * work_per_tick, rel=1e-12)
        assert tank.injected == pytest.approx(float(totals["injected"]), rel=1e-12)


@pytest.mark.parametrize("scale", SCALES, ids=[f"{s:g}" for s in SCALES])
def test_random_pushes_and_brakes_keep_the_balance(scale: float) -> None:
    """Forces along, against and across random velocities: the balance holds every tick."""
    rng = np.random.default_rng(11)
    for energy_scale in (1e-300, 1e-3, 1.0, 1e300):
        capacity = 2.0 * energy_scale
        tank = EnergyTank(Push(np.array([1.0, -2.0, 0.5]) * 1e-3), capacity, initial=energy_scale)
        velocities = [scale * rng.standard_normal(3) for _ in range(25)]
        run(tank, velocities)


def test_the_accounting_at_ordinary_scale_matches_the_exact_work() -> None:
    """At ordinary speeds the tank's injected and dissipated energies are the exact works."""
    rng = np.random.default_rng(3)
    tank = EnergyTank(Push(np.array([0.4, -0.2, 0.1])), capacity=1e-3, initial=5e-4)
    totals = run(tank, [rng.standard_normal(3) for _ in range(40)])
    assert tank.dissipated == pytest.approx(float(totals["dissipated"]), rel=1e-12)
    assert tank.injected == pytest.approx(float(totals["injected"]), rel=1e-12, abs=1e-18)


def test_a_damper_passes_through_unchanged_at_any_speed() -> None:
    for scale in SCALES:
        tank = EnergyTank(va.Damper(("x", "y", "z"), 3.0), capacity=1.0, initial=0.0)
        velocity = scale * np.array([1.0, -0.5, 0.25])
        for k in range(3):
            wrench = tank.compute_wrench(np.zeros(3), velocity, k * DT)
            assert np.array_equal(wrench, -3.0 * velocity)
            assert 0.0 <= tank.energy <= 1.0 and tank.injected == 0.0


def test_a_velocity_that_is_not_finite_or_the_wrong_size_is_refused() -> None:
    tank = EnergyTank(Push(np.ones(3)), capacity=1.0)
    for bad in (np.array([np.nan, 0.0, 0.0]), np.array([0.0, np.inf, 0.0])):
        with pytest.raises(va.InvalidInputError, match="velocity"):
            tank.compute_wrench(np.zeros(3), bad, 0.0)
    with pytest.raises(va.InvalidInputError, match="one per axis"):
        tank.compute_wrench(np.zeros(3), np.ones(2), 0.0)
