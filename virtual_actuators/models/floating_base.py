"""Guess whether a URDF describes a robot with a floating base or one welded to the world.

``floating_base=None`` in :func:`~virtual_actuators.models.loader.load_robot` guesses from the
description. The base floats (a free-flyer root joint) when a link or joint name, the robot's name
or the file stem contains a leg word (foot, feet, sole, toe, ankle, leg, knee, hip, thigh, shin,
shank, calf) or a flying word (flying, quadrotor, quadcopter, multirotor, hexarotor, hexacopter,
octocopter, drone, uav, rotor, propeller), and is fixed otherwise (arms, hands, grippers,
pendulums, wheeled bases). Names are split into words at ``_``, digits and camel-case humps, so
``base_footprint`` or ``allegro`` do not count. A URDF whose root link is ``world`` is always
fixed. Pass ``floating_base`` explicitly to override the guess.
"""

from __future__ import annotations

import re
import xml.etree.ElementTree as ET

__all__ = ["guess_floating_base"]

_LEG_WORDS = frozenset(
    "foot feet sole soles toe toes ankle ankles leg legs knee knees hip hips thigh thighs "
    "shin shins shank shanks calf calves".split()
)
_FLYING_WORDS = frozenset(
    "flying quadrotor quadcopter multirotor hexarotor hexacopter octocopter drone uav "
    "rotor rotors propeller propellers".split()
)
_WORD = re.compile(r"[A-Z]+(?=[A-Z][a-z])|[A-Z]?[a-z]+|[A-Z]+")


def guess_floating_base(root: ET.Element, stem: str = "") -> bool:
    """Guess whether a URDF describes a legged or flying robot (see the module documentation).

    Args:
        root: The ``<robot>`` element of the URDF.
        stem: The URDF file stem, whose words count as well.

    Returns:
        True for a floating base, False for a fixed one.

    """
    links = [link.get("name", "") for link in root.iter("link")]
    joints = root.findall("joint")
    children = {child.get("link") for joint in joints for child in joint.iter("child")}
    roots = [link for link in links if link not in children]
    if roots == ["world"]:
        return False
    names = [*links, *(joint.get("name", "") for joint in joints), root.get("name", ""), stem]
    words = {word.lower() for name in names for word in _WORD.findall(name)}
    return bool(words & (_LEG_WORDS | _FLYING_WORDS))
