"""The walks' loop is ``va.run``'s (its final zero effort); ``va.run``'s sense and after_tick.

Oracles: MuJoCo's own state after a walk (its clock and controls), and the values a law of the
stamp makes.
"""

from __future__ import annotations

import numpy as np
import pytest

import virtual_actuators as va
from virtual_actuators.gaits.registry import run_walk

PENDULUM = va.load_robot("double_pendulum")  # nq = nv = 2


def test_a_walk_ends_on_zero_effort_without_another_step():
    result = run_walk("turkey-walk", duration=0.2, progress=False)
    loop, simulator = result.loop, result.simulator
    period = simulator.control_period
    assert loop.ticks == loop.run.ticks == 200 and loop.run.failed_ticks == 0
    assert simulator.time == pytest.approx(0.2)  # the final zero did not step it
    assert result.log.time[-1] == pytest.approx(0.2 - period)  # the last control tick's sample
    assert not simulator.data.ctrl.any() and np.abs(loop.efforts[-1]).max() > 0.1


class StampLaw:
    """Efforts equal to what ``sense`` returned (the reading's stamp)."""

    robot = PENDULUM

    def compute(self, q, v, time, sensed):
        return np.full(2, sensed)


def _readings():
    stamps = iter(range(10**6))
    return lambda: (np.zeros(2), np.zeros(2), 1e-3 * next(stamps))


def test_sense_feeds_compute_and_after_tick_sees_every_write():
    seen = []
    stats = va.run(
        StampLaw(), _readings(), lambda tau: None, realtime=False,
        should_stop=lambda: len(seen) >= 5, sense=lambda q, v, stamp: stamp,
        after_tick=lambda q, v, stamp, output, tau: seen.append((stamp, output, tau.copy())),
    )  # fmt: skip
    assert stats.ticks == 5 and stats.failed_ticks == 0
    for stamp, output, tau in seen:
        np.testing.assert_array_equal(tau, [stamp, stamp])
        np.testing.assert_array_equal(output, tau)


def test_a_failing_sense_sends_the_safe_action():
    seen = []
    stats = va.run(
        StampLaw(), _readings(), lambda tau: None, realtime=False,
        should_stop=lambda: len(seen) >= 3, sense=lambda q, v, stamp: 1.0 / 0.0,
        after_tick=lambda q, v, stamp, output, tau: seen.append((output, tau.copy())),
    )  # fmt: skip
    assert stats.reasons == {"sense error: ZeroDivisionError": 3} and stats.zero_ticks == 3
    assert all(output is None and not tau.any() for output, tau in seen)


def test_hooks_must_be_callable():
    with pytest.raises(va.InvalidInputError, match="after_tick"):
        va.run(StampLaw(), _readings(), lambda tau: None, duration=0.01, after_tick=3)
