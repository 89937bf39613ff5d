// virtual_actuators._core: the Python module of the compiled kernels (nanobind), built at install
// by scikit-build-core (CMakeLists.txt). The kernels are header-only C++17 with no Python in them
// (kinematics.hpp, linalg.hpp, batch.hpp, solves.hpp, distribute.hpp, ...); each concept binds
// its own in a bind_<concept>.cpp beside them (bind_kinematics.cpp, bind_qp.cpp, ...), and this
// file makes the module and calls each. Arguments are checked in the binding files; the GIL is
// released while a kernel runs.
//
// Objects hold what a declaration fixes (Tree: the kinematic tables; Distribution: the packed
// tables of one distribution mode), so that a tick passes only q (v) and the wrench.
#include <nanobind/nanobind.h>

namespace nb = nanobind;

namespace va::py {
void bind_kinematics(nb::module_& m);
void bind_distribution(nb::module_& m);
void bind_qp(nb::module_& m);
void bind_sensor(nb::module_& m);
void bind_contact_margins(nb::module_& m);
void bind_attachment(nb::module_& m);
void bind_gait(nb::module_& m);
void bind_simulation(nb::module_& m);
void bind_contacts_view(nb::module_& m);
void bind_plan(nb::module_& m);
void bind_estimator(nb::module_& m);
}  // namespace va::py

NB_MODULE(_core, m) {
  m.doc() =
      "Compiled kernels of virtual_actuators (C++, built at install); see "
      "virtual_actuators.native.";
  // Trees and distributions live in the robots' caches (module-level registries) until the
  // interpreter's teardown, which may free the module first: not a leak worth a report.
  nb::set_leak_warnings(false);
  va::py::bind_kinematics(m);
  va::py::bind_distribution(m);
  va::py::bind_qp(m);
  va::py::bind_sensor(m);
  va::py::bind_contact_margins(m);
  va::py::bind_attachment(m);
  va::py::bind_gait(m);
  va::py::bind_simulation(m);
  va::py::bind_contacts_view(m);
  va::py::bind_plan(m);
  va::py::bind_estimator(m);
}
