"""The control tick's fast paths against the checked (numpy) paths they stand in for.

Every fast path must give the same bits as the path it skips (the walks' trajectories may not
move), and anything it does not handle must take the checked path with its typed error.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import virtual_actuators as va
from virtual_actuators.actuators.serial import wrench_array
from virtual_actuators.components.walking import GrannyWalker
from virtual_actuators.exceptions import InvalidInputError
from virtual_actuators.gaits.planar_walk import RECORD_EVERY
from virtual_actuators.kinematics.snapshot import Snapshot
from virtual_actuators.simulation import Simulator
from virtual_actuators.simulation.conversions import (
    configuration_from_mujoco,
    gathers,
    torques_to_ctrl,
    velocity_from_mujoco,
)
from virtual_actuators.simulation.terrain import Terrain

AXES3 = ("x", "z", "ry")


def _array_formula(spring: va.SpringDamper, position: np.ndarray, velocity: np.ndarray):
    """The component formula written with numpy arrays (the reference of the float path).

    The one rotational axis (``ry``) takes the angle difference wrapped to ``[-pi, pi]``.
    """
    deflection = spring.setpoint - position
    if abs(deflection[2]) > math.pi:
        deflection[2] = math.remainder(deflection[2], 2.0 * math.pi)
    wrench = spring.stiffness * deflection + spring.damping * (spring.velocity_setpoint - velocity)
    wrench = np.minimum(np.maximum(wrench, -spring.limit), spring.limit)
    return wrench + spring.force


@pytest.mark.parametrize("seed", range(5))
def test_spring_damper_float_path_gives_the_array_formula_bits(seed):
    rng = np.random.default_rng(seed)
    for limit in (np.inf, rng.uniform(0.1, 5.0, 3)):
        spring = va.SpringDamper(
            AXES3,
            stiffness=rng.uniform(0, 1e3, 3),
            damping=rng.uniform(0, 50, 3),
            setpoint=rng.normal(size=3),
            velocity_setpoint=rng.normal(size=3),
            force=rng.normal(size=3) * 10,
            limit=limit,
        )
        for _ in range(50):
            position, velocity = rng.normal(size=3), rng.normal(size=3) * 3
            fast = spring.compute_wrench(position, velocity, 0.0)
            assert type(fast) is np.ndarray and fast.dtype == np.float64
            np.testing.assert_array_equal(fast, _array_formula(spring, position, velocity))
        # other inputs (lists, ints, a float32 array) take the array path: same values
        np.testing.assert_allclose(
            spring.compute_wrench([0.1, 0.2, 0.3], [0, 0, 0], 0.0),
            _array_formula(spring, np.array([0.1, 0.2, 0.3]), np.zeros(3)),
            rtol=1e-15,
        )


def test_parameters_changed_in_place_are_seen_by_the_float_path():
    spring = va.SpringDamper(("x", "z"), stiffness=10.0, setpoint=(1.0, 2.0))
    spring.setpoint[1] = 5.0  # an in-place edit of the returned array
    np.testing.assert_array_equal(spring.compute_wrench(np.zeros(2), np.zeros(2), 0.0), [10, 50])


def test_per_axis_fast_paths_keep_the_checks():
    spring = va.SpringDamper(("x", "z"))
    spring.setpoint = (1, np.float64(2.0))
    assert spring.setpoint.dtype == np.float64 and spring.setpoint.tolist() == [1.0, 2.0]
    spring.setpoint = (1e308, 1e308)  # the sum overflows: the checked path accepts it
    assert spring.setpoint.tolist() == [1e308, 1e308]
    spring.setpoint = 0.25
    assert spring.setpoint.tolist() == [0.25, 0.25]
    for bad in ((np.nan, 0.0), (np.inf, 0.0), np.array([0.0, np.nan]), np.nan, None, "x"):
        with pytest.raises(InvalidInputError):
            spring.setpoint = bad
    spring.limit = (np.inf, 1.0)
    assert spring.limit.tolist() == [np.inf, 1.0]
    with pytest.raises(InvalidInputError):
        spring.limit = (np.nan, 1.0)


def test_wrench_array_fast_path_and_its_errors():
    wrench = np.array([1.0, -2.0, 3.0])
    assert wrench_array(wrench, AXES3) is wrench
    np.testing.assert_array_equal(
        wrench_array(np.array([1e308, 1e308, 0.0]), AXES3), [1e308] * 2 + [0]
    )
    for bad in (np.array([1.0, np.nan, 0.0]), np.array([np.inf, 0.0, 0.0]), np.zeros(2)):
        with pytest.raises(InvalidInputError):
            wrench_array(bad, AXES3)


@pytest.mark.parametrize("seed", range(3))
def test_terrain_height_of_one_number_is_numpys_interp(seed):
    rng = np.random.default_rng(seed)
    terrains = [Terrain.flat(0.3), Terrain.builtin("profile-one"), Terrain.builtin("profile-two")]
    terrains.append(Terrain([(0.0, 1.0)]))
    for terrain in terrains:
        xs = terrain.points[:, 0]
        samples = np.concatenate(
            (xs, rng.uniform(xs[0] - 3, xs[-1] + 3, 200), [np.nextafter(xs[0], -1), -1e9])
        )
        for x in samples:
            expected = np.interp(x, terrain.points[:, 0], terrain.points[:, 1])
            for value in (float(x), np.float64(x)):
                height = terrain.height(value)
                assert type(height) is float and height == expected
        assert np.isnan(terrain.height(float("nan")))
        np.testing.assert_array_equal(
            terrain.height(samples), np.interp(samples, terrain.points[:, 0], terrain.points[:, 1])
        )


@pytest.mark.parametrize("robot", ["spring_turkey", "spring_flamingo", "solo12"])
def test_conversion_gathers_equal_the_joint_by_joint_maps(robot):
    simulator = Simulator(va.load_robot(robot))
    mm = simulator.mujoco_model
    maps = gathers(mm)
    rng = np.random.default_rng(0)
    qpos = simulator.data.qpos + 0.01 * rng.normal(size=simulator.model.nq)
    qvel = rng.normal(size=simulator.model.nv)
    if maps.direct_q is not None:  # the joint-by-joint map, written out here
        q = np.zeros(mm.robot.model.nq)
        for joint in mm.joints:
            a, i = joint.qpos_adr, joint.idx_q
            if joint.kind == "free":  # a direct gather only when the placement is the identity
                assert joint.placement.isIdentity()
                q[i : i + 3] = qpos[a : a + 3]
                q[i + 3 : i + 7] = qpos[[a + 4, a + 5, a + 6, a + 3]]  # wxyz -> xyzw
            elif joint.kind == "ball":
                q[i : i + 4] = qpos[[a + 1, a + 2, a + 3, a]]
            else:  # a direct gather has no continuous joint
                assert joint.kind in ("hinge", "slide")
                q[i] = qpos[a]
        np.testing.assert_array_equal(configuration_from_mujoco(mm, qpos), q)
    if maps.direct_v is not None:
        v = np.zeros(mm.robot.model.nv)
        for joint in mm.joints:  # no free joint
            v[joint.idx_v : joint.idx_v + joint.nv] = qvel[joint.dof_adr : joint.dof_adr + joint.nv]
        np.testing.assert_array_equal(velocity_from_mujoco(mm, qpos, qvel), v)
    actuated = [joint for joint in mm.joints if joint.actuator is not None]
    actuated_v = [joint.idx_v for joint in actuated]
    tau = np.zeros(mm.robot.model.nv)
    tau[actuated_v] = rng.normal(size=len(actuated_v))
    ctrl = np.zeros(simulator.model.nu)
    ctrl[[joint.actuator for joint in actuated]] = tau[actuated_v]
    np.testing.assert_array_equal(torques_to_ctrl(mm, tau), ctrl)
    if maps.unactuated_v.size:
        tau[maps.unactuated_v[0]] = 1e-6  # more than the tolerance on an unactuated dof
        with pytest.raises(InvalidInputError, match="no actuator"):
            torques_to_ctrl(mm, tau)
        np.testing.assert_array_equal(torques_to_ctrl(mm, tau, ignore_unactuated=True), ctrl)
        tau[maps.unactuated_v[0]] = 1e-10  # within it
        np.testing.assert_array_equal(torques_to_ctrl(mm, tau), ctrl)


def test_turkey_direct_gathers_are_used():
    maps = gathers(Simulator(va.load_robot("spring_turkey")).mujoco_model)
    assert maps.direct_q is not None and maps.direct_v is not None
    assert maps.direct_ctrl is not None


def test_cached_contact_queries_equal_a_fresh_scan():
    robot = va.load_robot("spring_flamingo")
    simulator = Simulator(robot, Terrain.builtin("profile-one"))
    frames = ("left_heel", "left_toe", "right_heel", "right_toe", "body")
    for _ in range(200):
        simulator.step(np.zeros(robot.model.nv))
        for _ in range(2):  # the second round reads the cache
            for frame in frames:
                geoms = simulator._frame_geoms(frame)
                fresh_switch = any(g in geoms for _, g, _ in simulator._scan_contacts())
                assert simulator.in_contact(frame) == fresh_switch
        touching = simulator.touching_terrain()
        owners = simulator.mujoco_model.geom_frames
        fresh = {n for _, g, _ in simulator._scan_contacts() for n in owners[g]}
        assert touching == fresh
        touching.add("not a frame")  # the caller's copy: the next answer is unchanged
        assert "not a frame" not in simulator.touching_terrain()
    assert simulator.in_contact("left_heel") or simulator.in_contact("right_heel")
    with pytest.raises(va.FrameNotFoundError):
        simulator.in_contact("no_such_frame")


def test_frame_velocity_equals_the_array_formula():
    robot = va.load_robot("spring_flamingo")
    rng = np.random.default_rng(1)
    q = robot.neutral() + 0.05 * rng.normal(size=robot.model.nq)
    v = rng.normal(size=robot.model.nv)
    snapshot = Snapshot(robot, q, v)
    for frame in ("body", "left_foot", "right_toe"):
        frame_id = snapshot.tree.frame_id(frame)
        x, y, z = snapshot.placement(frame_id)[1]
        columns = snapshot.tree.frame_columns(frame_id)
        vx, vy, vz, wx, wy, wz = snapshot.jacobian_world[:, columns] @ v[columns]
        expected = np.array((vx + wy * z - wz * y, vy + wz * x - wx * z, vz + wx * y - wy * x))
        # the compiled kernel sums the columns in its own order: equal to rounding
        np.testing.assert_allclose(snapshot.frame_velocity(frame), expected, rtol=0, atol=1e-14)
        np.testing.assert_array_equal(
            snapshot.frame_velocity(frame_id), snapshot.frame_velocity(frame)
        )
        expected = snapshot.frame_velocity(frame)
        first = snapshot.frame_velocity(frame)
        first[:] = 0.0  # a copy: the cache is unchanged
        np.testing.assert_array_equal(snapshot.frame_velocity(frame), expected)


def test_contact_switches_and_touching_terrain_equal_a_scan_of_mujocos_contacts():
    robot = va.load_robot("spring_flamingo")
    simulator = Simulator(robot, Terrain.builtin("profile-one"))
    mm = simulator.mujoco_model
    frames = ("left_heel", "left_toe", "right_heel", "right_toe", "body")
    rng = np.random.default_rng(3)
    seen = set()
    for tick in range(300):
        tau = np.zeros(robot.model.nv)
        tau[3:] = 20.0 * rng.normal(size=robot.model.nv - 3)  # kick the legs about
        simulator.step(tau)
        data = simulator.data
        touched = set()  # oracle: MuJoCo's contact list read directly
        for i in range(data.ncon):
            g1, g2 = (int(g) for g in data.contact.geom[i])
            if data.contact.exclude[i] != 0 or (g1 in mm.terrain_geoms) == (g2 in mm.terrain_geoms):
                continue
            touched.add(g2 if g1 in mm.terrain_geoms else g1)
        expected = {f: bool(touched & set(mm.frame_geoms.get(f, ()))) for f in frames}
        order = frames if tick % 2 else tuple(reversed(frames))
        switches = simulator.contact_switches(order)
        assert switches == expected and tuple(switches) == order
        assert {f: simulator.in_contact(f) for f in frames} == expected
        assert simulator.contact_switches(list(frames)) == expected  # a list: not cached
        owners = {n for g in touched if g in mm.geom_frames for n in mm.geom_frames[g]}
        assert simulator.touching_terrain() == owners
        seen.add(tuple(expected.values()))
    assert len(seen) > 1  # the switches did change
    with pytest.raises(va.FrameNotFoundError, match="no_such_frame"):
        simulator.contact_switches(("left_heel", "no_such_frame"))


def test_foot_geoms_flag_the_geoms_that_only_feet_own():
    """The fall test's allowed geoms: every frame owning the geom names a foot (the frame rule)."""
    from virtual_actuators.gaits.runner import FOOT_WORDS, foot_geoms

    simulator = Simulator(va.load_robot("spring_flamingo"))
    flags = foot_geoms(simulator)
    owners = simulator.mujoco_model.geom_frames
    assert flags.shape == (simulator.model.ngeom,)
    for geom, flag in enumerate(flags.tolist()):
        frames = owners.get(geom, ())
        assert bool(flag) is all(any(word in f for word in FOOT_WORDS) for f in frames)
    robot_flags = flags[sorted(owners)]
    assert robot_flags.any() and not robot_flags.all()  # heels and toes; shins and body


