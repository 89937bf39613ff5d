"""The bodies, joints and actuators of the MuJoCo model, one body per Pinocchio joint."""

from __future__ import annotations

import math
import warnings
from collections.abc import Iterable

import mujoco
import numpy as np
import pinocchio as pin

from virtual_actuators.exceptions import (
    InvalidInputError,
    JointNotFoundError,
    RobotDescriptionError,
    suggestion,
)
from virtual_actuators.models.robot import Robot
from virtual_actuators.simulation.geoms import quat_wxyz

#: Lower bounds that let massless moving bodies compile [kg] and [kg m^2]; real links are far
#: heavier, so these change nothing for them.
BOUND_MASS = 1e-6
BOUND_INERTIA = 1e-10


def joint_kind(model: pin.Model, j: int) -> str:
    """Classify Pinocchio joint ``j`` as free, ball, hinge, continuous or slide.

    Raises:
        RobotDescriptionError: For a joint type MuJoCo has no single joint for.
    """
    joint = model.joints[j]
    short = joint.shortname()
    if short == "JointModelFreeFlyer":
        if model.parents[j] != 0:
            raise RobotDescriptionError(
                f"Joint {model.names[j]!r} is a free-flyer that is not the root joint; MuJoCo "
                "only allows free joints on bodies attached to the world."
            )
        return "free"
    if short == "JointModelSpherical":
        return "ball"
    if joint.nv == 1 and joint.nq in (1, 2) and "Mimic" not in short:
        axis_lin, axis_ang = _motion_axis(model, j)
        if np.linalg.norm(axis_lin) < 1e-12 and abs(np.linalg.norm(axis_ang) - 1.0) < 1e-9:
            return "continuous" if joint.nq == 2 else "hinge"
        if np.linalg.norm(axis_ang) < 1e-12 and abs(np.linalg.norm(axis_lin) - 1.0) < 1e-9:
            if joint.nq == 1:
                return "slide"
    raise RobotDescriptionError(
        f"Joint {model.names[j]!r} has type {short.removeprefix('JointModel')}, which cannot be "
        "simulated: supported joints are revolute (any axis, bounded or continuous), prismatic "
        "(any axis), spherical and a free-flyer root."
    )


def _motion_axis(model: pin.Model, j: int) -> tuple[np.ndarray, np.ndarray]:
    """Linear and angular parts of the motion subspace of 1-DoF joint ``j`` (joint frame)."""
    joint = model.joints[j]
    jdata = joint.createData()
    joint.calc(jdata, pin.neutral(model))
    s = np.asarray(jdata.S, dtype=float).reshape(6)
    return s[:3], s[3:]


def actuated_joints(robot: Robot, kinds: list[str], actuated: Iterable[str] | None) -> list[str]:
    """Names of the actuated joints in Pinocchio order (see [`build_mujoco_model`][])."""
    model = robot.model
    names = list(model.names)[1:]
    one_dof = {n for n, kind in zip(names, kinds, strict=True) if kind not in ("free", "ball")}
    if actuated is None:
        passive = set(robot.passive_joints)
        return [name for name in names if name in one_dof and name not in passive]
    requested = [actuated] if isinstance(actuated, str) else list(actuated)
    for name in requested:
        if name not in names:
            raise JointNotFoundError(
                f"Cannot actuate {name!r}: robot {robot.name!r} has no such joint. "
                + suggestion(str(name), names, "joints")
            )
        if name not in one_dof:
            raise InvalidInputError(
                f"Cannot actuate joint {name!r}: a motor drives one degree of freedom and this "
                f"joint has {model.joints[model.getJointId(name)].nv}."
            )
    return [name for name in names if name in set(requested)]


def add_actuators(spec: mujoco.MjSpec, model: pin.Model, actuated_names: list[str]) -> None:
    """Add one ``motor`` (gear 1, range ``+-effortLimit`` if finite and positive) per joint."""
    for name in actuated_names:
        effort = float(model.effortLimit[model.joints[model.getJointId(name)].idx_v])
        actuator = spec.add_actuator(name=name, target=name, trntype=mujoco.mjtTrn.mjTRN_JOINT)
        if math.isfinite(effort) and effort > 0.0:  # limited by autolimits
            actuator.ctrlrange = [-effort, effort]


