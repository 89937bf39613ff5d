"""The floating base's attitude (yaw, pitch, roll) and planar velocity, shared by the walks."""

from __future__ import annotations

import math

import numpy as np

from ..vocabulary.scalar import asin, atan2, cos, maximum, minimum, select, sin, sqrt

_EPS = 2.220446049250313e-16  # double's machine epsilon
_TAYLOR = _EPS**0.25  # below this angle Pinocchio's exp3 takes its Taylor expansions


def rotation_vector_angles(x: object, y: object, z: object) -> tuple:
    """Yaw, pitch, roll (Z-Y-X) of the rotation vector ``(x, y, z)`` [rad], floats or traced.

    ``pinocchio.exp3``'s operations in its order, so the same bits as the angles of
    ``pin.exp3(v)`` (``R = Rz(yaw) Ry(pitch) Rx(roll)``).
    """
    t2 = x * x + y * y + z * z + _EPS * _EPS
    t = sqrt(t2)
    large = t > _TAYLOR
    cosine = cos(t)
    outer = select(large, (1 - cosine) / t2, 0.5 - t2 / 24)
    cross = select(large, sin(t) / t, 1 - t2 / 6)
    cosine = select(large, cosine, 1 - t2 / 2)
    r00 = outer * x * x + cosine
    r10 = outer * y * x + cross * z
    r20 = outer * z * x - cross * y
    r21 = outer * z * y + cross * x
    r22 = outer * z * z + cosine
    return atan2(r10, r00), asin(maximum(-1.0, minimum(1.0, -r20))), atan2(r21, r22)


def attitude_and_velocity(
    q: np.ndarray, v: np.ndarray
) -> tuple[float, float, float, float, float]:
    """Yaw, pitch, roll [rad] (Z-Y-X) and the world x, y velocity [m/s] of the free flyer."""
    x, y, z, w = q[3:7].tolist()
    u, s, t = v[:3].tolist()  # body axes [m/s]
    r00, r01, r02 = 1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)
    r10, r11, r12 = 2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)
    r20, r21, r22 = 2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)
    return (
        math.atan2(r10, r00),
        math.asin(max(-1.0, min(1.0, -r20))),
        math.atan2(r21, r22),
        r00 * u + r01 * s + r02 * t,
        r10 * u + r11 * s + r12 * t,
    )
