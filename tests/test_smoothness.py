"""effort_smoothness on hand-made signals, beside an oracle written out tick by tick."""

import json
import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from virtual_actuators.exceptions import InvalidInputError
from virtual_actuators.experiments.metrics import WalkMetrics
from virtual_actuators.experiments.smoothness import (
    RATE_FLOOR_RADPS,
    SmoothnessFigures,
    effort_smoothness,
)

DT = 1e-3  # [s]
TICKS = 3000
T = np.arange(TICKS) * DT  # [s]
SIGN = np.where(np.arange(TICKS) % 2 == 0, 1.0, -1.0)  # +1, -1, +1, ...


def column(*signals):
    return np.column_stack(signals)


# -- the oracle: the definitions written out tick by tick -------------------------------------


def oracle(efforts, limits, rates=None, skip_s=1.0, floor=RATE_FLOOR_RADPS):
    """(oscillation, worst joint index, rms change, alternation, rate oscillation)."""
    ticks = len(efforts)
    start = max(1, math.ceil(skip_s / DT - 1e-9))
    limited = [j for j, limit in enumerate(limits) if 0.0 < limit < math.inf]
    per_joint, squares = {}, []
    for j in limited:
        values = [
            abs(efforts[k, j] - (efforts[k - 1, j] + efforts[k + 1, j]) / 2) / limits[j]
            for k in range(start, ticks - 1)
        ]
        per_joint[j] = float(np.percentile(values, 75))
        squares += [((efforts[k, j] - efforts[k - 1, j]) / limits[j]) ** 2
                    for k in range(start, ticks)]  # fmt: skip
    worst = max(per_joint, key=per_joint.get)
    rms = math.sqrt(sum(squares) / len(squares))
    if rates is None:
        return per_joint[worst], worst, rms, None, None
    alternations, oscillations = [], []
    for a in range(rates.shape[1]):
        w = rates[:, a]
        count, seconds = 0, []
        first = max(start, 2)
        for k in range(first, ticks - 2):
            c = [w[i] - w[i - 1] for i in (k - 1, k, k + 1, k + 2)]
            if all(c[i] * c[i + 1] < 0 for i in range(3)) and all(abs(x) > floor for x in c):
                count += 1
        for k in range(first, ticks - 1):
            seconds.append(abs(w[k] - (w[k - 1] + w[k + 1]) / 2))
        alternations.append(count / (ticks - 2 - first))
        oscillations.append(float(np.percentile(seconds, 75)))
    return per_joint[worst], worst, rms, max(alternations), max(oscillations)


def figures(s):
    return s.oscillation, s.joints.index(s.oscillation_joint), s.change_rms, s.rate_alternation, \
        s.rate_oscillation_radps  # fmt: skip


@given(st.integers(0, 2**32 - 1))
def test_the_figures_are_the_definitions(seed):
    rng = np.random.default_rng(seed)
    ticks = 1100 + int(rng.integers(0, 40))
    smooth = np.cumsum(rng.normal(0.0, 0.2, (ticks, 4)), axis=0)
    efforts = smooth + rng.choice([0.0, 1.0], (1, 4)) * rng.normal(0.0, 3.0, (ticks, 4))
    rates = 0.01 * np.cumsum(rng.normal(0.0, 1.0, (ticks, 3)), axis=0)
    rates += rng.choice([0.0, 0.02]) * SIGN[:ticks, None] * rng.uniform(0.5, 1.5, (ticks, 3))
    limits = np.array([10.0, np.inf, 0.0, 30.0]) * rng.uniform(0.5, 2.0, 4)
    names = ["a", "b", "c", "d"]
    result = effort_smoothness(efforts, limits, rates, names=names)
    expected = oracle(efforts, limits, rates)
    assert result.joints == ("a", "d")  # inf and 0: no limit
    np.testing.assert_allclose(figures(result)[0], expected[0], rtol=1e-12)
    assert names.index(result.oscillation_joint) == expected[1]
    np.testing.assert_allclose(figures(result)[2:], expected[2:], rtol=1e-12)
    assert result.ticks == ticks - 1001


# -- hand-made signals ---------------------------------------------------------------------------


