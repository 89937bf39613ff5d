"""Inertance and the energy tank: properties on a point mass integrated in the test."""

from __future__ import annotations

import numpy as np
import pytest

import virtual_actuators as va
from virtual_actuators.components.energy_tank import EnergyTank
from virtual_actuators.components.inertance import Inertance


class Pump(va.Component):
    """A negative damper: pushes along the velocity (injects energy)."""

    def __init__(self, gain: float) -> None:
        super().__init__(("x",))
        self.gain = gain

    def compute_wrench(self, position, velocity, time):
        return self.gain * np.asarray(velocity, dtype=float)


def _simulate(component: va.Component, seconds: float, mass: float = 2.0, dt: float = 1e-3):
    """A point mass on x driven by the component; returns the kinetic energies [J]."""
    x, v = np.zeros(1), np.array([0.5])
    energies = []
    for k in range(int(seconds / dt)):
        force = component.compute_wrench(x, v, k * dt)
        v = v + dt * force / mass
        x = x + dt * v
        energies.append(0.5 * mass * float(v @ v))
    return np.array(energies)


def test_inertance_is_minus_mass_times_acceleration():
    inertance = Inertance(("x", "z"), [2.0, 3.0], time_constant=0.0)
    acceleration = np.array([1.5, -0.5])
    wrench = None
    for k in range(5):
        t = 0.001 * k
        wrench = inertance.compute_wrench(np.zeros(2), acceleration * t, t)
    assert np.allclose(wrench, -np.array([2.0, 3.0]) * acceleration, atol=1e-9)
    filtered = Inertance(("x",), 1.0, time_constant=0.01)
    for k in range(200):  # 20 time constants
        t = 0.001 * k
        wrench = filtered.compute_wrench(np.zeros(1), np.array([4.0 * t]), t)
    assert wrench == pytest.approx([-4.0], rel=1e-6)
    filtered.reset(np.zeros(1), 1.0)
    assert np.array_equal(filtered.compute_wrench(np.zeros(1), np.ones(1), 1.0), [0.0])


def test_inertance_rejects_bad_parameters():
    with pytest.raises(va.InvalidInputError, match="inertance"):
        Inertance(("x",), -1.0)
    with pytest.raises(va.InvalidInputError, match="time_constant"):
        Inertance(("x",), 1.0, time_constant=float("nan"))


def test_tank_bounds_the_energy_a_pump_injects():
    free = _simulate(Pump(4.0), 2.0)
    assert free[-1] > 100 * free[0]  # unbounded without the tank (e^(2 * 4 / 2 * 2))
    tank = EnergyTank(Pump(4.0), capacity=1.0)
    kept = _simulate(tank, 2.0)
    start = 0.5 * 2.0 * 0.25
    assert tank.injected == pytest.approx(1.0, rel=1e-12)  # all of it, never more
    assert tank.energy == pytest.approx(0.0, abs=1e-12)
    # the mass gained what the tank paid, up to explicit Euler's own gain (F^2 dt^2 / 2m a tick)
    assert kept.max() <= start + 1.0 + 1e-3
    assert kept[-1] == pytest.approx(kept[-100])  # empty tank: no more gain


def test_tank_passes_a_passive_component_through_and_refills():
    damper = va.Damper(("x",), 3.0)
    tank = EnergyTank(va.Damper(("x",), 3.0), capacity=5.0, initial=1.0)
    x, v = np.zeros(1), np.array([0.4])
    for k in range(50):
        assert np.array_equal(tank.compute_wrench(x, v, 1e-3 * k), damper.compute_wrench(x, v, 0))
    assert tank.injected == 0.0
    assert tank.energy == pytest.approx(1.0 + 49e-3 * 3.0 * 0.16)
    assert tank.dissipated == pytest.approx(49e-3 * 3.0 * 0.16)


def test_tank_rejects_bad_arguments():
    with pytest.raises(va.InvalidInputError, match="va.Component"):
        EnergyTank(lambda p, v, t: 0.0, 1.0)
    with pytest.raises(va.InvalidInputError, match="exceeds"):
        EnergyTank(Pump(1.0), capacity=1.0, initial=2.0)
    with pytest.raises(va.InvalidInputError, match="capacity"):
        EnergyTank(Pump(1.0), capacity=-1.0)
    assert "Pump" in repr(EnergyTank(Pump(1.0), 1.0))
