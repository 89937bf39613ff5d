// The kinematics' bindings (kinematics.hpp): Tree (bind_kinematics.hpp), and the configuration
// checks (a reading's too) and a point's velocity.
#include "bind_kinematics.hpp"

#include <nanobind/stl/optional.h>

#include <cstdint>

#include "bind_common.hpp"
#include "kinematics.hpp"

namespace va::py {
namespace {

double unit_norm_error(const F1& q, const I2& bounds) {
  require(bounds.shape(1) == 2, "bounds must be (m, 2)");
  const auto m = static_cast<std::int64_t>(bounds.shape(0));
  for (std::int64_t s = 0; s < m; ++s)
    require(bounds.data()[2 * s] >= 0 && bounds.data()[2 * s] <= bounds.data()[2 * s + 1] &&
                bounds.data()[2 * s + 1] <= length(q),
            "bounds out of range");
  return va::unit_norm_error(q.data(), length(q), bounds.data(), m);
}

// control.run_loop's check of a reading: unit_norm_error of q, -1 when q or v is not finite.
double reading_error(const F1& q, const F1& v, const I2& bounds) {
  if (!va::all_finite(v.data(), length(v))) return -1.0;
  return unit_norm_error(q, bounds);
}

bool all_finite(const F1& values) { return va::all_finite(values.data(), length(values)); }

nb::tuple point_velocity(const F2& jacobian_world, const F1& v, const I1& columns, double x,
                         double y, double z) {
  require(jacobian_world.shape(0) == 6, "jacobian_world must be (6, nv)");
  const auto nv = static_cast<std::int64_t>(jacobian_world.shape(1));
  require(length(v) == nv, "v must be (nv,)");
  for (std::size_t j = 0; j < columns.shape(0); ++j)
    require(columns.data()[j] >= 0 && columns.data()[j] < nv, "columns out of range");
  double out[3];
  va::point_velocity(jacobian_world.data(), nv, v.data(), columns.data(),
                     static_cast<std::int64_t>(columns.shape(0)), x, y, z, out);
  return nb::make_tuple(out[0], out[1], out[2]);
}

}  // namespace

void bind_kinematics(nb::module_& m) {
  nb::class_<Tree>(m, "Tree",
                   "A kinematic tree's tables (KinematicTree): forward kinematics per tick.")
      .def(nb::init<const I2&, const F2&, const I1&, const F2&, const I1&, const F2&, const I2&>(),
           "joint_ints"_a, "joint_floats"_a, "velocity_joint"_a, "velocity_subspace"_a,
           "frame_parents"_a, "frame_floats"_a, "unit_bounds"_a)
      .def("compute", &Tree::compute, "q"_a, "v"_a = nb::none(),
           "Joint placements, world joint Jacobian, frame placements (and velocities) in one "
           "buffer (kinematics.tree.KinematicTree.core_pass).")
      .def("size", &Tree::size, "with_velocity"_a, "Length of compute()'s buffer.")
      .def_prop_ro("nf", &Tree::nf, "Number of frames compute() places.")
      .def_prop_ro("nq", &Tree::nq, "Length of the configurations the tree accepts.");

  m.def("unit_norm_error", &unit_norm_error, "q"_a, "bounds"_a,
        "kinematics.kernels.unit_norm_error: largest | ||q[a:b]|| - 1 | (-1: q not finite).");
  m.def("reading_error", &reading_error, "q"_a, "v"_a, "bounds"_a,
        "control.run_loop's reading check: unit_norm_error of q (-1: q or v not finite).");
  m.def("all_finite", &all_finite, "values"_a,
        "kinematics.kernels.all_finite: no NaN, no infinity.");
  m.def("point_velocity", &point_velocity, "jacobian_world"_a, "v"_a, "columns"_a, "x"_a, "y"_a,
        "z"_a, "kinematics.kernels.point_velocity: a body point's linear velocity.");
}

}  // namespace va::py
