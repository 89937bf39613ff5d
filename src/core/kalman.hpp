// The Kalman filter's measurement update on a dense state (attitude_filter.hpp, leg_filter.hpp):
// one block of m <= 7 measurements z = H x + noise with a full m x m noise covariance R.
//   S = H P H^T + R,  K = P H^T S^-1,  x <- x + K (z - H x),  P <- (I - K H) P (I - K H)^T + K R
//   K^T
// with the optimal gain P <- P - K S K^T = P - K (P H^T)^T, kept exactly symmetric (the upper
// triangle computed, mirrored), in plain loops.
#pragma once

#include <cmath>
#include <cstdint>

namespace va::kalman {

constexpr int MAX_BLOCK = 7;

// Invert the symmetric positive m x m matrix s (row-major) into inv by Cholesky; false when it
// is not positive definite.
inline bool invert_spd(const double* s, int m, double* inv) {
  double l[MAX_BLOCK * MAX_BLOCK] = {};
  for (int i = 0; i < m; ++i)
    for (int j = 0; j <= i; ++j) {
      double sum = s[i * m + j];
      for (int k = 0; k < j; ++k) sum -= l[i * m + k] * l[j * m + k];
      if (i == j) {
        if (!(sum > 0.0)) return false;
        l[i * m + i] = std::sqrt(sum);
      } else {
        l[i * m + j] = sum / l[j * m + j];
      }
    }
  double linv[MAX_BLOCK * MAX_BLOCK] = {};  // L^-1, lower triangular
  for (int i = 0; i < m; ++i) {
    linv[i * m + i] = 1.0 / l[i * m + i];
    for (int j = 0; j < i; ++j) {
      double sum = 0.0;
      for (int k = j; k < i; ++k) sum -= l[i * m + k] * linv[k * m + j];
      linv[i * m + j] = sum / l[i * m + i];
    }
  }
  for (int i = 0; i < m; ++i)  // S^-1 = L^-T L^-1
    for (int j = 0; j < m; ++j) {
      double sum = 0.0;
      for (int k = i > j ? i : j; k < m; ++k) sum += linv[k * m + i] * linv[k * m + j];
      inv[i * m + j] = sum;
    }
  return true;
}

// The update once H P (hp, m x n: row a is (P h_a)^T, P symmetric) and S = H P H^T + R (s,
// m x m) are known: K^T = S^-1 hp, x += K y, P -= K hp (the upper triangle, mirrored: P stays
// symmetric). Every inner loop runs along a row of n (contiguous). gain: m n doubles. False
// (x, P untouched) when S is not positive definite. A residual whose squared Mahalanobis
// distance y^T S^-1 y exceeds gate is an outlier: skipped (x, P untouched), true.
inline bool apply_gain(double* x, double* P, std::int64_t n, const double* hp, double* s, int m,
                       const double* y, double* gain, double gate = INFINITY) {
  double sinv[MAX_BLOCK * MAX_BLOCK];
  for (int a = 0; a < m; ++a)  // symmetric to rounding
    for (int b = 0; b < a; ++b) s[a * m + b] = s[b * m + a] = 0.5 * (s[a * m + b] + s[b * m + a]);
  if (!invert_spd(s, m, sinv)) return false;
  if (gate < INFINITY) {
    double distance = 0.0;
    for (int a = 0; a < m; ++a)
      for (int b = 0; b < m; ++b) distance += y[a] * sinv[a * m + b] * y[b];
    if (distance > gate) return true;
  }
  for (std::int64_t k = 0; k < m * n; ++k) gain[k] = 0.0;
  for (int a = 0; a < m; ++a)
    for (int b = 0; b < m; ++b) {
      const double c = sinv[a * m + b];
      const double* h = hp + b * n;
      double* g = gain + a * n;
      for (std::int64_t i = 0; i < n; ++i) g[i] += c * h[i];
    }
  for (int a = 0; a < m; ++a) {
    const double* g = gain + a * n;
    for (std::int64_t i = 0; i < n; ++i) x[i] += g[i] * y[a];
  }
  for (std::int64_t i = 0; i < n; ++i) {
    double* row = P + i * n;
    for (int a = 0; a < m; ++a) {
      const double g = gain[a * n + i];
      const double* h = hp + a * n;
      for (std::int64_t j = i; j < n; ++j) row[j] -= g * h[j];
    }
  }
  for (std::int64_t i = 0; i < n; ++i)
    for (std::int64_t j = i + 1; j < n; ++j) P[j * n + i] = P[i * n + j];
  return true;
}

// One block update of (x, P) (n states, P row-major n x n, symmetric) by the residual
// y = z - H x (m), H (m x n) and R (m x m), both row-major. scratch: 2 n m doubles. Returns
// false (and leaves x, P as they were) when S is not positive definite; a residual beyond gate
// (apply_gain) is skipped.
inline bool update(double* x, double* P, std::int64_t n, const double* H, const double* R, int m,
                   const double* y, double* scratch, double gate = INFINITY) {
  double* hp = scratch;  // H P (m x n)
  double s[MAX_BLOCK * MAX_BLOCK];
  for (std::int64_t k = 0; k < m * n; ++k) hp[k] = 0.0;
  for (int a = 0; a < m; ++a) {
    const double* h = H + a * n;
    double* out = hp + a * n;
    for (std::int64_t k = 0; k < n; ++k) {
      if (h[k] == 0.0) continue;
      const double* p = P + k * n;
      for (std::int64_t i = 0; i < n; ++i) out[i] += h[k] * p[i];
    }
  }
  for (int a = 0; a < m; ++a)
    for (int b = 0; b < m; ++b) {
      double sum = R[a * m + b];
      const double* h = H + a * n;
      const double* p = hp + b * n;
      for (std::int64_t k = 0; k < n; ++k)
        if (h[k] != 0.0) sum += h[k] * p[k];
      s[a * m + b] = sum;
    }
  return apply_gain(x, P, n, hp, s, m, y, hp + n * m, gate);
}

// The same update for rows of H with at most two nonzero entries each: row a is
// coef[2a] x[index[2a]] + coef[2a + 1] x[index[2a + 1]] (a coefficient 0 for one entry), as the
// position filter's measurements are (leg_filter.hpp); scratch: 2 n m doubles.
inline bool update_sparse(double* x, double* P, std::int64_t n, const std::int64_t* index,
                          const double* coef, const double* R, int m, const double* y,
                          double* scratch) {
  double* hp = scratch;  // H P (m x n): rows of P (symmetric) combined
  double s[MAX_BLOCK * MAX_BLOCK];
  for (int a = 0; a < m; ++a) {
    const double c0 = coef[2 * a], c1 = coef[2 * a + 1];
    const double* p0 = P + index[2 * a] * n;
    const double* p1 = P + index[2 * a + 1] * n;
    double* out = hp + a * n;
    for (std::int64_t i = 0; i < n; ++i) out[i] = c0 * p0[i] + c1 * p1[i];
  }
  for (int a = 0; a < m; ++a)
    for (int b = 0; b < m; ++b) {
      const double* p = hp + b * n;
      s[a * m + b] =
          R[a * m + b] + coef[2 * a] * p[index[2 * a]] + coef[2 * a + 1] * p[index[2 * a + 1]];
    }
  return apply_gain(x, P, n, hp, s, m, y, hp + n * m);
}

}  // namespace va::kalman