def test_a_full_swing_between_the_limits_is_200_percent():
    limit = 30.0  # [N m]
    result = effort_smoothness(column(limit * SIGN), [limit], names=["knee"])
    assert result.oscillation == pytest.approx(2.0) and result.oscillation_joint == "knee"
    assert result.change_rms == pytest.approx(2.0)  # 2 L every tick
    half = effort_smoothness(column(0.25 * limit * SIGN + 5.0), [limit])
    assert half.oscillation == pytest.approx(0.5)


def test_ramps_and_slow_sines_do_not_oscillate():
    sine = 20.0 * np.sin(2 * np.pi * 2.0 * T)  # [N m], 2 Hz
    result = effort_smoothness(column(3.0 * T, sine, -7.0 + 0 * T), [30.0, 30.0, 30.0])
    assert result.oscillation < 1e-4  # 20 (2 pi 2 dt)^2 / 2 / 30 = 5e-5
    assert max(result.joint_oscillation[:1] + result.joint_oscillation[2:]) < 1e-12
    expected = math.sqrt(((3.0 * DT / 30.0) ** 2 + np.mean(np.diff(sine[999:]) ** 2) / 900) / 3)
    assert result.change_rms == pytest.approx(expected, rel=1e-3)


def test_a_step_is_no_oscillation():
    step = np.where(T >= 2.0, 15.0, 0.0)  # [N m], a touchdown
    result = effort_smoothness(column(step), [30.0])
    assert result.oscillation == 0.0
    assert result.change_rms == pytest.approx(0.5 / math.sqrt(TICKS - 1000))
    assert max(result.joint_oscillation) == 0.0


def test_the_worst_joint_and_what_is_left_out():
    efforts = column(5.0 * SIGN, 1.0 * SIGN, 100.0 * SIGN, 50 * SIGN)
    result = effort_smoothness(efforts, [50.0, 1.0, np.inf, -1.0], names=["a", "b", "c", "d"])
    assert result.joints == ("a", "b") and result.oscillation_joint == "b"
    assert result.joint_oscillation == pytest.approx((0.2, 2.0))
    unnamed = effort_smoothness(efforts, [50.0, 1.0, np.inf, 0.0])
    assert unnamed.oscillation_joint == "dof 1"


def test_the_first_second_is_left_out():
    start_up = np.where(T < 1.0, 30.0 * SIGN, 0.0)
    result = effort_smoothness(column(start_up), [30.0], column(start_up))
    assert result.oscillation == 0.0 and result.rate_alternation == 0.0
    everything = effort_smoothness(column(start_up), [30.0], column(start_up), skip_s=0.0)
    assert everything.oscillation == pytest.approx(2.0)  # a third of the ticks at 200 %
    assert everything.rate_alternation == pytest.approx(1000 / 2997, rel=0.01)
    assert effort_smoothness(column(SIGN[:2000]), [1.0], time_step=2e-3).ticks == 1499


def test_base_rate_alternation():
    floor = RATE_FLOOR_RADPS
    alternating = 0.38 * SIGN  # [rad/s], g1's balance before the fix
    touchdown = np.where(T >= 2.0, 0.4, 0.1) - np.where(T >= 2.001, 0.05, 0.0)  # up, back once
    decay = np.exp(-np.maximum(T - 2.0, 0.0) / 2e-3)
    ringing = 0.01 + np.where(T >= 2.0, 0.2, 0.0) * (1 + 0.1 * SIGN * decay)  # a touchdown's
    noise = 0.2 * floor * np.random.default_rng(3).uniform(-1.0, 1.0, TICKS)
    slow = 0.5 * np.sin(2 * np.pi * 2.0 * T)
    rates = column(touchdown, ringing, alternating)
    result = effort_smoothness(column(0 * T), [1.0], rates)
    assert result.rate_alternation == pytest.approx(1.0)
    assert result.rate_oscillation_radps == pytest.approx(0.76)
    for axis in (touchdown, noise, slow):
        quiet = effort_smoothness(column(0 * T), [1.0], column(axis))
        assert quiet.rate_alternation == 0.0, axis
    ringing_only = effort_smoothness(column(0 * T), [1.0], column(ringing))
    assert 0.0 < ringing_only.rate_alternation < 5 / 1997  # a few ticks of it
    small = effort_smoothness(column(0 * T), [1.0], column(0.4 * floor * SIGN))
    assert small.rate_alternation == 0.0 and small.rate_oscillation_radps > 0.0
    one_axis = effort_smoothness(column(0 * T), [1.0], column(alternating))
    assert one_axis.rate_alternation == pytest.approx(1.0)


