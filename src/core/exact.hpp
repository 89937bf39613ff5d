// The QP's exact final step on an active set (see virtual_actuators.distribution.qp.exact, whose
// Python is the fallback without the core and the oracle of tests/test_core_parity_qp.py).
#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

#include "contact_rows.hpp"
#include "linalg.hpp"

namespace va {

constexpr double DEPENDENT_TOL = 1e-9;
constexpr double NEARLY_DEPENDENT_TOL = 1e-6;  // tolerances.NEARLY_DEPENDENT_TOL
// exact.EXACT_STEPS: active-set changes allowed before ProxQP's answer is kept.
constexpr std::int64_t EXACT_STEPS = 16;

// The rows of one active-set problem: equality (k, size) with the design rows first, their
// right-hand sides, inequality (m, size) bounded by lows and uppers (row-major).
struct ExactRows {
  const double* equality;
  const double* equality_rhs;
  std::int64_t k, size, design;
  const double* weights;  // (k - design,)
  const double* inequality;
  const double* lows;
  const double* uppers;
  std::int64_t m;
};

// Scratch of the exact step, one per thread (exact_scratch): a warm call allocates nothing.
// zeroed() gives each array the sizes and the zeros the per-call arrays had, keeping capacity.
struct ExactScratch {
  std::vector<std::int64_t> order, kept, side, deferred;
  std::vector<double> factor_row, coefficients, combination, row, target, multipliers, gradient,
      fit, norm, bounds;
  Arr basis, lower, spread, columns, upper;
};

inline ExactScratch& exact_scratch() {
  thread_local ExactScratch scratch;
  return scratch;
}

template <typename T>
inline T* zeroed(std::vector<T>& vector, std::int64_t size) {
  vector.assign(static_cast<std::size_t>(size), T{});
  return vector.data();
}

inline Arr& zeroed(Arr& array, std::int64_t rows, std::int64_t columns) {
  array.v.assign(static_cast<std::size_t>(rows * columns), 0.0);
  array.d0 = rows;
  array.d1 = columns;
  array.d2 = 1;
  return array;
}

// Row `index` of [equality; inequality] into out. exact._row.
inline void exact_row(const ExactRows& R, std::int64_t index, double* out) {
  for (std::int64_t j = 0; j < R.size; ++j)
    out[j] =
        index < R.k ? R.equality[index * R.size + j] : R.inequality[(index - R.k) * R.size + j];
}

// Gram-Schmidt of row `index` against the `rank` rows kept: the new rank, and whether the row
// was deferred (defer, and what it adds below NEARLY_DEPENDENT_TOL of its norm). exact._add_row.
inline std::int64_t exact_add_row(const ExactRows& R, std::int64_t index, std::int64_t rank,
                                  bool defer, Arr& basis, Arr& lower, std::int64_t* kept,
                                  double* row, double* coefficients, bool& deferred) {
  const std::int64_t size = R.size;
  deferred = false;
  exact_row(R, index, row);
  double norm = 0.0;
  for (std::int64_t j = 0; j < size; ++j) norm += row[j] * row[j];
  norm = std::sqrt(norm);
  if (norm == 0.0) return rank;
  for (std::int64_t b = 0; b < rank; ++b) coefficients[b] = 0.0;
  double rest = norm;
  for (int sweep = 0; sweep < 3; ++sweep) {
    const double before = rest;
    for (std::int64_t b = 0; b < rank; ++b) {
      double dot = 0.0;
      for (std::int64_t j = 0; j < size; ++j) dot += basis(b, j) * row[j];
      coefficients[b] += dot;
      for (std::int64_t j = 0; j < size; ++j) row[j] -= dot * basis(b, j);
    }
    rest = 0.0;
    for (std::int64_t j = 0; j < size; ++j) rest += row[j] * row[j];
    rest = std::sqrt(rest);
    if (rank == 0 || rest > 0.7 * before || rest <= DEPENDENT_TOL * norm) break;
  }
  if (rest <= DEPENDENT_TOL * norm) return rank;
  if (defer && rest <= NEARLY_DEPENDENT_TOL * norm) {
    deferred = true;
    return rank;
  }
  for (std::int64_t j = 0; j < size; ++j) basis(rank, j) = row[j] / rest;
  for (std::int64_t b = 0; b < rank; ++b) lower(rank, b) = coefficients[b];
  lower(rank, rank) = rest;
  kept[rank] = index;
  return rank + 1;
}

// Gram-Schmidt on the design rows, the active rows, then the request rows, a nearly dependent
// row taken again after the others of its group. exact._factor.
// Returns (rank, rank of the design and active rows).
inline std::pair<std::int64_t, std::int64_t> exact_factor(const ExactRows& R,
                                                          const std::int64_t* side, Arr& basis,
                                                          Arr& lower, std::int64_t* kept) {
  const std::int64_t k = R.k, size = R.size;
  ExactScratch& S = exact_scratch();
  std::int64_t* order = zeroed(S.order, k + R.m);
  std::int64_t count = 0;
  for (std::int64_t index = 0; index < R.design; ++index) order[count++] = index;
  for (std::int64_t r = 0; r < R.m; ++r)
    if (side[r] != 0) order[count++] = k + r;
  const std::int64_t fixed = count;
  for (std::int64_t index = R.design; index < k; ++index) order[count++] = index;
  double* row = zeroed(S.factor_row, size);
  double* coefficients = zeroed(S.coefficients, size);
  std::int64_t* deferred = zeroed(S.deferred, count);
  std::int64_t rank = 0, rank_fixed = 0;
  bool later = false;
  for (int group = 0; group < 2; ++group) {
    const std::int64_t start = group == 0 ? 0 : fixed, stop = group == 0 ? fixed : count;
    std::int64_t waiting = 0;
    for (std::int64_t position = start; position < stop; ++position) {
      if (rank == size) break;  // every later row depends on the kept ones (checked after)
      rank = exact_add_row(R, order[position], rank, true, basis, lower, kept, row, coefficients,
                           later);
      if (later) deferred[waiting++] = order[position];
    }
    for (std::int64_t position = 0; position < waiting; ++position) {
      if (rank == size) break;
      rank = exact_add_row(R, deferred[position], rank, false, basis, lower, kept, row,
                           coefficients, later);
    }
    if (group == 0) rank_fixed = rank;
  }
  return {rank, rank_fixed};
}

// lower[start:stop, start:stop]^T out = rhs. exact._back.
inline void exact_back(const Arr& lower, std::int64_t start, std::int64_t stop, const double* rhs,
                       double* out) {
  for (std::int64_t r = stop - 1; r > start - 1; --r) {
    double acc = rhs[r];
    for (std::int64_t b = r + 1; b < stop; ++b) acc -= lower(b, r) * out[b];
    out[r] = acc / lower(r, r);
  }
}

// The answer on one active set and its multipliers (x; fit and norm over k + m). exact._solve.
inline void exact_solve(const ExactRows& R, const double* bounds, const std::int64_t* side,
                        bool exact, double* x, double* fit, double* norm) {
  const std::int64_t k = R.k, size = R.size, m = R.m;
  ExactScratch& S = exact_scratch();
  Arr& basis = zeroed(S.basis, size, size);
  Arr& lower = zeroed(S.lower, size, size);
  std::int64_t* kept = zeroed(S.kept, size);
  const auto [rank, fixed] = exact_factor(R, side, basis, lower, kept);
  double* combination = zeroed(S.combination, size);
  for (std::int64_t r = 0; r < fixed; ++r) {
    const std::int64_t index = kept[r];
    double acc = index < k ? R.equality_rhs[index] : bounds[index - k];
    for (std::int64_t b = 0; b < r; ++b) acc -= lower(r, b) * combination[b];
    combination[r] = acc / lower(r, r);
  }
  const std::int64_t requests = k - R.design, extra = rank - fixed;
  double* row = zeroed(S.row, size);
  Arr& spread = zeroed(S.spread, requests, size);
  double* target = zeroed(S.target, requests);
  for (std::int64_t i = 0; i < requests; ++i) {
    exact_row(R, R.design + i, row);
    for (std::int64_t b = 0; b < rank; ++b) {
      double dot = 0.0;
      for (std::int64_t j = 0; j < size; ++j) dot += basis(b, j) * row[j];
      spread(i, b) = dot;
    }
    double acc = R.equality_rhs[R.design + i];
    for (std::int64_t b = 0; b < fixed; ++b) acc -= spread(i, b) * combination[b];
    const double root = std::sqrt(R.weights[i]);
    target[i] = root * acc;
  }
  Arr& columns = zeroed(S.columns, extra, requests);
  Arr& upper = zeroed(S.upper, extra, extra);
  for (std::int64_t c = 0; c < extra; ++c) {
    for (std::int64_t i = 0; i < requests; ++i)
      columns(c, i) = std::sqrt(R.weights[i]) * spread(i, fixed + c);
    for (int sweep = 0; sweep < 2; ++sweep)
      for (std::int64_t b = 0; b < c; ++b) {
        double dot = 0.0;
        for (std::int64_t i = 0; i < requests; ++i) dot += columns(b, i) * columns(c, i);
        upper(b, c) += dot;
        for (std::int64_t i = 0; i < requests; ++i) columns(c, i) -= dot * columns(b, i);
      }
    double length = 0.0;
    for (std::int64_t i = 0; i < requests; ++i) length += columns(c, i) * columns(c, i);
    upper(c, c) = std::sqrt(length);
    for (std::int64_t i = 0; i < requests; ++i) columns(c, i) /= upper(c, c);
  }
  for (std::int64_t c = extra - 1; c > -1; --c) {
    double acc = 0.0;
    for (std::int64_t i = 0; i < requests; ++i) acc += columns(c, i) * target[i];
    for (std::int64_t b = c + 1; b < extra; ++b) acc -= upper(c, b) * combination[fixed + b];
    combination[fixed + c] = acc / upper(c, c);
  }
  for (std::int64_t j = 0; j < size; ++j) {
    double acc = 0.0;
    for (std::int64_t b = 0; b < rank; ++b) acc += basis(b, j) * combination[b];
    x[j] = acc;
  }
  double* multipliers = zeroed(S.multipliers, size);
  exact_back(lower, 0, rank, combination, multipliers);
  for (std::int64_t r = 0; r < k + m; ++r) norm[r] = 0.0;
  for (std::int64_t r = 0; r < rank; ++r) norm[kept[r]] = multipliers[r];
  for (std::int64_t r = 0; r < k + m; ++r) fit[r] = 0.0;
  if (exact) return;
  double* gradient = zeroed(S.gradient, size);
  for (std::int64_t i = 0; i < requests; ++i) {
    double acc = -R.equality_rhs[R.design + i];
    for (std::int64_t b = 0; b < rank; ++b) acc += spread(i, b) * combination[b];
    for (std::int64_t b = 0; b < fixed; ++b) gradient[b] += R.weights[i] * acc * spread(i, b);
  }
  exact_back(lower, 0, fixed, gradient, multipliers);
  for (std::int64_t r = 0; r < fixed; ++r) fit[kept[r]] = multipliers[r];
}

// The exact answer on the active set that guess names (exact.exact_step): x (size) and z (m)
// written, returns whether the KKT conditions hold (z all zero otherwise).
inline bool exact_step(const ExactRows& R, const double* guess, bool exact, double active_tol,
                       double tol, std::int64_t max_steps, double* x, double* z) {
  const std::int64_t k = R.k, m = R.m, size = R.size;
  ExactScratch& S = exact_scratch();
  std::int64_t* side = zeroed(S.side, m);
  for (std::int64_t r = 0; r < m; ++r) {
    if (guess[r] < -active_tol)
      side[r] = -1;
    else if (guess[r] > active_tol)
      side[r] = 1;
  }
  for (std::int64_t j = 0; j < size; ++j) x[j] = 0.0;
  double* fit = zeroed(S.fit, k + m);
  double* norm = zeroed(S.norm, k + m);
  double* bounds = zeroed(S.bounds, m);
  for (std::int64_t r = 0; r < m; ++r) z[r] = 0.0;
  for (std::int64_t step = 0; step < max_steps + 1; ++step) {
    for (std::int64_t r = 0; r < m; ++r) bounds[r] = side[r] < 0 ? R.lows[r] : R.uppers[r];
    exact_solve(R, bounds, side, exact, x, fit, norm);
    double worst = tol;
    std::int64_t leave = -1;
    for (std::int64_t r = 0; r < m; ++r) {
      if (side[r] == 0) continue;
      const double s = static_cast<double>(side[r]);
      const double wrong = exact || std::abs(fit[k + r]) <= tol ? s * norm[k + r] : s * fit[k + r];
      if (wrong > worst) {
        worst = wrong;
        leave = r;
      }
    }
    if (leave >= 0) {
      side[leave] = 0;
      continue;
    }
    worst = tol;
    std::int64_t enter = -1, enter_side = 0;
    bool consistent = true;
    for (std::int64_t r = 0; r < k + m; ++r) {
      double acc = 0.0;
      if (r < k) {
        for (std::int64_t j = 0; j < size; ++j) acc += R.equality[r * size + j] * x[j];
      } else {
        for (std::int64_t j = 0; j < size; ++j) acc += R.inequality[(r - k) * size + j] * x[j];
      }
      if (r < R.design || (r < k && exact)) {
        consistent &= std::abs(acc - R.equality_rhs[r]) <= tol;
      } else if (r < k) {
        continue;
      } else if (side[r - k] != 0) {
        consistent &= std::abs(acc - bounds[r - k]) <= tol;
      } else if (R.lows[r - k] - acc > worst) {
        worst = R.lows[r - k] - acc;
        enter = r - k;
        enter_side = -1;
      } else if (acc - R.uppers[r - k] > worst) {
        worst = acc - R.uppers[r - k];
        enter = r - k;
        enter_side = 1;
      }
    }
    // a violated row enters before the rows are checked: on an active set that still misses
    // rows x can be large, its rows met only to round-off of |x|; the answer is checked below
    if (enter >= 0) {
      side[enter] = enter_side;
      continue;
    }
    if (!consistent) break;
    for (std::int64_t r = 0; r < m; ++r)
      if (side[r] != 0)
        z[r] = static_cast<double>(side[r]) * (std::abs(fit[k + r]) + std::abs(norm[k + r]));
    return true;
  }
  return false;
}

}  // namespace va
