"""The compiled core's small kinematics kernels and its distribution against their oracles.

The small kernels (unit norms, finiteness, a point's velocity, the centre of mass) against numpy
and Pinocchio; the distribution kernel, on declarations that reach every path of it (mode 0 per
chain and in batches of shared or individual ball axes, mode 1 with design rows, passive
springs, limp joints, equal torques, millipedes of 6 and 100 legs), against the numpy solver;
its tables refused when bad. The forward kinematics against Pinocchio is in
``test_realtime.py``.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
from oracles import random_configuration

import virtual_actuators as va
from virtual_actuators.core import CORE
from virtual_actuators.distribution.partitioned import compiled
from virtual_actuators.kinematics import kernels as kinematics_kernels
from virtual_actuators.kinematics.tree import tree_of

pytestmark = pytest.mark.skipif(CORE is None, reason="virtual_actuators._core is not built")

FEET = {
    "solo12": ("base_link", ["FL_FOOT", "FR_FOOT", "HL_FOOT", "HR_FOOT"]),
    "hexapod": ("body", [f"foot_{i}" for i in range(1, 7)]),
    "talos": ("base_link", ["left_sole_link", "right_sole_link"]),
}


def test_the_small_kinematics_kernels_equal_their_numpy_fallbacks():
    rng = np.random.default_rng(3)
    robot = va.load_robot("talos")
    tree = tree_of(robot)
    bounds = np.array([(s.start, s.stop) for s in tree.unit_slices], dtype=np.int64)
    for k in range(50):
        q = random_configuration(robot, rng, scale=2.0)
        q[3:7] *= 1.0 + rng.normal(scale=1e-3)  # off unit norm
        if k % 10 == 0:
            q[rng.integers(robot.model.nq)] = [np.nan, np.inf, -np.inf][k % 3]
        error = CORE.unit_norm_error(q, bounds)
        if not np.isfinite(q).all():
            assert error == -1.0
        else:
            norms = [np.linalg.norm(q[a:b]) for a, b in bounds]
            assert error == pytest.approx(max(abs(n - 1.0) for n in norms), abs=1e-15)
        values = rng.normal(size=k)
        if k % 3 == 0 and k:
            values[rng.integers(k)] = np.nan
        assert CORE.all_finite(values) == kinematics_kernels.all_finite(values)
        jacobian = rng.normal(size=(6, robot.model.nv))
        v = rng.normal(size=robot.model.nv)
        columns = np.sort(rng.choice(robot.model.nv, size=k % robot.model.nv, replace=False))
        point = tuple(rng.normal(size=3))
        ours = np.array(CORE.point_velocity(jacobian, v, columns, *point))
        oracle = np.array(kinematics_kernels.point_velocity(jacobian, v, columns, *point))
        scale = max(1.0, np.abs(jacobian).sum() * np.abs(v).max() * (1 + np.abs(point).max()))
        np.testing.assert_allclose(ours, oracle, rtol=0.0, atol=1e-14 * scale)
    masses, levers = tree.masses, tree.levers
    for _ in range(10):
        q = random_configuration(robot, rng, scale=1.0)
        data = robot.model.createData()
        pin.forwardKinematics(robot.model, data, q)
        joints = np.array([np.concatenate((m.rotation.ravel(), m.translation)) for m in data.oMi])
        ours = np.array(CORE.center_of_mass(joints, masses, levers))
        np.testing.assert_allclose(ours, pin.centerOfMass(robot.model, data, q), atol=1e-12)
        np.testing.assert_allclose(
            np.array(kinematics_kernels.center_of_mass(joints, masses, levers)), ours, atol=1e-12
        )


def _declarations():
    solo = va.load_robot("solo12")
    base, feet = FEET["solo12"]
    yield "solo12 point feet (mode 0)", va.ParallelVirtualActuator(solo, base, feet, "world"), ()
    design = [
        va.Equal((feet[0], "x"), (feet[1], "x")),
        va.Equal((feet[0], "x"), (feet[2], "x")),
        va.Equal((feet[0], "x"), (feet[3], "x")),
        va.Equal((feet[0], "y"), (feet[1], "y")),
        va.Equal((feet[2], "y"), (feet[3], "y")),
        va.Linear({(feet[0], "z"): 1, (feet[3], "z"): 1, (feet[1], "z"): -1, (feet[2], "z"): -1}),
    ]
    yield (
        "solo12 6 design rows (mode 1)",
        va.ParallelVirtualActuator(solo, base, feet, reference=base, design=design),
        (),
    )
    hexapod = va.load_robot("hexapod")
    base, feet = FEET["hexapod"]
    yield "hexapod 6 point feet", va.ParallelVirtualActuator(hexapod, base, feet, "world"), ()
    for legs in (6, 100):
        millipede = va.millipede(legs=legs)
        feet = [f"foot_{i}" for i in range(1, legs + 1)]
        yield (
            f"millipede {legs} legs",
            va.ParallelVirtualActuator(millipede, "body", feet, reference="body"),
            (),
        )
    millipede = va.millipede(legs=12)
    feet = [f"foot_{i}" for i in range(1, 13)]
    yield (
        "millipede 12 legs, flat feet, yaw free",
        va.ParallelVirtualActuator(millipede, "body", feet, "world", contact="flat"),
        ("rz",),
    )
    turkey = va.load_robot("spring_turkey")
    yield (
        "turkey double support, equal hip torques",
        va.ParallelVirtualActuator(
            turkey, "body", ["left_foot", "right_foot"], "world", ("x", "z", "ry"),
            design=[va.EqualTorque("left_hip", "right_hip")],
        ),
        (),
    )  # fmt: skip
    flamingo = va.load_robot("spring_flamingo")
    yield (
        "flamingo single support, passive ankle, x free",
        va.ParallelVirtualActuator(
            flamingo, "body", ["left_foot"], "world", ("x", "z", "ry"), contact="flat",
            passive={"left_ankle": (3.0, 0.1)},
        ),
        ("x",),
    )  # fmt: skip
    talos = va.load_robot("talos")
    base, feet = FEET["talos"]
    yield (
        "talos both soles, one limp ankle",
        va.ParallelVirtualActuator(
            talos, base, feet, "world", contact="flat", unactuated=["leg_left_5_joint"]
        ),
        (),
    )


DECLARATIONS = list(_declarations())


@pytest.fixture
def distribution_calls(monkeypatch):
    """Every compiled distribution tick's arguments (distribution, snapshot, wrench, keep)."""
    calls = []
    original = compiled.CompiledDistribution.solve

    def recording(self, snapshot, wrench, request):
        calls.append((self, snapshot, wrench.copy(), request.keep.copy()))
        return original(self, snapshot, wrench, request)

    monkeypatch.setattr(compiled.CompiledDistribution, "solve", recording)
    return calls


