"""Tests of robot loading: example-robot-data by name, URDF paths, robots folders, millipede."""

from __future__ import annotations

import functools
import importlib.metadata
import math
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest

from virtual_actuators.exceptions import (
    InvalidInputError,
    RobotDescriptionError,
    RobotNotFoundError,
    VirtualActuatorError,
)
from virtual_actuators.models import (
    Robot,
    catalog,
    list_robots,
    load_robot,
    loader,
    millipede,
    robots_dir,
)

ERD = Path(
    str(
        importlib.metadata.distribution("example-robot-data").locate_file(
            "cmeel.prefix/share/example-robot-data/robots"
        )
    )
)

FLOATING = (
    "solo12 solo anymal anymal_c hyq_no_sensors talos_reduced go2 g1_29dof_rev_1_0 a1 go1 bolt "
    "icub romeo simple_humanoid"
).split()
FIXED = (
    "ur5_robot ur3 ur10_robot panda kinova xarm7 z1 so100 allegro_left_hand finger_edu "
    "double_pendulum TwoDofs"
).split()

# name: (nq, nv, floating base by default)
SIZES = {
    "solo12": (19, 18, True),
    "anymal": (19, 18, True),
    "hyq_no_sensors": (19, 18, True),
    "talos_reduced": (39, 38, True),
    "ur5_robot": (6, 6, False),
    "panda": (9, 9, False),
    "go2": (19, 18, True),
    "g1_29dof_rev_1_0": (36, 35, True),
}

# name: (SRDF relative to the example-robot-data robots folder, group state), None if no pose
SRDF_POSES = {
    "solo12": ("solo_description/srdf/solo.srdf", "standing"),
    "anymal": ("anymal_b_simple_description/srdf/anymal.srdf", "standing"),
    "hyq_no_sensors": ("hyq_description/srdf/hyq.srdf", "standing"),
    "talos_reduced": ("talos_data/srdf/talos.srdf", "half_sitting"),
    "panda": ("panda_description/srdf/panda.srdf", "default"),
    "go2": ("go2_description/srdf/go2.srdf", "standing"),
    "ur5_robot": None,  # ur5.srdf has no group state
    "g1_29dof_rev_1_0": None,  # no SRDF shipped
}


@functools.cache
def cached(name: str) -> Robot:
    """Load each robot once per test session (tests must not modify it)."""
    return load_robot(name)


def srdf_configuration(model: pin.Model, srdf: Path, state: str) -> np.ndarray:
    """Read a group state with xml.etree, independently of Pinocchio's SRDF parser."""
    group_state = next(
        element
        for element in ET.parse(srdf).getroot().iter("group_state")
        if element.get("name") == state
    )
    q = pin.neutral(model)
    for joint in group_state.iter("joint"):
        if not model.existJointName(joint.get("name")):
            continue
        values = [float(value) for value in joint.get("value").split()]
        joint_model = model.joints[model.getJointId(joint.get("name"))]
        if joint_model.nq == 2 and len(values) == 1:  # unbounded revolute: cos, sin
            values = [math.cos(values[0]), math.sin(values[0])]
        q[joint_model.idx_q : joint_model.idx_q + joint_model.nq] = values
    return q


URDF_TEMPLATE = """<?xml version="1.0"?>
<robot name="{robot}">
  <link name="base">
    <inertial><mass value="2"/>
      <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>
  </link>
  <link name="{child}">
    <inertial><mass value="0.5"/>
      <inertia ixx="0.001" ixy="0" ixz="0" iyy="0.001" iyz="0" izz="0.001"/></inertial>
  </link>
  <joint name="{joint}" type="revolute">
    <parent link="{parent}"/>
    <child link="{child}"/>
    <origin xyz="0 0 -0.1"/>
    <axis xyz="0 1 0"/>
    <limit lower="-1" upper="1" effort="10" velocity="5"/>
  </joint>
</robot>
"""


def write_urdf(
    folder: Path,
    stem: str,
    *,
    robot: str = "test_robot",
    parent: str = "base",
    child: str = "arm",
    joint: str = "elbow",
) -> Path:
    """Write a two-link URDF and return its path."""
    path = folder / f"{stem}.urdf"
    path.write_text(URDF_TEMPLATE.format(robot=robot, parent=parent, child=child, joint=joint))
    return path


