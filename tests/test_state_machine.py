"""Gait state machines, events and the tick context; the planar gait helpers of gaits/base.py.

Frame quantities are checked against Pinocchio forward kinematics run in the test (velocities
against central finite differences of positions); leg inverse kinematics against the closed-form
forward kinematics of a two-link leg written out here and against Pinocchio.
"""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin
import pytest
from oracles import random_configuration, robot

import virtual_actuators as va
from virtual_actuators.components import DogtrackBunny, GrannyWalker
from virtual_actuators.control import Context, Controller, State, StateMachine, Transition, events
from virtual_actuators.gaits.base import Gait
from virtual_actuators.gaits.planar import planar_leg_ik, planar_standing_configuration

TURKEY = "spring_turkey"
FLAMINGO = "spring_flamingo"


def context(time: float = 0.0, contacts=None, name: str = TURKEY, q=None, v=None) -> Context:
    rob = robot(name)
    q = rob.neutral() if q is None else q
    v = np.zeros(rob.model.nv) if v is None else v
    return Context(rob, q, v, time, contacts)


def always(_context) -> bool:
    return True


def never(_context) -> bool:
    return False


# -- declaration --------------------------------------------------------------------------------
def test_duplicate_state_names():
    with pytest.raises(va.InvalidInputError, match="'a'"):
        StateMachine([State("a"), State("b"), State("a")], [], "a")


@pytest.mark.parametrize(
    ("transitions", "initial", "bad"),
    [
        ([Transition("stand", "walks", always)], "stand", "walks"),
        ([Transition("stands", "walk", always)], "stand", "stands"),
        ([], "wlak", "wlak"),
    ],
)
def test_unknown_states_are_invalid_input_and_name_the_states(transitions, initial, bad):
    states = [State("stand"), State("walk")]
    with pytest.raises(va.InvalidInputError, match=f"'{bad}'") as error:
        StateMachine(states, transitions, initial)
    message = str(error.value)
    assert "'walk'" in message or "'stand'" in message


def test_unknown_state_far_from_every_name_lists_them_all():
    with pytest.raises(va.InvalidInputError) as error:
        StateMachine([State("stand"), State("walk")], [], "zzz")
    assert "'stand'" in str(error.value) and "'walk'" in str(error.value)


def test_state_lookup_and_names():
    machine = StateMachine([State("a"), State("b", active=["x"])], [], "b")
    assert machine.names == ["a", "b"]
    assert machine.index == {"a": 0, "b": 1}
    assert machine.state("b").active == ("x",)
    assert machine.current.name == "b"
    with pytest.raises(va.InvalidInputError, match="'c'"):
        machine.state("c")
    with pytest.raises(va.InvalidInputError, match="'c'"):
        machine.start(context(), "c")


def test_state_fields_become_tuples():
    state = State("s", active=["a", "b"], support=["left_foot"], limp=["left_hip"])
    assert state.active == ("a", "b")
    assert state.support == ("left_foot",)
    assert state.limp == ("left_hip",)


# -- stepping -----------------------------------------------------------------------------------
def test_first_firing_transition_wins_and_one_transition_per_tick():
    states = [State("a"), State("b"), State("c"), State("d")]
    transitions = [
        Transition("a", "b", never),
        Transition("a", "c", always),  # first that fires
        Transition("a", "d", always),
        Transition("c", "d", always),  # would fire at once, but only on the next tick
        Transition("d", "a", never),
    ]
    machine = StateMachine(states, transitions, "a")
    assert machine.update(context(0.0)).name == "c"
    assert machine.current.name == "c"
    assert machine.update(context(0.1)).name == "d"
    assert machine.update(context(0.2)).name == "d"
    assert machine.history == [(0.0, "a"), (0.0, "c"), (0.1, "d")]


def test_update_starts_the_machine_and_start_resets_history():
    machine = StateMachine([State("a"), State("b")], [Transition("a", "b", always)], "a")
    assert not machine.started
    machine.update(context(1.0))
    assert machine.started
    assert machine.history == [(1.0, "a"), (1.0, "b")]
    machine.start(context(5.0))
    assert machine.history == [(5.0, "a")] and machine.current.name == "a"
    machine.start(context(6.0), "b")
    assert machine.history == [(6.0, "b")] and machine.entered_at == 6.0


