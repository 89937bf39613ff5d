"""Every tick's efforts and velocities recorded by the walks' loop, and the walks' JSON of them.

Oracle: MuJoCo's own state after each tick (its controls, the velocity the next tick reads),
read by an ``on_tick`` callback.
"""

import json

import numpy as np
import pytest

from virtual_actuators.experiments.smoothness import SmoothnessFigures
from virtual_actuators.gaits.balance.walk import run_balance
from virtual_actuators.gaits.registry import WALKS, run_walk
from virtual_actuators.simulation.conversions import torques_to_ctrl

KEYS = ("effort_oscillation", "effort_oscillation_joint", "effort_change_rms",
        "base_rate_alternation", "base_rate_oscillation_radps")  # fmt: skip


class Reader:
    """An on_tick callback: MuJoCo's controls and the state's velocity after every tick."""

    def __init__(self):
        self.ctrl, self.v = [], []

    def __call__(self, simulator, gait):
        self.ctrl.append(simulator.data.ctrl.copy())
        self.v.append(simulator.v)


@pytest.mark.parametrize(("name", "pitch"), [("legged", None), ("turkey-walk", "boom_pitch")])
def test_the_loop_records_what_it_sends_and_reads(name, pitch):
    reader = Reader()
    result = run_walk(name, duration=0.4, progress=False, on_tick=reader)
    loop, mm, model = result.loop, result.simulator.mujoco_model, result.simulator.robot.model
    assert loop.efforts.shape == loop.velocities.shape == (400, model.nv) and loop.ticks == 400
    sent = np.array([torques_to_ctrl(mm, tau, ignore_unactuated=True) for tau in loop.efforts])
    np.testing.assert_array_equal(sent, np.array(reader.ctrl))
    np.testing.assert_array_equal(loop.velocities[1:], np.array(reader.v)[:-1])
    rate = model.joints[model.getJointId(pitch)].idx_v if pitch else 3  # the free-flyer's
    axes = 1 if pitch else 3
    np.testing.assert_array_equal(loop.base_rates, loop.velocities[:, rate : rate + axes])
    assert np.abs(loop.efforts).max() > 0.1 and np.abs(loop.base_rates).max() > 1e-3


def test_the_measured_ticks_end_at_the_fall():
    result = run_balance("solo12", 2.5, "150@1.1:90", progress=False)
    loop, smoothness = result.loop, result.smoothness
    assert result.metrics.fell and loop.fall_tick is not None
    assert loop.fall_tick * loop.time_step == pytest.approx(result.metrics.fall_time_s)
    assert smoothness.ticks == max(0, loop.fall_tick - 1 - 1000)  # ticks in [1 s, fall)
    assert loop.ticks > loop.fall_tick + 400  # it went on for 0.5 s


@pytest.mark.parametrize("name", list(WALKS))
def test_every_walks_json_and_summary_carry_the_figures(name):
    result = run_walk(name, duration=1.3, progress=False)
    data = json.loads(json.dumps(result.to_json(), allow_nan=False))
    figures = {key: data[key] for key in KEYS}
    assert figures == result.smoothness.metrics_fields()
    assert all(value is not None for value in figures.values()), figures
    assert isinstance(figures["effort_oscillation_joint"], str)
    assert data["effort_oscillation"] < 0.005  # these five walks are smooth (issue 35)
    summary = result.metrics.summary()
    assert summary.endswith(SmoothnessFigures(**figures).smoothness_summary()), summary
    assert "effort osc" in summary and "-0.0" not in summary.split("effort osc")[1]
    assert result.smoothness.ticks == 299
