"""A standing pose for a legged robot whose description gives none."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import pinocchio as pin

from ..exceptions import InvalidInputError, SingularConfigurationError
from ..vocabulary.arguments import check_number
from .feet import find_feet
from .robot import Robot, frame_id

#: Hip-to-foot height of the generated pose, as a fraction of the all-zero pose's.
HEIGHT_RATIO = 0.9

#: Initial fold of each leg joint [rad], towards the larger side of its range near zero.
_FOLD = 0.3


def standing_pose(
    robot: Robot,
    feet: Sequence[str] | None = None,
    height_ratio: float = HEIGHT_RATIO,
) -> np.ndarray:
    """A standing configuration: the SRDF's, else one built from the legs.

    Each leg is folded so that its foot keeps its horizontal place and rises by
    ``1 - height_ratio`` of the hip-to-foot distance, knees bent the way the limits allow (a leg
    of six or more joints keeps its foot's orientation); the body is level, the lowest foot
    frame at ``z = 0``, the centre of mass over the feet.

    Args:
        robot: A floating-base legged robot.
        feet: Foot frames (default: [`find_feet`][]).
        height_ratio: Hip-to-foot height as a fraction of the all-zero pose's, in (0.3, 1].

    Raises:
        InvalidInputError: A fixed-base robot, or ``height_ratio`` out of range.
        FrameNotFoundError: No feet found (or a name in ``feet`` that is not a frame).
        SingularConfigurationError: A leg that cannot reach its target (the message names it).
    """
    if not robot.floating_base:
        raise InvalidInputError(f"standing_pose: robot {robot.name!r} has a fixed base.")
    height_ratio = check_number(height_ratio, "standing_pose: height_ratio")
    if not 0.3 < height_ratio <= 1.0:
        raise InvalidInputError(
            f"standing_pose: height_ratio must be in (0.3, 1], got {height_ratio}."
        )
    if robot.default_pose is not None:
        return robot.neutral()
    model = robot.model
    if feet is None:
        feet = find_feet(robot).feet
    ids = [frame_id(robot, foot) for foot in feet]
    shift = np.zeros(2)  # of the feet, to bring the centre of mass over their middle
    for _ in range(3):
        q = pin.neutral(model)
        for foot in ids:
            _fold_leg(robot, q, foot, height_ratio, shift)
        data = model.createData()
        pin.framesForwardKinematics(model, data, q)
        middle = np.mean([data.oMf[foot].translation[:2] for foot in ids], axis=0)
        shift += robot.center_of_mass(q)[:2] - middle
    q[2] -= min(float(data.oMf[foot].translation[2]) for foot in ids)
    return q


def leg_joints(model: pin.Model, foot: int) -> list[int]:
    """The joints (one degree of freedom each) from the body down to frame ``foot``."""
    joints = [j for j in model.supports[model.frames[foot].parentJoint] if j > 1]
    return [j for j in joints if model.joints[j].nv == 1 and model.joints[j].nq == 1]


def upper_joints(robot: Robot, feet: Sequence[str]) -> list[str]:
    """The driven 1-DoF joints on no leg from the body to ``feet``, in model order."""
    model = robot.model
    legs = {j for foot in feet for j in leg_joints(model, model.getFrameId(foot))}
    return [
        model.names[j]
        for j in range(2, model.njoints)
        if j not in legs and model.joints[j].nv == 1 and model.names[j] not in robot.passive_joints
    ]


def _fold_leg(robot: Robot, q: np.ndarray, foot: int, ratio: float, shift: np.ndarray) -> None:
    """Move one leg's joints in ``q`` so its foot reaches the folded target (damped IK)."""
    model = robot.model
    name = model.frames[foot].name
    joints = leg_joints(model, foot)
    if not joints:
        raise SingularConfigurationError(f"standing_pose: foot {name!r} has no leg joints.")
    columns = [model.joints[j].idx_v for j in joints]
    rows = [model.joints[j].idx_q for j in joints]
    lower = model.lowerPositionLimit[rows]
    upper = model.upperPositionLimit[rows]
    data = model.createData()
    pin.framesForwardKinematics(model, data, q)
    start = data.oMf[foot].copy()
    hip = data.oMi[joints[0]].translation
    target = start.translation.copy()
    target[2] = hip[2] - ratio * (hip[2] - start.translation[2])
    target[:2] += shift
    orient = len(joints) >= 6
    # each joint starts at its range's middle within +-_FOLD (a symmetric range at the fold),
    # else at its bound nearest 0
    low, high = np.maximum(lower, -_FOLD), np.minimum(upper, _FOLD)
    middle = 0.5 * (low + high)
    miss = np.inf
    for fold in (0.0, _FOLD, -_FOLD):  # legs straight at zero fold one way, then the other
        folded = np.where(np.abs(middle) < 1e-9, fold, middle)
        q[rows] = np.clip(np.where(low <= high, folded, 0.0), lower, upper)
        ik = model.createData()
        for _ in range(200):  # damped least squares on the leg's joints
            pin.framesForwardKinematics(model, ik, q)
            here = ik.oMf[foot]
            rotation_error = pin.log3(start.rotation @ here.rotation.T)
            error = np.concatenate((target - here.translation, rotation_error))
            if not orient:
                error = error[:3]
            if np.linalg.norm(error) < 1e-9:
                break
            jacobian = pin.computeFrameJacobian(
                model, ik, q, foot, pin.ReferenceFrame.LOCAL_WORLD_ALIGNED
            )[: len(error), columns]
            step = jacobian.T @ np.linalg.solve(
                jacobian @ jacobian.T + 1e-6 * np.eye(len(error)), error
            )
            q[rows] = np.clip(q[rows] + np.clip(step, -0.2, 0.2), lower, upper)
        miss = float(np.linalg.norm(error[:3]))
        if miss < 1e-4 * max(1.0, abs(hip[2] - target[2])):
            return
    raise SingularConfigurationError(
        f"standing_pose: the leg of foot {name!r} cannot reach {target.round(3).tolist()} "
        f"within its joint limits (left {miss:.3g} m away)."
    )
