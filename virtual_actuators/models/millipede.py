"""A generated many-legged robot: the millipede of the seed (000_..., section 2.5.1)."""

from __future__ import annotations

import math
import numbers
import xml.etree.ElementTree as ET

import pinocchio as pin

from virtual_actuators.exceptions import InvalidInputError
from virtual_actuators.models.robot import Robot
from virtual_actuators.vocabulary.arguments import check_flag, check_number

#: Mass (kg) and sphere radius (m) of each point foot: tiny, but not zero for the simulators
#: that reject massless bodies.
FOOT_MASS = 1e-3
FOOT_RADIUS = 0.005
#: Default length (m) of each thigh and each shin.
DEFAULT_LEG_LENGTH = 0.10
#: Most legs a millipede may have (1000 legs build in about 0.5 s and 50 MiB).
MAX_LEGS = 2000


def _vec(*values: float) -> str:
    """Numbers for a URDF attribute, space-separated, without losing precision."""
    return " ".join(repr(float(v)) for v in values)


def _add_inertial(
    link: ET.Element, mass: float, com: tuple[float, float, float], diag: tuple[float, float, float]
) -> None:
    """Append an ``<inertial>`` with a diagonal inertia (about the centre of mass) to ``link``."""
    inertial = ET.SubElement(link, "inertial")
    ET.SubElement(inertial, "origin", xyz=_vec(*com), rpy="0 0 0")
    ET.SubElement(inertial, "mass", value=_vec(mass))
    ixx, iyy, izz = diag
    ET.SubElement(
        inertial, "inertia", ixx=_vec(ixx), ixy="0", ixz="0", iyy=_vec(iyy), iyz="0", izz=_vec(izz)
    )


def _add_geometry(
    link: ET.Element,
    tag: str,
    xyz: tuple[float, float, float],
    shape: str,
    collision: bool,
    rpy: tuple[float, float, float] = (0.0, 0.0, 0.0),
    **size: str,
) -> None:
    """Append a ``<visual>`` (and optionally a matching ``<collision>``) to ``link``."""
    for kind in ("visual", "collision") if collision else ("visual",):
        element = ET.SubElement(link, kind)
        ET.SubElement(element, "origin", xyz=_vec(*xyz), rpy=_vec(*rpy))
        geometry = ET.SubElement(element, "geometry")
        ET.SubElement(geometry, shape, **size)
        if kind == "visual":
            ET.SubElement(element, "material", name=tag)


def _add_joint(
    robot: ET.Element,
    name: str,
    kind: str,
    parent: str,
    child: str,
    xyz: tuple[float, float, float],
    limit: dict[str, str] | None = None,
    axis: str = "",
) -> None:
    """Append a joint; a moving one (with a ``limit``) gets its axis, limits and damping."""
    joint = ET.SubElement(robot, "joint", name=name, type=kind)
    ET.SubElement(joint, "parent", link=parent)
    ET.SubElement(joint, "child", link=child)
    ET.SubElement(joint, "origin", xyz=_vec(*xyz), rpy="0 0 0")
    if limit is not None:
        ET.SubElement(joint, "axis", xyz=axis)
        ET.SubElement(joint, "limit", **limit)
        ET.SubElement(joint, "dynamics", damping="0.01", friction="0.0")


def _check_legs(legs: object) -> int:
    """``legs`` as an int, checked to be in ``1..MAX_LEGS``."""
    if isinstance(legs, bool) or not isinstance(legs, numbers.Integral):
        raise InvalidInputError(
            f"millipede(legs=...) needs an integer number of legs >= 1, got {legs!r} "
            f"({type(legs).__name__})."
        )
    if legs < 1:
        raise InvalidInputError(f"millipede(legs=...) needs at least 1 leg, got {legs}.")
    if legs > MAX_LEGS:
        raise InvalidInputError(
            f"millipede(legs=...) builds at most {MAX_LEGS} legs (MAX_LEGS; 1000 legs take about "
            f"0.5 s and 50 MiB, and the memory grows faster than the legs), got {legs}."
        )
    return int(legs)


