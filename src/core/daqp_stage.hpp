// The first stage of the QP distribution on DAQP (third_party/daqp, MIT): the least-norm x
// that meets the equality rows exactly and the inequality rows within their bounds,
//   min 0.5 |x|^2  s.t.  E x = e,  lows <= G x <= uppers,
// a least-distance problem (no Hessian, no linear term), solved from cold (the same answer
// whatever came before). qp.stages certifies DAQP's active set with the exact step.
#pragma once

#include <cstdint>
#include <vector>

#include "exact.hpp"  // zeroed

extern "C" {
#include "api.h"
}

namespace va {

// The problem's arrays, one set per thread (daqp_scratch; DAQP's own workspace is its own).
struct DaqpScratch {
  std::vector<double> A, upper, lower, lam;
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

// x (size) and the inequalities' multipliers lam (m; < 0 at a lower bound, > 0 at an upper
// one) written. equality (k, size), inequality (m, size) row-major.
inline DaqpAnswer daqp_least_norm(const double* equality, const double* equality_rhs,
                                  std::int64_t k, std::int64_t size, const double* inequality,
                                  const double* lows, const double* uppers, std::int64_t m,
                                  int iter_limit, double* x, double* lam) {
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
  problem.H = nullptr;
  problem.f = nullptr;
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
  double* all_lam = zeroed(S.lam, rows);
  DAQPResult result{};
  result.x = x;
  result.lam = all_lam;
  daqp_quadprog(&result, &problem, &settings);
  for (std::int64_t r = 0; r < m; ++r) lam[r] = all_lam[k + r];
  return {result.exitflag, result.iter};
}

}  // namespace va
