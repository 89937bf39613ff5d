"""Inertance and the energy tank: properties on a point mass integrated in the test."""

from __future__ import annotations

import numpy as np
import pytest

import virtual_actuators as va
from virtual_actuators.components.energy_tank import EnergyTank
from virtual_actuators.components.springs import Inertance


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


def test_spring_with_a_force_law():
    cubic = va.Spring(("x", "z"), setpoint=[0.1, 0.5], law=lambda d: 2000.0 * d**3)
    wrench = cubic.compute_wrench(np.array([0.0, 0.3]), np.zeros(2), 0.0)
    assert np.allclose(wrench, 2000.0 * np.array([0.1, 0.2]) ** 3)
    one_way = va.Spring(("z",), setpoint=0.2, law=lambda d: np.where(d > 0.0, 500.0 * d, 0.0))
    assert one_way.compute_wrench(np.array([0.1]), np.zeros(1), 0.0) == pytest.approx([50.0])
    assert one_way.compute_wrench(np.array([0.3]), np.zeros(1), 0.0) == pytest.approx([0.0])
    # a linear law equals the linear spring
    linear = va.Spring(("x", "z"), 300.0, setpoint=[0.1, 0.5])
    as_law = va.Spring(("x", "z"), setpoint=[0.1, 0.5], law=lambda d: 300.0 * d)
    position = np.array([0.04, 0.61])
    assert np.allclose(
        linear.compute_wrench(position, np.zeros(2), 0.0),
        as_law.compute_wrench(position, np.zeros(2), 0.0),
        rtol=1e-15,
    )
    assert "law=<lambda>" in repr(as_law)


def test_spring_law_errors():
    with pytest.raises(va.InvalidInputError, match="exactly one"):
        va.Spring(("x",))
    with pytest.raises(va.InvalidInputError, match="exactly one"):
        va.Spring(("x",), 100.0, law=lambda d: d)
    with pytest.raises(va.InvalidInputError, match="callable"):
        va.Spring(("x",), law="hard")
    wrong = va.Spring(("x", "z"), law=lambda d: [1.0, 2.0, 3.0])
    with pytest.raises(va.InvalidInputError, match="expected 2 numbers"):
        wrong.compute_wrench(np.zeros(2), np.zeros(2), 0.0)
    nan = va.Spring(("x",), law=lambda d: np.nan)
    with pytest.raises(va.InvalidInputError, match="non-finite"):
        nan.compute_wrench(np.zeros(1), np.zeros(1), 0.0)


def test_a_law_spring_in_a_controller_matches_rnea():
    import pinocchio as pin

    robot = va.load_robot("ur5")
    tool = va.VirtualActuator(robot, "tool0", "world", "world", ("x", "y", "z"))
    q = robot.q(shoulder_lift_joint=-1.0, elbow_joint=1.2)
    target = tool.position(q) + np.array([0.02, -0.01, 0.03])
    controller = va.Controller(robot, clip=False)
    controller.add(
        "tool",
        tool,
        [va.Spring(("x", "y", "z"), setpoint=target, law=lambda d: 1e4 * d * np.abs(d))],
    )
    tau = controller.compute(q, np.zeros(robot.model.nv), 0.0).tau
    deflection = target - tool.position(q)
    force = 1e4 * deflection * np.abs(deflection)  # [N] on tool0, world axes
    model = robot.model.copy()
    model.gravity.setZero()
    data = model.createData()
    pin.framesForwardKinematics(model, data, q)
    frame = model.frames[model.getFrameId("tool0")]
    fext = [pin.Force.Zero() for _ in range(model.njoints)]
    placement = data.oMi[frame.parentJoint]  # force at tool0's origin, in the joint frame
    lever = data.oMf[model.getFrameId("tool0")].translation - placement.translation
    world = pin.Force(force, np.cross(lever, force))
    fext[frame.parentJoint] = pin.Force(
        placement.rotation.T @ world.linear, placement.rotation.T @ world.angular
    )
    oracle = -pin.rnea(
        model, data, q, np.zeros(model.nv), np.zeros(model.nv), pin.StdVec_Force(fext)
    )
    assert np.allclose(tau, oracle, atol=1e-9 * np.abs(oracle).max())
