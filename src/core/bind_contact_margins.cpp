// The contact margins' bindings (contact_rows.hpp): the controller's yield policy, the smallest
// margin of the contact rows and the largest scale of a request that keeps them.
#include <cstdint>
#include <vector>

#include "bind_common.hpp"
#include "contact_rows.hpp"

namespace va::py {
namespace {

// The margins' arguments checked; returns the number of rows.
std::int64_t margin_rows(const F2& frames, const I1& orientation_rows, const F2& forces,
                         const F2& points, const I1& axis_rows, const I1& minima_axes,
                         const F1& lows) {
  const auto p = static_cast<std::int64_t>(forces.shape(0));
  const auto n = static_cast<std::int64_t>(forces.shape(1));
  require(n >= 1 && n <= 6 && len(axis_rows) == n, "forces must be (p, n), axis_rows (n,)");
  for (std::int64_t a = 0; a < n; ++a)
    require(axis_rows.data()[a] >= 0 && axis_rows.data()[a] < 6, "axis_rows must be in 0..5");
  for (std::int64_t m = 0; m < len(minima_axes); ++m)
    require(minima_axes.data()[m] >= 0 && minima_axes.data()[m] < n, "minima_axes out of range");
  const auto np = static_cast<std::int64_t>(points.shape(0));
  require((np == 0 || np == p) && points.shape(1) == 7, "points must be (p, 7) or (0, 7)");
  require(frames.shape(1) == 12 && len(orientation_rows) >= 1 + (np ? p : 0),
          "frames must be (nf, 12), orientation_rows ({O}, then each reaction frame)");
  for (std::int64_t r = 0; r < (np ? 1 + p : 0); ++r)
    require(orientation_rows.data()[r] >= 0 &&
                orientation_rows.data()[r] < static_cast<std::int64_t>(frames.shape(0)),
            "orientation_rows out of the frame table");
  std::int64_t rows = len(minima_axes) * p;
  for (std::int64_t c = 0; c < np; ++c) {
    const double* row = points.data() + 7 * c;
    rows += (row[2] > 0.0 ? 1 : 0) + (row[0] < 0.0 ? 0 : 4);
  }
  require(length(lows) == rows, "lows must have one entry per contact row");
  return rows;
}

double contact_least_margin(const F2& frames, const I1& orientation_rows, const F2& forces,
                            const F2& points, const I1& axis_rows, const I1& minima_axes,
                            const F1& lows) {
  const std::int64_t rows =
      margin_rows(frames, orientation_rows, forces, points, axis_rows, minima_axes, lows);
  std::vector<double> values(static_cast<std::size_t>(rows));
  nb::gil_scoped_release release;
  va::contact_margins(frames.data(), orientation_rows.data(), forces.data(),
                      static_cast<std::int64_t>(forces.shape(0)), len(axis_rows), points.data(),
                      static_cast<std::int64_t>(points.shape(0)), axis_rows.data(),
                      minima_axes.data(), len(minima_axes), values.data());
  return va::contact_least_margin(values.data(), lows.data(), rows);
}

double contact_largest_scale(const F2& frames, const I1& orientation_rows, const F2& full,
                             const F2& base, const F2& points, const I1& axis_rows,
                             const I1& minima_axes, const F1& lows) {
  const std::int64_t rows =
      margin_rows(frames, orientation_rows, full, points, axis_rows, minima_axes, lows);
  require(base.shape(0) == full.shape(0) && base.shape(1) == full.shape(1),
          "base must be shaped like full");
  std::vector<double> at_full(static_cast<std::size_t>(rows)), at_base(at_full.size());
  const auto p = static_cast<std::int64_t>(full.shape(0));
  const auto np = static_cast<std::int64_t>(points.shape(0));
  nb::gil_scoped_release release;
  va::contact_margins(frames.data(), orientation_rows.data(), full.data(), p, len(axis_rows),
                      points.data(), np, axis_rows.data(), minima_axes.data(), len(minima_axes),
                      at_full.data());
  va::contact_margins(frames.data(), orientation_rows.data(), base.data(), p, len(axis_rows),
                      points.data(), np, axis_rows.data(), minima_axes.data(), len(minima_axes),
                      at_base.data());
  return va::contact_largest_scale(at_full.data(), at_base.data(), lows.data(), rows);
}

}  // namespace

void bind_contact_margins(nb::module_& m) {
  m.def("contact_least_margin", &contact_least_margin, "frames"_a, "orientation_rows"_a, "forces"_a,
        "points"_a, "axis_rows"_a, "minima_axes"_a, "lows"_a,
        "contacts.contact_set.least_margin: smallest G @ forces.ravel() - lows.");
  m.def("contact_largest_scale", &contact_largest_scale, "frames"_a, "orientation_rows"_a, "full"_a,
        "base"_a, "points"_a, "axis_rows"_a, "minima_axes"_a, "lows"_a,
        "contacts.contact_set.largest_scale: the largest alpha in [0, 1] meeting the rows.");
}

}  // namespace va::py
