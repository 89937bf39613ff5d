// The simulation's kernels' bindings (simulation.hpp): efforts into MuJoCo's controls, and
// MuJoCo's velocity in Pinocchio's convention.
#include <cstdint>
#include <memory>
#include <utility>

#include "bind_common.hpp"
#include "simulation.hpp"

namespace va::py {
namespace {

// simulation.actuation.efforts_to_ctrl: 0 (ctrl written), 1 (an effort not finite), 2 (an
// unactuated effort beyond the tolerance).
std::int64_t simulation_efforts_to_ctrl(const F1& tau, const I1& direct, const I1& unactuated,
                                        double tolerance, const MF1& ctrl) {
  const std::int64_t nv = length(tau), nu = static_cast<std::int64_t>(direct.shape(0));
  const std::int64_t count = static_cast<std::int64_t>(unactuated.shape(0));
  require(length(ctrl) == nu, "ctrl must have one entry per direct index");
  for (std::int64_t k = 0; k < nu; ++k)
    require(direct.data()[k] >= 0 && direct.data()[k] < nv, "direct index out of range");
  for (std::int64_t k = 0; k < count; ++k)
    require(unactuated.data()[k] >= 0 && unactuated.data()[k] < nv,
            "unactuated index out of range");
  nb::gil_scoped_release release;
  return va::efforts_to_ctrl(tau.data(), nv, direct.data(), nu, unactuated.data(), count, tolerance,
                             ctrl.data());
}

// simulation.conversions.state_velocity: a new (len(gather),) v of MuJoCo's qpos and qvel.
Owned simulation_state_velocity(const F1& qpos, const F1& qvel, const I1& gather, const I2& free) {
  const std::int64_t nv = len(gather), nq = length(qpos), nqvel = length(qvel);
  const std::int64_t nfree = static_cast<std::int64_t>(free.shape(0));
  require(free.shape(1) == 3, "free must be (k, 3): qpos_adr, dof_adr, idx_v");
  for (std::int64_t k = 0; k < nv; ++k)
    require(gather.data()[k] >= 0 && gather.data()[k] < nqvel, "gather index out of range");
  for (std::int64_t s = 0; s < nfree; ++s) {
    const std::int64_t* row = free.data() + 3 * s;
    require(row[0] >= 0 && row[0] + 7 <= nq && row[1] >= 0 && row[1] + 3 <= nqvel && row[2] >= 0 &&
                row[2] + 3 <= nv,
            "free joint index out of range");
  }
  std::unique_ptr<double[]> v(new double[static_cast<std::size_t>(nv)]);
  va::state_velocity(qpos.data(), qvel.data(), gather.data(), nv, free.data(), nfree, v.get());
  return owned(std::move(v), static_cast<std::size_t>(nv));
}

}  // namespace

void bind_simulation(nb::module_& m) {
  m.def("efforts_to_ctrl", &simulation_efforts_to_ctrl, "tau"_a, "direct"_a, "unactuated"_a,
        "tolerance"_a, "ctrl"_a.noconvert(),
        "simulation.actuation.efforts_to_ctrl: efforts into ctrl in place; 0, 1 or 2.");
  m.def("state_velocity", &simulation_state_velocity, "qpos"_a, "qvel"_a, "gather"_a, "free"_a,
        "simulation.conversions.state_velocity: MuJoCo's velocity in Pinocchio's convention.");
}

}  // namespace va::py