# ---------------------------------------------------------------------------------------------
# example-robot-data by name


@pytest.mark.parametrize("name", sorted(SIZES))
def test_load_by_name_sizes_and_base(name: str) -> None:
    nq, nv, floating = SIZES[name]
    robot = cached(name)
    assert robot.name == name
    assert (robot.model.nq, robot.model.nv) == (nq, nv)
    assert robot.floating_base is floating
    assert (robot.model.names[1] == "root_joint") is floating
    assert isinstance(robot.data, pin.Data)
    assert robot.urdf_path is not None and robot.urdf_path.is_file()
    assert robot.urdf_path.is_relative_to(ERD.resolve())
    assert robot.urdf_string == robot.urdf_path.read_text(encoding="utf-8")
    share = Path(robot.package_dirs[0])
    assert (share / "example-robot-data" / "robots").is_dir()


@pytest.mark.parametrize("name", sorted(SRDF_POSES))
def test_neutral_is_the_srdf_pose(name: str) -> None:
    robot = cached(name)
    q = robot.neutral()
    assert q.shape == (robot.model.nq,)
    if SRDF_POSES[name] is None:
        assert robot.default_pose is None
        np.testing.assert_array_equal(q, pin.neutral(robot.model))
        return
    srdf, state = SRDF_POSES[name]
    assert robot.default_pose == state
    expected = srdf_configuration(robot.model, ERD / srdf, state)
    assert not np.allclose(expected, pin.neutral(robot.model))  # the comparison means something
    np.testing.assert_allclose(q, expected, atol=1e-12)
    q[:] = 0.0  # neutral() returns a copy
    np.testing.assert_allclose(robot.neutral(), expected, atol=1e-12)


def test_standing_poses_of_legged_robots() -> None:
    solo = cached("solo12")
    assert sorted(solo.reference_configurations) == ["standing", "straight_standing"]
    assert solo.neutral()[2] == pytest.approx(0.235)  # base height from solo.srdf
    hyq = cached("hyq_no_sensors")  # hyq_no_sensors.urdf uses hyq.srdf (longest stem prefix)
    assert set(hyq.reference_configurations) == {"standing", "straight_standing"}


@pytest.mark.parametrize(
    ("name", "frames"),
    [
        ("solo12", ["FL_FOOT", "FR_FOOT", "HL_FOOT", "HR_FOOT", "base_link"]),
        ("anymal", ["LF_FOOT", "RF_FOOT", "LH_FOOT", "RH_FOOT", "base"]),
        ("hyq_no_sensors", ["lf_foot", "rf_foot", "lh_foot", "rh_foot"]),
        ("talos_reduced", ["left_sole_link", "right_sole_link", "base_link"]),
        ("go2", ["FL_foot", "FR_foot", "RL_foot", "RR_foot"]),
        ("ur5_robot", ["tool0", "ee_link"]),
        ("panda", ["panda_hand", "panda_link0"]),
    ],
)
def test_frame_names(name: str, frames: list[str]) -> None:
    robot = cached(name)
    for frame in frames:
        assert robot.model.existFrame(frame), frame
        assert frame in robot.frame_names


@pytest.mark.parametrize("name", FLOATING)
def test_heuristic_floats_legged_and_humanoid_robots(name: str) -> None:
    robot = cached(name)
    assert robot.floating_base
    assert robot.model.joints[1].shortname() == "JointModelFreeFlyer"


@pytest.mark.parametrize("name", FIXED)
def test_heuristic_fixes_arms_and_hands(name: str) -> None:
    robot = cached(name)
    assert not robot.floating_base
    assert "root_joint" not in robot.joint_names


def test_floating_base_override() -> None:
    solo = load_robot("solo12", floating_base=False)
    assert not solo.floating_base
    assert (solo.model.nq, solo.model.nv) == (12, 12)
    # the SRDF pose still applies, without the base
    np.testing.assert_allclose(solo.neutral(), cached("solo12").neutral()[7:])
    panda = load_robot("panda", floating_base=True)
    assert panda.floating_base
    assert (panda.model.nq, panda.model.nv) == (16, 15)
    assert panda.joint_names[0] == "root_joint"
    np.testing.assert_allclose(panda.neutral()[7:], cached("panda").neutral())


