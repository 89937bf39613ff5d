"""The walking tick's fast paths agree with the general ones they replace.

- `Context.frame_coordinate` against the frame positions Pinocchio's forward kinematics give
  (run in the test), for a frame of the snapshot's table and for one outside it;
- the contact scan (a role per geom; read in place by the compiled core when it was built with
  MuJoCo's headers) against a scan of MuJoCo's contact list written out here from the model's
  terrain and robot geoms, and the fall test's "a part other than a foot touches" against the
  touching frames' names, with the core's view and without it;
- the stance-force reader's support bookkeeping (kept while the support set stays) against the
  definition (every foot's entry time re-derived at every sample);
- the state machine's compiled exits against the transitions' declaration order.
"""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin
import pytest

import virtual_actuators as va
from virtual_actuators.control import Context, State, StateMachine, Transition, events
from virtual_actuators.core import CORE
from virtual_actuators.experiments.contact_stats import SETTLE_TIME, StanceForces
from virtual_actuators.gaits.runner import FOOT_WORDS, foot_geoms
from virtual_actuators.simulation import Simulator, contact_queries
from virtual_actuators.simulation.terrain import Terrain


def test_frame_coordinate_equals_forward_kinematics():
    robot = va.load_robot("spring_flamingo")
    rng = np.random.default_rng(3)
    q = robot.neutral() + 0.05 * rng.normal(size=robot.model.nq)
    context = Context(robot, q, np.zeros(robot.model.nv), 0.0)
    data = robot.model.createData()
    pin.framesForwardKinematics(robot.model, data, q)
    tabled = set(context.snapshot.tree.name_rows)
    frames = ["body", "left_foot", "right_toe"]
    untabled = [f.name for f in robot.model.frames if f.name not in tabled]
    assert untabled, "every frame is tabled: the general path is not exercised"
    for frame in [*frames, untabled[0]]:
        expected = data.oMf[robot.model.getFrameId(frame)].translation
        for index, axis in enumerate("xyz"):
            value = context.frame_coordinate(frame, axis)
            assert value.__class__ is float
            assert value == context.frame_position(frame)[index]  # the same read, bit for bit
            assert math.isclose(value, expected[index], rel_tol=1e-12, abs_tol=1e-12)


@pytest.mark.parametrize("axis", ["w", 0, None, "X"])
def test_frame_coordinate_refuses_an_unknown_axis(axis):
    robot = va.load_robot("spring_turkey")
    context = Context(robot, robot.neutral(), np.zeros(robot.model.nv), 0.0)
    with pytest.raises(va.InvalidAxisError, match="'x', 'y' or 'z'"):
        context.frame_coordinate("body", axis)


def test_frame_coordinate_names_an_unknown_frame():
    robot = va.load_robot("spring_turkey")
    context = Context(robot, robot.neutral(), np.zeros(robot.model.nv), 0.0)
    with pytest.raises(va.FrameNotFoundError):
        context.frame_coordinate("no_such_frame", "x")


def _reference_scan(simulator: Simulator) -> list[tuple[int, int, float]]:
    """Robot-terrain contacts straight from MuJoCo's contact list (the definition)."""
    mm = simulator.mujoco_model
    terrain, robot_geoms = mm.terrain_geoms, set(mm.geom_frames) - set(mm.terrain_geoms)
    hits = []
    for i in range(simulator.data.ncon):
        contact = simulator.data.contact[i]
        if contact.exclude != 0:
            continue
        g1, g2 = (int(g) for g in contact.geom)
        if g1 in terrain and g2 in robot_geoms:
            hits.append((i, g2, 1.0))
        elif g2 in terrain and g1 in robot_geoms:
            hits.append((i, g1, -1.0))
    return hits


@pytest.mark.parametrize("name", ["spring_flamingo", "spring_turkey"])
def test_contact_scan_equals_the_definition(name):
    robot = va.load_robot(name)
    simulator = Simulator(robot, Terrain.builtin("profile-one"))
    seen = 0
    for _ in range(300):  # falling limp: feet, knees and body reach the ground
        simulator.step(np.zeros(robot.model.nv))
        hits = simulator._scan_contacts()
        assert hits == _reference_scan(simulator)
        seen += len(hits)
    assert seen > 0


