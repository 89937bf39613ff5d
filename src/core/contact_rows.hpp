// The contacts' rows over a chain's free coordinates, in the compiled QP (the point kind's
// pyramid and least normal force, the flat kind's sole), and the contact margins of the
// controller's yield policy. The rows are those of virtual_actuators.contacts' numpy kinds
// (contact_rows, ContactSet.rows), which the tests compare them with
// (tests/test_core_parity_qp.py, test_qp_paths.py).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "linalg.hpp"
#include "scalar.hpp"

namespace va {

// A chain's free basis N_i: rows a (its n force entries) of the basis, columns start .. start +
// d_i, in a row-major array of `free` columns (the view basis[i n:(i+1) n, start:]).
struct BasisView {
  const double* data;
  std::int64_t free;
  double operator()(std::int64_t a, std::int64_t j) const { return data[a * free + j]; }
};

// The pyramid's rows (>= 0, in the world) about `normal` into out (5, 3): returns how many.
// point.face_rows.
inline std::int64_t face_rows(const double* normal, double friction, bool with_normal,
                              double out[][3]) {
  std::int64_t count = 0;
  if (with_normal) {
    for (int c = 0; c < 3; ++c) out[0][c] = normal[c];
    count = 1;
  }
  if (friction < 0.0) return count;
  double helper[3] = {1.0, 0.0, 0.0};
  if (!(std::abs(normal[0]) < 0.9)) {
    helper[0] = 0.0;
    helper[1] = 1.0;
  }
  double t1[3];
  t1[0] = normal[1] * helper[2] - normal[2] * helper[1];
  t1[1] = normal[2] * helper[0] - normal[0] * helper[2];
  t1[2] = normal[0] * helper[1] - normal[1] * helper[0];
  const double length = std::sqrt(t1[0] * t1[0] + t1[1] * t1[1] + t1[2] * t1[2]);
  for (int c = 0; c < 3; ++c) t1[c] /= length;
  double t2[3];
  t2[0] = normal[1] * t1[2] - normal[2] * t1[1];
  t2[1] = normal[2] * t1[0] - normal[0] * t1[2];
  t2[2] = normal[0] * t1[1] - normal[1] * t1[0];
  for (int face = 0; face < 4; ++face) {
    const double* tangent = face < 2 ? t1 : t2;
    const double sign = face % 2 == 0 ? -1.0 : 1.0;
    for (int c = 0; c < 3; ++c) out[count][c] = friction * normal[c] + sign * tangent[c];
    ++count;
  }
  return count;
}

// rows[:count] (world vectors) into {O}'s axes in place: R_O^T v. point.to_o.
inline void to_o(const double rot_o[3][3], double rows[][3], std::int64_t count) {
  for (std::int64_t f = 0; f < count; ++f) {
    const double v0 = rows[f][0], v1 = rows[f][1], v2 = rows[f][2];
    for (int c = 0; c < 3; ++c) rows[f][c] = rot_o[0][c] * v0 + rot_o[1][c] * v1 + rot_o[2][c] * v2;
  }
}

// vector . f_i >= low over z_i: the row into out (d_i entries), the bound into lows[row].
// point.force_row.
inline void force_row(const double* vector, const std::int64_t* axis_rows, std::int64_t n,
                      const double* chain_x0, const BasisView& chain_basis, std::int64_t d_i,
                      double* out, double* lows, std::int64_t row, double low) {
  double constant = 0.0;
  for (std::int64_t a = 0; a < n; ++a) {
    const std::int64_t component = axis_rows[a];
    if (component >= 3) continue;
    const double weight = vector[component];
    constant += weight * chain_x0[a];
    for (std::int64_t j = 0; j < d_i; ++j) out[j] += weight * chain_basis(a, j);
  }
  lows[row] = low - constant;
}

// The sole's six rows >= 0 over z_i into out (6 rows of `free` columns, from the chain's start)
// and lows (6). placement: the reaction frame's row of the frames; sole: its table row (flag,
// half length, half width); friction < 0 for none. flat.sole_rows.
inline void sole_rows(const double* placement, const double rot_o[3][3], const double* sole,
                      double friction, const double offset[3], const std::int64_t* axis_rows,
                      std::int64_t n, const double* chain_x0, const BasisView& chain_basis,
                      std::int64_t d_i, double* out, std::int64_t out_stride, double* lows) {
  double frame_o[3][3];  // columns: the reaction frame's axes in {O}
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) {
      double acc = 0.0;
      for (int k = 0; k < 3; ++k) acc += rot_o[k][r] * placement[3 * k + c];
      frame_o[r][c] = acc;
    }
  const double mu = friction >= 0.0 ? friction : 0.0;
  const double halves[3] = {sole[2], sole[1], mu * py_min(sole[1], sole[2])};
  double entry[6] = {};   // the moment row over F_i (n <= 6 axes)
  double normal[6] = {};  // the force along the normal
  for (int c = 0; c < 3; ++c) {
    const double e0 = frame_o[0][c], e1 = frame_o[1][c], e2 = frame_o[2][c];
    const double lever[3] = {e1 * offset[2] - e2 * offset[1], e2 * offset[0] - e0 * offset[2],
                             e0 * offset[1] - e1 * offset[0]};
    for (std::int64_t a = 0; a < n; ++a) {
      const std::int64_t component = axis_rows[a];
      if (component >= 3) {
        entry[a] = frame_o[component - 3][c];
      } else {
        entry[a] = lever[component];
        normal[a] = frame_o[component][2];
      }
    }
    for (int side = 0; side < 2; ++side) {
      const double sign = side == 0 ? -1.0 : 1.0;
      const int row = 2 * c + side;
      double constant = 0.0;
      for (std::int64_t a = 0; a < n; ++a) {
        const double weight = halves[c] * normal[a] + sign * entry[a];
        constant += weight * chain_x0[a];
        for (std::int64_t j = 0; j < d_i; ++j)
          out[row * out_stride + j] += weight * chain_basis(a, j);
      }
      lows[row] = -constant;
    }
  }
}

}  // namespace va

