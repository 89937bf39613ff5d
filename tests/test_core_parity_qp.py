"""The compiled core's QP pieces against their oracles, and its threads and one-call paths.

The exact step on an active set (``_core.exact_step``) against the same step in Python
(``qp.exact.exact_step``, the fallback without the core), on the arguments of real
``method="qp"`` solves: solo12's point feet with friction (feasible and infeasible requests, a
least normal force, torque limits), talos' soles, the hexapod, nearly dependent request rows,
and walking ticks of the legged trot and pace (solo12) and of talos' balance. The serial actuators'
virtual sensor (``_core.relative_sensor``) against its numpy twin on every branch of the
rotation's log; the controller's contact margins (``contact_least_margin``,
``contact_largest_scale``) against the numpy rows of the same `ContactSet`. The answers of the
core's QP against the numpy QP, ProxQP, the KKT conditions and RNEA are tested in the
``test_qp*.py`` files.
"""

from __future__ import annotations

import concurrent.futures

import numpy as np
import pytest
from oracles import random_configuration

import virtual_actuators as va
from virtual_actuators.contacts import contact_set
from virtual_actuators.control import failures as contact_limits
from virtual_actuators.core import CORE
from virtual_actuators.distribution.qp import compiled, exact, stages
from virtual_actuators.distribution.tolerances import ACTIVE_TOL, EPS_ABS, EXACT_TOL
from virtual_actuators.gaits.registry import run_walk
from virtual_actuators.kinematics import relative
from virtual_actuators.vocabulary.axes import AXES

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


def _close(ours: np.ndarray, theirs: np.ndarray, scale: float) -> bool:
    return ours.shape == theirs.shape and bool(np.all(np.abs(ours - theirs) <= 1e-12 * scale))


def _check(recorder: Recorder, signs: bool = False) -> dict[str, int]:
    """Every recorded exact step through the core and through Python: the same answer (with
    ``signs``, the multipliers' signs alone: the active set they hand on)."""
    for arguments in recorder.steps:  # exact_answer's: rows, x, guess, exact, active_tol
        rows, (guess, certify, active_tol) = arguments[:7], arguments[8:]
        step = (*rows, guess, certify, active_tol, EXACT_TOL, exact.EXACT_STEPS)
        ok, x, z = exact.exact_step(*step)
        ok_c, x_c, z_c = CORE.exact_step(*step)
        assert ok == ok_c
        if ok:
            scale = max(1.0, np.abs(x).max(), np.abs(rows[1]).max())
            assert _close(x_c, x, scale)
            if signs:
                np.testing.assert_array_equal(np.sign(z_c), np.sign(z))
            else:
                assert _close(z_c, z, max(scale, np.abs(z).max()))
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
def test_the_exact_steps_of_qp_solves_equal_python(name, recorder):
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


def test_nearly_dependent_request_rows_in_both_exact_steps(recorder):
    """Two diagonal feet of solo12 at heights 1e-11..1e-7 m apart: the exact step takes a nearly
    dependent request row after the others (`exact._factor`), in the core and in Python alike."""
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


@pytest.mark.parametrize(("walk", "options", "signs"), [
    ("legged", {"robot": "solo12", "gait": "trot"}, False),
    # tick 266: an intermediate active set of the closest wrench with |x| ~ 1e6, its rows met
    # to round-off (Python's rounding passed the check, the core's did not: ProxQP answered);
    # its closest-wrench multipliers (~1e3) agree to 1e-11 of their size, their signs exactly
    ("legged", {"robot": "solo12", "gait": "pace", "distribution": "qp"}, True),
    ("balance", {}, False),
])  # fmt: skip
def test_walking_qp_ticks_exact_steps_equal_python(walk, options, signs, recorder, monkeypatch):
    monkeypatch.setenv("VA_PLAN", "0")  # the gaits' Python ticks, where the QP kernels are called
    run_walk(walk, duration=0.4, progress=False, stop_on_fall=False, **options)
    counts = _check(recorder, signs)
    assert counts["again"] + counts["ticks"] > 100 and counts["exact"] > 0


def _rotation(axis: np.ndarray, angle: float) -> np.ndarray:
    axis = axis / np.linalg.norm(axis)
    skew = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + np.sin(angle) * skew + (1 - np.cos(angle)) * skew @ skew


def test_the_virtual_sensor_equals_numpy_on_every_branch():
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
        reference = relative.relative_sensor(*arguments)
        assert _close(CORE.relative_sensor(*arguments), reference, _sensor_scale(arguments))


