// Small dense linear algebra of the compiled distribution: plain loops, no BLAS, in a fixed order
// of operations (no FMA contraction: CMakeLists.txt), so that a tick's bits do not depend on the
// machine. Checked against numpy in the tests (tests/test_core_parity.py, test_realtime.py).
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

#include "scalar.hpp"

namespace va {

// virtual_actuators.distribution.tolerances
constexpr double JACOBIAN_FLOOR = 1e-12;
constexpr double ROUNDING = 1e-12;
constexpr double ILL_CONDITIONED = 1e10;
constexpr double CONSTRAINT_TOL = 1e-10;
constexpr double NEAR_SINGULAR = 1e-7;
constexpr double INF = std::numeric_limits<double>::infinity();

// A dense row-major array of up to three dimensions, zero-filled (numpy's np.zeros).
struct Arr {
  std::vector<double> v;
  std::int64_t d0 = 0, d1 = 1, d2 = 1;
  Arr() = default;
  explicit Arr(std::int64_t a, std::int64_t b = 1, std::int64_t c = 1)
      : v(static_cast<std::size_t>(a * b * c), 0.0), d0(a), d1(b), d2(c) {}
  double* data() { return v.data(); }
  const double* data() const { return v.data(); }
  double& operator()(std::int64_t i) { return v[static_cast<std::size_t>(i)]; }
  double operator()(std::int64_t i) const { return v[static_cast<std::size_t>(i)]; }
  double& operator()(std::int64_t i, std::int64_t j) {
    return v[static_cast<std::size_t>(i * d1 + j)];
  }
  double operator()(std::int64_t i, std::int64_t j) const {
    return v[static_cast<std::size_t>(i * d1 + j)];
  }
  double& operator()(std::int64_t i, std::int64_t j, std::int64_t k) {
    return v[static_cast<std::size_t>((i * d1 + j) * d2 + k)];
  }
  double operator()(std::int64_t i, std::int64_t j, std::int64_t k) const {
    return v[static_cast<std::size_t>((i * d1 + j) * d2 + k)];
  }
  // The sub-array at first index i (d1 x d2 entries).
  double* at(std::int64_t i) { return v.data() + i * d1 * d2; }
  const double* at(std::int64_t i) const { return v.data() + i * d1 * d2; }
};

// Invert the leading m x m block of `matrix` into `inv` by Gauss-Jordan with partial pivoting
// (`a`: scratch); the three have leading dimension ld. Returns ||A||_inf ||A^-1||_inf (inf
// when exactly singular).
inline double inverse_into(const double* matrix, std::int64_t ld, std::int64_t m, double* a,
                           double* inv) {
  for (std::int64_t i = 0; i < m; ++i)
    for (std::int64_t j = 0; j < m; ++j) {
      a[i * ld + j] = matrix[i * ld + j];
      inv[i * ld + j] = i == j ? 1.0 : 0.0;
    }
  double norm = 0.0;
  for (std::int64_t i = 0; i < m; ++i) {
    double row = 0.0;
    for (std::int64_t j = 0; j < m; ++j) row += std::abs(matrix[i * ld + j]);
    norm = py_max(norm, row);
  }
  for (std::int64_t col = 0; col < m; ++col) {
    std::int64_t pivot = col;
    for (std::int64_t r = col + 1; r < m; ++r)
      if (std::abs(a[r * ld + col]) > std::abs(a[pivot * ld + col])) pivot = r;
    if (a[pivot * ld + col] == 0.0) return INF;
    if (pivot != col)
      for (std::int64_t j = 0; j < m; ++j) {
        std::swap(a[col * ld + j], a[pivot * ld + j]);
        std::swap(inv[col * ld + j], inv[pivot * ld + j]);
      }
    const double scale = 1.0 / a[col * ld + col];
    for (std::int64_t j = 0; j < m; ++j) {
      a[col * ld + j] *= scale;
      inv[col * ld + j] *= scale;
    }
    for (std::int64_t r = 0; r < m; ++r)
      if (r != col && a[r * ld + col] != 0.0) {
        const double factor = a[r * ld + col];
        for (std::int64_t j = 0; j < m; ++j) {
          a[r * ld + j] -= factor * a[col * ld + j];
          inv[r * ld + j] -= factor * inv[col * ld + j];
        }
      }
  }
  double norm_inv = 0.0;
  for (std::int64_t i = 0; i < m; ++i) {
    double row = 0.0;
    for (std::int64_t j = 0; j < m; ++j) row += std::abs(inv[i * ld + j]);
    norm_inv = py_max(norm_inv, row);
  }
  double estimate = norm * norm_inv;
  if (!std::isfinite(estimate)) estimate = INF;
  return estimate;
}

// The inverse of a square (m, m) matrix into inv, and its condition estimate.
//
inline double invert(const Arr& matrix, Arr& inv) {
  const std::int64_t m = matrix.d0;
  inv = Arr(m, m);
  Arr scratch(m, m);
  return inverse_into(matrix.data(), m, m, scratch.data(), inv.data());
}

// out (rows) = a (rows, cols) x.
inline void mv(const Arr& a, const double* x, double* out) {
  for (std::int64_t r = 0; r < a.d0; ++r) {
    double acc = 0.0;
    for (std::int64_t k = 0; k < a.d1; ++k) acc += a(r, k) * x[k];
    out[r] = acc;
  }
}

// a b with the zero entries of a skipped.
inline Arr mm(const Arr& a, const Arr& b) {
  Arr out(a.d0, b.d1);
  for (std::int64_t r = 0; r < a.d0; ++r)
    for (std::int64_t k = 0; k < a.d1; ++k) {
      const double value = a(r, k);
      if (value != 0.0)
        for (std::int64_t c = 0; c < b.d1; ++c) out(r, c) += value * b(k, c);
    }
  return out;
}

// max(||D^-1 A||_inf, 1) ||A^-1 D||_inf with D = diag(row_scale).
inline double scaled_condition(const Arr& matrix, const Arr& inverse, const double* row_scale) {
  const std::int64_t m = matrix.d0;
  double norm = 0.0, norm_inv = 0.0;
  for (std::int64_t i = 0; i < m; ++i) {
    if (!(row_scale[i] > 0.0)) return INF;
    double row = 0.0, row_inv = 0.0;
    for (std::int64_t j = 0; j < m; ++j) {
      row += std::abs(matrix(i, j));
      row_inv += std::abs(inverse(i, j)) * row_scale[j];
    }
    norm = py_max(norm, row / row_scale[i]);
    norm_inv = py_max(norm_inv, row_inv);
  }
  double estimate = py_max(norm, 1.0) * norm_inv;
  if (!std::isfinite(estimate)) estimate = INF;
  return estimate;
}

// Scratch of null_rows for chains of up to `columns` columns in n dimensions.
struct NullScratch {
  Arr work, basis;
  std::vector<char> used;
  std::vector<double> vec, best_vec;
  NullScratch(std::int64_t n, std::int64_t columns)
      : work(n, columns),
        basis(n, n),
        used(static_cast<std::size_t>(columns), 0),
        vec(static_cast<std::size_t>(n)),
        best_vec(static_cast<std::size_t>(n)) {}
};

// Orthonormal rows spanning the left null space of full (n x c, full[r][j] = columns(j, r))
// into out (rows from 0): pivoted modified Gram-Schmidt, then the unit vectors of largest
// residual. Returns the last pivot over the first (0 for an exactly singular chain).
//
inline double null_rows(const Arr& columns, std::int64_t n, std::int64_t c, std::int64_t rank,
                        Arr& out, NullScratch& s) {
  Arr& work = s.work;
  Arr& basis = s.basis;
  for (std::int64_t r = 0; r < n; ++r)
    for (std::int64_t j = 0; j < c; ++j) work(r, j) = columns(j, r);
  for (std::int64_t j = 0; j < c; ++j) s.used[static_cast<std::size_t>(j)] = 0;
  double first = 0.0, last = 0.0;
  for (std::int64_t step = 0; step < rank; ++step) {
    std::int64_t best = -1;
    double best_norm = -1.0;
    for (std::int64_t j = 0; j < c; ++j)
      if (!s.used[static_cast<std::size_t>(j)]) {
        double sum = 0.0;
        for (std::int64_t r = 0; r < n; ++r) sum += work(r, j) * work(r, j);
        if (sum > best_norm) {
          best = j;
          best_norm = sum;
        }
      }
    const double norm = std::sqrt(best_norm);
    if (step == 0) first = norm;
    last = norm;
    s.used[static_cast<std::size_t>(best)] = 1;
    if (norm <= JACOBIAN_FLOOR) return 0.0;  // a direction produced by nothing
    for (std::int64_t r = 0; r < n; ++r) basis(r, step) = work(r, best) / norm;
    for (std::int64_t j = 0; j < c; ++j)
      if (!s.used[static_cast<std::size_t>(j)]) {
        double dot = 0.0;
        for (std::int64_t r = 0; r < n; ++r) dot += basis(r, step) * work(r, j);
        for (std::int64_t r = 0; r < n; ++r) work(r, j) -= dot * basis(r, step);
      }
  }
  double* vec = s.vec.data();
  double* best_vec = s.best_vec.data();
  for (std::int64_t step = rank; step < n; ++step) {
    double best_norm = -1.0;
    for (std::int64_t e = 0; e < n; ++e) {
      for (std::int64_t r = 0; r < n; ++r) vec[r] = 0.0;
      vec[e] = 1.0;
      for (std::int64_t b = 0; b < step; ++b) {
        const double dot = basis(e, b);
        for (std::int64_t r = 0; r < n; ++r) vec[r] -= dot * basis(r, b);
      }
      double sum = 0.0;
      for (std::int64_t r = 0; r < n; ++r) sum += vec[r] * vec[r];
      if (sum > best_norm) {
        best_norm = sum;
        for (std::int64_t r = 0; r < n; ++r) best_vec[r] = vec[r];
      }
    }
    const double norm = std::sqrt(best_norm);
    for (std::int64_t r = 0; r < n; ++r) {
      basis(r, step) = best_vec[r] / norm;
      out(step - rank, r) = basis(r, step);
    }
  }
  return first > 0.0 ? last / first : 0.0;
}

// Largest miss of an exact row (natural or hard), relative to |row| |F| + |rhs|. rows (l, n, p)
// and rhs (l, p) have the chain index last; hard (s, p, n); forces (p, n).
//
inline double constraint_error(const Arr& rows, const Arr& rhs, const Arr& hard,
                               const Arr& hard_rhs, const double* forces, std::int64_t p,
                               std::int64_t n) {
  double peak = 0.0;
  for (std::int64_t i = 0; i < p * n; ++i) peak = py_max(peak, std::abs(forces[i]));
  double worst = 0.0;
  std::vector<double> acc(static_cast<std::size_t>(p)), size(static_cast<std::size_t>(p));
  for (std::int64_t r = 0; r < rows.d0; ++r) {
    for (std::int64_t i = 0; i < p; ++i) {
      acc[i] = -rhs(r, i);
      size[i] = std::abs(rhs(r, i));
    }
    for (std::int64_t a = 0; a < n; ++a)
      for (std::int64_t i = 0; i < p; ++i) {
        acc[i] += rows(r, a, i) * forces[i * n + a];
        size[i] = py_max(size[i], std::abs(rows(r, a, i)) * peak);
      }
    for (std::int64_t i = 0; i < p; ++i)
      if (size[i] > 0.0) worst = py_max(worst, std::abs(acc[i]) / size[i]);
  }
  for (std::int64_t t = 0; t < hard.d0; ++t) {
    double a_t = -hard_rhs(t), s_t = std::abs(hard_rhs(t));
    for (std::int64_t i = 0; i < p; ++i)
      for (std::int64_t a = 0; a < n; ++a) {
        a_t += hard(t, i, a) * forces[i * n + a];
        s_t = py_max(s_t, std::abs(hard(t, i, a)) * peak);
      }
    if (s_t > 0.0) worst = py_max(worst, std::abs(a_t) / s_t);
  }
  return worst;
}

// Entry `row` (x y z rx ry rz) of a point contact's column (e_axis x d, e_axis).
//
inline double ball_entry(std::int64_t axis, std::int64_t row, double d0, double d1, double d2) {
  if (row >= 3) return row - 3 == axis ? 1.0 : 0.0;
  if (axis == 0) return row == 0 ? 0.0 : (row == 1 ? -d2 : d1);
  if (axis == 1) return row == 0 ? d2 : (row == 1 ? 0.0 : -d0);
  return row == 0 ? -d1 : (row == 1 ? d0 : 0.0);
}

// Sum in four interleaved partial sums.
inline double chain_sum(const double* values, std::int64_t count) {
  double s0 = 0.0, s1 = 0.0, s2 = 0.0, s3 = 0.0;
  const std::int64_t end = count - count % 4;
  for (std::int64_t i = 0; i < end; i += 4) {
    s0 += values[i];
    s1 += values[i + 1];
    s2 += values[i + 2];
    s3 += values[i + 3];
  }
  for (std::int64_t i = end; i < count; ++i) s0 += values[i];
  return (s0 + s1) + (s2 + s3);
}

// wrench_transform: the 6x6 map from world twists to twists of {B}'s origin in
// {O}'s axes, and {O}'s rotation; frames (nf, 12) rows b ({B}) and o ({O}). Shared by the
// partitioned and QP ticks.
inline void wrench_transform(const double* frames, std::int64_t b, std::int64_t o,
                             double rot_o[3][3], double transform[6][6]) {
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) rot_o[r][c] = frames[12 * o + 3 * r + c];
  const double x = frames[12 * b + 9], y = frames[12 * b + 10], z = frames[12 * b + 11];
  const double shift[3][3] = {{0.0, z, -y}, {-z, 0.0, x}, {y, -x, 0.0}};
  for (int r = 0; r < 6; ++r)
    for (int c = 0; c < 6; ++c) transform[r][c] = 0.0;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) {
      transform[r][c] = rot_o[c][r];
      transform[3 + r][3 + c] = rot_o[c][r];
      double acc = 0.0;
      for (int k = 0; k < 3; ++k) acc += rot_o[k][r] * shift[k][c];
      transform[r][3 + c] = acc;
    }
}

}  // namespace va
