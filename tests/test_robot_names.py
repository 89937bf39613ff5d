"""Robots by common name: every alias loads the robot of its file stem; unknown names get the
closest names and aliases by edit distance; the robots' table describes each one.

The oracle for an alias is the robot loaded by its file stem (and example-robot-data's own file
on disk): same URDF file, same Pinocchio model (joints, placements, inertias, limits).
"""

from __future__ import annotations

import numpy as np
import pytest

import virtual_actuators as va
from virtual_actuators.exceptions import closest_names, edit_distance
from virtual_actuators.models import catalog
from virtual_actuators.models.catalog import ALIASES
from virtual_actuators.models.directory import describe_robots, robot_table

AVAILABLE = catalog.aliases()


def same_model(a: va.Robot, b: va.Robot) -> None:
    ma, mb = a.model, b.model
    assert (ma.nq, ma.nv, ma.njoints, ma.nframes) == (mb.nq, mb.nv, mb.njoints, mb.nframes)
    assert list(ma.names) == list(mb.names)
    assert [f.name for f in ma.frames] == [f.name for f in mb.frames]
    for j in range(ma.njoints):
        np.testing.assert_array_equal(
            ma.jointPlacements[j].homogeneous, mb.jointPlacements[j].homogeneous
        )
        assert ma.inertias[j] == mb.inertias[j]
    np.testing.assert_array_equal(ma.effortLimit, mb.effortLimit)
    np.testing.assert_array_equal(ma.lowerPositionLimit, mb.lowerPositionLimit)
    np.testing.assert_array_equal(a.neutral(), b.neutral())
    assert a.floating_base == b.floating_base
    assert a.passive_joints == b.passive_joints


def test_the_common_names_of_the_issue_are_available():
    for alias in ("talos", "ur5", "hyq", "g1", "ur10", "solo8", "talos_full"):
        assert alias in AVAILABLE, alias
    names = va.list_robots()
    for name in ("panda", "go2", "a1", "go1", "anymal", "solo12", "ur3"):
        assert name in names, name  # file stems: no alias needed


def test_every_alias_names_a_shipped_robot_and_never_shadows_a_stem():
    names = set(va.list_robots())
    assert set(AVAILABLE) <= set(ALIASES)
    for alias, target in AVAILABLE.items():
        assert target in names, (alias, target)
        assert alias not in names, alias
    # an alias whose target ships is dropped only if a real robot has its name
    for alias, target in ALIASES.items():
        if target in names and alias not in names:
            assert alias in AVAILABLE, alias


@pytest.mark.parametrize("alias", sorted(AVAILABLE))
def test_each_alias_loads_the_same_model_as_its_target(alias):
    target = AVAILABLE[alias]
    by_alias, by_stem = va.load_robot(alias), va.load_robot(target)
    assert by_alias.name == alias and by_stem.name == target
    assert by_alias.urdf_path == by_stem.urdf_path
    assert by_alias.urdf_path.is_relative_to(catalog.example_robot_data().share)
    same_model(by_alias, by_stem)


def test_the_documented_variant_choices():
    assert va.load_robot("talos").urdf_path.name == "talos_reduced.urdf"
    assert va.load_robot("talos_full").urdf_path.name == "talos_full_v2.urdf"
    assert va.load_robot("ur5").urdf_path.name == "ur5_robot.urdf"
    assert va.load_robot("g1").urdf_path.name == "g1_29dof_rev_1_0.urdf"
    assert va.load_robot("hyq").urdf_path.name == "hyq_no_sensors.urdf"


def test_list_robots_with_and_without_aliases():
    plain = va.list_robots()
    full = va.list_robots(include_aliases=True)
    assert plain == sorted(plain) and full == sorted(full)
    assert set(full) == set(plain) | set(AVAILABLE)
    assert "talos" not in plain and "talos" in full


def test_a_local_robot_named_like_an_alias_wins(tmp_path, monkeypatch):
    folder = tmp_path / "robots"
    folder.mkdir()
    stem = va.load_robot("solo12").urdf_path
    text = stem.read_text(encoding="utf-8")
    (folder / "talos.urdf").write_text(text, encoding="utf-8")
    monkeypatch.setenv(catalog.ROBOTS_PATH_ENV, str(folder))
    assert "talos" not in catalog.aliases()
    robot = va.load_robot("talos")
    assert robot.urdf_path == (folder / "talos.urdf").resolve()
    assert robot.model.nv == va.load_robot("solo12").model.nv


# -- suggestions -----------------------------------------------------------------------------


