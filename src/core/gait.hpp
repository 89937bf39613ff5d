// Kernels the library reaches in the core: the bodies' centre of mass
// (virtual_actuators.kinematics.kernels.center_of_mass is its numpy oracle), and a parallel
// actuator's producible directions with two point feet and the request given way along one
// missing direction (actuators.producible's closed forms; the numpy general path is their oracle,
// tests/test_core_parity_gait.py). The legged walker's body model and swing feet are va.scalar
// formulas that a compiled plan traces into its ops: they have no port here.
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
