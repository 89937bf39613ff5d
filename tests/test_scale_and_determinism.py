"""Scale-free answers, absolute floors, typed errors and determinism of the parallel solve.

Regression tests of the robustness issue's items 1-4: each states a property (homogeneity in
the request's magnitude, a chain that produces nothing is singular, no untyped error, results
that depend on the arguments alone, from any thread) and checks it against the dense reference.
"""

from __future__ import annotations

import concurrent.futures

import numpy as np
import pytest

import virtual_actuators as va
from virtual_actuators.core import CORE
from virtual_actuators.distribution.qp import stages
from virtual_actuators.gaits.registry import run_walk

FEET = ["FL_FOOT", "FR_FOOT", "HL_FOOT", "HR_FOOT"]
SIX = ("x", "y", "z", "rx", "ry", "rz")


@pytest.fixture(scope="module")
def solo():
    return va.load_robot("solo12")


def _tiny_arm(tmp_path, length: float):
    """A planar two-link arm whose links are ``length`` long (fixed base)."""
    urdf = f"""<?xml version="1.0"?>
<robot name="tiny">
  <link name="base"><inertial><mass value="1"/><origin xyz="0 0 0"/>
    <inertia ixx="1" iyy="1" izz="1" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="upper"><inertial><mass value="1"/><origin xyz="0 0 0"/>
    <inertia ixx="1" iyy="1" izz="1" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="lower"><inertial><mass value="1"/><origin xyz="0 0 0"/>
    <inertia ixx="1" iyy="1" izz="1" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="tip"/>
  <joint name="shoulder" type="revolute"><parent link="base"/><child link="upper"/>
    <axis xyz="0 1 0"/><limit lower="-3" upper="3" effort="10" velocity="10"/></joint>
  <joint name="elbow" type="revolute"><parent link="upper"/><child link="lower"/>
    <origin xyz="0 0 {-length}"/><axis xyz="0 1 0"/>
    <limit lower="-3" upper="3" effort="10" velocity="10"/></joint>
  <joint name="tip_joint" type="fixed"><parent link="lower"/><child link="tip"/>
    <origin xyz="0 0 {-length}"/></joint>
</robot>
"""
    path = tmp_path / f"tiny_{length:g}.urdf"
    path.write_text(urdf)
    return va.load_robot(str(path))


# -- item 1: absolute floors ----------------------------------------------------------------------


def test_chain_that_produces_nothing_is_singular_not_credited(tmp_path):
    """Links 1e-22 m long: relative ranks look perfect, but the chain produces no force."""
    q = np.array([0.4, 0.9])
    tiny = _tiny_arm(tmp_path, 1e-22)
    arm = va.VirtualActuator(tiny, "tip", "world", "world", ("x", "z"))
    assert not arm.is_admissible(q, np.array([1.0, 0.0]))
    body = va.ParallelVirtualActuator(tiny, "tip", ["base"], "tip", axes=("x", "z"))
    for kwargs in ({}, {"compiled": False}):
        with pytest.raises(va.SingularConfigurationError, match="'base'"):
            body.solve(q, np.array([1.0, 0.0]), **kwargs)
    # the same arm at a human scale is regular: admissible, solved exactly
    normal = _tiny_arm(tmp_path, 0.3)
    arm = va.VirtualActuator(normal, "tip", "world", "world", ("x", "z"))
    assert arm.is_admissible(q, np.array([1.0, 0.0]))
    body = va.ParallelVirtualActuator(normal, "tip", ["base"], "tip", axes=("x", "z"))
    assert body.solve(q, np.array([1.0, 0.0])).residual < 1e-12


