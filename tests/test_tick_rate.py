"""The per-tick rate of springs and dampers (control.tick_rate), against MuJoCo's own dynamics.

A damper held over a control period multiplies the velocity error of its fastest direction by
``1 - rate`` per tick: the oracle runs the controller in MuJoCo (zero gravity, one period of
efforts held, as the walks do) from a perturbed velocity and reads that factor off the
simulated velocities.
"""

from __future__ import annotations

import numpy as np
import pytest

import virtual_actuators as va
from virtual_actuators.components.gains import Gains
from virtual_actuators.control.tick_rate import RATE_LIMIT, bound_tick_rate, tick_rate
from virtual_actuators.gaits.legged.body import BodyModel
from virtual_actuators.kinematics.snapshot import Snapshot

PERIOD = 1e-3  # [s]


@pytest.fixture(scope="module")
def ur5():
    return va.load_robot("ur5")


def _arm_controller(robot, damping: float, tool: float):
    controller = va.Controller(robot, clip=False)
    joints = [robot.model.names[j] for j in range(1, robot.model.njoints)]
    controller.add("hold", va.Posture(joints, 0.0, damping))
    tcp = va.VirtualActuator(robot, "tool0", "world", "world", ("x", "y", "z"))
    controller.add("tool", tcp, [va.Damper(("x", "y", "z"), tool)])
    return controller


def _measured_factor(robot, controller, q, direction, ticks=8) -> float:
    """The per-tick factor of the velocity's decay in MuJoCo, from ``direction`` (joint space)."""
    pytest.importorskip("mujoco")
    from virtual_actuators.simulation import Simulator

    simulator = Simulator(robot)
    simulator.model.opt.gravity[:] = 0.0
    simulator.reset(q, 1e-3 * direction / np.linalg.norm(direction))
    speeds = []
    for _ in range(ticks):
        v = simulator.v
        speeds.append(np.linalg.norm(v) * np.sign(v @ direction))
        simulator.step(controller.compute(simulator.q, v, simulator.time).tau)
    speeds = np.array(speeds)
    return float(np.median(speeds[2:] / speeds[1:-1]))


@pytest.mark.parametrize("damping, tool", [(2.0, 0.0), (0.0, 150.0), (1.5, 120.0)])
def test_the_rate_is_the_factor_mujoco_decays_the_fastest_direction_by(ur5, damping, tool):
    controller = _arm_controller(ur5, damping, tool)
    q = np.array([0.3, -1.2, 1.4, -0.8, 1.1, 0.2])
    rate = tick_rate(controller, q, period=PERIOD)
    # the fastest direction in joint space: the mobility times the rows of the top entry mix
    model, data = ur5.model, ur5.model.createData()
    import pinocchio as pin

    mass = pin.crba(model, data, q)
    mass = np.triu(mass) + np.triu(mass, 1).T
    rows = np.vstack([np.eye(6), controller.attachments["tool"].sensor.jacobian(Snapshot(ur5, q))])
    gain = np.r_[np.full(6, damping), np.full(3, tool)]
    damping_matrix = rows.T @ np.diag(gain) @ rows
    values, vectors = np.linalg.eig(PERIOD * np.linalg.solve(mass, damping_matrix))
    top = np.argmax(values.real)
    assert rate.rate == pytest.approx(values.real[top], rel=1e-9)  # an independent eigenproblem
    factor = _measured_factor(ur5, controller, q, vectors[:, top].real)
    assert factor == pytest.approx(1.0 - rate.rate, abs=0.03 * max(1.0, rate.rate))


def test_above_one_the_velocity_alternates_tick_to_tick(ur5):
    controller = _arm_controller(ur5, 0.0, 5000.0)
    q = np.array([0.3, -1.2, 1.4, -0.8, 1.1, 0.2])
    rate = tick_rate(controller, q, period=PERIOD)
    assert rate.rate > 1.2 and rate.dominant(1)[0][0].startswith("tool.")
    model, data = ur5.model, ur5.model.createData()
    import pinocchio as pin

    mass = pin.crba(model, data, q)
    jacobian = controller.attachments["tool"].sensor.jacobian(q)
    values, vectors = np.linalg.eig(
        PERIOD * 5000.0 * np.linalg.solve(np.triu(mass) + np.triu(mass, 1).T, jacobian.T @ jacobian)
    )
    factor = _measured_factor(ur5, controller, q, vectors[:, np.argmax(values.real)].real)
    assert factor < -0.1  # the sign flips every tick


def test_the_support_held_removes_its_motions():
    robot = va.load_robot("solo12")
    walker = va.LeggedWalker(robot)
    q = walker.initial_configuration()
    free = tick_rate(walker.controller, q, ["support_all"], (), PERIOD)
    held = tick_rate(walker.controller, q, ["support_all"], walker.feet, PERIOD)
    assert held.rate <= free.rate + 1e-12
    assert set(held.labels) == {f"support_all.{axis}" for axis in ("x", "y", "z", "rx", "ry", "rz")}
    assert held.participation.sum() == pytest.approx(1.0)


