"""The hexapod's tripod kernel: the compiled core's port against its reference, and both against
the footholds functions they fold together.

``gaits.hexapod.kernel.tripod_setpoints`` (numba; plain Python without numba) and its C++ port
(``src/core/hexapod.hpp``) run on copies of the same arrays, recorded from hexapod walks and
completed by random ones for the branches walks rarely reach (support feet in a line, a body
at rest, a fast body whose stance is cut short, no elapsed time, a phase that would go back);
what they write is compared with ``np.array_equal``. The kernel's arithmetic is then checked
against :mod:`virtual_actuators.gaits.hexapod.footholds` (plain Python, written separately: the
plane, the lag, the landing places and the swing targets, which use ``hypot`` and powers where
the kernel multiplies), to round-off.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from virtual_actuators.core import CORE
from virtual_actuators.gaits.hexapod import footholds, kernel, walker
from virtual_actuators.gaits.hexapod.parameters import HexapodParameters
from virtual_actuators.gaits.planar import lift_profile, smoothstep
from virtual_actuators.gaits.registry import run_walk

core = pytest.mark.skipif(CORE is None, reason="virtual_actuators._core is not built")


def _copies(arguments: tuple) -> tuple:
    return tuple(a.copy() if isinstance(a, np.ndarray) else a for a in arguments)


def _compare(arguments: tuple) -> None:
    """Both kernels on copies of ``arguments``: the same writes, bit for bit."""
    ours, theirs = _copies(arguments), _copies(arguments)
    kernel.tripod_setpoints(*theirs)
    CORE.tripod_setpoints(*ours)
    for a, b in zip(ours, theirs, strict=True):
        assert np.array_equal(a, b), (a, b)


@pytest.fixture
def recorded(monkeypatch):
    """Every call of the walker's tripod kernel while installed (argument copies)."""
    calls = []
    original = walker.TRIPOD_SETPOINTS

    def recording(*arguments):
        calls.append(_copies(arguments))
        return original(*arguments)

    monkeypatch.setattr(walker, "TRIPOD_SETPOINTS", recording)
    return calls


@core
@pytest.mark.parametrize("options", [{}, {"yaw_rate": 0.5}, {"path": "sine"}, {"pendulum": True}])
def test_the_walks_tripod_kernel_is_bit_identical(options, recorded):
    # an on_tick callback keeps the Python tick (the native one calls the core's kernel)
    run_walk("hexapod-walk", duration=0.6, progress=False, stop_on_fall=False,
             on_tick=lambda simulator, gait: None, **options)  # fmt: skip
    assert len(recorded) > 300
    for arguments in recorded:
        _compare(arguments)


def _random_arguments(rng: np.random.Generator, k: int) -> tuple:
    p = HexapodParameters()
    nominal = np.array([(x, y, -0.1) for x in (0.12, 0.0, -0.12) for y in (0.1, -0.1)])
    feet = nominal + rng.normal(scale=0.03, size=(6, 3))
    rows = np.array([0, 3, 4, 1, 2, 5], dtype=np.int64)
    if k % 7 == 0:  # the support feet in a line: the plane is kept
        feet[3] = feet[0] + 0.5 * (feet[4] - feet[0])
    speed = 0.0 if k % 11 == 0 else rng.uniform(-3.0, 3.0)  # at rest, or fast (short stances)
    dt = 0.0 if k % 5 == 0 else rng.uniform(1e-4, 2e-2)
    yaw_rate = 0.0 if k % 11 == 0 else rng.normal()
    across = 0.3 * speed * rng.normal()
    height, elapsed = rng.uniform(0.1, 0.3), rng.uniform(0.0, 0.5)
    motion = np.array((height, speed, across, *rng.normal(size=4), yaw_rate, elapsed, dt))
    shape = np.array([getattr(p, name, 0.05) for name in kernel.SHAPE])
    swing = rng.normal(scale=0.1, size=(3, 9))
    state = np.array((*rng.normal(scale=0.1, size=3), rng.uniform(0.0, 1.2), 0.0))
    # the frame table: the body (turned, anywhere) and its feet in world axes, rows shuffled
    rotation, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    rotation *= np.sign(np.linalg.det(rotation))
    frames = rng.normal(size=(9, 12))
    frame_rows = rng.permutation(9)[:7].astype(np.int64)
    frames[frame_rows[0], :9], frames[frame_rows[0], 9:] = rotation.ravel(), rng.normal(size=3)
    frames[frame_rows[1:], 9:] = frames[frame_rows[0], 9:] + feet @ rotation.T
    return frames, frame_rows, rows, nominal, motion, shape, swing, state


