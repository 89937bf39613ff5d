"""Convert configurations, velocities and torques between Pinocchio and MuJoCo conventions.

Each actuated joint has one ``motor`` of gear 1 named after it: a control is the joint's effort.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from virtual_actuators.core import CORE, has
from virtual_actuators.exceptions import InvalidInputError
from virtual_actuators.kinematics.kernels import finite
from virtual_actuators.simulation.model import MujocoModel


@dataclass(frozen=True)
class Gathers:
    """Index arrays of one model's conversions, built once."""

    free: tuple  # JointMap of the free joints
    unactuated_v: np.ndarray  # Pinocchio v indices no actuator drives
    gather_v: np.ndarray  # qvel[gather_v]: v but the free joints' linear parts
    direct_ctrl: np.ndarray  # ctrl = tau[direct_ctrl] (one motor per actuated joint)
    direct_q: np.ndarray | None = None  # q = qpos[direct_q]: see _direct_q
    direct_v: np.ndarray | None = None  # v = qvel[direct_v] when no joint is free


def _direct(target: list[int], source: list[int], size: int) -> np.ndarray | None:
    """The index with ``values[index]`` equal to ``out[target] = values[source]``, or None."""
    if sorted(target) != list(range(size)):
        return None
    index = np.zeros(size, dtype=np.intp)
    index[np.array(target, dtype=np.intp)] = source
    return index


def _direct_q(mm: MujocoModel) -> np.ndarray | None:
    """``direct_q`` if every joint is a hinge, slide, ball or free joint at its parent's origin."""
    target, source = [], []
    for joint in mm.joints:
        a, i = joint.qpos_adr, joint.idx_q
        if joint.kind in ("hinge", "slide"):
            target.append(i)
            source.append(a)
        elif joint.kind == "ball" or (joint.kind == "free" and joint.placement.isIdentity()):
            w = a + (3 if joint.kind == "free" else 0)  # a free joint's position first
            target += range(i, i + joint.nq)
            source += [*range(a, w), w + 1, w + 2, w + 3, w]
        else:
            return None
    return _direct(target, source, mm.robot.model.nq)


def gathers(mm: MujocoModel) -> Gathers:
    """The `Gathers` of ``mm``, built on first use and kept with ``mm``."""
    cached = mm.__dict__.get("_gathers")
    if cached is not None:
        return cached
    all_v, all_qvel, unactuated, actuated_v, actuator = [], [], [], [], []
    for joint in mm.joints:
        all_v.extend(range(joint.idx_v, joint.idx_v + joint.nv))
        all_qvel.extend(range(joint.dof_adr, joint.dof_adr + joint.nv))
        if joint.actuator is not None:
            actuated_v.append(joint.idx_v)
            actuator.append(joint.actuator)
        else:
            unactuated.extend(range(joint.idx_v, joint.idx_v + joint.nv))
    free = tuple(j for j in mm.joints if j.kind == "free")
    gather_v = _direct(all_v, all_qvel, mm.robot.model.nv)  # the joints cover v: never None
    maps = Gathers(
        free=free,
        unactuated_v=np.array(unactuated, dtype=np.intp),
        gather_v=gather_v,
        direct_ctrl=_direct(actuator, actuated_v, mm.model.nu),
        direct_q=_direct_q(mm),
        direct_v=None if free else gather_v,
    )
    mm.__dict__["_gathers"] = maps  # frozen dataclass: cache beside its fields
    return maps


def finite_vector(value: object, size: int, what: str) -> np.ndarray:
    """A finite float64 vector of ``size`` entries (a fitting array is not copied).

    ``value`` may be any array-like; ``what`` names it in the error message.

    Raises:
        InvalidInputError: If ``value`` is not ``size`` finite numbers.
    """
    if (
        isinstance(value, np.ndarray)
        and value.shape == (size,)
        and value.dtype == np.float64
        and finite(value)
    ):
        return value
    try:
        array = np.array(value, dtype=float).reshape(-1)
    except (TypeError, ValueError) as exc:
        raise InvalidInputError(f"{what} must be a vector of {size} numbers: {exc}.") from exc
    if array.shape != (size,):
        raise InvalidInputError(f"{what} must have {size} entries, got shape {np.shape(value)}.")
    if not np.all(np.isfinite(array)):
        index = int(np.argmax(~np.isfinite(array)))
        raise InvalidInputError(f"{what} holds a non-finite value at index {index}.")
    return array


def _rotation_xyzw(quat: np.ndarray) -> np.ndarray:
    """Rotation matrix of a quaternion ``(x, y, z, w)`` (normalised first)."""
    x, y, z, w = quat / np.linalg.norm(quat)
    return pin.Quaternion(w, x, y, z).toRotationMatrix()


