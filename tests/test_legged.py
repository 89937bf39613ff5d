"""The legged gait layer without physics: patterns, the tick wiring, gains in physical units."""

from __future__ import annotations

import numpy as np
import pytest

import virtual_actuators as va
from virtual_actuators.gaits.legged import LeggedParameters, LeggedWalker, named_pattern, npod
from virtual_actuators.gaits.legged.patterns import GaitPattern

QUAD = ("LF", "RF", "LH", "RH")
QUAD_XY = np.array([(0.3, 0.2), (0.3, -0.2), (-0.3, 0.2), (-0.3, -0.2)])
HEX = ("L1", "L2", "L3", "R1", "R2", "R3")
HEX_XY = np.array([(0.2, 0.1), (0.0, 0.12), (-0.2, 0.1), (0.2, -0.1), (0.0, -0.12), (-0.2, -0.1)])


def _as_sets(groups):
    return [set(group) for group in groups]


def test_trot_swings_diagonal_pairs_in_turn():
    pattern = named_pattern("trot", QUAD, QUAD_XY)
    assert _as_sets(pattern.groups()) == [{"LF", "RH"}, {"RF", "LH"}]
    assert set(pattern.swinging(0.1)) == {"LF", "RH"}
    assert set(pattern.swinging(0.6)) == {"RF", "LH"}
    assert set(pattern.swinging(1.1)) == {"LF", "RH"}  # the cycle repeats


def test_pace_swings_one_side_then_the_other():
    pattern = named_pattern("pace", QUAD, QUAD_XY)
    assert _as_sets(pattern.groups()) == [{"LF", "LH"}, {"RF", "RH"}]


def test_walk_lifts_one_foot_at_a_time_in_the_lateral_sequence():
    pattern = named_pattern("walk", QUAD, QUAD_XY)
    assert pattern.groups() == (("LH",), ("LF",), ("RH",), ("RF",))
    order = [pattern.swinging(k / 4 + 0.01) for k in range(4)]
    assert order == [("LH",), ("LF",), ("RH",), ("RF",)]


def test_tripod_alternates_along_each_side_and_across():
    pattern = named_pattern("tripod", HEX, HEX_XY)
    assert _as_sets(pattern.groups()) == [{"L1", "L3", "R2"}, {"R1", "R3", "L2"}]



def test_each_pattern_takes_the_feet_it_needs_and_names_the_others():
    """One rule for all (issue 35: a tripod was taken on four legs, a trot refused on six): a trot
    needs two feet a side, a tripod three or more a side, a pace one or more a side."""
    from virtual_actuators.gaits.legged.patterns import fitting_patterns

    assert fitting_patterns(QUAD, QUAD_XY) == ("trot", "pace", "walk")
    assert fitting_patterns(HEX, HEX_XY) == ("pace", "walk", "tripod")
    assert fitting_patterns(QUAD[:2], QUAD_XY[:2]) == ("pace", "walk")  # one foot a side
    assert fitting_patterns(("LF", "LH"), QUAD_XY[[0, 2]]) == ("walk",)  # both on the left
    with pytest.raises(va.GaitPatternError, match="three feet or more on each side") as error:
        named_pattern("tripod", QUAD, QUAD_XY)
    assert "the gaits that fit them are trot, pace, walk" in str(error.value)
    with pytest.raises(va.GaitPatternError, match="two feet on each side") as error:
        named_pattern("trot", HEX, HEX_XY)
    assert "3 on the left (L1, L2, L3)" in str(error.value)
    assert "the gaits that fit them are pace, walk, tripod" in str(error.value)
    assert isinstance(error.value, va.InvalidInputError)  # what it always was


@pytest.mark.parametrize("name", ["trot", "pace", "walk", "tripod"])
def test_every_foot_swings_once_per_cycle(name):
    feet, xy = (HEX, HEX_XY) if name == "tripod" else (QUAD, QUAD_XY)
    pattern = named_pattern(name, feet, xy)
    swung = [foot for group in pattern.groups() for foot in group]
    assert sorted(swung) == sorted(feet)
    phases = np.linspace(0.0, 1.0, 400, endpoint=False)
    for foot in feet:
        # its swing is one contiguous slot of 1 / groups of the cycle
        swinging = np.array([foot in pattern.swinging(p) for p in phases])
        assert swinging.mean() == pytest.approx(1.0 / len(pattern.groups()), abs=1e-9)
        assert np.count_nonzero(np.diff(swinging.astype(int)) == 1) <= 1


def test_npod_takes_groups_as_data_and_rejects_bad_ones():
    pattern = npod([["a", "b"], ["c"], ["d", "e", "f"]])
    assert pattern.groups() == (("a", "b"), ("c",), ("d", "e", "f"))
    assert pattern.offsets["c"] == pytest.approx(1 / 3)
    with pytest.raises(va.InvalidInputError, match="two groups"):
        npod([["a"], ["a", "b"]])
    with pytest.raises(va.InvalidInputError, match=r"\[0, 1\)"):
        GaitPattern("bad", {"a": 0.0, "b": 1.0})
    with pytest.raises(va.InvalidInputError, match="Unknown gait pattern"):
        named_pattern("gallop", QUAD, QUAD_XY)