def millipede_urdf(
    legs: int = 100,
    *,
    spacing: float = 0.06,
    body_width: float = 0.10,
    body_height: float = 0.04,
    leg_length: float = DEFAULT_LEG_LENGTH,
    body_mass_per_pair: float = 0.15,
    thigh_mass: float = 0.03,
    shin_mass: float = 0.02,
    leg_radius: float = 0.008,
    effort: float = 2.0,
    velocity: float = 10.0,
) -> str:
    """The URDF text of a millipede with ``legs`` legs (see [`millipede`][]).

    Args:
        legs: Number of legs, an integer from 1 to `MAX_LEGS`.
        spacing: Distance along ``x`` between successive leg pairs [m].
        body_width: Width of the body along ``y`` [m]; the hips sit on its sides.
        body_height: Height of the body along ``z`` [m].
        leg_length: Length of each thigh and of each shin [m].
        body_mass_per_pair: Body mass per pair of legs [kg] (``spacing`` of body per pair).
        thigh_mass: Mass of each thigh [kg].
        shin_mass: Mass of each shin [kg].
        leg_radius: Radius of the thighs' and shins' cylinders [m].
        effort: Effort limit of every joint [N m].
        velocity: Velocity limit of every joint [rad/s].

    Raises:
        InvalidInputError: If ``legs`` is not an integer from 1 to `MAX_LEGS` or a
            dimension, mass or limit is not a finite positive number.
    """
    legs = _check_legs(legs)
    for name, value in list(locals().items())[1:]:  # the dimensions, masses and limits
        check_number(value, f"millipede({name}=...)", positive=True)
    pairs = (legs + 1) // 2
    robot = ET.Element("robot", name="millipede")
    for material, rgba in (("body", "0.45 0.3 0.15 1"), ("leg", "0.2 0.2 0.2 1")):
        ET.SubElement(ET.SubElement(robot, "material", name=material), "color", rgba=rgba)
    length, mass = pairs * spacing, pairs * body_mass_per_pair
    body = ET.SubElement(robot, "link", name="body")  # a box along x, centred on its frame
    x2, y2, z2 = length**2, body_width**2, body_height**2
    inertia = (mass * (y2 + z2) / 12.0, mass * (x2 + z2) / 12.0, mass * (x2 + y2) / 12.0)
    _add_inertial(body, mass, (0.0, 0.0, 0.0), inertia)
    box = _vec(length, body_width, body_height)
    _add_geometry(body, "body", (0.0, 0.0, 0.0), "box", collision=True, size=box)
    limit = {"effort": _vec(effort), "velocity": _vec(velocity)}
    sphere = 0.4 * FOOT_MASS * FOOT_RADIUS**2
    for i in range(1, legs + 1):  # thigh, shin and foot links, then the three joints
        side = 1.0 if i % 2 == 1 else -1.0
        mount = (0.5 * (pairs - 1) * spacing - (i - 1) // 2 * spacing, side * 0.5 * body_width, 0.0)
        thigh = (0.0, side * 0.5 * leg_length, 0.0), (0.5 * math.pi, 0.0, 0.0), 1  # along y
        shin = (0.0, 0.0, -0.5 * leg_length), (0.0, 0.0, 0.0), 2  # along z
        cylinders = ((f"thigh_{i}", thigh_mass, thigh), (f"shin_{i}", shin_mass, shin))
        for link_name, mass, (centre, rpy, axial) in cylinders:  # solid, inertia about the COM
            inertia = [mass * (3.0 * leg_radius**2 + leg_length**2) / 12.0] * 3
            inertia[axial] = 0.5 * mass * leg_radius**2
            link = ET.SubElement(robot, "link", name=link_name)
            _add_inertial(link, mass, centre, tuple(inertia))
            _add_geometry(link, "leg", centre, "cylinder", collision=False, rpy=rpy,
                          radius=_vec(leg_radius), length=_vec(leg_length))  # fmt: skip
        foot = ET.SubElement(robot, "link", name=f"foot_{i}")
        _add_inertial(foot, FOOT_MASS, (0.0, 0.0, 0.0), (sphere, sphere, sphere))
        _add_geometry(foot, "leg", (0, 0, 0), "sphere", collision=True, radius=_vec(FOOT_RADIUS))
        hip, knee = {"lower": "-1.0", "upper": "1.0"}, {"lower": "-2.0", "upper": "2.0"}
        _add_joint(robot, f"hip_{i}", "revolute", "body", f"thigh_{i}", mount,
                   {**hip, **limit}, "0 0 1")  # fmt: skip
        _add_joint(robot, f"knee_{i}", "revolute", f"thigh_{i}", f"shin_{i}",
                   (0, side * leg_length, 0), {**knee, **limit}, "1 0 0")  # fmt: skip
        _add_joint(robot, f"foot_{i}_joint", "fixed", f"shin_{i}", f"foot_{i}", (0, 0, -leg_length))
    ET.indent(robot)
    return ET.tostring(robot, encoding="unicode", xml_declaration=True) + "\n"


def millipede(
    legs: int = 100, *, floating_base: bool = True, knee_angle: float = 0.5, **dimensions: float
) -> Robot:
    """Build a millipede: ``legs`` legs along a box body, two joints per leg, point feet.

    Leg ``i`` in ``1..legs`` has joints ``hip_i`` (about ``z``) and ``knee_i`` (about ``x``),
    links ``thigh_i``, ``shin_i`` and ``foot_i`` (fixed joint ``foot_i_joint``); the action
    frame is ``body``. Odd legs are on the left (``y > 0``); legs ``2k - 1`` and ``2k`` share
    the same ``x``, pair 1 at the front (``+x``).

    Args:
        legs: Number of legs, an integer from 1 to `MAX_LEGS`.
        floating_base: Whether ``body`` is attached to the world by a free-flyer.
        knee_angle: Knee bend of the standing pose [rad]: left knees at ``+knee_angle``, right
            at ``-knee_angle``, every foot outboard of its knee.
        **dimensions: Keyword arguments of [`millipede_urdf`][].

    Returns:
        The robot ``"millipede"``, whose [`neutral`][virtual_actuators.Robot.neutral] is the
        standing pose ``"standing"``: with a floating base the body at height
        ``leg_length cos(knee_angle)`` and every foot on ``z = 0``; with a fixed base the body
        at the origin.

    Raises:
        InvalidInputError: If ``legs`` is not an integer from 1 to `MAX_LEGS` (refused before
            anything is built), ``knee_angle`` is not in ``(0, pi/2)``, ``floating_base`` is
            not a bool, or a dimension is not a finite positive number.
        TypeError: If an unknown keyword is passed in ``dimensions``.
    """
    legs = _check_legs(legs)
    floating_base = check_flag(floating_base, "floating_base")
    if not check_number(knee_angle, "knee_angle [rad]", positive=True) < 0.5 * math.pi:
        raise InvalidInputError(f"knee_angle must be a number in (0, pi/2), got {knee_angle!r}.")
    urdf = millipede_urdf(legs, **dimensions)
    leg_length = float(dimensions.get("leg_length", DEFAULT_LEG_LENGTH))

    model = pin.buildModelFromXML(urdf, *((pin.JointModelFreeFlyer(),) if floating_base else ()))
    model.name = "millipede"

    standing = pin.neutral(model)
    idx_q = list(model.idx_qs)  # one copy: indexing model.idx_qs copies the whole vector each time
    for i in range(1, legs + 1):
        side = 1.0 if i % 2 == 1 else -1.0
        standing[idx_q[model.getJointId(f"knee_{i}")]] = side * knee_angle
    if floating_base:
        standing[2] = leg_length * math.cos(knee_angle)
    model.referenceConfigurations["standing"] = standing

    return Robot(
        name="millipede",
        model=model,
        urdf_string=urdf,
        floating_base=floating_base,
        reference_configurations={"standing": standing.copy()},
        default_pose="standing",
    )
