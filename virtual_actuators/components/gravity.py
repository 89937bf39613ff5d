"""Gravity compensation: the joint efforts ``g(q)`` that hold (some of) the links up."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import pinocchio as pin

from ..exceptions import InvalidInputError, JointNotFoundError
from ..kinematics.snapshot import Snapshot, thread_data
from ..kinematics.tree import tree_of
from ..models.robot import Robot
from ..vocabulary.arguments import check_names, check_robot, describe
from ..vocabulary.axes import resolve_frame, resolve_joint


class GravityCompensation:
    """Joint efforts that cancel gravity on all links, or on some of them.

    Args:
        robot: The robot.
        links: Names of links or joints whose moving bodies (with the links welded to them)
            are compensated, the others keeping their weight; None for the whole robot.
        joints: The joints whose efforts it gives, zero on the others; None for all.

    Raises:
        InvalidInputError: ``robot`` is not a robot, or ``links`` or ``joints`` is not a
            collection of names.
        FrameNotFoundError: A name in ``links`` is neither a joint nor a frame of the model
            (with close matches).
        JointNotFoundError: A name in ``joints`` is not a joint of the model.

    Example:
        >>> controller.add("gravity", va.GravityCompensation(robot))  # in every tick's tau
        >>> tau = controller.compute(q, v).tau          # g(q) included, then clipped
    """

    def __init__(
        self, robot: Robot, links: Sequence[str] | None = None, joints: Sequence[str] | None = None
    ) -> None:
        check_robot(robot, "GravityCompensation")
        self.robot = robot
        model = robot.model
        self._columns = None  # every velocity entry
        if joints is not None:
            names = check_names(joints, "GravityCompensation: joints", JointNotFoundError)
            entries = [model.joints[resolve_joint(model, n)] for n in names]
            self._columns = np.array(
                [v for j in entries for v in range(j.idx_v, j.idx_v + j.nv)], dtype=np.intp
            )
        if links is None:
            self.bodies: tuple[str, ...] = tuple(model.names[1:])
            self.model = model
        else:
            names = check_names(links, "GravityCompensation: links (link or joint names)")
            joints = sorted({_body_joint(model, name) for name in names})
            self.bodies = tuple(model.names[j] for j in joints)
            self.model = model.copy()
            for j in range(model.njoints):
                if j not in joints:
                    self.model.inertias[j] = pin.Inertia.Zero()

    @property
    def columns(self) -> np.ndarray:
        """The velocity entries it gives efforts on (``joints``; every entry by default)."""
        if self._columns is None:
            return np.arange(self.robot.model.nv)
        return self._columns.copy()

    @property
    def mass(self) -> float:
        """Mass of the compensated bodies [kg]."""
        return float(sum(inertia.mass for inertia in self.model.inertias))

    def bind(self, robot: Robot) -> GravityCompensation:
        """Check that the compensation is of ``robot`` (``Controller.add``); returns ``self``.

        Raises:
            InvalidInputError: ``robot`` is another robot.
        """
        if getattr(robot, "model", None) is not self.robot.model:
            raise InvalidInputError(
                f"GravityCompensation of robot {self.robot.name!r} added to a controller of "
                f"{getattr(robot, 'name', describe(robot))!r}: make one per robot."
            )
        return self

    def reset(self, q: np.ndarray | Snapshot) -> None:
        """Nothing to reset (``Controller.reset`` calls it): the term has no state."""

    def torques(self, q: np.ndarray | Snapshot, v: np.ndarray | None = None) -> np.ndarray:
        """Efforts ``(nv,)`` that hold the selected bodies against gravity [N m or N].

        On a floating base the first six entries are the wrench the base would need.

        Args:
            q: Configuration ``(nq,)`` or the tick's [`Snapshot`][].
            v: Not used (gravity depends on ``q`` only).

        Raises:
            InvalidInputError: A bad ``q``, or a snapshot of another robot.
        """
        if isinstance(q, Snapshot):
            if q.tree.model is not self.robot.model:
                raise InvalidInputError(
                    f"GravityCompensation: the snapshot is of robot "
                    f"{getattr(q.robot, 'name', '?')!r}, not {self.robot.name!r}."
                )
            configuration = q.q
        else:
            configuration = tree_of(self.robot).check_configuration(q)
        data = thread_data(self.model)
        gravity = pin.computeGeneralizedGravity(self.model, data, configuration)
        if self._columns is None:
            return gravity.copy()
        tau = np.zeros(self.robot.model.nv)
        tau[self._columns] = gravity[self._columns]
        return tau

    def __repr__(self) -> str:
        what = "all bodies" if self.model is self.robot.model else f"bodies {list(self.bodies)}"
        return f"GravityCompensation(robot={self.robot.name!r}, {what}, {self.mass:.3f} kg)"


def _body_joint(model: pin.Model, name: str) -> int:
    """The joint whose moving body ``name`` (a joint or a link) belongs to."""
    if name in list(model.names)[1:]:
        return resolve_joint(model, name)
    return int(model.frames[resolve_frame(model, name, "link")].parentJoint)
