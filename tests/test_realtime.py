"""The real-time core: snapshots, the compiled kernels and their oracles, threads, memory.

Oracles: Pinocchio's own kinematics (``computeJointJacobians``, ``oMf``, ``getFrameVelocity``)
for the compiled forward kinematics, and the numpy implementation of the partitioned solver
(``solve(..., compiled=False)``, itself checked against RNEA and the dense eq. 10-11 system in
the other test files) for the compiled distribution.
"""

from __future__ import annotations

import resource
import subprocess
import sys
import threading

import numpy as np
import pinocchio as pin
import pytest
from oracles import random_configuration, relative_error, requires_core

import virtual_actuators as va
from virtual_actuators.kinematics.tree import tree_of

KINEMATIC_ROBOTS = [
    "solo12",
    "anymal_c",
    "hyq_no_sensors",
    "talos_reduced",
    "ur5_robot",
    "panda",
    "pr2",
    "tiago",
    "double_pendulum_continuous",
    "hexapod",
    "spring_flamingo",
]


@requires_core
@pytest.mark.parametrize("name", KINEMATIC_ROBOTS)
def test_compiled_kinematics_equal_pinocchio(name):
    robot = va.load_robot(name)
    model = robot.model
    data = pin.Data(model)
    tree = tree_of(robot)
    assert tree.compiled, tree.unsupported
    frames = range(len(model.frames))
    rng = np.random.default_rng(11)
    for _ in range(4):
        q = random_configuration(robot, rng, scale=1.5)
        v = rng.normal(size=model.nv)
        compiled = va.Snapshot(robot, q, v, backend="compiled")
        reference = va.Snapshot(robot, q, v, backend="pinocchio")
        pin.computeJointJacobians(model, data, q)
        pin.forwardKinematics(model, data, q, v)
        pin.updateFramePlacements(model, data)
        np.testing.assert_allclose(compiled.jacobian_world, data.J, atol=1e-12)
        np.testing.assert_allclose(reference.jacobian_world, data.J, atol=1e-12)
        for f in frames:
            for snapshot in (compiled, reference):
                rotation, position = snapshot.placement(f)
                np.testing.assert_allclose(rotation, data.oMf[f].rotation, atol=1e-12)
                np.testing.assert_allclose(position, data.oMf[f].translation, atol=1e-12)
        for f in list(frames)[:: max(1, len(model.frames) // 12)]:
            expected = pin.getFrameVelocity(model, data, f, pin.LOCAL_WORLD_ALIGNED).linear
            np.testing.assert_allclose(compiled.frame_velocity(f), expected, atol=1e-10)


@requires_core
@pytest.mark.parametrize("name", ["solo12", "anymal", "ur5_robot", "spring_flamingo"])
def test_tabled_frame_velocities_equal_pinocchio_and_the_point_kernel(name):
    """The forward-kinematics pass computes the tabled frames' velocities with the kinematics.

    They equal Pinocchio's (``LOCAL_WORLD_ALIGNED`` linear velocity) and, bit for bit, the
    core's point-velocity kernel that answers for frames outside the table (the same sums in the
    same order); its numpy fallback to rounding.
    """
    from virtual_actuators.kinematics.kernels import point_velocity, velocity_of_point

    robot = va.load_robot(name)
    model = robot.model
    data = pin.Data(model)
    tree = tree_of(robot)
    picked = list(range(1, len(model.frames), max(1, len(model.frames) // 10)))
    tree.require(picked)  # what declaring actuators on these frames does
    rng = np.random.default_rng(5)
    for _ in range(4):
        q = random_configuration(robot, rng, scale=1.5)
        v = rng.normal(size=model.nv)
        snapshot = va.Snapshot(robot, q, v, backend="compiled")
        pin.forwardKinematics(model, data, q, v)
        pin.updateFramePlacements(model, data)
        for f in picked:
            velocity = snapshot.frame_velocity(f)
            expected = pin.getFrameVelocity(model, data, f, pin.LOCAL_WORLD_ALIGNED).linear
            scale = 1.0 + np.abs(expected).max()
            np.testing.assert_allclose(velocity, expected, rtol=0, atol=1e-12 * scale)
            x, y, z = snapshot.placement(f)[1].tolist()
            columns = tree.frame_columns(f)
            kernel = velocity_of_point(snapshot.jacobian_world, v, columns, x, y, z)
            np.testing.assert_array_equal(velocity, np.array(kernel))
            fallback = point_velocity(snapshot.jacobian_world, v, columns, x, y, z)
            np.testing.assert_allclose(fallback, velocity, rtol=0, atol=1e-12 * scale)
    assert snapshot._frame_velocities is not None  # the table answered, not the kernel


def test_all_finite_kernel_agrees_with_numpy() -> None:
    """The per-tick finiteness check (velocities, efforts, the simulator's tau) says what
    ``np.isfinite(...).all()`` says: NaN or an infinity at any place, strided views too."""
    from virtual_actuators.kinematics.kernels import all_finite, finite

    rng = np.random.default_rng(3)
    for size in (0, 1, 7, 40):
        values = rng.normal(scale=1e300, size=size)
        for check in (all_finite, finite):
            assert check(values) is True
            assert check(values[::2]) is True
        for place in range(size):
            for bad in (np.nan, np.inf, -np.inf):
                broken = values.copy()
                broken[place] = bad
                assert all_finite(broken) is False and finite(broken) is False
                view = broken[place % 2 :: 2]
                assert finite(view) is bool(np.isfinite(view).all())


def test_snapshot_rejects_other_robots_and_bad_input():
    solo, ur5 = va.load_robot("solo12"), va.load_robot("ur5_robot")
    arm = va.VirtualActuator(ur5, "tool0", "world")
    snapshot = va.Snapshot(solo, solo.neutral())
    with pytest.raises(va.InvalidInputError, match="solo12"):
        arm.jacobian(snapshot)
    with pytest.raises(va.InvalidInputError, match="backend"):
        va.Snapshot(solo, solo.neutral(), backend="fast")
    with pytest.raises(va.InvalidInputError, match="velocity"):
        arm.read(va.Snapshot(ur5, ur5.neutral()))
    with pytest.raises(va.InvalidInputError, match="NaN"):
        va.Snapshot(ur5, np.full(ur5.model.nq, np.nan))
    with pytest.raises(va.FrameNotFoundError, match="tool0"):
        va.Snapshot(ur5, ur5.neutral()).frame_position("tool")


def _declarations():
    """Parallel actuators covering both kernel modes and every kind of natural constraint."""
    solo = va.load_robot("solo12")
    feet = ["FL_FOOT", "FR_FOOT", "HL_FOOT", "HR_FOOT"]
    yield "solo12 min-norm", va.ParallelVirtualActuator(solo, "base_link", feet, "base_link"), ()
    square = [
        va.Equal((feet[0], "x"), (feet[1], "x")),
        va.Equal((feet[1], "x"), (feet[2], "x")),
        va.Equal((feet[2], "x"), (feet[3], "x")),
        va.Equal((feet[0], "y"), (feet[1], "y")),
        va.Equal((feet[2], "y"), (feet[3], "y")),
        va.Equal((feet[0], "z"), (feet[3], "z")),
    ]
    yield (
        "solo12 square",
        va.ParallelVirtualActuator(solo, "base_link", feet, "world", design=square),
        (),
    )
    yield (
        "solo12 flat feet, one limp knee",
        va.ParallelVirtualActuator(
            solo, "base_link", feet, "world", contact="flat", unactuated=["FL_KFE"]
        ),
        (),
    )
    hexapod = va.load_robot("hexapod")
    tripod = ["foot_1", "foot_4", "foot_5"]
    design = [
        va.Equal(("foot_4", "x"), ("foot_5", "x")),
        va.Linear({("foot_1", "y"): 1.0, ("foot_4", "y"): -2.0}),
        va.Equal(("foot_1", "x"), ("foot_4", "x")),
    ]
    yield "hexapod tripod", va.ParallelVirtualActuator(hexapod, "body", tripod, design=design), ()
    yield (
        "millipede 8",
        va.ParallelVirtualActuator(
            va.millipede(legs=8), "body", [f"foot_{i}" for i in range(1, 9)], "body"
        ),
        (),
    )
    turkey = va.load_robot("spring_turkey")
    yield (
        "turkey double support, equal hip torques",
        va.ParallelVirtualActuator(
            turkey,
            "body",
            ["left_foot", "right_foot"],
            "world",
            ("x", "z", "ry"),
            design=[va.EqualTorque("left_hip", "right_hip")],
        ),
        (),
    )
    flamingo = va.load_robot("spring_flamingo")
    yield (
        "flamingo single support, passive ankle, x free",
        va.ParallelVirtualActuator(
            flamingo,
            "body",
            ["left_foot"],
            "world",
            ("x", "z", "ry"),
            contact="flat",
            passive={"left_ankle": (3.0, 0.1)},
        ),
        ("x",),
    )
    talos = va.load_robot("talos_reduced")
    yield (
        "talos pelvis over both soles, one limp ankle",
        va.ParallelVirtualActuator(
            talos,
            "base_link",
            ["left_sole_link", "right_sole_link"],
            "world",
            contact="flat",
            unactuated=["leg_left_5_joint"],
        ),
        (),
    )


DECLARATIONS = list(_declarations())


@requires_core
@pytest.mark.parametrize("case", DECLARATIONS, ids=[c[0] for c in DECLARATIONS])
def test_compiled_distribution_equals_numpy_reference(case):
    _, actuator, free = case
    rng = np.random.default_rng(5)
    compiled_ticks = 0
    for _ in range(25):
        q = random_configuration(actuator.robot, rng, scale=0.3)
        wrench = rng.normal(size=actuator.n) * rng.choice([1e-3, 1.0, 1e3])
        try:
            reference = actuator.solve(q, wrench, free=free, compiled=False)
        except va.SingularConfigurationError:
            with pytest.raises(va.SingularConfigurationError):
                actuator.solve(q, wrench, free=free)
            continue
        fast = actuator.solve(q, wrench, free=free)
        compiled_ticks += fast.compiled
        scale = max(1.0, np.abs(reference.forces).max())
        np.testing.assert_allclose(fast.forces, reference.forces, atol=1e-9 * scale)
        np.testing.assert_allclose(fast.tau, reference.tau, atol=1e-9 * scale)
        np.testing.assert_allclose(fast.tau_passive, reference.tau_passive, atol=1e-12)
        assert fast.method == reference.method
        assert fast.sets == reference.sets
        assert abs(fast.residual - reference.residual) <= 1e-9 * max(1.0, np.abs(wrench).max())
    # the kernel really ran (a fallback on every tick would make this test vacuous)
    assert compiled_ticks >= 20


@requires_core
def test_compiled_solution_satisfies_rnea():
    """tau = -rnea(q, 0, 0, fext) with the chains' wrenches, gravity off (an oracle sharing no
    code with the kernel): +F_i on {B}, -F_i on {A_i}, forces from the compiled path."""
    from oracles import external_forces, rnea_torques

    robot = va.load_robot("solo12")
    feet = ["FL_FOOT", "FR_FOOT", "HL_FOOT", "HR_FOOT"]
    body = va.ParallelVirtualActuator(robot, "base_link", feet, "world")
    rng = np.random.default_rng(2)
    for _ in range(10):
        q = random_configuration(robot, rng, scale=0.3)
        sol = body.solve(q, rng.normal(size=6) * 20)
        assert sol.compiled
        expected = np.zeros(robot.model.nv)
        for foot, force in zip(feet, sol.forces, strict=True):
            pairs = [("base_link", foot, "world", body.axes, force)]
            expected += rnea_torques("solo12", q, external_forces(robot.model, q, pairs))
        assert relative_error(sol.tau[6:], expected[6:]) < 1e-9


def test_one_actuator_shared_by_four_threads_gives_serial_results():
    robot = va.load_robot("solo12")
    feet = ["FL_FOOT", "FR_FOOT", "HL_FOOT", "HR_FOOT"]
    body = va.ParallelVirtualActuator(robot, "base_link", feet, "base_link")
    arm_robot = va.load_robot("ur5_robot")
    arm = va.VirtualActuator(arm_robot, "tool0", "world", "world", ("x", "y", "z"))
    rng = np.random.default_rng(3)
    cases = [
        (random_configuration(robot, rng, 0.3), rng.normal(size=6) * 10, arm_robot.neutral())
        for _ in range(50)
    ]
    expected = [body.solve(q, w).tau for q, w, _ in cases]
    expected_arm = [arm.jacobian(qa) for _, _, qa in cases]
    errors: list[str] = []

    def work(offset: int) -> None:
        for k in range(500):
            index = (k + offset) % len(cases)
            q, w, qa = cases[index]
            if not np.array_equal(body.solve(q, w).tau, expected[index]):
                errors.append(f"solve {index}")
            if not np.array_equal(arm.jacobian(qa), expected_arm[index]):
                errors.append(f"jacobian {index}")

    threads = [threading.Thread(target=work, args=(i * 7,)) for i in range(4)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    assert not errors, errors[:5]


@requires_core
@pytest.mark.parametrize("with_velocity", [True, False])
def test_a_snapshots_lazy_parts_are_the_passs_bits(with_velocity):
    """The joints and frame velocities a snapshot cuts from the pass on first read."""
    robot = va.load_robot("solo12")
    tree = tree_of(robot)
    tree.frame_id("FL_FOOT")  # tabled: computed every pass
    rng = np.random.default_rng(6)
    q = random_configuration(robot, rng)
    v = rng.normal(size=robot.model.nv) if with_velocity else None
    snapshot = va.Snapshot(robot, q, v)
    buffer, _, rows = tree.core_pass(snapshot.q, snapshot.v)
    joints = buffer[: tree.njoints * 12].reshape(tree.njoints, 12)
    jacobian = buffer[tree.njoints * 12 : tree.njoints * 12 + 6 * tree.nv].reshape(6, tree.nv)
    end = tree.njoints * 12 + 6 * tree.nv + 12 * len(rows)
    frames = buffer[tree.njoints * 12 + 6 * tree.nv : end].reshape(len(rows), 12)
    assert np.array_equal(snapshot.jacobian_world, jacobian)
    assert np.array_equal(snapshot.frame_table, frames)
    assert np.array_equal(snapshot._joint_table(), joints)
    if with_velocity:
        velocities = buffer[end:].reshape(len(rows), 3)
        assert np.array_equal(snapshot._velocity_table(), velocities)
        row = tree.name_rows["FL_FOOT"]
        assert np.array_equal(snapshot.frame_velocity("FL_FOOT"), velocities[row])
    else:
        assert snapshot._velocity_table() is None and buffer.shape == (end,)
    com = pin.centerOfMass(robot.model, robot.model.createData(), snapshot.q)
    np.testing.assert_allclose(snapshot.center_of_mass(), com, rtol=0.0, atol=1e-12)


@requires_core
def test_a_gait_tick_runs_the_kinematics_once(monkeypatch):
    from virtual_actuators.gaits.turkey import TurkeyWalker

    robot = va.load_robot("spring_turkey")
    gait = TurkeyWalker(robot)
    tree = tree_of(robot)
    calls = []
    core_pass = type(tree).core_pass

    def counting_pass(self, q, v=None):  # the compiled core's pass (compute's too)
        calls.append(1)
        return core_pass(self, q, v)

    q, v = gait.initial_configuration(), np.zeros(robot.model.nv)
    gait.compute(q, v, 0.0)  # first use: declaration-time checks run once per set of free axes
    gait.wiring.compute_in_python(q, v, 0.0)  # the same machine in Python
    monkeypatch.setattr(type(tree), "core_pass", counting_pass)
    for k in range(1, 6):
        calls.clear()
        out = gait.wiring.compute_in_python(q, v, 0.001 * k)  # Python: one pass, shared
        assert out.active and len(calls) == 1
    assert gait.compiled is not None  # compiled: the core's one pass, none in Python
    calls.clear()
    assert gait.compute(q, v, 0.01).active and calls == []


def test_robot_data_is_created_only_on_access():
    robot = va.millipede(legs=4)
    assert robot.__dict__.get("_data") is None
    assert isinstance(robot.data, pin.Data)


CHILD = """
import numpy as np, virtual_actuators as va
legs = {legs}
robot = va.millipede(legs=legs)
body = va.ParallelVirtualActuator(robot, "body", [f"foot_{{i}}" for i in range(1, legs + 1)],
                                  "body")
sol = body.solve(robot.neutral(), np.array([1.0, 2.0, 100.0, 0.5, 0.3, 0.1]))
assert sol.compiled and abs(sol.wrench[2] - 100.0) < 1e-6
# this process's own peak (kB): VmHWM starts anew at exec, ru_maxrss keeps the forked parent's
with open("/proc/self/status") as status:
    print(next(line.split()[1] for line in status if line.startswith("VmHWM:")))
"""


@requires_core
def test_a_400_legged_millipede_declares_and_solves_in_little_memory():
    """Memory grows linearly in the legs: no pinocchio.Data (nv^3 tensors: 4 GB each here)."""

    def limit() -> None:
        resource.setrlimit(resource.RLIMIT_AS, (3 << 30, 3 << 30))

    out = subprocess.run(
        [sys.executable, "-c", CHILD.format(legs=400)],
        capture_output=True,
        text=True,
        timeout=300,
        preexec_fn=limit,
    )
    assert out.returncode == 0, out.stderr[-2000:]
    assert int(out.stdout.split()[-1]) < 1024 * 1024  # peak RSS < 1 GiB (kB)
