"""Compiled forward kinematics: joint placements, world joint Jacobian and frame placements.

One call computes, for a configuration ``q``, what a control tick reads from the kinematic tree:
every joint's placement in the world, the world joint Jacobian (the same matrix as Pinocchio's
``data.J`` after ``computeJointJacobians``: column ``v`` is the spatial velocity of joint
``v``'s motion subspace at the world origin, in world axes) and the placements of the frames the
declared actuators need. It needs no ``pinocchio.Data``, so its memory is linear in the size of
the tree, and it owns its outputs, so concurrent calls from several threads are independent.

The kernels are compiled with numba when it is installed (``@njit(cache=True)``, from
`jit`: numba is imported only when a reference kernel runs);
without numba they run as plain Python (correct, slow) and
`KinematicTree` prefers Pinocchio instead. They are
checked against Pinocchio in the tests.
They are also the reference of the compiled core's C++ ports (``src/core/kinematics.hpp``),
which the library calls when the core is built (`finite`, `velocity_of_point`,
`KinematicTree`): both agree bit for bit
(``tests/test_core_parity.py``), and an edit here goes with the same edit there.

Joint placements are stored as ``(n, 12)`` rows: the rotation matrix row by row (9 entries),
then the translation (3 entries).
"""

from __future__ import annotations

import numpy as np

from ..core import CORE
from .jit import HAVE_NUMBA, njit

#: Joint kinds understood by the kernels.
REVOLUTE, REVOLUTE_UNBOUNDED, PRISMATIC, FREE_FLYER, SPHERICAL = 1, 2, 3, 4, 5


@njit(cache=True)
def _quaternion_rotation(x: float, y: float, z: float, w: float, out: np.ndarray) -> None:
    """Write the rotation matrix of the unit quaternion ``(x, y, z, w)`` into ``out`` (3, 3)."""
    out[0, 0] = 1.0 - 2.0 * (y * y + z * z)
    out[0, 1] = 2.0 * (x * y - z * w)
    out[0, 2] = 2.0 * (x * z + y * w)
    out[1, 0] = 2.0 * (x * y + z * w)
    out[1, 1] = 1.0 - 2.0 * (x * x + z * z)
    out[1, 2] = 2.0 * (y * z - x * w)
    out[2, 0] = 2.0 * (x * z - y * w)
    out[2, 1] = 2.0 * (y * z + x * w)
    out[2, 2] = 1.0 - 2.0 * (x * x + y * y)


def revolute_terms(rotation: np.ndarray, axis: np.ndarray) -> np.ndarray:
    """``P [axis]x`` (row by row) and ``P axis`` of a revolute joint: columns 15-26 of its row.

    Args:
        rotation: ``(3, 3)`` rotation ``P`` of the joint's placement in its parent.
        axis: ``(3,)`` unit axis.

    """
    ax, ay, az = axis
    skew = np.array(((0.0, -az, ay), (az, 0.0, -ax), (-ay, ax, 0.0)))
    return np.concatenate(((rotation @ skew).ravel(), rotation @ axis))


