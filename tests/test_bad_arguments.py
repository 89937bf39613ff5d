"""Bad arguments to every public entry point raise a typed error that names the argument.

A table of calls, each with one bad argument (wrong type, wrong shape, NaN, negative, complex,
bool where a number is expected, None where a value is needed, ...). Every call must raise a
:class:`va.VirtualActuatorError` (never a bare ``TypeError``, ``ValueError`` or
``AttributeError``) whose message names the argument; none may be silently accepted.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from types import SimpleNamespace

import numpy as np
import pytest
from oracles import robot

import virtual_actuators as va
from virtual_actuators.control import events

FEET = ["FL_FOOT", "FR_FOOT", "HL_FOOT", "HR_FOOT"]
AXES = ("x", "y", "z", "rx", "ry", "rz")


@pytest.fixture(scope="module")
def env() -> SimpleNamespace:
    """Real robots, actuators and a controller, built once (treated as read-only)."""
    solo, ur5, turkey = robot("solo12"), robot("ur5_robot"), robot("spring_turkey")
    arm = va.VirtualActuator(ur5, "tool0", "world", "world", AXES)
    body = va.ParallelVirtualActuator(solo, "base_link", FEET, "base_link", contact="point")
    double = va.ParallelVirtualActuator(
        turkey,
        "body",
        ["left_foot", "right_foot"],
        "world",
        ("x", "z", "ry"),
        contact="point",
        design=[va.EqualTorque("left_hip", "right_hip")],
    )
    controller = va.Controller(ur5)
    controller.add("arm", arm, [va.SpringDamper(AXES, 100.0, 10.0)])
    walker = va.Controller(turkey)
    walker.add("double", double, [va.GrannyWalker(0.54, (1500, 200), (150, 20))])
    machine = va.StateMachine([va.State("a"), va.State("b")], [], "a")
    q_ur5, q_solo, q_turkey = ur5.neutral() + 0.3, solo.neutral(), turkey.neutral()
    return SimpleNamespace(
        solo=solo,
        ur5=ur5,
        turkey=turkey,
        arm=arm,
        body=body,
        double=double,
        controller=controller,
        walker=walker,
        machine=machine,
        q_ur5=q_ur5,
        v_ur5=np.zeros(ur5.model.nv),
        q_solo=q_solo,
        q_turkey=q_turkey,
        v_turkey=np.zeros(turkey.model.nv),
        w6=np.array([0.0, 0.0, 24.5, 0.0, 0.1, 0.0]),
        context=va.Context(turkey, q_turkey, np.zeros(turkey.model.nv), 0.0),
    )


def parallel(env: SimpleNamespace, **kwargs: object) -> va.ParallelVirtualActuator:
    """Solo12's body actuator over its four feet, with some arguments replaced."""
    args = {"robot": env.solo, "action": "base_link", "reactions": FEET, "reference": "world"}
    args.update(kwargs)
    return va.ParallelVirtualActuator(**args)


def turkey_parallel(env: SimpleNamespace, **kwargs: object) -> va.ParallelVirtualActuator:
    """Spring Turkey's double-support actuator, with some arguments replaced."""
    args = {
        "robot": env.turkey,
        "action": "body",
        "reactions": ["left_foot", "right_foot"],
        "reference": "world",
        "axes": ("x", "z", "ry"),
    }
    args.update(kwargs)
    return va.ParallelVirtualActuator(**args)


def add(env: SimpleNamespace, **kwargs: object) -> None:
    """``Controller.add`` on a fresh turkey controller with some arguments replaced."""
    controller = va.Controller(env.turkey)
    args = {"name": "double", "actuator": env.double, "components": ()}
    args.update(kwargs)
    controller.add(**args)


Call = Callable[[SimpleNamespace], object]
NAN, INF = math.nan, math.inf

