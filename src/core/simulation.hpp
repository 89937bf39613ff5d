// The simulation's per-tick kernel: joint efforts into MuJoCo's actuator controls.
// A line-by-line port of virtual_actuators.simulation.actuation.efforts_to_ctrl.
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

}  // namespace va
