// A spring-damper attachment's sensing and wrench (and a serial one's efforts) in one call
// (virtual_actuators.control.attachment_kernel's SpringTick; the sensor's geometry shared with
// sensor.hpp). The same floating-point operations in the same order as the controller's general
// path, which the tests compare it with bit for bit (tests/test_attachment_kernel.py; no FMA
// contraction: CMakeLists.txt sets -ffp-contract=off). Plain pointers, no Python: usable from a C++
// controller.
#pragma once

#include <cmath>
#include <cstdint>

#include "sensor.hpp"

namespace va::serial {

// The fixed tables of a serial actuator's sensor (sensor_kernels.relative_sensor's arguments).
struct SensorTables {
  const std::int64_t* axis_rows;  // (n,) rows of the axes among x y z rx ry rz, increasing
  std::int64_t n;
  const std::int64_t* rows;     // (3,) rows of {B}, {O}, {A} in the frame table
  const std::int64_t* columns;  // (m,) the chain's velocity indices
  const double* signs;          // (m,) their +1 / -1
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

// The spring-dampers' entries: each component's axes, component after component
// (attachment_kernel.spring_tick's targets, rotations, summed and parameters).
struct SpringEntries {
  const std::int64_t* targets;    // (e,) the axis of each entry
  const std::int64_t* rotations;  // (e,) 1: its component's one rotational axis
  std::int64_t e;
  bool summed;   // each axis sums its entries from 0.0 (several components)
  bool efforts;  // compute J^T w (a serial actuator that is its own sensor)
  // (6, e): stiffness, damping, setpoint, velocity setpoint, force, limit
  const double* parameters;
};

// attachment_kernel.spring_tick: out (nv + 3n + 1) = effort (nv, J^T w on the chain's columns
// when p.efforts, zero elsewhere), position (n), velocity (n), wrench (n), then 1.0, or 0.0 when
// the general path must run (a rotational difference outside [-pi, pi], a wrench not finite;
// effort left zero). jacobian: scratch of m n doubles. out must be zeroed by the caller.
inline bool spring_tick(const double* jacobian_world, std::int64_t nv, const double* frames,
                        const double* v, const SensorTables& s, const SpringEntries& p,
                        double* jacobian, double* out) {
  const std::int64_t n = s.n;
  double* position = out + nv;
  double* velocity = out + nv + n;
  double* wrench = out + nv + 2 * n;
  relative_sensor(jacobian_world, nv, frames, v, s, jacobian, position, velocity);
  const double* stiffness = p.parameters;
  const double* damping = p.parameters + p.e;
  const double* setpoint = p.parameters + 2 * p.e;
  const double* velocity_setpoint = p.parameters + 3 * p.e;
  const double* force = p.parameters + 4 * p.e;
  const double* limit = p.parameters + 5 * p.e;
  bool ok = true;
  for (std::int64_t e = 0; e < p.e; ++e) {
    const std::int64_t i = p.targets[e];
    const double bent = setpoint[e] - position[i];
    if (p.rotations[e] == 1 && !(-M_PI <= bent && bent <= M_PI)) ok = false;
    double w = stiffness[e] * bent + damping[e] * (velocity_setpoint[e] - velocity[i]);
    const double low = -limit[e];
    w = low > w ? low : w;            // max(w, -limit): w unless -limit > w
    w = limit[e] < w ? limit[e] : w;  // min(w, limit): w unless limit < w
    w = w + force[e];
    if (p.summed)
      wrench[i] += w;
    else
      wrench[i] = w;
  }
  double total = 0.0;
  for (std::int64_t i = 0; i < n; ++i) total += wrench[i];
  if (!std::isfinite(total)) ok = false;
  if (!ok) return false;
  if (p.efforts)
    for (std::int64_t j = 0; j < s.m; ++j) {
      double acc = 0.0;
      for (std::int64_t i = 0; i < n; ++i) acc += jacobian[j * n + i] * wrench[i];
      out[s.columns[j]] = acc;
    }
  out[nv + 3 * n] = 1.0;
  return true;
}

}  // namespace va::serial
