"""The compiled core's gait kernels (C++, ``src/core/gait.hpp``) against their oracles.

The legged gait's body model (``gaits.legged.body.body_wrench``) and swing feet
(``gaits.legged.footholds.swing_setpoints``) against the same functions in Python: their
arguments recorded from real walks (the legged trot, pace and walk of solo12 and go2, the
hexapod's tripod) and completed by random ones for the branches walks rarely reach, their
outputs (and what they write in place) compared with ``np.array_equal``. The body actuator's
producible wrenches with two point feet (``two_points``) against the numpy general path, and
the request given way along one missing direction (``give_way_one``) against its least move in
numpy. The gaits' behaviour is tested in ``test_legged*.py`` and
``test_producible.py``.
"""

from __future__ import annotations

import numpy as np
import pytest

from virtual_actuators.actuators import producible
from virtual_actuators.core import CORE
from virtual_actuators.gaits.legged import body, footholds
from virtual_actuators.gaits.registry import run_walk

pytestmark = pytest.mark.skipif(CORE is None, reason="virtual_actuators._core is not built")

#: The module attribute each kernel is called through, its reference and its port's name.
KERNELS = {
    "body_wrench": (body, "_BODY_WRENCH", body.body_wrench),
    "swing_setpoints": (footholds, "_SWING_SETPOINTS", footholds.swing_setpoints),
}


def _copies(arguments: tuple) -> tuple:
    return tuple(a.copy() if isinstance(a, np.ndarray) else a for a in arguments)


def _same(ours, theirs) -> bool:
    if theirs is None:
        return ours is None
    if isinstance(theirs, tuple):
        return len(ours) == len(theirs) and all(map(_same, ours, theirs))
    if isinstance(theirs, np.ndarray):
        return np.array_equal(ours, theirs)
    return type(ours)(theirs) == ours or (ours != ours and theirs != theirs)


def _compare(name: str, arguments: tuple) -> None:
    """Both kernels on copies of ``arguments``: the same result and the same writes."""
    _, _, reference = KERNELS[name]
    ours_args, theirs_args = _copies(arguments), _copies(arguments)
    theirs = reference(*theirs_args)
    ours = getattr(CORE, name)(*ours_args)
    assert _same(ours, theirs), name
    for a, b in zip(ours_args, theirs_args, strict=True):
        if isinstance(b, np.ndarray):
            assert np.array_equal(a, b), name


@pytest.fixture
def recorded(monkeypatch):
    """Every call of the gait's kernels while installed: name -> argument copies."""
    calls = {name: [] for name in KERNELS}
    for name, (module, attribute, _) in KERNELS.items():
        original = getattr(module, attribute)

        def recording(*arguments, _name=name, _original=original):
            calls[_name].append(_copies(arguments))
            return _original(*arguments)

        monkeypatch.setattr(module, attribute, recording)
    return calls


@pytest.mark.parametrize(("walk", "options"), [
    ("legged", {"robot": "solo12", "gait": "trot"}),
    ("legged", {"robot": "go2", "gait": "pace"}),
    ("legged", {"robot": "go2", "gait": "walk"}),
    ("legged", {"robot": "hexapod", "gait": "tripod"}),
    ("legged", {"robot": "go2", "gait": "trot"}),
])  # fmt: skip
def test_walking_gait_kernels_are_bit_identical(walk, options, recorded):
    run_walk(walk, duration=0.3, progress=False, stop_on_fall=False, **options)
    expected = {"body_wrench", "swing_setpoints"}
    assert {name for name, calls in recorded.items() if len(calls) > 50} >= expected
    for name, calls in recorded.items():
        for arguments in calls:
            _compare(name, arguments)


def _rotation(rng: np.random.Generator) -> np.ndarray:
    q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    return q * np.sign(np.linalg.det(q))


