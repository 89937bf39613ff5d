// The virtual sensor's binding (sensor.hpp): a relative sensor's Jacobian, position and velocity.
#include <cstdint>
#include <memory>

#include "bind_common.hpp"
#include "sensor.hpp"

namespace va::py {
namespace {

// sensor_kernels.relative_sensor: one buffer, jacobian (n, nv), position (n), velocity (n).
Owned relative_sensor(const F2& jacobian_world, const F2& frames, const F1& v, const I1& axis_rows,
                      const I1& rows, const I1& columns, const F1& signs) {
  require(jacobian_world.shape(0) == 6, "jacobian_world must be (6, nv)");
  const auto nv = static_cast<std::int64_t>(jacobian_world.shape(1));
  const std::int64_t n = len(axis_rows), nc = len(columns);
  require(n >= 1 && n <= 6, "axis_rows must have 1 to 6 entries");
  for (std::int64_t a = 0; a < n; ++a)
    require(axis_rows.data()[a] >= 0 && axis_rows.data()[a] < 6, "axis_rows must be in 0..5");
  require(len(rows) == 3 && frames.shape(1) == 12, "rows must be (3,), frames (nf, 12)");
  for (std::int64_t r = 0; r < 3; ++r)
    require(rows.data()[r] >= 0 && rows.data()[r] < static_cast<std::int64_t>(frames.shape(0)),
            "rows out of the frame table");
  require(length(signs) == nc, "signs must be like columns");
  for (std::int64_t j = 0; j < nc; ++j)
    require(columns.data()[j] >= 0 && columns.data()[j] < nv, "columns out of range");
  require(length(v) == 0 || length(v) == nv, "v must be (nv,) or empty");
  const auto size = static_cast<std::size_t>(n * nv + 2 * n);
  std::unique_ptr<double[]> buffer(new double[size]());
  {
    nb::gil_scoped_release release;
    va::relative_sensor(jacobian_world.data(), nv, frames.data(), length(v) ? v.data() : nullptr,
                        axis_rows.data(), n, rows.data(), columns.data(), signs.data(), nc,
                        buffer.get());
  }
  return owned(std::move(buffer), size);
}

}  // namespace

void bind_sensor(nb::module_& m) {
  m.def("relative_sensor", &relative_sensor, "jacobian_world"_a, "frames"_a, "v"_a, "axis_rows"_a,
        "rows"_a, "columns"_a, "signs"_a,
        "kinematics.sensor_kernels.relative_sensor: jacobian, position, velocity in one buffer.");
}

}  // namespace va::py
