"""The tripod's per-tick update in one call: ground plane, lag, phase, landing, swing set points.

`tripod_setpoints` is what `HexapodWalker._update_tripod` does with the feet it measured: the
ground plane through the support tripod (`support_plane`), how far the support
feet lag behind their nominal places (`behind`), the swing's phase, where the
swing feet land (`landing`), their set points this tick
(`swing_targets`) and the set points' low-passed velocities; the same
arithmetic on plain loops (squares as products, ``hypot`` as the square root of the sum of
squares). The compiled core's port (``src/core/hexapod.hpp``) gives the same bits
(``tests/test_core_parity_hexapod.py``); `TRIPOD_SETPOINTS` is the one the walker calls.
"""

from __future__ import annotations

import math

import numpy as np

from ...core import CORE
from ..planar import lift_profile, smoothstep
from .body import GRAVITY

#: ``shape``'s entries (:func:`tripod_setpoints`), in order
SHAPE = (
    "velocity_filter",
    "foot_radius",
    "height",
    "step_length",
    "step_width",
    "max_stance_time",
    "lift",
    "lift_peak",
    "touchdown_depth",
    "placement_gain",
    "double_support_time",
)


def _strides(x: float, y: float, length: float, width: float) -> float:
    """`strides` (the ellipse of axes ``length`` and ``width`` is 1)."""
    return math.sqrt((x / length) * (x / length) + (y / width) * (y / width))


def _advance_support(
    frames: np.ndarray,
    frame_rows: np.ndarray,
    rows: np.ndarray,
    nominal: np.ndarray,
    motion: np.ndarray,
    shape: np.ndarray,
    state: np.ndarray,
) -> None:
    """`tripod_setpoints`' first half: the support tripod's ground plane, height and phase.

    Writes ``state`` (`tripod_setpoints`' arguments, the same meanings).
    """
    height, fx, fy, yaw_rate, elapsed = motion[0], motion[1], motion[2], motion[7], motion[8]
    foot_radius, length, width, max_stance = shape[1], shape[3], shape[4], shape[5]
    # the feet relative to the body, body axes: (foot - body) @ rotation
    body = frame_rows[0]
    feet = np.empty((6, 3))
    for i in range(6):
        foot = frame_rows[1 + i]
        dx = frames[foot, 9] - frames[body, 9]
        dy = frames[foot, 10] - frames[body, 10]
        dz = frames[foot, 11] - frames[body, 11]
        for j in range(3):
            feet[i, j] = dx * frames[body, j] + dy * frames[body, 3 + j] + dz * frames[body, 6 + j]
    # the ground plane through the support tripod (footholds.support_plane)
    s1, s2, s3 = rows[0], rows[1], rows[2]
    x1, y1, z1 = feet[s1, 0], feet[s1, 1], feet[s1, 2]
    ux, uy, uz = feet[s2, 0] - x1, feet[s2, 1] - y1, feet[s2, 2] - z1
    vx, vy, vz = feet[s3, 0] - x1, feet[s3, 1] - y1, feet[s3, 2] - z1
    nx, ny, nz = uy * vz - uz * vy, uz * vx - ux * vz, ux * vy - uy * vx
    if abs(nz) > 1e-9:
        a, b = -nx / nz, -ny / nz
        state[0], state[1], state[2] = a, b, z1 - a * x1 - b * y1
    state[4] = height + state[2] - foot_radius
    # how far the support feet lag behind their nominal places (footholds.behind)
    lag = 0.0
    found = False
    for j in range(3):
        r = rows[j]
        sx = fx - yaw_rate * nominal[r, 1]  # the nominal place's velocity over the ground
        sy = fy + yaw_rate * nominal[r, 0]
        speed = math.sqrt(sx * sx + sy * sy)
        if speed > 1e-3:
            ex, ey = sx / speed, sy / speed
            ox, oy = feet[r, 0] - nominal[r, 0], feet[r, 1] - nominal[r, 1]
            value = -(ox * ex + oy * ey) * _strides(ex, ey, length, width)
            if not found or value > lag:
                lag = value
            found = True
    progress = 0.5 + lag
    by_time = elapsed / max_stance
    if by_time > progress:
        progress = by_time
    if 1.0 < progress:
        progress = 1.0
    if progress > state[3]:
        state[3] = progress


