"""Read the standing poses and passive joints of a robot from its SRDF.

Where the SRDF of a URDF is found, and which pose [`Robot.neutral`][] returns, is on the
"Robots" reference page. An SRDF that cannot be read is ignored.
"""

from __future__ import annotations

import logging
import xml.etree.ElementTree as ET
from collections.abc import Mapping
from pathlib import Path

import numpy as np
import pinocchio as pin

__all__ = [
    "DEFAULT_POSE_NAMES",
    "default_pose",
    "find_srdf",
    "passive_joints",
    "reference_configurations",
]

_logger = logging.getLogger(__name__)

#: Group states that :meth:`Robot.neutral` prefers, best first.
DEFAULT_POSE_NAMES = (
    "standing",
    "half_sitting",
    "straight_standing",
    "default",
    "home",
    "neutral",
)


def find_srdf(urdf: Path) -> Path | None:
    """The SRDF of a URDF (same stem, else the longest stem prefix), or None."""
    folders = [urdf.parent, urdf.parent / "srdf", urdf.parent.parent / "srdf"]
    folders = [folder for folder in folders if folder.is_dir()]
    for folder in folders:
        exact = folder / f"{urdf.stem}.srdf"
        if exact.is_file():
            return exact
    best: Path | None = None
    for folder in folders:
        for candidate in sorted(folder.glob("*.srdf")):
            if urdf.stem.startswith(candidate.stem) and (
                best is None or len(candidate.stem) > len(best.stem)
            ):
                best = candidate
    return best


def reference_configurations(model: pin.Model, srdf: Path | None) -> dict[str, np.ndarray]:
    """Read the SRDF's group states into the model; return them (empty if it cannot be read)."""
    if srdf is None:
        return {}
    try:
        pin.loadReferenceConfigurations(model, str(srdf), False)
        entries = [
            (entry.key(), np.array(entry.data(), dtype=float))
            for entry in model.referenceConfigurations
        ]
    except Exception as exc:  # a broken SRDF must never stop the robot from loading
        _logger.debug("Ignoring the SRDF %s: %s", srdf, exc)
        return {}
    return {key: q for key, q in entries if q.shape == (model.nq,) and np.all(np.isfinite(q))}


def passive_joints(model: pin.Model, srdf: Path | None) -> tuple[str, ...]:
    """The SRDF's ``<passive_joint name="..."/>`` entries that are joints of the model, in order."""
    if srdf is None:
        return ()
    try:
        root = ET.parse(srdf).getroot()
    except (ET.ParseError, OSError) as exc:
        _logger.debug("Ignoring the SRDF %s: %s", srdf, exc)
        return ()
    declared = {element.get("name", "") for element in root.iter("passive_joint")}
    joints = list(model.names)[1:]
    for name in sorted(declared - set(joints)):
        _logger.debug("%s: passive joint %r is not a joint of the model; ignored", srdf, name)
    return tuple(name for name in joints if name in declared)


def default_pose(configurations: Mapping[str, np.ndarray]) -> str | None:
    """Pick the pose that [`Robot.neutral`][] returns."""
    for name in DEFAULT_POSE_NAMES:
        if name in configurations:
            return name
    return next(iter(configurations), None)
