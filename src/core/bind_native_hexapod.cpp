// The native hexapod's binding: NativeHexapod (bind_native_hexapod.hpp), a HexapodWalker's whole
// tick.
#include "bind_native_hexapod.hpp"

#include <nanobind/stl/optional.h>

#include "bind_attachment.hpp"
#include "bind_common.hpp"
#include "bind_kinematics.hpp"
#include "bind_qp.hpp"

namespace va::py {

void bind_native_hexapod(nb::module_& m) {
  nb::class_<NativeHexapod>(m, "NativeHexapod",
                            "A HexapodWalker's whole tick in one call (gaits.hexapod.native): "
                            "the kinematics, the state machine and its callbacks, the body's "
                            "components and QP, the swing legs, the sums, the limp joints and "
                            "the clipping.")
      .def(nb::init<const Tree&, const I1&, const F1&, const F2&, const F1&, const F1&, const F1&,
                    const F1&, const F1&>(),
           "tree"_a, "rows"_a, "parameters"_a, "nominal"_a, "shape"_a, "body"_a, "tolerances"_a,
           "lower"_a, "upper"_a, nb::keep_alive<1, 2>())
      .def("add_body", &NativeHexapod::add_body, "axis_rows"_a, "sensor_rows"_a, "columns"_a,
           "signs"_a, "qp"_a, "q"_a, "buffer"_a.noconvert(), "layout"_a, "kept"_a, "keep"_a,
           "weights"_a, nb::keep_alive<1, 6>(), nb::keep_alive<1, 8>())
      .def("set_guess", &NativeHexapod::set_guess, "index"_a, "guess"_a.noconvert().none())
      .def("set_body", &NativeHexapod::set_body, "body"_a)
      .def("set_swing", &NativeHexapod::set_swing, "index"_a, "values"_a)
      .def("add_swing", &NativeHexapod::add_swing, "tick"_a, "leg"_a, "values"_a,
           nb::keep_alive<1, 2>())
      .def("add_state", &NativeHexapod::add_state, "attachments"_a, "limp"_a)
      .def("memory", &NativeHexapod::memory)
      .def("swing", &NativeHexapod::swing)
      .def("set_memory", &NativeHexapod::set_memory, "values"_a, "swing"_a)
      .def("tick", &NativeHexapod::tick, "q"_a, "v"_a, "time"_a, "command"_a, "contacts"_a,
           "tau"_a.noconvert(), "readings"_a.noconvert())
      .def_prop_ro("state", &NativeHexapod::state)
      .def_prop_ro("nv", &NativeHexapod::nv)
      .def_ro_static("MEMORY", &NativeHexapod::MEMORY)
      .def_ro_static("DEFER", &NativeHexapod::DEFER)
      .def_ro_static("TICKED", &NativeHexapod::TICKED)
      .def_ro_static("ENTERED", &NativeHexapod::ENTERED);
}

}  // namespace va::py
