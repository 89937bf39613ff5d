"""The flat contact (contacts/flat.py): its numpy rows and a centre-of-pressure oracle agree, on
random sole placements, offsets and wrenches (the compiled core's sole rows against these numpy
rows: ``test_qp_paths.py``)."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

from virtual_actuators.contacts import flat
from virtual_actuators.contacts.constraint import Entries

SOLE = (0.1, 0.05)  # half length, half width [m]
MU = 0.7
ENTRIES = Entries(np.arange(3), np.arange(3, 6), [0, 1, 2], [0, 1, 2], 6)


def _oracle(rotation_a, rotation_o, offset_o, wrench_o):
    """The six margins from the centre of pressure and the yaw moment, in the sole's frame."""
    force, moment = wrench_o[:3], wrench_o[3:] + np.cross(offset_o, wrench_o[:3])  # m_A
    frame_o = rotation_o.T @ rotation_a
    f_local, m_local = frame_o.T @ force, frame_o.T @ moment
    halves = (SOLE[1], SOLE[0], MU * min(SOLE))
    pairs = zip(halves, m_local, strict=True)
    return np.array([h * f_local[2] + s * m for h, m in pairs for s in (-1.0, 1.0)])


@pytest.mark.parametrize("seed", range(5))
def test_numpy_rows_and_the_oracle_agree(seed):
    rng = np.random.default_rng(seed)
    rotation_a, rotation_o = pin.SE3.Random().rotation, pin.SE3.Random().rotation
    offset = rng.normal(size=3) * 0.2
    wrench = rng.normal(size=6) * 10.0
    rows = flat.rows(SOLE, MU, rotation_o.T @ rotation_a, offset, ENTRIES)
    expected = _oracle(rotation_a, rotation_o, offset, wrench)
    np.testing.assert_allclose(rows @ wrench, expected, rtol=0, atol=1e-12)


def test_names_and_parsing():
    assert flat.names("foot", SOLE, None)[-1] == "foot: moment z >= -0 f_n"
    assert flat.parse_soles({"b": [0.2, 0.1]}, ["a", "b"], ["point", "flat"]) == {1: (0.2, 0.1)}
    with pytest.raises(Exception, match="a sole needs contact='flat'"):
        flat.parse_soles({"a": (0.2, 0.1)}, ["a", "b"], ["point", "flat"])
