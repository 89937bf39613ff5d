"""Check a URDF's XML before Pinocchio reads it, with messages that say what is wrong.

The optional ``yourdfpy`` (the ``urdf`` extra) checks as well when installed; Pinocchio's own
parser remains the final check. The checks are listed on the "Robots" reference page.
"""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET
from collections import Counter
from pathlib import Path

import numpy as np

from virtual_actuators.exceptions import RobotDescriptionError, suggestion

#: The six entries of a URDF ``<inertia>``.
INERTIA_KEYS = ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")
#: Round-off allowed on moments of inertia (URDF files print about six significant digits):
#: relative to the largest principal moment, and [kg m^2].
_INERTIA_RTOL = 1e-6
_INERTIA_ATOL = 1e-9


def _floats(text: str | None, count: int) -> list[float] | None:
    """``count`` numbers from an attribute (None when absent or malformed)."""
    try:
        values = [float(x) for x in (text or "").split()]
    except ValueError:
        return None
    return values if len(values) == count else None


def _link_problems(link: ET.Element) -> tuple[list[str], list[str]]:
    """Problems of one link's ``<inertial>``: (always fatal, fatal unless curated)."""
    fatal: list[str] = []
    lenient: list[str] = []
    inertial = link.find("inertial")
    if inertial is None:
        return fatal, lenient
    name = link.get("name")
    mass = inertial.find("mass")
    text = None if mass is None else mass.get("value")
    value = _floats(text, 1)
    if value is not None and not (math.isfinite(value[0]) and value[0] >= 0.0):
        fatal.append(
            f"link {name!r} has <mass value={text!r}/>; a mass must be a finite number >= 0 kg "
            "(0 is fine for a massless link)"
        )
    inertia = inertial.find("inertia")
    if inertia is None:
        return fatal, lenient
    texts = {key: inertia.get(key, "0") for key in INERTIA_KEYS}
    try:
        values = {key: float(text) for key, text in texts.items()}
    except ValueError:
        return fatal, lenient  # malformed numbers: yourdfpy (or Pinocchio) reports them
    bad = [f"{key}={texts[key]!r}" for key, number in values.items() if not math.isfinite(number)]
    if bad:
        fatal.append(
            f"link {name!r} has a non-finite inertia ({', '.join(bad)}); ixx, ixy, ixz, iyy, iyz "
            "and izz must be finite numbers in kg m^2"
        )
        return fatal, lenient
    xx, xy, xz, yy, yz, zz = (values[key] for key in INERTIA_KEYS)
    matrix = np.array([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]])
    eigenvalues = np.linalg.eigvalsh(matrix)
    tolerance = max(_INERTIA_ATOL, _INERTIA_RTOL * max(abs(eigenvalues[0]), abs(eigenvalues[-1])))
    negative = [f"{key}={texts[key]}" for key in ("ixx", "iyy", "izz") if values[key] < -tolerance]
    if negative:
        fatal.append(
            f"link {name!r} has a negative moment of inertia ({', '.join(negative)} kg m^2); "
            "ixx, iyy and izz must be >= 0"
        )
    elif eigenvalues[0] < -tolerance:
        shown = " ".join(f"{key}={texts[key]}" for key in INERTIA_KEYS)
        lenient.append(
            f"link {name!r} has an inertia that is not positive semi-definite ({shown}: "
            f"smallest principal moment {eigenvalues[0]:.3g} kg m^2); the products of inertia "
            "are too large for the moments: a valid inertia has principal moments >= 0"
        )
    return fatal, lenient


def _joint_problems(joint: ET.Element) -> tuple[list[str], list[str]]:
    """Problems of one joint: (always fatal, fatal unless curated)."""
    fatal: list[str] = []
    lenient: list[str] = []
    name, kind = joint.get("name"), joint.get("type")
    axis = joint.find("axis")
    if axis is not None and kind in ("revolute", "continuous", "prismatic", "planar"):
        xyz = _floats(axis.get("xyz"), 3)
        if xyz is not None and not (all(map(math.isfinite, xyz)) and any(xyz)):
            fatal.append(
                f"joint {name!r} ({kind}) has <axis xyz={axis.get('xyz')!r}/>; its axis must be "
                "a finite, nonzero vector such as '0 0 1' (only fixed joints may have a zero axis)"
            )
    limit = joint.find("limit")
    if limit is not None and kind in ("revolute", "prismatic"):
        bounds = {key: _floats(limit.get(key, "0"), 1) for key in ("lower", "upper")}
        lower, upper = bounds["lower"], bounds["upper"]
        nan = [f"{key}={limit.get(key)!r}" for key, v in bounds.items() if v and math.isnan(v[0])]
        if nan:
            fatal.append(
                f"joint {name!r} has a limit that is not a number ({', '.join(nan)}); lower and "
                "upper must be numbers with lower <= upper"
            )
        elif lower is not None and upper is not None and lower[0] > upper[0]:
            missing = [key for key in ("lower", "upper") if limit.get(key) is None]
            note = f" (a missing {' and '.join(missing)} reads as 0)" if missing else ""
            fatal.append(
                f"joint {name!r} has limits lower={lower[0]:g} > upper={upper[0]:g}{note}; the "
                "lower limit must be <= the upper one (swap them; lower == upper is fine)"
            )
    mimic = joint.find("mimic")
    if mimic is not None:
        leader = mimic.get("joint")
        lenient.append(
            f"joint {name!r} mimics joint {leader!r} (<mimic joint={leader!r}/>): mimic joints "
            "are not supported (Pinocchio would load it as an independent joint); remove the "
            "<mimic> tag, and if the two joints must share the effort, declare the design "
            f"constraint EqualTorque({name!r}, {leader!r}) on the actuator"
        )
    return fatal, lenient


def physics_problems(root: ET.Element, strict: bool = True) -> tuple[list[str], list[str]]:
    """What Pinocchio would load silently but no robot can be (it loads a NaN mass as 0).

    Args:
        root: The ``<robot>`` element.
        strict: False for the curated example-robot-data files: their mimic joints and
            inertias that are not positive semi-definite are then tolerated.

    Returns:
        The problems that forbid loading, and those tolerated (empty when ``strict``).
    """
    problems: list[str] = []
    tolerated: list[str] = []
    links, joints = root.findall("link"), root.findall("joint")
    for fatal, lenient in [*map(_link_problems, links), *map(_joint_problems, joints)]:
        problems += fatal
        (problems if strict else tolerated).extend(lenient)
    return problems, tolerated


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


def validate_urdf(path: Path, root: ET.Element) -> None:
    """Check a URDF thoroughly, its XML parsed by `parse_xml` into ``root``.

    Raises:
        RobotDescriptionError: If it is not a valid URDF; the message names the file and lists
            what is wrong.
    """
    problems = _element_problems(root)
    if not problems:
        problems = _number_problems(root) or _tree_problems(root)
    if not problems:
        problems = _yourdfpy_problems(path)
    if problems:
        raise RobotDescriptionError(f"{path} is not a valid URDF:{listed(problems)}")


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
                    bad = [word for word in words if _floats(word, 1) is None]
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
        # the collision scene graph and meshes are not built by default (yourdfpy >= 0.0.56)
        urdf = yourdfpy.URDF.load(str(path), build_scene_graph=False, load_meshes=False)
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
