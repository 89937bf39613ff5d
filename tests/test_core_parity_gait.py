"""The compiled core's gait kernels (C++, ``src/core/gait.hpp``) against their reference kernels.

The reference kernels (numba; plain Python without numba) are a parallel actuator's
producible wrenches with two point feet (``actuators.producible._two_points``), the request
given way along one missing direction (``_give_way_one``), and the snapshot's centre of mass
(``kinematics.kernels.center_of_mass``). The legged gait's body model and swing feet are
``va.scalar`` formulas (``gaits.legged.body``, ``footholds``), lowered into the compiled plan
and tested there (``test_plan_walks.py``). The arguments are recorded from real walks in Python
(the legged trot, pace and walk of solo12 and go2, the hexapod's tripod), and
completed by random ones for the branches walks rarely reach; both kernels then run on copies of
the same arrays and their outputs (and what they write in place) are compared with
``np.array_equal``. The gaits' behaviour is tested in ``test_legged*.py`` and
``test_producible.py``.
"""

from __future__ import annotations

import numpy as np
import pytest

from virtual_actuators.actuators import producible
from virtual_actuators.core import CORE
from virtual_actuators.gaits.registry import run_walk
from virtual_actuators.kinematics import kernels, snapshot

pytestmark = pytest.mark.skipif(CORE is None, reason="virtual_actuators._core is not built")

#: The module attribute each kernel is called through, its reference and its port's name.
KERNELS = {
    "two_points": (producible, "_TWO_POINTS", producible._two_points),
    "give_way_one": (producible, "_GIVE_WAY_ONE", producible._give_way_one),
    "center_of_mass": (snapshot, "center_of_mass_of", kernels.center_of_mass),
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
def test_walking_gait_kernels_are_bit_identical(walk, options, recorded, monkeypatch):
    monkeypatch.setenv("VA_PLAN", "0")  # the Python tick (the compiled one calls no kernel)
    run_walk(walk, duration=0.3, progress=False, stop_on_fall=False, **options)
    expected = {"center_of_mass"}
    assert {name for name, calls in recorded.items() if len(calls) > 50} >= expected
    for name, calls in recorded.items():
        for arguments in calls:
            _compare(name, arguments)


def _rotation(rng: np.random.Generator) -> np.ndarray:
    q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    return q * np.sign(np.linalg.det(q))


def test_random_gait_kernels_are_bit_identical():
    """Branches walks rarely reach: coincident feet, rows past the table, a yielding set that
    cannot move the request, massless bodies."""
    rng = np.random.default_rng(7)
    for k in range(300):
        frames = np.zeros((5, 12))
        for row in range(5):
            frames[row, :9] = _rotation(rng).ravel()
            frames[row, 9:] = rng.normal(size=3)
        if k % 5 == 0:
            frames[3, 9:] = frames[2, 9:] + (1e-7 if k % 10 else 0.0)
        rows = np.array([0, 1, 2, 3 if k % 7 else 9], dtype=np.int64)
        _compare("two_points", (frames, rows))
        n, m = 6, int(rng.integers(1, 4))
        missing = rng.normal(size=(n, 1))
        yielding = rng.normal(size=(n, m)) * (1e-8 if k % 6 == 0 else 1.0)
        _compare("give_way_one", (rng.normal(size=n), yielding, missing, np.zeros(n)))
        joints = rng.normal(size=(8, 12))
        masses = rng.uniform(0.0, 3.0, size=8) * (rng.random(8) > 0.3)
        masses[0] = 1.0
        _compare("center_of_mass", (joints, masses, rng.normal(size=(8, 3))))