namespace va {

// A contact's pyramid rows over its force F_i (n entries) into out (5, n),
// zeros, and lows; parameters: point.parameters' row (friction, least normal force, normal row,
// frame normal, world normal); placement: the reaction frame's row of the frames. Returns how
// many rows.
inline std::int64_t point_kernel_rows(const double* parameters, const double* placement,
                                      const double rot_o[3][3], const std::int64_t* axis_rows,
                                      std::int64_t n, const double* identity, double* out,
                                      double* lows) {
  double normal[3];
  for (int c = 0; c < 3; ++c)
    normal[c] = parameters[3] > 0.0 ? placement[3 * c + 2] : parameters[4 + c];
  double faces[5][3];
  const bool with_normal = parameters[2] > 0.0;
  const std::int64_t count = face_rows(normal, parameters[0], with_normal, faces);
  to_o(rot_o, faces, count);
  std::vector<double> particular(static_cast<std::size_t>(n), 0.0);
  const BasisView basis{identity, n};
  for (std::int64_t f = 0; f < count; ++f) {
    const double low = with_normal && f == 0 ? parameters[1] : 0.0;
    force_row(faces[f], axis_rows, n, particular.data(), basis, n, out + f * n, lows, f, low);
  }
  return count;
}

// The contact rows' values G @ forces.ravel() (no sole rows) into out: contact_set.margins.
// forces (p, n); points (np = p or 0, 7); orientation_rows: {O} then each reaction frame.
inline void contact_margins(const double* frames, const std::int64_t* orientation_rows,
                            const double* forces, std::int64_t p, std::int64_t n,
                            const double* points, std::int64_t np, const std::int64_t* axis_rows,
                            const std::int64_t* minima_axes, std::int64_t nm, double* out) {
  std::int64_t row = 0;
  for (std::int64_t m = 0; m < nm; ++m)
    for (std::int64_t c = 0; c < p; ++c) out[row++] = forces[c * n + minima_axes[m]];
  if (np == 0) return;
  double rot_o[3][3];
  const double* o = frames + 12 * orientation_rows[0];
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) rot_o[r][c] = o[3 * r + c];
  std::vector<double> identity(static_cast<std::size_t>(n * n), 0.0);
  for (std::int64_t a = 0; a < n; ++a) identity[a * n + a] = 1.0;
  std::vector<double> rows(static_cast<std::size_t>(5 * n));
  double lows[5];
  for (std::int64_t c = 0; c < p; ++c) {
    std::fill(rows.begin(), rows.end(), 0.0);
    const double* placement = frames + 12 * orientation_rows[1 + c];
    const std::int64_t count = point_kernel_rows(points + 7 * c, placement, rot_o, axis_rows, n,
                                                 identity.data(), rows.data(), lows);
    for (std::int64_t f = 0; f < count; ++f) {
      double total = 0.0;
      for (std::int64_t a = 0; a < n; ++a) total += rows[f * n + a] * forces[c * n + a];
      out[row++] = total;
    }
  }
}

// Smallest G @ forces.ravel() - lows (contact_set.least_margin); values: scratch of nl.
inline double contact_least_margin(const double* values, const double* lows, std::int64_t nl) {
  double least = INF;
  for (std::int64_t r = 0; r < nl; ++r) least = py_min(least, values[r] - lows[r]);
  return least;
}

// The largest alpha in [0, 1] with at_base + alpha (at_full - at_base) >= lows; 0 when none
// (contact_set.largest_scale, from the margins at the full request and at its base).
inline double contact_largest_scale(const double* at_full, const double* at_base,
                                    const double* lows, std::int64_t nl) {
  double upper = 1.0, lower = 0.0;
  for (std::int64_t r = 0; r < nl; ++r) {
    const double slope = at_full[r] - at_base[r];
    if (slope == 0.0) {
      if (at_base[r] < lows[r]) return 0.0;
      continue;
    }
    const double ratio = (lows[r] - at_base[r]) / slope;
    if (slope < 0.0)
      upper = py_min(upper, ratio);
    else
      lower = py_max(lower, ratio);
  }
  return lower > upper ? 0.0 : py_min(upper, 1.0);
}

}  // namespace va
