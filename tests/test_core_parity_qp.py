"""The compiled core's QP tick (C++, ``_core.QP``) against its reference kernels, bit for bit.

The reference kernels (numba; plain Python without numba) of the QP distribution are
``qp.kernels.reduced_qp`` (with the point and flat contacts' rows), ``qp.exact.exact_step``,
``qp.kernel_answer.violation``, ``read_out`` (``finish``) and ``again``, and the serial
actuators' virtual sensor (``kinematics.sensor_kernels.relative_sensor``) and the contact
margins of the controller's yield policy (``contacts.contact_set.least_margin``,
``largest_scale``). Their arguments are
recorded from real ``method="qp"`` solves: solo12's point feet with friction (feasible and
infeasible requests, a least normal force, torque limits), talos' soles (flat contacts), the
hexapod, and walking ticks of the legged trot (solo12) and of talos' balance. Both kernels then
run on the same arrays and their outputs are compared with ``np.array_equal``. The answers'
correctness against independent oracles (ProxQP, the KKT conditions, RNEA) is tested in the
``test_qp*.py`` files.
"""

from __future__ import annotations

import concurrent.futures

import numpy as np
import pytest
from oracles import random_configuration

import virtual_actuators as va
from virtual_actuators.contacts import contact_set
from virtual_actuators.control import contact_limits
from virtual_actuators.core import CORE
from virtual_actuators.distribution.qp import compiled, exact, kernel_answer, kernels, stages
from virtual_actuators.distribution.tolerances import ACTIVE_TOL, EPS_ABS, EXACT_TOL
from virtual_actuators.gaits.registry import run_walk
from virtual_actuators.kinematics import relative, sensor_kernels

pytestmark = pytest.mark.skipif(CORE is None, reason="virtual_actuators._core is not built")


class Recorder:
    """The QP kernels' arguments of every solve while installed (copies at call time)."""

    def __init__(self, monkeypatch) -> None:
        self.ticks, self.agains, self.steps, self.misses, self.finishes = [], [], [], [], []
        build, again = compiled.CompiledQPMatrices.build, compiled.CompiledQPMatrices.again
        miss, finish = compiled.Workspace.violation, compiled.Workspace.finish
        answer = stages.exact_answer

        def snap(snapshot, wrench):
            return (snapshot.jacobian_world.copy(), snapshot.frame_table.copy(),
                    snapshot.q.copy(), np.array(wrench, dtype=float))  # fmt: skip

        def record_build(matrices, snapshot, wrench, keep):
            self.ticks.append((matrices, matrices.workspace(keep), *snap(snapshot, wrench)))
            return build(matrices, snapshot, wrench, keep)

        def record_again(matrices, snapshot, wrench, keep, workspace, weights, guess,
                         tree=None):  # fmt: skip
            if tree is None:
                state = snap(snapshot, wrench)
            else:
                state = kinematics(matrices, tree, snapshot, wrench)
            self.agains.append((matrices, workspace, *state, keep.copy(), weights.copy(),
                                guess.copy()))  # fmt: skip
            return again(matrices, snapshot, wrench, keep, workspace, weights, guess, tree)

        def kinematics(matrices, tree, q, wrench):  # a configuration: the tree's kinematics
            buffer, njoints = tree.compute(q), matrices.problem.model.njoints
            nv = matrices.problem.model.nv
            jacobian = buffer[12 * njoints : 12 * njoints + 6 * nv].reshape(6, nv)
            frames = buffer[12 * njoints + 6 * nv :].reshape(-1, 12)
            return jacobian.copy(), frames.copy(), q.copy(), np.array(wrench, dtype=float)

        def record_miss(workspace, z, count):
            self.misses.append((workspace, workspace.buffer.copy(), np.array(z), count))
            return miss(workspace, z, count)

        def record_finish(workspace, z, multipliers, wrench, keep):
            self.finishes.append((
                workspace, workspace.buffer.copy(), np.array(z), np.array(multipliers),
                np.array(wrench), keep.copy(),
            ))  # fmt: skip
            return finish(workspace, z, multipliers, wrench, keep)

        def record_answer(*arguments):
            self.steps.append(tuple(np.array(a) if isinstance(a, np.ndarray) else a
                                    for a in arguments))  # fmt: skip
            return answer(*arguments)

        monkeypatch.setattr(compiled.CompiledQPMatrices, "build", record_build)
        monkeypatch.setattr(compiled.CompiledQPMatrices, "again", record_again)
        monkeypatch.setattr(compiled.Workspace, "violation", record_miss)
        monkeypatch.setattr(compiled.Workspace, "finish", record_finish)
        monkeypatch.setattr(stages, "exact_answer", record_answer)

    def counts(self) -> dict[str, int]:
        return {"ticks": len(self.ticks), "again": len(self.agains), "exact": len(self.steps),
                "violation": len(self.misses), "finish": len(self.finishes)}  # fmt: skip


