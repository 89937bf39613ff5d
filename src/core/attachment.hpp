// A serial spring-damper attachment's tick in C++: the kernels of
// virtual_actuators.control.attachment_kernel (spring_damper_tick) and of
// virtual_actuators.kinematics.sensor_kernels (relative_sensor; its geometry shared with
// sensor.hpp).
//
// Line-by-line ports of the reference (numba) kernels: the same floating-point operations in
// the same order, so that the results agree bit for bit (no FMA contraction: CMakeLists.txt sets
// -ffp-contract=off). Plain pointers, no Python: usable from a C++ controller.
#pragma once

#include <cmath>
#include <cstdint>

#include "sensor.hpp"

namespace va::serial {

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
  double transform[6][6];
  sensor_transform(b, o, transform);
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
  sensor_pose(b, o, a, s.axis_rows, n, position);
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
