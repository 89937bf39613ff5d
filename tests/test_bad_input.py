"""Bad input of issue 24: typed errors naming the argument, bounded work, no silent garbage.

Each case passes one bad value to a public entry point and checks the error's type (a
:class:`va.VirtualActuatorError`, never a bare ``ValueError``, ``TypeError``, ``OSError`` or
``RuntimeError``) and that its message names the argument and what would be valid.
"""

from __future__ import annotations

import os
import warnings
from pathlib import Path

import numpy as np
import pytest
from oracles import robot

import virtual_actuators as va
from virtual_actuators.exceptions import closest_names, edit_distance
from virtual_actuators.models.millipede import MAX_LEGS, millipede_urdf

FEET = ["FL_FOOT", "FR_FOOT", "HL_FOOT", "HR_FOOT"]
NO_USER = "~va_no_such_user_x9"  # a home folder that no account has


# -- ParallelVirtualActuator(torque_limits=..., normals=..., soles=...) -------------------------
def _body(**kwargs: object) -> va.ParallelVirtualActuator:
    return va.ParallelVirtualActuator(robot("solo12"), "base_link", FEET, "world", **kwargs)


@pytest.mark.parametrize(
    "limits",
    [
        "yes",
        object(),
        [object()] * 18,
        [1.0 + 1.0j] * 18,
        np.full(18, 2.0 + 0.5j),
        np.True_,
        {"FL_HFE": 1.0},
        [[1.0, 2.0], [3.0]],
    ],
    ids=["str", "object", "objects", "complex-list", "complex-array", "np-bool", "dict", "ragged"],
)
def test_bad_torque_limits_are_a_typed_error(limits: object) -> None:
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no ComplexWarning on the way: the value is refused
        with pytest.raises(va.InvalidInputError, match=r"torque_limits must be True, False or 18"):
            _body(torque_limits=limits)


def test_bad_normals_and_soles_are_a_typed_error() -> None:
    with pytest.raises(va.InvalidInputError, match=r"normals\['FL_FOOT'\].*3-vector"):
        _body(normals={"FL_FOOT": object()})
    with pytest.raises(va.InvalidInputError, match=r"normals\['FL_FOOT'\].*complex"):
        _body(normals={"FL_FOOT": [0.0, 0.0, 1.0j]})
    with pytest.raises(va.InvalidInputError, match=r"soles\['FL_FOOT'\].*half_length"):
        _body(contact="flat", soles={"FL_FOOT": "ab"})


def test_valid_torque_limits_still_bound_the_torques() -> None:
    """True, a list and an array of limits are accepted, and the QP's torques respect them."""
    solo = robot("solo12")
    q, wrench = solo.neutral(), np.array([0.0, 0.0, 20.0, 0.0, 0.0, 0.0])
    limits = np.full(solo.model.nv, 0.5)
    for given in (list(limits), limits, limits.astype(np.float32)):
        tau = _body(torque_limits=given).solve(q, wrench, method="qp").tau
        assert np.all(np.abs(tau[6:]) <= 0.5 * (1 + 1e-6))
    assert _body(torque_limits=True).solve(q, wrench, method="qp").tau.shape == (solo.model.nv,)


# -- load_robot ---------------------------------------------------------------------------------
@pytest.mark.parametrize(
    "name_or_path",
    [
        f"{NO_USER}/x.urdf",
        NO_USER,
        Path(f"{NO_USER}/x.urdf"),
        "x" * 5000,
        "x" * 5000 + ".urdf",
        "/" + "x" * 300 + "/a.urdf",
        Path("/" + "y" * 300 + "/a.urdf"),
    ],
    ids=[
        "tilde-user-path",
        "tilde-user",
        "tilde-user-pathlike",
        "long-name",
        "long-file",
        "long-folder",
        "long-pathlike",
    ],
)
def test_unusable_names_and_paths_are_robot_not_found(name_or_path: object) -> None:
    with pytest.raises(va.RobotNotFoundError) as error:
        va.load_robot(name_or_path)
    message = str(error.value)
    assert "name_or_path" in message or "No robot named" in message
    assert len(message) < 2000  # a 5000-character name is shortened in the message


def test_a_path_of_bytes_is_refused() -> None:
    class BytesPath(os.PathLike):
        def __fspath__(self) -> bytes:
            return b"robot.urdf"

    with pytest.raises(va.InvalidInputError, match="name_or_path"):
        va.load_robot(BytesPath())


def test_an_unexpandable_robots_folder_is_skipped(monkeypatch: pytest.MonkeyPatch) -> None:
    """A ``~user`` folder in VIRTUAL_ACTUATORS_ROBOTS that names nobody: robots still load."""
    monkeypatch.setenv("VIRTUAL_ACTUATORS_ROBOTS", os.pathsep.join([NO_USER, "z" * 5000]))
    assert va.load_robot("solo12").model.nv == robot("solo12").model.nv
    with pytest.raises(va.RobotNotFoundError, match="sol12"):
        va.load_robot("sol12")


def test_closest_names_skips_only_names_that_cannot_be_close() -> None:
    """The length pre-check changes nothing: same answer as the documented rule on every pair."""
    candidates = ["solo12", "solo8", "talos", "talos_reduced", "ur5_robot", "panda", "a1", "go2"]

    def documented(name: str) -> list[str]:  # the rule of closest_names' docstring, in full
        ranked = []
        wanted = name.lower().replace("-", "").replace("_", "")
        for candidate in candidates:
            key = candidate.lower().replace("-", "").replace("_", "")
            distance = edit_distance(wanted, key)
            contained = bool(wanted) and bool(key) and (wanted in key or key in wanted)
            if contained or distance <= max(2, max(len(wanted), len(key)) // 2):
                first = candidate.lower() != name.lower()  # equal but for case
                ranked.append(
                    (first, distance, not contained, abs(len(key) - len(wanted)), candidate)
                )
        return [candidate for *_, candidate in sorted(ranked)[:5]]

    for name in ["sol12", "talo", "ur5", "pand", "a", "go", "x" * 40, "solo12_extra_long", "t"]:
        assert closest_names(name, candidates) == documented(name), name
    assert closest_names("x" * 5000, candidates) == []


# -- millipede(legs=...) ------------------------------------------------------------------------
def test_millipede_refuses_more_than_max_legs_before_building() -> None:
    assert MAX_LEGS >= 1000  # the benchmark declares 1000 legs
    for legs in (10**9, MAX_LEGS + 1, np.int64(10**12)):
        with pytest.raises(va.InvalidInputError, match=rf"legs.*at most {MAX_LEGS}"):
            va.millipede(legs=legs)
        with pytest.raises(va.InvalidInputError, match="legs"):
            millipede_urdf(legs)
    assert va.millipede(legs=3).model.nv == 6 + 2 * 3


# -- Spring(law=...) ----------------------------------------------------------------------------
@pytest.mark.parametrize(
    "law",
    [
        lambda d: d * (1.0 + 1.0j),
        lambda d: [1.0j, 0.0],
        lambda d: 2.0j,
        lambda d: np.complex64(1.0),
        lambda d: np.array([1.0, 2.0], dtype=object) * 1j,
    ],
    ids=["complex-array", "complex-list", "complex-scalar", "complex-zero-imaginary", "objects"],
)
def test_a_law_that_returns_complex_values_is_refused(law) -> None:
    spring = va.Spring(("x", "z"), setpoint=[0.1, 0.2], law=law)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # refused, not a ComplexWarning
        with pytest.raises(va.InvalidInputError, match=r"law returned .*real and finite"):
            spring.compute_wrench(np.zeros(2), np.zeros(2), 0.0)