def _quat_xyzw(rotation: np.ndarray) -> np.ndarray:
    """Unit quaternion ``(x, y, z, w)`` with ``w >= 0`` of a rotation matrix (Pinocchio's)."""
    q = np.array(pin.Quaternion(rotation).normalized().coeffs())
    return q if q[3] >= 0.0 else -q


def _free_pose(joint, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """World rotation and position of a free-flyer's body from the Pinocchio ``q``."""
    position = q[joint.idx_q : joint.idx_q + 3]
    rotation = _rotation_xyzw(q[joint.idx_q + 3 : joint.idx_q + 7])
    placement = joint.placement
    return placement.rotation @ rotation, placement.rotation @ position + placement.translation


def configuration_to_mujoco(mm: MujocoModel, q: np.ndarray) -> np.ndarray:
    """MuJoCo ``qpos`` of a Pinocchio configuration ``q`` ``(model.nq,)``.

    Raises:
        InvalidInputError: If ``q`` has the wrong size or non-finite entries.
    """
    q = finite_vector(q, mm.robot.model.nq, "q")
    qpos = np.array(mm.model.qpos0, dtype=float)
    for joint in mm.joints:
        a, i = joint.qpos_adr, joint.idx_q
        if joint.kind == "free":
            rotation, position = _free_pose(joint, q)
            identity = joint.placement.isIdentity()  # then keep the caller's quaternion exactly
            x, y, z, w = q[i + 3 : i + 7] if identity else _quat_xyzw(rotation)
            qpos[a : a + 3] = position
            qpos[a + 3 : a + 7] = (w, x, y, z)
        elif joint.kind == "ball":
            x, y, z, w = q[i : i + 4]
            qpos[a : a + 4] = (w, x, y, z)
        elif joint.kind == "continuous":
            qpos[a] = np.arctan2(q[i + 1], q[i])
        else:
            qpos[a] = q[i]
    return qpos


def configuration_from_mujoco(mm: MujocoModel, qpos: np.ndarray) -> np.ndarray:
    """Pinocchio configuration ``(model.nq,)`` of a MuJoCo ``qpos``.

    Raises:
        InvalidInputError: If ``qpos`` has the wrong size or non-finite entries.
    """
    qpos = finite_vector(qpos, mm.model.nq, "qpos")
    maps = gathers(mm)
    if maps.direct_q is not None:  # every joint's q is its qpos reordered: one gather
        return qpos[maps.direct_q]
    q = np.zeros(mm.robot.model.nq)
    for joint in mm.joints:
        a, i = joint.qpos_adr, joint.idx_q
        if joint.kind == "free":
            w, x, y, z = qpos[a + 3 : a + 7]
            position = qpos[a : a + 3]
            if joint.placement.isIdentity():
                q[i : i + 3] = position
                q[i + 3 : i + 7] = (x, y, z, w)
            else:
                rotation = _rotation_xyzw(np.array([x, y, z, w]))
                back = joint.placement.rotation.T
                q[i : i + 3] = back @ (position - joint.placement.translation)
                q[i + 3 : i + 7] = _quat_xyzw(back @ rotation)
        elif joint.kind == "ball":
            w, x, y, z = qpos[a : a + 4]
            q[i : i + 4] = (x, y, z, w)
        elif joint.kind == "continuous":
            angle = float(qpos[a])
            q[i : i + 2] = (math.cos(angle), math.sin(angle))
        else:
            q[i] = qpos[a]
    return q


def velocity_to_mujoco(mm: MujocoModel, q: np.ndarray, v: np.ndarray) -> np.ndarray:
    """MuJoCo ``qvel`` of a Pinocchio velocity ``v`` at configuration ``q``.

    Raises:
        InvalidInputError: If ``q`` or ``v`` has the wrong size or non-finite entries.
    """
    q = finite_vector(q, mm.robot.model.nq, "q")
    v = finite_vector(v, mm.robot.model.nv, "v")
    qvel = np.zeros(mm.model.nv)
    for joint in mm.joints:
        d, i = joint.dof_adr, joint.idx_v
        if joint.kind == "free":
            rotation, _ = _free_pose(joint, q)
            qvel[d : d + 3] = rotation @ v[i : i + 3]
            qvel[d + 3 : d + 6] = v[i + 3 : i + 6]
        else:
            qvel[d : d + joint.nv] = v[i : i + joint.nv]
    return qvel


def velocity_from_mujoco(mm: MujocoModel, qpos: np.ndarray, qvel: np.ndarray) -> np.ndarray:
    """Pinocchio velocity ``(model.nv,)`` of a MuJoCo ``qvel`` at positions ``qpos``.

    A free-flyer's velocities are in its body frame.

    Raises:
        InvalidInputError: If ``qpos`` or ``qvel`` has the wrong size or non-finite entries.
    """
    qpos = finite_vector(qpos, mm.model.nq, "qpos")
    return state_velocity(mm, qpos, finite_vector(qvel, mm.model.nv, "qvel"))


def state_velocity(mm: MujocoModel, qpos: np.ndarray, qvel: np.ndarray) -> np.ndarray:
    """`velocity_from_mujoco` of MuJoCo's own state, unchecked (MuJoCo keeps it finite)."""
    if (maps := gathers(mm)).direct_v is not None:  # no free joint: one gather
        return qvel[maps.direct_v]
    v = qvel[maps.gather_v]  # the free joints' angular velocities included
    for joint in maps.free:
        d, i, a = joint.dof_adr, joint.idx_v, joint.qpos_adr
        v[i : i + 3] = _rotate_back(qpos[a + 3 : a + 7].tolist(), qvel[d : d + 3].tolist())
    return v


def _rotate_back(quat_wxyz: list[float], vector: list[float]) -> tuple[float, float, float]:
    """``R^T vector`` for a MuJoCo quaternion ``(w, x, y, z)`` (normalised), on floats."""
    w, x, y, z = quat_wxyz
    scale = 1.0 / math.sqrt(w * w + x * x + y * y + z * z)
    w, x, y, z = w * scale, x * scale, y * scale, z * scale
    a, b, c = vector
    return (
        (1.0 - 2.0 * (y * y + z * z)) * a + 2.0 * (x * y + w * z) * b + 2.0 * (x * z - w * y) * c,
        2.0 * (x * y - w * z) * a + (1.0 - 2.0 * (x * x + z * z)) * b + 2.0 * (y * z + w * x) * c,
        2.0 * (x * z + w * y) * a + 2.0 * (y * z - w * x) * b + (1.0 - 2.0 * (x * x + y * y)) * c,
    )


#: Largest effort [N m or N] tolerated on an unactuated degree of freedom.
UNACTUATED_TOLERANCE = 1e-9


def ctrl_writer(mm: MujocoModel, ctrl: np.ndarray) -> Callable[[np.ndarray, bool], bool] | None:
    """A per-tick writer of efforts into ``ctrl`` (MuJoCo's ``data.ctrl``); None without the core.

    ``write(tau, ignore_unactuated)`` writes what `torques_to_ctrl` returns and returns True, or
    writes nothing and returns False (`torques_to_ctrl` then says why): one compiled call.
    """
    maps = gathers(mm)
    if not has("efforts_to_ctrl"):
        return None
    kernel, direct, unactuated = CORE.efforts_to_ctrl, maps.direct_ctrl, maps.unactuated_v
    none = unactuated[:0]
    shape = (mm.robot.model.nv,)

    def write(tau: np.ndarray, ignore_unactuated: bool) -> bool:
        if tau.__class__ is not np.ndarray or tau.shape != shape:
            return False
        checked = none if ignore_unactuated else unactuated
        return kernel(tau, direct, checked, UNACTUATED_TOLERANCE, ctrl) == 0

    return write


def torques_to_ctrl(
    mm: MujocoModel, tau: np.ndarray, *, ignore_unactuated: bool = False
) -> np.ndarray:
    """The actuators' controls ``(mj_model.nu,)`` for joint efforts ``tau`` (not clipped).

    Args:
        mm: The MuJoCo model and its maps.
        tau: Joint efforts [N m or N], shape ``(model.nv,)``, Pinocchio velocity order.
        ignore_unactuated: Drop efforts on unactuated degrees of freedom instead of raising.

    Raises:
        InvalidInputError: If ``tau`` has the wrong size or non-finite entries, or (unless
            ``ignore_unactuated``) asks for more than 1e-9 on a degree of freedom that no
            actuator drives (the message names the joint).
    """
    tau = finite_vector(tau, mm.robot.model.nv, "tau")
    maps = gathers(mm)
    ctrl = tau[maps.direct_ctrl]
    if ignore_unactuated or np.all(np.abs(tau[maps.unactuated_v]) <= UNACTUATED_TOLERANCE):
        return ctrl
    for joint in mm.joints:
        effort = tau[joint.idx_v : joint.idx_v + joint.nv]
        if joint.actuator is None and np.any(np.abs(effort) > UNACTUATED_TOLERANCE):
            raise InvalidInputError(
                f"tau asks for {effort.tolist()} on joint {joint.name!r}, which no actuator "
                f"drives (actuated joints: {', '.join(mm.actuated) or 'none'}); pass "
                "ignore_unactuated=True to drop it."
            )
    return ctrl
