"""Build ``hexapod.urdf`` and ``hexapod.srdf``: the hexapod of the 1996 virtual actuator paper.

This script is the single source of truth of the robot: run ``python robots/hexapod/build.py``
to regenerate both files next to it. Every number is a named constant with its source:

- "seed": Pratt, Torres, Dilworth & Pratt, *Virtual Actuator Control* (1996), section 3
  ("Implementation on a Hexapod"): 3.8 kg, 45 cm long, stands 15 cm tall;
- "IHMC": the public reproduction of the 1996 hexapod (IHMC open robotics software,
  "agileHexapod" example, github.com/ihmcrobotics/ihmc-open-robotics-software);
- "chosen": an assumption of this description, documented where it is made.

Leg numbering (chosen): odd legs form one support tripod, even legs the other, so
``foot_1, foot_3, foot_5`` is a tripod as in the seed's figure 3 and eq. 26::

    leg 1 front-left   (+0.15, +0.075)     leg 2 front-right  (+0.15, -0.075)
    leg 4 middle-left  ( 0.00, +0.075)     leg 3 middle-right ( 0.00, -0.075)
    leg 5 hind-left    (-0.15, +0.075)     leg 6 hind-right   (-0.15, -0.075)

Joint axes: the seed's eq. 24 has, per leg, rotation axes (0, 0, -1) for theta_h2 and
(-cos h2, -sin h2, 0) for both theta_h1 and theta_k (they only appear as the sum k + h1). So the
first joint from the body is a yaw joint about z, followed by two parallel joints whose axis is
the body's x axis when the yaw is zero: the legs swing sideways, as on an insect. Here
``hip1_i`` is the yaw joint (about z, the seed's theta_h2), ``hip2_i`` the hip about x (the
seed's theta_h1) and ``knee_i`` the knee about x (theta_k). Axes point along +x and +z (the seed's
J has -x and -z: only the sign of the angles and torques differs). A knee about y would put hip1
and hip2 in a singular pair whenever hip2 = 0 (both move the foot along y).

All joints zero: each leg points straight down from its mount (seed), the foot centre 0.20 m
below it (thigh 0.10 + shin 0.08 + foot radius 0.02, IHMC).

Standing pose (group state "standing" of the SRDF): body origin (the box centre, where the hips
are mounted, at z = 0 in the body frame as in the seed) 0.13 m above the ground (IHMC desired
body height); hip1 = hip2 = 0, thigh straight down, knee bent outward (away from the body) so
that the foot sphere touches the ground (foot centre at z = FOOT_RADIUS). With a body box
0.04 m tall its top is at 0.13 + 0.02 = 0.15 m: the seed's "stands 15 cm tall".
"""

from __future__ import annotations

import math
from pathlib import Path
from xml.dom import minidom

HERE = Path(__file__).resolve().parent

# Masses (IHMC): body 3.0877 kg, thigh 0.0866 kg, shin 0.0396 kg per leg.
BODY_MASS = 3.0877
THIGH_MASS = 0.0866
SHIN_MASS = 0.0396  # shin including the foot sphere (IHMC has no separate foot mass)
HIP_MASS = 0.005  # chosen: the small link between the two hip axes

# Lengths (IHMC; seed: upper and lower links both of length L).
THIGH_LENGTH = 0.10  # hip to knee
SHIN_LENGTH = 0.08  # knee to the foot sphere's surface
FOOT_RADIUS = 0.02  # point foot modelled as a sphere for collisions
LINK_LENGTH = SHIN_LENGTH + FOOT_RADIUS  # knee to foot centre: L = 0.10 m

# Body (seed: 45 cm long; IHMC: mounts at y = +-0.075 m; chosen: width = 2 * 0.075, height
# 0.04 m so that the top is at 0.15 m when standing at 0.13 m).
BODY_LENGTH = 0.45
BODY_WIDTH = 0.15
BODY_HEIGHT = 0.04

# Hip mounts (IHMC): x in {+0.15, 0, -0.15} m, y = +-0.075 m, z = 0 (seed: (Px, Py, 0)).
MOUNT_X = 0.15
MOUNT_Y = 0.075
# leg number: (Px, Py); see the module docstring for the numbering.
MOUNTS = {
    1: (+MOUNT_X, +MOUNT_Y),
    2: (+MOUNT_X, -MOUNT_Y),
    3: (0.0, -MOUNT_Y),
    4: (0.0, +MOUNT_Y),
    5: (-MOUNT_X, +MOUNT_Y),
    6: (-MOUNT_X, -MOUNT_Y),
}