@pytest.fixture
def recorder(monkeypatch):
    return Recorder(monkeypatch)


def _tables(matrices, workspace) -> tuple:
    return (
        workspace.kept, matrices.axis_rows, matrices.frame_rows, matrices.chain_ints,
        matrices.chain_signs, matrices.springs, matrices.const_rows, matrices.const_rhs,
        matrices.normals_world, matrices.frame_normals, matrices.settings, matrices.soles,
        matrices.limited_v, matrices.limits,
    )  # fmt: skip


def _check(recorder: Recorder) -> dict[str, int]:
    """Every recorded call through both kernels: the same bits."""
    for matrices, work, jacobian, frames, q, wrench in recorder.ticks:
        assert matrices.core is not None
        ours, theirs = np.full_like(work.buffer, np.nan), np.full_like(work.buffer, np.nan)
        status = kernels.reduced_qp(jacobian, frames, q, wrench, *_tables(matrices, work), theirs,
                                    work.layout)  # fmt: skip
        core = matrices.core.reduced(jacobian, frames, q, wrench, work.kept, ours, work.layout)
        assert tuple(core) == tuple(status)
        assert np.array_equal(ours, theirs)
    for matrices, work, jacobian, frames, q, wrench, keep, weights, guess in recorder.agains:
        results = []
        for run in ("reference", "core"):
            buffer = np.zeros_like(work.buffer)
            out = np.zeros(work.pn + 2 * work.nv + 2 * len(wrench))
            hot, active = guess.copy(), np.zeros(len(guess), dtype=np.int64)
            if run == "core":
                count, norms = matrices.core.again(
                    jacobian, frames, q, wrench, work.kept, buffer, work.layout, keep, weights,
                    hot, ACTIVE_TOL, EXACT_TOL, EPS_ABS, out, active,
                )  # fmt: skip
            else:
                count, norms = kernel_answer.again(
                    jacobian, frames, q, wrench, *_tables(matrices, work), buffer, work.layout,
                    work.pn, work.nv, keep, weights, hot, ACTIVE_TOL, EXACT_TOL, EPS_ABS, out,
                    active,
                )  # fmt: skip
            results.append((count, tuple(norms), buffer, out, hot, active[: max(count, 0)]))
        (count, norms, *arrays), (count_c, norms_c, *arrays_c) = results
        assert (count, norms) == (count_c, norms_c)
        assert all(np.array_equal(a, b) for a, b in zip(arrays, arrays_c, strict=True))
    for arguments in recorder.steps:  # exact_answer's: rows, x, guess, exact, active_tol
        rows, (guess, certify, active_tol) = arguments[:7], arguments[8:]
        step = (*rows, guess, certify, active_tol, EXACT_TOL, exact.EXACT_STEPS)
        ok, x, z = exact.exact_step(*step)
        ok_c, x_c, z_c = CORE.exact_step(*step)
        assert ok == ok_c and np.array_equal(x, x_c) and np.array_equal(z, z_c)
    for work, buffer, z, count in recorder.misses:
        reference = kernel_answer.violation(buffer, work.layout, work.pn, work.nv, z, count)
        core = CORE.qp_violation(buffer, work.layout, work.pn, work.nv, z, count)
        assert core == reference or (np.isnan(core) and np.isnan(reference))
    for work, buffer, z, multipliers, wrench, keep in recorder.finishes:
        answer = kernel_answer.finish(buffer, work.layout, work.pn, work.nv, z, multipliers,
                                      work.scale, wrench, keep, ACTIVE_TOL, EPS_ABS)  # fmt: skip
        out, active = np.zeros_like(answer.out), np.empty(len(multipliers), dtype=np.int64)
        count, norms = CORE.qp_read_out(buffer, work.layout, work.pn, work.nv, z, multipliers,
                                        work.scale, wrench, keep, ACTIVE_TOL, EPS_ABS, out,
                                        active)  # fmt: skip
        assert tuple(norms) == (answer.residual, answer.scale, answer.rounding)
        assert np.array_equal(out, answer.out) and np.array_equal(active[:count], answer.active)
    return recorder.counts()


