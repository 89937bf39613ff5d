// The legged gait's per-tick kernels and the ones it reaches in the core: C++ ports, operation by
// operation, of virtual_actuators.kinematics.kernels.center_of_mass,
// actuators.producible._two_points and _give_way_one, gaits.legged.body.body_wrench and
// gaits.legged.footholds.swing_setpoints (with foothold, swing_point and gaits.planar's
// smoothstep and lift_profile, in scalar.hpp), so that both agree bit for bit
// (tests/test_core_parity_gait.py). An edit of a reference kernel goes with the same edit here.
#pragma once

#include <cmath>
#include <cstdint>

#include "linalg.hpp"
#include "scalar.hpp"

namespace va {

// kinematics.kernels.center_of_mass: joints (njoints, 12), masses (njoints), levers (njoints, 3).
inline void center_of_mass(const double* joints, const double* masses, const double* levers,
                           std::int64_t njoints, double out[3]) {
  double x = 0.0, y = 0.0, z = 0.0, total = 0.0;
  for (std::int64_t j = 0; j < njoints; ++j) {
    const double m = masses[j];
    if (m == 0.0) continue;
    const double* J = joints + 12 * j;
    const double cx = levers[3 * j], cy = levers[3 * j + 1], cz = levers[3 * j + 2];
    x += m * (J[0] * cx + J[1] * cy + J[2] * cz + J[9]);
    y += m * (J[3] * cx + J[4] * cy + J[5] * cz + J[10]);
    z += m * (J[6] * cx + J[7] * cy + J[8] * cz + J[11]);
    total += m;
  }
  out[0] = x / total;
  out[1] = y / total;
  out[2] = z / total;
}

// gaits.legged.body.body_wrench: rotation (3, 3), position (6), velocity (6), gains (11),
// setpoints (8), out (6); returns the yaw.
inline double body_wrench(const double* rotation, const double* position, const double* velocity,
                          const double* gains, const double* setpoints, double* out) {
  const double yaw = std::atan2(rotation[3], rotation[0]);
  const double pitch = std::asin(py_max(-1.0, py_min(1.0, -rotation[6])));
  const double roll = std::atan2(rotation[7], rotation[8]);
  const double c = std::cos(yaw), s = std::sin(yaw);
  const double v0 = velocity[0], v1 = velocity[1], v2 = velocity[2];
  const double w0 = velocity[3], w1 = velocity[4], w2 = velocity[5];
  const double vx = c * v0 + s * v1;
  const double vy = -s * v0 + c * v1;
  const double wx = c * w0 + s * w1;
  const double wy = -s * w0 + c * w1;
  const double height = setpoints[0], set_x = setpoints[1], set_y = setpoints[2];
  const double ax = setpoints[3], ay = setpoints[4], yaw_rate = setpoints[5];
  const double lever_x = setpoints[6], lever_y = setpoints[7];
  const double mass = gains[9], weight = gains[10];
  const double fx = gains[0] * (set_x - vx) + mass * ax;
  const double fy = gains[1] * (set_y - vy) + mass * ay;
  const double fz = weight + gains[2] * (height - position[2]) - gains[3] * v2;
  const double mx = -gains[4] * roll - gains[6] * wx;
  const double my = -gains[5] * pitch - gains[7] * wy;
  const double mz = gains[8] * (yaw_rate - w2);
  out[0] = c * fx - s * fy;
  out[1] = s * fx + c * fy;
  out[2] = fz;
  out[3] = c * mx - s * my + lever_y * weight;
  out[4] = s * mx + c * my - lever_x * weight;
  out[5] = mz;
  return yaw;
}

// gaits.legged.footholds.foothold: the foothold relative to the centre of mass, heading frame.
inline void foothold(double x, double y, double vx, double vy, double ex, double ey,
                     double yaw_rate, double stance_time, double capture_time, double reach,
                     double out[2]) {
  const double half = 0.5 * stance_time;
  const double angle = yaw_rate * half;
  const double c = std::cos(angle), s = std::sin(angle);
  const double dx = c * x - s * y - x + vx * half + capture_time * ex;
  const double dy = s * x + c * y - y + vy * half + capture_time * ey;
  const double scale = py_min(1.0, reach / py_max(std::hypot(dx, dy), 1e-12));
  out[0] = x + scale * dx;
  out[1] = y + scale * dy;
}

// gaits.legged.footholds.swing_point: start (3), the landing point, phase, lift and peak.
inline void swing_point(const double* start, double x, double y, double z, double phase,
                        double lift, double peak, double out[3]) {
  const double x0 = start[0], y0 = start[1], z0 = start[2];
  const double reach = smoothstep(py_min(1.0, 1.25 * phase));
  const double height = z0 + (z - z0) * smoothstep(phase) + lift * lift_profile(phase, peak);
  out[0] = x0 + (x - x0) * reach;
  out[1] = y0 + (y - y0) * reach;
  out[2] = height;
}

// gaits.legged.footholds.swing_setpoints: feet (k), swing (f, 9) updated, nominal (f, 2),
// body (12), motion (8), dt, shape (8), out (k, 6) written.
inline void swing_setpoints(const std::int64_t* feet, std::int64_t count, double* swing,
                            const double* nominal, const double* body, const double* motion,
                            double dt, const double* shape, double* out) {
  const double vx = motion[0], vy = motion[1], ex = motion[2], ey = motion[3];
  const double yaw_rate = motion[4], yaw = motion[5], elapsed = motion[6], ground = motion[7];
  const double swing_time = shape[0], stance_time = shape[1], capture = shape[2];
  const double reach = shape[3], lift = shape[4], peak = shape[5];
  double depth = shape[6];
  const double rate_filter = shape[7];
  const double phase = elapsed / swing_time;
  const double remaining = py_max(0.0, swing_time - elapsed);
  const double heading = yaw + yaw_rate * remaining;
  const double c = std::cos(heading), s = std::sin(heading);
  const double cy = std::cos(yaw), sy = std::sin(yaw);
  const double centre_x = body[0] + remaining * (cy * vx - sy * vy);
  const double centre_y = body[1] + remaining * (sy * vx + cy * vy);
  depth = depth * (1.0 + 4.0 * py_max(0.0, phase - 1.0));
  const double blend = dt > 0.0 ? py_min(1.0, dt / rate_filter) : 0.0;
  const double a0 = body[9], a1 = body[10], a2 = body[11];
  for (std::int64_t j = 0; j < count; ++j) {
    const std::int64_t k = feet[j];
    double* row = swing + 9 * k;
    double* o = out + 6 * j;
    double xy[2];
    foothold(nominal[2 * k], nominal[2 * k + 1], vx, vy, ex, ey, yaw_rate, stance_time, capture,
             reach, xy);
    const double x = xy[0], y = xy[1];
    double target[3];
    swing_point(row, centre_x + c * x - s * y, centre_y + s * x + c * y, ground - depth, phase,
                lift, peak, target);
    for (int i = 0; i < 3; ++i) {
      if (dt > 0.0) row[6 + i] += blend * ((target[i] - row[3 + i]) / dt - row[6 + i]);
      row[3 + i] = target[i];
      o[i] = target[i] - body[3 + i];
    }
    const double o0 = o[0], o1 = o[1], o2 = o[2];
    o[3] = row[6] - body[6] - (a1 * o2 - a2 * o1);
    o[4] = row[7] - body[7] - (a2 * o0 - a0 * o2);
    o[5] = row[8] - body[8] - (a0 * o1 - a1 * o0);
  }
}

// actuators.producible._two_points: frames (nf, 12), rows (4) all in the table; buffer (36)
// written. Returns false (nothing written) when the two contacts coincide.
inline bool two_points(const double* frames, const std::int64_t* rows, double* buffer) {
  constexpr double rank_tol = 1e-9;  // producible.RANK_TOL
  const std::int64_t b = rows[0], o = rows[1];
  double offsets[2][3];
  for (int i = 0; i < 2; ++i) {
    const std::int64_t a = rows[2 + i];
    for (int j = 0; j < 3; ++j) {
      double acc = 0.0;
      for (int k = 0; k < 3; ++k)
        acc += (frames[12 * b + 9 + k] - frames[12 * a + 9 + k]) * frames[12 * o + 3 * k + j];
      offsets[i][j] = acc;
    }
  }
  const double x = -offsets[0][0], y = -offsets[0][1], z = -offsets[0][2];
  const double dx = offsets[0][0] - offsets[1][0];
  const double dy = offsets[0][1] - offsets[1][1];
  const double dz = offsets[0][2] - offsets[1][2];
  if (dx * dx + dy * dy + dz * dz <= rank_tol * py_max(x * x + y * y + z * z, 1e-300)) return false;
  double values[6] = {y * dz - z * dy, z * dx - x * dz, x * dy - y * dx, dx, dy, dz};
  double norm = 0.0;
  for (double value : values) norm += value * value;
  const double root = std::sqrt(norm);
  for (double& value : values) value /= root;
  int k = 0;  // np.argmax(np.abs(values)): the first largest
  for (int r = 1; r < 6; ++r)
    if (std::fabs(values[r]) > std::fabs(values[k])) k = r;
  double v[6];
  for (int r = 0; r < 6; ++r) v[r] = values[r];
  v[k] += values[k] >= 0.0 ? 1.0 : -1.0;
  double vv = 0.0;
  for (int r = 0; r < 6; ++r) vv += v[r] * v[r];
  const double scale = 2.0 / vv;
  int column = 0;
  for (int c = 0; c < 6; ++c) {
    if (c == k) continue;
    for (int r = 0; r < 6; ++r)
      buffer[5 * r + column] = (r == c ? 1.0 : 0.0) - scale * (v[r] * v[c]);
    ++column;
  }
  for (int r = 0; r < 6; ++r) buffer[30 + r] = values[r];
  return true;
}

// actuators.producible._give_way_one: wrench (n), yielding (n, m), missing (n, 1), out (n).
// across is m doubles of workspace.
inline bool give_way_one(const double* wrench, const double* yielding, std::int64_t n,
                         std::int64_t m, const double* missing, double* out, double* across) {
  for (std::int64_t j = 0; j < m; ++j) across[j] = 0.0;
  double gap = 0.0;
  for (std::int64_t r = 0; r < n; ++r) {
    gap += missing[r] * wrench[r];
    for (std::int64_t j = 0; j < m; ++j) across[j] += missing[r] * yielding[m * r + j];
  }
  double norm2 = 0.0;
  for (std::int64_t j = 0; j < m; ++j) norm2 += across[j] * across[j];
  if (norm2 <= 1e-12) return false;
  const double ratio = gap / norm2;
  double rest = 0.0;
  for (std::int64_t r = 0; r < n; ++r) {
    double shift = 0.0;
    for (std::int64_t j = 0; j < m; ++j) shift += yielding[m * r + j] * (across[j] * ratio);
    out[r] = wrench[r] - shift;
    rest += missing[r] * out[r];
  }
  for (std::int64_t r = 0; r < n; ++r) out[r] -= missing[r] * rest;
  return true;
}

}  // namespace va