# Pendulum variant (seed section 4, Fig. 5: "a pendulum of length 30cm and mass 0.18kg attached
# via a pin joint in the x direction"; IHMC: a 0.1829 kg, 0.30 m rod). Chosen: a uniform rod
# (IHMC) pinned at the centre of the body's top face, turning about the body's y axis so that it
# swings in the walking direction x; unactuated (an SRDF passive joint), no damping; its limits
# (+-PENDULUM_LIMIT) only bound the model (a pendulum that far over has fallen long before).
PENDULUM_LENGTH = 0.30
PENDULUM_MASS = 0.18
PENDULUM_RADIUS = 0.005  # visual and collision rod radius (chosen)
PENDULUM_TIP_RADIUS = 0.015  # visual ball at the tip (chosen, massless)
PENDULUM_PIVOT = (0.0, 0.0, BODY_HEIGHT / 2)  # top face centre, in `body`
PENDULUM_LIMIT = 2.5  # rad (chosen)

# Standing (IHMC): desired body height 0.13 m.
STANDING_HEIGHT = 0.13

# Link radii for inertia and visuals (chosen).
HIP_RADIUS = 0.012
THIGH_RADIUS = 0.008
SHIN_RADIUS = 0.006

# Joint limits (chosen). hip1: yaw +-0.8 rad; hip2: +-1.0 rad; knee: bends both ways (legs on
# the left bend with positive angles, on the right with negative ones when standing; one URDF
# range for all legs keeps the description mirror-free) up to +-2.6 rad (about 150 degrees).
HIP1_LIMIT = 0.8
HIP2_LIMIT = 1.0
KNEE_LIMIT = 2.6
EFFORT_LIMIT = 5.0  # N m (chosen; standing on a tripod needs about 0.6 N m at a knee)
VELOCITY_LIMIT = 10.0  # rad/s (chosen)
DAMPING = 0.01  # N m s/rad (chosen, visual simulators only)


def standing_knee_angle() -> float:
    """Return the knee bend magnitude that puts the foot sphere on the ground when standing.

    Foot centre height = STANDING_HEIGHT - THIGH_LENGTH - LINK_LENGTH * cos(knee) = FOOT_RADIUS.
    """
    c = (STANDING_HEIGHT - FOOT_RADIUS - THIGH_LENGTH) / LINK_LENGTH
    if not -1.0 < c < 1.0:
        raise ValueError(f"standing height {STANDING_HEIGHT} out of reach (cos = {c})")
    return math.acos(c)


def standing_pose() -> dict[str, float]:
    """Return the standing joint angles: knees bent outward (positive on the left, y > 0)."""
    knee = standing_knee_angle()
    pose: dict[str, float] = {}
    for i, (_, py) in MOUNTS.items():
        pose[f"hip1_{i}"] = 0.0
        pose[f"hip2_{i}"] = 0.0
        # A positive rotation about +x moves a downward leg towards +y.
        pose[f"knee_{i}"] = knee if py > 0 else -knee
    return pose


def total_mass() -> float:
    """Return the robot's total mass in kg."""
    return BODY_MASS + len(MOUNTS) * (HIP_MASS + THIGH_MASS + SHIN_MASS)


def _f(x: float) -> str:
    return f"{x:.10g}"


def _vec(*xs: float) -> str:
    return " ".join(_f(x) for x in xs)


def _box_inertia(m: float, a: float, b: float, c: float) -> tuple[float, float, float]:
    return (m * (b * b + c * c) / 12, m * (a * a + c * c) / 12, m * (a * a + b * b) / 12)


def _cylinder_inertia(m: float, r: float, h: float) -> tuple[float, float, float]:
    """Solid cylinder along z."""
    side = m * (3 * r * r + h * h) / 12
    return (side, side, m * r * r / 2)


def _sphere_inertia(m: float, r: float) -> tuple[float, float, float]:
    i = 2 * m * r * r / 5
    return (i, i, i)


def _sub(parent, tag: str, **attrs: str):
    el = parent.ownerDocument.createElement(tag)
    for k, v in attrs.items():
        el.setAttribute(k, v)
    parent.appendChild(el)
    return el