CASES: list[tuple[str, Call, str]] = [
    # -- robot -------------------------------------------------------------------------------
    ("serial-robot-None", lambda e: va.VirtualActuator(None, "tool0", "world"), "robot"),
    ("serial-robot-str", lambda e: va.VirtualActuator("ur5_robot", "tool0", "world"), "robot"),
    ("serial-robot-model", lambda e: va.VirtualActuator(e.ur5.model, "tool0", "world"), "robot"),
    ("parallel-robot-None", lambda e: parallel(e, robot=None), "robot"),
    ("parallel-robot-str", lambda e: parallel(e, robot="solo12"), "robot"),
    ("controller-robot-None", lambda e: va.Controller(None), "robot"),
    ("controller-robot-str", lambda e: va.Controller("ur5_robot"), "robot"),
    ("context-robot-None", lambda e: va.Context(None, e.q_turkey, e.v_turkey, 0.0), "robot"),
    # -- frames ------------------------------------------------------------------------------
    ("serial-action-None", lambda e: va.VirtualActuator(e.ur5, None, "world"), "action"),
    ("serial-reaction-int", lambda e: va.VirtualActuator(e.ur5, "tool0", 3), "reaction"),
    (
        "serial-reference-list",
        lambda e: va.VirtualActuator(e.ur5, "tool0", "world", ["world"]),
        "reference",
    ),
    ("serial-action-is-reaction", lambda e: va.VirtualActuator(e.ur5, "tool0", "tool0"), "tool0"),
    (
        "serial-world-is-universe",
        lambda e: va.VirtualActuator(e.solo, "world", "universe"),
        "action frame",
    ),
    ("parallel-reactions-None", lambda e: parallel(e, reactions=None), "reactions"),
    ("parallel-reactions-int", lambda e: parallel(e, reactions=5), "reactions"),
    ("parallel-reactions-empty", lambda e: parallel(e, reactions=[]), "reaction"),
    ("parallel-reactions-dict", lambda e: parallel(e, reactions={"FL_FOOT": 1}), "reactions"),
    ("parallel-reaction-None", lambda e: parallel(e, reactions=["FL_FOOT", None]), "reaction"),
    ("parallel-action-in-reactions", lambda e: parallel(e, action="FL_FOOT"), "FL_FOOT"),
    # -- axes --------------------------------------------------------------------------------
    ("serial-axes-None", lambda e: va.VirtualActuator(e.ur5, "tool0", "world", axes=None), "axes"),
    ("serial-axes-int", lambda e: va.VirtualActuator(e.ur5, "tool0", "world", axes=5), "axes"),
    ("serial-axes-set", lambda e: va.VirtualActuator(e.ur5, "tool0", "world", axes={"x"}), "axes"),
    (
        "serial-axes-bytes",
        lambda e: va.VirtualActuator(e.ur5, "tool0", "world", axes=b"x"),
        "axes",
    ),
    (
        "serial-axes-bad-entry",
        lambda e: va.VirtualActuator(e.ur5, "tool0", "world", axes=("x", 3)),
        "axis",
    ),
    ("parallel-axes-None", lambda e: parallel(e, axes=None), "axes"),
    ("parallel-axes-float", lambda e: parallel(e, axes=1.5), "axes"),
    # -- contact, unactuated, passive, design ------------------------------------------------
    ("contact-None", lambda e: parallel(e, contact=None), "contact"),
    ("contact-int", lambda e: parallel(e, contact=5), "contact"),
    ("contact-list", lambda e: parallel(e, contact=["point"] * 4), "contact"),
    ("contact-bad-kind", lambda e: parallel(e, contact={"FL_FOOT": "sticky"}), "contact"),
    ("contact-bad-key", lambda e: parallel(e, contact={3: "flat"}), "contact"),
    ("unactuated-int", lambda e: parallel(e, unactuated=5), "unactuated"),
    ("unactuated-None", lambda e: parallel(e, unactuated=None), "unactuated"),
    ("unactuated-entry-int", lambda e: parallel(e, unactuated=[5]), "unactuated"),
    ("passive-list", lambda e: parallel(e, passive=["FL_KFE"]), "passive"),
    ("passive-list-of-pairs", lambda e: parallel(e, passive=[("FL_KFE", 1.0)]), "passive"),
    ("passive-int", lambda e: parallel(e, passive=5), "passive"),
    ("passive-scalar-value", lambda e: parallel(e, passive={"FL_KFE": 5.0}), "passive"),
    ("passive-str-value", lambda e: parallel(e, passive={"FL_KFE": ("abc", 0.0)}), "passive"),
    ("passive-bool-value", lambda e: parallel(e, passive={"FL_KFE": (True, 0.0)}), "passive"),
    ("passive-complex-value", lambda e: parallel(e, passive={"FL_KFE": (1j, 0.0)}), "passive"),
    ("passive-nan-value", lambda e: parallel(e, passive={"FL_KFE": (1.0, NAN)}), "passive"),
    ("passive-key-int", lambda e: parallel(e, passive={5: (1.0, 0.0)}), "passive"),
    ("design-None", lambda e: parallel(e, design=None), "design"),
    ("design-int", lambda e: parallel(e, design=5), "design"),
    ("design-entry-str", lambda e: parallel(e, design=["Equal"]), "design"),
    # -- design constraints ------------------------------------------------------------------
    ("equal-a-None", lambda e: va.Equal(None, ("FR_FOOT", "x")), "a"),
    ("equal-b-str", lambda e: va.Equal(("FL_FOOT", "x"), "FR_FOOT"), "b"),
    ("equal-b-triple", lambda e: va.Equal(("FL_FOOT", "x"), ("FR_FOOT", "x", 1)), "b"),
    ("equal-bad-axis", lambda e: va.Equal(("FL_FOOT", "w"), ("FR_FOOT", "x")), "axis"),
    ("equal-frame-int", lambda e: va.Equal((3, "x"), ("FR_FOOT", "x")), "a"),
    ("linear-coefficients-None", lambda e: va.Linear(None), "coefficients"),
    ("linear-coefficients-list", lambda e: va.Linear([("FL_FOOT", "x")]), "coefficients"),
    ("linear-coefficients-empty", lambda e: parallel(e, design=[va.Linear({})]), "coefficient"),
    ("linear-coefficient-str", lambda e: va.Linear({("FL_FOOT", "x"): "abc"}), "coefficient"),
    ("linear-coefficient-bool", lambda e: va.Linear({("FL_FOOT", "x"): True}), "coefficient"),
    (
        "linear-coefficient-nan",
        lambda e: parallel(e, design=[va.Linear({("FL_FOOT", "x"): NAN})]),
        "coefficient",
    ),
    ("linear-coefficient-complex", lambda e: va.Linear({("FL_FOOT", "x"): 1j}), "coefficient"),
    ("linear-label-str", lambda e: va.Linear({"FL_FOOT": 1.0}), "coefficients"),
    ("linear-rhs-str", lambda e: va.Linear({("FL_FOOT", "x"): 1.0}, rhs="0"), "rhs"),
    (
        "linear-rhs-inf",
        lambda e: parallel(e, design=[va.Linear({("FL_FOOT", "x"): 1.0}, rhs=INF)]),
        "rhs",
    ),
    ("equal-torque-None", lambda e: va.EqualTorque(None, "right_hip"), "joint_a"),
    ("equal-torque-int", lambda e: va.EqualTorque("left_hip", 5), "joint_b"),
    # -- serial actuator methods -------------------------------------------------------------
    ("position-q-str", lambda e: e.arm.position("abc"), "q"),
    ("position-q-short", lambda e: e.arm.position([0.0, 0.0]), "q"),
    ("position-q-dict", lambda e: e.arm.position({"a": 1.0}), "q"),
    ("position-q-None", lambda e: e.arm.position(None), "q"),
    ("position-q-2d", lambda e: e.arm.position(np.zeros((1, 6))), "q"),
    ("jacobian-q-nan", lambda e: e.arm.jacobian(np.full(6, NAN)), "q"),
    ("read-v-None", lambda e: e.arm.read(e.q_ur5), "v"),
    ("read-v-str", lambda e: e.arm.read(e.q_ur5, "abc"), "v"),
    ("read-v-short", lambda e: e.arm.read(e.q_ur5, [0.0]), "v"),
    ("velocity-v-None", lambda e: e.arm.velocity(e.q_ur5), "v"),
    ("torques-wrench-str", lambda e: e.arm.torques(e.q_ur5, "abc"), "wrench"),
    ("torques-wrench-short", lambda e: e.arm.torques(e.q_ur5, [1.0]), "wrench"),
    ("torques-wrench-complex", lambda e: e.arm.torques(e.q_ur5, np.full(6, 1j)), "wrench"),
    ("torques-wrench-complex-list", lambda e: e.arm.torques(e.q_ur5, [1j] * 6), "wrench"),
    ("torques-wrench-bool", lambda e: e.arm.torques(e.q_ur5, [True] * 6), "wrench"),
    ("torques-wrench-None", lambda e: e.arm.torques(e.q_ur5, None), "wrench"),
    ("admissible-tol-str", lambda e: e.arm.is_admissible(e.q_ur5, np.ones(6), "abc"), "tol"),
    ("admissible-tol-nan", lambda e: e.arm.is_admissible(e.q_ur5, np.ones(6), NAN), "tol"),
    ("admissible-tol-negative", lambda e: e.arm.is_admissible(e.q_ur5, np.ones(6), -1.0), "tol"),
    ("admissible-tol-bool", lambda e: e.arm.is_admissible(e.q_ur5, np.ones(6), True), "tol"),
    ("admissible-tol-complex", lambda e: e.arm.is_admissible(e.q_ur5, np.ones(6), 1j), "tol"),
    ("admissible-wrench-str", lambda e: e.arm.is_admissible(e.q_ur5, "abc"), "wrench"),
    # -- parallel actuator methods -----------------------------------------------------------
    ("solve-q-str", lambda e: e.body.solve("abc", e.w6), "q"),
    ("solve-q-short", lambda e: e.body.solve([0.0] * 3, e.w6), "q"),
    ("solve-q-dict", lambda e: e.body.solve({"q": 0.0}, e.w6), "q"),
    ("solve-q-other-robot", lambda e: e.body.solve(va.Snapshot(e.ur5, e.q_ur5), e.w6), "robot"),
    ("solve-wrench-str", lambda e: e.body.solve(e.q_solo, "abc"), "wrench"),
    ("solve-wrench-complex", lambda e: e.body.solve(e.q_solo, e.w6 + 1j), "wrench"),
    ("solve-wrench-bool", lambda e: e.body.solve(e.q_solo, np.ones(6, dtype=bool)), "wrench"),
    ("solve-wrench-inf", lambda e: e.body.solve(e.q_solo, np.full(6, INF)), "wrench"),
    ("solve-free-int", lambda e: e.body.solve(e.q_solo, e.w6, free=3), "free"),
    ("solve-free-None", lambda e: e.body.solve(e.q_solo, e.w6, free=None), "free"),
    ("solve-free-bad-axis", lambda e: e.body.solve(e.q_solo, e.w6, free=("w",)), "free"),
    ("solve-free-unhashable", lambda e: e.body.solve(e.q_solo, e.w6, free=[["x"]]), "free"),
    ("solve-tol-str", lambda e: e.body.solve(e.q_solo, e.w6, tol="abc"), "tol"),
    ("solve-tol-nan", lambda e: e.body.solve(e.q_solo, e.w6, tol=NAN), "tol"),
    ("solve-tol-negative", lambda e: e.body.solve(e.q_solo, e.w6, tol=-1e-6), "tol"),
    ("solve-tol-None", lambda e: e.body.solve(e.q_solo, e.w6, tol=None), "tol"),
    ("solve-tol-bool", lambda e: e.body.solve(e.q_solo, e.w6, tol=False), "tol"),
    ("solve-strict-str", lambda e: e.body.solve(e.q_solo, e.w6, strict="yes"), "strict"),
    ("solve-compiled-None", lambda e: e.body.solve(e.q_solo, e.w6, compiled=None), "compiled"),
    ("solve-method-int", lambda e: e.body.solve(e.q_solo, e.w6, method=5), "method"),
    ("solve-method-unknown", lambda e: e.body.solve(e.q_solo, e.w6, method="simplex"), "method"),
    ("ptorques-forces-str", lambda e: e.body.torques(e.q_solo, "abc"), "forces"),
    ("ptorques-forces-complex", lambda e: e.body.torques(e.q_solo, np.ones((4, 6)) * 1j), "forces"),
    ("ptorques-forces-shape", lambda e: e.body.torques(e.q_solo, np.ones(6)), "forces"),
    # -- controller --------------------------------------------------------------------------
    ("controller-clip-str", lambda e: va.Controller(e.ur5, clip="no"), "clip"),
    ("controller-on-singular", lambda e: va.Controller(e.ur5, on_singular=0), "on_singular"),
    ("controller-on-failure", lambda e: va.Controller(e.ur5, on_failure="ignore"), "on_failure"),
    ("add-name-int", lambda e: add(e, name=5), "name"),
    ("add-name-None", lambda e: add(e, name=None), "name"),
    ("add-actuator-None", lambda e: add(e, actuator=None), "actuator"),
    ("add-actuator-str", lambda e: add(e, actuator="body"), "actuator"),
    ("add-components-None", lambda e: add(e, components=None), "components"),
    ("add-components-entry-int", lambda e: add(e, components=[5]), "components"),
    ("add-components-bad-axes", lambda e: add(e, components=[va.Spring(("y",), 1.0)]), "axes"),
    ("add-sensor-str", lambda e: add(e, sensor="body"), "sensor"),
    ("add-free-int", lambda e: add(e, free=3), "free"),
    ("add-unilateral-int", lambda e: add(e, unilateral=5, yield_axes=("x",)), "unilateral"),
    (
        "add-unilateral-str-value",
        lambda e: add(e, unilateral={"z": "abc"}, yield_axes=("x",)),
        "unilateral",
    ),
    (
        "add-unilateral-nan-value",
        lambda e: add(e, unilateral={"z": NAN}, yield_axes=("x",)),
        "unilateral",
    ),
    (
        "add-unilateral-bool-value",
        lambda e: add(e, unilateral={"z": True}, yield_axes=("x",)),
        "unilateral",
    ),
    ("add-yield-axes-int", lambda e: add(e, unilateral={"z": 1.0}, yield_axes=5), "yield_axes"),
    ("add-friction-str", lambda e: add(e, friction="abc", yield_axes=("x",)), "friction"),
    ("add-friction-bool", lambda e: add(e, friction=True, yield_axes=("x",)), "friction"),
    ("add-friction-negative", lambda e: add(e, friction=-0.5, yield_axes=("x",)), "friction"),
    ("add-min-normal-str", lambda e: add(e, min_normal="abc"), "min_normal"),
    ("add-min-normal-nan", lambda e: add(e, min_normal=NAN), "min_normal"),
    ("compute-q-str", lambda e: e.controller.compute("abc", e.v_ur5), "q"),
    ("compute-q-short", lambda e: e.controller.compute([0.0], e.v_ur5), "q"),
    ("compute-v-None", lambda e: e.controller.compute(e.q_ur5), "v"),
    ("compute-v-str", lambda e: e.controller.compute(e.q_ur5, "abc"), "v"),
    ("compute-time-str", lambda e: e.controller.compute(e.q_ur5, e.v_ur5, "abc"), "time"),
    ("compute-time-nan", lambda e: e.controller.compute(e.q_ur5, e.v_ur5, NAN), "time"),
    ("compute-time-None", lambda e: e.controller.compute(e.q_ur5, e.v_ur5, None), "time"),
    ("compute-active-int", lambda e: e.controller.compute(e.q_ur5, e.v_ur5, 0.0, 5), "active"),
    (
        "compute-active-unknown",
        lambda e: e.controller.compute(e.q_ur5, e.v_ur5, 0.0, ["leg"]),
        "attachment",
    ),
    ("compute-limp-str", lambda e: e.controller.compute(e.q_ur5, e.v_ur5, 0.0, None, "a"), "limp"),
    (
        "compute-limp-out-of-range",
        lambda e: e.controller.compute(e.q_ur5, e.v_ur5, 0.0, None, [100]),
        "limp",
    ),
    (
        "compute-limp-negative",
        lambda e: e.controller.compute(e.q_ur5, e.v_ur5, 0.0, None, [-1]),
        "limp",
    ),
    (
        "compute-limp-float",
        lambda e: e.controller.compute(e.q_ur5, e.v_ur5, 0.0, None, [1.5]),
        "limp",
    ),
    (
        "compute-limp-array-out-of-range",
        lambda e: e.controller.compute(e.q_ur5, e.v_ur5, 0.0, None, np.array([6])),
        "limp",
    ),
    ("joint-indices-int", lambda e: e.controller.joint_indices(5), "joints"),
    ("joint-indices-unknown", lambda e: e.controller.joint_indices(["elbow"]), "elbow"),
    ("reset-names-int", lambda e: e.controller.reset(5, e.q_ur5, 0.0), "names"),
    ("reset-time-str", lambda e: e.controller.reset(["arm"], e.q_ur5, "abc"), "time"),
    # -- components --------------------------------------------------------------------------
    ("component-axes-None", lambda e: va.SpringDamper(None), "axes"),
    ("component-axes-int", lambda e: va.Spring(3, 1.0), "axes"),
    ("component-name-int", lambda e: va.Spring(("x",), 1.0, name=5), "name"),
    ("spring-stiffness-str", lambda e: va.SpringDamper(("x",), stiffness="abc"), "stiffness"),
    ("spring-stiffness-bool", lambda e: va.Spring(("x",), True), "stiffness"),
    ("spring-stiffness-None", lambda e: va.Spring(("x",), None), "stiffness"),
    ("spring-stiffness-complex", lambda e: va.Spring(("x",), 1j), "stiffness"),
    ("spring-stiffness-dict", lambda e: va.Spring(("x",), {"x": 1.0}), "stiffness"),
    ("spring-stiffness-negative", lambda e: va.Spring(("x",), -1.0), "stiffness"),
    ("spring-stiffness-shape", lambda e: va.Spring(("x", "z"), [1.0, 2.0, 3.0]), "stiffness"),
    ("spring-setpoint-str", lambda e: va.Spring(("x",), 1.0, setpoint="abc"), "setpoint"),
    ("spring-setpoint-nan", lambda e: va.Spring(("x",), 1.0, setpoint=NAN), "setpoint"),
    ("damper-damping-str", lambda e: va.Damper(("x",), "abc"), "damping"),
    ("damper-damping-bool-array", lambda e: va.Damper(("x",), np.array([True])), "damping"),
    ("damper-velocity-setpoint-str", lambda e: va.Damper(("x",), 1.0, "v"), "velocity_setpoint"),
    ("spring-damper-limit-nan", lambda e: va.SpringDamper(("x",), limit=NAN), "limit"),
    ("spring-damper-limit-negative", lambda e: va.SpringDamper(("x",), limit=-1.0), "limit"),
    ("force-str", lambda e: va.ConstantForce(("z",), "abc"), "force"),
    ("force-complex-array", lambda e: va.ConstantForce(("z",), np.array([1j])), "force"),
    ("granny-height-str", lambda e: va.GrannyWalker("abc", (1, 1), (1, 1)), "height"),
    ("granny-height-bool", lambda e: va.GrannyWalker(True, (1, 1), (1, 1)), "height"),
    ("granny-pitch-None", lambda e: va.GrannyWalker(0.5, (1, 1), (1, 1), pitch=None), "pitch"),
    ("granny-weight-str", lambda e: va.GrannyWalker(0.5, (1, 1), (1, 1), weight="w"), "weight"),
    ("granny-stiffness-str", lambda e: va.GrannyWalker(0.5, "k", (1, 1)), "stiffness"),
    ("granny-axes-None", lambda e: va.GrannyWalker(0.5, (1, 1), (1, 1), axes=None), "axes"),
    ("bunny-speed-str", lambda e: va.DogtrackBunny("fast", 1.0), "speed"),
    ("bunny-speed-nan", lambda e: va.DogtrackBunny(NAN, 1.0), "speed"),
    ("bunny-speed-bool", lambda e: va.DogtrackBunny(True, 1.0), "speed"),
    ("bunny-damping-str", lambda e: va.DogtrackBunny(0.5, "b"), "damping"),
    ("bunny-axis-int", lambda e: va.DogtrackBunny(0.5, 1.0, axis=5), "axis"),
    ("bunny-reset-time-str", lambda e: va.DogtrackBunny(0.5, 1.0).reset([0.0], "t"), "time"),
    ("bunny-reset-position-str", lambda e: va.DogtrackBunny(0.5, 1.0).reset("x", 0.0), "position"),
    ("swing-stiffness-str", lambda e: va.SwingLegLinkage("k", 1.0), "stiffness"),
    ("swing-place-str", lambda e: va.SwingLegLinkage(1.0, 1.0).place("abc"), "setpoint"),
    (
        "swing-place-velocity-complex",
        lambda e: va.SwingLegLinkage(1.0, 1.0).place(0.0, 1j),
        "velocity_setpoint",
    ),
    # -- state machine and events ------------------------------------------------------------
    ("state-name-int", lambda e: va.State(5), "name"),
    ("state-active-int", lambda e: va.State("a", active=5), "active"),
    ("state-limp-entry-int", lambda e: va.State("a", limp=[5]), "limp"),
    ("state-on-enter-int", lambda e: va.State("a", on_enter=5), "on_enter"),
    ("transition-source-int", lambda e: va.Transition(5, "b", bool), "source"),
    ("transition-event-str", lambda e: va.Transition("a", "b", "go"), "event"),
    ("machine-states-None", lambda e: va.StateMachine(None, [], "a"), "states"),
    ("machine-states-entry-str", lambda e: va.StateMachine(["a"], [], "a"), "states"),
    ("machine-transitions-int", lambda e: va.StateMachine([va.State("a")], 5, "a"), "transitions"),
    (
        "machine-transitions-entry",
        lambda e: va.StateMachine([va.State("a")], [("a", "a")], "a"),
        "transitions",
    ),
    ("machine-initial-int", lambda e: va.StateMachine([va.State("a")], [], 5), "initial"),
    ("machine-update-None", lambda e: e.machine.update(None), "context"),
    ("machine-start-state-int", lambda e: e.machine.start(e.context, 5), "state"),
    ("machine-state-int", lambda e: e.machine.state(5), "state"),
    ("context-time-str", lambda e: va.Context(e.turkey, e.q_turkey, e.v_turkey, "t"), "time"),
    ("context-time-None", lambda e: va.Context(e.turkey, e.q_turkey, e.v_turkey, None), "time"),
    (
        "context-contacts-int",
        lambda e: va.Context(e.turkey, e.q_turkey, e.v_turkey, 0.0, 5),
        "contacts",
    ),
    ("context-q-str", lambda e: va.Context(e.turkey, "abc", e.v_turkey, 0.0), "q"),
    (
        "context-snapshot-str",
        lambda e: va.Context(e.turkey, e.q_turkey, e.v_turkey, 0.0, snapshot="s"),
        "snapshot",
    ),
    ("context-in-contact-unknown", lambda e: e.context.in_contact("left_heel"), "left_heel"),
    ("event-after-str", lambda e: events.after("1s"), "seconds"),
    ("event-after-nan", lambda e: events.after(NAN), "seconds"),
    ("event-after-bool", lambda e: events.after(True), "seconds"),
    ("event-ahead-of-frame-int", lambda e: events.ahead_of(5, "left_foot", 0.1), "frame"),
    (
        "event-ahead-of-distance-str",
        lambda e: events.ahead_of("body", "left_foot", "d"),
        "distance",
    ),
    ("event-ahead-of-axis", lambda e: events.ahead_of("body", "left_foot", 0.1, "rx"), "axis"),
    ("event-contact-int", lambda e: events.contact(5), "frames"),
    ("event-contact-none", lambda e: events.contact(), "frame"),
    ("event-no-contact-list", lambda e: events.no_contact(["left_heel"]), "frames"),
    ("event-any-of-int", lambda e: events.any_of(5), "events"),
    ("event-all-of-str", lambda e: events.all_of("go"), "events"),
    ("event-when-int", lambda e: events.when(5), "predicate"),
]

