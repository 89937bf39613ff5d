// The QP distribution's stages on DAQP (third_party/daqp, MIT), from cold (the same answer
// whatever came before); qp.stages certifies DAQP's active set with the exact step.
//  - daqp_least_norm, stage 1: the least-norm x that meets the equality rows exactly and the
//    inequality rows within their bounds, min 0.5 |x|^2 s.t. E x = e, lows <= G x <= uppers
//    (a least-distance problem: no Hessian, no linear term);
//  - daqp_closest, stages 2 and 3 at once (an infeasible request): the closest wrench,
//    regularised, min 0.5 |x|^2 + 0.5 / eps sum_a omega_a (A x - w)_a^2 s.t. D x = d and the
//    bounded rows, whose active set tends to the closest wrench's least-norm answer's as eps
//    goes to 0 (the exact step then finds that answer on it).
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include "exact.hpp"  // zeroed

extern "C" {
#include "api.h"
}

namespace va {

// The problem's arrays, one set per thread (daqp_scratch; DAQP's own workspace is its own).
struct DaqpScratch {
  std::vector<double> A, upper, lower, lam, H, f;
  std::vector<int> sense;
};

inline DaqpScratch& daqp_scratch() {
  thread_local DaqpScratch scratch;
  return scratch;
}

struct DaqpAnswer {
  int exitflag = 0;    // DAQP's: 1 optimal, -1 infeasible, < 0 failed
  int iterations = 0;  // active-set changes
};

// min 0.5 x' H x + f' x (H, f null: 0.5 |x|^2) s.t. the k equality rows exactly and the m
// inequality rows within their bounds; x (size) and the inequalities' multipliers lam (m; < 0
// at a lower bound, > 0 at an upper one) written. equality (k, size), inequality (m, size),
// H (size, size) row-major.
inline DaqpAnswer daqp_rows(double* H, double* f, const double* equality,
                            const double* equality_rhs, std::int64_t k, std::int64_t size,
                            const double* inequality, const double* lows, const double* uppers,
                            std::int64_t m, int iter_limit, double* x, double* lam) {
  const std::int64_t rows = k + m;
  DaqpScratch& S = daqp_scratch();
  double* A = zeroed(S.A, rows * size);
  double* upper = zeroed(S.upper, rows);
  double* lower = zeroed(S.lower, rows);
  int* sense = zeroed(S.sense, rows);
  for (std::int64_t r = 0; r < k; ++r) {
    for (std::int64_t j = 0; j < size; ++j) A[r * size + j] = equality[r * size + j];
    upper[r] = lower[r] = equality_rhs[r];
    sense[r] = DAQP_ACTIVE | DAQP_IMMUTABLE;
  }
  for (std::int64_t r = 0; r < m; ++r) {
    for (std::int64_t j = 0; j < size; ++j) A[(k + r) * size + j] = inequality[r * size + j];
    upper[k + r] = uppers[r];
    lower[k + r] = lows[r];
  }
  DAQPProblem problem{};
  problem.n = static_cast<int>(size);
  problem.m = static_cast<int>(rows);
  problem.ms = 0;
  problem.H = H;
  problem.f = f;
  problem.A = A;
  problem.bupper = upper;
  problem.blower = lower;
  problem.sense = sense;
  problem.break_points = nullptr;
  problem.nh = 0;
  problem.problem_type = 0;
  DAQPSettings settings;
  daqp_default_settings(&settings);
  settings.iter_limit = iter_limit;
  if (H != nullptr) settings.eps_prox = 0.0;  // positive definite: no proximal iterations
  double* all_lam = zeroed(S.lam, rows);
  DAQPResult result{};
  result.x = x;
  result.lam = all_lam;
  daqp_quadprog(&result, &problem, &settings);
  for (std::int64_t r = 0; r < m; ++r) lam[r] = all_lam[k + r];
  return {result.exitflag, result.iter};
}

// Stage 1: see the file's head.
inline DaqpAnswer daqp_least_norm(const double* equality, const double* equality_rhs,
                                  std::int64_t k, std::int64_t size, const double* inequality,
                                  const double* lows, const double* uppers, std::int64_t m,
                                  int iter_limit, double* x, double* lam) {
  return daqp_rows(nullptr, nullptr, equality, equality_rhs, k, size, inequality, lows, uppers, m,
                   iter_limit, x, lam);
}

// Stages 2 and 3, regularised (the file's head): equality (k, size) holds the design rows D
// (the first `design`), then the request's rows A with weights (k - design, > 0); eps is
// relative to the largest weight.
inline DaqpAnswer daqp_closest(const double* equality, const double* equality_rhs, std::int64_t k,
                               std::int64_t design, std::int64_t size, const double* weights,
                               const double* inequality, const double* lows, const double* uppers,
                               std::int64_t m, int iter_limit, double eps, double* x, double* lam) {
  DaqpScratch& S = daqp_scratch();
  double* H = zeroed(S.H, size * size);
  double* f = zeroed(S.f, size);
  double largest = 0.0;
  for (std::int64_t i = 0; i < k - design; ++i) largest = std::max(largest, weights[i]);
  for (std::int64_t i = 0; i < k - design; ++i) {
    const double* row = equality + (design + i) * size;
    const double weight = weights[i] / (largest * eps);
    for (std::int64_t a = 0; a < size; ++a) {
      f[a] -= weight * equality_rhs[design + i] * row[a];
      for (std::int64_t b = 0; b < size; ++b) H[a * size + b] += weight * row[a] * row[b];
    }
  }
  for (std::int64_t a = 0; a < size; ++a) H[a * size + a] += 1.0;
  return daqp_rows(H, f, equality, equality_rhs, design, size, inequality, lows, uppers, m,
                   iter_limit, x, lam);
}

}  // namespace va
