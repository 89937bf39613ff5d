// The projectors of many chains of full column rank side by side (mode 0 of the distribution
// with BATCH_CHAINS chains or more).
#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

#include "linalg.hpp"

namespace va {

// Fewest chains for which mode 0 runs the chains of full column rank side by side.
constexpr std::int64_t BATCH_CHAINS = 8;

// Every array has the chains last (`count` of them), row-major:
//   q (>= c, n, count): each chain's c columns, the m_c constraint columns first; q[:c] is
//     overwritten with Q^T (modified Gram-Schmidt);
//   t (>= m_c, count): right-hand sides of the constraint rows (may be a row of q's array
//     beyond c: the QR never writes there);
//   ratio, bound (count); proj (n, n, count); part (n, count); null (n - c, n, count).
inline void full_rank_batch(double* q, std::int64_t n, std::int64_t count, std::int64_t c,
                            std::int64_t m_c, const double* t, double* ratio, double* bound,
                            double* proj, double* part, double* null) {
  auto Q = [&](std::int64_t j, std::int64_t r, std::int64_t i) -> double& {
    return q[(j * n + r) * count + i];
  };
  std::vector<double> first2(static_cast<std::size_t>(count), 0.0);
  std::vector<double> c_fro(static_cast<std::size_t>(count), 0.0);
  std::vector<double> acc(static_cast<std::size_t>(count));
  std::vector<char> bad(static_cast<std::size_t>(count), 0);
  Arr rr(c, c, count), x(c, c, count);
  for (std::int64_t j = 0; j < c; ++j) {
    for (std::int64_t i = 0; i < count; ++i) acc[i] = 0.0;
    for (std::int64_t r = 0; r < n; ++r)
      for (std::int64_t i = 0; i < count; ++i) acc[i] += Q(j, r, i) * Q(j, r, i);
    for (std::int64_t i = 0; i < count; ++i) {
      first2[i] = py_max(first2[i], acc[i]);
      if (j < m_c) c_fro[i] += acc[i];
    }
  }
  for (std::int64_t j = 0; j < c; ++j) {
    for (std::int64_t b = 0; b < j; ++b) {
      for (std::int64_t i = 0; i < count; ++i) acc[i] = 0.0;
      for (std::int64_t r = 0; r < n; ++r)
        for (std::int64_t i = 0; i < count; ++i) acc[i] += Q(b, r, i) * Q(j, r, i);
      for (std::int64_t i = 0; i < count; ++i) rr(b, j, i) = acc[i];
      for (std::int64_t r = 0; r < n; ++r)
        for (std::int64_t i = 0; i < count; ++i) Q(j, r, i) -= acc[i] * Q(b, r, i);
    }
    for (std::int64_t i = 0; i < count; ++i) acc[i] = 0.0;
    for (std::int64_t r = 0; r < n; ++r)
      for (std::int64_t i = 0; i < count; ++i) acc[i] += Q(j, r, i) * Q(j, r, i);
    for (std::int64_t i = 0; i < count; ++i) {
      const double norm = std::sqrt(acc[i]);
      rr(j, j, i) = norm;
      bad[i] |= !(norm > JACOBIAN_FLOOR);
      acc[i] = 1.0 / norm;
    }
    for (std::int64_t r = 0; r < n; ++r)
      for (std::int64_t i = 0; i < count; ++i) Q(j, r, i) *= acc[i];
  }
  std::vector<double> inv_fro(static_cast<std::size_t>(count), 0.0);
  std::vector<double> inv_c(static_cast<std::size_t>(count), 0.0);
  for (std::int64_t j = 0; j < c; ++j) {  // X = R^-1, column by column
    for (std::int64_t i = 0; i < count; ++i) x(j, j, i) = 1.0 / rr(j, j, i);
    for (std::int64_t row = j - 1; row >= 0; --row) {
      for (std::int64_t i = 0; i < count; ++i) acc[i] = 0.0;
      for (std::int64_t k = row + 1; k < j + 1; ++k)
        for (std::int64_t i = 0; i < count; ++i) acc[i] += rr(row, k, i) * x(k, j, i);
      for (std::int64_t i = 0; i < count; ++i) x(row, j, i) = -acc[i] / rr(row, row, i);
    }
    for (std::int64_t row = 0; row < j + 1; ++row)
      for (std::int64_t i = 0; i < count; ++i) {
        inv_fro[i] += x(row, j, i) * x(row, j, i);
        if (j < m_c) inv_c[i] += x(row, j, i) * x(row, j, i);
      }
  }
  const std::int64_t l_rows = m_c + n - c;
  for (std::int64_t i = 0; i < count; ++i) {
    const double sigma = 1.0 / std::sqrt(inv_fro[i]);
    double value = sigma / std::sqrt(first2[i]);
    if (bad[i] || !(sigma > JACOBIAN_FLOOR) || !std::isfinite(value)) value = 0.0;
    ratio[i] = value;
    double estimate = 0.0;
    if (l_rows > 0) {
      double big = c_fro[i], small = inv_c[i];
      if (n > c) {
        big = py_max(big, 1.0);
        small = py_max(small, 1.0);
      }
      estimate = static_cast<double>(l_rows) * big * small;
      if (!(estimate < INF)) estimate = INF;
    }
    bound[i] = estimate;
  }
  for (std::int64_t r = 0; r < n; ++r)
    for (std::int64_t a = r; a < n; ++a) {
      for (std::int64_t i = 0; i < count; ++i) acc[i] = 0.0;
      for (std::int64_t j = m_c; j < c; ++j)
        for (std::int64_t i = 0; i < count; ++i) acc[i] += Q(j, r, i) * Q(j, a, i);
      for (std::int64_t i = 0; i < count; ++i) {
        proj[(r * n + a) * count + i] = acc[i];
        proj[(a * n + r) * count + i] = acc[i];
      }
    }
  for (std::int64_t e = 0; e < n * count; ++e) part[e] = 0.0;
  for (std::int64_t j = 0; j < m_c; ++j) {
    for (std::int64_t i = 0; i < count; ++i) acc[i] = 0.0;
    for (std::int64_t k = 0; k < j + 1; ++k)
      for (std::int64_t i = 0; i < count; ++i) acc[i] += x(k, j, i) * t[k * count + i];
    for (std::int64_t a = 0; a < n; ++a)
      for (std::int64_t i = 0; i < count; ++i) part[a * count + i] += acc[i] * Q(j, a, i);
  }
  if (c >= n) return;
  // left null space: complete Q with the unit vectors of largest residual
  auto N = [&](std::int64_t step, std::int64_t a, std::int64_t i) -> double& {
    return null[(step * n + a) * count + i];
  };
  Arr rows2(n, count);  // squared row norms of the basis so far
  for (std::int64_t j = 0; j < c; ++j)
    for (std::int64_t e = 0; e < n; ++e)
      for (std::int64_t i = 0; i < count; ++i) rows2(e, i) += Q(j, e, i) * Q(j, e, i);
  std::vector<std::int64_t> best(static_cast<std::size_t>(count));
  std::vector<double> best_sum(static_cast<std::size_t>(count));
  Arr coef(c + n, count);
  for (std::int64_t step = 0; step < n - c; ++step) {
    for (std::int64_t i = 0; i < count; ++i) {
      best[i] = 0;
      best_sum[i] = INF;
    }
    for (std::int64_t e = 0; e < n; ++e)
      for (std::int64_t i = 0; i < count; ++i)
        if (rows2(e, i) < best_sum[i]) {
          best[i] = e;
          best_sum[i] = rows2(e, i);
        }
    for (std::int64_t i = 0; i < count; ++i) {
      const std::int64_t e = best[i];
      for (std::int64_t j = 0; j < c; ++j) coef(j, i) = Q(j, e, i);
      for (std::int64_t b = 0; b < step; ++b) coef(c + b, i) = N(b, e, i);
    }
    for (std::int64_t a = 0; a < n; ++a) {
      for (std::int64_t i = 0; i < count; ++i) N(step, a, i) = a == best[i] ? 1.0 : 0.0;
      for (std::int64_t j = 0; j < c; ++j)
        for (std::int64_t i = 0; i < count; ++i) N(step, a, i) -= coef(j, i) * Q(j, a, i);
      for (std::int64_t b = 0; b < step; ++b)
        for (std::int64_t i = 0; i < count; ++i) N(step, a, i) -= coef(c + b, i) * N(b, a, i);
    }
    for (std::int64_t i = 0; i < count; ++i) acc[i] = 0.0;
    for (std::int64_t a = 0; a < n; ++a)
      for (std::int64_t i = 0; i < count; ++i) acc[i] += N(step, a, i) * N(step, a, i);
    for (std::int64_t i = 0; i < count; ++i) acc[i] = 1.0 / std::sqrt(acc[i]);
    for (std::int64_t a = 0; a < n; ++a)
      for (std::int64_t i = 0; i < count; ++i) {
        N(step, a, i) *= acc[i];
        rows2(a, i) += N(step, a, i) * N(step, a, i);
      }
  }
}

}  // namespace va