def test_too_short_a_run_is_not_measured():
    result = effort_smoothness(column(SIGN[:1001]), [1.0], column(SIGN[:1001]))
    assert result.oscillation is None and result.change_rms is None
    assert result.rate_alternation is None and result.ticks == 0
    assert result.summary() == "not measured"
    nothing_limited = effort_smoothness(column(SIGN), [np.inf])
    assert nothing_limited.oscillation is None and nothing_limited.joints == ()


def test_summary_and_json():
    result = effort_smoothness(column(30.0 * SIGN, 0 * T), [30.0, 10.0], column(-0.0 * T),
                               names=["LF_HAA", "LF_HFE"])  # fmt: skip
    assert result.summary() == (
        "effort osc 200.00 % (LF_HAA), change 141.4 %/tick, base rate alternating 0.0 %"
    )
    quiet = effort_smoothness(column(-1e-9 * T), [10.0], column(-1e-12 * T))
    assert "-0" not in quiet.summary() and "effort osc 0.00 %" in quiet.summary()
    data = json.loads(json.dumps(result.to_dict()))
    assert data["joints"] == ["LF_HAA", "LF_HFE"] and data["oscillation"] == pytest.approx(2.0)
    fields = result.metrics_fields()
    assert fields == {
        "effort_oscillation": result.oscillation,
        "effort_oscillation_joint": "LF_HAA",
        "effort_change_rms": result.change_rms,
        "base_rate_alternation": 0.0,
        "base_rate_oscillation_radps": 0.0,
    }
    assert SmoothnessFigures(**fields) == result.figures()
    assert SmoothnessFigures().smoothness_summary() == ""
    no_rates = effort_smoothness(column(30.0 * SIGN), [30.0])
    assert no_rates.summary() == "effort osc 200.00 % (dof 0), change 200.0 %/tick"


def test_walk_metrics_carry_the_figures_in_their_json():
    metrics = WalkMetrics(
        False, None, 3.0, 1.5, 0.5, 0.01, 0.01, 0.5, 0.03, 0.02, 6, 0.5, 10.0, 0.5, 2.0, 2.0,
        3.0, 3000,
    )
    assert metrics.to_dict()["effort_oscillation"] is None
    assert "effort osc" not in metrics.summary()
    figures = effort_smoothness(column(30.0 * SIGN), [30.0], names=["knee"]).metrics_fields()
    measured = WalkMetrics(**{**metrics.to_dict(), "step_states": (), **figures})
    assert measured.to_dict()["effort_oscillation_joint"] == "knee"
    assert measured.summary().endswith("effort osc 200.00 % (knee), change 200.0 %/tick")


@pytest.mark.parametrize(
    ("arguments", "match"),
    [
        ((np.zeros(10), [1.0]), "efforts"),
        ((np.full((10, 1), np.nan), [1.0]), "non-finite"),
        ((np.zeros((10, 2)), [1.0]), "limits"),
        ((np.zeros((10, 1)), [np.nan]), "limits"),
        ((np.zeros((10, 1)), [1.0], np.zeros((9, 3))), "base_rates"),
        ((np.zeros((10, 1)), [1.0], np.zeros((10, 4))), "base_rates"),
        ((np.zeros((10, 1)), [1.0], np.full((10, 3), np.inf)), "base_rates"),
        ((np.zeros((10, 1)), [1.0], np.zeros(10)), "base_rates"),
        (("abc", [1.0]), "efforts"),
    ],
)
def test_bad_arrays(arguments, match):
    with pytest.raises(InvalidInputError, match=match):
        effort_smoothness(*arguments)


@pytest.mark.parametrize(
    ("options", "match"),
    [
        ({"time_step": 0.0}, "time_step"),
        ({"time_step": np.nan}, "time_step"),
        ({"skip_s": -1.0}, "skip_s"),
        ({"rate_floor_radps": -0.01}, "rate_floor_radps"),
        ({"names": ["a"]}, "names"),
        ({"names": "ab"}, "names"),
    ],
)
def test_bad_options(options, match):
    with pytest.raises(InvalidInputError, match=match):
        effort_smoothness(np.zeros((10, 2)), [1.0, 1.0], **options)
