"""The simulation's kernel: the compiled core's ``efforts_to_ctrl`` against its definition, and
the simulator's one-call effort writer against the general conversion it replaces.

The core's ``efforts_to_ctrl`` (``src/core/simulation.hpp``) and its definition in numpy (a
gather after two checks, written here) run on copies of the same arguments, recorded from a
turkey walk and completed by the branches walks do not reach (a NaN, an infinity, an unactuated
effort at and beyond the tolerance); their answers and what they write are compared with
``np.array_equal``.
`Simulator.step` is then checked against ``torques_to_ctrl`` (numpy fancy indexing, the
definition): the same controls, the same errors. The free-flyer's velocity read
(``state_velocity``) and ``va.run``'s reading check (``reading_error``) against theirs.
"""

from __future__ import annotations

import numpy as np
import pytest

import virtual_actuators as va
from virtual_actuators.core import CORE
from virtual_actuators.gaits.registry import run_walk
from virtual_actuators.simulation import Simulator, conversions
from virtual_actuators.simulation.conversions import UNACTUATED_TOLERANCE, gathers, torques_to_ctrl

core = pytest.mark.skipif(CORE is None, reason="virtual_actuators._core is not built")


def efforts_to_ctrl(tau, direct, unactuated, tolerance, ctrl) -> int:
    """The definition: 1 if an effort is not finite, 2 if an unactuated one is beyond the
    tolerance (``ctrl`` untouched), else ``ctrl = tau[direct]`` and 0."""
    if not np.isfinite(tau).all():
        return 1
    if np.any(np.abs(tau[unactuated]) > tolerance):
        return 2
    ctrl[:] = tau[direct]
    return 0


def _compare(tau, direct, unactuated, tolerance, ctrl) -> int:
    ours, theirs = ctrl.copy(), ctrl.copy()
    answer = CORE.efforts_to_ctrl(tau, direct, unactuated, tolerance, ours)
    assert answer == efforts_to_ctrl(tau, direct, unactuated, tolerance, theirs)
    assert np.array_equal(ours, theirs)
    return answer


@core
def test_the_walks_efforts_are_written_bit_identically(monkeypatch):
    calls = []
    original = conversions.ctrl_writer

    def recording(mm, ctrl):
        maps = gathers(mm)

        def write(tau, ignore_unactuated):
            unactuated = maps.unactuated_v[:0] if ignore_unactuated else maps.unactuated_v
            calls.append((tau.copy(), maps.direct_ctrl, unactuated, ctrl.copy()))
            return inner(tau, ignore_unactuated)

        inner = original(mm, ctrl)
        return write

    monkeypatch.setattr("virtual_actuators.simulation.simulator.ctrl_writer", recording)
    run_walk("turkey-walk", duration=0.3, progress=False)
    assert len(calls) == 300
    for tau, direct, unactuated, ctrl in calls:
        assert _compare(tau, direct, unactuated, UNACTUATED_TOLERANCE, ctrl) == 0


@core
@pytest.mark.parametrize(
    ("index", "value", "answer"),
    [
        (4, np.nan, 1),
        (0, np.inf, 1),
        (5, -np.inf, 1),
        (1, UNACTUATED_TOLERANCE, 0),
        (1, -UNACTUATED_TOLERANCE, 0),
        (1, 2 * UNACTUATED_TOLERANCE, 2),
        (2, -1.0, 2),
        (3, 1e3, 0),  # an actuated joint: any finite effort
    ],
)
def test_both_kernels_refuse_alike(index, value, answer):
    rng = np.random.default_rng(index)
    tau = rng.normal(size=7)
    tau[:3] = 0.0
    tau[index] = value
    direct = np.array([3, 4, 5, 6], dtype=np.intp)
    unactuated = np.array([0, 1, 2], dtype=np.intp)
    assert _compare(tau, direct, unactuated, UNACTUATED_TOLERANCE, np.full(4, 7.0)) == answer