def _inertial(link, mass: float, com: tuple[float, float, float], diag) -> None:
    inertial = _sub(link, "inertial")
    _sub(inertial, "origin", xyz=_vec(*com), rpy="0 0 0")
    _sub(inertial, "mass", value=_f(mass))
    ixx, iyy, izz = diag
    _sub(inertial, "inertia", ixx=_f(ixx), ixy="0", ixz="0", iyy=_f(iyy), iyz="0", izz=_f(izz))


def _geometry(link, kind: str, xyz: tuple[float, float, float], material: str | None, **shape):
    el = _sub(link, kind)
    _sub(el, "origin", xyz=_vec(*xyz), rpy="0 0 0")
    geometry = _sub(el, "geometry")
    if "size" in shape:
        _sub(geometry, "box", size=_vec(*shape["size"]))
    elif "length" in shape:
        _sub(geometry, "cylinder", radius=_f(shape["radius"]), length=_f(shape["length"]))
    else:
        _sub(geometry, "sphere", radius=_f(shape["radius"]))
    if material is not None and kind == "visual":
        _sub(el, "material", name=material)


def _joint(robot, name, kind, parent, child, xyz, axis=None, limit=None) -> None:
    joint = _sub(robot, "joint", name=name, type=kind)
    _sub(joint, "parent", link=parent)
    _sub(joint, "child", link=child)
    _sub(joint, "origin", xyz=_vec(*xyz), rpy="0 0 0")
    if axis is not None:
        _sub(joint, "axis", xyz=_vec(*axis))
    if limit is not None:
        _sub(
            joint,
            "limit",
            lower=_f(-limit),
            upper=_f(limit),
            effort=_f(EFFORT_LIMIT),
            velocity=_f(VELOCITY_LIMIT),
        )
        _sub(joint, "dynamics", damping=_f(DAMPING), friction="0")


def _pendulum(robot) -> None:
    """Add the pendulum link and its passive pin joint (about the body's y axis)."""
    rod = _sub(robot, "link", name="pendulum")
    com = (0, 0, PENDULUM_LENGTH / 2)
    ixx, _, izz = _cylinder_inertia(PENDULUM_MASS, PENDULUM_RADIUS, PENDULUM_LENGTH)
    _inertial(rod, PENDULUM_MASS, com, (ixx, ixx, izz))
    _geometry(rod, "visual", com, "leg_blue", radius=PENDULUM_RADIUS, length=PENDULUM_LENGTH)
    _geometry(rod, "collision", com, None, radius=PENDULUM_RADIUS, length=PENDULUM_LENGTH)
    tip = (0, 0, PENDULUM_LENGTH)
    _geometry(rod, "visual", tip, "foot_orange", radius=PENDULUM_TIP_RADIUS)
    joint = _sub(robot, "joint", name="pendulum_joint", type="revolute")
    _sub(joint, "parent", link="body")
    _sub(joint, "child", link="pendulum")
    _sub(joint, "origin", xyz=_vec(*PENDULUM_PIVOT), rpy="0 0 0")
    _sub(joint, "axis", xyz="0 1 0")
    _sub(
        joint,
        "limit",
        lower=_f(-PENDULUM_LIMIT),
        upper=_f(PENDULUM_LIMIT),
        effort="0",
        velocity=_f(100.0),
    )
    _sub(joint, "dynamics", damping="0", friction="0")


