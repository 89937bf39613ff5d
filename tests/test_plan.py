"""The compiled machine (control.plan) against the same machine run in Python, tick by tick.

Two copies of one declaration: one runs as a `MachineController` in Python (the oracle), the
other is lowered and runs in the core. Both are fed the same states, from a MuJoCo run driven by
the Python copy's efforts; every tick's efforts, wrenches, readings and state agree.
"""

from __future__ import annotations

import numpy as np
import pytest

import virtual_actuators as va
from virtual_actuators.core import CORE

pytestmark = pytest.mark.skipif(
    CORE is None or not hasattr(CORE, "PlanMachine"), reason="no compiled core"
)


def _turkey(event=None, component=None, bunny=va.DogtrackBunny):
    """The docs' turkey machine (tutorials/bipeds.md): double support, then a right swing."""
    robot = va.load_robot("spring_turkey")
    double = va.ParallelVirtualActuator(
        robot, "body", ["left_foot", "right_foot"], "world", ("x", "z", "ry"), contact="point",
        design=[va.EqualTorque("left_hip", "right_hip")],
    )  # fmt: skip
    swing = va.VirtualActuator(robot, "right_foot", "body", "world", ("x", "z"))
    granny = va.GrannyWalker(height=0.54, stiffness=(1500, 200), damping=(150, 20), weight=98.1)
    bunny = bunny(speed=0.5, damping=80)
    controller = va.Controller(robot)
    controller.add("double", double, [granny, bunny], unilateral={"z": 10.0}, yield_axes=("x",))
    swinging = [va.SwingLegLinkage((400, 600), (20, 25))]
    if component is not None:
        swinging.append(component())
    controller.add("swing", swing, swinging)
    machine = va.StateMachine(
        states=[
            va.State("double_support", active=("double",), support=("left_foot", "right_foot")),
            va.State("right_swing", active=("double", "swing"), support=("left_foot",)),
        ],
        transitions=[
            va.Transition("double_support", "right_swing", event or va.events.after(0.2)),
            va.Transition("right_swing", "double_support", va.events.after(0.3)),
        ],
        initial="double_support",
    )
    return robot, va.MachineController(controller, machine)


def _compiled(machine):
    from virtual_actuators.control.plan.compiled import CompiledMachine

    return CompiledMachine(machine)


def _run_both(build, ticks=1200, contacts=None):
    """Tick both copies on the Python copy's own MuJoCo run; the worst relative difference."""
    from virtual_actuators.simulation import Simulator

    robot, python = build()
    _, twin = build()
    compiled = _compiled(twin)
    simulator = Simulator(robot)
    simulator.reset(robot.neutral())
    worst = 0.0
    for _ in range(ticks):
        q, v, time = simulator.q, simulator.v, simulator.time
        switches = None if contacts is None else contacts(simulator)
        expected = python.compute_in_python(q, v, time, switches)
        got = compiled.compute(q, v, time, switches)
        scale = max(1.0, np.abs(expected.tau).max())
        worst = max(worst, np.abs(expected.tau - got.tau).max() / scale)
        assert got.active == expected.active
        assert set(got.wrenches) == set(expected.wrenches)
        for name in expected.wrenches:
            assert np.array_equal(got.wrenches[name], expected.wrenches[name]), name
            assert np.array_equal(got.positions[name], expected.positions[name]), name
        simulator.step(expected.tau)
    assert python.machine.history == twin.machine.history
    return worst, compiled


def test_a_users_machine_runs_compiled_to_the_same_bits():
    worst, compiled = _run_both(_turkey)
    assert worst == 0.0
    assert compiled.pieces == []  # nothing of it runs in Python
    assert len(compiled.machine.machine.history) >= 4


def test_a_lambda_is_a_python_piece_of_the_same_tick():
    def build():
        return _turkey(event=lambda context: context.time_in_state >= 0.2)

    worst, compiled = _run_both(build)
    assert worst == 0.0
    assert [what for what, _ in compiled.pieces] == [
        "state 'double_support': the event <lambda>"
    ] or any("event" in what for what, _ in compiled.pieces)


class _Drag(va.Component):
    """A user's component (Python only): a drag on the swing foot."""

    def __init__(self) -> None:
        super().__init__(("x", "z"))

    def compute_wrench(self, position, velocity, time):
        return -3.0 * np.asarray(velocity)


def test_a_users_component_is_a_python_piece():
    worst, compiled = _run_both(lambda: _turkey(component=_Drag))
    assert worst < 1e-12
    assert any("Drag" in what for what, _ in compiled.pieces)