@pytest.mark.parametrize("case", DECLARATIONS, ids=[c[0] for c in DECLARATIONS])
def test_the_core_distribution_equals_the_numpy_solver(case, distribution_calls):
    """Every path of the core's kernel against the numpy solver; a tick from q is the same bits.

    The oracle is ``solve(..., compiled=False)`` (the numpy PartitionedSolver, itself checked
    against RNEA and the dense eq. 10-11 system in the solver tests), to 1e-9 of the forces'
    scale; the core's one-call tick from ``q`` (kinematics and distribution) equals its solve on
    a snapshot bit for bit.
    """
    _, actuator, free = case
    robot = actuator.robot
    rng = np.random.default_rng(5)
    ticks = 12 if robot.model.nv > 200 else 40
    compared = 0
    for _ in range(ticks):
        q = random_configuration(robot, rng, scale=0.3)
        wrench = rng.normal(size=actuator.n) * rng.choice([1e-3, 1.0, 1e3])
        try:
            reference = actuator.solve(q, wrench, free=free, compiled=False)
        except va.SingularConfigurationError:
            continue
        fast = actuator.solve(va.Snapshot(robot, q), wrench, free=free)
        same = actuator.solve(q, wrench, free=free)
        assert np.array_equal(same.forces, fast.forces) and np.array_equal(same.tau, fast.tau)
        scale = max(1.0, np.abs(reference.forces).max())
        np.testing.assert_allclose(fast.forces, reference.forces, rtol=0.0, atol=1e-9 * scale)
        np.testing.assert_allclose(fast.tau, reference.tau, rtol=0.0, atol=1e-9 * scale)
        assert fast.method == reference.method and fast.sets == reference.sets
        compared += fast.compiled
    assert len(distribution_calls) >= ticks // 2
    tree = tree_of(robot)
    solved = 0
    for distribution, snapshot, wrench, keep in distribution_calls:
        mode = distribution.mode_for(keep)
        if mode.mode < 0:
            continue
        core = CORE.Distribution(*mode.packed, robot.model.nv)
        by_snapshot = core.solve(snapshot.jacobian_world, snapshot.frame_table, snapshot.q, wrench)
        by_q = core.tick(tree.core_tree, snapshot.q, wrench)
        assert by_snapshot[4] == by_q[4]
        if by_q[4] == 0:
            assert np.array_equal(by_snapshot[0], by_q[0])
            assert by_snapshot[1:4] == by_q[1:4]
        solved += by_q[4] == 0
    assert solved >= len(distribution_calls) // 2 and compared  # the core ran, not only fallbacks


def test_bad_tables_are_refused_not_read():
    actuator = DECLARATIONS[0][1]
    actuator.solve(actuator.robot.neutral(), np.ones(actuator.n))
    distribution = actuator.compiled
    ints, floats = distribution.mode_for(np.ones(actuator.n, dtype=bool)).packed
    nv = actuator.robot.model.nv
    CORE.Distribution(ints, floats, nv)  # the real tables are accepted
    with pytest.raises(ValueError, match="wrong length"):
        CORE.Distribution(ints[:-1], floats, nv)
    with pytest.raises(ValueError, match="nv rows"):
        CORE.Distribution(ints, floats, nv + 1)
    bad = ints.copy()
    bad[9 + actuator.n] = 7  # the first axis row (after the header and keep): not in 0..5
    with pytest.raises(ValueError, match="axis rows"):
        CORE.Distribution(bad, floats, nv)
    core = CORE.Distribution(ints, floats, nv)
    tree = tree_of(actuator.robot)
    with pytest.raises(ValueError, match="wrench"):
        core.tick(tree.core_tree, actuator.robot.neutral(), np.ones(actuator.n + 1))
    with pytest.raises(ValueError, match="q is shorter"):
        core.tick(tree.core_tree, np.zeros(3), np.ones(actuator.n))
