"""A spring-damper attachment's one-call tick (``control/attachment_kernel.py``).

The tick senses {B} relative to {A}, sums the spring-dampers' wrenches and, for a serial
actuator that is its own sensor, computes the efforts ``J^T w`` in one compiled call (a parallel
actuator's wrench goes to its distribution). Tested here:

- a parallel attachment's tick against the general path: the same readings, wrench and
  efforts, bit for bit;
- the tick (``_core.SpringTick``) against the controller's general path on solo12 legs, the
  flamingo's planar swing leg with its pitch axis and a UR5 tool with one rotational axis,
  saturating springs and wrapped angles (the same sensor readings and wrench bits,
  the efforts to round-off: the general path lets numpy's ``J.T @ w`` round its own way);
- the efforts against an independent oracle: RNEA with the wrench on {B} and its reaction on {A};
- the cases it hands to the general path (a wrapped angle, an overflowing wrench, a spring law, a
  subclass with its own wrench, components changed after ``add``).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from oracles import external_forces, random_configuration, requires_core, rnea_torques

import virtual_actuators as va
from virtual_actuators.control.attachment_kernel import SpringTick
from virtual_actuators.core import CORE

pytestmark = requires_core  # the one-call tick is the compiled core's

#: (robot, action, reaction, axes) of the serial actuators the tick serves
CASES = {
    "solo12_leg": ("solo12", "FL_FOOT", "base_link", ("x", "y", "z")),
    "solo12_hind": ("solo12", "HR_FOOT", "base_link", ("x", "z")),
    "flamingo_swing": ("spring_flamingo", "left_foot", "body", ("x", "z", "ry")),
    "ur5_tool": ("ur5", "tool0", "world", ("x", "y", "z", "rz")),
}



def _buffer(tick, components, snapshot, time):
    """The spring tick's buffer without a distribution (None: the general path runs)."""
    return tick.run_solve(components, snapshot, time, solve=False)[0]

def _controller(case: str, spring: va.SpringDamper | None = None):
    name, action, reaction, axes = CASES[case]
    robot = va.load_robot(name)
    actuator = va.VirtualActuator(robot, action, reaction, "world", axes)
    spring = spring or va.SpringDamper(axes, 300.0, 12.0, name="spring")
    controller = va.Controller(robot, clip=False)
    attachment = controller.add("leg", actuator, [spring])
    return robot, controller, attachment, spring


def _states(robot, spring, rng, count=12):
    """Random states and spring parameters (some saturating, some far from the set point)."""
    n = len(spring.axes)
    for k in range(count):
        q = random_configuration(robot, rng, scale=1.0)
        v = rng.normal(size=robot.model.nv)
        spring.stiffness = rng.uniform(0.0, 500.0, n)
        spring.damping = rng.uniform(0.0, 20.0, n)
        spring.setpoint = rng.normal(scale=0.3 if k % 4 else 4.0, size=n)  # some wrap
        spring.velocity_setpoint = rng.normal(size=n)
        spring.force = rng.normal(scale=5.0, size=n)
        spring.limit = np.where(rng.random(n) < 0.5, rng.uniform(0.1, 20.0, n), np.inf)
        yield q, v


@pytest.mark.skipif(CORE is None, reason="virtual_actuators._core is not built")
@pytest.mark.filterwarnings("ignore:overflow encountered")  # the general path's overflow
def test_an_overflowing_wrench_is_handed_to_the_general_path_which_names_it():
    robot, controller, attachment, spring = _controller("ur5_tool")
    rng = np.random.default_rng(11)
    q, v = next(_states(robot, spring, rng, count=1))
    snapshot = va.Snapshot(robot, q, v)
    assert _buffer(attachment.spring_tick, attachment.components, snapshot, 0.0) is not None
    spring.stiffness, spring.setpoint, spring.limit = 1e308, 1e10, np.inf  # overflows
    assert _buffer(attachment.spring_tick, attachment.components, snapshot, 0.0) is None
    with pytest.raises(va.InvalidInputError, match="non-finite"):
        controller.compute(q, v)


def _body(components, **options):
    """solo12's body on its four feet, with ``components``, and the same on the general path."""
    robot = va.load_robot("solo12")
    feet = ["FL_FOOT", "FR_FOOT", "HL_FOOT", "HR_FOOT"]
    axes = ("x", "y", "z", "rx", "ry", "rz")
    actuator = va.ParallelVirtualActuator(robot, "base_link", feet, "world", axes)
    controllers = []
    for _ in range(2):
        controller = va.Controller(robot, clip=False)
        controller.add("body", actuator, components, **options)
        controllers.append(controller)
    controllers[1].attachments["body"].spring_tick = None  # the general path
    return robot, *controllers