class _ClampedBunny(va.DogtrackBunny):
    """A bunny whose formula traces but whose reset holds a Python ``if`` (a Python piece)."""

    def reset(self, position, time):
        super().reset(max(float(np.asarray(position).reshape(-1)[0]), -1.0), time)

    def traced_reset(self, slots, position, time):
        if position[0] > -1.0:  # a Python `if` on a traced value: a TraceError
            slots.store("start", (position[0], time))


def test_a_component_whose_reset_cannot_trace_leaves_no_program_behind():
    """Its formula's traced program goes with the failed reset's: two Python pieces instead."""
    plain = _compiled(_turkey()[1])
    clamped = _compiled(_turkey(bunny=_ClampedBunny)[1])
    pieces = [what for what, _ in clamped.pieces]
    assert pieces == ["double: _ClampedBunny", "double: _ClampedBunny: reset"]
    programs = clamped.lowering.builder.programs
    assert len(programs) == len(plain.lowering.builder.programs)  # no orphan of the formula
    assert [p.index for p in programs] == list(range(len(programs)))
    worst, _ = _run_both(lambda: _turkey(bunny=_ClampedBunny))  # and it ticks as in Python
    assert worst < 1e-12


def test_the_plan_keeps_the_components_parameters_one_owner():
    robot, machine = _turkey()
    compiled = _compiled(machine)
    granny = machine.controller.attachments["double"].components[0]
    q, v = robot.neutral(), np.zeros(robot.model.nv)
    first = compiled.compute(q, v, 0.0).wrenches["double"].copy()
    granny.height = 0.60  # set in Python between ticks: the compiled tick reads it
    second = compiled.compute(q, v, 0.001).wrenches["double"]
    assert second[1] - first[1] == pytest.approx(1500 * 0.06, rel=1e-9)
    assert np.shares_memory(granny.setpoint, compiled.registers)
    assert machine.machine.current.name == "double_support"  # read from the plan's registers


def test_a_contact_switch_an_event_reads_must_be_given():
    def build():
        return _turkey(event=va.events.contact("left_foot"))

    robot, machine = build()
    compiled = _compiled(machine)
    q, v = robot.neutral(), np.zeros(robot.model.nv)
    with pytest.raises(va.InvalidInputError, match="left_foot"):
        compiled.compute(q, v, 0.0, {})
    output = compiled.compute(q, v, 0.0, {"left_foot": False})
    assert output.active == ("double",)
    output = compiled.compute(q, v, 0.001, {"left_foot": True})  # the switch closes: the swing
    assert output.active == ("double", "swing")
    assert machine.machine.current.name == "right_swing"


def test_joint_space_terms_posture_and_gravity_compiled():
    def build():
        robot = va.load_robot("ur5")
        controller = va.Controller(robot)
        joints = [robot.model.names[j] for j in range(1, robot.model.njoints)]
        controller.add("hold", va.Posture(joints, 40.0, 4.0))
        controller.add("gravity", va.GravityCompensation(robot))
        tool = va.VirtualActuator(robot, "tool0", "world", "world", ("x", "y", "z"))
        controller.add("tool", tool, [va.SpringDamper(("x", "y", "z"), 200.0, 20.0)])
        machine = va.StateMachine(
            [va.State("hold", ("hold", "gravity")), va.State("reach", ("tool", "gravity"))],
            [va.Transition("hold", "reach", va.events.after(0.3))],
            "hold",
        )
        return robot, va.MachineController(controller, machine)

    worst, compiled = _run_both(build, ticks=600)
    assert worst < 1e-12  # the core's gravity against Pinocchio's, in the Python tick
    assert compiled.pieces == []


def test_a_second_thread_in_a_tick_gets_a_typed_error():
    """One compiled machine, one run's registers: a tick entered while another thread's is
    running raises ConcurrentUseError (and leaves that tick and the next ones intact)."""
    import threading

    inside, release = threading.Event(), threading.Event()

    def blocking(context):  # a Python piece: the first thread waits in it
        if threading.current_thread() is not threading.main_thread():
            inside.set()
            release.wait(10.0)
        return False

    robot, machine = _turkey(event=blocking)
    compiled = _compiled(machine)
    q, v = robot.neutral(), np.zeros(robot.model.nv)
    outputs = []
    worker = threading.Thread(target=lambda: outputs.append(compiled.compute(q, v, 0.0)))
    worker.start()
    assert inside.wait(10.0)
    with pytest.raises(va.ConcurrentUseError, match="another thread"):
        compiled.compute(q, v, 0.0)
    release.set()
    worker.join(10.0)
    assert len(outputs) == 1 and np.all(np.isfinite(outputs[0].tau))
    assert np.all(np.isfinite(compiled.compute(q, v, 0.001).tau))  # the lock was released