@pytest.mark.parametrize("magnitude", [1e-12, 1e-9, 1.0, 1e7, 1e12, 1e200, 1e-200])
@pytest.mark.parametrize("solver", ["compiled", "numpy", "dense"])
def test_inadmissible_request_is_labelled_at_every_magnitude(solo, magnitude, solver):
    """Two point feet cannot push a moment about the line between them, whatever its size."""
    body = va.ParallelVirtualActuator(solo, "base_link", FEET[:2], "base_link")
    q = solo.neutral()
    request = magnitude * np.array([0.0, 0.0, 1.0, 5.0, 5.0, 5.0])
    kwargs = {
        "compiled": solver == "compiled",
        "method": "dense" if solver == "dense" else "partitioned",
    }
    solution = body.solve(q, request, **kwargs)
    reference = body.solve(q, np.array([0.0, 0.0, 1.0, 5.0, 5.0, 5.0]), **kwargs)
    assert solution.method == reference.method == "least-squares"
    assert np.isfinite(solution.residual) and np.all(np.isfinite(solution.forces))
    assert solution.residual == pytest.approx(magnitude * reference.residual, rel=1e-9)
    np.testing.assert_allclose(solution.forces, magnitude * reference.forces, rtol=1e-9, atol=0)
    with pytest.raises(va.InadmissibleWrenchError):
        body.solve(q, request, strict=True, **kwargs)


@pytest.mark.parametrize("magnitude", [1e-9, 1e-3, 1e7, 1e12, 1e200])
def test_admissible_request_is_homogeneous(solo, magnitude):
    """solve(q, s w) == s solve(q, w), same label, every solver (four feet: admissible)."""
    body = va.ParallelVirtualActuator(solo, "base_link", FEET, "base_link")
    q = solo.neutral()
    request = np.array([1.0, -2.0, 20.0, 0.3, 0.2, -0.1])
    for kwargs in ({}, {"compiled": False}, {"method": "dense"}):
        base = body.solve(q, request, **kwargs)
        scaled = body.solve(q, magnitude * request, **kwargs)
        assert scaled.method == base.method == "pseudo-inverse"
        np.testing.assert_allclose(scaled.forces, magnitude * base.forces, rtol=1e-9, atol=0)
        np.testing.assert_allclose(scaled.tau, magnitude * base.tau, rtol=1e-9, atol=0)
        assert scaled.residual <= 1e-12 * magnitude * np.linalg.norm(request)


# -- item 2: typed errors -------------------------------------------------------------------------


@pytest.mark.parametrize("kwargs", [{}, {"compiled": False}, {"method": "dense"}])
def test_every_axis_free(solo, kwargs):
    """Nothing prescribed: the least forces that meet the constraints (zero here)."""
    body = va.ParallelVirtualActuator(solo, "base_link", FEET, "base_link")
    solution = body.solve(solo.neutral(), np.ones(6), free=SIX, **kwargs)
    assert solution.method == "pseudo-inverse"
    assert np.all(solution.forces == 0.0) and np.all(solution.tau == 0.0)


def test_chain_of_passive_joints_only(solo):
    passive = {"FL_HAA": (10.0, 0.0), "FL_HFE": (10.0, 0.1), "FL_KFE": (10.0, -0.2)}
    body = va.ParallelVirtualActuator(solo, "base_link", FEET[:2], "base_link", passive=passive)
    q = solo.neutral()
    results = [body.solve(q, np.ones(6), **kw) for kw in ({}, {"compiled": False})]
    dense = body.solve(q, np.ones(6), method="dense")
    for solution in results:
        assert solution.residual <= dense.residual * (1 + 1e-9) + 1e-12
        assert np.all(solution.tau[[6, 7, 8]] == 0.0)  # passive joints: no command


def test_unbalanced_passive_spring_is_a_typed_error():
    """A waist spring that no selected axis can balance: the constraints contradict."""
    talos = va.load_robot("talos_reduced")
    body = va.ParallelVirtualActuator(
        talos,
        "torso_2_link",
        ["left_sole_link", "right_sole_link"],
        "world",
        axes=("x", "z", "ry"),
        contact="flat",
        passive={"torso_1_joint": (100.0, 0.3)},
    )
    for kwargs in ({}, {"compiled": False}, {"method": "dense"}):
        with pytest.raises(va.ConstraintError, match="torso_1_joint"):
            body.solve(talos.neutral(), np.array([10.0, 20.0, 30.0]), **kwargs)


# -- item 4: determinism and threads --------------------------------------------------------------


