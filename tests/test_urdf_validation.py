"""URDF files that Pinocchio would load silently but no robot can be are typed errors.

Each malformed case is a small URDF written to ``tmp_path``; the error must be a
:class:`va.RobotDescriptionError` whose message names the offending link or joint and the bad
value. Odd but valid descriptions (zero masses, round-off in inertias, continuous joints without
limits, fixed joints with any axis, ``lower == upper``) must still load, and so must every URDF
of example-robot-data that :func:`va.load_robot` lists, and the project's own robots.
"""

from __future__ import annotations

import shutil
from pathlib import Path

import pinocchio as pin
import pytest

import virtual_actuators as va
from virtual_actuators.models import catalog

PROJECT_URDFS = sorted(catalog.robots_dir.glob("*/*.urdf"))


def link(name: str, mass: str = "1", inertia: dict[str, str] | None = None) -> str:
    """One ``<link>`` with an ``<inertial>`` (diagonal 0.1 kg m^2 unless overridden)."""
    values = {"ixx": "0.1", "iyy": "0.1", "izz": "0.1", "ixy": "0", "ixz": "0", "iyz": "0"}
    values.update(inertia or {})
    attributes = " ".join(f'{key}="{value}"' for key, value in values.items())
    return (
        f'<link name="{name}"><inertial><mass value="{mass}"/><inertia {attributes}/>'
        "</inertial></link>"
    )


def joint(
    name: str,
    parent: str,
    child: str,
    kind: str = "revolute",
    axis: str | None = "0 0 1",
    limit: tuple[str, str] | None = ("-1", "1"),
    extra: str = "",
) -> str:
    """One ``<joint>``; ``axis`` / ``limit`` None leave the element out."""
    axis_tag = "" if axis is None else f'<axis xyz="{axis}"/>'
    limit_tag = (
        ""
        if limit is None
        else f'<limit lower="{limit[0]}" upper="{limit[1]}" effort="10" velocity="10"/>'
    )
    return (
        f'<joint name="{name}" type="{kind}"><parent link="{parent}"/><child link="{child}"/>'
        f'<origin xyz="0 0 0.3"/>{axis_tag}{limit_tag}{extra}</joint>'
    )


def write_urdf(tmp_path: Path, links: list[str], joints: list[str], stem: str = "arm") -> Path:
    """Write a URDF (an arm: no leg word, so a fixed base) and return its path."""
    text = (
        '<?xml version="1.0"?>\n<robot name="test_arm">\n  '
        + "\n  ".join([*links, *joints])
        + "\n</robot>\n"
    )
    path = tmp_path / f"{stem}.urdf"
    path.write_text(text, encoding="utf-8")
    return path


def two_joint_arm(
    tmp_path: Path,
    *,
    mass: str = "1",
    inertia: dict[str, str] | None = None,
    kind: str = "revolute",
    axis: str | None = "0 0 1",
    limit: tuple[str, str] | None = ("-1", "1"),
    wrist_extra: str = "",
) -> Path:
    """base -shoulder-> upper (the link and joint under test) -wrist-> hand."""
    return write_urdf(
        tmp_path,
        [link("base"), link("upper", mass, inertia), link("hand", "0.5")],
        [
            joint("shoulder", "base", "upper", kind, axis, limit),
            joint("wrist", "upper", "hand", axis="0 1 0", extra=wrist_extra),
        ],
    )


def rejected(path: Path) -> str:
    """Load ``path``, expect a RobotDescriptionError, return its message."""
    with pytest.raises(va.RobotDescriptionError) as error:
        va.load_robot(path)
    return str(error.value)


# -- malformed descriptions ------------------------------------------------------------------


