// The spring-damper attachments' bindings: SpringTick and SpringSolve (bind_attachment.hpp).
#include "bind_attachment.hpp"

#include <nanobind/stl/vector.h>

#include <cstdint>

#include "bind_common.hpp"

namespace va::py {

void bind_attachment(nb::module_& m) {
  nb::class_<SpringTick>(m, "SpringTick",
                         "A sensor's tables and its spring-dampers' entries (control.attachment_"
                         "kernel.SpringTick): one spring-damper attachment's tick per call.")
      .def(nb::init<const I1&, const I1&, const I1&, const F1&, const I1&, const I1&, std::int64_t,
                    std::int64_t, std::int64_t>(),
           "axis_rows"_a, "rows"_a, "columns"_a, "signs"_a, "targets"_a, "rotations"_a, "summed"_a,
           "efforts"_a, "nv"_a)
      .def("tick", &SpringTick::tick, "jacobian_world"_a, "frames"_a, "v"_a, "parameters"_a,
           "attachment_kernel.spring_tick: effort (nv), position, velocity, wrench (n) and the "
           "flag (1.0, or 0.0: the general path runs) in one buffer.");
  nb::class_<SpringSolve>(m, "SpringSolve",
                          "A parallel actuator's spring-damper attachment (attachment_kernel."
                          "SpringTick with a distribution): the spring tick, then the "
                          "distribution of its wrench, in one call.")
      .def(nb::init<const SpringTick&, const I1&, const F1&>(), "spring"_a, "ints"_a, "floats"_a,
           nb::keep_alive<1, 2>())
      .def("tick", &SpringSolve::tick, "jacobian_world"_a, "frames"_a, "v"_a, "q"_a, "parameters"_a,
           "(spring buffer, distribution buffer, residual, scale, rounding, status): "
           "SpringTick.tick, then Distribution.solve on its wrench (status -1: not run).")
      .def_ro_static("NOT_RUN", &SpringSolve::NOT_RUN);
}

}  // namespace va::py
