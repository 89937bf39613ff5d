"""Joint effort limits: finding the implausible ones a URDF declares, and setting them.

Controllers clip to the URDF's effort limits, the contact QP bounds its torques by them and the
simulator's motors saturate at them, so a limit a robot cannot have (solo12's URDF declares
1000 N m on every joint of a 2.5 kg robot) silently turns all three off.
[`implausible_effort_limits`][] reports the limits above [`effort_bound`][]: ten times the
torque that holds the robot's whole weight at arm's length, its extent from the base at its
standing pose (a generous bound: real motors rarely reach a tenth of it).
[`set_effort_limits`][] writes new limits into the model, which every controller, actuator and
simulator built afterwards reads.
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
    """The largest plausible joint effort of ``robot`` [N m]: see the module docstring.

    Returns:
        ``EFFORT_MARGIN * mass * 9.81 * extent`` (extent: the farthest frame origin from the
        root at [`Robot.neutral`][], at least 0.1 m).
    """
    model = robot.model
    data = model.createData()
    pin.framesForwardKinematics(model, data, robot.neutral())
    root = data.oMi[1].translation if robot.floating_base else np.zeros(3)
    extent = max(float(np.linalg.norm(frame.translation - root)) for frame in data.oMf)
    return EFFORT_MARGIN * robot.mass * 9.81 * max(extent, 0.1)


def implausible_effort_limits(robot: Robot) -> dict[str, float]:
    """The driven one-degree-of-freedom joints whose effort limit exceeds [`effort_bound`][].

    Prismatic joints are held to ``EFFORT_MARGIN`` times the weight [N]; passive joints are
    not checked.

    Returns:
        ``{joint: declared limit}`` in the model's order (empty when all are plausible).
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
        limits: One limit [N m or N] for every one-degree-of-freedom joint, or
            ``{joint: limit}`` (a limit > 0; ``inf`` for none).

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
        value = check_number(limit, what, positive=True, allow_inf=True)
        model.effortLimit[joint.idx_v] = value