# The kinematics layer's own checks: complex or bool q / v, a robot that is not a va.Robot, a
# frame that is neither a name nor an id.
KINEMATICS_CASES: list[tuple[str, Call, str]] = [
    ("solve-q-complex", lambda e: e.body.solve(e.q_solo + 0j, e.w6), "q"),
    ("position-q-bool", lambda e: e.arm.position(np.ones(6, dtype=bool)), "q"),
    ("read-v-complex", lambda e: e.arm.read(e.q_ur5, e.v_ur5 + 1j), "v"),
    ("snapshot-q-complex", lambda e: va.Snapshot(e.ur5, e.q_ur5 + 1j), "q"),
    ("snapshot-robot-None", lambda e: va.Snapshot(None, e.q_ur5), "robot"),
    ("snapshot-frame-None", lambda e: va.Snapshot(e.ur5, e.q_ur5).frame_position(None), "frame"),
    ("context-frame-None", lambda e: e.context.frame_position(None), "frame"),
]


@pytest.mark.parametrize(("call", "match"), [pytest.param(c, m, id=i) for i, c, m in CASES])
def test_bad_argument_raises_typed_error_naming_it(env, call, match):
    with pytest.raises(va.VirtualActuatorError, match=match):
        call(env)


@pytest.mark.parametrize(
    ("call", "match"),
    [pytest.param(c, m, id=i) for i, c, m in KINEMATICS_CASES],
)
def test_bad_configuration_in_kinematics_layer(env, call, match):
    with pytest.raises(va.VirtualActuatorError, match=match):
        call(env)