def test_repicked_sets_serve_one_call_only(solo):
    """An ill-conditioned CFS block is re-picked for that call; the declaration never changes."""
    body = va.ParallelVirtualActuator(solo, "base_link", FEET, "base_link", unactuated=["FL_KFE"])
    partitioner = body.partitioner
    ev = body.problem.evaluate(solo.neutral())
    index = next(i for i, rows in enumerate(ev.groups) if rows.rows.shape[1])
    rows = ev.groups[index].rows.copy()
    declared = partitioner.cfs[index].copy()
    rows[0][:, declared[0][0]] *= 1e-14  # chain 0's declared CFS block is singular here
    used = partitioner.eliminate(index, rows, ev.groups[index].rhs).cfs
    assert not np.array_equal(used[0], declared[0])
    assert np.array_equal(partitioner.cfs[index], declared)


def _cases(robot, count, seed):
    rng = np.random.default_rng(seed)
    cases = []
    for _ in range(count):
        q = robot.neutral()
        q[7:] += rng.uniform(-0.4, 0.4, robot.model.nq - 7)
        cases.append((q, rng.normal(size=6) * 10 ** rng.uniform(-3, 3)))
    return cases


@pytest.mark.parametrize("kwargs", [{}, {"compiled": False}])
def test_same_call_same_bits_from_four_threads(solo, kwargs):
    """One actuator shared by four threads: every answer equals the sequential one, bitwise."""
    body = va.ParallelVirtualActuator(
        solo,
        "base_link",
        FEET,
        "base_link",
        unactuated=["FL_HAA"],
        design=[va.Equal(("FL_FOOT", "z"), ("HR_FOOT", "z"))],
    )
    cases = _cases(solo, 200, seed=3)

    def run(case):
        q, wrench = case
        try:
            solution = body.solve(q, wrench, **kwargs)
        except va.VirtualActuatorError as error:
            return type(error).__name__
        return solution.forces.tobytes() + solution.tau.tobytes() + solution.method.encode()

    sequential = [run(case) for case in cases]
    with concurrent.futures.ThreadPoolExecutor(max_workers=4) as pool:
        for _ in range(3):
            assert list(pool.map(run, cases)) == sequential
    assert sequential == [run(case) for case in reversed(cases)][::-1]  # order does not matter


def test_dense_fallback_when_no_cfs_is_well_conditioned(solo):
    """A natural constraint that vanishes at q: the partitioned closed form cannot decide, the
    dense reference answers (and the solution says so) instead of an error."""
    body = va.ParallelVirtualActuator(solo, "base_link", FEET, "base_link", unactuated=["FL_KFE"])
    q = solo.neutral()
    solver, dense = body.partitioner, body.dense
    ev = body.problem.evaluate(q)
    index = next(i for i, rows in enumerate(ev.groups) if rows.rows.shape[1])
    ev.groups[index].rows[0] = 0.0  # every natural row of chain 0 vanishes (vacuous, rhs 0)
    with pytest.raises(va.SingularConfigurationError):
        solver.solve(ev, np.array([0.0, 0.0, 20.0, 0.0, 0.0, 0.0]), np.ones(6, dtype=bool))
    reference = dense.solve(ev, np.array([0.0, 0.0, 20.0, 0.0, 0.0, 0.0]), np.ones(6, dtype=bool))
    assert reference.solver == "dense" and np.all(np.isfinite(reference.forces))
    # through the public path, a regular configuration stays partitioned
    assert body.solve(q, np.array([0.0, 0.0, 20.0, 0.0, 0.0, 0.0])).solver == "partitioned"


@pytest.mark.skipif(CORE is None, reason="without the core ProxQP solves every stage (no DAQP)")
def test_pace_walk_on_the_qp_is_the_same_bits_after_another_walk(monkeypatch):
    """solo12's pace on the QP: every tick certified by DAQP or the exact step, never ProxQP's
    last iterate (its AVX builds round by where the heap put their buffers: an iterate it stops
    on differed between processes and after other walks, from tick 266). Run after a trot, the
    pace is the same bits."""
    runs = []
    original = stages.ProxStages._run

    def counting(self, key, *arguments):
        runs.append(key)
        return original(self, key, *arguments)

    monkeypatch.setattr(stages.ProxStages, "_run", counting)
    walk = {"robot": "solo12", "duration": 0.3, "progress": False, "distribution": "qp"}
    first = run_walk("legged", gait="pace", **walk)
    run_walk("legged", gait="trot", **walk)
    again = run_walk("legged", gait="pace", **walk)
    assert runs == []
    np.testing.assert_array_equal(first.loop.efforts, again.loop.efforts)