DECLARATIONS = {
    "solo12 friction": ("solo12", "base_link", ["FL_FOOT", "FR_FOOT", "HL_FOOT", "HR_FOOT"],
                        {"contact": "point", "friction": 0.7}),
    "solo12 least normal, limits": ("solo12", "base_link",
                                    ["FL_FOOT", "FR_FOOT", "HL_FOOT", "HR_FOOT"],
                                    {"contact": "point", "friction": 0.5, "min_normal": 2.0,
                                     "torque_limits": True}),
    "hexapod": ("hexapod", "body", [f"foot_{i}" for i in range(1, 7)],
                {"contact": "point", "friction": 0.6}),
    "talos soles": ("talos", "base_link", ["left_sole_link", "right_sole_link"],
                    {"contact": "flat", "friction": 0.8,
                     "soles": {"left_sole_link": (0.1, 0.05), "right_sole_link": (0.1, 0.05)}}),
}  # fmt: skip


@pytest.mark.parametrize("name", sorted(DECLARATIONS))
def test_qp_solves_are_bit_identical(name, recorder):
    robot_name, base, feet, options = DECLARATIONS[name]
    robot = va.load_robot(robot_name)
    body = va.ParallelVirtualActuator(robot, base, feet, "world", **options)
    assert body.qp.matrices.core is not None
    rng = np.random.default_rng(11)
    q0 = robot.neutral()
    weight = 9.81 * sum(inertia.mass for inertia in robot.model.inertias)
    for k in range(60):
        q = q0 if k % 3 == 0 else random_configuration(robot, rng, scale=0.2)
        wrench = np.zeros(body.n)
        wrench[2] = weight * rng.uniform(0.2, 1.5)
        wrench += rng.normal(scale=0.3 * weight if k % 4 else 0.02 * weight, size=body.n)
        try:
            body.solve(q, wrench, method="qp")
        except va.ConstraintError:
            pass
    counts = _check(recorder)
    assert counts["ticks"] > 0 and counts["exact"] > 0 and counts["finish"] > 0
    assert counts["again"] > 0


def test_nearly_dependent_request_rows_are_bit_identical(recorder):
    """Two diagonal feet of solo12 at heights 1e-11..1e-7 m apart: the exact step takes a nearly
    dependent request row after the others (`exact._factor`), in both kernels alike."""
    robot = va.load_robot("solo12")
    body = va.ParallelVirtualActuator(robot, "base_link", ["FL_FOOT", "HR_FOOT"], "world",
                                      contact="point", friction=0.6)  # fmt: skip
    knee = robot.model.joints[robot.model.getJointId("HR_KFE")].idx_q
    rng = np.random.default_rng(2)
    for angle in np.logspace(-10, -6, 9):
        q = robot.neutral()
        q[knee] += angle
        wrench = np.array([0.0, 0.0, 20.0, 0.0, 0.0, 0.0]) + rng.normal(scale=2.0, size=6)
        for request in (wrench, body.solve(q, wrench, method="qp").wrench.copy()):
            body.qp.reset()
            body.solve(q, request, method="qp")
            body.solve(q, request, method="qp")  # the active set certified again
    counts = _check(recorder)
    assert counts["exact"] > 0 and counts["again"] > 0


@pytest.mark.parametrize(("walk", "options"), [
    ("legged", {"robot": "solo12", "gait": "trot"}),
    ("balance", {}),
])  # fmt: skip
def test_walking_qp_ticks_are_bit_identical(walk, options, recorder, monkeypatch):
    monkeypatch.setenv("VA_PLAN", "0")  # the gaits' Python ticks, where the QP kernels are called
    run_walk(walk, duration=0.4, progress=False, stop_on_fall=False, **options)
    counts = _check(recorder)
    assert counts["again"] + counts["ticks"] > 100


def _rotation(axis: np.ndarray, angle: float) -> np.ndarray:
    axis = axis / np.linalg.norm(axis)
    skew = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + np.sin(angle) * skew + (1 - np.cos(angle)) * skew @ skew