def test_callbacks_are_called_with_the_context():
    calls = []

    def enter(name):
        return lambda c: calls.append(("enter", name, c.state, c.time, c.time_in_state))

    def update(name):
        return lambda c: calls.append(("update", name, c.state, c.time, c.time_in_state))

    states = [
        State("a", on_enter=enter("a"), on_update=update("a")),
        State("b", on_enter=enter("b"), on_update=update("b")),
    ]
    machine = StateMachine(states, [Transition("a", "b", events.after(0.25))], "a")
    for t in (0.0, 0.1, 0.3, 0.4):
        machine.update(context(t))
    assert calls == [
        ("enter", "a", "a", 0.0, 0.0),
        ("update", "a", "a", 0.0, 0.0),
        ("update", "a", "a", 0.1, pytest.approx(0.1)),
        ("enter", "b", "b", 0.3, 0.0),
        ("update", "b", "b", 0.3, 0.0),  # the new state's on_update runs on the entry tick
        ("update", "b", "b", 0.4, pytest.approx(0.1)),
    ]


def test_time_in_state_and_timer_events():
    states = [State("stand"), State("step"), State("rest")]
    transitions = [
        Transition("stand", "step", events.after(0.5), "timer"),
        Transition("step", "rest", events.after(0.2)),
        Transition("rest", "stand", events.after(0.0)),
    ]
    machine = StateMachine(states, transitions, "stand")
    seen = []
    for k in range(13):
        c = context(0.1 * k)
        machine.update(c)
        seen.append((machine.current.name, round(c.time_in_state, 9)))
    # stand entered at 0 -> step at 0.5 -> rest at 0.7 -> stand at 0.8 -> step at 1.3 (tick 13)
    assert [name for name, _ in seen] == (["stand"] * 5 + ["step"] * 2 + ["rest"] + ["stand"] * 5)
    assert seen[3] == ("stand", 0.3)
    assert seen[6] == ("step", 0.1)
    assert seen[5] == ("step", 0.0)
    assert [name for _, name in machine.history] == ["stand", "step", "rest", "stand"]
    assert [t for t, _ in machine.history] == pytest.approx([0.0, 0.5, 0.7, 0.8])
    assert machine.entered_at == pytest.approx(0.8)
    assert machine.steps_into(["step"]) == 1
    assert machine.steps_into(["stand", "rest"]) == 3
    assert machine.steps_into([]) == 0


@pytest.mark.parametrize("seconds", [-1e-3, math.nan, math.inf])
def test_after_validates(seconds):
    with pytest.raises(va.InvalidInputError):
        events.after(seconds)


def test_after_fires_at_the_threshold():
    event = events.after(0.2)
    c = context(1.0)
    c.time_in_state = 0.19
    assert not event(c)
    c.time_in_state = 0.2
    assert event(c)


# -- events on frames and contacts --------------------------------------------------------------
def _world(name, q, frame):
    model = robot(name).model
    data = model.createData()
    pin.framesForwardKinematics(model, data, q)
    return data.oMf[model.getFrameId(frame)]


def test_ahead_of_on_the_turkey_standing_pose():
    q = robot(TURKEY).neutral()
    body, foot = _world(TURKEY, q, "body").translation, _world(TURKEY, q, "left_foot").translation
    assert foot[0] - body[0] == pytest.approx(0.1, abs=1e-9)
    c = context(q=q)
    assert events.ahead_of("left_foot", "body", 0.09)(c)
    assert not events.ahead_of("left_foot", "body", 0.11)(c)
    # the seed's "body nearly over the foot" is body - foot > -distance
    assert events.ahead_of("body", "left_foot", -0.11)(c)
    assert not events.ahead_of("body", "left_foot", -0.09)(c)
    assert events.ahead_of("body", "right_foot", 0.09)(c)
    assert not events.ahead_of("body", "right_foot", 0.11)(c)
    height = body[2] - foot[2]
    assert events.ahead_of("body", "left_foot", height - 1e-6, axis="z")(c)
    assert not events.ahead_of("body", "left_foot", height + 1e-6, axis="z")(c)
    assert events.ahead_of("left_foot", "right_foot", 0.1, axis="y")(c) == (
        foot[1] - _world(TURKEY, q, "right_foot").translation[1] > 0.1
    )


