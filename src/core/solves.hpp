// The two solves of the compiled distribution: the minimum norm (mode 0) and the partitioned
// solve over the Constrained, Redundant and Minimum Force Sets (mode 1); the numpy solvers of
// virtual_actuators.distribution.partitioned (least_norm.py, reference.py) are their oracles.
#pragma once

#include <cstdint>
#include <vector>

#include "linalg.hpp"
#include "tables.hpp"

namespace va {

// Least sum ||F_i||^2 meeting every constraint: projectors and one KKT solve. rows (l, n, p),
// rhs (l, p), projectors (n, n, p), particular (n, p) have the chain index last; hard (s, p, n);
// forces (p, n). Chains whose state is -2 come with their projector and particular solution
// (full_rank_batch). Returns 0, or 2 for an ill-conditioned system.
inline std::int64_t minimum_norm(const Arr& rows, const Arr& rhs, const Packed& P, const Arr& hard,
                                 const Arr& hard_rhs, const double* wrench,
                                 const std::vector<std::int64_t>& kept, double* forces,
                                 Arr& projectors, Arr& particular,
                                 const std::vector<std::int64_t>& state) {
  const std::int64_t p = P.p, n = P.n, s = hard.d0, k = static_cast<std::int64_t>(kept.size());
  const std::int64_t width = rows.d0;
  Arr gram(width, width), gram_inv(width, width), scratch(width, width), pseudo(n, width);
  for (std::int64_t i = 0; i < p; ++i) {
    if (state[static_cast<std::size_t>(i)] == -2) continue;
    const std::int64_t l_i = P.chain(i, L_ROWS);
    for (std::int64_t a = 0; a < n; ++a) particular(a, i) = 0.0;
    for (std::int64_t r = 0; r < n; ++r)
      for (std::int64_t c = 0; c < n; ++c) projectors(r, c, i) = r == c ? 1.0 : 0.0;
    if (l_i == 0) continue;
    for (std::int64_t r = 0; r < l_i; ++r)
      for (std::int64_t c = 0; c < l_i; ++c) {
        double acc = 0.0;
        for (std::int64_t a = 0; a < n; ++a) acc += rows(r, a, i) * rows(c, a, i);
        gram(r, c) = acc;
      }
    if (inverse_into(gram.data(), width, l_i, scratch.data(), gram_inv.data()) > ILL_CONDITIONED)
      return 2;
    for (std::int64_t a = 0; a < n; ++a)  // pseudo = G^T (G G^T)^-1
      for (std::int64_t c = 0; c < l_i; ++c) {
        double acc = 0.0;
        for (std::int64_t r = 0; r < l_i; ++r) acc += rows(r, a, i) * gram_inv(r, c);
        pseudo(a, c) = acc;
      }
    for (std::int64_t r = 0; r < n; ++r) {  // P = I - pseudo G, particular = pseudo t
      double acc_t = 0.0;
      for (std::int64_t c = 0; c < l_i; ++c) {
        acc_t += pseudo(r, c) * rhs(c, i);
        const double value = pseudo(r, c);
        for (std::int64_t a = 0; a < n; ++a) projectors(r, a, i) -= value * rows(c, a, i);
      }
      particular(r, i) = acc_t;
    }
  }
  const std::int64_t size = k + s;
  Arr kkt(size, size), target(size);
  // the kept block of the projectors' sum over the chains, and the wrench the particular
  // solutions leave (four partial sums over the chains, then in order)
  for (std::int64_t r = 0; r < k; ++r) {
    const std::int64_t a = kept[static_cast<std::size_t>(r)];
    target(r) = wrench[a] - chain_sum(particular.at(a), p);
    for (std::int64_t c = r; c < k; ++c) {
      const double value = chain_sum(&projectors(a, kept[static_cast<std::size_t>(c)], 0), p);
      kkt(r, c) = value;
      kkt(c, r) = value;
    }
  }
  for (std::int64_t t = 0; t < s; ++t) target(k + t) = hard_rhs(t);
  Arr hp(s, n, p);  // C_i P_i
  for (std::int64_t i = 0; i < (s ? p : 0); ++i)
    for (std::int64_t t = 0; t < s; ++t) {
      for (std::int64_t a = 0; a < n; ++a) {
        double acc = 0.0;
        for (std::int64_t b = 0; b < n; ++b) acc += hard(t, i, b) * projectors(b, a, i);
        hp(t, a, i) = acc;
        target(k + t) -= hard(t, i, a) * particular(a, i);
      }
      for (std::int64_t r = 0; r < k; ++r) {
        const double value = hp(t, kept[static_cast<std::size_t>(r)], i);
        kkt(r, k + t) += value;
        kkt(k + t, r) += value;
      }
      for (std::int64_t u = 0; u < s; ++u) {
        double acc = 0.0;
        for (std::int64_t a = 0; a < n; ++a) acc += hp(t, a, i) * hard(u, i, a);
        kkt(k + t, k + u) += acc;
      }
    }
  if (size == 0) {
    for (std::int64_t i = 0; i < p; ++i)
      for (std::int64_t a = 0; a < n; ++a) forces[i * n + a] = particular(a, i);
    return 0;
  }
  Arr kkt_inv;
  if (invert(kkt, kkt_inv) > ILL_CONDITIONED) return 2;
  std::vector<double> multipliers(static_cast<std::size_t>(size));
  mv(kkt_inv, target.data(), multipliers.data());
  std::vector<double> value(static_cast<std::size_t>(p));
  for (std::int64_t a = 0; a < n; ++a) {  // side by side over the chains
    for (std::int64_t i = 0; i < p; ++i) value[i] = particular(a, i);
    for (std::int64_t r = 0; r < k; ++r) {
      const double m = multipliers[r];
      const double* proj = &projectors(a, kept[static_cast<std::size_t>(r)], 0);
      for (std::int64_t i = 0; i < p; ++i) value[i] += proj[i] * m;
    }
    for (std::int64_t t = 0; t < s; ++t) {
      const double m = multipliers[k + t];
      for (std::int64_t i = 0; i < p; ++i) value[i] += hp(t, a, i) * m;
    }
    for (std::int64_t i = 0; i < p; ++i) forces[i * n + a] = value[i];
  }
  return 0;
}

// The Partitioned Actuator Set solve with the declaration's CFS, RFS and MFS (mode 1).
// Returns 0, or 2 for an ill-conditioned block (the RFS block measured against the hard rows'
// size before the CFS was eliminated).
inline std::int64_t partitioned_solve(const Arr& rows, const Arr& rhs, const Packed& P,
                                      std::int64_t cfs_start, std::int64_t free_start,
                                      const Arr& hard, const Arr& hard_rhs, const double* wrench,
                                      const std::vector<std::int64_t>& kept, double* forces) {
  const std::int64_t p = P.p, n = P.n, s = hard.d0, k = static_cast<std::int64_t>(kept.size());
  const std::int64_t m = P.m, width = rows.d0;
  Arr transforms(p, n, n), offsets(p, n);  // F_i = T_i f_i + w_i, T_i padded to n columns
  Arr block(width, width), scratch(width, width), inverse(width, width);
  for (std::int64_t i = 0; i < p; ++i) {
    const std::int64_t l_i = P.chain(i, L_ROWS), d_i = P.chain(i, D_FREE);
    const std::int64_t* cfs = P.chain_row(i) + cfs_start;
    const std::int64_t* free = P.chain_row(i) + free_start;
    for (std::int64_t j = 0; j < d_i; ++j) transforms(i, free[j], j) = 1.0;
    if (l_i) {
      for (std::int64_t r = 0; r < l_i; ++r)
        for (std::int64_t c = 0; c < l_i; ++c) block(r, c) = rows(r, cfs[c], i);
      if (inverse_into(block.data(), width, l_i, scratch.data(), inverse.data()) > ILL_CONDITIONED)
        return 2;
      for (std::int64_t r = 0; r < l_i; ++r) {  // Q = -G_b^-1 G_a, u = G_b^-1 t
        double acc = 0.0;
        for (std::int64_t c = 0; c < l_i; ++c) acc += inverse(r, c) * rhs(c, i);
        offsets(i, cfs[r]) = acc;
        for (std::int64_t c = 0; c < d_i; ++c) {
          double sum = 0.0;
          for (std::int64_t t = 0; t < l_i; ++t) sum += inverse(r, t) * rows(t, free[c], i);
          transforms(i, cfs[r], c) = -sum;
        }
      }
    }
  }
  Arr a_rows(k, m), a_rhs(k), h_rows(s, m), h_rhs(s), h_scale(s);
  for (std::int64_t r = 0; r < k; ++r) a_rhs(r) = wrench[kept[static_cast<std::size_t>(r)]];
  for (std::int64_t t = 0; t < s; ++t) h_rhs(t) = hard_rhs(t);
  for (std::int64_t i = 0; i < p; ++i) {
    const std::int64_t d_i = P.chain(i, D_FREE), start = P.chain(i, START);
    if (s) {  // sum_i |c_i|_1 max|T_i|: what cancels in a reduced hard row
      double t_max = 0.0;
      for (std::int64_t a = 0; a < n; ++a)
        for (std::int64_t j = 0; j < d_i; ++j) t_max = py_max(t_max, std::abs(transforms(i, a, j)));
      for (std::int64_t t = 0; t < s; ++t) {
        double acc = 0.0;
        for (std::int64_t a = 0; a < n; ++a) acc += std::abs(hard(t, i, a));
        h_scale(t) += acc * t_max;
      }
    }
    for (std::int64_t r = 0; r < k; ++r) {
      const std::int64_t a = kept[static_cast<std::size_t>(r)];
      a_rhs(r) -= offsets(i, a);
      for (std::int64_t j = 0; j < d_i; ++j) a_rows(r, start + j) = transforms(i, a, j);
    }
    for (std::int64_t t = 0; t < s; ++t) {
      for (std::int64_t a = 0; a < n; ++a) h_rhs(t) -= hard(t, i, a) * offsets(i, a);
      for (std::int64_t j = 0; j < d_i; ++j) {
        double acc = 0.0;
        for (std::int64_t a = 0; a < n; ++a) acc += hard(t, i, a) * transforms(i, a, j);
        h_rows(t, start + j) = acc;
      }
    }
  }
  const std::int64_t* rfs = P.plan;
  const std::int64_t* mfs = P.plan + s;
  std::vector<double> f(static_cast<std::size_t>(m), 0.0);
  Arr gain(s, m - s), bias(s);
  if (s) {
    Arr h_r(s, s), h_m(s, m - s);
    for (std::int64_t t = 0; t < s; ++t) {
      for (std::int64_t c = 0; c < s; ++c) h_r(t, c) = h_rows(t, rfs[c]);
      for (std::int64_t c = 0; c < m - s; ++c) h_m(t, c) = h_rows(t, mfs[c]);
    }
    Arr h_inv;
    const double cond = invert(h_r, h_inv);
    if (cond > ILL_CONDITIONED || scaled_condition(h_r, h_inv, h_scale.data()) > ILL_CONDITIONED)
      return 2;  // singular here, or hard rows the natural ones imply: numpy decides
    const Arr product = mm(h_inv, h_m);
    for (std::int64_t e = 0; e < s * (m - s); ++e) gain.v[e] = -product.v[e];
    mv(h_inv, h_rhs.data(), bias.data());
  }
  Arr system(k, m - s), target(k);
  for (std::int64_t r = 0; r < k; ++r) target(r) = a_rhs(r);
  for (std::int64_t r = 0; r < k; ++r) {
    for (std::int64_t c = 0; c < m - s; ++c) {
      double value = a_rows(r, mfs[c]);
      for (std::int64_t t = 0; t < s; ++t) value += a_rows(r, rfs[t]) * gain(t, c);
      system(r, c) = value;
    }
    for (std::int64_t t = 0; t < s; ++t) target(r) -= a_rows(r, rfs[t]) * bias(t);
  }
  Arr system_inv;
  if (invert(system, system_inv) > ILL_CONDITIONED) return 2;
  std::vector<double> f_m(static_cast<std::size_t>(k));
  mv(system_inv, target.data(), f_m.data());
  for (std::int64_t c = 0; c < m - s; ++c) f[mfs[c]] = f_m[c];
  for (std::int64_t t = 0; t < s; ++t) {
    double value = bias(t);
    for (std::int64_t c = 0; c < m - s; ++c) value += gain(t, c) * f_m[c];
    f[rfs[t]] = value;
  }
  for (std::int64_t i = 0; i < p; ++i) {
    const std::int64_t d_i = P.chain(i, D_FREE), start = P.chain(i, START);
    for (std::int64_t a = 0; a < n; ++a) {
      double value = offsets(i, a);
      for (std::int64_t j = 0; j < d_i; ++j) value += transforms(i, a, j) * f[start + j];
      forces[i * n + a] = value;
    }
  }
  return 0;
}

}  // namespace va