def test_the_virtual_sensor_is_bit_identical_on_every_branch():
    """Relative rotations near 0, generic and near pi (rotation_log's three branches)."""
    rng = np.random.default_rng(5)
    nv = 9
    angles = [0.0, 1e-6, 5e-5, 0.3, 2.0, np.pi - 2e-3, np.pi - 1e-5, np.pi]
    for k in range(200):
        frames = np.zeros((4, 12))
        for row in range(4):
            angle = angles[k % len(angles)] if row == 1 else rng.uniform(0, np.pi)
            frames[row, :9] = _rotation(rng.normal(size=3), angle).ravel()
            frames[row, 9:] = rng.normal(size=3)
        if k % 2:  # {A} = row 2 and {B} = row 1 related by the chosen angle
            frames[1, :9] = (frames[2, :9].reshape(3, 3) @ frames[1, :9].reshape(3, 3)).ravel()
        jacobian = rng.normal(size=(6, nv))
        n = rng.integers(1, 7)
        axis_rows = np.sort(rng.choice(6, size=n, replace=False)).astype(np.int64)
        columns = rng.choice(nv, size=4, replace=False).astype(np.int64)
        signs = rng.choice([-1.0, 1.0], size=4)
        v = rng.normal(size=nv) if k % 3 else np.zeros(0)
        rows = np.array([1, 3, 2], dtype=np.int64)
        arguments = (jacobian, frames, v, axis_rows, rows, columns, signs)
        reference = sensor_kernels.relative_sensor(*arguments)
        assert np.array_equal(CORE.relative_sensor(*arguments), reference)


def test_walking_sensor_readings_are_bit_identical(monkeypatch):
    calls = []
    original = relative._relative_sensor

    def recording(*arguments):
        calls.append(tuple(np.array(a) for a in arguments))
        return original(*arguments)

    monkeypatch.setattr(relative, "_relative_sensor", recording)
    monkeypatch.setenv("VA_PLAN", "0")  # the gaits' Python ticks, where the sensors are read
    run_walk("balance", duration=0.2, progress=False, stop_on_fall=False)
    run_walk("turkey-walk", duration=0.2, progress=False, stop_on_fall=False)
    assert len(calls) > 100
    for arguments in calls:
        reference = sensor_kernels.relative_sensor(*arguments)
        assert np.array_equal(CORE.relative_sensor(*arguments), reference)


def _standing_ticks(robot, n: int, count: int, seed: int):
    """``count`` (q, wrench): configurations near neutral (each kept two ticks), requests
    around the weight."""
    rng = np.random.default_rng(seed)
    weight = 9.81 * sum(inertia.mass for inertia in robot.model.inertias)
    q = robot.neutral()
    for k in range(count):
        q = q if k % 2 else random_configuration(robot, rng, scale=0.05)
        wrench = np.zeros(n)
        wrench[2] = weight * rng.uniform(0.5, 1.2)
        wrench += rng.normal(scale=0.05 * weight, size=n)
        yield q, wrench


def _core_again(case) -> bytes:
    """The compiled tick of a recorded ``again`` on fresh arrays: every output's bytes."""
    matrices, work, jacobian, frames, q, wrench, keep, weights, guess = case
    buffer, hot = np.zeros_like(work.buffer), guess.copy()
    out = np.zeros(work.pn + 2 * work.nv + 2 * len(wrench))
    active = np.zeros(len(guess), dtype=np.int64)
    count, norms = matrices.core.again(
        jacobian, frames, q, wrench, work.kept, buffer, work.layout, keep, weights, hot,
        ACTIVE_TOL, EXACT_TOL, EPS_ABS, out, active,
    )  # fmt: skip
    return b"".join(np.asarray(a).tobytes() for a in
                    (count, norms, buffer, out, hot, active[: max(count, 0)]))  # fmt: skip


def test_compiled_qp_ticks_from_four_threads_give_the_serial_bits(recorder):
    """The compiled QP's per-thread scratch: ticks of three declarations of different sizes
    (talos' soles, the hexapod, solo12), interleaved and shared by four threads that run them at
    once (the GIL released), give the bits of one thread running each alone, in any order."""
    for name in ("talos soles", "hexapod", "solo12 least normal, limits"):
        robot_name, base, feet, options = DECLARATIONS[name]
        robot = va.load_robot(robot_name)
        body = va.ParallelVirtualActuator(robot, base, feet, "world", **options)
        for q, wrench in _standing_ticks(robot, body.n, 30, seed=5):
            try:
                body.solve(q, wrench, method="qp")
            except va.ConstraintError:
                pass
    sizes: dict[int, list] = {}
    for case in recorder.agains:
        sizes.setdefault(len(case[1].buffer), []).append(case)
    assert len(sizes) == 3  # one tick of each size in turn
    cases = [case for group in zip(*sizes.values(), strict=False) for case in group]
    assert len(cases) >= 30
    alone = [_core_again(case) for case in cases]
    with concurrent.futures.ThreadPoolExecutor(max_workers=4) as pool:
        for _ in range(3):
            assert list(pool.map(_core_again, cases)) == alone
    assert [_core_again(case) for case in reversed(cases)] == alone[::-1]