def test_ahead_of_follows_the_configuration():
    rob = robot(TURKEY)
    q = rob.neutral()
    q[rob.model.joints[rob.model.getJointId("boom_x")].idx_q] = 3.0  # moves body and feet alike
    assert events.ahead_of("left_foot", "body", 0.09)(context(q=q))
    q2 = q.copy()
    q2[rob.model.joints[rob.model.getJointId("boom_pitch")].idx_q] = 0.3  # lean: feet go back
    foot = (
        _world(TURKEY, q2, "left_foot").translation[0] - _world(TURKEY, q2, "body").translation[0]
    )
    assert events.ahead_of("left_foot", "body", foot - 1e-6)(context(q=q2))
    assert not events.ahead_of("left_foot", "body", foot + 1e-6)(context(q=q2))


@pytest.mark.parametrize("axis", ["rx", "w", "X"])
def test_ahead_of_axis_validated(axis):
    with pytest.raises(va.InvalidAxisError):
        events.ahead_of("body", "left_foot", 0.0, axis=axis)


def test_contact_events():
    both = context(contacts={"left_heel": True, "left_toe": True, "right_heel": False})
    heel_only = context(contacts={"left_heel": True, "left_toe": False, "right_heel": False})
    none = context(contacts={"left_heel": False, "left_toe": False, "right_heel": False})
    assert events.contact("left_heel", "left_toe")(both)
    assert not events.contact("left_heel", "left_toe")(heel_only)
    assert events.contact("left_heel", "left_toe", require_all=False)(heel_only)
    assert not events.contact("left_heel", "left_toe", require_all=False)(none)
    assert events.no_contact("left_heel", "left_toe")(none)
    assert not events.no_contact("left_heel", "left_toe")(heel_only)
    assert events.no_contact("right_heel")(both)
    with pytest.raises(va.InvalidInputError):
        events.contact()
    with pytest.raises(va.InvalidInputError):
        events.no_contact()


def test_combinators():
    c = context()
    assert events.any_of(never, always)(c)
    assert not events.any_of(never, never)(c)
    assert events.all_of(always, always)(c)
    assert not events.all_of(always, never)(c)
    assert events.all_of(events.any_of(never, always), events.when(always))(c)
    assert events.when(always) is always


def test_unknown_contact_switch_is_invalid_input():
    c = context(contacts={"left_heel": True, "right_heel": False})
    with pytest.raises(va.InvalidInputError, match="'left_hel'") as error:
        c.in_contact("left_hel")
    assert "'left_heel'" in str(error.value)
    with pytest.raises(va.InvalidInputError):
        events.contact("left_toe")(c)
    assert c.in_contact("left_heel") is True and c.in_contact("right_heel") is False


# -- the context's frame quantities --------------------------------------------------------------
@pytest.mark.parametrize(
    ("name", "frames"),
    [
        (TURKEY, ["body", "left_foot", "right_shin", "world"]),
        (FLAMINGO, ["left_toe", "right_heel", "body"]),
        ("solo12", ["base_link", "FL_FOOT", "HR_FOOT"]),
    ],
)
def test_context_frames_match_pinocchio(name, frames):
    rob = robot(name)
    model = rob.model
    rng = np.random.default_rng(11)
    eps = 1e-6
    for _ in range(3):
        q = random_configuration(rob, rng, scale=0.4)
        v = rng.uniform(-1.0, 1.0, model.nv)
        c = Context(rob, q, v, 0.0)
        for frame in frames:
            placement = _world(name, q, frame) if frame != "world" else pin.SE3.Identity()
            np.testing.assert_allclose(
                c.frame_position(frame), placement.translation, rtol=0, atol=1e-12
            )
            np.testing.assert_allclose(
                c.frame_rotation(frame), placement.rotation, rtol=0, atol=1e-12
            )
            if frame == "world":
                continue
            plus = _world(name, pin.integrate(model, q, eps * v), frame).translation
            minus = _world(name, pin.integrate(model, q, -eps * v), frame).translation
            np.testing.assert_allclose(
                c.frame_velocity(frame), (plus - minus) / (2 * eps), rtol=0, atol=1e-8
            )


