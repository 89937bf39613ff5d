"""``solve(q, wrench)``'s one-call path against the general path it stands in for, bit for bit.

The default request from a configuration (no free axes, the partitioned method, the compiled
kernels, the declaration's weights) is answered by one call of the compiled core that checks
``q`` and the wrench, runs the kinematics and the distribution
(:class:`~virtual_actuators.distribution.partitioned.compiled.ConfigurationSolve`). Every field of
its solution must equal the general path's (the argument checks in Python, then the same kernels
through ``Solution.from_tick``), and every argument the Python checks would refuse or change must
reach them, with the same typed error.
"""

from __future__ import annotations

import dataclasses
import threading

import numpy as np
import pytest
from oracles import random_configuration

import virtual_actuators as va
from virtual_actuators.core import CORE
from virtual_actuators.distribution.result import Solution
from virtual_actuators.exceptions import InvalidInputError
from virtual_actuators.kinematics.tree import tree_of

pytestmark = pytest.mark.skipif(CORE is None, reason="virtual_actuators._core is not built")

SOLO_FEET = ["FL_FOOT", "FR_FOOT", "HL_FOOT", "HR_FOOT"]


def _declarations():
    solo = va.load_robot("solo12")
    yield (
        "solo12 (README)",
        va.ParallelVirtualActuator(
            solo, "base_link", SOLO_FEET, reference="base_link", contact="point"
        ),
    )
    design = [
        va.Equal((SOLO_FEET[0], "x"), (SOLO_FEET[1], "x")),
        va.Equal((SOLO_FEET[0], "x"), (SOLO_FEET[2], "x")),
        va.Equal((SOLO_FEET[0], "x"), (SOLO_FEET[3], "x")),
        va.Equal((SOLO_FEET[0], "y"), (SOLO_FEET[1], "y")),
        va.Equal((SOLO_FEET[2], "y"), (SOLO_FEET[3], "y")),
        va.Linear({(SOLO_FEET[0], "z"): 1, (SOLO_FEET[3], "z"): 1, (SOLO_FEET[1], "z"): -1}),
    ]
    yield (
        "solo12 design rows (mode 1)",
        va.ParallelVirtualActuator(solo, "base_link", SOLO_FEET, reference="world", design=design),
    )
    hexapod = va.load_robot("hexapod")
    feet = [f"foot_{i}" for i in range(1, 7)]
    yield "hexapod", va.ParallelVirtualActuator(hexapod, "body", feet, "world")
    talos = va.load_robot("talos")
    yield "talos flat soles, limp ankle", va.ParallelVirtualActuator(
        talos, "base_link", ["left_sole_link", "right_sole_link"], "world", contact="flat",
        unactuated=["leg_left_5_joint"],
    )  # fmt: skip
    flamingo = va.load_robot("spring_flamingo")
    yield "flamingo, passive ankle", va.ParallelVirtualActuator(
        flamingo, "body", ["left_foot", "right_foot"], "world", ("x", "z", "ry"),
        contact="flat", passive={"left_ankle": (3.0, 0.1)},
    )  # fmt: skip
    turkey = va.load_robot("spring_turkey")
    yield "turkey, equal hip torques", va.ParallelVirtualActuator(
        turkey, "body", ["left_foot", "right_foot"], "world", ("x", "z", "ry"),
        design=[va.EqualTorque("left_hip", "right_hip")],
    )  # fmt: skip


DECLARATIONS = list(_declarations())


def _general(body: va.ParallelVirtualActuator, q, wrench, **options) -> Solution:
    """The general path: ``free`` as a list is not the default request's tuple."""
    return body.solve(q, wrench, free=[], **options)


def _assert_same(fast: Solution, general: Solution) -> None:
    for field in dataclasses.fields(Solution):
        a, b = getattr(fast, field.name), getattr(general, field.name)
        if isinstance(b, np.ndarray):
            assert a.dtype == b.dtype and a.shape == b.shape, field.name
            assert np.array_equal(a, b), (field.name, a, b)
        else:
            assert type(a) is type(b) and a == b, (field.name, a, b)
    assert fast.admissible == general.admissible


@pytest.mark.parametrize("case", DECLARATIONS, ids=[c[0] for c in DECLARATIONS])
def test_the_one_call_solve_gives_the_general_paths_bits(case):
    _, body = case
    robot = body.robot
    rng = np.random.default_rng(11)
    decided = 0
    for k in range(60):
        q = random_configuration(robot, rng, scale=0.4)
        wrench = rng.normal(size=body.n) * rng.choice([1e-6, 1.0, 1e3, 1e200])
        tol = [1e-6, 0.0, 1e-3][k % 3]
        q.flags.writeable = wrench.flags.writeable = k % 2 == 0  # read-only arrays too
        one_call = body._configuration_solve(q, wrench, tol)  # None: handed on
        try:
            general = _general(body, q, wrench, tol=tol)
        except va.SingularConfigurationError:
            assert one_call is None
            continue
        solution = body.solve(q, wrench, tol=tol)
        _assert_same(solution, general)
        if one_call is not None:
            _assert_same(one_call, general)
            decided += 1
    assert decided >= 30  # the one-call path ran, not only the general one


def test_the_default_call_takes_the_one_call_path(monkeypatch):
    body = DECLARATIONS[0][1]
    q, wrench = body.robot.neutral(), np.array([2.0, 1.0, 25.0, 0.1, -0.2, 0.05])
    one_call, calls = body._configuration_solve, []

    def counting(*arguments):
        calls.append(arguments)
        return one_call(*arguments)

    monkeypatch.setattr(body, "_configuration_solve", counting)
    body.solve(q, wrench)
    body.solve(q, wrench, (), False, 1e-3, "partitioned", True, None)
    assert len(calls) == 2
    body.solve(q, wrench, free=[])
    body.solve(q, wrench, compiled=False)
    body.solve(va.Snapshot(body.robot, q), wrench)
    body.solve(q, wrench, method="dense")
    assert len(calls) == 2