@pytest.mark.parametrize("kind", ["revolute", "continuous", "prismatic"])
def test_zero_joint_axis(tmp_path: Path, kind: str) -> None:
    limit = None if kind == "continuous" else ("-1", "1")
    message = rejected(two_joint_arm(tmp_path, kind=kind, axis="0 0 0", limit=limit))
    assert "joint 'shoulder'" in message
    assert "'0 0 0'" in message and "nonzero" in message


def test_non_finite_joint_axis(tmp_path: Path) -> None:
    message = rejected(two_joint_arm(tmp_path, axis="nan 0 1"))
    assert "joint 'shoulder'" in message and "'nan 0 1'" in message


def test_negative_mass(tmp_path: Path) -> None:
    message = rejected(two_joint_arm(tmp_path, mass="-2.5"))
    assert "link 'upper'" in message and "-2.5" in message and ">= 0 kg" in message


def test_nan_mass_is_caught_before_pinocchio_reads_it_as_zero(tmp_path: Path) -> None:
    path = two_joint_arm(tmp_path, mass="nan")
    # Pinocchio itself loads the NaN mass silently (as 0): the check must happen on the XML
    model = pin.buildModelFromUrdf(str(path))
    assert model.inertias[model.getJointId("shoulder")].mass == 0.0
    message = rejected(path)
    assert "link 'upper'" in message and "'nan'" in message and "finite" in message


def test_infinite_mass(tmp_path: Path) -> None:
    message = rejected(two_joint_arm(tmp_path, mass="inf"))
    assert "link 'upper'" in message and "'inf'" in message


@pytest.mark.parametrize("key", ["ixx", "iyy", "izz"])
def test_negative_moment_of_inertia(tmp_path: Path, key: str) -> None:
    message = rejected(two_joint_arm(tmp_path, inertia={key: "-0.05"}))
    assert "link 'upper'" in message and f"{key}=-0.05" in message and ">= 0" in message


@pytest.mark.parametrize(("key", "value"), [("ixx", "nan"), ("iyz", "inf"), ("ixy", "-inf")])
def test_non_finite_inertia(tmp_path: Path, key: str, value: str) -> None:
    message = rejected(two_joint_arm(tmp_path, inertia={key: value}))
    assert "link 'upper'" in message and f"{key}='{value}'" in message and "finite" in message


def test_inertia_not_positive_semi_definite(tmp_path: Path) -> None:
    """Positive moments, but products of inertia too large: principal moment 0.1 - 0.3 < 0."""
    message = rejected(two_joint_arm(tmp_path, inertia={"ixy": "0.3"}))
    assert "link 'upper'" in message and "ixy=0.3" in message
    assert "positive semi-definite" in message and "-0.2" in message


def test_limit_lower_above_upper(tmp_path: Path) -> None:
    message = rejected(two_joint_arm(tmp_path, limit=("1.5", "-0.5")))
    assert "joint 'shoulder'" in message and "lower=1.5 > upper=-0.5" in message
    assert "lower limit must be <= the upper" in message


def test_limit_lower_above_missing_upper(tmp_path: Path) -> None:
    path = write_urdf(
        tmp_path,
        [link("base"), link("upper")],
        [
            '<joint name="slide" type="prismatic"><parent link="base"/><child link="upper"/>'
            '<axis xyz="1 0 0"/><limit lower="0.2" effort="10" velocity="1"/></joint>'
        ],
    )
    message = rejected(path)
    assert "joint 'slide'" in message and "lower=0.2 > upper=0" in message
    assert "missing upper reads as 0" in message


def test_nan_limit(tmp_path: Path) -> None:
    message = rejected(two_joint_arm(tmp_path, limit=("nan", "1")))
    assert "joint 'shoulder'" in message and "lower='nan'" in message


def test_mimic_joint(tmp_path: Path) -> None:
    path = two_joint_arm(tmp_path, wrist_extra='<mimic joint="shoulder" multiplier="1"/>')
    message = rejected(path)
    assert "joint 'wrist' mimics joint 'shoulder'" in message
    assert "not supported" in message and "remove the <mimic> tag" in message
    assert "EqualTorque('wrist', 'shoulder')" in message


