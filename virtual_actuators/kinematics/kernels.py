"""The kinematic tree's per-tick readings: the compiled core's kernels, with numpy fallbacks.

Joint placements are ``(n, 12)`` rows: the rotation row by row (9 entries), then the translation.
"""

from __future__ import annotations

import numpy as np

from .. import core

#: Joint kinds understood by the kernels.
REVOLUTE, REVOLUTE_UNBOUNDED, PRISMATIC, FREE_FLYER, SPHERICAL = 1, 2, 3, 4, 5


def revolute_terms(rotation: np.ndarray, axis: np.ndarray) -> np.ndarray:
    """``P [axis]x`` (row by row) and ``P axis`` of a revolute joint: columns 15-26 of its row.

    Args:
        rotation: ``(3, 3)`` rotation ``P`` of the joint's placement in its parent.
        axis: ``(3,)`` unit axis.
    """
    ax, ay, az = axis
    skew = np.array(((0.0, -az, ay), (az, 0.0, -ax), (-ay, ax, 0.0)))
    return np.concatenate(((rotation @ skew).ravel(), rotation @ axis))


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

__all__ = [
    "FREE_FLYER",
    "PRISMATIC",
    "REVOLUTE",
    "REVOLUTE_UNBOUNDED",
    "SPHERICAL",
    "all_finite",
    "center_of_mass",
    "center_of_mass_of",
    "finite",
    "point_velocity",
    "revolute_terms",
    "velocity_of_point",
]
