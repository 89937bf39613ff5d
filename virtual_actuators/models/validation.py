"""Check a URDF's XML before Pinocchio reads it, with messages that say what is wrong.

The optional ``yourdfpy`` (the ``urdf`` extra) validates as well when installed; it never
loads meshes. Pinocchio's own parser remains the final check.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from collections import Counter
from pathlib import Path

from virtual_actuators.exceptions import RobotDescriptionError, suggestion
from virtual_actuators.models.physics_checks import INERTIA_KEYS, parse_floats

__all__ = ["listed", "parse_xml", "validate_urdf"]

_JOINT_TYPES = ("revolute", "continuous", "prismatic", "fixed", "floating", "planar")
_MAX_PROBLEMS = 10


def parse_xml(path: Path, text: str) -> ET.Element:
    """Parse the URDF text and check that its root is a ``<robot>``.

    Raises:
        RobotDescriptionError: If the text is not well-formed XML (the message gives the line
            and column) or its root element is not ``<robot>``.
    """
    try:
        root = ET.fromstring(text)
    except ET.ParseError as exc:
        line, column = exc.position
        reason = str(exc).split(":")[0]
        raise RobotDescriptionError(
            f"{path} is not well-formed XML: {reason} at line {line}, column {column + 1}."
        ) from exc
    if root.tag != "robot":
        raise RobotDescriptionError(
            f"{path} is not a URDF: its root element is <{root.tag}>, not <robot>."
        )
    return root


def listed(problems: list[str]) -> str:
    """The first problems as an indented list, with how many more were left out."""
    shown = problems[:_MAX_PROBLEMS]
    more = len(problems) - len(shown)
    tail = f"\n  ... and {more} more" if more else ""
    return "".join(f"\n  - {problem}" for problem in shown) + tail


def validate_urdf(path: Path, text: str) -> ET.Element:
    """Check a URDF thoroughly and return its root element.

    Raises:
        RobotDescriptionError: If the file is not well-formed XML or not a valid URDF; the message
            names the file and lists what is wrong.
    """
    root = parse_xml(path, text)
    problems = _element_problems(root)
    if not problems:
        problems = _number_problems(root) or _tree_problems(root)
    if not problems:
        problems = _yourdfpy_problems(path)
    if problems:
        raise RobotDescriptionError(f"{path} is not a valid URDF:{listed(problems)}")
    return root


def _element_problems(root: ET.Element) -> list[str]:
    """Problems that would make yourdfpy fail with an unhelpful error (missing names, tags)."""
    problems = []
    if any(element.tag.startswith("{http://wiki.ros.org/xacro}") for element in root.iter()):
        problems.append("it contains xacro elements: expand it with xacro first")
    if not root.get("name"):
        problems.append("the <robot> element has no 'name' attribute")
    links = root.findall("link")
    if not links:
        problems.append("it declares no <link>")
    for number, link in enumerate(links, start=1):
        if not link.get("name"):
            problems.append(f"link number {number} has no 'name' attribute")
            continue
        for kind in ("visual", "collision"):
            for element in link.findall(kind):
                geometry = element.find("geometry")
                shapes = [] if geometry is None else list(geometry)
                if len(shapes) != 1:
                    problems.append(
                        f"a <{kind}> of link {link.get('name')!r} needs a <geometry> with exactly "
                        "one <box>, <cylinder>, <sphere> or <mesh>"
                    )
    for number, joint in enumerate(root.findall("joint"), start=1):
        name = joint.get("name")
        label = f"joint {name!r}" if name else f"joint number {number}"
        if not name:
            problems.append(f"{label} has no 'name' attribute")
        if joint.get("type") not in _JOINT_TYPES:
            problems.append(
                f"{label} has type {joint.get('type')!r}; valid types: {', '.join(_JOINT_TYPES)}"
            )
        for tag in ("parent", "child"):
            element = joint.find(tag)
            if element is None or not element.get("link"):
                problems.append(f'{label} has no <{tag} link="..."/>')
    return problems


#: Numeric attributes of URDF elements (path from a link or joint, attribute, how many numbers).
_NUMBERS = {
    "joint": [
        ("origin", "xyz", 3), ("origin", "rpy", 3), ("axis", "xyz", 3),
        ("limit", "lower", 1), ("limit", "upper", 1), ("limit", "effort", 1),
        ("limit", "velocity", 1), ("dynamics", "damping", 1), ("dynamics", "friction", 1),
    ],
    "link": [
        ("inertial/origin", "xyz", 3), ("inertial/origin", "rpy", 3),
        ("inertial/mass", "value", 1),
        *[("inertial/inertia", key, 1) for key in INERTIA_KEYS],
        *[(f"{kind}/origin", key, 3) for kind in ("visual", "collision") for key in ("xyz", "rpy")],
        *[(f"{kind}/geometry/box", "size", 3) for kind in ("visual", "collision")],
        *[(f"{kind}/geometry/sphere", "radius", 1) for kind in ("visual", "collision")],
        *[(f"{kind}/geometry/cylinder", key, 1) for kind in ("visual", "collision")
          for key in ("radius", "length")],
    ],
}  # fmt: skip


def _number_problems(root: ET.Element) -> list[str]:
    """Attributes that must hold numbers but do not (``xyz="0 one 0"``)."""
    problems = []
    for tag, entries in _NUMBERS.items():
        for element in root.findall(tag):
            label = f"{tag} {element.get('name')!r}"
            for path, attribute, count in entries:
                for child in element.findall(path):
                    text = child.get(attribute)
                    if text is None:
                        continue
                    words = text.split()
                    bad = [word for word in words if parse_floats(word, 1) is None]
                    if bad or len(words) != count:
                        what = f"{bad[0]!r} is not a number" if bad else f"needs {count} numbers"
                        problems.append(
                            f"{label} has <{path.split('/')[-1]} {attribute}={text!r}>: {what}"
                        )
    return problems


def _yourdfpy_problems(path: Path) -> list[str]:
    """What yourdfpy (optional: the ``urdf`` extra) finds wrong, reading no mesh."""
    try:
        import yourdfpy  # half a second to import (trimesh)
    except ModuleNotFoundError as error:
        if error.name is None or error.name.split(".")[0] != "yourdfpy":
            raise
        return []

    try:
        urdf = yourdfpy.URDF.load(
            str(path),
            build_scene_graph=False,
            build_collision_scene_graph=False,
            load_meshes=False,
            load_collision_meshes=False,
        )
    except Exception as exc:  # yourdfpy raises ValueError, KeyError... on malformed values
        return [f"yourdfpy cannot parse it: {type(exc).__name__}: {exc}"]

    try:
        urdf.validate()
        errors = [str(error) for error in urdf.errors]
    except Exception as exc:
        errors = [f"{type(exc).__name__}: {exc}"]
    # urdfdom (hence Pinocchio) reads a missing lower/upper bound as 0, and `_tree_problems`
    # reports the limit problems with the joint's name.
    limits = ("<limit>", "'lower'", "'upper'")
    return list(dict.fromkeys(e for e in errors if not any(word in e for word in limits)))


def _tree_problems(root: ET.Element) -> list[str]:
    """Check that links and joints form one tree and that joints have the limits they need."""
    links = [link.get("name", "") for link in root.findall("link")]
    link_set = set(links)
    problems = [
        f"link {name!r} is declared more than once"
        for name in sorted(link for link, count in Counter(links).items() if count > 1)
    ]
    parent_of: dict[str, str] = {}
    parent_link: dict[str, str] = {}
    joint_names: set[str] = set()
    for joint in root.findall("joint"):
        name, kind, limit = joint.get("name", ""), joint.get("type", ""), joint.find("limit")
        parent = joint.find("parent").get("link", "")  # type: ignore[union-attr]
        child = joint.find("child").get("link", "")  # type: ignore[union-attr]
        if name in joint_names:
            problems.append(f"joint {name!r} is declared more than once")
        joint_names.add(name)
        for role, link in (("parent", parent), ("child", child)):
            if link not in link_set:
                problems.append(
                    f"joint {name!r} names the {role} link {link!r}, which is not declared. "
                    + suggestion(link, links, "links")
                )
        if child in parent_of:
            problems.append(
                f"link {child!r} is the child of two joints ({parent_of[child]!r} and {name!r})"
            )
        parent_of.setdefault(child, name)
        parent_link[child] = parent
        if kind in ("revolute", "prismatic") and limit is None:
            problems.append(f"joint {name!r} ({kind}) has no <limit> element")
        elif limit is not None and None in (limit.get("effort"), limit.get("velocity")):
            problems.append(f"the <limit> of joint {name!r} needs 'effort' and 'velocity'")
    roots = [link for link in dict.fromkeys(links) if link not in parent_of]
    looped = []
    for link in dict.fromkeys(links):
        seen = {link}
        while link in parent_link and parent_link[link] in link_set:
            link = parent_link[link]
            if link in seen:
                looped.append(link)
                break
            seen.add(link)
    if looped:
        problems.append(
            "its joints form a loop (through links "
            + ", ".join(repr(link) for link in dict.fromkeys(looped))
            + "): a URDF must be a tree"
        )
    elif len(roots) > 1:
        problems.append(
            "its links do not form a single tree: several links have no parent joint ("
            + ", ".join(repr(link) for link in roots[:8])
            + ")"
        )
    return problems