@core
def test_the_core_refuses_indices_out_of_range():
    tau, ctrl = np.zeros(7), np.zeros(2)
    with pytest.raises(ValueError, match="out of range"):
        CORE.efforts_to_ctrl(tau, np.array([0, 7]), np.array([], dtype=np.intp), 1e-9, ctrl)
    with pytest.raises(ValueError, match="one entry per"):
        CORE.efforts_to_ctrl(tau, np.array([0]), np.array([], dtype=np.intp), 1e-9, ctrl)


@pytest.mark.parametrize("name", ["spring_turkey", "solo12"])
def test_step_writes_what_torques_to_ctrl_returns(name):
    robot = va.load_robot(name)
    simulator = Simulator(robot)
    mm, nv = simulator.mujoco_model, robot.model.nv
    unactuated = gathers(mm).unactuated_v.tolist()
    rng = np.random.default_rng(2)
    for _ in range(20):
        tau = rng.normal(size=nv)
        tau[unactuated] = 0.0
        for candidate in (tau, tau.astype(np.float32), tau[::-1].copy()[::-1], list(tau)):
            simulator.step(candidate)
            expected = torques_to_ctrl(mm, np.asarray(candidate, dtype=float))
            assert np.array_equal(simulator.data.ctrl, expected)
        loaded = tau.copy()
        loaded[unactuated] = 1.0  # dropped on request
        simulator.step(loaded, ignore_unactuated=True)
        expected = torques_to_ctrl(mm, loaded, ignore_unactuated=True)
        assert np.array_equal(simulator.data.ctrl, expected)


def test_step_refuses_bad_efforts_and_keeps_the_controls():
    robot = va.load_robot("spring_turkey")
    simulator = Simulator(robot)
    nv = robot.model.nv
    simulator.step(np.zeros(nv))
    before = simulator.data.ctrl.copy()
    bad = np.zeros(nv)
    bad[4] = np.nan
    with pytest.raises(va.InvalidInputError, match="non-finite value at index 4"):
        simulator.step(bad)
    pushed = np.zeros(nv)
    pushed[1] = 1.0  # boom_z: no actuator
    with pytest.raises(va.InvalidInputError, match="boom_z"):
        simulator.step(pushed)
    with pytest.raises(va.InvalidInputError, match=f"{nv} entries"):
        simulator.step(np.zeros(nv + 1))
    assert np.array_equal(simulator.data.ctrl, before)


@core
@pytest.mark.parametrize("name", ["solo12", "hexapod", "talos"])
def test_the_free_flyer_velocity_is_read_bit_identically(name):
    """``Simulator.v`` (the core's ``state_velocity``) against the Python conversion."""
    from virtual_actuators.simulation.conversions import state_velocity

    simulator = Simulator(va.load_robot(name))
    rng = np.random.default_rng(3)
    for _ in range(50):
        simulator.data.qvel[:] = rng.normal(size=simulator.model.nv)
        simulator.data.qpos[3:7] = rng.normal(size=4) * 0.5 + (1.0, 0.0, 0.0, 0.0)
        expected = state_velocity(simulator.mujoco_model, simulator.data.qpos, simulator.data.qvel)
        assert np.array_equal(simulator.v, expected)


@core
def test_the_reading_check_is_the_unit_norm_check_and_finiteness():
    """``reading_error``: ``unit_norm_error`` of ``q``, -1 when ``q`` or ``v`` is not finite."""
    q, v = np.array([0.0, 0.0, 0.3, 0.0, 0.0, 0.6, 0.8, 0.1]), np.zeros(7)
    bounds = np.array([[3, 7]], dtype=np.int64)
    assert CORE.reading_error(q, v, bounds) == CORE.unit_norm_error(q, bounds)
    v[2] = np.nan
    assert CORE.reading_error(q, v, bounds) == -1.0
    v[2], q[0] = 0.0, np.inf
    assert CORE.reading_error(q, v, bounds) == -1.0
    with pytest.raises(ValueError):
        CORE.reading_error(q, v, np.array([[3, 9]], dtype=np.int64))
