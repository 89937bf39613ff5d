// The Kalman filter's measurement update on a dense state (attitude_filter.hpp, leg_filter.hpp):
// one block of m <= 7 measurements z = H x + noise with a full m x m noise covariance R.
//   S = H P H^T + R,  K = P H^T S^-1,  x <- x + K (z - H x),  P <- P - K S K^T,
// computed whitened by the Cholesky factor S = L L^T: W = L^-1 H P, z = L^-1 (z - H x),
// x <- x + W^T z, P <- P - W^T W (no inverse, no gain), P kept exactly symmetric (the upper
// triangle computed, mirrored).
#pragma once

#include <cmath>
#include <cstdint>

namespace va::kalman {

constexpr int MAX_BLOCK = 7;

// The Cholesky factor L (lower, row-major m x m) of the symmetric m x m matrix s: s = L L^T;
// false when s is not positive definite.
inline bool cholesky(const double* s, int m, double* l) {
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
  return true;
}

// The correction of a block of M <= MAX_BLOCK measurements, whitened by S = L L^T (l: M x M):
// hp (M x n, H P) becomes W = L^-1 H P column by column, x += W^T z, then P -= W^T W, each
// entry of the upper triangle once, mirrored (P stays exactly symmetric). M known to the
// compiler: its loops unrolled.
template <int M>
inline void correct_block(double* x, double* P, std::int64_t n, double* hp, const double* l,
                          const double* z) {
  double inverse[M];
#pragma GCC unroll 8
  for (int a = 0; a < M; ++a) inverse[a] = 1.0 / l[a * M + a];
  for (std::int64_t i = 0; i < n; ++i) {
    double column[M], dx = 0.0;
#pragma GCC unroll 8
    for (int a = 0; a < M; ++a) {
      double value = hp[a * n + i];
#pragma GCC unroll 8
      for (int b = 0; b < a; ++b) value -= l[a * M + b] * column[b];
      column[a] = value * inverse[a];
      hp[a * n + i] = column[a];
      dx += column[a] * z[a];
    }
    x[i] += dx;
  }
  for (std::int64_t i = 0; i < n; ++i) {
    double wi[M];
#pragma GCC unroll 8
    for (int a = 0; a < M; ++a) wi[a] = hp[a * n + i];
    double* row = P + i * n;
    for (std::int64_t j = i; j < n; ++j) {
      double sum = 0.0;
#pragma GCC unroll 8
      for (int a = 0; a < M; ++a) sum += wi[a] * hp[a * n + j];
      row[j] -= sum;
    }
  }
  for (std::int64_t i = 0; i < n; ++i)
    for (std::int64_t j = i + 1; j < n; ++j) P[j * n + i] = P[i * n + j];
}

// The update once H P (hp, m x n: row a is (P h_a)^T, P symmetric) and S = H P H^T + R (s,
// m x m) are known, whitened by S = L L^T: W = L^-1 H P (in hp's place), z = L^-1 y, then
// x += W^T z and P -= W^T W (= K S K^T; correct_block). False (x, P untouched) when S is not
// positive definite. A residual whose squared Mahalanobis distance y^T S^-1 y = |z|^2 exceeds
// gate is an outlier: skipped (x, P untouched), true.
template <int M>
inline bool apply_block(double* x, double* P, std::int64_t n, double* hp, double* s,
                        const double* y, double gate) {
  double l[M * M], z[M];
  for (int a = 0; a < M; ++a)  // symmetric to rounding
    for (int b = 0; b < a; ++b) s[a * M + b] = s[b * M + a] = 0.5 * (s[a * M + b] + s[b * M + a]);
  if (!cholesky(s, M, l)) return false;
  double distance = 0.0;
  for (int a = 0; a < M; ++a) {  // z = L^-1 y
    double value = y[a];
    for (int b = 0; b < a; ++b) value -= l[a * M + b] * z[b];
    z[a] = value / l[a * M + a];
    distance += z[a] * z[a];
  }
  if (distance > gate) return true;
  correct_block<M>(x, P, n, hp, l, z);
  return true;
}

inline bool apply_gain(double* x, double* P, std::int64_t n, double* hp, double* s, int m,
                       const double* y, double gate = INFINITY) {
  switch (m) {  // the block's size known to the compiler
    case 1: return apply_block<1>(x, P, n, hp, s, y, gate);
    case 2: return apply_block<2>(x, P, n, hp, s, y, gate);
    case 3: return apply_block<3>(x, P, n, hp, s, y, gate);
    case 4: return apply_block<4>(x, P, n, hp, s, y, gate);
    case 5: return apply_block<5>(x, P, n, hp, s, y, gate);
    case 6: return apply_block<6>(x, P, n, hp, s, y, gate);
    default: return apply_block<MAX_BLOCK>(x, P, n, hp, s, y, gate);
  }
}

// One block update of (x, P) (n states, P row-major n x n, symmetric) by the residual
// y = z - H x (m), H (m x n) and R (m x m), both row-major. scratch: n m doubles. Returns
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
  return apply_gain(x, P, n, hp, s, m, y, gate);
}

// The same update for rows of H with at most two nonzero entries each: row a is
// coef[2a] x[index[2a]] + coef[2a + 1] x[index[2a + 1]] (a coefficient 0 for one entry), as the
// position filter's measurements are (leg_filter.hpp); scratch: n m doubles.
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
  return apply_gain(x, P, n, hp, s, m, y);
}

}  // namespace va::kalman
