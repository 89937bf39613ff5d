// The hexapod's tripod update: the C++ port, operation by operation, of
// virtual_actuators.gaits.hexapod.kernel.tripod_setpoints (with its _strides and gaits.planar's
// smoothstep and lift_profile from scalar.hpp), so that both agree bit for bit
// (tests/test_core_parity_hexapod.py). An edit of the reference kernel goes with the same edit
// here.
#pragma once

#include <cmath>
#include <cstdint>

#include "gait.hpp"
#include "linalg.hpp"

namespace va {

// gaits.hexapod.kernel._strides.
inline double strides(double x, double y, double length, double width) {
  return std::sqrt((x / length) * (x / length) + (y / width) * (y / width));
}

// gaits.hexapod.kernel.tripod_setpoints: frames (nf, 12), frame_rows (7), rows (6), nominal
// (6, 3), motion (10), shape (11); swing (3, 9) and state (5) updated.
inline void tripod_setpoints(const double* frames, const std::int64_t* frame_rows,
                             const std::int64_t* rows, const double* nominal, const double* motion,
                             const double* shape, double* swing, double* state) {
  constexpr double gravity = 9.81;  // gaits.hexapod.body.GRAVITY
  const double height = motion[0], fx = motion[1], fy = motion[2], cx = motion[3], cy = motion[4],
               ax = motion[5], ay = motion[6], yaw_rate = motion[7], elapsed = motion[8],
               dt = motion[9];
  const double velocity_filter = shape[0], foot_radius = shape[1], nominal_height = shape[2];
  const double length = shape[3], width = shape[4], max_stance = shape[5], lift = shape[6],
               peak = shape[7];
  const double depth = shape[8], gain = shape[9], double_time = shape[10];
  const double* body = frames + 12 * frame_rows[0];
  double feet[18];  // the feet relative to the body, body axes: (foot - body) @ rotation
  for (int i = 0; i < 6; ++i) {
    const double* foot = frames + 12 * frame_rows[1 + i];
    const double dx = foot[9] - body[9];
    const double dy = foot[10] - body[10];
    const double dz = foot[11] - body[11];
    for (int j = 0; j < 3; ++j)
      feet[3 * i + j] = dx * body[j] + dy * body[3 + j] + dz * body[6 + j];
  }
  const std::int64_t s1 = rows[0], s2 = rows[1], s3 = rows[2];
  const double x1 = feet[3 * s1], y1 = feet[3 * s1 + 1], z1 = feet[3 * s1 + 2];
  const double ux = feet[3 * s2] - x1, uy = feet[3 * s2 + 1] - y1, uz = feet[3 * s2 + 2] - z1;
  const double vx = feet[3 * s3] - x1, vy = feet[3 * s3 + 1] - y1, vz = feet[3 * s3 + 2] - z1;
  const double nx = uy * vz - uz * vy, ny = uz * vx - ux * vz, nz = ux * vy - uy * vx;
  if (std::abs(nz) > 1e-9) {
    const double a = -nx / nz, b = -ny / nz;
    state[0] = a;
    state[1] = b;
    state[2] = z1 - a * x1 - b * y1;
  }
  const double a = state[0], b = state[1], c = state[2];
  state[4] = height + c - foot_radius;
  double lag = 0.0;
  bool found = false;
  for (int j = 0; j < 3; ++j) {
    const std::int64_t r = rows[j];
    const double sx = fx - yaw_rate * nominal[3 * r + 1];
    const double sy = fy + yaw_rate * nominal[3 * r];
    const double speed = std::sqrt(sx * sx + sy * sy);
    if (speed > 1e-3) {
      const double ex = sx / speed, ey = sy / speed;
      const double ox = feet[3 * r] - nominal[3 * r], oy = feet[3 * r + 1] - nominal[3 * r + 1];
      const double value = -(ox * ex + oy * ey) * strides(ex, ey, length, width);
      if (!found || value > lag) lag = value;
      found = true;
    }
  }
  double progress = 0.5 + lag;
  const double by_time = elapsed / max_stance;
  if (by_time > progress) progress = by_time;
  if (1.0 < progress) progress = 1.0;
  if (progress > state[3]) state[3] = progress;
  const double phase = state[3];
  const double reach = smoothstep(py_min(1.0, 1.25 * phase));
  const double rest = 1.0 - smoothstep(phase);
  const double up = lift * lift_profile(phase, peak) - depth * phase;
  double rate = 0.0;
  for (int j = 3; j < 6; ++j) {
    const std::int64_t r = rows[j];
    const double value =
        strides(fx - yaw_rate * nominal[3 * r + 1], fy + yaw_rate * nominal[3 * r], length, width);
    if (j == 3 || value > rate) rate = value;
  }
  const double stance = rate * max_stance <= 1.0 ? max_stance : 1.0 / rate;
  const double lean = nominal_height / gravity;
  const double offset_x = gain * (fx - cx) - lean * ax;
  const double offset_y = gain * (fy - cy) - lean * ay;
  const double lead = 0.5 * stance + double_time;
  const double blend = dt > 0.0 ? py_min(1.0, dt / velocity_filter) : 0.0;
  for (int k = 0; k < 3; ++k) {
    const std::int64_t r = rows[3 + k];
    const double ox = lead * (fx - yaw_rate * nominal[3 * r + 1]) + offset_x;
    const double oy = lead * (fy + yaw_rate * nominal[3 * r]) + offset_y;
    const double factor = py_min(1.0, 0.6 / py_max(strides(ox, oy, length, width), 1e-9));
    const double land_x = nominal[3 * r] + ox * factor, land_y = nominal[3 * r + 1] + oy * factor;
    double* foot = swing + 9 * k;
    const double start_x = foot[0], start_y = foot[1], start_z = foot[2];
    const double x = start_x + (land_x - start_x) * reach;
    const double y = start_y + (land_y - start_y) * reach;
    const double above = start_z - (a * start_x + b * start_y + c);
    const double target[3] = {x, y, a * x + b * y + c + rest * above + up};
    for (int i = 0; i < 3; ++i) {
      if (dt > 0.0) foot[6 + i] += blend * ((target[i] - foot[3 + i]) / dt - foot[6 + i]);
      foot[3 + i] = target[i];
    }
  }
}

}  // namespace va