def test_machine_controller_is_the_gait_tick():
    """MachineController: the state's attachments, limp joints and resets, as written by hand."""
    robot = va.load_robot("solo12")
    controller = va.Controller(robot)
    spring = va.SpringDamper(("x", "y", "z"), 300.0, 5.0)
    controller.add("leg", va.VirtualActuator(robot, "FL_FOOT", "base_link", "world"), [spring])
    controller.add("other", va.VirtualActuator(robot, "FR_FOOT", "base_link", "world"),
                   [va.SpringDamper(("x", "y", "z"), 100.0, 1.0)])
    states = [va.State("a", ("leg",), limp=("FL_KFE",)), va.State("b", ("leg", "other"))]
    machine = va.StateMachine(states, [va.Transition("a", "b", va.events.after(0.01))], "a")
    wiring = va.MachineController(controller, machine)
    q, v = robot.neutral(), np.zeros(robot.model.nv)
    first = wiring.compute(q, v, 0.0)
    assert first.active == ("leg",)
    knee = controller.joint_indices("FL_KFE")
    assert first.tau[knee] == 0.0
    hand = controller.compute(q, v, 0.0, ["leg"], knee)
    assert np.array_equal(first.tau, hand.tau)
    later = wiring.compute(q, v, 0.02)
    assert wiring.state.name == "b" and later.active == ("leg", "other")
    with pytest.raises(va.InvalidInputError, match="not an attachment"):
        va.MachineController(controller, va.StateMachine([va.State("c", ("nope",))], [], "c"))


def test_gains_scale_with_mass_and_inertia():
    """The same choices give each robot its own gains: stiffness m w^2, damping 2 zeta m w."""
    parameters = LeggedParameters()
    small, large = (LeggedWalker(va.load_robot(name)) for name in ("solo12", "anymal"))
    w = 2 * np.pi * parameters.frequency
    for walker in (small, large):
        mass = walker.robot.mass
        assert walker.gains.stiffness_z == pytest.approx(mass * w * w)
        assert walker.gains.damping_z == pytest.approx(2 * parameters.damping_ratio * mass * w)
        assert walker.gains.time_scale == pytest.approx(np.sqrt(walker.stand_height / 9.81))
    ratio = large.robot.mass / small.robot.mass
    assert large.gains.stiffness_z / small.gains.stiffness_z == pytest.approx(ratio)
    # the stance is centred under the centre of mass
    for walker in (small, large):
        assert np.allclose(walker.nominal.mean(axis=0), 0.0, atol=1e-12)


def test_walker_rejects_what_it_cannot_walk():
    robot = va.load_robot("solo12")
    with pytest.raises(va.InvalidInputError, match="two or more feet"):
        LeggedWalker(robot, feet=["FL_FOOT"], body="base_link")
    with pytest.raises(va.FrameNotFoundError):
        LeggedWalker(robot, feet=["FL_FOOT", "nope"])
    with pytest.raises(va.InvalidInputError, match="not the walker's"):
        LeggedWalker(robot, pattern=npod([["FL_FOOT"], ["FR_FOOT"]]))
    walker = LeggedWalker(robot)
    with pytest.raises(va.InvalidInputError, match="finite"):
        walker.set_command((float("nan"), 0.0), 0.0)


def _swing_oracle(start, nominal, body, motion, shape):
    """The swing set point from the definitions (module docstring of ``footholds``), numpy."""
    com = body[:3]
    vx, vy, ex, ey, wz, yaw, elapsed, ground = motion
    swing_time, stance_time, capture, reach, lift, peak, depth, _ = shape

    def turn(angle):
        return np.array([[np.cos(angle), -np.sin(angle)], [np.sin(angle), np.cos(angle)]])

    def smooth(s):
        s = np.clip(s, 0.0, 1.0)
        return s * s * (3.0 - 2.0 * s)

    phase = elapsed / swing_time
    remaining = max(0.0, swing_time - elapsed)
    centre = com[:2] + remaining * turn(yaw) @ np.array([vx, vy])
    half = 0.5 * stance_time
    move = turn(wz * half) @ nominal - nominal + np.array([vx, vy]) * half
    move = move + capture * np.array([ex, ey])
    move *= min(1.0, reach / np.linalg.norm(move))
    land = centre + turn(yaw + wz * remaining) @ (nominal + move)
    land_z = ground - depth * (1.0 + 4.0 * max(0.0, phase - 1.0))
    s = np.clip(phase, 0.0, 1.0)
    up = 0.5 * np.pi * (s / peak if s < peak else (s - peak) / (1 - peak))
    rise = np.sin(up) if s < peak else np.cos(up)
    point = np.empty(3)
    point[:2] = start[:2] + (land - start[:2]) * smooth(min(1.0, 1.25 * phase))
    point[2] = start[2] + (land_z - start[2]) * smooth(phase) + lift * rise
    return point