def _bobbing(pitch=0.0):
    """A user's machine from the public classes only: solo12's body on a spring-damper on all six
    axes (an orientation set point pitched by ``pitch``), two states taking turns."""
    robot = va.load_robot("solo12")
    feet = ["FL_FOOT", "FR_FOOT", "HL_FOOT", "HR_FOOT"]
    body = va.ParallelVirtualActuator(robot, "base_link", feet, "world", contact="point")
    controller = va.Controller(robot, clip=True)
    for name, z in (("high", 0.24), ("low", 0.21)):
        spring = va.SpringDamper(body.axes, [600, 600, 900, 60, 60, 30], [40, 40, 60, 4, 4, 2],
                                 setpoint=[0, 0, z, 0.1, pitch, -0.2],
                                 force=[0, 0, robot.mass * 9.81, 0, 0, 0])  # fmt: skip
        controller.add(name, body, [spring])
    machine = va.StateMachine(
        states=[va.State("high", active=("high",), support=feet),
                va.State("low", active=("low",), support=feet)],
        transitions=[va.Transition("high", "low", va.events.after(0.3)),
                     va.Transition("low", "high", va.events.after(0.3))],
        initial="high",
    )  # fmt: skip
    return robot, va.MachineController(controller, machine)


@pytest.mark.parametrize("pitch", [0.0, 0.3])
def test_a_users_six_axis_body_spring_is_compiled_whole(pitch):
    """The orientation spring on three rotational axes (SO(3) deflection) is lowered: no Python
    piece, the Python machine's efforts to the bit."""
    worst, compiled = _run_both(lambda: _bobbing(pitch), ticks=800)
    assert compiled.pieces == []
    assert worst == 0.0


@pytest.mark.parametrize("name", ["talos", "solo12", "ur5", "anymal_kinova"])
def test_gravity_compensation_runs_in_the_core_as_pinocchio_computes_it(name):
    """The GRAVITY mapping (subtree masses and mass moments over the pass's Jacobian columns)
    against Pinocchio's computeGeneralizedGravity, on random configurations; on anymal_kinova
    only the arm's bodies on the arm's joints (links= and joints=)."""
    import pinocchio as pin

    from virtual_actuators.models.feet import find_feet
    from virtual_actuators.models.standing import upper_joints

    robot = va.load_robot(name)
    model = robot.model
    if name == "anymal_kinova":
        arm = upper_joints(robot, find_feet(robot).feet)
        gravity = va.GravityCompensation(robot, links=arm, joints=arm)
    else:
        gravity = va.GravityCompensation(robot)
    controller = va.Controller(robot, clip=False)
    controller.add("gravity", gravity)
    machine = va.MachineController(
        controller, va.StateMachine([va.State("hold", active=("gravity",))], [], "hold")
    )
    rng = np.random.default_rng(3)
    for k in range(12):
        q = pin.randomConfiguration(model, -np.ones(model.nq), np.ones(model.nq))
        if robot.floating_base:
            q[:3] = rng.normal(size=3)
        tau = machine.compute(q, np.zeros(model.nv), 0.001 * k).tau
        data = gravity.model.createData()
        expected = np.zeros(model.nv)
        expected[gravity.columns] = pin.computeGeneralizedGravity(gravity.model, data, q)[
            gravity.columns
        ]
        np.testing.assert_allclose(tau, expected, rtol=0, atol=1e-13 * np.abs(expected).max())
    assert machine.compiled is not None and machine.compiled.pieces == []


def test_the_hypot_op_is_pythons():
    """``va.scalar.hypot`` traced gives ``math.hypot``'s bits, also where the C library's
    ``hypot`` rounds the other way (CPython computes it its own way)."""
    import math

    rng = np.random.default_rng(7)
    pairs = []
    while len(pairs) < 20:  # times and constants where libm and CPython differ
        t, c = float(rng.uniform(0.1, 10.0)), float(rng.uniform(0.1, 10.0))
        if math.hypot(t, c) != float(np.hypot(t, c)):
            pairs.append((t, c))
    robot = va.load_robot("solo12")
    feet = ["FL_FOOT", "FR_FOOT", "HL_FOOT", "HR_FOOT"]
    body = va.ParallelVirtualActuator(robot, "base_link", feet, "world", contact="point")
    controller = va.Controller(robot)
    controller.add("body", body, [va.SpringDamper(body.axes, 100.0, 10.0)])
    memory = va.Memory(h=tuple(0.0 for _ in pairs))

    @va.lowerable
    def norms(context):
        memory.h = tuple(va.scalar.hypot(context.time * (t / 1.0), c) for t, c in pairs)

    machine = va.MachineController(
        controller, va.StateMachine([va.State("s", active=("body",), on_update=norms)], [], "s")
    )
    machine.compute(robot.neutral(), np.zeros(robot.model.nv), 1.0)
    assert machine.compiled.pieces == []
    assert memory.h == tuple(math.hypot(t, c) for t, c in pairs)
