"""A serial actuator's virtual sensor, {B} relative to {A} in {O}: the core's kernel, or numpy."""

from __future__ import annotations

import math

import numpy as np

from .. import core


def rotation_log(rotation: np.ndarray) -> np.ndarray:
    """Rotation vector ``log(R)`` of a 3x3 rotation matrix [rad] (angle in ``[0, pi]``).

    Near ``pi`` the axis comes from the symmetric part, its sign from the skew part; near 0 a
    series keeps full precision.
    """
    cosine = min(max(0.5 * (np.trace(rotation) - 1.0), -1.0), 1.0)
    theta = math.acos(cosine)
    skew = np.array(  # vee(R - R^T) = 2 sin(theta) axis
        (rotation[2, 1] - rotation[1, 2], rotation[0, 2] - rotation[2, 0],
         rotation[1, 0] - rotation[0, 1])
    )  # fmt: skip
    if theta < 1e-4:
        return 0.5 * (1.0 + theta * theta / 6.0) * skew  # theta / (2 sin theta)
    if math.pi - theta > 1e-3:
        return 0.5 * theta / math.sin(theta) * skew
    # near pi: (R + R^T) / 2 - cos I = (1 - cos) a a^T; take the largest diagonal entry
    k = int(np.argmax(np.diag(rotation)))
    scale = 1.0 - cosine
    a_k = math.sqrt(max(rotation[k, k] - cosine, 0.0) / scale)
    axis = 0.5 * (rotation[k] + rotation[:, k]) / (scale * a_k)
    axis[k] = a_k
    return (-theta if axis @ skew < 0.0 else theta) * axis


def relative_sensor(
    jacobian_world: np.ndarray,
    frames: np.ndarray,
    v: np.ndarray,
    axis_rows: np.ndarray,
    rows: np.ndarray,
    columns: np.ndarray,
    signs: np.ndarray,
) -> np.ndarray:
    """A serial actuator's Jacobian, position and velocity of {B} relative to {A} in {O}.

    Args:
        jacobian_world: ``(6, nv)`` world joint Jacobian.
        frames: ``(nf, 12)`` frame placements (rotation row by row, translation).
        v: ``(nv,)`` velocity (empty: no velocity).
        axis_rows: ``(n,)`` rows of the selected axes among ``x y z rx ry rz``.
        rows: ``(3,)`` rows of {B}, {O} and {A} in ``frames``.
        columns: velocity indices of the chain between {A} and {B}.
        signs: their +1 / -1.

    Returns:
        One buffer: ``jacobian (n, nv)``, ``position (n,)`` (translations ``R_O^T (p_B - p_A)``,
        rotations ``R_O^T R_A log(R_A^T R_B)``) and ``velocity (n,)`` (zero without ``v``).
    """
    b, o, a = (int(row) for row in rows)
    n, nv = axis_rows.shape[0], jacobian_world.shape[1]
    rotation_b, rotation_o, rotation_a = (frames[i, :9].reshape(3, 3) for i in (b, o, a))
    x, y, z = frames[b, 9:12]
    transform = np.zeros((6, 6))
    transform[:3, :3] = transform[3:, 3:] = rotation_o.T
    # linear part at {B}'s origin: R_O^T (v - skew(p_B) w)
    transform[:3, 3:] = rotation_o.T @ np.array(((0.0, z, -y), (-z, 0.0, x), (y, -x, 0.0)))
    buffer = np.zeros(n * nv + 2 * n)
    jacobian = buffer[: n * nv].reshape(n, nv)
    jacobian[:, columns] = (transform[axis_rows] @ jacobian_world[:, columns]) * signs
    if v.shape[0]:
        buffer[n * nv + n :] = jacobian @ v
    pose = np.zeros(6)
    pose[:3] = rotation_o.T @ (frames[b, 9:12] - frames[a, 9:12])
    if axis_rows[n - 1] >= 3:  # a rotation axis: log of R_A^T R_B, expressed in {O}
        pose[3:] = rotation_o.T @ (rotation_a @ rotation_log(rotation_a.T @ rotation_b))
    buffer[n * nv : n * nv + n] = pose[axis_rows]
    return buffer


#: `relative_sensor` as the library calls it: the compiled core's when it is built.
sensor = core.kernel("relative_sensor", relative_sensor)

__all__ = ["relative_sensor", "rotation_log", "sensor"]