def test_every_problem_is_listed(tmp_path: Path) -> None:
    path = two_joint_arm(tmp_path, mass="-1", axis="0 0 0", inertia={"izz": "-1"})
    message = rejected(path)
    assert message.count("\n  - ") == 3
    assert "link 'upper'" in message and "joint 'shoulder'" in message


def test_robot_by_name_from_a_robots_folder_is_checked(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Robots found by name in ``VIRTUAL_ACTUATORS_ROBOTS`` get the same checks as paths."""
    two_joint_arm(tmp_path, mass="nan").rename(tmp_path / "nan_arm.urdf")
    monkeypatch.setenv(catalog.ROBOTS_PATH_ENV, str(tmp_path))
    with pytest.raises(va.RobotDescriptionError, match="link 'upper'"):
        va.load_robot("nan_arm")


def test_copied_example_robot_data_file_with_mimic_joints_is_rejected(tmp_path: Path) -> None:
    """Only the curated example-robot-data files are exempt from the mimic check."""
    source = catalog.example_robot_data().robots["panda"]
    copy = tmp_path / "panda.urdf"
    shutil.copy(source, copy)
    message = rejected(copy)
    assert "joint 'panda_finger_joint2' mimics joint 'panda_finger_joint1'" in message


# -- odd but valid descriptions --------------------------------------------------------------


def test_zero_mass_and_equal_limits_load(tmp_path: Path) -> None:
    robot = va.load_robot(two_joint_arm(tmp_path, mass="0", limit=("0.2", "0.2")))
    assert robot.model.nq == 2


def test_round_off_in_inertia_loads(tmp_path: Path) -> None:
    """Tiny negative principal moments and diagonals (as shipped by iCub, ANYmal) are round-off."""
    inertia = {"ixx": "1e-6", "iyy": "1e-6", "izz": "1e-6", "ixy": "1.0000001e-6"}
    va.load_robot(two_joint_arm(tmp_path, inertia=inertia))
    va.load_robot(two_joint_arm(tmp_path, inertia={"ixx": "-5.42101e-20"}))


def test_continuous_joint_without_limit_and_fixed_joint_with_zero_axis_load(
    tmp_path: Path,
) -> None:
    path = write_urdf(
        tmp_path,
        [link("base"), link("upper"), link("tool", "0")],
        [
            joint("shoulder", "base", "upper", "continuous", limit=None),
            joint("flange", "upper", "tool", "fixed", axis="0 0 0", limit=None),
        ],
    )
    robot = va.load_robot(path)
    assert robot.model.nv == 1 and robot.model.existFrame("tool")


def test_revolute_joint_without_axis_uses_the_default_axis(tmp_path: Path) -> None:
    va.load_robot(two_joint_arm(tmp_path, axis=None))


# -- real robots -----------------------------------------------------------------------------


def test_every_listed_robot_loads_by_name() -> None:
    """Every name of ``list_robots`` (example-robot-data and the project's robots) loads."""
    names = va.list_robots()
    assert {"solo12", "anymal", "hyq_no_sensors", "talos_reduced", "ur5_robot", "panda"} <= set(
        names
    )
    for name in names:
        va.load_robot(name)


def test_every_example_robot_data_file_loads_by_path() -> None:
    """By path (with the structural checks too), the curated files still load."""
    for path in catalog.example_robot_data().robots.values():
        va.load_robot(path)


@pytest.mark.parametrize("path", PROJECT_URDFS, ids=[path.stem for path in PROJECT_URDFS])
def test_project_robots_load_by_path(path: Path) -> None:
    assert va.load_robot(path).model.nq > 0


def test_curated_files_keep_their_mimic_joints_as_independent_joints() -> None:
    panda = va.load_robot("panda")
    assert panda.model.existJointName("panda_finger_joint2")