def test_context_of_tick_is_the_constructed_context():
    """The tick's shortcut gives the context the constructor gives, or its checks' errors."""
    rob = robot(TURKEY)
    rng = np.random.default_rng(3)
    q = random_configuration(rob, rng, scale=0.4)
    v = rng.uniform(-1.0, 1.0, rob.model.nv)
    snapshot = va.Snapshot(rob, q, v)
    switches = {"left_foot": True}
    for contacts in (None, switches):
        fast = Context.of_tick(rob, snapshot, 0.25, contacts)
        slow = Context(rob, q, v, 0.25, contacts, snapshot=snapshot)
        assert fast.snapshot is slow.snapshot is snapshot
        assert fast.q is slow.q and fast.v is slow.v and fast.time == slow.time == 0.25
        assert fast.contacts == slow.contacts and fast.contacts is not contacts
        assert (fast.state, fast.time_in_state) == (slow.state, slow.time_in_state)
        for frame in ("body", "left_foot", "left_shin"):  # tabled or not
            assert np.array_equal(fast.frame_position(frame), slow.frame_position(frame))
    for time in (math.nan, "0.1"):
        with pytest.raises(va.InvalidInputError, match="time"):
            Context.of_tick(rob, snapshot, time, None)
    with pytest.raises(va.InvalidInputError, match="contacts"):
        Context.of_tick(rob, snapshot, 0.0, [("left_foot", True)])
    with pytest.raises(va.InvalidInputError, match="snapshot"):
        Context.of_tick(rob, va.Snapshot(robot(FLAMINGO), robot(FLAMINGO).neutral()), 0.0, None)


def test_frame_reads_by_name_read_the_frame_by_id():
    """A frame read by name (its tabled row) and by id (the tree's lookup) agree."""
    rob = robot(FLAMINGO)
    q = random_configuration(rob, np.random.default_rng(8), scale=0.4)
    early = va.Snapshot(rob, q)
    assert early.frame_table.shape[1] == 12  # computed before a frame is added to the table
    late_name = "right_toe"
    frame_id = rob.model.getFrameId(late_name)
    snapshot = va.Snapshot(rob, q)
    by_name = snapshot.frame_position(late_name)  # tabled now: a row of the kernel's output
    assert np.array_equal(by_name, snapshot.frame_position(frame_id))
    assert np.array_equal(early.frame_position(late_name), by_name)  # a row it lacks: computed
    by_name[:] = 9.0  # a copy
    assert not np.array_equal(snapshot.frame_position(late_name), by_name)
    v = np.random.default_rng(9).uniform(-1.0, 1.0, rob.model.nv)
    moving = va.Snapshot(rob, q, v)
    for frame in ("body", late_name):
        velocity = moving.frame_velocity(frame)
        assert np.array_equal(velocity, moving.frame_velocity(rob.model.getFrameId(frame)))
        velocity[:] = 9.0  # a copy
        assert not np.array_equal(moving.frame_velocity(frame), velocity)
    with pytest.raises(va.InvalidInputError, match="needs a snapshot built with v"):
        snapshot.frame_velocity("body")


def test_context_returns_copies():
    c = context()
    c.frame_position("body")[:] = 99.0
    c.frame_rotation("body")[:] = 0.0
    np.testing.assert_allclose(c.frame_position("body"), _world(TURKEY, c.q, "body").translation)
    np.testing.assert_allclose(c.frame_rotation("body"), np.eye(3), atol=1e-15)


def test_frame_pitch_on_the_turkey():
    rob = robot(TURKEY)
    model = rob.model
    rng = np.random.default_rng(12)

    def angle(q, joint):
        return q[model.joints[model.getJointId(joint)].idx_q]

    for _ in range(5):
        q = rob.neutral() + rng.uniform(-0.6, 0.6, model.nq)
        c = Context(rob, q, np.zeros(model.nv), 0.0)
        assert c.frame_pitch("body") == pytest.approx(angle(q, "boom_pitch"), abs=1e-12)
        thigh = angle(q, "boom_pitch") + angle(q, "left_hip")
        shin = thigh + angle(q, "left_knee")
        assert c.frame_pitch("left_thigh") == pytest.approx(thigh, abs=1e-12)
        assert c.frame_pitch("left_shin") == pytest.approx(shin, abs=1e-12)


def test_unknown_frame_in_context():
    c = context()
    for method in (c.frame_position, c.frame_rotation, c.frame_pitch, c.frame_velocity):
        with pytest.raises(va.FrameNotFoundError, match="left_foot"):
            method("left_fot")