def test_anymal_b_and_anymal_c_are_both_available() -> None:
    b, c = cached("anymal"), cached("anymal_c")
    assert "anymal_b_simple_description" in b.urdf_path.parts
    assert "anymal_c_simple_description" in c.urdf_path.parts
    assert c.name == "anymal_c"
    assert c.floating_base and c.default_pose == "standing"
    assert len(b.model.frames) != len(c.model.frames)


def test_ur3_xacro_stub_resolves_to_the_expanded_urdf() -> None:
    # ur3.urdf in example-robot-data 6.0.0 is an empty <robot> that Pinocchio cannot load
    assert "<link" not in (ERD / "ur_description/urdf/ur3.urdf").read_text()
    ur3 = cached("ur3")
    assert ur3.urdf_path.name == "ur3_robot.urdf"
    assert ur3.model.nq == 6 and not ur3.floating_base


def test_list_robots() -> None:
    names = list_robots()
    assert names == sorted(set(names))
    for name in [*FLOATING, *FIXED, *SIZES, "millipede", "anymal_c", "anymal-kinova"]:
        assert name in names, name
    stems = {path.stem for path in ERD.rglob("*.urdf")}
    assert stems <= set(names)
    assert all(isinstance(name, str) and "/" not in name for name in names)


def test_every_listed_robot_loads() -> None:
    for name in list_robots():
        robot = cached(name)
        assert robot.model.nq >= robot.model.nv > 0, name
        assert robot.neutral().shape == (robot.model.nq,)


def test_millipede_by_name() -> None:
    robot = load_robot("millipede")
    assert robot.name == "millipede"
    assert robot.model.nq == 7 + 2 * 100
    assert robot.floating_base


# ---------------------------------------------------------------------------------------------
# URDF files by path


def test_load_by_path(tmp_path: Path) -> None:
    path = write_urdf(tmp_path, "my_arm")
    for given in (path, str(path), tmp_path):  # Path, string, folder holding one URDF
        robot = load_robot(given)
        assert robot.name == "my_arm"
        assert robot.urdf_path == path.resolve()
        assert not robot.floating_base  # no leg word: fixed
        assert robot.model.nq == 1 and robot.joint_names == ["elbow"]
        assert robot.default_pose is None
        assert str(tmp_path.resolve()) in robot.package_dirs


def test_leg_words_make_a_path_robot_float(tmp_path: Path) -> None:
    robot = load_robot(write_urdf(tmp_path, "hopper", child="lower_leg", joint="knee"))
    assert robot.floating_base and robot.model.nq == 8
    assert not load_robot(tmp_path / "hopper.urdf", floating_base=False).floating_base
    # a word inside a longer word does not count
    robot = load_robot(write_urdf(tmp_path, "allegro", child="base_footprint2", joint="j"))
    assert not robot.floating_base


def test_srdf_beside_the_urdf_by_longest_prefix(tmp_path: Path) -> None:
    path = write_urdf(tmp_path, "my_arm_v2")
    (tmp_path / "my.srdf").write_text(
        '<robot name="x"><group_state name="home" group="g">'
        '<joint name="elbow" value="0.1"/></group_state></robot>'
    )
    (tmp_path / "my_arm.srdf").write_text(
        '<robot name="x"><group_state name="zz" group="g"><joint name="elbow" value="0.5"/>'
        '</group_state><group_state name="home" group="g"><joint name="elbow" value="0.3"/>'
        "</group_state></robot>"
    )
    robot = load_robot(path)
    assert robot.default_pose == "home"
    assert set(robot.reference_configurations) == {"home", "zz"}
    np.testing.assert_allclose(robot.neutral(), [0.3])


def test_broken_srdf_is_ignored(tmp_path: Path) -> None:
    path = write_urdf(tmp_path, "my_arm")
    (tmp_path / "my_arm.srdf").write_text("<robot><group_state name='home'")
    robot = load_robot(path)
    assert robot.reference_configurations == {} and robot.default_pose is None
    np.testing.assert_array_equal(robot.neutral(), pin.neutral(robot.model))


def test_missing_file(tmp_path: Path) -> None:
    missing = tmp_path / "nowhere" / "robot.urdf"
    for given in (missing, str(missing)):
        with pytest.raises(RobotNotFoundError, match="nowhere") as info:
            load_robot(given)
        assert str(missing) in str(info.value)


