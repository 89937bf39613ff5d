// The virtual sensor of a serial actuator: the C++ port of
// virtual_actuators.kinematics.sensor_kernels (rotation_log, relative_sensor), operation by
// operation, so that both agree bit for bit (tests/test_core_parity_qp.py).
#pragma once

#include <cmath>
#include <cstdint>

#include "linalg.hpp"
#include "scalar.hpp"

namespace va {

constexpr double PI = 3.141592653589793;

// Rotation vector log(R) of a row-major 3x3 rotation matrix [rad]. sensor_kernels.rotation_log.
inline void rotation_log(const double R[3][3], double out[3]) {
  const double trace = R[0][0] + R[1][1] + R[2][2];
  const double cosine = py_min(py_max(0.5 * (trace - 1.0), -1.0), 1.0);
  const double theta = std::acos(cosine);
  const double skew[3] = {R[2][1] - R[1][2], R[0][2] - R[2][0], R[1][0] - R[0][1]};
  if (theta < 1e-4) {
    const double factor = 0.5 * (1.0 + theta * theta / 6.0);
    for (int i = 0; i < 3; ++i) out[i] = factor * skew[i];
    return;
  }
  if (PI - theta > 1e-3) {
    const double factor = 0.5 * theta / std::sin(theta);
    for (int i = 0; i < 3; ++i) out[i] = factor * skew[i];
    return;
  }
  int k = 0;  // near pi: the largest diagonal entry
  for (int i = 1; i < 3; ++i)
    if (R[i][i] > R[k][k]) k = i;
  const double scale = 1.0 - cosine;
  const double a_k = std::sqrt(py_max(R[k][k] - cosine, 0.0) / scale);
  double dot = 0.0;
  for (int i = 0; i < 3; ++i) {
    out[i] = i == k ? a_k : 0.5 * (R[k][i] + R[i][k]) / (scale * a_k);
    dot += out[i] * skew[i];
  }
  const double sign = dot < 0.0 ? -1.0 : 1.0;
  for (int i = 0; i < 3; ++i) out[i] *= sign * theta;
}

// The 6x6 map from world-axes twists at the world origin to twists of {B}'s origin in {O}'s
// axes (rows x y z rx ry rz); fb, fo: frame-table rows of {B} and {O}. relative_sensor's first
// lines.
inline void sensor_transform(const double* fb, const double* fo, double transform[6][6]) {
  const double x = fb[9], y = fb[10], z = fb[11];
  for (int r = 0; r < 6; ++r)
    for (int c = 0; c < 6; ++c) transform[r][c] = 0.0;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) {
      const double value = fo[3 * c + r];
      transform[r][c] = value;
      transform[3 + r][3 + c] = value;
    }
  for (int r = 0; r < 3; ++r) {
    const double t0 = transform[r][0], t1 = transform[r][1], t2 = transform[r][2];
    transform[r][3] = t2 * y - t1 * z;
    transform[r][4] = t0 * z - t2 * x;
    transform[r][5] = t1 * x - t0 * y;
  }
}

// The sensed position of {B} from {A} in {O}'s axes, on the actuator's axes (n): the
// translation, and log(R_A^T R_B) in {O} when the last axis is a rotation. relative_sensor's
// last lines.
inline void sensor_pose(const double* fb, const double* fo, const double* fa,
                        const std::int64_t* axis_rows, std::int64_t n, double* position) {
  double pose[6] = {};
  for (int r = 0; r < 3; ++r) {
    double acc = 0.0;
    for (int k = 0; k < 3; ++k) acc += fo[3 * k + r] * (fb[9 + k] - fa[9 + k]);
    pose[r] = acc;
  }
  if (axis_rows[n - 1] >= 3) {  // a rotation axis: log of R_A^T R_B, expressed in {O}
    double relative[3][3];
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) {
        double acc = 0.0;
        for (int k = 0; k < 3; ++k) acc += fa[3 * k + r] * fb[3 * k + c];
        relative[r][c] = acc;
      }
    double log_a[3];
    rotation_log(relative, log_a);
    for (int r = 0; r < 3; ++r) {
      double acc = 0.0;
      for (int k = 0; k < 3; ++k) {
        double in_world = 0.0;
        for (int m = 0; m < 3; ++m) in_world += fa[3 * k + m] * log_a[m];
        acc += fo[3 * k + r] * in_world;
      }
      pose[3 + r] = acc;
    }
  }
  for (std::int64_t i = 0; i < n; ++i) position[i] = pose[axis_rows[i]];
}

// A serial actuator's Jacobian (n, nv), position (n) and velocity (n) into buffer (zeros),
// from the world Jacobian (6, nv) and frames (nf, 12); v null: no velocity; rows: {B}, {O},
// {A}. sensor_kernels.relative_sensor.
inline void relative_sensor(const double* jacobian_world, std::int64_t nv, const double* frames,
                            const double* v, const std::int64_t* axis_rows, std::int64_t n,
                            const std::int64_t* rows, const std::int64_t* columns,
                            const double* signs, std::int64_t ncolumns, double* buffer) {
  const std::int64_t b = rows[0], o = rows[1], a = rows[2];
  const double* fb = frames + 12 * b;
  const double* fo = frames + 12 * o;
  const double* fa = frames + 12 * a;
  double transform[6][6];
  sensor_transform(fb, fo, transform);
  double* jacobian = buffer;
  double* position = buffer + n * nv;
  double* velocity = buffer + n * nv + n;
  for (std::int64_t j = 0; j < ncolumns; ++j) {
    const std::int64_t col = columns[j];
    for (std::int64_t i = 0; i < n; ++i) {
      double acc = 0.0;
      for (int k = 0; k < 6; ++k) acc += transform[axis_rows[i]][k] * jacobian_world[k * nv + col];
      acc *= signs[j];
      jacobian[i * nv + col] = acc;
      if (v != nullptr) velocity[i] += acc * v[col];
    }
  }
  sensor_pose(fb, fo, fa, axis_rows, n, position);
}

}  // namespace va
