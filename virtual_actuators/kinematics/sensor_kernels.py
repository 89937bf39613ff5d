"""Compiled virtual sensor of a serial actuator: {B} relative to {A} in {O}, in one call.

`relative_sensor` reads a snapshot's world joint Jacobian and frame table (see
`kernels`) and returns a serial actuator's Jacobian, position
and velocity; `rotation_log` is the rotation vector it uses for rotational axes. Compiled
with numba when it is installed, plain Python otherwise; checked against Pinocchio in the tests.
"""

from __future__ import annotations

import numpy as np

from .kernels import njit


@njit(cache=True)
def rotation_log(rotation: np.ndarray) -> np.ndarray:
    """Rotation vector ``log(R)`` of a 3x3 rotation matrix [rad] (angle in ``[0, pi]``).

    Near ``pi`` the axis comes from the symmetric part (the skew part vanishes there), its sign
    from the skew part; near 0 a series keeps full precision.
    """
    trace = rotation[0, 0] + rotation[1, 1] + rotation[2, 2]
    cosine = min(max(0.5 * (trace - 1.0), -1.0), 1.0)
    theta = np.arccos(cosine)
    skew = np.empty(3)  # vee(R - R^T) = 2 sin(theta) axis
    skew[0] = rotation[2, 1] - rotation[1, 2]
    skew[1] = rotation[0, 2] - rotation[2, 0]
    skew[2] = rotation[1, 0] - rotation[0, 1]
    out = np.empty(3)
    if theta < 1e-4:
        factor = 0.5 * (1.0 + theta * theta / 6.0)  # theta / (2 sin theta)
        for i in range(3):
            out[i] = factor * skew[i]
        return out
    if np.pi - theta > 1e-3:
        factor = 0.5 * theta / np.sin(theta)
        for i in range(3):
            out[i] = factor * skew[i]
        return out
    # near pi: (R + R^T) / 2 - cos I = (1 - cos) a a^T; take the largest diagonal entry
    k = 0
    for i in range(1, 3):
        if rotation[i, i] > rotation[k, k]:
            k = i
    scale = 1.0 - cosine
    a_k = np.sqrt(max(rotation[k, k] - cosine, 0.0) / scale)
    dot = 0.0
    for i in range(3):
        if i == k:
            out[i] = a_k
        else:
            out[i] = 0.5 * (rotation[k, i] + rotation[i, k]) / (scale * a_k)
        dot += out[i] * skew[i]
    sign = -1.0 if dot < 0.0 else 1.0
    for i in range(3):
        out[i] *= sign * theta
    return out


@njit(cache=True)
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
        frames: ``(nf, 12)`` frame placements.
        v: ``(nv,)`` velocity (empty: no velocity).
        axis_rows: ``(n,)`` rows of the selected axes among ``x y z rx ry rz``.
        rows: ``(3,)`` rows of {B}, {O} and {A} in ``frames``.
        columns: velocity indices of the chain between {A} and {B}.
        signs: their +1 / -1.

    Returns:
        One buffer holding ``jacobian (n, nv)``, ``position (n,)`` and ``velocity (n,)`` (zero
        without ``v``), in that order: the position's translations are ``R_O^T (p_B - p_A)``,
        its rotations ``R_O^T R_A log(R_A^T R_B)``, on the selected axes.

    """
    b, o, a = rows[0], rows[1], rows[2]
    n = axis_rows.shape[0]
    nv = jacobian_world.shape[1]
    x, y, z = frames[b, 9], frames[b, 10], frames[b, 11]
    transform = np.zeros((6, 6))
    for r in range(3):
        for c in range(3):
            value = frames[o, 3 * c + r]  # R_O^T
            transform[r, c] = value
            transform[3 + r, 3 + c] = value
    # linear part at {B}'s origin: R_O^T (v - skew(p_B) w)
    for r in range(3):
        t0, t1, t2 = transform[r, 0], transform[r, 1], transform[r, 2]
        transform[r, 3] = t2 * y - t1 * z
        transform[r, 4] = t0 * z - t2 * x
        transform[r, 5] = t1 * x - t0 * y
    # one buffer for the three results (one array to hand back: a cheaper call)
    buffer = np.zeros(n * nv + 2 * n)
    jacobian = buffer[: n * nv].reshape(n, nv)
    position = buffer[n * nv : n * nv + n]
    velocity = buffer[n * nv + n :]
    for j in range(columns.shape[0]):
        col = columns[j]
        for i in range(n):
            acc = 0.0
            for k in range(6):
                acc += transform[axis_rows[i], k] * jacobian_world[k, col]
            acc *= signs[j]
            jacobian[i, col] = acc
            if v.shape[0]:
                velocity[i] += acc * v[col]
    pose = np.zeros(6)
    for r in range(3):
        acc = 0.0
        for k in range(3):
            acc += frames[o, 3 * k + r] * (frames[b, 9 + k] - frames[a, 9 + k])
        pose[r] = acc
    if axis_rows[n - 1] >= 3:  # a rotation axis: log of R_A^T R_B, expressed in {O}
        relative = np.zeros((3, 3))
        for r in range(3):
            for c in range(3):
                acc = 0.0
                for k in range(3):
                    acc += frames[a, 3 * k + r] * frames[b, 3 * k + c]
                relative[r, c] = acc
        log_a = rotation_log(relative)  # in {A}
        for r in range(3):
            acc = 0.0
            for k in range(3):
                in_world = 0.0
                for m in range(3):
                    in_world += frames[a, 3 * k + m] * log_a[m]  # (R_A log)_k
                acc += frames[o, 3 * k + r] * in_world
            pose[3 + r] = acc
    for i in range(n):
        position[i] = pose[axis_rows[i]]
    return buffer


__all__ = ["relative_sensor", "rotation_log"]
