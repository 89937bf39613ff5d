"""Progress bars: set from the clock, never past the total, one final line, no warnings."""

from __future__ import annotations

import io
import warnings

import pytest

from virtual_actuators.experiments.progress import Progress


def test_no_drift_no_clamping_warning_and_one_final_line(monkeypatch):
    stream = io.StringIO()
    monkeypatch.setattr("sys.stderr", stream)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # tqdm's clamping warning would raise here
        bar = Progress(2.0)
        t = 0.0
        for _ in range(2100):  # 1 ms ticks, a little past the end, summed in floats
            t += 1e-3
            bar.set(t)
        assert bar._bar.n == 2.0
        bar.close(t)
        bar.close()  # idempotent
    text = stream.getvalue()
    assert "2.0/2.0 s" in text
    assert "-" not in text.split("[")[-1]  # no negative time left
    assert text.rstrip().endswith("]")


def test_items_and_early_stop(monkeypatch):
    stream = io.StringIO()
    monkeypatch.setattr("sys.stderr", stream)
    with Progress(8, unit="walks", description="sweep") as bar:
        for k in range(1, 4):
            bar.set(k)
    assert "3/8 walks" in stream.getvalue()
    assert repr(bar) == "Progress(3/8)"


@pytest.mark.parametrize("value", [-5.0, 1e9])
def test_clipped(value):
    bar = Progress(1.0)
    bar.set(value)
    assert 0.0 <= bar._bar.n <= 1.0
    bar.close()