def test_walk_rows_land_in_their_channels():
    from virtual_actuators.demos import run_walk

    log = run_walk("turkey-walk", duration=0.4, progress=False, terrain="flat:0.1").log
    time = log["time"]
    steps = np.diff(time)  # a row every RECORD_EVERY ticks of 1 ms, and the last tick's
    assert np.allclose(steps[:-1], RECORD_EVERY * 1e-3) and 0 < steps[-1] <= RECORD_EVERY * 1e-3
    assert time[-1] == pytest.approx(0.399)
    assert np.allclose(log["z_world"] - log["z"], 0.1)  # ground height
    assert np.allclose(np.gradient(log["x"], time)[5:-5], log["xdot"][5:-5], atol=0.02)
    assert not log["fallen"].any()
    assert np.all(np.isfinite(log["z_setpoint"])) and np.all(np.isfinite(log["fz"]))
    assert np.all(log["pitch_setpoint"] == 0.0)  # the granny walker's pitch set point
    assert np.all(np.abs(log["z_setpoint"] - 0.54) < 0.03)  # the hip height above the ground


def test_granny_setters_equal_the_setpoint_path():
    granny = GrannyWalker(0.8, (1000.0, 100.0), (50.0, 5.0), pitch=0.1)
    reference = GrannyWalker(0.8, (1000.0, 100.0), (50.0, 5.0), pitch=0.1)
    held = granny.setpoint
    granny.height, granny.pitch = 0.7312, -0.043
    reference.setpoint = (0.7312, -0.043)
    np.testing.assert_array_equal(granny.setpoint, reference.setpoint)
    assert granny.setpoint is not held and held.tolist() == [0.8, 0.1]  # a new array
    granny.height = 1  # an int: the checked path
    assert granny.setpoint.tolist() == [1.0, -0.043]
    for bad in (np.nan, np.inf, "1", None):
        with pytest.raises(InvalidInputError, match="height"):
            granny.height = bad
        with pytest.raises(InvalidInputError, match="pitch"):
            granny.pitch = bad
    assert granny.setpoint.tolist() == [1.0, -0.043]


