"""The compiled core (C++, ``virtual_actuators._core``) against its reference kernels, bit for bit.

Each C++ kernel follows a reference kernel of the package (numba; plain Python without numba)
operation by operation, so that both give the same bits. The arguments are recorded from real
solves: the kinematics of every snapshot that solo12, the hexapod and talos declarations compute
(with velocities), and the distribution ticks of declarations that reach every path of the
kernel (mode 0 per chain and in batches of shared or individual ball axes, mode 1 with design
rows, passive springs, limp joints, equal torques, millipedes of 6 and 100 legs). Both kernels
then run on the same arrays and their outputs are compared with ``np.array_equal`` (NaN equal
to NaN nowhere: a NaN fails). The kernels' correctness against independent oracles (Pinocchio,
RNEA, the numpy reference solver) is tested in ``test_realtime.py`` and the solver tests.
"""

from __future__ import annotations

import numpy as np
import pytest
from oracles import random_configuration

import virtual_actuators as va
from virtual_actuators.core import CORE
from virtual_actuators.distribution.partitioned import compiled, kernels
from virtual_actuators.kinematics import kernels as kinematics_kernels
from virtual_actuators.kinematics.tree import KinematicTree, tree_of

pytestmark = pytest.mark.skipif(CORE is None, reason="virtual_actuators._core is not built")

FEET = {
    "solo12": ("base_link", ["FL_FOOT", "FR_FOOT", "HL_FOOT", "HR_FOOT"]),
    "hexapod": ("body", [f"foot_{i}" for i in range(1, 7)]),
    "talos": ("base_link", ["left_sole_link", "right_sole_link"]),
}


@pytest.fixture
def kinematics_calls(monkeypatch):
    """Every compiled kinematics pass's arguments (tree, q, v), recorded.

    ``KinematicTree.core_pass``: a snapshot's pass, and ``compute``'s with the core.
    """
    calls = []
    original = KinematicTree.core_pass

    def recording(self, q, v=None):
        calls.append((self, q.copy(), None if v is None else v.copy()))
        return original(self, q, v)

    monkeypatch.setattr(KinematicTree, "core_pass", recording)
    return calls


@pytest.mark.parametrize("name", sorted(FEET))
def test_forward_kinematics_is_bit_identical(name, kinematics_calls):
    robot = va.load_robot(name)
    base, feet = FEET[name]
    contact = "flat" if name == "talos" else "point"
    body = va.ParallelVirtualActuator(robot, base, feet, "world", contact=contact)
    rng = np.random.default_rng(7)
    for k in range(40):
        q = random_configuration(robot, rng, scale=1.0)
        v = rng.normal(size=robot.model.nv) if k % 2 else None
        snapshot = va.Snapshot(robot, q, v)
        assert snapshot.jacobian_world.shape == (6, robot.model.nv)  # the kinematics pass
        body.solve(snapshot, rng.normal(size=body.n), compiled=True)
        if v is not None:
            snapshot.frame_velocity(feet[0])
    assert len(kinematics_calls) >= 40
    tree = tree_of(robot)
    _, parents, floats = tree.frame_tables
    assert tree.core_tree is not None and tree.core_tree.nf == len(parents)
    no_v = np.zeros(0)
    for recorded_tree, q, v in kinematics_calls:
        assert recorded_tree is tree
        reference = kinematics_kernels.forward_kinematics(
            q, no_v if v is None else v, *tree.joint_tables, parents, floats
        )
        core = tree.core_tree.compute(q, v)
        assert reference.shape == core.shape
        assert np.array_equal(reference, core), np.abs(reference - core).max()


def test_the_small_kinematics_kernels_are_bit_identical():
    rng = np.random.default_rng(3)
    robot = va.load_robot("talos")
    tree = tree_of(robot)
    bounds = np.array([(s.start, s.stop) for s in tree.unit_slices], dtype=np.int64)
    for k in range(50):
        q = random_configuration(robot, rng, scale=2.0)
        q[3:7] *= 1.0 + rng.normal(scale=1e-3)  # off unit norm
        if k % 10 == 0:
            q[rng.integers(robot.model.nq)] = [np.nan, np.inf, -np.inf][k % 3]
        assert CORE.unit_norm_error(q, bounds) == kinematics_kernels.unit_norm_error(q, bounds)
        values = rng.normal(size=k)
        if k % 3 == 0 and k:
            values[rng.integers(k)] = np.nan
        assert CORE.all_finite(values) == kinematics_kernels.all_finite(values)
        jacobian = rng.normal(size=(6, robot.model.nv))
        v = rng.normal(size=robot.model.nv)
        columns = np.sort(rng.choice(robot.model.nv, size=k % robot.model.nv, replace=False))
        point = tuple(rng.normal(size=3))
        assert CORE.point_velocity(jacobian, v, columns, *point) == tuple(
            kinematics_kernels.point_velocity(jacobian, v, columns, *point)
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
def test_distribution_is_bit_identical(case, distribution_calls):
    _, actuator, free = case
    robot = actuator.robot
    rng = np.random.default_rng(5)
    ticks = 12 if robot.model.nv > 200 else 40
    for _ in range(ticks):
        q = random_configuration(robot, rng, scale=0.3)
        wrench = rng.normal(size=actuator.n) * rng.choice([1e-3, 1.0, 1e3])
        try:  # a snapshot: the solve goes through CompiledDistribution.solve (recorded)
            actuator.solve(va.Snapshot(robot, q), wrench, free=free)
        except va.SingularConfigurationError:
            pass
        try:  # from q alone (kinematics and distribution in one call): the same answer
            same = actuator.solve(q, wrench, free=free)
        except va.SingularConfigurationError:
            continue
        again = actuator.solve(va.Snapshot(robot, q), wrench, free=free)
        assert np.array_equal(same.forces, again.forces) and np.array_equal(same.tau, again.tau)
    assert len(distribution_calls) >= ticks
    tree = tree_of(robot)
    solved = 0
    for distribution, snapshot, wrench, keep in distribution_calls:
        mode = distribution.mode_for(keep)
        if mode.mode < 0:
            continue
        args = (snapshot.jacobian_world, snapshot.frame_table, snapshot.q, wrench)
        reference = kernels.distribute(*args, *mode.packed)
        core = CORE.Distribution(*mode.packed, robot.model.nv)
        for answer in (core.solve(*args), core.tick(tree.core_tree, snapshot.q, wrench)):
            assert answer[4] == reference.status
            assert answer[5] == reference.worst and answer[6] == reference.worst_chain
            if reference.status == 0:
                assert np.array_equal(answer[0], reference.out)
                assert answer[1:4] == (reference.residual, reference.scale, reference.rounding)
        solved += reference.status == 0
    assert solved >= len(distribution_calls) // 2  # the solves ran, not only the fallbacks


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
