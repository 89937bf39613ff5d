"""Read the standing poses and passive joints of a robot from its SRDF.

The SRDF of a URDF is ``STEM.srdf`` in the URDF's folder, in a ``srdf/`` folder beside it or in
the ``srdf/`` folder of its parent (the layout of example-robot-data); failing that, the SRDF in
those folders whose stem is the longest prefix of the URDF stem (``solo12`` uses ``solo.srdf``,
``talos_reduced`` uses ``talos.srdf``). Its ``group_state`` entries become
`Robot.reference_configurations`, and [`Robot.neutral`][] returns the first of
``standing``, ``half_sitting``, ``straight_standing``, ``default``, ``home``, ``neutral`` that
exists, else the first group state, else Pinocchio's neutral configuration. An SRDF that cannot be
read is ignored. Its ``passive_joint`` entries become `Robot.passive_joints` (joints that
no actuator drives, such as the boom of a planar biped).
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
    """Return the SRDF that goes with a URDF (same stem, else the longest stem prefix), or None."""
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
    """Names of the SRDF's ``<passive_joint name="..."/>`` entries that are joints of the model.

    Entries naming no joint of the model are ignored (logged at debug level), as is an SRDF that
    cannot be read. The order is the model's joint order.
    """
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