@pytest.mark.parametrize("overlap", [False, True])
def test_parallel_tick_agrees_with_the_general_path_bit_for_bit(overlap):
    height = va.SpringDamper(("z",), 800.0, 40.0, setpoint=0.3, force=20.0, name="height")
    level = va.SpringDamper(("ry",), 30.0, 2.0, limit=1.0, name="level")
    heading = va.SpringDamper(("rz",), 20.0, 1.0, setpoint=0.2, name="heading")
    bunny = va.DogtrackBunny(0.4, 60.0, stiffness=5.0, limit=25.0)
    components = [height, level, heading, bunny]
    if overlap:  # two on z: summed in order, from 0.0
        components.append(va.SpringDamper(("z",), 100.0, 3.0, setpoint=0.25, name="more"))
    robot, tick, general = _body(components)
    assert tick.attachments["body"].spring_tick is not None
    rng = np.random.default_rng(4)
    ran = 0
    for k in range(10):
        q = random_configuration(robot, rng, scale=0.3)
        v = rng.normal(size=robot.model.nv)
        time = 0.1 * k
        snapshot = va.Snapshot(robot, q, v)
        ran += _buffer(tick.attachments["body"].spring_tick, components, snapshot, time) is not None
        out, expected = tick.compute(snapshot, time=time), general.compute(snapshot, time=time)
        for field in ("positions", "velocities", "wrenches", "produced"):
            assert np.array_equal(getattr(out, field)["body"], getattr(expected, field)["body"])
        assert np.array_equal(out.tau, expected.tau)
    assert ran == 10
    assert bunny.setpoint[0] == bunny.position_at(0.9)


@pytest.mark.parametrize("case", sorted(CASES))
def test_tick_agrees_with_the_general_path(case):
    robot, controller, attachment, spring = _controller(case)
    _, general, plain, plain_spring = _controller(case)
    plain.spring_tick = None  # the controller's general path
    rng = np.random.default_rng(5)
    ran = 0
    for q, v in _states(robot, spring, rng):
        for field in ("stiffness", "damping", "setpoint", "velocity_setpoint", "force", "limit"):
            setattr(plain_spring, field, getattr(spring, field))
        snapshot = va.Snapshot(robot, q, v)
        ran += _buffer(attachment.spring_tick, attachment.components, snapshot, 0.0) is not None
        out, expected = controller.compute(q, v), general.compute(q, v)
        for field in ("positions", "velocities", "wrenches", "produced"):
            assert np.array_equal(getattr(out, field)["leg"], getattr(expected, field)["leg"])
        scale = np.abs(expected.tau).max() + 1.0
        np.testing.assert_allclose(out.tau, expected.tau, rtol=0.0, atol=1e-13 * scale)
    assert ran >= 6  # most states ran the one-call tick


@pytest.mark.parametrize("case", ["solo12_leg", "ur5_tool"])
def test_efforts_balance_the_wrench_pair_rnea(case):
    """``tau`` from the tick equals RNEA's torques for +w on {B} and -w on {A} (no gravity)."""
    name, action, reaction, axes = CASES[case]
    robot, controller, attachment, spring = _controller(case)
    rng = np.random.default_rng(2)
    for q, v in _states(robot, spring, rng, count=6):
        out = controller.compute(q, v)
        wrench = out.wrenches["leg"]
        fext = external_forces(robot.model, q, [(action, reaction, "world", axes, wrench)])
        expected = rnea_torques(name, q, fext)
        np.testing.assert_allclose(out.tau, expected, atol=1e-9 * (1 + np.abs(wrench).max()))


def test_serial_tick_of_several_springs_agrees_with_the_general_path():
    """A tool held by a position spring and a heading spring: one call, the same readings and
    wrench bits, the efforts to round-off (``J^T w`` summed in order, not numpy's matmul)."""
    robot = va.load_robot("ur5")
    axes = ("x", "y", "z", "rz")
    tool = va.VirtualActuator(robot, "tool0", "world", "world", axes)
    springs = [
        va.SpringDamper(("x", "y", "z"), 300.0, 10.0, setpoint=(0.3, 0.1, 0.4), limit=50.0),
        va.SpringDamper(("rz",), 20.0, 1.0, setpoint=0.5, force=0.2),
    ]
    controllers = []
    for _ in range(2):
        controller = va.Controller(robot, clip=False)
        controller.add("tool", tool, springs)
        controllers.append(controller)
    tick, general = controllers
    assert tick.attachments["tool"].spring_tick.efforts
    general.attachments["tool"].spring_tick = None
    rng = np.random.default_rng(6)
    for _ in range(8):
        q = random_configuration(robot, rng, scale=0.8)
        v = rng.normal(size=robot.model.nv)
        out, expected = tick.compute(q, v), general.compute(q, v)
        for field in ("positions", "velocities", "wrenches", "produced"):
            assert np.array_equal(getattr(out, field)["tool"], getattr(expected, field)["tool"])
        scale = np.abs(expected.tau).max() + 1.0
        np.testing.assert_allclose(out.tau, expected.tau, rtol=0.0, atol=1e-13 * scale)


def test_warm_up_runs_the_tick_and_moves_no_set_point(monkeypatch):
    height = va.SpringDamper(("z",), 800.0, 40.0, setpoint=0.3)
    bunny = va.DogtrackBunny(0.4, 60.0)
    robot, controller, _ = _body([height, bunny])
    calls = []
    original = SpringTick.warm_up
    monkeypatch.setattr(SpringTick, "warm_up", lambda self, s: calls.append(original(self, s)))
    before = bunny.setpoint.copy()
    controller.warm_up(robot.neutral())
    assert len(calls) == 1 and np.array_equal(bunny.setpoint, before)