def _sensor_scale(arguments: tuple) -> float:
    """The reading's scale times the rotation log's condition near pi (``theta / sin theta``:
    the rounding of ``R_A^T R_B`` grows by it in the log)."""
    jacobian, frames, v, _, rows = arguments[:5]
    reach = 1.0 + np.abs(frames[:, 9:]).max()
    relative = frames[rows[2], :9].reshape(3, 3).T @ frames[rows[0], :9].reshape(3, 3)
    theta = np.arccos(np.clip(0.5 * (np.trace(relative) - 1.0), -1.0, 1.0))
    condition = 1.0 + theta / max(np.sin(theta), 1e-3)
    return max(1.0, np.abs(jacobian).max() * reach * (1.0 + np.abs(v).sum())) * condition


def test_walking_sensor_readings_equal_numpy(monkeypatch):
    calls = []
    original = relative.sensor

    def recording(*arguments):
        calls.append(tuple(np.array(a) for a in arguments))
        return original(*arguments)

    monkeypatch.setattr(relative, "sensor", recording)
    monkeypatch.setenv("VA_PLAN", "0")  # the gaits' Python ticks, where the sensors are read
    run_walk("balance", duration=0.2, progress=False, stop_on_fall=False)
    run_walk("turkey-walk", duration=0.2, progress=False, stop_on_fall=False)
    assert len(calls) > 100
    for arguments in calls:
        reference = relative.relative_sensor(*arguments)
        assert _close(CORE.relative_sensor(*arguments), reference, _sensor_scale(arguments))


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


def _random_contacts(rng: np.random.Generator, k: int):
    """A `ContactSet` of every kind of point row (minima, pyramids with and without the normal
    row, frame normals) and a frame table holding {O} after the reactions."""
    p = int(rng.integers(1, 5))
    axes = tuple(AXES[i] for i in np.sort(rng.choice(6, size=int(rng.integers(3, 7)),
                                                      replace=False)))  # fmt: skip
    reactions = [f"foot_{i}" for i in range(p)]
    forces_axes = [i for i, axis in enumerate(axes) if axis in ("x", "y", "z")]
    minima = {int(i): float(rng.uniform(0, 2)) for i in rng.choice(
        forces_axes or [0], size=int(rng.integers(0, 3)), replace=True)} if forces_axes else {}
    friction = float(rng.uniform(0.2, 1.0)) if k % 3 and {"x", "y", "z"} <= set(axes) else None
    min_normal = float(rng.uniform(0.0, 2.0)) if friction is not None and k % 2 else 0.0
    normals = "frames" if k % 4 == 1 and friction is not None else None
    contacts = contact_set.declare(reactions, axes, "point", friction, min_normal, normals,
                                   minima=minima)  # fmt: skip
    frames = np.zeros((p + 1, 12))
    for row in range(p + 1):
        frames[row, :9] = _rotation(rng.normal(size=3), rng.uniform(0, np.pi)).ravel()
    orientation_rows = np.array([p, *range(p)], dtype=np.int64)
    return contacts, frames, orientation_rows


def test_contact_margins_equal_the_numpy_rows():
    """The yield policy's margins on random contact sets and forces: the core's least margin
    and largest feasible scale against ``ContactSet.rows`` (numpy) and the numpy ratio test."""
    rng = np.random.default_rng(8)
    checked = 0
    for k in range(300):
        contacts, frames, orientation_rows = _random_contacts(rng, k)
        tables = contacts.compiled()
        if tables is None:
            continue
        p, n = len(contacts.reactions), len(contacts.axes)
        rotation_o = frames[orientation_rows[0], :9].reshape(3, 3)
        rotations = frames[orientation_rows[1:], :9].reshape(-1, 3, 3)
        rows = contacts.rows(rotation_o, rotations)
        if not len(rows.lows):
            continue
        full, base = rng.normal(size=(p, n)) * 10.0, rng.normal(size=(p, n)) * 10.0
        least = CORE.contact_least_margin(frames, orientation_rows, full, *tables)
        oracle = float((rows.G @ full.ravel() - rows.lows).min())
        assert abs(least - oracle) <= 1e-12 * max(1.0, np.abs(full).max()), k
        scale = CORE.contact_largest_scale(frames, orientation_rows, full, base, *tables)
        expected = contact_limits.ratio_test(rows.G @ full.ravel(), rows.G @ base.ravel(),
                                             rows.lows)  # fmt: skip
        assert abs(scale - expected) <= 1e-9, k
        checked += 1
    assert checked > 150