def build_urdf(pendulum: bool = False) -> str:
    """Return the URDF text (``pendulum``: with the pendulum on the back, ``hexapod_pendulum``)."""
    name = "hexapod_pendulum" if pendulum else "hexapod"
    doc = minidom.Document()
    doc.appendChild(doc.createComment(" Generated by robots/hexapod/build.py: do not edit. "))
    robot = doc.createElement("robot")
    robot.setAttribute("name", name)
    doc.appendChild(robot)
    for name, rgba in (
        ("body_grey", "0.6 0.6 0.65 1"),
        ("leg_blue", "0.2 0.35 0.8 1"),
        ("joint_black", "0.1 0.1 0.1 1"),
        ("foot_orange", "0.9 0.5 0.1 1"),
    ):
        _sub(_sub(robot, "material", name=name), "color", rgba=rgba)

    body_size = (BODY_LENGTH, BODY_WIDTH, BODY_HEIGHT)
    body = _sub(robot, "link", name="body")
    _inertial(body, BODY_MASS, (0, 0, 0), _box_inertia(BODY_MASS, *body_size))
    _geometry(body, "visual", (0, 0, 0), "body_grey", size=body_size)
    _geometry(body, "collision", (0, 0, 0), None, size=body_size)

    for i, (px, py) in MOUNTS.items():
        hip = _sub(robot, "link", name=f"hip_{i}")
        _inertial(hip, HIP_MASS, (0, 0, 0), _sphere_inertia(HIP_MASS, HIP_RADIUS))
        _geometry(hip, "visual", (0, 0, 0), "joint_black", radius=HIP_RADIUS)

        thigh = _sub(robot, "link", name=f"thigh_{i}")
        com = (0, 0, -THIGH_LENGTH / 2)
        _inertial(thigh, THIGH_MASS, com, _cylinder_inertia(THIGH_MASS, THIGH_RADIUS, THIGH_LENGTH))
        _geometry(thigh, "visual", com, "leg_blue", radius=THIGH_RADIUS, length=THIGH_LENGTH)

        shin = _sub(robot, "link", name=f"shin_{i}")
        com = (0, 0, -SHIN_LENGTH / 2)
        _inertial(shin, SHIN_MASS, com, _cylinder_inertia(SHIN_MASS, SHIN_RADIUS, SHIN_LENGTH))
        _geometry(shin, "visual", com, "leg_blue", radius=SHIN_RADIUS, length=SHIN_LENGTH)

        foot = _sub(robot, "link", name=f"foot_{i}")  # massless: the shin mass includes it
        _geometry(foot, "visual", (0, 0, 0), "foot_orange", radius=FOOT_RADIUS)
        _geometry(foot, "collision", (0, 0, 0), None, radius=FOOT_RADIUS)

        _joint(
            robot, f"hip1_{i}", "revolute", "body", f"hip_{i}", (px, py, 0), (0, 0, 1), HIP1_LIMIT
        )
        _joint(
            robot,
            f"hip2_{i}",
            "revolute",
            f"hip_{i}",
            f"thigh_{i}",
            (0, 0, 0),
            (1, 0, 0),
            HIP2_LIMIT,
        )
        _joint(
            robot,
            f"knee_{i}",
            "revolute",
            f"thigh_{i}",
            f"shin_{i}",
            (0, 0, -THIGH_LENGTH),
            (1, 0, 0),
            KNEE_LIMIT,
        )
        _joint(robot, f"foot_joint_{i}", "fixed", f"shin_{i}", f"foot_{i}", (0, 0, -LINK_LENGTH))
    if pendulum:
        _pendulum(robot)
    return doc.toprettyxml(indent="  ")


def build_srdf(pendulum: bool = False) -> str:
    """Return the SRDF text: one group with all leg joints and the "standing" group state.

    Pinocchio's ``loadReferenceConfigurations`` reads the free-flyer ``root_joint`` as its 7
    configuration entries: position x y z, then the quaternion x y z w. With ``pendulum`` the
    pendulum joint is declared passive (no motor drives it) and stands upright (angle 0).
    """
    doc = minidom.Document()
    doc.appendChild(doc.createComment(" Generated by robots/hexapod/build.py: do not edit. "))
    robot = doc.createElement("robot")
    robot.setAttribute("name", "hexapod_pendulum" if pendulum else "hexapod")
    doc.appendChild(robot)
    pose = standing_pose()
    group = _sub(robot, "group", name="all_legs")
    for name in pose:
        _sub(group, "joint", name=name)
    state = _sub(robot, "group_state", name="standing", group="all_legs")
    _sub(state, "joint", name="root_joint", value=_vec(0, 0, STANDING_HEIGHT, 0, 0, 0, 1))
    for name, value in pose.items():
        _sub(state, "joint", name=name, value=_f(value))
    if pendulum:
        _sub(robot, "passive_joint", name="pendulum_joint")
    return doc.toprettyxml(indent="  ")


def main() -> None:
    """Write hexapod.urdf / .srdf and hexapod_pendulum.urdf / .srdf next to this script."""
    (HERE / "hexapod.urdf").write_text(build_urdf(), encoding="utf-8")
    (HERE / "hexapod.srdf").write_text(build_srdf(), encoding="utf-8")
    (HERE / "hexapod_pendulum.urdf").write_text(build_urdf(pendulum=True), encoding="utf-8")
    (HERE / "hexapod_pendulum.srdf").write_text(build_srdf(pendulum=True), encoding="utf-8")
    print(
        f"hexapod: total mass {total_mass():.4f} kg, standing height {STANDING_HEIGHT} m, "
        f"knee bend {standing_knee_angle():.6f} rad"
    )


if __name__ == "__main__":
    main()
