// The native turkey's binding: NativeTurkey (bind_native_turkey.hpp), a TurkeyWalker's whole tick.
#include "bind_native_turkey.hpp"

#include "bind_attachment.hpp"
#include "bind_common.hpp"
#include "bind_kinematics.hpp"

namespace va::py {

void bind_native_turkey(nb::module_& m) {
  nb::class_<NativeTurkey>(m, "NativeTurkey",
                           "A TurkeyWalker's whole tick in one call (gaits.turkey.native): the "
                           "kinematics, the state machine and its callbacks, the attachments, "
                           "the sums, the limp joints and the clipping.")
      .def(nb::init<const Tree&, const I1&, const F1&, const F1&, const F1&>(), "tree"_a, "rows"_a,
           "parameters"_a, "lower"_a, "upper"_a, nb::keep_alive<1, 2>())
      .def("add_slot", &NativeTurkey::add_slot, "values"_a, "role"_a)
      .def("slot", &NativeTurkey::slot, "slot"_a)
      .def("set_slot", &NativeTurkey::set_slot, "slot"_a, "values"_a)
      .def("add_attachment", &NativeTurkey::add_attachment, "tick"_a, "solve"_a.none(), "slots"_a,
           "reset_axes"_a, "yields"_a, "yield_mask"_a, "orientation_rows"_a, "points"_a,
           "axis_rows"_a, "minima_axes"_a, "lows"_a, nb::keep_alive<1, 2>(), nb::keep_alive<1, 3>())
      .def("add_state", &NativeTurkey::add_state, "attachments"_a, "limp"_a)
      .def("memory", &NativeTurkey::memory)
      .def("set_memory", &NativeTurkey::set_memory, "values"_a)
      .def("tick", &NativeTurkey::tick, "q"_a, "v"_a, "time"_a, "tau"_a.noconvert(),
           "readings"_a.noconvert())
      .def_prop_ro("state", &NativeTurkey::state)
      .def_prop_ro("nv", &NativeTurkey::nv)
      .def_ro_static("MEMORY", &NativeTurkey::MEMORY)
      .def_ro_static("DEFER", &NativeTurkey::DEFER)
      .def_ro_static("TICKED", &NativeTurkey::TICKED)
      .def_ro_static("ENTERED", &NativeTurkey::ENTERED);
}

}  // namespace va::py
