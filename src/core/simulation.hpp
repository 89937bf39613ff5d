// The simulation's per-tick kernels: joint efforts into MuJoCo's actuator controls, and MuJoCo's
// velocity read in Pinocchio's convention. Line-by-line ports of
// virtual_actuators.simulation.actuation.efforts_to_ctrl and conversions.state_velocity.
#pragma once

#include <cmath>
#include <cstdint>

namespace va {

// ctrl[k] = tau[direct[k]] when every effort is finite (returns 0) and each effort on an
// unactuated degree of freedom is within +-tolerance (else returns 2); 1 for a non-finite
// effort. ctrl is written only when 0 is returned.
inline std::int64_t efforts_to_ctrl(const double* tau, std::int64_t nv, const std::int64_t* direct,
                                    std::int64_t nu, const std::int64_t* unactuated,
                                    std::int64_t count, double tolerance, double* ctrl) {
  for (std::int64_t i = 0; i < nv; ++i)
    if (!std::isfinite(tau[i])) return 1;
  for (std::int64_t k = 0; k < count; ++k) {
    const double effort = tau[unactuated[k]];
    if (effort > tolerance || effort < -tolerance) return 2;
  }
  for (std::int64_t k = 0; k < nu; ++k) ctrl[k] = tau[direct[k]];
  return 0;
}

// v[k] = qvel[gather[k]], then each free joint's world-frame linear velocity rotated into its
// body frame (R^T v for the normalised quaternion w x y z at qpos[a + 3]); free holds one row
// (qpos_adr, dof_adr, idx_v) per free joint. The operations of conversions._rotate_back, in its
// order.
inline void state_velocity(const double* qpos, const double* qvel, const std::int64_t* gather,
                           std::int64_t nv, const std::int64_t* free, std::int64_t nfree,
                           double* v) {
  for (std::int64_t k = 0; k < nv; ++k) v[k] = qvel[gather[k]];
  for (std::int64_t s = 0; s < nfree; ++s) {
    const std::int64_t a = free[3 * s], d = free[3 * s + 1], i = free[3 * s + 2];
    double w = qpos[a + 3], x = qpos[a + 4], y = qpos[a + 5], z = qpos[a + 6];
    const double scale = 1.0 / std::sqrt(w * w + x * x + y * y + z * z);
    w = w * scale;
    x = x * scale;
    y = y * scale;
    z = z * scale;
    const double p = qvel[d], b = qvel[d + 1], c = qvel[d + 2];
    v[i] =
        (1.0 - 2.0 * (y * y + z * z)) * p + 2.0 * (x * y + w * z) * b + 2.0 * (x * z - w * y) * c;
    v[i + 1] =
        2.0 * (x * y - w * z) * p + (1.0 - 2.0 * (x * x + z * z)) * b + 2.0 * (y * z + w * x) * c;
    v[i + 2] =
        2.0 * (x * z + w * y) * p + 2.0 * (y * z - w * x) * b + (1.0 - 2.0 * (x * x + y * y)) * c;
  }
}

}  // namespace va