@njit(cache=True)
def forward_kinematics(
    q: np.ndarray,
    velocity: np.ndarray,
    joint_ints: np.ndarray,
    joint_floats: np.ndarray,
    velocity_joint: np.ndarray,
    velocity_subspace: np.ndarray,
    frame_parents: np.ndarray,
    frame_floats: np.ndarray,
) -> np.ndarray:
    """Joint placements, world joint Jacobian, frame placements and velocities at ``q``, ``v``.

    Args:
        q: ``(nq,)`` configuration (quaternions and (cos, sin) pairs of unit norm).
        velocity: ``(nv,)`` velocity ``v``, or empty for no velocities.
        joint_ints: ``(njoints, 3)`` parent joint, kind (see the constants) and ``idx_q`` of each
            joint; row 0 is the universe.
        joint_floats: ``(njoints, 27)`` placement ``P`` in the parent (rotation row by row,
            translation), the joint axis of 1-dof joints, and for revolute joints ``P [axis]x``
            (row by row) and ``P axis`` (see `revolute_terms`).
        velocity_joint: ``(nv,)`` joint of each velocity index (non-decreasing: a joint's
            velocity indices follow its parent's, as in Pinocchio).
        velocity_subspace: ``(nv, 6)`` that velocity's motion subspace column in the joint's
            frame (linear, angular).
        frame_parents: ``(nf,)`` parent joint of each requested frame.
        frame_floats: ``(nf, 12)`` placement of each requested frame in its parent joint.

    Returns:
        One buffer holding, in order: ``(njoints, 12)`` world placements of the joints,
        ``(6, nv)`` world joint Jacobian (linear rows first), ``(nf, 12)`` world placements of
        the requested frames and, with a velocity, ``(nf, 3)`` the linear velocities of their
        origins in world axes (`point_velocity`'s sums, in its order, with each joint's
        twist accumulated once from its parent's). `split_kinematics` cuts it.

    """
    njoints = joint_ints.shape[0]
    nv = velocity_joint.shape[0]
    nf = frame_parents.shape[0]
    with_velocity = velocity.shape[0] > 0
    # one buffer for the four results (one array to hand back: a fourth of the call's cost)
    buffer = np.empty(njoints * 12 + 6 * nv + nf * 12 + (nf * 3 if with_velocity else 0))
    joints = buffer[: njoints * 12].reshape(njoints, 12)
    joints[0] = 0.0
    joints[0, 0] = 1.0
    joints[0, 4] = 1.0
    joints[0, 8] = 1.0
    motion = np.empty((3, 3))
    local = np.empty(12)
    for j in range(1, njoints):
        parent = joint_ints[j, 0]
        kind = joint_ints[j, 1]
        iq = joint_ints[j, 2]
        if kind == REVOLUTE or kind == REVOLUTE_UNBOUNDED:
            # P R(axis, angle) = c P + s P [axis]x + (1 - c) (P axis) axis^T, from the tables
            if kind == REVOLUTE:
                c, s = np.cos(q[iq]), np.sin(q[iq])
            else:
                c, s = q[iq], q[iq + 1]
            t = 1.0 - c
            ax, ay, az = joint_floats[j, 12], joint_floats[j, 13], joint_floats[j, 14]
            for r in range(3):
                tu = t * joint_floats[j, 24 + r]
                local[3 * r] = (
                    c * joint_floats[j, 3 * r] + s * joint_floats[j, 15 + 3 * r] + tu * ax
                )
                local[3 * r + 1] = (
                    c * joint_floats[j, 3 * r + 1] + s * joint_floats[j, 16 + 3 * r] + tu * ay
                )
                local[3 * r + 2] = (
                    c * joint_floats[j, 3 * r + 2] + s * joint_floats[j, 17 + 3 * r] + tu * az
                )
                local[9 + r] = joint_floats[j, 9 + r]
        else:
            ax, ay, az = joint_floats[j, 12], joint_floats[j, 13], joint_floats[j, 14]
            tx, ty, tz = 0.0, 0.0, 0.0
            if kind == PRISMATIC:
                motion[:, :] = 0.0
                motion[0, 0] = 1.0
                motion[1, 1] = 1.0
                motion[2, 2] = 1.0
                tx, ty, tz = ax * q[iq], ay * q[iq], az * q[iq]
            elif kind == FREE_FLYER:
                tx, ty, tz = q[iq], q[iq + 1], q[iq + 2]
                _quaternion_rotation(q[iq + 3], q[iq + 4], q[iq + 5], q[iq + 6], motion)
            else:  # SPHERICAL
                _quaternion_rotation(q[iq], q[iq + 1], q[iq + 2], q[iq + 3], motion)
            # local placement = joint placement * joint motion
            for r in range(3):
                p0 = joint_floats[j, 3 * r]
                p1 = joint_floats[j, 3 * r + 1]
                p2 = joint_floats[j, 3 * r + 2]
                for c in range(3):
                    local[3 * r + c] = p0 * motion[0, c] + p1 * motion[1, c] + p2 * motion[2, c]
                local[9 + r] = p0 * tx + p1 * ty + p2 * tz + joint_floats[j, 9 + r]
        # world placement = parent's world placement * local placement
        for r in range(3):
            p0, p1, p2 = joints[parent, 3 * r], joints[parent, 3 * r + 1], joints[parent, 3 * r + 2]
            for c in range(3):
                joints[j, 3 * r + c] = p0 * local[c] + p1 * local[3 + c] + p2 * local[6 + c]
            joints[j, 9 + r] = (
                p0 * local[9] + p1 * local[10] + p2 * local[11] + joints[parent, 9 + r]
            )
    at = njoints * 12
    jacobian = buffer[at : at + 6 * nv].reshape(6, nv)
    for v in range(nv):
        j = velocity_joint[v]
        for r in range(3):
            jacobian[r, v] = (
                joints[j, 3 * r] * velocity_subspace[v, 0]
                + joints[j, 3 * r + 1] * velocity_subspace[v, 1]
                + joints[j, 3 * r + 2] * velocity_subspace[v, 2]
            )
            jacobian[3 + r, v] = (
                joints[j, 3 * r] * velocity_subspace[v, 3]
                + joints[j, 3 * r + 1] * velocity_subspace[v, 4]
                + joints[j, 3 * r + 2] * velocity_subspace[v, 5]
            )
        px, py, pz = joints[j, 9], joints[j, 10], joints[j, 11]
        wx, wy, wz = jacobian[3, v], jacobian[4, v], jacobian[5, v]
        # velocity of the point at the world origin: v_joint + p x omega
        jacobian[0, v] += py * wz - pz * wy
        jacobian[1, v] += pz * wx - px * wz
        jacobian[2, v] += px * wy - py * wx
    at += 6 * nv
    frames = buffer[at : at + nf * 12].reshape(nf, 12)
    for f in range(nf):
        j = frame_parents[f]
        for r in range(3):
            p0, p1, p2 = joints[j, 3 * r], joints[j, 3 * r + 1], joints[j, 3 * r + 2]
            for c in range(3):
                frames[f, 3 * r + c] = (
                    p0 * frame_floats[f, c]
                    + p1 * frame_floats[f, 3 + c]
                    + p2 * frame_floats[f, 6 + c]
                )
            frames[f, 9 + r] = (
                p0 * frame_floats[f, 9]
                + p1 * frame_floats[f, 10]
                + p2 * frame_floats[f, 11]
                + joints[j, 9 + r]
            )
    if not with_velocity:
        return buffer
    twists = np.zeros((njoints, 6))  # J[:, support] v[support] of each joint, at the origin
    column = 0
    for j in range(1, njoints):
        parent = joint_ints[j, 0]
        for k in range(6):
            twists[j, k] = twists[parent, k]
        while column < nv and velocity_joint[column] == j:
            rate = velocity[column]
            for k in range(6):
                twists[j, k] += jacobian[k, column] * rate
            column += 1
    velocities = buffer[at + nf * 12 :].reshape(nf, 3)
    for f in range(nf):
        j = frame_parents[f]
        x, y, z = frames[f, 9], frames[f, 10], frames[f, 11]
        wx, wy, wz = twists[j, 3], twists[j, 4], twists[j, 5]
        velocities[f, 0] = twists[j, 0] + wy * z - wz * y
        velocities[f, 1] = twists[j, 1] + wz * x - wx * z
        velocities[f, 2] = twists[j, 2] + wx * y - wy * x
    return buffer


