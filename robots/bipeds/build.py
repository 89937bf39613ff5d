"""Generate the URDF and SRDF of the seed's two planar bipeds, Spring Turkey and Spring Flamingo.

One source of truth for both robots (seed 003_01cbf1bf710fbcc7, Chew and Pratt, "Virtual model
control: an intuitive approach for bipedal locomotion", IJRR 2001, sections 2 and 4). Run
``python robots/bipeds/build.py`` to regenerate::

    robots/spring_turkey/spring_turkey.urdf     robots/spring_turkey/spring_turkey.srdf
    robots/spring_flamingo/spring_flamingo.urdf robots/spring_flamingo/spring_flamingo.srdf

Structure (both robots): link ``world`` -> prismatic ``boom_x`` (axis x) -> ``boom_x_link`` ->
prismatic ``boom_z`` (axis z) -> ``boom_z_link`` -> revolute ``boom_pitch`` (axis y) -> ``body``.
The body frame sits at hip height, mid-way between the hips. Each leg: revolute ``SIDE_hip`` about
y at ``y = +-HIP_SPACING / 2``, thigh, revolute ``SIDE_knee`` about y, shin; the turkey ends in a
point foot ``SIDE_foot`` (fixed joint at the shin tip), the flamingo in a revolute ``SIDE_ankle``
about y at the shin tip carrying the foot link ``SIDE_foot`` with fixed ``SIDE_heel`` and
``SIDE_toe`` frames at its contact points.

The SRDF lists the three boom joints as ``passive_joint`` entries (no actuator drives them;
:attr:`virtual_actuators.Robot.passive_joints`).

Sign convention: every revolute joint turns about +y, so a positive angle swings the distal link
backward (towards -x). The knee stop is at 0 and the knee bends positively only: the foot goes
back relative to the thigh and the knee points forward, like a human knee.

Sources quoted in the constants: ``[seed]`` is the seed paper (IJRR 2001); ``[IHMC]`` is the
public reproduction of Spring Flamingo in IHMC's open robotics software ("springflamingo"
example, github.com/ihmcrobotics/ihmc-open-robotics-software); ``[estimate]`` marks our own choices.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

ROBOTS_DIR = Path(__file__).resolve().parent.parent

# ---------------------------------------------------------------------------------------------
# Shared constants

HIP_SPACING = 0.12  # m, hips apart in y [IHMC]
BOOM_LINK_MASS = 1e-3  # kg, the boom carriages (a fixture, not the robot) [estimate]
BOOM_LINK_INERTIA = 1e-6  # kg m^2 [estimate]
BOOM_X_LIMIT = 100.0  # m, +- travel along the boom [estimate]
BOOM_Z_RANGE = (0.0, 2.0)  # m, body height range on the boom [estimate]
BOOM_PITCH_LIMIT = 1.5  # rad, +- body pitch [estimate]
BOOM_LINEAR_VELOCITY = 5.0  # m/s [estimate]
BOOM_ANGULAR_VELOCITY = 10.0  # rad/s [estimate]
HIP_LIMIT = 2.0  # rad, +- hip swing [estimate]
KNEE_RANGE = (0.0, 2.6)  # rad, knee stop at 0, bends one way only [IHMC]; 2.6 rad [estimate]
JOINT_VELOCITY = 12.0  # rad/s, hips, knees, ankles [estimate]
LEG_RADIUS = 0.02  # m, radius of the thigh and shin cylinders (inertia and visuals) [estimate]
SHIN_CLEARANCE = 0.10  # m, shin collision cylinder stops this far above the tip [estimate]:
# clear of a sloped ground with the ankle at its 1.3 rad stop
STANDING_FOOT_OFFSET = 0.10  # m, feet at +-0.10 m in x from the hips when standing [estimate]


@dataclass(frozen=True)
class Biped:
    """The numbers of one planar biped (all SI units; see the constants below for sources)."""

    name: str
    body_mass: float
    body_com_height: float  # above the hips
    body_size: tuple[float, float, float]  # box (x, y, z) for inertia and visuals
    thigh_mass: float
    thigh_length: float
    thigh_com: float  # below the hip
    shin_mass: float
    shin_length: float
    shin_com: float  # below the knee
    hip_effort: float
    knee_effort: float
    standing_height: float  # hip height in the standing pose
    foot_radius: float  # contact sphere radius (point foot, or heel and toe)
    # Flamingo only (foot_mass == 0 means a point foot at the shin tip):
    foot_mass: float = 0.0
    foot_heel: float = 0.0  # heel behind the ankle (m, > 0)
    foot_toe: float = 0.0  # toe in front of the ankle (m, > 0)
    ankle_height: float = 0.0  # ankle above the sole
    ankle_limit: float = 0.0
    ankle_effort: float = 0.0

    @property
    def has_ankles(self) -> bool:
        """Whether the legs end in ankles and feet (Spring Flamingo) rather than point feet."""
        return self.foot_mass > 0.0

    @property
    def total_mass(self) -> float:
        """Mass of the robot, boom carriages excluded."""
        return self.body_mass + 2.0 * (self.thigh_mass + self.shin_mass + self.foot_mass)


# ---------------------------------------------------------------------------------------------
# Spring Turkey: five links, point feet, hips and knees actuated [seed, section 2]

TURKEY_TOTAL_MASS = 10.0  # kg, "about 10 kg" [seed]
TURKEY_THIGH_MASS = 1.0  # kg, legs relatively heavy (actuators in the body, cables) [estimate]
TURKEY_SHIN_MASS = 0.5  # kg [estimate]
TURKEY_BODY_MASS = TURKEY_TOTAL_MASS - 2.0 * (TURKEY_THIGH_MASS + TURKEY_SHIN_MASS)  # the rest
TURKEY_TOE_TO_HIP = 0.60  # m, "60 cm toe to hip" [seed]
TURKEY_THIGH_LENGTH = 0.30  # m, half of toe to hip [estimate]
TURKEY_SHIN_LENGTH = TURKEY_TOE_TO_HIP - TURKEY_THIGH_LENGTH  # m, point foot at the shin tip
TURKEY_THIGH_COM = TURKEY_THIGH_LENGTH / 2.0  # m below the hip, uniform rod [estimate]
TURKEY_SHIN_COM = TURKEY_SHIN_LENGTH / 2.0  # m below the knee, uniform rod [estimate]
TURKEY_BODY_COM_HEIGHT = 0.10  # m above the hips [estimate]
TURKEY_BODY_SIZE = (0.25, 0.20, 0.20)  # m, box holding four actuators [estimate]
TURKEY_HIP_EFFORT = 30.0  # N m [estimate]
TURKEY_KNEE_EFFORT = 30.0  # N m [estimate]
TURKEY_NOMINAL_HEIGHT = 0.54  # m, "nominal height of 54 cm" [seed, section 5]
TURKEY_FOOT_RADIUS = 0.02  # m, U-shaped rubber foot as a sphere [estimate]

# ---------------------------------------------------------------------------------------------
# Spring Flamingo: seven links, feet on ankles [seed, section 2]; numbers [IHMC], scaled so that
# the whole robot weighs the seed's 12 kg (the reproduction's body alone weighs 12 kg).

FLAMINGO_TOTAL_MASS = 12.0  # kg, "about 12 kg" [seed]
IHMC_BODY_MASS = 12.0  # kg [IHMC]
IHMC_BODY_INERTIA = 0.1  # kg m^2 about y [IHMC]
IHMC_THIGH_MASS = 0.46  # kg [IHMC]
IHMC_SHIN_MASS = 0.31  # kg [IHMC]
IHMC_FOOT_MASS = 0.35  # kg [IHMC]
IHMC_TOTAL_MASS = IHMC_BODY_MASS + 2.0 * (IHMC_THIGH_MASS + IHMC_SHIN_MASS + IHMC_FOOT_MASS)
FLAMINGO_MASS_SCALE = FLAMINGO_TOTAL_MASS / IHMC_TOTAL_MASS  # 12 / 14.24 = 0.8427
FLAMINGO_BODY_MASS = IHMC_BODY_MASS * FLAMINGO_MASS_SCALE
FLAMINGO_THIGH_MASS = IHMC_THIGH_MASS * FLAMINGO_MASS_SCALE
FLAMINGO_SHIN_MASS = IHMC_SHIN_MASS * FLAMINGO_MASS_SCALE
FLAMINGO_FOOT_MASS = IHMC_FOOT_MASS * FLAMINGO_MASS_SCALE
FLAMINGO_TOE_TO_HIP = 0.84  # m, "84 cm toe to hip" [seed]
FLAMINGO_THIGH_LENGTH = 0.42  # m [IHMC]
FLAMINGO_SHIN_LENGTH = 0.42  # m, knee to ankle [IHMC]
FLAMINGO_ANKLE_HEIGHT = FLAMINGO_TOE_TO_HIP - FLAMINGO_THIGH_LENGTH - FLAMINGO_SHIN_LENGTH  # 0
FLAMINGO_THIGH_COM = 0.30  # m below the hip [IHMC]
FLAMINGO_SHIN_COM = 0.18  # m below the knee [IHMC]
FLAMINGO_BODY_COM_HEIGHT = 0.20  # m above the hips [IHMC]
# Box whose y inertia is the reproduction's 0.1 kg m^2 scaled like the mass:
# m (x^2 + z^2) / 12 = 0.0843 with x^2 + z^2 = 0.10 [estimate of the shape]
FLAMINGO_BODY_SIZE = (0.20, 0.24, math.sqrt(0.10 - 0.20**2))
FLAMINGO_FOOT_LENGTH = 0.23  # m, heel to toe [IHMC]
FLAMINGO_FOOT_HEEL = 0.08  # m, heel behind the ankle [estimate]
FLAMINGO_FOOT_TOE = FLAMINGO_FOOT_LENGTH - FLAMINGO_FOOT_HEEL  # m, toe in front of the ankle
FLAMINGO_HIP_EFFORT = 40.0  # N m [estimate]
FLAMINGO_KNEE_EFFORT = 40.0  # N m [estimate]
FLAMINGO_ANKLE_EFFORT = 10.0  # N m [estimate]
FLAMINGO_ANKLE_LIMIT = 1.3  # rad, +- [estimate]: a limp stance ankle on a 20-degree slope under a
# bent knee reaches about -0.95 rad; a tighter stop would brake the body like an ankle torque
FLAMINGO_STANDING_HEIGHT = 0.78  # m hip height, knees bent (below the 0.84 m leg) [estimate]
FLAMINGO_FOOT_RADIUS = 0.01  # m, heel and toe contact spheres [estimate]

SPRING_TURKEY = Biped(
    name="spring_turkey",
    body_mass=TURKEY_BODY_MASS,
    body_com_height=TURKEY_BODY_COM_HEIGHT,
    body_size=TURKEY_BODY_SIZE,
    thigh_mass=TURKEY_THIGH_MASS,
    thigh_length=TURKEY_THIGH_LENGTH,
    thigh_com=TURKEY_THIGH_COM,
    shin_mass=TURKEY_SHIN_MASS,
    shin_length=TURKEY_SHIN_LENGTH,
    shin_com=TURKEY_SHIN_COM,
    hip_effort=TURKEY_HIP_EFFORT,
    knee_effort=TURKEY_KNEE_EFFORT,
    standing_height=TURKEY_NOMINAL_HEIGHT,
    foot_radius=TURKEY_FOOT_RADIUS,
)

SPRING_FLAMINGO = Biped(
    name="spring_flamingo",
    body_mass=FLAMINGO_BODY_MASS,
    body_com_height=FLAMINGO_BODY_COM_HEIGHT,
    body_size=FLAMINGO_BODY_SIZE,
    thigh_mass=FLAMINGO_THIGH_MASS,
    thigh_length=FLAMINGO_THIGH_LENGTH,
    thigh_com=FLAMINGO_THIGH_COM,
    shin_mass=FLAMINGO_SHIN_MASS,
    shin_length=FLAMINGO_SHIN_LENGTH,
    shin_com=FLAMINGO_SHIN_COM,
    hip_effort=FLAMINGO_HIP_EFFORT,
    knee_effort=FLAMINGO_KNEE_EFFORT,
    standing_height=FLAMINGO_STANDING_HEIGHT,
    foot_radius=FLAMINGO_FOOT_RADIUS,
    foot_mass=FLAMINGO_FOOT_MASS,
    foot_heel=FLAMINGO_FOOT_HEEL,
    foot_toe=FLAMINGO_FOOT_TOE,
    ankle_height=FLAMINGO_ANKLE_HEIGHT,
    ankle_limit=FLAMINGO_ANKLE_LIMIT,
    ankle_effort=FLAMINGO_ANKLE_EFFORT,
)

BIPEDS = (SPRING_TURKEY, SPRING_FLAMINGO)

# Foot placement in the standing pose: left foot ahead, right foot behind the hips.
SIDES = (("left", 1.0), ("right", -1.0))


# ---------------------------------------------------------------------------------------------
# Kinematics


def leg_ik(dx: float, dz: float, thigh: float, shin: float) -> tuple[float, float]:
    """Planar inverse kinematics of a two-link leg, knee bent the allowed way (knee > 0).

    Every joint turns about +y, so a link of length L at absolute angle phi below its joint
    ends at ``(-L sin phi, -L cos phi)`` in (x, z).

    Args:
        dx: Foot (or ankle) x minus hip x, in the body frame (body upright).
        dz: Foot z minus hip z (negative: the foot is below the hip).
        thigh: Hip-to-knee length.
        shin: Knee-to-foot length.

    Returns:
        (hip, knee) angles in radians.

    Raises:
        ValueError: If the point is out of reach.

    """
    u, w = -dx, -dz
    reach2 = u * u + w * w
    cos_knee = (reach2 - thigh**2 - shin**2) / (2.0 * thigh * shin)
    if not -1.0 <= cos_knee <= 1.0:
        raise ValueError(f"({dx}, {dz}) is out of reach of a {thigh} + {shin} m leg")
    knee = math.acos(cos_knee)
    hip = math.atan2(u, w) - math.atan2(shin * math.sin(knee), thigh + shin * math.cos(knee))
    return hip, knee


def standing_pose(robot: Biped) -> dict[str, float]:
    """Joint values of the standing pose: body upright at ``standing_height``, feet on the ground.

    Point feet: the foot frame (sphere centre) at z = foot radius. Feet with ankles: the sole at
    z = 0 and the foot horizontal (ankle = -(hip + knee)).
    """
    pose = {"boom_x": 0.0, "boom_z": robot.standing_height, "boom_pitch": 0.0}
    ground = robot.foot_radius if not robot.has_ankles else robot.ankle_height
    for side, sign in SIDES:
        hip, knee = leg_ik(
            sign * STANDING_FOOT_OFFSET,
            ground - robot.standing_height,
            robot.thigh_length,
            robot.shin_length,
        )
        pose[f"{side}_hip"] = hip
        pose[f"{side}_knee"] = knee
        if robot.has_ankles:
            pose[f"{side}_ankle"] = -(hip + knee)
    return pose


# ---------------------------------------------------------------------------------------------
# URDF text


def _f(value: float) -> str:
    """Format a number for the XML (shortest round-trip form, no negative zero)."""
    value = 0.0 if value == 0.0 else value
    return repr(float(value))


def _xyz(x: float, y: float, z: float) -> str:
    return f"{_f(x)} {_f(y)} {_f(z)}"


def _inertial(mass: float, com: tuple[float, float, float], ixx: float, iyy: float, izz: float):
    return (
        f'    <inertial>\n      <origin xyz="{_xyz(*com)}" rpy="0 0 0"/>\n'
        f'      <mass value="{_f(mass)}"/>\n'
        f'      <inertia ixx="{_f(ixx)}" ixy="0" ixz="0" iyy="{_f(iyy)}" iyz="0"'
        f' izz="{_f(izz)}"/>\n'
        "    </inertial>\n"
    )


def _box_inertia(mass: float, size: tuple[float, float, float]) -> tuple[float, float, float]:
    x, y, z = size
    return (
        mass * (y * y + z * z) / 12.0,
        mass * (x * x + z * z) / 12.0,
        mass * (x * x + y * y) / 12.0,
    )


def _rod_inertia(mass: float, length: float) -> tuple[float, float, float]:
    """Solid cylinder along z of radius LEG_RADIUS, about its centre."""
    across = mass * (3.0 * LEG_RADIUS**2 + length**2) / 12.0
    return across, across, mass * LEG_RADIUS**2 / 2.0


def _visual(geometry: str, xyz: tuple[float, float, float], material: str) -> str:
    return (
        f'    <visual>\n      <origin xyz="{_xyz(*xyz)}" rpy="0 0 0"/>\n'
        f"      <geometry>{geometry}</geometry>\n"
        f'      <material name="{material}"/>\n    </visual>\n'
    )


def _sphere_collision(radius: float, xyz: tuple[float, float, float]) -> str:
    return (
        f'    <collision>\n      <origin xyz="{_xyz(*xyz)}" rpy="0 0 0"/>\n'
        f'      <geometry><sphere radius="{_f(radius)}"/></geometry>\n    </collision>\n'
    )


def _collision(geometry: str, xyz: tuple[float, float, float]) -> str:
    return (
        f'    <collision>\n      <origin xyz="{_xyz(*xyz)}" rpy="0 0 0"/>\n'
        f"      <geometry>{geometry}</geometry>\n    </collision>\n"
    )


def _joint(
    name: str,
    kind: str,
    parent: str,
    child: str,
    xyz: tuple[float, float, float] = (0.0, 0.0, 0.0),
    axis: str = "0 1 0",
    limits: tuple[float, float, float, float] | None = None,
) -> str:
    text = f'  <joint name="{name}" type="{kind}">\n'
    text += f'    <parent link="{parent}"/>\n    <child link="{child}"/>\n'
    text += f'    <origin xyz="{_xyz(*xyz)}" rpy="0 0 0"/>\n'
    if kind != "fixed":
        text += f'    <axis xyz="{axis}"/>\n'
    if limits is not None:
        lower, upper, effort, velocity = limits
        text += (
            f'    <limit lower="{_f(lower)}" upper="{_f(upper)}" effort="{_f(effort)}" '
            f'velocity="{_f(velocity)}"/>\n'
        )
    return text + "  </joint>\n"


MATERIALS = {
    "boom": "0.5 0.5 0.5 1",
    "body": "0.2 0.35 0.7 1",
    "left": "0.85 0.45 0.1 1",
    "right": "0.3 0.6 0.3 1",
    "foot": "0.15 0.15 0.15 1",
}


def urdf(robot: Biped) -> str:
    """Return the URDF text of a planar biped on a boom."""
    out = ['<?xml version="1.0"?>\n']
    out.append("<!-- Generated by robots/bipeds/build.py: do not edit by hand. -->\n")
    out.append(f'<robot name="{robot.name}">\n')
    for name, rgba in MATERIALS.items():
        out.append(f'  <material name="{name}"><color rgba="{rgba}"/></material>\n')
    tiny = _inertial(BOOM_LINK_MASS, (0.0, 0.0, 0.0), *(BOOM_LINK_INERTIA,) * 3)
    out.append('  <link name="world"/>\n')
    out.append(f'  <link name="boom_x_link">\n{tiny}  </link>\n')
    out.append(f'  <link name="boom_z_link">\n{tiny}  </link>\n')
    out.append(
        _joint(
            "boom_x",
            "prismatic",
            "world",
            "boom_x_link",
            axis="1 0 0",
            limits=(-BOOM_X_LIMIT, BOOM_X_LIMIT, 1000.0, BOOM_LINEAR_VELOCITY),
        )
    )
    out.append(
        _joint(
            "boom_z",
            "prismatic",
            "boom_x_link",
            "boom_z_link",
            axis="0 0 1",
            limits=(*BOOM_Z_RANGE, 1000.0, BOOM_LINEAR_VELOCITY),
        )
    )
    out.append(
        _joint(
            "boom_pitch",
            "revolute",
            "boom_z_link",
            "body",
            limits=(-BOOM_PITCH_LIMIT, BOOM_PITCH_LIMIT, 1000.0, BOOM_ANGULAR_VELOCITY),
        )
    )
    body_com = (0.0, 0.0, robot.body_com_height)
    sx, sy, sz = robot.body_size
    out.append(
        '  <link name="body">\n'
        + _inertial(robot.body_mass, body_com, *_box_inertia(robot.body_mass, robot.body_size))
        + _visual(f'<box size="{_xyz(sx, sy, sz)}"/>', body_com, "body")
        + _visual(
            f'<box size="{_xyz(2 * LEG_RADIUS, HIP_SPACING + 2 * LEG_RADIUS, 2 * LEG_RADIUS)}"/>',
            (0.0, 0.0, 0.0),
            "body",
        )
        + _collision(f'<box size="{_xyz(sx, sy, sz)}"/>', body_com)
        + "  </link>\n"
    )
    for side, _ in SIDES:
        out.append(_leg(robot, side))
    out.append("</robot>\n")
    return "".join(out)


def _leg(robot: Biped, side: str) -> str:
    y = HIP_SPACING / 2.0 if side == "left" else -HIP_SPACING / 2.0
    out = []
    for part, mass, length, com in (
        ("thigh", robot.thigh_mass, robot.thigh_length, robot.thigh_com),
        ("shin", robot.shin_mass, robot.shin_length, robot.shin_com),
    ):
        cylinder = f'<cylinder radius="{_f(LEG_RADIUS)}" length="{_f(length)}"/>'
        # Collision: the whole thigh; the shin stops SHIN_CLEARANCE above its tip, so that only
        # the feet touch the ground in normal walking (anything else touching means a fall).
        hit = round(length - (SHIN_CLEARANCE if part == "shin" else 0.0), 9)
        hit_cylinder = f'<cylinder radius="{_f(LEG_RADIUS)}" length="{_f(hit)}"/>'
        out.append(
            f'  <link name="{side}_{part}">\n'
            + _inertial(mass, (0.0, 0.0, -com), *_rod_inertia(mass, length))
            + _visual(cylinder, (0.0, 0.0, -length / 2.0), side)
            + _collision(hit_cylinder, (0.0, 0.0, round(-hit / 2.0, 9)))
            + "  </link>\n"
        )
    effort, velocity = robot.hip_effort, JOINT_VELOCITY
    out.append(
        _joint(
            f"{side}_hip",
            "revolute",
            "body",
            f"{side}_thigh",
            (0.0, y, 0.0),
            limits=(-HIP_LIMIT, HIP_LIMIT, effort, velocity),
        )
    )
    out.append(
        _joint(
            f"{side}_knee",
            "revolute",
            f"{side}_thigh",
            f"{side}_shin",
            (0.0, 0.0, -robot.thigh_length),
            limits=(*KNEE_RANGE, robot.knee_effort, velocity),
        )
    )
    tip = (0.0, 0.0, -robot.shin_length)
    foot = f"{side}_foot"
    if not robot.has_ankles:
        out.append(
            f'  <link name="{foot}">\n'
            + _visual(f'<sphere radius="{_f(robot.foot_radius)}"/>', (0.0, 0.0, 0.0), "foot")
            + _sphere_collision(robot.foot_radius, (0.0, 0.0, 0.0))
            + "  </link>\n"
        )
        out.append(_joint(f"{side}_foot_joint", "fixed", f"{side}_shin", foot, tip))
        return "".join(out)
    # Foot: ankle at the link origin, sole at z = -ankle_height, heel behind, toe in front.
    sole = -robot.ankle_height
    heel, toe = (-robot.foot_heel, 0.0, sole), (robot.foot_toe, 0.0, sole)
    length = robot.foot_heel + robot.foot_toe
    thickness = 2.0 * robot.foot_radius
    centre = ((toe[0] + heel[0]) / 2.0, 0.0, sole + robot.foot_radius)
    ixx, iyy, izz = _box_inertia(robot.foot_mass, (length, 2 * LEG_RADIUS, thickness))
    out.append(
        f'  <link name="{foot}">\n'
        + _inertial(robot.foot_mass, centre, ixx, iyy, izz)
        + _visual(f'<box size="{_xyz(length, 4 * LEG_RADIUS, thickness)}"/>', centre, "foot")
        + "  </link>\n"
    )
    out.append(
        _joint(
            f"{side}_ankle",
            "revolute",
            f"{side}_shin",
            foot,
            tip,
            limits=(-robot.ankle_limit, robot.ankle_limit, robot.ankle_effort, velocity),
        )
    )
    # Contact spheres tangent to the sole plane, one in each of the heel and toe links, so that
    # a simulator reports the heel and toe contact switches by frame.
    for point, xyz in (("heel", heel), ("toe", toe)):
        sphere = _sphere_collision(robot.foot_radius, (0.0, 0.0, robot.foot_radius))
        out.append(f'  <link name="{side}_{point}">\n{sphere}  </link>\n')
        out.append(_joint(f"{side}_{point}_joint", "fixed", foot, f"{side}_{point}", xyz))
    return "".join(out)


#: Joints of the boom: they guide the robot in its plane and no actuator drives them.
PASSIVE_JOINTS = ("boom_x", "boom_z", "boom_pitch")


def srdf(robot: Biped) -> str:
    """Return the SRDF text: all joints, the "standing" state, the boom as passive joints."""
    pose = standing_pose(robot)
    out = ['<?xml version="1.0"?>\n']
    out.append("<!-- Generated by robots/bipeds/build.py: do not edit by hand. -->\n")
    out.append(f'<robot name="{robot.name}">\n  <group name="all_joints">\n')
    out.extend(f'    <joint name="{name}"/>\n' for name in pose)
    out.append('  </group>\n  <group_state name="standing" group="all_joints">\n')
    out.extend(f'    <joint name="{name}" value="{_f(value)}"/>\n' for name, value in pose.items())
    out.append("  </group_state>\n")
    out.extend(f'  <passive_joint name="{name}"/>\n' for name in PASSIVE_JOINTS)
    out.append("</robot>\n")
    return "".join(out)


def build(robots_dir: Path = ROBOTS_DIR) -> list[Path]:
    """Write the URDF and SRDF of both bipeds under ``robots_dir``; return the paths written."""
    written = []
    for robot in BIPEDS:
        folder = robots_dir / robot.name
        folder.mkdir(parents=True, exist_ok=True)
        for suffix, text in ((".urdf", urdf(robot)), (".srdf", srdf(robot))):
            path = folder / f"{robot.name}{suffix}"
            path.write_text(text)
            written.append(path)
    return written


if __name__ == "__main__":
    for written_path in build():
        print(written_path)