def tripod_setpoints(
    frames: np.ndarray,
    frame_rows: np.ndarray,
    rows: np.ndarray,
    nominal: np.ndarray,
    motion: np.ndarray,
    shape: np.ndarray,
    swing: np.ndarray,
    state: np.ndarray,
) -> None:
    """The support tripod's ground plane and lag, the swing feet's set points (body axes).

    Args:
        frames: ``(nf, 12)`` the snapshot's frame table (rotation row-major, then position).
        frame_rows: ``(7,)`` its rows of the body and of the feet 1 to 6.
        rows: ``(6,)`` the support tripod's feet (0 to 5) then the swing tripod's.
        nominal: ``(6, 3)`` the feet's nominal places relative to the body [m].
        motion: ``(10,)`` the body's height [m], its low-passed velocity ``(vx, vy)``, the
            velocity set point and its acceleration (heading frame) [m/s, m/s^2], the yaw
            rate command [rad/s], the time in the stance and since the last set points [s].
        shape: ``(11,)`` the constants `SHAPE` names [s, m, m, m, m, s, m, -, m, s, s].
        swing: ``(3, 9)`` per swing foot: lift-off point, last set point, its velocity (the
            last two updated) [m, m/s].
        state: ``(5,)`` the ground plane ``z = a x + b y + c`` (kept when the support feet are
            in a line), the swing's phase (never decreasing) and the ground height under the
            body [m], updated.

    """
    height, fx, fy, cx, cy, ax, ay, yaw_rate, elapsed, dt = motion
    velocity_filter, nominal_height = shape[0], shape[2]
    length, width, max_stance, lift, peak = shape[3], shape[4], shape[5], shape[6], shape[7]
    depth, gain, double_time = shape[8], shape[9], shape[10]
    _advance_support(frames, frame_rows, rows, nominal, motion, shape, state)
    a, b, c = state[0], state[1], state[2]
    phase = state[3]
    reach = smoothstep(min(1.0, 1.25 * phase))
    rest = 1.0 - smoothstep(phase)  # of the lift-off height above the plane
    up = lift * lift_profile(phase, peak) - depth * phase
    # where the swing feet land (footholds.landing)
    rate = 0.0
    for j in range(3, 6):
        r = rows[j]
        value = _strides(fx - yaw_rate * nominal[r, 1], fy + yaw_rate * nominal[r, 0], length,
                         width)  # fmt: skip
        if j == 3 or value > rate:
            rate = value
    stance = max_stance if rate * max_stance <= 1.0 else 1.0 / rate
    lean = nominal_height / GRAVITY  # the centre of pressure trails by lean * acceleration
    offset_x = gain * (fx - cx) - lean * ax
    offset_y = gain * (fy - cy) - lean * ay
    lead = 0.5 * stance + double_time
    blend = min(1.0, dt / velocity_filter) if dt > 0.0 else 0.0
    for k in range(3):
        r = rows[3 + k]
        ox = lead * (fx - yaw_rate * nominal[r, 1]) + offset_x
        oy = lead * (fy + yaw_rate * nominal[r, 0]) + offset_y
        factor = min(1.0, 0.6 / max(_strides(ox, oy, length, width), 1e-9))
        land_x, land_y = nominal[r, 0] + ox * factor, nominal[r, 1] + oy * factor
        # this tick's set point (footholds.swing_targets) and its low-passed velocity
        start_x, start_y, start_z = swing[k, 0], swing[k, 1], swing[k, 2]
        x = start_x + (land_x - start_x) * reach
        y = start_y + (land_y - start_y) * reach
        above = start_z - (a * start_x + b * start_y + c)  # lift-off height above the plane
        target = (x, y, a * x + b * y + c + rest * above + up)
        for i in range(3):
            if dt > 0.0:
                swing[k, 6 + i] += blend * ((target[i] - swing[k, 3 + i]) / dt - swing[k, 6 + i])
            swing[k, 3 + i] = target[i]


#: :func:`tripod_setpoints` as the walker calls it: the compiled core's port when it is built.
TRIPOD_SETPOINTS = CORE.tripod_setpoints if CORE is not None else tripod_setpoints

__all__ = ["SHAPE", "TRIPOD_SETPOINTS", "tripod_setpoints"]
