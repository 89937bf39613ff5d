"""The compiled kinematics kernel's joint tables, and its per-tick readings with numpy fallbacks.

Placements are rows of 12: the rotation row by row (9 entries), then the translation.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
import pinocchio as pin

from .. import core

#: Joint kinds understood by the kernels.
REVOLUTE, REVOLUTE_UNBOUNDED, PRISMATIC, FREE_FLYER, SPHERICAL = 1, 2, 3, 4, 5

#: Pinocchio's joint model name -> the kernel's joint kind
KINDS = {
    f"JointModel{name}": kind
    for names, kind in (
        (("RX", "RY", "RZ", "RevoluteUnaligned"), REVOLUTE),
        (("RUBX", "RUBY", "RUBZ", "RevoluteUnboundedUnaligned"), REVOLUTE_UNBOUNDED),
        (("PX", "PY", "PZ", "PrismaticUnaligned"), PRISMATIC),
        (("FreeFlyer",), FREE_FLYER),
        (("Spherical",), SPHERICAL),
    )
    for name in names
}


def skew(vector: np.ndarray) -> np.ndarray:
    """Return the ``(..., 3, 3)`` cross-product matrices of ``(..., 3)`` vectors."""
    vector = np.asarray(vector)
    out = np.zeros(vector.shape[:-1] + (3, 3))
    x, y, z = vector[..., 0], vector[..., 1], vector[..., 2]
    out[..., 0, 1], out[..., 0, 2] = -z, y
    out[..., 1, 0], out[..., 1, 2] = z, -x
    out[..., 2, 0], out[..., 2, 1] = -y, x
    return out


class JointTables(NamedTuple):
    """The joint tables of the kernel's forward kinematics.

    Attributes:
        joint_ints: ``(njoints, 3)`` parent, kind, ``idx_q``.
        joint_floats: ``(njoints, 27)`` placement in the parent, axis, and for a revolute joint
            ``P [axis]x`` (row by row) and ``P axis`` (``P`` its placement's rotation).
        velocity_joint: ``(nv,)`` joint of each velocity index.
        velocity_subspace: ``(nv, 6)`` motion subspace columns.
    """

    joint_ints: np.ndarray
    joint_floats: np.ndarray
    velocity_joint: np.ndarray
    velocity_subspace: np.ndarray


def placement_row(placement: pin.SE3) -> np.ndarray:
    """A placement as the kernels' row of 12: rotation row by row, then translation."""
    return np.concatenate((placement.rotation.ravel(), placement.translation))


def read_joints(model: pin.Model) -> tuple[JointTables, list[str], list[tuple[int, int]]]:
    """The kernel's joint tables of ``model``.

    Returns:
        ``(tables, unsupported, unit_slices)``: the `JointTables`, the names of the joints the
        kernel does not handle (kind 0), and the ``(start, stop)`` slices of ``q`` of unit norm.
    """
    joint_ints = np.zeros((model.njoints, 3), dtype=np.int64)
    joint_floats = np.zeros((model.njoints, 27))
    velocity_joint = np.zeros(model.nv, dtype=np.int64)
    subspace = np.zeros((model.nv, 6))
    unsupported: list[str] = []
    unit_slices: list[tuple[int, int]] = []
    q_zero = pin.neutral(model)
    for j in range(1, model.njoints):
        joint, placement = model.joints[j], model.jointPlacements[j]
        kind = KINDS.get(joint.shortname(), 0)
        if not kind:
            unsupported.append(model.names[j])
        joint_ints[j] = (model.parents[j], kind, joint.idx_q)
        joint_floats[j, :12] = placement_row(placement)
        velocities = slice(joint.idx_v, joint.idx_v + joint.nv)
        velocity_joint[velocities] = j
        joint_data = joint.createData()
        joint.calc(joint_data, q_zero)
        motion = np.asarray(joint_data.S).reshape(6, joint.nv)
        subspace[velocities] = motion.T
        if joint.nv == 1 and kind in (REVOLUTE, REVOLUTE_UNBOUNDED):
            axis, rotation = motion[3:, 0], placement.rotation
            joint_floats[j, 12:] = np.concatenate(
                (axis, (rotation @ skew(axis)).ravel(), rotation @ axis)
            )
        elif joint.nv == 1 and kind == PRISMATIC:
            joint_floats[j, 12:15] = motion[:3, 0]
        if kind == FREE_FLYER:
            unit_slices.append((joint.idx_q + 3, joint.idx_q + 7))
        elif kind == SPHERICAL:
            unit_slices.append((joint.idx_q, joint.idx_q + 4))
        elif joint.nq == 2 and joint.nv == 1:
            unit_slices.append((joint.idx_q, joint.idx_q + 2))
    return JointTables(joint_ints, joint_floats, velocity_joint, subspace), unsupported, unit_slices


def all_finite(values: np.ndarray) -> bool:
    """Whether every entry of a 1-D float array is finite (no NaN, no infinity)."""
    return bool(np.isfinite(values).all())


def point_velocity(
    jacobian_world: np.ndarray, v: np.ndarray, columns: np.ndarray, x: float, y: float, z: float
) -> tuple[float, float, float]:
    """Linear velocity [m/s] in world axes of the point ``(x, y, z)`` [m] fixed to a body.

    The body moves with the joints of ``columns``: the point moves at ``v + w x p``.
    """
    twist = jacobian_world[:, columns] @ v[columns]
    linear = twist[:3] + np.cross(twist[3:], (x, y, z))
    return float(linear[0]), float(linear[1]), float(linear[2])


def center_of_mass(
    joints: np.ndarray, masses: np.ndarray, levers: np.ndarray
) -> tuple[float, float, float]:
    """Centre of mass [m] in the world of the bodies carried by the joints.

    Args:
        joints: ``(njoints, 12)`` world placements of the joints.
        masses: ``(njoints,)`` mass of each joint's body [kg] (positive sum).
        levers: ``(njoints, 3)`` its centre of mass in the joint's frame [m].
    """
    rotations = joints[:, :9].reshape(-1, 3, 3)
    centres = np.einsum("jab,jb->ja", rotations, levers) + joints[:, 9:12]
    x, y, z = masses @ centres / masses.sum()
    return float(x), float(y), float(z)


#: Whether every entry of a 1-D float64 array is finite (`all_finite`).
finite = core.kernel("all_finite", all_finite)
#: `point_velocity` as the library calls it.
velocity_of_point = core.kernel("point_velocity", point_velocity)
#: `center_of_mass` as the library calls it.
center_of_mass_of = core.kernel("center_of_mass", center_of_mass)