@njit(cache=True)
def unit_norm_error(q: np.ndarray, bounds: np.ndarray) -> float:
    """Largest ``| ||q[a:b]|| - 1 |`` over the ``(m, 2)`` slices ``bounds`` (-1: q not finite)."""
    for i in range(q.shape[0]):
        if not np.isfinite(q[i]):
            return -1.0
    worst = 0.0
    for s in range(bounds.shape[0]):
        acc = 0.0
        for i in range(bounds[s, 0], bounds[s, 1]):
            acc += q[i] * q[i]
        worst = max(worst, abs(np.sqrt(acc) - 1.0))
    return worst


@njit(cache=True)
def all_finite(values: np.ndarray) -> bool:
    """Whether every entry of a 1-D float array is finite (no NaN, no infinity).

    The per-tick checks of velocities and efforts: one compiled pass costs a quarter of
    ``np.isfinite(values).all()`` on a few entries.
    """
    for i in range(values.shape[0]):
        if not np.isfinite(values[i]):
            return False
    return True


def _numpy_finite(values: np.ndarray) -> bool:
    """`all_finite` without numba: numpy's ``isfinite``."""
    return bool(np.isfinite(values).all())


#: Whether every entry of a 1-D float64 array is finite: the compiled core's ``all_finite``
#: when it is built, else :func:`all_finite` when numba is installed, else numpy's ``isfinite``
#: (the plain-Python loop would be slower).
finite = (
    CORE.all_finite if CORE is not None else all_finite if HAVE_NUMBA else _numpy_finite
)  # fmt: skip


