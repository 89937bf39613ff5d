// The simulation's kernel's binding (simulation.hpp): efforts into MuJoCo's controls.
#include <cstdint>

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

}  // namespace

void bind_simulation(nb::module_& m) {
  m.def("efforts_to_ctrl", &simulation_efforts_to_ctrl, "tau"_a, "direct"_a, "unactuated"_a,
        "tolerance"_a, "ctrl"_a.noconvert(),
        "simulation.actuation.efforts_to_ctrl: efforts into ctrl in place; 0, 1 or 2.");
}

}  // namespace va::py