def test_every_argument_the_checks_refuse_gets_their_error():
    body = DECLARATIONS[0][1]
    q, wrench = body.robot.neutral(), np.array([2.0, 1.0, 25.0, 0.1, -0.2, 0.05])
    bad_q = {
        "nan": np.where(np.arange(q.size) == 9, np.nan, q),
        "inf": np.where(np.arange(q.size) == 0, np.inf, q),
        "short": q[:-1].copy(),
        "2-D": q[None, :].copy(),
        "far from unit": np.concatenate((q[:3], 2 * q[3:7], q[7:])),
        "empty": np.zeros(0),
    }
    bad_wrench = {
        "nan": np.array([2.0, np.nan, 25.0, 0.1, -0.2, 0.05]),
        "-inf": np.array([2.0, 1.0, -np.inf, 0.1, -0.2, 0.05]),
        "long": np.ones(7),
        "2-D": wrench[None, :].copy(),
        "strings": np.array(["a"] * 6),
    }
    cases = [(b, wrench) for b in bad_q.values()] + [(q, b) for b in bad_wrench.values()]
    for arguments in cases:
        assert body._configuration_solve(*arguments, 1e-6) is None
        with pytest.raises(InvalidInputError) as general:
            _general(body, *arguments)
        with pytest.raises(InvalidInputError) as default:
            body.solve(*arguments)
        assert str(default.value) == str(general.value)


def test_arguments_the_checks_convert_reach_them():
    body = DECLARATIONS[0][1]
    rng = np.random.default_rng(4)
    q = random_configuration(body.robot, rng)
    wrench = np.array([2.0, 1.0, 25.0, 0.1, -0.2, 0.05])
    drifted = q.copy()
    drifted[3:7] *= 1.0 + 1e-7  # normalised by the checks (in a copy)
    strided = np.repeat(q, 2)[::2]  # not contiguous
    converted = [
        (drifted, wrench),
        (strided, wrench),
        (q.astype(np.float32), wrench),
        (q, wrench.astype(np.float32)),
        (q, np.array([2, 1, 25, 0, 0, 0])),
        (q, np.repeat(wrench, 2)[::2]),
        (q.astype(">f8"), wrench),  # not the native byte order
    ]
    for arguments in converted:
        assert body._configuration_solve(*arguments, 1e-6) is None
        _assert_same(body.solve(*arguments), _general(body, *arguments))
    assert not np.array_equal(drifted, q) and np.array_equal(drifted[7:], q[7:])


def test_strict_raises_the_same_error_on_both_paths():
    body = DECLARATIONS[0][1]
    q, wrench = body.robot.neutral(), np.array([2.0, 1.0, 25.0, 0.1, -0.2, 0.05])
    assert body._configuration_solve(q, wrench, 0.0) is not None
    _assert_same(body.solve(q, wrench, strict=True, tol=0.0), _general(body, q, wrench, tol=0.0))
    # two diagonal point feet: no moment about the line through them (the kernel hands it on)
    diagonal = va.ParallelVirtualActuator(
        body.robot, "base_link", ["FL_FOOT", "HR_FOOT"], "base_link", contact="point"
    )
    one_call = diagonal._configuration_solve  # None: no compiled tables for this mode
    assert one_call is None or one_call(q, wrench, 1e-6) is None
    with pytest.raises(va.InadmissibleWrenchError) as general:
        _general(diagonal, q, wrench, strict=True)
    with pytest.raises(va.InadmissibleWrenchError) as default:
        diagonal.solve(q, wrench, strict=True)
    assert str(default.value) == str(general.value)
    _assert_same(default.value.solution, general.value.solution)


def test_threads_share_the_one_call_solve():
    body = DECLARATIONS[0][1]
    rng = np.random.default_rng(8)
    configurations = [random_configuration(body.robot, rng, scale=0.2) for _ in range(40)]
    wrenches = [rng.normal(size=body.n) for _ in range(40)]
    expected = [_general(body, q, w) for q, w in zip(configurations, wrenches, strict=True)]
    failures: list[str] = []

    def worker(offset: int) -> None:
        for k in range(400):
            i = (k + offset) % 40
            solution = body.solve(configurations[i], wrenches[i])
            if not (
                np.array_equal(solution.tau, expected[i].tau)
                and np.array_equal(solution.forces, expected[i].forces)
            ):
                failures.append(f"thread {offset}, case {i}")

    threads = [threading.Thread(target=worker, args=(offset,)) for offset in range(4)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    assert not failures


def test_the_core_checks_what_the_python_checks_accept_unchanged():
    body = DECLARATIONS[3][1]  # talos: a free-flyer quaternion
    robot, tree = body.robot, tree_of(body.robot)
    core = body.compiled.mode_for(np.ones(body.n, dtype=bool)).core
    rng = np.random.default_rng(2)
    wrench = rng.normal(size=body.n)
    for name, other in DECLARATIONS:  # the length the core accepts is the model's nq
        assert tree_of(other.robot).core_tree.nq == other.robot.model.nq, name
    for k in range(40):
        q = random_configuration(robot, rng, scale=1.0)
        q[3:7] *= 1.0 + [0.0, 1e-13, 1e-9, 1e-4][k % 4]
        try:
            unchanged = tree.check_configuration(q) is q
        except InvalidInputError:
            unchanged = False
        status = core.checked_tick(tree.core_tree, q, wrench)[4]
        assert (status != CORE.Distribution.UNCHECKED) == unchanged, (k, status)
