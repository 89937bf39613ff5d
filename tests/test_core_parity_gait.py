"""The compiled core's gait kernels (C++, ``src/core/gait.hpp``) against their reference kernels.

The reference kernels (numba; plain Python without numba) are the legged gait's body model
(``gaits.legged.body.body_wrench``), its swing feet (``gaits.legged.footholds.swing_setpoints``
with ``foothold``, ``swing_point`` and ``gaits.planar``'s curves), the body actuator's
producible wrenches with two point feet (``actuators.producible._two_points``) and the request
given way along one missing direction (``_give_way_one``), and the snapshot's centre of mass
(``kinematics.kernels.center_of_mass``). Their arguments are recorded from real walks (the
legged trot, pace and walk of solo12 and go2, the hexapod's tripod), and
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
from virtual_actuators.gaits.legged import body, footholds
from virtual_actuators.gaits.registry import run_walk
from virtual_actuators.kinematics import kernels, snapshot

pytestmark = pytest.mark.skipif(CORE is None, reason="virtual_actuators._core is not built")

#: The module attribute each kernel is called through, its reference and its port's name.
KERNELS = {
    "two_points": (producible, "_TWO_POINTS", producible._two_points),
    "give_way_one": (producible, "_GIVE_WAY_ONE", producible._give_way_one),
    "body_wrench": (body, "_BODY_WRENCH", body.body_wrench),
    "swing_setpoints": (footholds, "_SWING_SETPOINTS", footholds.swing_setpoints),
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
def test_walking_gait_kernels_are_bit_identical(walk, options, recorded):
    run_walk(walk, duration=0.3, progress=False, stop_on_fall=False, **options)
    expected = {"body_wrench", "swing_setpoints", "center_of_mass"}
    if options.get("gait") in ("trot", "pace"):
        expected |= {"two_points", "give_way_one"}
    assert {name for name, calls in recorded.items() if len(calls) > 50} >= expected
    for name, calls in recorded.items():
        for arguments in calls:
            _compare(name, arguments)


def _rotation(rng: np.random.Generator) -> np.ndarray:
    q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    return q * np.sign(np.linalg.det(q))


def test_random_gait_kernels_are_bit_identical():
    """Branches walks rarely reach: coincident feet, rows past the table, a yielding set that
    cannot move the request, late touchdowns (phase past 1), no elapsed time, a saturated reach,
    massless bodies."""
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
        joints = rng.normal(size=(8, 12))
        masses = rng.uniform(0.0, 3.0, size=8) * (rng.random(8) > 0.3)
        masses[0] = 1.0
        _compare("center_of_mass", (joints, masses, rng.normal(size=(8, 3))))
