// The gait's kernels' bindings (gait.hpp): the centre of mass and the producible directions.
#include <cstdint>
#include <memory>
#include <vector>

#include "bind_common.hpp"
#include "gait.hpp"

namespace va::py {
namespace {

using GF2 = nb::ndarray<double, nb::numpy, nb::ndim<2>, nb::c_contig, nb::device::cpu>;

std::int64_t rows_of(const F2& a) { return static_cast<std::int64_t>(a.shape(0)); }

// kinematics.kernels.center_of_mass: (x, y, z).
nb::tuple gait_center_of_mass(const F2& joints, const F1& masses, const F2& levers) {
  const std::int64_t n = rows_of(joints);
  require(joints.shape(1) == 12, "joints must be (njoints, 12)");
  require(length(masses) == n && rows_of(levers) == n && levers.shape(1) == 3,
          "masses must be (njoints,), levers (njoints, 3)");
  double out[3];
  {
    nb::gil_scoped_release release;
    va::center_of_mass(joints.data(), masses.data(), levers.data(), n, out);
  }
  return nb::make_tuple(out[0], out[1], out[2]);
}

// actuators.producible._two_points: (36,), or empty (coincident contacts, a row not in frames).
Owned gait_two_points(const F2& frames, const I1& rows) {
  require(frames.shape(1) == 12 && len(rows) == 4, "frames must be (nf, 12), rows (4,)");
  for (std::int64_t r = 0; r < 4; ++r) {
    require(rows.data()[r] >= 0, "rows must be >= 0");
    if (rows.data()[r] >= rows_of(frames))
      return owned(std::unique_ptr<double[]>(new double[1]), 0);
  }
  std::unique_ptr<double[]> buffer(new double[36]());
  bool found;
  {
    nb::gil_scoped_release release;
    found = va::two_points(frames.data(), rows.data(), buffer.get());
  }
  if (!found) return owned(std::unique_ptr<double[]>(new double[1]), 0);
  return owned(std::move(buffer), 36);
}

// actuators.producible._give_way_one: out written when True.
bool gait_give_way_one(const F1& wrench, const F2& yielding, const F2& missing, const MF1& out) {
  const std::int64_t n = length(wrench);
  const auto m = static_cast<std::int64_t>(yielding.shape(1));
  require(rows_of(yielding) == n && rows_of(missing) == n && missing.shape(1) >= 1,
          "yielding must be (n, m), missing (n, >= 1)");
  require(length(out) == n, "out must be (n,)");
  std::vector<double> across(static_cast<std::size_t>(m));
  std::vector<double> column(static_cast<std::size_t>(n));  // missing[:, 0]
  const auto width = static_cast<std::int64_t>(missing.shape(1));
  for (std::int64_t r = 0; r < n; ++r) column[r] = missing.data()[width * r];
  nb::gil_scoped_release release;
  return va::give_way_one(wrench.data(), yielding.data(), n, m, column.data(), out.data(),
                          across.data());
}

}  // namespace

void bind_gait(nb::module_& m) {
  m.def("center_of_mass", &gait_center_of_mass, "joints"_a, "masses"_a, "levers"_a,
        "kinematics.kernels.center_of_mass: the bodies' centre of mass (x, y, z).");
  m.def("two_points", &gait_two_points, "frames"_a, "rows"_a,
        "actuators.producible._two_points: producible (6, 5) and missing (6, 1) row by row.");
  m.def("give_way_one", &gait_give_way_one, "wrench"_a, "yielding"_a, "missing"_a,
        "out"_a.noconvert(),
        "actuators.producible._give_way_one: the request given way along one direction.");
}

}  // namespace va::py