def test_malformed_xml(tmp_path: Path) -> None:
    path = tmp_path / "broken.urdf"
    path.write_text(URDF_TEMPLATE.replace("</robot>", "</robt>"))
    with pytest.raises(RobotDescriptionError) as info:
        load_robot(path)
    message = str(info.value)
    assert "broken.urdf" in message
    line = URDF_TEMPLATE.splitlines().index("</robot>") + 1
    assert "not well-formed XML" in message and f"line {line}," in message


def test_joint_naming_a_missing_link(tmp_path: Path) -> None:
    path = write_urdf(tmp_path, "typo", parent="bsae")
    with pytest.raises(RobotDescriptionError) as info:
        load_robot(path)
    message = str(info.value)
    assert "typo.urdf" in message
    assert "'elbow'" in message and "'bsae'" in message and "Closest links: 'base'" in message


@pytest.mark.parametrize(
    ("mutate", "expected"),
    [
        (lambda text: text.replace('<robot name="test_robot">', "<robot>"), "no 'name'"),
        (lambda text: text.replace('type="revolute"', 'type="hinge"'), "type 'hinge'"),
        (lambda text: text.replace('<axis xyz="0 1 0"/>', '<axis xyz="0 one 0"/>'), "'one'"),
        (
            lambda text: text.replace('<limit lower="-1" upper="1" effort="10" velocity="5"/>', ""),
            "no <limit>",
        ),
        (
            lambda text: text.replace("</robot>", '<link name="orphan"/></robot>'),
            "single tree",
        ),
        (
            lambda text: text.replace(
                "</robot>",
                '<joint name="back" type="fixed"><parent link="arm"/>'
                '<child link="base"/></joint></robot>',
            ),
            "loop",
        ),
        (lambda text: "<sdf><model/></sdf>", "root element is <sdf>"),
    ],
)
def test_invalid_urdf_content(tmp_path: Path, mutate, expected: str) -> None:
    path = tmp_path / "bad.urdf"
    path.write_text(
        mutate(URDF_TEMPLATE.format(robot="test_robot", parent="base", child="arm", joint="elbow"))
    )
    with pytest.raises(RobotDescriptionError, match="bad.urdf") as info:
        load_robot(path)
    assert expected in str(info.value)


def test_xacro_file_is_refused_with_a_hint(tmp_path: Path) -> None:
    path = tmp_path / "robot.urdf.xacro"
    path.write_text('<robot name="r" xmlns:xacro="http://wiki.ros.org/xacro"/>')
    with pytest.raises(RobotDescriptionError, match="xacro"):
        load_robot(path)


