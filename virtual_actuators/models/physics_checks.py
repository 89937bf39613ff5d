"""Check a URDF for what Pinocchio would load silently but no robot can be.

The checks run on the XML itself, before Pinocchio reads it (it loads a NaN mass as 0); the
list is on the "Robots" reference page.
"""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET

import numpy as np

__all__ = ["INERTIA_KEYS", "parse_floats", "physics_problems"]

#: The six entries of a URDF ``<inertia>``.
INERTIA_KEYS = ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")
#: Round-off allowed on moments of inertia (URDF files print about six significant digits):
#: relative to the largest principal moment, and [kg m^2].
_INERTIA_RTOL = 1e-6
_INERTIA_ATOL = 1e-9


def parse_floats(text: str | None, count: int) -> list[float] | None:
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
    value = parse_floats(text, 1)
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
        xyz = parse_floats(axis.get("xyz"), 3)
        if xyz is not None and not (all(map(math.isfinite, xyz)) and any(xyz)):
            fatal.append(
                f"joint {name!r} ({kind}) has <axis xyz={axis.get('xyz')!r}/>; its axis must be "
                "a finite, nonzero vector such as '0 0 1' (only fixed joints may have a zero axis)"
            )
    limit = joint.find("limit")
    if limit is not None and kind in ("revolute", "prismatic"):
        bounds = {key: parse_floats(limit.get(key, "0"), 1) for key in ("lower", "upper")}
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
    """What Pinocchio would load silently but no robot can be.

    Args:
        root: The ``<robot>`` element.
        strict: False for the curated example-robot-data files: their mimic joints and
            inertias that are not positive semi-definite are then tolerated.

    Returns:
        The problems that forbid loading, and those tolerated (empty when ``strict``).
    """
    problems: list[str] = []
    tolerated: list[str] = []
    checks = [(_link_problems, link) for link in root.findall("link")]
    checks += [(_joint_problems, joint) for joint in root.findall("joint")]
    for check, element in checks:
        fatal, lenient = check(element)
        problems += fatal
        (problems if strict else tolerated).extend(lenient)
    return problems, tolerated
