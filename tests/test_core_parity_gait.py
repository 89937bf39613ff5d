"""The compiled core's gait kernels (C++, ``src/core/gait.hpp``) against their oracles.

The body actuator's producible wrenches with two point feet (``two_points``) against the numpy
general path, and the request given way along one missing direction (``give_way_one``) against
its least move in numpy. (The legged gait's body model and swing feet are ``va.scalar``
formulas that the compiled plan traces: ``test_plan_walks.py`` runs them both ways, and
``test_legged.py`` checks them against hand-written definitions.) The gaits' behaviour is tested
in ``test_legged*.py`` and ``test_producible.py``.
"""

from __future__ import annotations

import numpy as np
import pytest

from virtual_actuators.actuators import producible
from virtual_actuators.core import CORE

pytestmark = pytest.mark.skipif(CORE is None, reason="virtual_actuators._core is not built")


def _rotation(rng: np.random.Generator) -> np.ndarray:
    q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    return q * np.sign(np.linalg.det(q))


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