def _body_names(robot: Robot) -> list[str]:
    """A unique MuJoCo body name per Pinocchio joint: its child link, else the joint name."""
    model = robot.model
    links: dict[int, str] = {}  # each joint's first child link
    for frame in model.frames:
        if frame.type == pin.FrameType.BODY:
            links.setdefault(frame.parentJoint, frame.name)
    names, used = ["world"], {"world"}
    for j in range(1, model.njoints):
        link = links.get(j, model.names[j])
        name = link if link not in used else model.names[j]
        while name in used:
            name += "_"
        used.add(name)
        names.append(name)
    return names


def add_bodies(spec: mujoco.MjSpec, robot: Robot, kinds: list[str]) -> list[mujoco.MjsBody]:
    """Add one body (with its joint and inertia) per Pinocchio joint; index 0 is the world."""
    model = robot.model
    bodies: list[mujoco.MjsBody] = [spec.worldbody]
    names = _body_names(robot)
    for j in range(1, model.njoints):
        kind = kinds[j - 1]
        joint = model.joints[j]
        placement = model.jointPlacements[j]
        body = bodies[model.parents[j]].add_body(
            name=names[j],
            pos=np.array(placement.translation, dtype=float),
            quat=quat_wxyz(placement.rotation),
        )
        inertia = model.inertias[j]
        body.explicitinertial = True
        body.mass = float(inertia.mass)
        body.ipos = np.array(inertia.lever, dtype=float)
        matrix = np.asarray(inertia.inertia, dtype=float)
        moments, axes = np.linalg.eigh((matrix + matrix.T) / 2.0)  # principal moments and axes
        if np.linalg.det(axes) < 0.0:  # a rotation
            axes[:, 2] = -axes[:, 2]
        body.inertia = np.maximum(moments, 0.0)  # a negative moment clamped to 0
        body.iquat = quat_wxyz(axes)
        bodies.append(body)
        name = model.names[j]
        if kind == "free":
            body.add_freejoint(name=name)
            continue
        mj_joint = body.add_joint(name=name)
        v = joint.idx_v
        _set_damping(mj_joint, float(model.damping[v]))
        mj_joint.frictionloss = float(model.friction[v])
        mj_joint.armature = float(model.armature[v])
        if kind == "ball":
            mj_joint.type = mujoco.mjtJoint.mjJNT_BALL
        else:
            linear, angular = _motion_axis(model, j)
            if kind == "slide":
                mj_joint.type, axis = mujoco.mjtJoint.mjJNT_SLIDE, linear
            else:
                mj_joint.type, axis = mujoco.mjtJoint.mjJNT_HINGE, angular
            mj_joint.axis = axis
            lower = float(model.lowerPositionLimit[joint.idx_q])
            upper = float(model.upperPositionLimit[joint.idx_q])
            if kind != "continuous" and -math.inf < lower < upper < math.inf:
                mj_joint.range = [lower, upper]  # limited by autolimits
    return bodies


def _set_damping(joint: mujoco.MjsJoint, damping: float) -> None:
    """Set a joint's linear damping [N m s/rad or N s/m] (MuJoCo 3 scalar, MuJoCo 4 array)."""
    current = joint.damping
    if np.ndim(current) == 0:
        joint.damping = damping
    else:
        values = np.zeros(np.shape(current))
        values[0] = damping
        joint.damping = values


def balance_inertias(spec: mujoco.MjSpec, robot: Robot) -> None:
    """Let MuJoCo repair physically impossible inertias, with a warning naming them."""
    model = robot.model
    bad = []
    for j in range(1, model.njoints):
        if model.inertias[j].mass <= 0.0:
            continue
        moments = np.sort(np.linalg.eigvalsh(np.asarray(model.inertias[j].inertia)))
        scale = max(float(moments[2]), 1e-300)
        if moments[0] < -1e-12 * scale or moments[0] + moments[1] < moments[2] - 1e-9 * scale:
            bad.append(model.names[j])
    if bad:
        spec.compiler.balanceinertia = True
        warnings.warn(
            f"Robot {robot.name!r}: the inertia of the bodies of joints {', '.join(bad)} is not "
            "physically possible (a negative principal moment, or the triangle inequality "
            "broken); MuJoCo uses a repaired one, so the simulation differs from the Pinocchio "
            "model there.",
            stacklevel=3,
        )