@pytest.mark.parametrize("name", sorted(DECLARATIONS))
def test_qp_solves_from_q_equal_solves_from_snapshots(name):
    """``solve(q)`` (kinematics and the certified tick in one compiled call) and ``solve`` on a
    snapshot of ``q`` (the kinematics first), with the same history: the same bits."""
    robot_name, base, feet, options = DECLARATIONS[name]
    robot = va.load_robot(robot_name)
    from_q, from_snapshot = (va.ParallelVirtualActuator(robot, base, feet, "world", **options)
                             for _ in range(2))  # fmt: skip
    for q, wrench in _standing_ticks(robot, from_q.n, 60, seed=2):
        solutions = []
        for body, state in ((from_q, q), (from_snapshot, va.Snapshot(robot, q))):
            try:
                solutions.append(body.solve(state, wrench, method="qp"))
            except va.ConstraintError as error:
                solutions.append(str(error))
        ours, theirs = solutions
        if isinstance(ours, str):
            assert ours == theirs
            continue
        for field in ("forces", "tau", "wrench", "residual", "active"):
            assert np.array_equal(getattr(ours, field), getattr(theirs, field)), field


def test_contact_margins_are_bit_identical(monkeypatch):
    """The yield policy's margins: recorded from walking ticks (the turkey's and the flamingo's
    unilateral feet and cones), and on random forces with every kind of contact row."""
    calls = {"least": [], "largest": []}
    for kind, name in (("least", "_least_margin"), ("largest", "_largest_scale")):
        original = getattr(contact_limits, name)

        def recording(*arguments, original=original, kind=kind):
            calls[kind].append(tuple(np.array(a) for a in arguments))
            return original(*arguments)

        monkeypatch.setattr(contact_limits, name, recording)
    monkeypatch.setenv("VA_PLAN", "0")  # the gaits' Python ticks, where the margins are called
    run_walk("turkey-walk", duration=0.3, progress=False, stop_on_fall=False)
    run_walk("flamingo-slopes", duration=0.3, progress=False, stop_on_fall=False)
    assert len(calls["least"]) > 100
    rng = np.random.default_rng(8)
    for k in range(300):  # random tables: minima, pyramids with and without normal rows
        p, n = rng.integers(1, 5), rng.integers(3, 7)
        frames = np.zeros((p + 2, 12))
        for row in range(p + 2):
            frames[row, :9] = _rotation(rng.normal(size=3), rng.uniform(0, np.pi)).ravel()
        points = np.zeros((p, 7))
        points[:, 0] = rng.uniform(0.2, 1.0) if k % 3 else -1.0  # friction (< 0: none)
        points[:, 1] = rng.uniform(0.0, 2.0)
        points[:, 2] = 1.0 if k % 3 == 0 or k % 2 else 0.0  # the normal row
        points[:, 3] = k % 2  # a frame normal
        points[:, 4:] = rng.normal(size=(p, 3))
        points[:, 4:] /= np.linalg.norm(points[:, 4:], axis=1, keepdims=True)
        points = points if k % 5 else points[:0]
        axis_rows = np.sort(rng.choice(6, size=n, replace=False)).astype(np.int64)
        minima = rng.choice(n, size=rng.integers(0, 3), replace=False).astype(np.int64)
        count = len(minima) * p + sum(int(r[2] > 0) + 4 * int(r[0] >= 0) for r in points)
        lows = rng.normal(size=count)
        rows = np.arange(p + 1, dtype=np.int64)[::-1].copy()
        full, base = rng.normal(size=(p, n)), rng.normal(size=(p, n))
        calls["least"].append((frames, rows, full, points, axis_rows, minima, lows))
        calls["largest"].append((frames, rows, full, base, points, axis_rows, minima, lows))
    for arguments in calls["least"]:
        reference = contact_set.least_margin(*arguments)
        assert CORE.contact_least_margin(*arguments) == reference
    for arguments in calls["largest"]:
        reference = contact_set.largest_scale(*arguments)
        assert CORE.contact_largest_scale(*arguments) == reference
