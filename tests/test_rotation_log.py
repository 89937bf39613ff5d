"""The compiled rotation logarithm against Pinocchio's ``log3`` (the oracle), everywhere on SO(3).

The serial sensors read rotations through it, so it must hold near 0 (series), at generic
angles and near pi (where the skew part vanishes and the axis comes from the symmetric part).
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
from hypothesis import given
from hypothesis import strategies as st

from virtual_actuators.kinematics.relative import rotation_log

unit = st.lists(st.floats(-1.0, 1.0), min_size=3, max_size=3).filter(
    lambda v: np.linalg.norm(v) > 1e-3
)


def _rotation(axis: list[float], angle: float) -> np.ndarray:
    axis = np.asarray(axis) / np.linalg.norm(axis)
    return pin.exp3(angle * axis)


@given(axis=unit, angle=st.floats(0.0, np.pi))
def test_matches_log3_at_any_angle(axis, angle):
    rotation = _rotation(axis, angle)
    assert np.allclose(rotation_log(rotation), pin.log3(rotation), rtol=0.0, atol=1e-9)


@given(axis=unit, offset=st.floats(0.0, 2e-3))
def test_matches_log3_near_pi(axis, offset):
    rotation = _rotation(axis, np.pi - offset)
    ours, oracle = rotation_log(rotation), pin.log3(rotation)
    if offset == 0.0:  # at pi, +axis and -axis are the same rotation
        assert np.allclose(pin.exp3(ours), rotation, atol=1e-9)
        assert np.isclose(np.linalg.norm(ours), np.pi, atol=1e-9)
    else:
        assert np.allclose(ours, oracle, rtol=0.0, atol=1e-7)


@pytest.mark.parametrize("angle", [0.0, 1e-12, 1e-8, 1e-5, 9.99e-5, 1.01e-4])
def test_small_angles_keep_relative_precision(angle):
    rotation = _rotation([0.3, -0.5, 0.8], angle)
    ours, oracle = rotation_log(rotation), pin.log3(rotation)
    assert np.allclose(ours, oracle, rtol=1e-7, atol=1e-15)


def test_identity_is_zero():
    assert np.array_equal(rotation_log(np.eye(3)), np.zeros(3))
