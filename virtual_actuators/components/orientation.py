"""How springs read an orientation: the deflection ``log(R_set R^T)`` on SO(3), in {O}'s axes.

On plain floats and on traced values (a compiled plan's ops) alike, to the same bits.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

from ..vocabulary.scalar import atan2, cos, logical_and, maximum, select, sin, sqrt
from ..vocabulary.traced import is_traced

_PI = math.pi
_TAU = math.tau


@dataclass(frozen=True)
class RotationAxes:
    """The first rotational axis's index, and each one's rotation-vector entry (0-2: rx, ry, rz)."""

    start: int
    which: tuple[int, ...]


def rotation_axes(axes: Sequence[str]) -> RotationAxes | None:
    """The rotational axes of an ordered axis tuple (None when there are none)."""
    which = tuple("xyz".index(axis[1]) for axis in axes if axis.startswith("r"))
    return RotationAxes(len(axes) - len(which), which) if which else None


def _quaternion(x: object, y: object, z: object) -> tuple:
    """``exp`` of the rotation vector ``(x, y, z)`` [rad] as a unit quaternion ``(w, v)``.

    Both branches are computed and one selected (the series near zero).
    """
    angle2 = x * x + y * y + z * z
    small = angle2 < 1e-8  # |r| < 1e-4: series of cos(a/2) and sin(a/2)/a (error < 1e-18)
    angle = sqrt(maximum(angle2, 1e-16))
    w = select(small, 1.0 - angle2 / 8.0, cos(0.5 * angle))
    s = select(small, 0.5 - angle2 / 48.0, sin(0.5 * angle) / angle)
    return w, s * x, s * y, s * z


def rotation_deflection(setpoint: Sequence, position: Sequence) -> tuple:
    """``log(R_set R^T)`` [rad] for ``R_set = exp(setpoint)`` and ``R = exp(position)``, ``(3,)``.

    The rotation from the current orientation to the set point, in the vectors' axes ({O}'s),
    of norm at most pi.
    """
    ws, xs, ys, zs = _quaternion(setpoint[0], setpoint[1], setpoint[2])
    wc, xc, yc, zc = _quaternion(position[0], position[1], position[2])
    # q_set * conj(q): (ws, vs)(wc, -vc) = (ws wc + vs.vc, wc vs - ws vc - vs x vc)
    w = ws * wc + xs * xc + ys * yc + zs * zc
    x = wc * xs - ws * xc - (ys * zc - zs * yc)
    y = wc * ys - ws * yc - (zs * xc - xs * zc)
    z = wc * zs - ws * zc - (xs * yc - ys * xc)
    sign = select(w < 0.0, -1.0, 1.0)  # q and -q are the same rotation: the angle in [0, pi]
    w, x, y, z = sign * w, sign * x, sign * y, sign * z
    norm = sqrt(x * x + y * y + z * z)  # sin(angle / 2); 0 only with x, y, z (nearly) 0
    factor = 2.0 * atan2(norm, w) / maximum(norm, 1e-300)
    return factor * x, factor * y, factor * z


def deflection(
    setpoint: list[float], position: list[float], rotations: RotationAxes | None
) -> list[float]:
    """``setpoint - position`` per axis [m, rad], the orientation deflection on rotational axes.

    ``rotations`` is the component's `rotation_axes`.
    """
    out = [x0 - x for x0, x in zip(setpoint, position, strict=True)]
    if rotations is None:
        return out
    start, which = rotations.start, rotations.which
    if len(which) == 1:  # the angle difference, wrapped (unchanged within [-pi, pi])
        angle = out[start]
        if is_traced(angle):
            inside = logical_and(-_PI <= angle, angle <= _PI)
            out[start] = select(inside, angle, angle.program.binary("remainder", angle, _TAU))
        elif not -_PI <= angle <= _PI:
            out[start] = math.remainder(angle, _TAU)
        return out
    target, current = [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]
    for i, k in enumerate(which, start):
        target[k], current[k] = setpoint[i], position[i]
    turn = rotation_deflection(target, current)
    for i, k in enumerate(which, start):
        out[i] = turn[k]
    return out