def test_the_general_path_takes_what_the_tick_hands_back():
    robot, controller, attachment, spring = _controller("flamingo_swing")
    q, v = robot.neutral(), np.zeros(robot.model.nv)
    snapshot = va.Snapshot(robot, q, v)
    tick = attachment.spring_tick
    assert _buffer(tick, attachment.components, snapshot, 0.0) is not None
    spring.setpoint = (0.0, 0.0, 7.0)  # pitch difference beyond pi: the float path wraps it
    assert _buffer(tick, attachment.components, snapshot, 0.0) is None
    out = controller.compute(q, v)
    wrapped = math.remainder(7.0 - out.positions["leg"][2], math.tau)  # the float path's wrap
    assert out.wrenches["leg"][2] == pytest.approx(300.0 * wrapped, rel=1e-12)
    other = va.SpringDamper(("x", "z", "ry"), 50.0)
    attachment.components[0] = other  # replaced after add: the general path reads it
    assert _buffer(tick, attachment.components, snapshot, 0.0) is None
    assert controller.compute(q, v).wrenches["leg"][0] == -50.0 * out.positions["leg"][0]


def test_laws_and_own_wrenches_take_the_general_path():
    law = va.Spring(("x", "y", "z"), law=lambda d: 100.0 * d**3)
    robot, controller, attachment, _ = _controller("solo12_leg", law)
    snapshot = va.Snapshot(robot, robot.neutral(), np.zeros(robot.model.nv))
    assert _buffer(attachment.spring_tick, attachment.components, snapshot, 0.0) is None  # law set

    class Doubled(va.SpringDamper):
        def compute_wrench(self, position, velocity, time):
            return 2.0 * super().compute_wrench(position, velocity, time)

    _, _, own, _ = _controller("solo12_leg", Doubled(("x", "y", "z"), 100.0))
    assert own.spring_tick is None
    _, _, three, _ = _controller("ur5_tool", va.SpringDamper(("x", "y", "z", "rz"), 10.0))
    assert three.spring_tick is not None
    arm = va.VirtualActuator(robot, "FL_FOOT", "base_link", "world", ("rx", "ry", "rz"))
    whole = [slice(0, 3)]
    assert SpringTick.of(arm, arm, [va.SpringDamper(("rx", "ry", "rz"), 1.0)], whole) is None
    other = va.VirtualActuator(robot, "FL_FOOT", "world", "world", ("rx", "ry", "rz"))
    assert SpringTick.of(arm, other, [va.SpringDamper(("rx",), 1.0)], [slice(0, 1)]) is None
    gathered = [np.array([0, 2])]  # axes not a contiguous run
    assert SpringTick.of(arm, arm, [va.SpringDamper(("rx", "rz"), 1.0)], gathered) is None


@pytest.mark.skipif(CORE is None, reason="virtual_actuators._core is not built")
def test_bad_tables_are_refused_not_read():
    _, _, attachment, spring = _controller("solo12_leg")
    tick = attachment.spring_tick
    axis_rows, rows, columns, signs, targets, rotations, summed, efforts = tick.tables
    tables = (axis_rows, rows, columns, signs, targets, rotations, summed, efforts)
    CORE.SpringTick(*tables, tick.nv)  # accepted
    with pytest.raises(ValueError, match="columns"):
        CORE.SpringTick(*tables, 2)
    with pytest.raises(ValueError, match="axis_rows"):
        CORE.SpringTick(axis_rows[::-1].copy(), *tables[1:], tick.nv)
    with pytest.raises(ValueError, match="signs"):
        CORE.SpringTick(*tables[:3], signs[:-1].copy(), *tables[4:], tick.nv)
    with pytest.raises(ValueError, match="targets"):
        CORE.SpringTick(*tables[:4], targets + 3, *tables[5:], tick.nv)
    with pytest.raises(ValueError, match="rotations"):
        CORE.SpringTick(*tables[:5], rotations + 2, *tables[6:], tick.nv)
    with pytest.raises(ValueError, match="one entry per axis"):
        CORE.SpringTick(*tables[:4], targets[:2].copy(), rotations[:2].copy(), 0, 1, tick.nv)
    jacobian, frames, v = np.zeros((6, tick.nv)), np.zeros((1, 12)), np.zeros(tick.nv)
    parameters = [np.zeros(3)] * 6
    with pytest.raises(ValueError, match="frames"):
        tick.core.tick(jacobian, frames, v, parameters)
    with pytest.raises(ValueError, match="one per axis"):
        tick.core.tick(jacobian, np.zeros((40, 12)), v, [*parameters[:5], np.zeros(2)])
    with pytest.raises(ValueError, match="six arrays"):
        tick.core.tick(jacobian, np.zeros((40, 12)), v, parameters[:5])
    with pytest.raises(ValueError, match="one entry per table entry"):
        tick.core.tick(jacobian, np.zeros((40, 12)), v, [np.zeros(2)] * 6)
