"""The joint tables of a Pinocchio model, as the compiled kinematics kernel reads them."""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
import pinocchio as pin

from . import kernels
from .kernels import FREE_FLYER, PRISMATIC, REVOLUTE, REVOLUTE_UNBOUNDED, SPHERICAL

#: Pinocchio's joint model name -> the kernel's joint kind
KINDS = {
    "JointModelRX": REVOLUTE,
    "JointModelRY": REVOLUTE,
    "JointModelRZ": REVOLUTE,
    "JointModelRevoluteUnaligned": REVOLUTE,
    "JointModelRUBX": REVOLUTE_UNBOUNDED,
    "JointModelRUBY": REVOLUTE_UNBOUNDED,
    "JointModelRUBZ": REVOLUTE_UNBOUNDED,
    "JointModelRevoluteUnboundedUnaligned": REVOLUTE_UNBOUNDED,
    "JointModelPX": PRISMATIC,
    "JointModelPY": PRISMATIC,
    "JointModelPZ": PRISMATIC,
    "JointModelPrismaticUnaligned": PRISMATIC,
    "JointModelFreeFlyer": FREE_FLYER,
    "JointModelSpherical": SPHERICAL,
}


class JointTables(NamedTuple):
    """The joint tables of `forward_kinematics`.

    Attributes:
        joint_ints: ``(njoints, 3)`` parent, kind, ``idx_q``.
        joint_floats: ``(njoints, 27)`` placement in the parent, axis and revolute terms.
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
        joint = model.joints[j]
        kind = KINDS.get(joint.shortname())
        if kind is None:
            unsupported.append(model.names[j])
            kind = 0
        joint_ints[j] = (model.parents[j], kind, joint.idx_q)
        joint_floats[j, :12] = placement_row(model.jointPlacements[j])
        velocity_joint[joint.idx_v : joint.idx_v + joint.nv] = j
        joint_data = joint.createData()
        joint.calc(joint_data, q_zero)
        motion = np.asarray(joint_data.S).reshape(6, joint.nv)
        subspace[joint.idx_v : joint.idx_v + joint.nv] = motion.T
        if joint.nv == 1 and kind in (REVOLUTE, REVOLUTE_UNBOUNDED):
            joint_floats[j, 12:15] = motion[3:, 0]
            joint_floats[j, 15:] = kernels.revolute_terms(
                model.jointPlacements[j].rotation, motion[3:, 0]
            )
        elif joint.nv == 1 and kind == PRISMATIC:
            joint_floats[j, 12:15] = motion[:3, 0]
        if kind == FREE_FLYER:
            unit_slices.append((joint.idx_q + 3, joint.idx_q + 7))
        elif joint.shortname() == "JointModelSpherical":
            unit_slices.append((joint.idx_q, joint.idx_q + 4))
        elif joint.nq == 2 and joint.nv == 1:
            unit_slices.append((joint.idx_q, joint.idx_q + 2))
    return JointTables(joint_ints, joint_floats, velocity_joint, subspace), unsupported, unit_slices


__all__ = ["KINDS", "JointTables", "placement_row", "read_joints"]