@pytest.mark.parametrize("name", ["spring_flamingo", "spring_turkey", "hexapod"])
@pytest.mark.parametrize("view", [True, False])
def test_fall_contact_test_equals_the_touching_terrain_names(name, view):
    robot = va.load_robot(name)
    simulator = Simulator(robot, Terrain.builtin("profile-one"))
    if not view:
        simulator._contact_view = None  # the Python scan
    elif simulator._contact_view is None:
        pytest.skip("the compiled core reads no MuJoCo contact list here")
    feet = foot_geoms(simulator)
    answers = set()
    for _ in range(400):  # falling limp: feet first, then knees and body
        simulator.step(np.zeros(robot.model.nv))
        frames = simulator.touching_terrain()
        expected = not all(any(word in frame for word in FOOT_WORDS) for frame in frames)
        assert simulator.touches_outside(feet) == expected
        answers.add(expected)
    assert answers == {False, True}


def test_grouped_contact_forces_equal_mujocos_contact_force():
    """The core's rows (mj_contactForce called in place) against the Python loop's, exactly."""
    robot = va.load_robot("spring_flamingo")
    simulators = [Simulator(robot, Terrain.builtin("profile-one")) for _ in range(2)]
    simulators[1]._contact_view = None  # the Python loop
    mm = simulators[0].mujoco_model
    groups = np.full(simulators[0].model.ngeom, -1, dtype=np.int64)
    for index, frame in enumerate(("left_heel", "left_toe", "right_heel", "right_toe")):
        groups[list(mm.frame_geoms[frame])] = index
    seen = 0
    for _ in range(300):  # falling limp onto the slope
        for simulator in simulators:
            simulator.step(np.zeros(robot.model.nv))
        rows = [simulator.grouped_contact_forces(groups) for simulator in simulators]
        assert rows[0] == rows[1]
        for group, normal, *_ in rows[0]:
            assert group in (0.0, 1.0, 2.0, 3.0) and normal >= 0.0
        seen += len(rows[0])
    assert seen > 0


def test_no_core_view_of_another_mujoco_version(monkeypatch):
    robot = va.load_robot("spring_turkey")
    simulator = Simulator(robot)
    if CORE is None or not getattr(CORE, "MJ_VERSION", 0):
        pytest.skip("the compiled core reads no MuJoCo contact list here")
    monkeypatch.setattr(contact_queries.mujoco, "mj_version", lambda: CORE.MJ_VERSION + 1)
    roles = [0] * simulator.model.ngeom
    assert contact_queries.contact_view(simulator.model, simulator.data, roles) is None


class _ReferenceSettle:
    """The settled feet by the definition: entry times re-derived at every sample."""

    def __init__(self) -> None:
        self.since: dict[tuple[str, ...], float] = {}

    def settle(self, feet, now: float) -> tuple[tuple[str, ...], ...]:
        self.since = {foot: self.since.get(foot, now) for foot in map(tuple, feet)}
        return tuple(f for f, t in self.since.items() if now - t >= SETTLE_TIME - 1e-9)


def test_stance_bookkeeping_equals_the_definition():
    robot = va.load_robot("spring_flamingo")
    stance = StanceForces(Simulator(robot))
    reference = _ReferenceSettle()
    left, right = ("left_heel", "left_toe"), ("right_heel", "right_toe")
    rng = np.random.default_rng(5)
    supports = [[left], [right], [left, right], [right, left], [], [list(left)], (left, right)]
    now = 0.0
    for _ in range(600):
        if rng.random() < 0.05:  # a new support set now and then, held for a while
            supports.append(supports.pop(int(rng.integers(len(supports)))))
        feet = supports[-1]
        now += 0.004
        assert stance._settle(feet, now) == reference.settle(feet, now)


def test_state_machine_takes_the_first_firing_transition_in_declaration_order():
    robot = va.load_robot("spring_turkey")
    states = [State("a"), State("b"), State("c")]
    transitions = [
        Transition("a", "c", events.after(0.5)),
        Transition("a", "b", events.after(0.2)),
        Transition("b", "a", events.after(0.1)),
    ]
    machine = StateMachine(states, transitions, "a")
    q, v = robot.neutral(), np.zeros(robot.model.nv)
    visited = []
    for tick in range(1000):
        visited.append(machine.update(Context(robot, q, v, tick * 1e-3)).name)
    assert "c" not in visited  # a -> b fires first (0.2 s) every time
    entries = [name for _, name in machine.history]
    assert entries[:4] == ["a", "b", "a", "b"]
    times = [t for t, _ in machine.history]
    assert np.allclose(np.diff(times)[:4], [0.2, 0.1, 0.2, 0.1], atol=1.5e-3)
