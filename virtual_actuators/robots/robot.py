"""The :class:`Robot` container: a Pinocchio model with its name, description and poses."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pinocchio as pin


@dataclass(repr=False)
class Robot:
    """A robot loaded from a URDF: Pinocchio model and data plus where it came from.

    Attributes:
        name: Short name (the URDF stem, or the name given to a generated robot).
        model: Pinocchio model (kinematics and inertias).
        data: Pinocchio data matching ``model``, created on first access (a ``pinocchio.Data``
            holds ``nv^3`` tensors: 14 GB at ``nv = 1206``); the library's computations never
            use it.
        urdf_path: Path of the URDF file, or None for a robot built from a string.
        urdf_string: The URDF text (kept so that viewers and simulators use the same source).
        package_dirs: Folders that ``package://`` mesh URIs are resolved against.
        floating_base: Whether the root is a free-flyer joint (7 entries of ``q``, 6 of ``v``).
        reference_configurations: Named poses (from the SRDF's ``group_state`` entries or the
            robot's own description), each of size ``model.nq``.
        default_pose: Key of ``reference_configurations`` that :meth:`neutral` returns, or None.
        passive_joints: Names of the joints that no actuator drives (the SRDF's
            ``passive_joint`` entries, e.g. the boom of a planar biped); empty by default.

    """

    name: str
    model: pin.Model
    data: pin.Data | None = None
    urdf_path: Path | None = None
    urdf_string: str | None = None
    package_dirs: list[str] = field(default_factory=list)
    floating_base: bool = False
    reference_configurations: dict[str, np.ndarray] = field(default_factory=dict)
    default_pose: str | None = None
    passive_joints: tuple[str, ...] = ()

    def neutral(self) -> np.ndarray:
        """Return a standing / home configuration if the robot has one, else Pinocchio's neutral.

        Returns:
            A copy of the configuration, shape ``(model.nq,)``.

        """
        if self.default_pose is not None:
            return self.reference_configurations[self.default_pose].copy()
        return pin.neutral(self.model)

    @property
    def frame_names(self) -> list[str]:
        """Names of all frames of the model (links, joints, fixed frames)."""
        return [frame.name for frame in self.model.frames]

    @property
    def joint_names(self) -> list[str]:
        """Names of the joints with degrees of freedom (the free-flyer ``root_joint`` included)."""
        return [name for name in list(self.model.names)[1:]]

    def __repr__(self) -> str:
        base = "floating" if self.floating_base else "fixed"
        return (
            f"Robot(name={self.name!r}, nq={self.model.nq}, nv={self.model.nv}, "
            f"{base} base, {len(self.model.frames)} frames)"
        )


def _get_data(self: Robot) -> pin.Data:
    data = self.__dict__.get("_data")
    if data is None:
        data = self.__dict__["_data"] = pin.Data(self.model)
    return data


def _set_data(self: Robot, value: pin.Data | None) -> None:
    self.__dict__["_data"] = value


# ``data`` is created lazily: the dataclass's __init__ assigns through this property
Robot.data = property(_get_data, _set_data, doc="Pinocchio data of ``model`` (created lazily).")
