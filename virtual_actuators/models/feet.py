"""Which frames of a legged robot are its body and its feet.

:func:`find_feet` answers from the robot's SRDF when it names them (``<end_effector>`` entries
whose name or link says foot, sole or ankle), else from the frame names: frames called like a
foot (``foot``, ``sole``, ``toe``; the ``FOOT`` frames of solo, ANYmal's ``LF_FOOT``...), keeping
one per leg (the most distal foot-like frame of each chain from the body). The body is the link
carried by the floating base (``base_link``, ``pelvis``, ``trunk``...), or the first link of a
fixed-base robot.
"""

from __future__ import annotations

import re
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from pathlib import Path

import pinocchio as pin

from ..exceptions import FrameNotFoundError
from .robot import Robot
from .srdf import find_srdf

#: Link names taken as the body of a fixed-base (e.g. boom-mounted) robot, in this order.
BODY_NAMES = ("body", "base_link", "base", "pelvis", "trunk", "torso")

#: Words that make a frame (or an SRDF end effector) a foot, as whole words of its name.
FOOT_WORDS = ("foot", "feet", "sole", "toe", "ankle")

__all__ = ["BODY_NAMES", "FOOT_WORDS", "Feet", "body_frame", "find_feet"]


@dataclass(frozen=True)
class Feet:
    """A legged robot's body frame and foot frames.

    Attributes:
        body: The frame carried by the floating base (the action frame of a body actuator).
        feet: One frame per leg, in the model's order.
        source: ``"srdf"`` or ``"names"``: where the feet were found.

    """

    body: str
    feet: tuple[str, ...]
    source: str


def find_feet(robot: Robot) -> Feet:
    """The body and the feet of a legged robot (see the module docstring).

    Args:
        robot: The robot.

    Returns:
        The :class:`Feet`.

    Raises:
        FrameNotFoundError: The robot has fewer than two feet (an arm, a hand, a drone...): the
            message says what was looked for.

    """
    model = robot.model
    body = body_frame(model, bool(getattr(robot, "floating_base", False)))
    feet = _srdf_feet(robot, model)
    source = "srdf"
    if len(feet) < 2:
        feet, source = _named_feet(model), "names"
    if len(feet) < 2:
        raise FrameNotFoundError(
            f"Robot {robot.name!r} has no feet: no SRDF end effector and no frame named with "
            f"{', '.join(FOOT_WORDS)} on two or more legs (found {list(feet) or 'none'}). "
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
    path = getattr(robot, "urdf_path", None)
    srdf = find_srdf(Path(path)) if path else None
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
    """One foot-named frame per leg: on the most distal such joint of each chain, a link first.

    Several frames on one joint (a link, its joint, a sole, a heel) count as one leg: the link
    (a BODY frame) is taken before a joint or fixed frame, then the first declared.
    """
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