@pytest.mark.parametrize("name", ["anymal", "go2", "hyq"])
def test_the_walker_bounds_every_state_and_keeps_what_is_not_fast(name):
    robot = va.load_robot(name)
    walker = va.LeggedWalker(robot)
    q = walker.initial_configuration()
    before = walker.tick_rates
    assert max(rate.rate for rate in before.values()) > 1.0  # the derived gains alternate
    for state in walker.machine.states:
        after = tick_rate(walker.controller, q, state.active, state.support, PERIOD)
        assert after.rate <= RATE_LIMIT * (1 + 1e-9), (state.name, str(after))
    derived, bounded = walker.gains, walker.body.gains
    # the heavy body directions (nearly) keep their gains, the light swing directions do not
    assert bounded.damping_xy == pytest.approx(derived.damping_xy, rel=0.02)
    assert min(walker.swing[f].damping.min() for f in walker.feet) < 0.5 * min(
        derived.swing_damping
    )
    for foot, stiffness in zip(walker.feet, derived.swing_stiffness, strict=True):
        spring = walker.swing[foot]
        assert (spring.stiffness <= stiffness + 1e-9).all() and (spring.stiffness > 0).all()
        # stiffness and damping scaled together: each axis keeps its ratio
        assert spring.damping / spring.stiffness == pytest.approx(
            np.full(3, walker.gains.swing_damping[0] / walker.gains.swing_stiffness[0]), rel=1e-9
        )


def test_the_balancer_bounds_a_light_pelvis_under_a_held_torso():
    from virtual_actuators.gaits.balance.balancer import Balancer

    balancer = Balancer(va.load_robot("g1"))
    labels = [label for label, _ in balancer.tick_rate.dominant(2)]
    assert balancer.tick_rate.rate > 2.0 and set(labels) == {"body.ry", "posture.waist_pitch_joint"}
    state = balancer.machine.states[0]
    after = tick_rate(balancer.controller, balancer.q0, state.active, state.support, PERIOD)
    assert after.rate <= RATE_LIMIT * (1 + 1e-9)


def test_gains_under_the_limit_are_left_alone(ur5):
    controller = _arm_controller(ur5, 0.5, 10.0)
    q = np.array([0.3, -1.2, 1.4, -0.8, 1.1, 0.2])
    (rate,) = bound_tick_rate(controller, q, [(None, ())], PERIOD)
    assert rate.rate < RATE_LIMIT
    assert (controller.postures["hold"].damping == 0.5).all()
    assert (controller.attachments["tool"].components[0].damping == 10.0).all()


def test_bad_arguments_name_what_is_wrong(ur5):
    controller = _arm_controller(ur5, 1.0, 1.0)
    q = ur5.neutral()
    with pytest.raises(va.InvalidInputError, match="period"):
        tick_rate(controller, q, period=0.0)
    with pytest.raises(va.InvalidInputError, match="below 1"):
        bound_tick_rate(controller, q, [(None, ())], PERIOD, limit=1.0)
    with pytest.raises(va.InvalidInputError, match="'hodl'"):
        tick_rate(controller, q, ["hodl"])
    with pytest.raises(va.InvalidInputError, match="6 finite numbers"):
        tick_rate(controller, q[:3])
    with pytest.raises(va.FrameNotFoundError, match="tool0"):
        tick_rate(controller, q, support=["tool_0"])


def test_components_report_and_scale_their_linear_gains():
    spring = va.SpringDamper(("x", "z"), (100.0, 200.0), (10.0, 20.0))
    spring.scale_gains(np.array([0.5, 1.0]))
    assert np.array_equal(spring.linear_gains().stiffness, [50.0, 200.0])
    assert np.array_equal(spring.linear_gains().damping, [5.0, 20.0])
    assert va.Spring("x", law=lambda d: d**3).linear_gains() is None
    with pytest.raises(va.InvalidInputError, match="gain factor"):
        spring.scale_gains(np.array([-1.0, 1.0]))
    posture = va.Posture(["a", "b"], 4.0, 2.0)
    posture.scale_gains(np.array([0.25, 1.0]))
    assert np.array_equal(posture.stiffness, [1.0, 4.0])
    assert np.array_equal(posture.damping, [0.5, 2.0])

    class Push(va.Component):
        def compute_wrench(self, position, velocity, time):
            return np.ones(len(self.axes))

    assert Push(("x",)).linear_gains() is None
    with pytest.raises(va.InvalidInputError, match="no gains"):
        Push(("x",)).scale_gains(np.ones(1))


def test_the_body_model_scales_each_axis():
    walker = va.LeggedWalker(va.load_robot("solo12"))
    body = BodyModel(2.5, walker.gains)
    gains = body.linear_gains()
    assert isinstance(gains, Gains) and gains.stiffness[[0, 1, 5]].tolist() == [0.0, 0.0, 0.0]
    body.scale_gains(np.array([1.0, 0.5, 1.0, 1.0, 0.25, 1.0]))
    scaled = body.linear_gains()
    assert scaled.damping[1] == pytest.approx(0.5 * gains.damping[1])
    assert scaled.stiffness[4] == pytest.approx(0.25 * gains.stiffness[4])
    assert scaled.damping[[0, 2, 3, 5]] == pytest.approx(gains.damping[[0, 2, 3, 5]])


def test_a_degree_of_freedom_without_inertia_is_fast_not_singular():
    """romeo's URDF leaves some bodies without inertia: its mass matrix is singular."""
    import pinocchio as pin

    from virtual_actuators.gaits.balance.balancer import Balancer

    robot = va.load_robot("romeo")
    mass = pin.crba(robot.model, robot.model.createData(), robot.neutral())
    assert np.linalg.matrix_rank(np.triu(mass) + np.triu(mass, 1).T) < robot.model.nv
    balancer = Balancer(robot)
    assert np.isfinite(balancer.tick_rate.rate)
    state = balancer.machine.states[0]
    after = tick_rate(balancer.controller, balancer.q0, state.active, state.support, PERIOD)
    assert after.rate <= RATE_LIMIT * (1 + 1e-9)