def test_edit_distance_against_hand_counted_cases():
    assert edit_distance("talso", "talos") == 1  # one swap of neighbours
    assert edit_distance("kitten", "sitting") == 3
    assert edit_distance("", "abc") == 3 and edit_distance("abc", "") == 3
    assert edit_distance("ur5", "ur5") == 0
    assert edit_distance("ca", "abc") == 3  # optimal string alignment, not unrestricted


def suggested(name: str) -> list[str]:
    with pytest.raises(va.RobotNotFoundError) as error:
        va.load_robot(name)
    message = str(error.value)
    assert f"No robot named {name!r}" in message
    return message.split("Closest robots: ", 1)[1].split(".")[0].split(", ")


@pytest.mark.parametrize(
    ("typo", "expected"),
    [("talso", "'talos' (talos_reduced)"), ("ur_5", "'ur5' (ur5_robot)"), ("panda_arm", "'panda'"),
     ("hyg", "'hyq' (hyq_no_sensors)"), ("Go2", "'go2'"), ("sol12", "'solo12'")],
)  # fmt: skip
def test_a_typo_suggests_the_intended_robot_first(typo, expected):
    assert suggested(typo)[0] == expected


def test_suggestions_are_ranked_by_distance_and_unrelated_names_left_out():
    candidates = va.list_robots(include_aliases=True)
    for typo in ("talso", "ur_5", "panda_arm", "g2"):
        ranked = closest_names(typo, candidates)
        key = typo.lower().replace("_", "")
        distances = [
            edit_distance(key, c.lower().replace("_", "").replace("-", "")) for c in ranked
        ]
        contained = [key in c.replace("_", "") or c.replace("_", "") in key for c in ranked]
        assert ranked, typo
        # sorted by distance, except names containing the typo (or contained in it)
        plain = [d for d, inside in zip(distances, contained, strict=True) if not inside]
        assert plain == sorted(plain), (typo, ranked)
    assert "centauro" not in closest_names("talso", candidates)
    assert "tiago" not in closest_names("talso", candidates)


def test_a_name_close_to_nothing_lists_known_robots():
    with pytest.raises(va.RobotNotFoundError) as error:
        va.load_robot("qqqqqqqqqqqq")
    assert "Known robots:" in str(error.value) and "include_aliases=True" in str(error.value)


# -- the robots' table -----------------------------------------------------------------------


def test_descriptions_of_well_known_robots():
    solo, talos, ur5, hexapod = describe_robots(["solo12", "talos", "ur5_robot", "hexapod"])
    assert (solo.kind, solo.dof, solo.legs, solo.floating_base) == ("quadruped", 12, 4, True)
    assert solo.feet == ("FL_FOOT", "FR_FOOT", "HL_FOOT", "HR_FOOT")
    assert talos.kind == "humanoid" and talos.legs == 2 and "talos" in talos.aliases
    assert talos.feet == ("right_sole_link", "left_sole_link")  # the SRDF's order
    robot = va.load_robot("talos")
    assert talos.dof == robot.model.nv - 6 - len(robot.passive_joints)
    assert (ur5.kind, ur5.dof, ur5.legs, ur5.feet) == ("arm", 6, None, ())
    assert ur5.aliases == ("ur5",)
    # the project's robot: kind read from its feet
    assert (hexapod.kind, hexapod.legs, hexapod.dof) == ("hexapod", 6, 18)


@pytest.mark.parametrize("name", ["spring_flamingo", "g1_29dof_rev_1_0", "centauro", "anymal"])
def test_the_listed_feet_are_the_feet_the_walkers_find(name):
    # robots whose feet a name pattern of the listing's own once got wrong or missed (the
    # flamingo's toes, g1's and centauro's ankles, anymal's order)
    (info,) = describe_robots([name])
    assert info.feet == va.models.feet.find_feet(va.load_robot(name)).feet
    assert len(info.feet) == info.legs


def test_the_table_has_a_line_per_robot_with_its_aliases():
    infos = describe_robots(["solo12", "talos_reduced", "ur5_robot", "panda"])
    table = robot_table(infos).splitlines()
    assert table[0].split() == ["name", "aliases", "description"]
    assert len(table) == 5
    assert table[2].startswith("talos_reduced") and " talos " in table[2]
    assert "humanoid (PAL Robotics TALOS)" in table[2]
    assert "franka" in table[4] and "arm (Franka Emika Panda), 9 DoF" in table[4]


def test_a_name_equal_but_for_case_comes_first():
    candidates = ["FR_FOOT", "FLfoot", "FL_FOOT", "HL_FOOT"]
    assert closest_names("FL_foot", candidates)[:2] == ["FL_FOOT", "FLfoot"]
    assert closest_names("go2", ["GO_2", "Go2"])[0] == "Go2"