def _feet(frames: np.ndarray, frame_rows: np.ndarray) -> np.ndarray:
    """The feet relative to the body in body axes (numpy)."""
    body = frames[frame_rows[0]]
    return (frames[frame_rows[1:], 9:] - body[9:]) @ body[:9].reshape(3, 3)


@core
def test_random_tripod_kernels_are_bit_identical():
    rng = np.random.default_rng(11)
    for k in range(400):
        _compare(_random_arguments(rng, k))


def test_the_kernel_is_the_footholds_functions():
    """Plane, phase, landing places, set points and their rates as the footholds functions give
    them (the parameters' ``HexapodParameters``), to round-off; the phase never decreases."""
    rng = np.random.default_rng(5)
    p = HexapodParameters()
    for k in range(200):
        arguments = _random_arguments(rng, k)
        frames, frame_rows, rows, nominal, motion, shape, swing, state = arguments
        feet = _feet(frames, frame_rows)
        p.velocity_filter, radius = shape[0], shape[1]
        before_swing, before_state = swing.copy(), state.copy()
        kernel.tripod_setpoints(*arguments)
        height, fx, fy, cx, cy, ax, ay, yaw_rate, elapsed, dt = motion.tolist()
        stance, legs = rows[:3].tolist(), rows[3:].tolist()
        plane = footholds.support_plane(feet[stance].tolist(), tuple(before_state[:3]))
        np.testing.assert_allclose(state[:3], plane, rtol=1e-12, atol=1e-12)
        assert state[4] == pytest.approx(height + plane[2] - radius, abs=1e-12)
        ground = footholds.ground_velocity((fx, fy), yaw_rate, nominal.tolist())
        lag = footholds.behind(
            p,
            (feet[stance] - nominal[stance])[:, :2].tolist(),
            [ground[r][0] for r in stance],
            [ground[r][1] for r in stance],
        )
        progress = max(0.5 + lag, elapsed / p.max_stance_time)
        phase = max(before_state[3], min(progress, 1.0))
        assert state[3] == pytest.approx(phase, abs=1e-12)
        places = footholds.landing(p, [ground[r] for r in legs], nominal[legs].tolist(),
                                   (fx, fy), (cx, cy), (ax, ay))  # fmt: skip
        reach, rest = smoothstep(min(1.0, 1.25 * phase)), 1.0 - smoothstep(phase)
        up = p.lift * lift_profile(phase, p.lift_peak) - p.touchdown_depth * phase
        targets = footholds.swing_targets(before_swing[:, :3].tolist(), places, plane, reach,
                                          rest, up)  # fmt: skip
        np.testing.assert_allclose(swing[:, 3:6], targets, rtol=1e-12, atol=1e-12)
        np.testing.assert_array_equal(swing[:, :3], before_swing[:, :3])
        rates = before_swing[:, 6:]
        if dt > 0.0:
            blend = min(1.0, dt / p.velocity_filter)
            rates = rates + blend * ((np.array(targets) - before_swing[:, 3:6]) / dt - rates)
        np.testing.assert_allclose(swing[:, 6:], rates, rtol=1e-9, atol=1e-9)
        assert math.isfinite(float(swing.sum()))
