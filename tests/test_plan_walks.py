"""Every registered walk on the compiled machine against the same walk in Python.

Each walk runs twice from the same start: lowered into the core (the default) and in Python
(``VA_PLAN=0``). Over the first `TICKS` ticks, each tick's efforts agree to `TOLERANCE` of the
tick's scale (its largest effort, at least 1 N m), and the machines' histories agree. Past that,
a walk whose next touchdown turns on the last bits of a contact's timing may drift apart from
rounding alone: the Python path's numpy products round by the arrays' alignment in memory, so
even two Python runs of solo12's pace in one process can part at its first flight phase; the
walks' own targets are checked in their test files.
"""

from __future__ import annotations

import numpy as np
import pytest
from oracles import assert_same_walk

import virtual_actuators as va
from virtual_actuators.core import CORE
from virtual_actuators.gaits.legged import LeggedWalker
from virtual_actuators.gaits.registry import WALKS, run_walk

pytestmark = [
    pytest.mark.skipif(CORE is None or not hasattr(CORE, "PlanMachine"), reason="no core"),
    pytest.mark.filterwarnings("ignore:Robot 'hyq'"),
]

TICKS = 250
TOLERANCE = 1e-12  # [-] of the tick's scale

CASES = {name: (name, {}) for name in WALKS} | {
    "legged go2 trot, partitioned": ("legged", {"robot": "go2", "distribution": "partitioned"}),
    "legged go2 pace": ("legged", {"robot": "go2", "gait": "pace"}),
    "legged hexapod tripod": ("legged", {"robot": "hexapod", "gait": "tripod"}),
    "balance g1": ("balance", {"robot": "g1"}),
    "hexapod pendulum": ("hexapod-walk", {"pendulum": True}),
    "hexapod tracking": ("hexapod-walk", {"track": True}),
    "hexapod circle": ("hexapod-walk", {"yaw_rate": 0.5}),
    "hexapod sine": ("hexapod-walk", {"path": "sine"}),
    "hexapod partitioned": ("hexapod-walk", {"distribution": "partitioned"}),
}


@pytest.mark.parametrize("case", list(CASES))
def test_the_compiled_walk_is_the_python_walk(case, monkeypatch):
    name, options = CASES[case]
    seconds = TICKS * 0.001
    compiled = run_walk(name, duration=seconds, progress=False, stop_on_fall=False, **options)
    monkeypatch.setenv("VA_PLAN", "0")
    python = run_walk(name, duration=seconds, progress=False, stop_on_fall=False, **options)
    assert python.gait.compiled is None
    assert compiled.gait.compiled is not None, "the walk did not run on the compiled machine"
    ours, theirs = compiled.loop.efforts, python.loop.efforts
    assert ours.shape == theirs.shape and len(ours) >= TICKS - 1
    scale = np.maximum(1.0, np.abs(theirs).max(axis=1))
    worst = np.abs(ours - theirs).max(axis=1) / scale
    assert worst.max() <= TOLERANCE, f"tick {int(worst.argmax())}: {worst.max():.3g}"
    assert compiled.gait.machine.history == python.gait.machine.history


@pytest.mark.slow
def test_the_hexapods_compiled_walk_is_its_python_walk_bit_for_bit(monkeypatch):
    """Two simulated seconds balancing the pendulum, lowered whole (no Python piece): every log
    channel, state, effort and velocity the Python machine's, bit for bit."""
    options = {"duration": 2.0, "progress": False, "pendulum": True}
    compiled = run_walk("hexapod-walk", **options)
    assert compiled.gait.compiled is not None and compiled.gait.compiled.pieces == []
    monkeypatch.setenv("VA_PLAN", "0")
    python = run_walk("hexapod-walk", **options)
    assert python.gait.compiled is None
    assert_same_walk(compiled, python)
    assert not compiled.metrics.fell


@pytest.mark.parametrize(
    ("robot", "pattern"),
    [("solo12", "trot"), ("go2", "trot"), ("go2", "walk"), ("hexapod", "tripod")],
)
def test_a_legged_walker_lowers_whole(robot, pattern):
    """Its hooks, its body model, its swing feet and its touchdown events: no Python piece."""
    walker = LeggedWalker(va.load_robot(robot), pattern=pattern)
    walker.wiring.warm_up(walker.initial_configuration())
    compiled = walker.wiring.compiled
    assert compiled is not None and compiled.pieces == [], compiled.pieces
    assert walker.memory.fields["setpoint"] == (0.0, 0.0)  # the state: a view of the registers