def test_event_combinators_equal_all_and_any():
    from itertools import product

    from virtual_actuators.control import events
    from virtual_actuators.control.state_machine import Context

    robot = va.load_robot("spring_flamingo")
    frames = ("left_heel", "left_toe", "right_heel")
    q, v = robot.neutral(), np.zeros(robot.model.nv)
    for values in product((False, True), repeat=3):
        context = Context(robot, q, v, 0.0, dict(zip(frames, values, strict=True)))
        assert events.contact(*frames)(context) is all(values)
        assert events.contact(*frames, require_all=False)(context) is any(values)
        assert events.no_contact(*frames)(context) is (not any(values))
        calls = []
        flags = [lambda c, x=x, calls=calls: calls.append(x) or x for x in values]
        assert events.all_of(*flags)(context) is all(values)
        assert calls == list(values[: values.index(False) + 1] if False in values else values)
        calls.clear()
        assert events.any_of(*flags)(context) is any(values)
        assert calls == list(values[: values.index(True) + 1] if True in values else values)


def test_context_checks_stay_with_a_snapshot():
    from virtual_actuators.control.state_machine import Context

    flamingo, turkey = va.load_robot("spring_flamingo"), va.load_robot("spring_turkey")
    q, v = flamingo.neutral(), np.zeros(flamingo.model.nv)
    snapshot = Snapshot(flamingo, q, v)
    context = Context(flamingo, q, v, 0.5, {"left_heel": True}, snapshot=snapshot)
    assert context.snapshot is snapshot and context.in_contact("left_heel") is True
    with pytest.raises(InvalidInputError, match="snapshot"):
        Context(turkey, turkey.neutral(), np.zeros(turkey.model.nv), 0.0, snapshot=snapshot)
    with pytest.raises(InvalidInputError):
        Context(flamingo.model, q, v, 0.0, snapshot=snapshot)  # a bare model is not a robot
    with pytest.raises(InvalidInputError, match="contacts"):
        Context(flamingo, q, v, 0.0, [("left_heel", True)], snapshot=snapshot)