def test_table_is_large_and_ids_unique():
    ids = [case[0] for case in CASES + KINEMATICS_CASES]
    assert len(ids) == len(set(ids))
    assert len(CASES) >= 60


# -- the valid forms still work ------------------------------------------------------------------
def test_valid_forms_are_still_accepted(env):
    q, w = env.q_solo, env.w6
    base = env.body.solve(q, w)
    assert np.allclose(env.body.solve(list(q), list(w)).tau, base.tau)
    assert np.allclose(env.body.solve(q, w, tol=0).tau, base.tau)  # an int tolerance
    assert np.allclose(env.body.solve(q, w, tol=np.float32(1e-6)).tau, base.tau)
    assert np.allclose(env.body.solve(q, w.astype(np.float32)).tau, base.tau, atol=1e-4)
    assert np.allclose(env.body.solve(q, w.astype(int)).tau, env.body.solve(q, w.round()).tau)
    assert env.body.solve(q, w, free="x").free == ("x",)
    assert env.body.solve(q, w, strict=np.bool_(False)).method
    assert va.VirtualActuator(env.ur5, "tool0", "world", axes="z").axes == ("z",)
    assert va.VirtualActuator(env.ur5, "tool0", "world", axes=np.array(["x", "z"])).axes == (
        "x",
        "z",
    )
    assert env.arm.is_admissible(env.q_ur5, np.zeros(6), tol=0)
    single = turkey_parallel(env, design=va.EqualTorque("left_hip", "right_hip"))
    assert len(single.design) == 1
    limp = turkey_parallel(env, unactuated="left_knee", passive={"right_knee": [10, 0.1]})
    assert limp.problem.limp_v and limp.problem.passive_v
    assert parallel(env, reactions="FL_FOOT", axes=("x", "y", "z")).p == 1
    assert va.Linear({("FL_FOOT", "x"): np.float64(2.0), ("FR_FOOT", "x"): -1}, rhs=1).rhs == 1.0
    assert va.Equal(["FL_FOOT", "x"], ("FR_FOOT", "x")).a == ("FL_FOOT", "x")
    out = env.controller.compute(env.q_ur5, env.v_ur5, 1, "arm", (0, np.int64(5)))
    assert out.active == ("arm",) and out.tau[0] == 0.0 and out.tau[5] == 0.0
    assert env.controller.joint_indices("elbow_joint").tolist() == [2]
    assert va.Spring(("x", "y"), np.array([1, 2])).stiffness.tolist() == [1.0, 2.0]
    assert va.SpringDamper("x", limit=np.inf).limit.tolist() == [np.inf]
    assert va.DogtrackBunny(np.float32(0.5), 1).speed == 0.5
    assert va.State("a", active="arm").active == ("arm",)
    assert callable(events.after(0)) and callable(events.contact("left_heel"))