def test_reprs():
    c = context(1.5, {"left_heel": True})
    assert repr(c) == "Context(time=1.5000, state=None, contacts={'left_heel': True})"
    assert repr(State("a", active=("x",))) == "State('a', active=('x',), support=())"
    assert repr(Transition("a", "b", always, "go")) == "Transition('a' -> 'b', 'go')"
    assert repr(Transition("a", "b", always)) == "Transition('a' -> 'b')"
    machine = StateMachine([State("a"), State("b")], [Transition("a", "b", always)], "a")
    assert repr(machine) == "StateMachine(states=['a', 'b'], transitions=1, current='a')"


# -- gait glue (gaits/base.py) ------------------------------------------------------------------
def two_link_fk(hip: float, knee: float, thigh: float, shin: float) -> tuple[float, float]:
    """Foot minus hip for joints about +y, legs hanging along -z at zero angles."""
    return (
        -thigh * math.sin(hip) - shin * math.sin(hip + knee),
        -thigh * math.cos(hip) - shin * math.cos(hip + knee),
    )


@pytest.mark.parametrize(("thigh", "shin"), [(0.3, 0.3), (0.42, 0.37), (0.2, 0.35)])
def test_planar_leg_ik_round_trip(thigh, shin):
    rng = np.random.default_rng(13)
    for _ in range(50):
        reach = rng.uniform(abs(thigh - shin) + 1e-3, thigh + shin - 1e-3)
        direction = rng.uniform(-math.pi, math.pi)
        dx, dz = reach * math.sin(direction), -reach * math.cos(direction)
        hip, knee = planar_leg_ik(dx, dz, thigh, shin)
        assert 0.0 <= knee <= math.pi  # the knee bends positively
        assert two_link_fk(hip, knee, thigh, shin) == pytest.approx((dx, dz), abs=1e-12)


def test_planar_leg_ik_folded_leg_is_reachable():
    hip, knee = planar_leg_ik(0.0, -0.06, 0.3, 0.24)
    assert knee == pytest.approx(math.pi, abs=1e-12)
    assert two_link_fk(hip, knee, 0.3, 0.24) == pytest.approx((0.0, -0.06), abs=1e-12)


@pytest.mark.parametrize(
    ("dx", "dz", "thigh", "shin"),
    [(0.0, -0.6, 0.3, 0.3), (0.6, 0.0, 0.3, 0.3), (0.0, -0.54, 0.3, 0.24)],
)
def test_planar_leg_ik_straight_leg_is_reachable(dx, dz, thigh, shin):
    hip, knee = planar_leg_ik(dx, dz, thigh, shin)
    assert knee == pytest.approx(0.0, abs=1e-6)
    assert two_link_fk(hip, knee, thigh, shin) == pytest.approx((dx, dz), abs=1e-12)


@pytest.mark.parametrize(
    ("dx", "dz", "thigh", "shin"),
    [
        (0.0, -0.61, 0.3, 0.3),
        (0.5, -0.5, 0.3, 0.3),
        (0.0, -0.6 - 1e-9, 0.3, 0.3),
        (0.05, -0.05, 0.4, 0.2),  # inside the inner circle |thigh - shin|
        (0.0, 0.0, 0.3, 0.24),
    ],
)
def test_planar_leg_ik_out_of_reach(dx, dz, thigh, shin):
    with pytest.raises(va.InvalidInputError, match="out of reach"):
        planar_leg_ik(dx, dz, thigh, shin)


def test_planar_leg_ik_matches_the_turkey_with_pinocchio():
    rob = robot(TURKEY)
    model = rob.model
    rng = np.random.default_rng(14)
    q = rob.neutral()
    for _ in range(10):
        dx, dz = rng.uniform(-0.2, 0.2), rng.uniform(-0.55, -0.35)
        hip, knee = planar_leg_ik(dx, dz, 0.3, 0.3)
        q[model.joints[model.getJointId("left_hip")].idx_q] = hip
        q[model.joints[model.getJointId("left_knee")].idx_q] = knee
        offset = (
            _world(TURKEY, q, "left_foot").translation - _world(TURKEY, q, "left_hip").translation
        )
        assert offset[[0, 2]] == pytest.approx((dx, dz), abs=1e-12)


