// A serial spring-damper attachment's tick in C++: the kernels of
// virtual_actuators.control.attachment_kernel (spring_damper_tick) and of
// virtual_actuators.kinematics.sensor_kernels (relative_sensor, rotation_log).
//
// Line-by-line ports of the reference (numba) kernels: the same floating-point operations in
// the same order, so that the results agree bit for bit (no FMA contraction: CMakeLists.txt sets
// -ffp-contract=off). Plain pointers, no Python: usable from a C++ controller.
#pragma once

#include <cmath>
#include <cstdint>

namespace va::serial {

// Rotation vector log(R) of a row-major 3x3 rotation (sensor_kernels.rotation_log).
inline void rotation_log(const double* r, double* out) {
  const double trace = r[0] + r[4] + r[8];
  double cosine = 0.5 * (trace - 1.0);
  cosine = -1.0 > cosine ? -1.0 : cosine;  // min(max(c, -1), 1) as Python's max / min pick
  cosine = 1.0 < cosine ? 1.0 : cosine;
  const double theta = std::acos(cosine);
  const double skew[3] = {r[7] - r[5], r[2] - r[6], r[3] - r[1]};
  if (theta < 1e-4) {
    const double factor = 0.5 * (1.0 + theta * theta / 6.0);
    for (int i = 0; i < 3; ++i) out[i] = factor * skew[i];
    return;
  }
  if (M_PI - theta > 1e-3) {
    const double factor = 0.5 * theta / std::sin(theta);
    for (int i = 0; i < 3; ++i) out[i] = factor * skew[i];
    return;
  }
  int k = 0;
  for (int i = 1; i < 3; ++i)
    if (r[4 * i] > r[4 * k]) k = i;
  const double scale = 1.0 - cosine;
  const double diagonal = r[4 * k] - cosine;
  const double a_k = std::sqrt((0.0 > diagonal ? 0.0 : diagonal) / scale);
  double dot = 0.0;
  for (int i = 0; i < 3; ++i) {
    if (i == k)
      out[i] = a_k;
    else
      out[i] = 0.5 * (r[3 * k + i] + r[3 * i + k]) / (scale * a_k);
    dot += out[i] * skew[i];
  }
  const double sign = dot < 0.0 ? -1.0 : 1.0;
  for (int i = 0; i < 3; ++i) out[i] *= sign * theta;
}

// The fixed tables of a serial actuator's sensor (sensor_kernels.relative_sensor's arguments).
struct SensorTables {
  const std::int64_t* axis_rows;  // (n,) rows of the axes among x y z rx ry rz, increasing
  std::int64_t n;
  const std::int64_t* rows;  // (3,) rows of {B}, {O}, {A} in the frame table
  const std::int64_t* columns;  // (m,) the chain's velocity indices
  const double* signs;  // (m,) their +1 / -1
  std::int64_t m;
};

// relative_sensor on the chain's columns: jacobian (m, n) column j's entries (the reference's
// jacobian[:, columns[j]]), position (n), velocity (n). jacobian_world (6, nv), frames (nf, 12).
inline void relative_sensor(const double* jacobian_world, std::int64_t nv, const double* frames,
                            const double* v, const SensorTables& s, double* jacobian,
                            double* position, double* velocity) {
  const double* b = frames + 12 * s.rows[0];
  const double* o = frames + 12 * s.rows[1];
  const double* a = frames + 12 * s.rows[2];
  const std::int64_t n = s.n;
  const double x = b[9], y = b[10], z = b[11];
  double transform[6][6] = {};
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) {
      const double value = o[3 * c + r];  // R_O^T
      transform[r][c] = value;
      transform[3 + r][3 + c] = value;
    }
  for (int r = 0; r < 3; ++r) {
    const double t0 = transform[r][0], t1 = transform[r][1], t2 = transform[r][2];
    transform[r][3] = t2 * y - t1 * z;
    transform[r][4] = t0 * z - t2 * x;
    transform[r][5] = t1 * x - t0 * y;
  }
  for (std::int64_t i = 0; i < n; ++i) velocity[i] = 0.0;
  for (std::int64_t j = 0; j < s.m; ++j) {
    const std::int64_t col = s.columns[j];
    for (std::int64_t i = 0; i < n; ++i) {
      const double* row = transform[s.axis_rows[i]];
      double acc = 0.0;
      for (int k = 0; k < 6; ++k) acc += row[k] * jacobian_world[k * nv + col];
      acc *= s.signs[j];
      jacobian[j * n + i] = acc;
      if (v != nullptr) velocity[i] += acc * v[col];
    }
  }
  double pose[6] = {};
  for (int r = 0; r < 3; ++r) {
    double acc = 0.0;
    for (int k = 0; k < 3; ++k) acc += o[3 * k + r] * (b[9 + k] - a[9 + k]);
    pose[r] = acc;
  }
  if (s.axis_rows[n - 1] >= 3) {  // a rotation axis: log of R_A^T R_B, expressed in {O}
    double relative[9];
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) {
        double acc = 0.0;
        for (int k = 0; k < 3; ++k) acc += a[3 * k + r] * b[3 * k + c];
        relative[3 * r + c] = acc;
      }
    double log_a[3];
    rotation_log(relative, log_a);  // in {A}
    for (int r = 0; r < 3; ++r) {
      double acc = 0.0;
      for (int k = 0; k < 3; ++k) {
        double in_world = 0.0;
        for (int m = 0; m < 3; ++m) in_world += a[3 * k + m] * log_a[m];
        acc += o[3 * k + r] * in_world;
      }
      pose[3 + r] = acc;
    }
  }
  for (std::int64_t i = 0; i < n; ++i) position[i] = pose[s.axis_rows[i]];
}

