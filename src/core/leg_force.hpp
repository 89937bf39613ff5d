// The legged estimator's per-foot arithmetic (legged_estimator.hpp): a leg's quasi-static
// ground force from its efforts, a covariance rotated into world axes, the smooth ramp of the
// contact probabilities.
#pragma once

#include <cstdint>

#include "so3.hpp"

namespace va {

// 0 below 0, 1 above 1, smooth (3x^2 - 2x^3) in between.
inline double ramp(double x) { return x <= 0.0 ? 0.0 : x >= 1.0 ? 1.0 : x * x * (3.0 - 2.0 * x); }

// out = r base r^T (3 x 3, row-major).
inline void rotate_covariance(const so3::Mat3 r, const double* base, double* out) {
  double rb[9] = {};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k) rb[3 * i + j] += r[i][k] * base[3 * k + j];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      double sum = 0.0;
      for (int k = 0; k < 3; ++k) sum += rb[3 * i + k] * r[j][k];
      out[3 * i + j] = sum;
    }
}

// The force of the ground on a foot at r (base axes) that its leg's efforts hold
// quasi-statically: f = (J J^T + eps I)^-1 J (g - tau), J (3 x k) the point's Jacobian on the
// leg's velocity columns (columns, k of them; jacobian (6, nv) row-major, spatial at the origin),
// g the generalized gravity (nv). jjt (3 x 3) gets J J^T (the encoders' noise map).
inline void leg_force(const std::int64_t* columns, std::int64_t k, const double* r,
                      const double* jacobian, std::int64_t nv, const double* gravity_tau,
                      const double* tau, double* force, double* jjt) {
  double jr[3] = {0.0, 0.0, 0.0};
  for (int i = 0; i < 9; ++i) jjt[i] = 0.0;
  for (std::int64_t c = 0; c < k; ++c) {
    const std::int64_t col = columns[c];
    const double lin[3] = {jacobian[col], jacobian[nv + col], jacobian[2 * nv + col]};
    const double ang[3] = {jacobian[3 * nv + col], jacobian[4 * nv + col], jacobian[5 * nv + col]};
    double point[3];
    so3::cross(ang, r, point);
    for (int i = 0; i < 3; ++i) point[i] += lin[i];
    const double e = gravity_tau[col] - tau[col];
    for (int i = 0; i < 3; ++i) {
      jr[i] += point[i] * e;
      for (int j = 0; j < 3; ++j) jjt[3 * i + j] += point[i] * point[j];
    }
  }
  double a[9], inv[9];
  const double eps = 1e-6 * (jjt[0] + jjt[4] + jjt[8]) + 1e-12;
  for (int i = 0; i < 9; ++i) a[i] = jjt[i] + (i % 4 == 0 ? eps : 0.0);
  const double det = a[0] * (a[4] * a[8] - a[5] * a[7]) - a[1] * (a[3] * a[8] - a[5] * a[6]) +
                     a[2] * (a[3] * a[7] - a[4] * a[6]);
  inv[0] = (a[4] * a[8] - a[5] * a[7]) / det;
  inv[1] = (a[2] * a[7] - a[1] * a[8]) / det;
  inv[2] = (a[1] * a[5] - a[2] * a[4]) / det;
  inv[3] = (a[5] * a[6] - a[3] * a[8]) / det;
  inv[4] = (a[0] * a[8] - a[2] * a[6]) / det;
  inv[5] = (a[2] * a[3] - a[0] * a[5]) / det;
  inv[6] = (a[3] * a[7] - a[4] * a[6]) / det;
  inv[7] = (a[1] * a[6] - a[0] * a[7]) / det;
  inv[8] = (a[0] * a[4] - a[1] * a[3]) / det;
  for (int i = 0; i < 3; ++i)
    force[i] = inv[3 * i] * jr[0] + inv[3 * i + 1] * jr[1] + inv[3 * i + 2] * jr[2];
}

}  // namespace va