@pytest.mark.parametrize("name", [TURKEY, FLAMINGO])
@pytest.mark.parametrize(
    ("height", "feet", "ground"),
    [
        (0.5, {"left": 0.1, "right": -0.1}, 0.0),
        (0.45, {"left": -0.05, "right": 0.15}, 0.0),
        (0.52, {"left": 0.2}, 0.3),
    ],
)
def test_planar_standing_configuration(name, height, feet, ground):
    rob = robot(name)
    model = rob.model
    q = planar_standing_configuration(rob, height, feet, ground=ground)
    assert q.shape == (model.nq,)
    body = _world(name, q, "body")
    assert body.translation[2] == pytest.approx(ground + height, abs=1e-12)
    assert Context(rob, q, np.zeros(model.nv), 0.0).frame_pitch("body") == pytest.approx(0.0)
    for side, dx in feet.items():
        hip = _world(name, q, f"{side}_hip").translation
        foot = _world(name, q, f"{side}_foot")
        assert foot.translation[0] - hip[0] == pytest.approx(dx, abs=1e-12)
        assert foot.translation[2] == pytest.approx(ground, abs=1e-12)
        if name == FLAMINGO:  # flat foot: no pitch, heel and toe on the ground
            rotation = foot.rotation
            assert math.atan2(rotation[0, 2], rotation[0, 0]) == pytest.approx(0.0, abs=1e-12)
            for end in ("heel", "toe"):
                assert _world(name, q, f"{side}_{end}").translation[2] == pytest.approx(
                    foot.translation[2], abs=1e-12
                )


def test_planar_standing_configuration_out_of_reach():
    with pytest.raises(va.InvalidInputError):
        planar_standing_configuration(robot(TURKEY), 0.7, {"left": 0.0})


class _BunnyGait(Gait):
    """Two states on the same attachment; the left leg is limp in the first."""

    def __init__(self, rob):
        super().__init__(rob)
        self.bunny = DogtrackBunny(0.5, 80.0)
        body = va.ParallelVirtualActuator(
            rob,
            "body",
            ["left_foot", "right_foot"],
            "world",
            ("x", "z", "ry"),
            design=[va.EqualTorque("left_hip", "right_hip")],
        )
        granny = GrannyWalker(0.5, (1000.0, 100.0), (10.0, 1.0), weight=50.0)
        self.controller.add("double", body, [granny, self.bunny])
        states = [
            State("wait", active=("double",), limp=("left_hip", "left_knee")),
            State("push", active=("double",)),
        ]
        transitions = [
            Transition("wait", "push", events.after(0.1)),
            Transition("push", "wait", events.after(0.1)),
        ]
        self._finish(StateMachine(states, transitions, "wait"))


def test_gait_resets_components_on_entry_and_applies_limp_joints():
    rob = robot(TURKEY)
    model = rob.model
    gait = _BunnyGait(rob)
    reference = Controller(rob, clip=True)
    reference.attachments = gait.controller.attachments
    q, v = rob.neutral(), np.zeros(model.nv)
    bx = model.joints[model.getJointId("boom_x")].idx_q
    limp = [model.joints[model.getJointId(j)].idx_v for j in ("left_hip", "left_knee")]

    q[bx] = 0.2
    out = gait.compute(q, v, 0.0)
    assert gait.state == "wait" and out.active == ("double",)
    assert (gait.bunny.start_position, gait.bunny.start_time) == (pytest.approx(0.2), 0.0)
    expected = reference.compute(q, v, 0.0).tau
    assert np.any(expected[limp] != 0.0)
    expected[limp] = 0.0
    np.testing.assert_array_equal(out.tau, expected)

    q[bx] = 0.7
    out = gait.compute(q, v, 0.15)
    assert gait.state == "push"
    assert (gait.bunny.start_position, gait.bunny.start_time) == (pytest.approx(0.7), 0.15)
    np.testing.assert_array_equal(out.tau, reference.compute(q, v, 0.15).tau)
    assert np.all(out.tau[limp] != 0.0)

    q[bx] = 0.9
    gait.compute(q, v, 0.2)  # still pushing: no reset
    assert gait.bunny.start_position == pytest.approx(0.7)
    assert gait.machine.history == [(0.0, "wait"), (0.15, "push")]
    assert gait.last is not None and repr(gait) == "_BunnyGait(robot='spring_turkey', state='push')"