def test_random_gait_kernels_are_bit_identical():
    """Branches walks rarely reach: late touchdowns (phase past 1), no elapsed time, a
    saturated reach."""
    rng = np.random.default_rng(7)
    for k in range(300):
        gains = rng.uniform(1.0, 100.0, size=11)
        rotation = _rotation(rng) if k % 4 else np.eye(3)
        _compare("body_wrench", (rotation, rng.normal(size=6), rng.normal(size=6), gains,
                                 rng.normal(size=8), np.zeros(6)))  # fmt: skip
        f = int(rng.integers(1, 7))
        feet = rng.choice(f, size=int(rng.integers(0, f + 1)), replace=False).astype(np.int64)
        motion = rng.normal(size=8)
        motion[6] = rng.uniform(0.0, 0.5)  # time in the swing, past it sometimes
        shape = np.array([0.25, 0.3, 0.1, rng.uniform(0.01, 0.3), 0.08, 0.3, 0.02, 0.01])
        dt = 0.0 if k % 3 == 0 else float(rng.uniform(1e-4, 2e-2))
        _compare("swing_setpoints", (feet, rng.normal(size=(f, 9)), rng.normal(size=(f, 2)),
                                     rng.normal(size=12), motion, dt, shape, np.zeros((f, 6))))


def test_two_point_feet_in_closed_form_equal_the_general_directions():
    """The core's ``two_points`` spans what the numpy path finds (its directions up to a basis),
    and hands back (empty) coincident feet and rows past the table."""
    rng = np.random.default_rng(7)
    for k in range(300):
        frames = np.zeros((5, 12))
        for row in range(5):
            frames[row, :9] = _rotation(rng).ravel()
            frames[row, 9:] = rng.normal(size=3)
        if k % 5 == 0:
            frames[3, 9:] = frames[2, 9:] + (1e-7 if k % 10 else 0.0)
        rows = np.array([0, 1, 2, 3 if k % 7 else 9], dtype=np.int64)
        found = CORE.two_points(frames, rows)
        if rows[3] >= frames.shape[0]:
            assert found.size == 0
            continue
        rotation_o = frames[1, :9].reshape(3, 3)
        offsets = (frames[0, 9:] - frames[2:4, 9:]) @ rotation_o  # from each foot to {B}, in {O}
        oracle = producible._split(producible._point_columns(offsets))
        if oracle.missing.shape[1] != 1:
            assert found.size == 0  # coincident feet: the general path decides
            continue
        if found.size == 0:  # within the closed form's rank tolerance of coincident
            assert np.linalg.norm(offsets[0] - offsets[1]) <= 1e-4 * np.linalg.norm(offsets[0])
            continue
        basis, missing = found[:30].reshape(6, 5), found[30:].reshape(6, 1)
        np.testing.assert_allclose(basis.T @ basis, np.eye(5), atol=1e-12)
        span = oracle.producible @ oracle.producible.T
        np.testing.assert_allclose(basis @ basis.T, span, atol=1e-9)
        np.testing.assert_allclose(abs(missing.T @ oracle.missing), [[1.0]], atol=1e-9)


def test_give_way_along_one_missing_direction_equals_its_least_move():
    """The core's ``give_way_one`` against the least move written in numpy, and its refusal."""
    rng = np.random.default_rng(8)
    for k in range(300):
        n, m = 6, int(rng.integers(1, 4))
        missing = rng.normal(size=(n, 1))
        missing /= np.linalg.norm(missing)
        yielding = rng.normal(size=(n, m)) * (1e-8 if k % 6 == 0 else 1.0)
        wrench, out = rng.normal(size=n), np.zeros(n)
        across, gap = (missing.T @ yielding)[0], float(missing[:, 0] @ wrench)
        if not CORE.give_way_one(wrench, yielding, missing, out):
            assert across @ across <= 1e-12
            continue
        moved = wrench - yielding @ (across * (gap / (across @ across)))
        oracle = moved - missing[:, 0] * (missing[:, 0] @ moved)
        np.testing.assert_allclose(out, oracle, rtol=0.0, atol=1e-12 * max(1.0, abs(gap)))
        assert abs(missing[:, 0] @ out) <= 1e-12 * max(1.0, abs(gap))