// A spring-damper's parameters per axis (SpringDamper's arrays).
struct SpringParameters {
  const double* stiffness;
  const double* damping;
  const double* setpoint;
  const double* velocity_setpoint;
  const double* force;
  const double* limit;
};

// attachment_kernel.spring_damper_tick: out (nv + 3n + 1) = effort (nv, J^T w on the chain's
// columns, zero elsewhere), position (n), velocity (n), wrench (n), then 1.0, or 0.0 when the
// general path must run (a rotational difference outside [-pi, pi], a wrench not finite; effort
// left zero). jacobian: scratch of m n doubles. out must be zeroed by the caller.
inline bool spring_damper_tick(const double* jacobian_world, std::int64_t nv, const double* frames,
                               const double* v, const SensorTables& s, std::int64_t rotation,
                               const SpringParameters& p, double* jacobian, double* out) {
  const std::int64_t n = s.n;
  double* position = out + nv;
  double* velocity = out + nv + n;
  double* wrench = out + nv + 2 * n;
  relative_sensor(jacobian_world, nv, frames, v, s, jacobian, position, velocity);
  bool ok = true;
  double total = 0.0;
  for (std::int64_t i = 0; i < n; ++i) {
    const double bent = p.setpoint[i] - position[i];
    if (i == rotation && !(-M_PI <= bent && bent <= M_PI)) ok = false;
    double w = p.stiffness[i] * bent + p.damping[i] * (p.velocity_setpoint[i] - velocity[i]);
    const double low = -p.limit[i];
    w = low > w ? low : w;  // max(w, -limit): w unless -limit > w
    w = p.limit[i] < w ? p.limit[i] : w;  // min(w, limit): w unless limit < w
    w = w + p.force[i];
    wrench[i] = w;
    total += w;
  }
  if (!std::isfinite(total)) ok = false;
  if (!ok) return false;
  for (std::int64_t j = 0; j < s.m; ++j) {
    double acc = 0.0;
    for (std::int64_t i = 0; i < n; ++i) acc += jacobian[j * n + i] * wrench[i];
    out[s.columns[j]] = acc;
  }
  out[nv + 3 * n] = 1.0;
  return true;
}

}  // namespace va::serial
