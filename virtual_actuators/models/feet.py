"""Which frames of a legged robot are its body and its feet."""

from __future__ import annotations

import re
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from pathlib import Path

import pinocchio as pin

from ..exceptions import FrameNotFoundError
from .loader import find_srdf
from .robot import Robot

#: Link names taken as the body of a fixed-base (e.g. boom-mounted) robot, in this order.
BODY_NAMES = ("body", "base_link", "base", "pelvis", "trunk", "torso")

#: Words that make a frame (or an SRDF end effector) a foot, as whole words of its name.
FOOT_WORDS = ("foot", "feet", "sole", "toe", "ankle")

#: A distal link is a foot when it lies this close to the lowest one, as a fraction of the
#: lowest one's depth below the body at the standing pose (arms hang higher than the feet).
FOOT_DEPTH_FRACTION = 0.25


@dataclass(frozen=True)
class Feet:
    """A legged robot's body frame and foot frames.

    Attributes:
        body: The frame carried by the floating base (the action frame of a body actuator).
        feet: One frame per leg, in the model's order.
        source: ``"srdf"``, ``"names"`` or ``"structure"``: where the feet were found.
    """

    body: str
    feet: tuple[str, ...]
    source: str


def find_feet(robot: Robot) -> Feet:
    """The body and the feet of a legged robot.

    The feet come from the SRDF's foot-like ``<end_effector>`` entries, else from the frame
    names (one per leg, the most distal), else from the structure ([`structural_feet`][]). The
    body is the link the floating base carries, or the first link of a fixed-base robot.

    Raises:
        FrameNotFoundError: The robot has fewer than two feet (an arm, a hand, a drone...): the
            message says what was looked for.
    """
    model = robot.model
    body = body_frame(model, robot.floating_base)
    feet = _srdf_feet(robot, model)
    source = "srdf"
    if len(feet) < 2:
        feet, source = _named_feet(model), "names"
    if len(feet) < 2 and robot.floating_base:
        feet, source = structural_feet(robot), "structure"
    if len(feet) < 2:
        raise FrameNotFoundError(
            f"Robot {robot.name!r} has no feet: no SRDF end effector, no frame named with "
            f"{', '.join(FOOT_WORDS)} on two or more legs and no two legs ending in collision "
            f"geometry at the bottom (found {list(feet) or 'none'}). "
            "Name the feet yourself (the stand demo takes --feet FRAME,FRAME,...)."
        )
    return Feet(body, tuple(feet), source)


def _is_foot(name: str) -> bool:
    spaced = re.sub(r"([a-z])([A-Z])", r"\1_\2", name)  # LeftFoot -> Left_Foot
    spaced = re.sub(r"([A-Z])([A-Z][a-z])", r"\1_\2", spaced)  # RAnkle -> R_Ankle
    words = re.split(r"[^a-z]+", spaced.lower())
    return any(word in FOOT_WORDS for word in words)


def body_frame(model: pin.Model, floating: bool) -> str:
    """The link the floating base carries; else a link called like a body; else the first."""
    bodies = [f for f in model.frames if f.type == pin.FrameType.BODY and f.name != "universe"]
    if floating:
        for frame in bodies:
            if frame.parentJoint == 1:
                return frame.name
    for name in BODY_NAMES:
        if model.existFrame(name):
            return name
    return bodies[0].name if bodies else model.frames[0].name


def _srdf_feet(robot: Robot, model: pin.Model) -> list[str]:
    """Links of the SRDF's foot-like ``<end_effector>`` entries that are frames of the model."""
    srdf = find_srdf(Path(robot.urdf_path)) if robot.urdf_path else None
    if srdf is None:
        return []
    try:
        root = ET.parse(srdf).getroot()
    except (ET.ParseError, OSError):
        return []
    feet = []
    for element in root.iter("end_effector"):
        link = element.get("parent_link", "")
        if (_is_foot(element.get("name", "")) or _is_foot(link)) and model.existFrame(link):
            if link not in feet:
                feet.append(link)
    return feet


def _named_feet(model: pin.Model) -> list[str]:
    """One foot-named frame per leg: on the most distal such joint of each chain, a link first."""
    candidates = [
        (frame.name, frame.parentJoint, frame.type != pin.FrameType.BODY)
        for frame in model.frames
        if frame.name != "universe" and _is_foot(frame.name)
    ]
    joints = {joint for _, joint, _ in candidates}
    feet: dict[int, tuple[bool, str]] = {}  # leaf joint -> (not a link, frame)
    for name, joint, not_link in candidates:
        # a frame on an ancestor of another candidate's joint is not the end of its leg
        if any(other != joint and joint in model.supports[other] for other in joints):
            continue
        current = feet.get(joint)
        if current is None or (current[0] and not not_link):
            feet[joint] = (not_link, name)
    return [feet[joint][1] for joint in sorted(feet)]


def collision_links(robot: Robot) -> frozenset[str]:
    """Names of the URDF links that have ``<collision>`` geometry (empty without URDF text)."""
    if not robot.urdf_string:
        return frozenset()
    try:
        root = ET.fromstring(robot.urdf_string)
    except ET.ParseError:
        return frozenset()
    return frozenset(
        link.get("name", "") for link in root.iter("link") if link.find("collision") is not None
    )


def structural_feet(robot: Robot) -> list[str]:
    """Feet found by structure: the lowest distal links with collision geometry.

    A distal link has no other such link further down its chain. At the standing pose, the
    distal links within `FOOT_DEPTH_FRACTION` of the lowest one's depth below the body are the
    feet, in joint order (fewer than two when the structure shows no legs).
    """
    model = robot.model
    colliding = collision_links(robot)
    ids = [
        i
        for i, frame in enumerate(model.frames)
        if frame.type == pin.FrameType.BODY and frame.name in colliding and frame.parentJoint > 0
    ]
    distal = [i for i in ids if not any(j != i and _below(model, j, i) for j in ids)]
    if len(distal) < 2:
        return []
    data = model.createData()
    pin.framesForwardKinematics(model, data, robot.neutral())
    body = model.getFrameId(body_frame(model, robot.floating_base))
    heights = {i: float(data.oMf[i].translation[2] - data.oMf[body].translation[2]) for i in distal}
    lowest = min(heights.values())
    if not lowest < 0.0:
        return []
    feet: dict[int, int] = {}  # one per leg: joint -> its lowest distal link
    for i in sorted(distal, key=lambda i: heights[i]):
        if heights[i] <= lowest * (1.0 - FOOT_DEPTH_FRACTION):
            feet.setdefault(model.frames[i].parentJoint, i)
    return [model.frames[feet[joint]].name for joint in sorted(feet)]


def _below(model: pin.Model, lower: int, upper: int) -> bool:
    """Whether frame ``lower`` lies further down the chain of frame ``upper``."""
    joint_lower, joint_upper = model.frames[lower].parentJoint, model.frames[upper].parentJoint
    if joint_lower != joint_upper:
        return joint_upper in model.supports[joint_lower]
    frame = model.frames[lower].parentFrame
    while frame != 0 and model.frames[frame].parentJoint == joint_lower:
        if frame == upper:
            return True
        frame = model.frames[frame].parentFrame
    return False
