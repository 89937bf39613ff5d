"""Joint effort limits: finding the implausible ones a URDF declares, and setting them.

Controllers, the contact QP and the simulator's motors all use the URDF's limits, so a limit
no robot can have (solo12 declares 1000 N m on a 2.5 kg robot) silently turns them all off.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
import pinocchio as pin

from ..exceptions import JointNotFoundError, suggestion
from ..vocabulary.arguments import check_number
from .robot import Robot

#: How many times the weight-at-extent torque a limit may reach before it is implausible.
EFFORT_MARGIN = 10.0

__all__ = ["EFFORT_MARGIN", "effort_bound", "implausible_effort_limits", "set_effort_limits"]


def effort_bound(robot: Robot) -> float:
    """The largest plausible joint effort of ``robot`` [N m].

    Returns:
        ``EFFORT_MARGIN * mass * 9.81 * extent``, the extent the farthest frame origin from the
        root at [`Robot.neutral`][] (at least 0.1 m).
    """
    model = robot.model
    data = model.createData()
    pin.framesForwardKinematics(model, data, robot.neutral())
    root = data.oMi[1].translation if robot.floating_base else np.zeros(3)
    extent = max(float(np.linalg.norm(frame.translation - root)) for frame in data.oMf)
    return EFFORT_MARGIN * robot.mass * 9.81 * max(extent, 0.1)


def implausible_effort_limits(robot: Robot) -> dict[str, float]:
    """``{joint: declared limit}`` of the driven 1-DoF joints above [`effort_bound`][].

    Prismatic joints are held to ``EFFORT_MARGIN`` times the weight [N]; passive joints are
    not checked.
    """
    model = robot.model
    torque = effort_bound(robot)
    force = EFFORT_MARGIN * robot.mass * 9.81  # [N], for prismatic joints
    out = {}
    for j in range(1, model.njoints):
        joint, name = model.joints[j], model.names[j]
        if joint.nv != 1 or name in robot.passive_joints:
            continue
        bound = force if joint.shortname().startswith("JointModelP") else torque
        if float(model.effortLimit[joint.idx_v]) > bound:
            out[name] = float(model.effortLimit[joint.idx_v])
    return out


def set_effort_limits(robot: Robot, limits: float | Mapping[str, float]) -> None:
    """Write effort limits into ``robot.model`` (read by everything built afterwards).

    Args:
        robot: The robot.
        limits: One limit [N m or N] per 1-DoF joint, or ``{joint: limit}`` (``inf``: none).

    Raises:
        JointNotFoundError: An unknown joint (with close matches) or one with several degrees
            of freedom.
        InvalidInputError: A limit that is not a number > 0.
    """
    model = robot.model
    names = list(model.names)[1:]
    if not isinstance(limits, Mapping):
        value = check_number(limits, "set_effort_limits: limits", positive=True, allow_inf=True)
        limits = {names[j - 1]: value for j in range(1, model.njoints) if model.joints[j].nv == 1}
    for name, limit in limits.items():
        if name not in names:
            raise JointNotFoundError(
                f"set_effort_limits: robot {robot.name!r} has no joint {name!r}. "
                f"{suggestion(str(name), names, 'joints')}"
            )
        joint = model.joints[model.getJointId(name)]
        if joint.nv != 1:
            raise JointNotFoundError(
                f"set_effort_limits: joint {name!r} has {joint.nv} degrees of freedom."
            )
        what = f"set_effort_limits: limits[{name!r}]"
        model.effortLimit[joint.idx_v] = check_number(limit, what, positive=True, allow_inf=True)