@pytest.mark.parametrize("elapsed", [0.0, 0.07, 0.16, 0.25, 0.3])
def test_swing_set_points_follow_the_foothold_and_the_curve(elapsed):
    """The set points against the definitions, one tick then the next (the rate)."""
    from virtual_actuators.gaits.legged.hooks import swing_setpoint

    rng = np.random.default_rng(3)
    shape = (0.25, 0.4, 0.12, 0.1, 0.05, 0.4, 0.004, 0.02)  # touchdown at 0.25 s
    starts = rng.normal(size=(2, 3)) * 0.1
    body = rng.normal(size=12) * 0.2  # centre of mass, origin, velocity, angular velocity
    base, linear, angular = body[3:6], body[6:9], body[9:]
    for foot, start in zip(("LF", "RH"), starts, strict=True):
        index = QUAD.index(foot)
        state, previous = (*start.tolist(), *start.tolist(), 0.0, 0.0, 0.0), None
        for tick, dt in enumerate((0.0, 0.001)):  # the first at rest (no time since the last)
            motion = (0.5, 0.1, 0.05, -0.02, 0.3, 0.4, elapsed + dt, -0.01)
            nominal = tuple(QUAD_XY[index].tolist())
            state, setpoints = swing_setpoint(state, nominal, tuple(body.tolist()), motion, dt,
                                              shape)  # fmt: skip
            point = _swing_oracle(start, QUAD_XY[index], body, np.array(motion), shape)
            # the second tick's rate: the new one low-passed, dt / filter of it
            rate = 0.05 * (point - previous) / 0.001 if tick else np.zeros(3)
            spin = rate - linear - np.cross(angular, point - base)
            np.testing.assert_allclose(setpoints[:3], point - base, atol=1e-12)
            np.testing.assert_allclose(setpoints[3:], spin, atol=1e-9)
            np.testing.assert_allclose(state[3:6], point, atol=1e-12)
            if elapsed == 0.0 and tick == 0:  # lift-off: where the foot is
                np.testing.assert_allclose(np.add(setpoints[:3], base), start, atol=1e-15)
            previous = point


def test_heading_angles_are_those_of_pinocchios_exp3():
    """The body model's angles from the rotation vector: the same bits as from ``pin.exp3``."""
    import pinocchio as pin
    from oracles import yaw_pitch_roll

    from virtual_actuators.gaits.attitude import rotation_vector_angles as heading_angles

    rng = np.random.default_rng(5)
    vectors = [rng.normal(size=3) * scale for scale in (1e-9, 1e-5, 1e-3, 0.3, 1.0, 3.0)]
    for vector in [*vectors, np.zeros(3), np.array([0.0, 0.0, np.pi - 1e-9])]:
        assert heading_angles(*vector.tolist()) == yaw_pitch_roll(pin.exp3(vector))


def test_two_feet_give_way_along_the_horizontal_force_only():
    """The missing direction spans what numpy's SVD of the point forces leaves out; the request
    given way is orthogonal to it, changed along x and y only (to rounding), and unchanged where
    producible."""
    from virtual_actuators.gaits.legged.body import give_way, missing_direction

    rng = np.random.default_rng(6)
    for _ in range(50):
        body, first, second = rng.normal(size=(3, 3))
        missing = np.array(missing_direction(body.tolist(), first.tolist(), second.tolist()))
        columns = np.zeros((6, 6))  # unit forces at each foot and their moments about the body
        for k, foot in enumerate((first, second)):
            for axis in range(3):
                force = np.eye(3)[axis]
                columns[:, 3 * k + axis] = np.r_[force, np.cross(foot - body, force)]
        u, s, _ = np.linalg.svd(columns)
        assert int(np.sum(s > 1e-9 * s[0])) == 5
        assert abs(abs(u[:, 5] @ missing) - 1.0) < 1e-12
        wrench = rng.normal(size=6) * 10.0
        out = np.array(give_way(wrench.tolist(), missing.tolist(), (0, 1)))
        assert abs(missing @ out) < 1e-12 * np.linalg.norm(wrench)
        scale = 1e-12 * np.linalg.norm(wrench)  # the rounding projected out last
        np.testing.assert_allclose(out[2:], wrench[2:], rtol=0.0, atol=scale)
        producible = wrench - missing * (missing @ wrench)
        given = give_way(producible.tolist(), missing.tolist(), (0, 1))
        np.testing.assert_allclose(given, producible, rtol=0.0, atol=scale)
    assert missing_direction((0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (1.0, 0.0, 0.0)) == (0.0,) * 6
    wrench = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0]
    assert give_way(wrench, (0.0,) * 6, (0, 1)) == wrench  # nothing missing: as it is