def test_pinocchio_failure_is_wrapped(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    path = write_urdf(tmp_path, "fine")

    def fail(*args: object) -> None:
        raise ValueError("simulated parser failure")

    monkeypatch.setattr(loader.pin, "buildModelFromUrdf", fail)
    with pytest.raises(RobotDescriptionError, match="fine.urdf.*simulated parser failure"):
        load_robot(path)


def test_unknown_name_lists_close_matches() -> None:
    with pytest.raises(RobotNotFoundError) as info:
        load_robot("sol12")
    message = str(info.value)
    assert "'sol12'" in message and "'solo12'" in message and "'solo'" in message
    with pytest.raises(RobotNotFoundError, match="'anymal'.*'anymal_c'"):
        load_robot("anymall")
    assert issubclass(RobotNotFoundError, VirtualActuatorError)


@pytest.mark.parametrize("bad", [3, None, "", "  ", ["solo12"]])
def test_invalid_name_argument(bad: object) -> None:
    with pytest.raises(InvalidInputError):
        load_robot(bad)  # type: ignore[arg-type]


@pytest.mark.parametrize("bad", ["yes", 1, 0.0])
def test_invalid_floating_base_argument(bad: object) -> None:
    with pytest.raises(InvalidInputError, match="floating_base"):
        load_robot("panda", floating_base=bad)  # type: ignore[arg-type]


# ---------------------------------------------------------------------------------------------
# robots folders


def test_robots_dir_is_the_repository_folder() -> None:
    assert isinstance(robots_dir, Path)
    assert robots_dir == Path(__file__).resolve().parents[1] / "robots"


def test_extra_robot_folders_from_the_environment(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    first, second = tmp_path / "a", tmp_path / "b"
    (first / "walker").mkdir(parents=True)
    second.mkdir()
    write_urdf(first / "walker", "walker", child="shin", joint="knee")
    (first / "walker" / "walker.srdf").write_text(
        '<robot name="walker"><group_state name="standing" group="all">'
        '<joint name="root_joint" value="0 0 0.3 0 0 0 1"/><joint name="knee" value="-0.4"/>'
        "</group_state></robot>"
    )
    write_urdf(second, "gripper")
    write_urdf(second, "walker", child="other")  # shadowed by the first folder
    (second / "notes.txt").write_text("not a robot")
    monkeypatch.setenv("VIRTUAL_ACTUATORS_ROBOTS", f"{first}{loader.os.pathsep}{second}")

    names = list_robots()
    assert {"walker", "gripper"} <= set(names) and "notes" not in names
    walker = load_robot("walker")
    assert walker.name == "walker" and walker.floating_base
    assert walker.model.existFrame("shin")
    np.testing.assert_allclose(walker.neutral(), [0, 0, 0.3, 0, 0, 0, 1, -0.4])
    gripper = load_robot("gripper")
    assert not gripper.floating_base and gripper.model.nq == 1

    monkeypatch.delenv("VIRTUAL_ACTUATORS_ROBOTS")
    assert "gripper" not in list_robots()
    with pytest.raises(RobotNotFoundError):
        load_robot("gripper")


def test_module_hook_in_a_robot_folder(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    (tmp_path / "centipede").mkdir()
    (tmp_path / "centipede" / "__init__.py").write_text(
        "from virtual_actuators.models import millipede\n\n"
        "def build_robot(floating_base=None):\n"
        "    return millipede(legs=3, floating_base=floating_base is not False)\n"
    )
    (tmp_path / "nohook").mkdir()
    (tmp_path / "nohook" / "__init__.py").write_text("X = 1\n")
    monkeypatch.setenv("VIRTUAL_ACTUATORS_ROBOTS", str(tmp_path))
    assert "centipede" in list_robots()
    robot = load_robot("centipede")
    assert robot.model.nq == 7 + 6
    assert load_robot("centipede", floating_base=False).model.nq == 6
    with pytest.raises(RobotDescriptionError, match="build_robot"):
        load_robot("nohook")


# ---------------------------------------------------------------------------------------------
# millipede


@functools.cache
def cached_millipede(legs: int) -> Robot:
    """Build each millipede once per test session."""
    return millipede(legs)


def urdf_mass(urdf: str) -> float:
    """Sum the link masses declared in a URDF string."""
    return sum(float(mass.get("value")) for mass in ET.fromstring(urdf).iter("mass"))


@pytest.mark.parametrize("legs", [1, 2, 7, 100])
def test_millipede_structure(legs: int) -> None:
    robot = cached_millipede(legs)
    model = robot.model
    assert robot.name == "millipede" and robot.floating_base
    assert (model.nq, model.nv) == (7 + 2 * legs, 6 + 2 * legs)
    assert robot.joint_names[0] == "root_joint"
    assert model.existFrame("body")
    for i in range(1, legs + 1):
        for joint in (f"hip_{i}", f"knee_{i}"):
            assert model.existJointName(joint), joint
            kind = "JointModelRZ" if joint.startswith("hip") else "JointModelRX"
            assert model.joints[model.getJointId(joint)].shortname() == kind
        for frame in (f"foot_{i}", f"thigh_{i}", f"shin_{i}", f"foot_{i}_joint"):
            assert model.existFrame(frame), frame
    assert not model.existFrame(f"foot_{legs + 1}")
    assert len(robot.joint_names) == 1 + 2 * legs
    assert np.all(model.effortLimit[6:] > 0) and np.all(model.velocityLimit[6:] > 0)
    assert np.all(model.upperPositionLimit[7:] > model.lowerPositionLimit[7:])


@pytest.mark.parametrize("legs", [1, 2, 7, 100])
def test_millipede_standing_pose(legs: int) -> None:
    robot = cached_millipede(legs)
    model, data = robot.model, pin.Data(robot.model)
    q = robot.neutral()
    assert robot.default_pose == "standing"
    assert q[2] > 0.05  # the body stands above the ground
    np.testing.assert_allclose(q[3:7], [0, 0, 0, 1])
    pin.framesForwardKinematics(model, data, q)
    body = data.oMf[model.getFrameId("body")].translation
    for i in range(1, legs + 1):
        foot = data.oMf[model.getFrameId(f"foot_{i}")].translation
        hip = data.oMi[model.getJointId(f"hip_{i}")].translation
        knee = data.oMi[model.getJointId(f"knee_{i}")].translation
        assert foot[2] == pytest.approx(0.0, abs=1e-9), i
        assert foot[0] == pytest.approx(hip[0], abs=1e-9)  # hips at zero: no forward swing
        side = 1.0 if i % 2 == 1 else -1.0
        assert side * hip[1] > 0  # odd legs on the left, even on the right
        assert side * (knee[1] - hip[1]) > 0  # thighs reach outwards
        assert side * (foot[1] - knee[1]) > 0  # feet outboard of the knees (bent knee)
        assert q[model.joints[model.getJointId(f"knee_{i}")].idx_q] != 0.0
    # legs of one pair share their x; pairs are spread symmetrically about the body centre
    hips_x = [data.oMi[model.getJointId(f"hip_{i}")].translation[0] for i in range(1, legs + 1)]
    if legs >= 2:
        assert hips_x[0] == pytest.approx(hips_x[1])
    pairs = sorted(set(np.round(hips_x, 9)))
    assert np.mean(pairs) == pytest.approx(body[0], abs=1e-9)
    assert hips_x[0] == max(hips_x)  # leg 1 at the front
    # all joints at zero: shins hang straight down, feet one leg length below the body
    q0 = pin.neutral(model)
    pin.framesForwardKinematics(model, data, q0)
    assert data.oMf[model.getFrameId("foot_1")].translation[2] == pytest.approx(-0.1)


@pytest.mark.parametrize("legs", [1, 2, 7, 100])
def test_millipede_mass(legs: int) -> None:
    robot = cached_millipede(legs)
    total = pin.computeTotalMass(robot.model)
    masses = [inertia.mass for inertia in robot.model.inertias]
    assert total > 0
    assert total == pytest.approx(sum(masses))
    assert total == pytest.approx(urdf_mass(robot.urdf_string))
    assert all(inertia.mass > 0 for inertia in list(robot.model.inertias)[1:])


def test_millipede_urdf_is_well_formed_and_reloadable() -> None:
    robot = cached_millipede(7)
    root = ET.fromstring(robot.urdf_string)
    assert root.tag == "robot" and root.get("name") == "millipede"
    assert len(root.findall("link")) == 1 + 3 * 7
    assert sorted(j.get("name") for j in root.findall("joint") if j.get("type") == "fixed") == [
        f"foot_{i}_joint" for i in range(1, 8)
    ]
    again = pin.buildModelFromXML(robot.urdf_string, pin.JointModelFreeFlyer())
    assert again.nq == robot.model.nq


def test_millipede_fixed_base() -> None:
    robot = millipede(4, floating_base=False)
    assert not robot.floating_base and robot.model.nq == 8


@pytest.mark.parametrize("legs", [0, -1, 2.5, "3", True, None])
def test_millipede_rejects_invalid_leg_counts(legs: object) -> None:
    with pytest.raises(InvalidInputError, match="legs"):
        millipede(legs)  # type: ignore[arg-type]


def test_installed_robot_folder_is_searched() -> None:
    """A regular (non-editable) install puts robots/ under <prefix>/share: it is searched."""
    import sysconfig

    installed = Path(sysconfig.get_path("data")) / "share" / "virtual_actuators" / "robots"
    assert installed in catalog.local_dirs()


def test_loader_module_keeps_its_public_names() -> None:
    """The names once defined in ``models.loader`` still import from there (the same objects)."""
    assert loader.__all__ == ["ROBOTS_PATH_ENV", "list_robots", "load_robot", "robots_dir"]
    assert loader.robots_dir is catalog.robots_dir == robots_dir
    assert loader.list_robots is catalog.list_robots is list_robots
    assert loader.ROBOTS_PATH_ENV == catalog.ROBOTS_PATH_ENV == "VIRTUAL_ACTUATORS_ROBOTS"