@njit(cache=True)
def point_velocity(
    jacobian_world: np.ndarray, v: np.ndarray, columns: np.ndarray, x: float, y: float, z: float
) -> tuple[float, float, float]:
    """Linear velocity [m/s] in world axes of the point ``(x, y, z)`` [m] fixed to a body.

    The body moves with the joints of ``columns`` (its support): the twist
    ``J[:, columns] v[columns]`` is at the world origin, so the point moves at ``v + w x p``.
    """
    vx = vy = vz = wx = wy = wz = 0.0
    for j in range(columns.shape[0]):
        c = columns[j]
        rate = v[c]
        vx += jacobian_world[0, c] * rate
        vy += jacobian_world[1, c] * rate
        vz += jacobian_world[2, c] * rate
        wx += jacobian_world[3, c] * rate
        wy += jacobian_world[4, c] * rate
        wz += jacobian_world[5, c] * rate
    return vx + wy * z - wz * y, vy + wz * x - wx * z, vz + wx * y - wy * x


@njit(cache=True)
def center_of_mass(
    joints: np.ndarray, masses: np.ndarray, levers: np.ndarray
) -> tuple[float, float, float]:
    """Centre of mass [m] in the world of the bodies carried by the joints.

    Args:
        joints: ``(njoints, 12)`` world placements of the joints (`forward_kinematics`).
        masses: ``(njoints,)`` mass of each joint's body [kg] (positive sum).
        levers: ``(njoints, 3)`` its centre of mass in the joint's frame [m].

    Returns:
        The mass-weighted mean of the bodies' centres of mass in world axes.

    """
    x = y = z = total = 0.0
    for j in range(joints.shape[0]):
        m = masses[j]
        if m == 0.0:
            continue
        cx, cy, cz = levers[j, 0], levers[j, 1], levers[j, 2]
        x += m * (joints[j, 0] * cx + joints[j, 1] * cy + joints[j, 2] * cz + joints[j, 9])
        y += m * (joints[j, 3] * cx + joints[j, 4] * cy + joints[j, 5] * cz + joints[j, 10])
        z += m * (joints[j, 6] * cx + joints[j, 7] * cy + joints[j, 8] * cz + joints[j, 11])
        total += m
    return x / total, y / total, z / total

#: :func:`point_velocity` as the library calls it: the compiled core's port when it is built.
velocity_of_point = CORE.point_velocity if CORE is not None else point_velocity
#: :func:`center_of_mass` as the library calls it: the compiled core's port when it is built.
center_of_mass_of = CORE.center_of_mass if CORE is not None else center_of_mass

__all__ = [
    "FREE_FLYER",
    "HAVE_NUMBA",
    "PRISMATIC",
    "REVOLUTE",
    "REVOLUTE_UNBOUNDED",
    "SPHERICAL",
    "all_finite",
    "center_of_mass",
    "center_of_mass_of",
    "finite",
    "forward_kinematics",
    "point_velocity",
    "revolute_terms",
    "unit_norm_error",
    "velocity_of_point",
]
