"""A URDF that Pinocchio would load silently but no robot can be is a typed error naming it."""

from __future__ import annotations

import pytest

import virtual_actuators as va

LINK = """<link name="{name}"><inertial><mass value="{mass}"/>
  <inertia ixx="{ixx}" iyy="0.1" izz="0.1" ixy="0" ixz="0" iyz="0"/></inertial></link>"""


def _urdf(tmp_path, mass="1", ixx="0.1", axis="0 0 1", limit=("-1", "1"), mimic=""):
    text = f"""<?xml version="1.0"?>
<robot name="bad">
  {LINK.format(name="base", mass="2", ixx="0.1")}
  {LINK.format(name="arm", mass=mass, ixx=ixx)}
  {LINK.format(name="hand", mass="0.5", ixx="0.1")}
  <joint name="shoulder" type="revolute"><parent link="base"/><child link="arm"/>
    <axis xyz="{axis}"/>
    <limit lower="{limit[0]}" upper="{limit[1]}" effort="10" velocity="10"/></joint>
  <joint name="wrist" type="revolute"><parent link="arm"/><child link="hand"/>
    <origin xyz="0 0 0.3"/><axis xyz="0 1 0"/>{mimic}
    <limit lower="-1" upper="1" effort="10" velocity="10"/></joint>
</robot>
"""
    path = tmp_path / "bad.urdf"
    path.write_text(text)
    return str(path)


@pytest.mark.parametrize(
    ("kwargs", "names"),
    [
        ({"axis": "0 0 0"}, ["'shoulder'", "axis"]),
        ({"mass": "-1"}, ["'arm'", "mass"]),
        ({"mass": "nan"}, ["'arm'", "mass"]),
        ({"ixx": "-0.5"}, ["'arm'", "inertia"]),
        ({"ixx": "inf"}, ["'arm'", "inertia"]),
        ({"limit": ("1", "-1")}, ["'shoulder'", "lower=1"]),
        ({"mimic": '<mimic joint="shoulder" multiplier="1"/>'}, ["'wrist'", "'shoulder'", "mimic"]),
    ],
)
def test_impossible_robot_is_rejected_by_name(tmp_path, kwargs, names):
    with pytest.raises(va.RobotDescriptionError) as error:
        va.load_robot(_urdf(tmp_path, **kwargs))
    for name in names:
        assert name in str(error.value)


def test_valid_edge_cases_load(tmp_path):
    """Zero mass, equal limits: odd but possible."""
    robot = va.load_robot(_urdf(tmp_path, mass="0", limit=("0.2", "0.2")))
    assert robot.model.nq == 2


@pytest.mark.parametrize(
    "name", ["solo12", "anymal", "hyq_no_sensors", "talos_reduced", "ur5_robot", "panda"]
)
def test_curated_robots_still_load(name):
    assert va.load_robot(name).model.nv > 0
