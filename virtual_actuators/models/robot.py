"""The [`Robot`][] container: a Pinocchio model with its name, description and poses."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pinocchio as pin

from ..exceptions import (
    FrameNotFoundError,
    InvalidInputError,
    JointNotFoundError,
    RobotDescriptionError,
    suggestion,
)
from ..vocabulary.arguments import as_float_array, check_number


@dataclass(repr=False)
class Robot:
    """A robot loaded from a URDF: Pinocchio model and data plus where it came from.

    Attributes:
        name: Short name (the URDF stem, or the name given to a generated robot).
        model: Pinocchio model (kinematics and inertias).
        data: Pinocchio data of ``model``, created on first access (it holds ``nv^3`` tensors);
            the library's computations never use it.
        urdf_path: Path of the URDF file, or None for a robot built from a string.
        urdf_string: The URDF text (viewers and simulators use the same source).
        package_dirs: Folders that ``package://`` mesh URIs are resolved against.
        floating_base: Whether the root is a free-flyer joint (7 entries of ``q``, 6 of ``v``).
        reference_configurations: Named poses of size ``model.nq`` (the SRDF's
            ``group_state`` entries, or the robot's own).
        default_pose: Key of ``reference_configurations`` that [`neutral`][] returns, or None.
        passive_joints: Joints no actuator drives (the SRDF's ``passive_joint`` entries).
        caches: What the library computes once per robot and keeps; not compared, not shown.
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
    caches: dict[str, object] = field(default_factory=dict, init=False, repr=False, compare=False)

    def neutral(self) -> np.ndarray:
        """A copy of the standing / home pose if the robot has one, else Pinocchio's neutral."""
        if self.default_pose is not None:
            return self.reference_configurations[self.default_pose].copy()
        return pin.neutral(self.model)

    @property
    def mass(self) -> float:
        """Total mass of the robot [kg], the floating base's included."""
        return float(sum(inertia.mass for inertia in self.model.inertias))

    def center_of_mass(self, q: object) -> np.ndarray:
        """Centre of mass ``(3,)`` of the whole robot at ``q``, world frame [m].

        Computed on a data of its own (`data` is untouched); in a control tick,
        ``Snapshot.center_of_mass()`` gives the same point from the tick's kinematics.

        Raises:
            InvalidInputError: ``q`` is not ``model.nq`` finite numbers, or the robot has no
                mass.
        """
        model = self.model
        configuration = as_float_array(q, "center_of_mass: q", f"{model.nq} numbers")
        if configuration.shape != (model.nq,) or not np.isfinite(configuration).all():
            raise InvalidInputError(
                f"center_of_mass: q must be {model.nq} finite numbers (model.nq) for robot "
                f"{self.name!r}, got shape {configuration.shape}."
            )
        data = self.caches.get("center_of_mass_data")
        if data is None:  # the mass checked once: summing it costs ~13 us, gaits call this per tick
            if not self.mass > 0.0:
                raise InvalidInputError(f"Robot {self.name!r} has no mass: no centre of mass.")
            data = self.caches["center_of_mass_data"] = pin.Data(model)
        return np.array(pin.centerOfMass(model, data, configuration, False), dtype=float)

    def q(self, base: object = None, **joint_values: float) -> np.ndarray:
        """A configuration from joint names: ``robot.q(knee_1=0.5, hip2_1=-0.2)``.

        Joints not named keep their value in [`neutral`][].

        Args:
            base: Floating base pose ``x y z qx qy qz qw`` (a unit quaternion), or None to keep
                the neutral pose's.
            **joint_values: Angle [rad] or position [m] per one-degree-of-freedom joint (a
                continuous joint takes its angle).

        Raises:
            JointNotFoundError: An unknown joint name (with close matches), or a joint with
                more than one degree of freedom (the free-flyer: use ``base``).
            InvalidInputError: A value that is not a finite real number, or a bad ``base``.
        """
        model = self.model
        q = self.neutral()
        if base is not None:
            if not self.floating_base:
                raise InvalidInputError(
                    f"Robot {self.name!r} has a fixed base: base= does not apply."
                )
            pose = as_float_array(base, "base", "7 numbers x y z qx qy qz qw")
            if pose.shape != (7,) or not np.all(np.isfinite(pose)):
                raise InvalidInputError(f"base must be 7 finite numbers, got {base!r}.")
            norm = float(np.linalg.norm(pose[3:]))
            if abs(norm - 1.0) > 1e-6:
                raise InvalidInputError(
                    f"base: the quaternion (qx, qy, qz, qw) must have unit norm, got {norm:.6g}."
                )
            q[:7] = pose
        names = list(model.names)
        for name, value in joint_values.items():
            if name not in names[1:]:
                raise JointNotFoundError(
                    f"Robot {self.name!r} has no joint {name!r}. "
                    f"{suggestion(name, names[1:], 'joints')}"
                )
            joint = model.joints[names.index(name)]
            angle = check_number(value, f"q(): {name}")
            if joint.nq == 1:
                q[joint.idx_q] = angle
            elif joint.nq == 2 and joint.nv == 1:  # continuous: (cos, sin)
                q[joint.idx_q : joint.idx_q + 2] = (np.cos(angle), np.sin(angle))
            else:
                raise JointNotFoundError(
                    f"Joint {name!r} has {joint.nv} degrees of freedom: set it through q "
                    "directly (or base= for the free-flyer)."
                )
        return q

    @property
    def frame_names(self) -> list[str]:
        """Names of all frames of the model (links, joints, fixed frames)."""
        return [frame.name for frame in self.model.frames]

    @property
    def joint_names(self) -> list[str]:
        """Names of the joints with degrees of freedom (the free-flyer's included)."""
        return list(self.model.names)[1:]

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


def frame_id(robot: Robot, frame: str) -> int:
    """The id of frame ``frame`` of ``robot``.

    Raises:
        FrameNotFoundError: If the robot has no such frame (with the closest names).
    """
    if not isinstance(frame, str) or not robot.model.existFrame(frame):
        raise FrameNotFoundError(
            f"Robot {robot.name!r} has no frame {frame!r}. "
            f"{suggestion(str(frame), robot.frame_names, 'frames')}"
        )
    return int(robot.model.getFrameId(frame))


def read_geometry(robot: Robot, visual: bool = False) -> pin.GeometryModel:
    """The robot's collision (or visual) geometry read by Pinocchio, cached on the robot.

    Raises:
        RobotDescriptionError: If Pinocchio cannot read it (a missing mesh, say).
    """
    what = "visual" if visual else "collision"
    geometry = robot.caches.get(f"{what}_geometry")
    if geometry is None:
        kind = pin.GeometryType.VISUAL if visual else pin.GeometryType.COLLISION
        model, dirs = robot.model, {"package_dirs": list(robot.package_dirs)}
        try:
            if robot.urdf_path is not None:
                geometry = pin.buildGeomFromUrdf(model, str(robot.urdf_path), kind, **dirs)
            elif robot.urdf_string is not None:
                geometry = pin.buildGeomFromUrdfString(model, robot.urdf_string, kind, **dirs)
            else:
                geometry = pin.GeometryModel()
        except Exception as exc:
            raise RobotDescriptionError(
                f"Pinocchio cannot read the {what} geometry of robot {robot.name!r}: {exc}"
            ) from exc
        robot.caches[f"{what}_geometry"] = geometry
    return geometry
