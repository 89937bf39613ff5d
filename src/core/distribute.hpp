// One tick of the compiled force distribution on the packed tables of
// virtual_actuators.distribution.partitioned (compiled.py), into the buffer that
// result.TickResult reads; the numpy PartitionedSolver is its oracle (tests/test_core_parity.py;
// no FMA contraction: CMakeLists.txt).
//
// Status: 0 solved; 1 a chain is singular or nearly so; 2 an elimination
// block or the final system is ill-conditioned, or the answer misses an exact row; 3 a result
// overflowed. A nonzero status hands the tick to the numpy path.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "batch.hpp"
#include "linalg.hpp"
#include "solves.hpp"
#include "tables.hpp"

namespace va {

struct Distributed {
  double residual = 0.0, scale = 0.0, rounding = 0.0;
  std::int64_t status = 0;
  double worst = INF;
  std::int64_t worst_chain = -1;
};

// The tail of a solve: fill `requested`, set residual, scale and rounding (result.close_norms).
inline void close_norms(const std::int64_t* keep, std::int64_t n, const double* wrench,
                        const double* forces, std::int64_t nforces, const double* produced,
                        double* requested, Distributed& d) {
  double peak = 0.0;
  for (std::int64_t a = 0; a < n; ++a) {
    if (keep[a]) {
      peak = py_max(py_max(py_max(peak, std::abs(wrench[a])), std::abs(produced[a])),
                    std::abs(produced[a] - wrench[a]));
      requested[a] = wrench[a];
    } else {
      requested[a] = produced[a];
    }
  }
  double residual = 0.0, request = 0.0, output = 0.0;
  if (std::isfinite(peak) && peak > 0.0) {
    for (std::int64_t a = 0; a < n; ++a)
      if (keep[a]) {
        const double error = (produced[a] - wrench[a]) / peak;
        residual += error * error;
        const double w = wrench[a] / peak, o = produced[a] / peak;
        request += w * w;
        output += o * o;
      }
  } else if (!std::isfinite(peak)) {
    peak = INF;
    residual = INF;
  }
  double force_peak = 0.0;
  for (std::int64_t r = 0; r < nforces; ++r) force_peak = py_max(force_peak, std::abs(forces[r]));
  d.residual = peak * std::sqrt(residual);
  d.scale = peak * std::sqrt(py_max(request, output));
  d.rounding = ROUNDING * force_peak;
}

// The ball columns of chains that share their ball axes, side by side over the chains
//. fulls (K + 4, n, p), rows (width, n, p), offsets (3, p).
inline void shared_ball_columns(const std::int64_t* header, std::int64_t ball_start,
                                const std::int64_t* axis_rows, const Arr& offsets, Arr& fulls,
                                Arr& rows) {
  const std::int64_t c_i = header[C_CON], nb = header[NB_BALL];
  const std::int64_t K = fulls.d0 - 4, n = fulls.d1, p = fulls.d2;
  for (std::int64_t j = 0; j < nb; ++j) {
    const std::int64_t axis = header[ball_start + j];
    const std::int64_t slot = c_i + j;
    for (std::int64_t i = 0; i < p; ++i) fulls(K + 3, slot, i) = 0.0;
    for (std::int64_t a = 0; a < n; ++a) {
      const std::int64_t row = axis_rows[a];
      double* out = &fulls(slot, a, 0);
      double* out_rows = &rows(slot, a, 0);
      if (row >= 3 || row == axis) {
        const double value = row - 3 == axis ? 1.0 : 0.0;
        for (std::int64_t i = 0; i < p; ++i) {
          out[i] = value;
          out_rows[i] = value;
        }
        continue;
      }
      // e_axis x d: entry row of (0, -d2, d1), (d2, 0, -d0) or (-d1, d0, 0)
      const double sign = ((row - axis) % 3 + 3) % 3 == 2 ? 1.0 : -1.0;  // Python's modulo
      const double* values = offsets.at(3 - axis - row);
      for (std::int64_t i = 0; i < p; ++i) {
        out[i] = sign * values[i];
        out_rows[i] = out[i];
      }
    }
  }
}

// The chains' natural rows and projectors: what a tick computes before the solve.
struct ChainRows {
  Arr rows, rhs, projectors, particular;
  std::vector<std::int64_t> state;  // -1 general, key >= 0 awaiting the batch, -2 done
  double worst = INF;
  std::int64_t worst_chain = -1;
  bool ill = false;
};

// Gather the chains of one key, run full_rank_batch on them, scatter the results.
inline void batch_members(const Packed& P, std::int64_t i, Arr& fulls, ChainRows& c) {
  const std::int64_t p = P.p, n = P.n, K = P.K;
  const std::int64_t key = c.state[static_cast<std::size_t>(i)];
  std::vector<std::int64_t> members;
  for (std::int64_t i2 = i; i2 < p; ++i2)
    if (c.state[static_cast<std::size_t>(i2)] == key) members.push_back(i2);
  const auto count = static_cast<std::int64_t>(members.size());
  const std::int64_t c_b = P.chain(i, RANK);
  const std::int64_t m_c = P.chain(i, C_CON) + P.chain(i, NB_BALL);
  std::vector<double> ratio_b(static_cast<std::size_t>(count));
  std::vector<double> bound_b(static_cast<std::size_t>(count));
  if (count == p) {  // every chain: in place (fulls is overwritten by the QR, row K + 3 kept)
    full_rank_batch(fulls.data(), n, p, c_b, m_c, fulls.at(K + 3), ratio_b.data(), bound_b.data(),
                    c.projectors.data(), c.particular.data(), c.rows.at(m_c));
  } else {
    Arr q_b(c_b, n, count), t_b(m_c, count), proj_b(n, n, count), part_b(n, count);
    Arr null_b(n - c_b, n, count);
    for (std::int64_t j = 0; j < c_b; ++j)
      for (std::int64_t a = 0; a < n; ++a)
        for (std::int64_t b = 0; b < count; ++b) q_b(j, a, b) = fulls(j, a, members[b]);
    for (std::int64_t j = 0; j < m_c; ++j)
      for (std::int64_t b = 0; b < count; ++b) t_b(j, b) = fulls(K + 3, j, members[b]);
    full_rank_batch(q_b.data(), n, count, c_b, m_c, t_b.data(), ratio_b.data(), bound_b.data(),
                    proj_b.data(), part_b.data(), null_b.data());
    for (std::int64_t b = 0; b < count; ++b) {
      const std::int64_t chain = members[b];
      for (std::int64_t r = 0; r < n; ++r) {
        c.particular(r, chain) = part_b(r, b);
        for (std::int64_t a = 0; a < n; ++a) c.projectors(r, a, chain) = proj_b(r, a, b);
      }
      for (std::int64_t j = 0; j < n - c_b; ++j)
        for (std::int64_t a = 0; a < n; ++a) c.rows(m_c + j, a, chain) = null_b(j, a, b);
    }
  }
  for (std::int64_t b = 0; b < count; ++b) {
    const std::int64_t chain = members[b];
    c.state[static_cast<std::size_t>(chain)] = -2;
    if (ratio_b[b] < c.worst) {
      c.worst = ratio_b[b];
      c.worst_chain = chain;
    }
    if (bound_b[b] > ILL_CONDITIONED) c.ill = true;
  }
}

// Whether every chain is fast with the same constrained count and ball axes (their ball columns
// are then written side by side after the loop).
inline bool shares_ball_axes(const Packed& P, std::int64_t ball_start) {
  for (std::int64_t i = 0; i < P.p; ++i) {
    const std::int64_t nb = P.chain(i, NB_BALL);
    if (!(P.chain(i, RANK) == P.chain(i, K_COLS) + nb && P.chain(i, C_CON) == P.chain(0, C_CON) &&
          nb == P.chain(0, NB_BALL)))
      return false;
    for (std::int64_t j = 0; j < nb; ++j)
      if (P.chain(i, ball_start + j) != P.chain(0, ball_start + j)) return false;
  }
  return true;
}

// The natural constraint rows of every chain (chain index last), their null spaces, and in
// mode 0 with BATCH_CHAINS chains or more the projectors of the chains of full column rank.
inline void chain_rows(const Packed& P, const Arr& jac_t, const double* frames,
                       const double (&rot_o)[3][3], const double* passive, ChainRows& c) {
  const std::int64_t n = P.n, p = P.p, K = P.K;
  const std::int64_t b = P.frame_rows[0];
  const std::int64_t width = std::max<std::int64_t>(P.layout[2], 1);
  c.rows = Arr(width, n, p);
  c.rhs = Arr(width, p);
  Arr columns(K + 3, n), null_buffer(n, n);  // a chain's columns, one per row
  NullScratch scratch(n, K + 3);
  c.projectors = Arr(n, n, p);
  c.particular = Arr(n, p);
  c.state.assign(static_cast<std::size_t>(p), -1);
  const bool batch = P.mode == 0 && p >= BATCH_CHAINS;
  // fast chains: columns in QR order, chains last; row K + 3: right-hand sides of the rows
  Arr fulls(K + 4, n, batch ? p : 0);
  const std::int64_t con_start = HEADER + K;
  const std::int64_t ball_start = con_start + P.layout[1];
  const bool shared = batch && shares_ball_axes(P, ball_start);
  Arr offsets(3, shared ? p : 0);
  for (std::int64_t i = 0; i < p; ++i) {
    const std::int64_t k_i = P.chain(i, K_COLS), c_i = P.chain(i, C_CON);
    const std::int64_t nb = P.chain(i, NB_BALL), rank = P.chain(i, RANK);
    const bool fast = batch && rank > 0 && rank == k_i + nb;
    double d0 = 0.0, d1 = 0.0, d2 = 0.0;
    if (nb) {  // offset from {A_i} to {B} in {O}
      const std::int64_t a = P.frame_rows[2 + i];
      const double dx = frames[12 * b + 9] - frames[12 * a + 9];
      const double dy = frames[12 * b + 10] - frames[12 * a + 10];
      const double dz = frames[12 * b + 11] - frames[12 * a + 11];
      d0 = rot_o[0][0] * dx + rot_o[1][0] * dy + rot_o[2][0] * dz;
      d1 = rot_o[0][1] * dx + rot_o[1][1] * dy + rot_o[2][1] * dz;
      d2 = rot_o[0][2] * dx + rot_o[1][2] * dy + rot_o[2][2] * dz;
    }
    if (fast) {
      // QR order: own constrained joints, ball axes, then the free joints; the constraint
      // columns are also the chain's first rows
      const std::int64_t m_c = c_i + nb;
      std::int64_t at = m_c;
      for (std::int64_t j = 0; j < k_i; ++j) {
        const std::int64_t v = P.chain(i, HEADER + j);
        const double sign = P.chain_signs[i * K + j];
        std::int64_t slot = -1;
        for (std::int64_t jj = 0; jj < c_i; ++jj)
          if (P.chain(i, con_start + jj) == j) slot = jj;
        if (slot < 0) {
          slot = at;
          ++at;
        } else {
          const double value = passive[v];
          c.rhs(slot, i) = value;
          fulls(K + 3, slot, i) = value;
        }
        for (std::int64_t a = 0; a < n; ++a) {
          const double value = jac_t(a, v) * sign;
          fulls(slot, a, i) = value;
          if (slot < c_i) c.rows(slot, a, i) = value;
        }
      }
      if (shared) {
        offsets(0, i) = d0;
        offsets(1, i) = d1;
        offsets(2, i) = d2;
        c.state[static_cast<std::size_t>(i)] = rank * (K + 4) + m_c;
        continue;
      }
      for (std::int64_t j = 0; j < nb; ++j) {
        const std::int64_t axis = P.chain(i, ball_start + j);
        fulls(K + 3, c_i + j, i) = 0.0;
        for (std::int64_t a = 0; a < n; ++a) {
          const double value = ball_entry(axis, P.axis_rows[a], d0, d1, d2);
          fulls(c_i + j, a, i) = value;
          c.rows(c_i + j, a, i) = value;
        }
      }
      c.state[static_cast<std::size_t>(i)] = rank * (K + 4) + m_c;
      continue;
    }
    for (std::int64_t j = 0; j < k_i; ++j) {
      const std::int64_t v = P.chain(i, HEADER + j);
      const double sign = P.chain_signs[i * K + j];
      for (std::int64_t a = 0; a < n; ++a) columns(j, a) = jac_t(a, v) * sign;
    }
    for (std::int64_t j = 0; j < nb; ++j) {
      const std::int64_t axis = P.chain(i, ball_start + j);
      for (std::int64_t a = 0; a < n; ++a)
        columns(k_i + j, a) = ball_entry(axis, P.axis_rows[a], d0, d1, d2);
    }
    // rows: own constrained joints, ball axes, null directions
    for (std::int64_t j = 0; j < c_i; ++j) {
      const std::int64_t position = P.chain(i, con_start + j);
      c.rhs(j, i) = passive[P.chain(i, HEADER + position)];
      for (std::int64_t a = 0; a < n; ++a) c.rows(j, a, i) = columns(position, a);
    }
    for (std::int64_t j = 0; j < nb; ++j)
      for (std::int64_t a = 0; a < n; ++a) c.rows(c_i + j, a, i) = columns(k_i + j, a);
    double ratio = 1.0;
    if (rank > 0) ratio = null_rows(columns, n, k_i + nb, rank, null_buffer, scratch);
    if (ratio < c.worst) {
      c.worst = ratio;
      c.worst_chain = i;
    }
    for (std::int64_t j = 0; j < n - rank; ++j)
      for (std::int64_t a = 0; a < n; ++a) c.rows(c_i + nb + j, a, i) = null_buffer(j, a);
  }
  if (shared) shared_ball_columns(P.chain_row(0), ball_start, P.axis_rows, offsets, fulls, c.rows);
  for (std::int64_t i = 0; i < (batch ? p : 0); ++i)
    if (c.state[static_cast<std::size_t>(i)] >= 0) batch_members(P, i, fulls, c);
}

// The hard rows: shared joints, constant design rows, equal torques.
inline void hard_rows(const Packed& P, const Arr& jac_t, const double* passive, Arr& hard,
                      Arr& hard_rhs) {
  const std::int64_t p = P.p, n = P.n, s0 = P.s0, s1 = P.s1;
  hard = Arr(s0 + s1, p, n);
  hard_rhs = Arr(s0 + s1);
  std::int64_t index = 0;
  for (int kind = 0; kind < 2; ++kind) {
    if (kind == 1)
      for (std::int64_t t = 0; t < s0; ++t) {
        std::copy(P.const_rows + t * p * n, P.const_rows + (t + 1) * p * n, hard.at(index));
        hard_rhs(index) = P.const_rhs[t];
        ++index;
      }
    for (std::int64_t t = 0; t < s1; ++t) {
      if (P.torque_rows[3 * t + 2] != kind) continue;
      const std::int64_t va = P.torque_rows[3 * t], vb = P.torque_rows[3 * t + 1];
      for (std::int64_t i = 0; i < p; ++i)
        for (std::int64_t a = 0; a < n; ++a) {
          double value = P.torque_signs[(t * 2) * p + i] * jac_t(a, va);
          if (vb >= 0) value -= P.torque_signs[(t * 2 + 1) * p + i] * jac_t(a, vb);
          hard(index, i, a) = value;
        }
      hard_rhs(index) = kind == 0 ? passive[va] : 0.0;
      ++index;
    }
  }
}

// One tick. jacobian_world (6, nv) and frames (nf, 12) row-major, q the configuration, wrench
// (n); out: P.out_size(nv) doubles, zeroed (forces, tau, passive, produced, requested).
inline Distributed distribute(const double* jacobian_world, std::int64_t nv, const double* frames,
                              const double* q, const double* wrench, const Packed& P, double* out) {
  Distributed d;
  const std::int64_t n = P.n, p = P.p, K = P.K;
  double* forces = out;
  double* tau = out + p * n;
  double* passive = out + p * n + nv;
  double* produced = out + p * n + 2 * nv;
  double* requested = out + p * n + 2 * nv + n;
  // -- the tick's kinematics, in {O} at {B}'s origin --------
  const std::int64_t b = P.frame_rows[0], o = P.frame_rows[1];
  double rot_o[3][3], transform[6][6];  // {O}'s rotation (row-major), the map
  wrench_transform(frames, b, o, rot_o, transform);
  Arr jac_t(n, nv);  // the Jacobian in {O}, one row per selected axis
  for (std::int64_t a = 0; a < n; ++a) {
    const double* t = transform[P.axis_rows[a]];
    for (std::int64_t v = 0; v < nv; ++v)
      jac_t(a, v) = t[0] * jacobian_world[v] + t[1] * jacobian_world[nv + v] +
                    t[2] * jacobian_world[2 * nv + v] + t[3] * jacobian_world[3 * nv + v] +
                    t[4] * jacobian_world[4 * nv + v] + t[5] * jacobian_world[5 * nv + v];
  }
  for (std::int64_t v = 0; v < P.nv_springs; ++v) {
    const double* sp = P.springs + 5 * v;
    if (sp[2] >= 0) {
      const auto iq = static_cast<std::int64_t>(sp[2]);
      const double angle = sp[3] > 0 ? std::atan2(q[iq + 1], q[iq]) : q[iq];
      passive[v] = -sp[0] * (angle - sp[1]);
    }
  }
  ChainRows c;
  chain_rows(P, jac_t, frames, rot_o, passive, c);
  d.worst = c.worst;
  d.worst_chain = c.worst_chain;
  if (c.worst < NEAR_SINGULAR) {
    d.status = 1;
    return d;
  }
  Arr hard, hard_rhs;
  hard_rows(P, jac_t, passive, hard, hard_rhs);
  std::vector<std::int64_t> kept;
  for (std::int64_t a = 0; a < n; ++a)
    if (P.keep[a]) kept.push_back(a);
  std::int64_t status;
  if (c.ill) {
    status = 2;  // a chain's rows are ill-conditioned: numpy decides
  } else if (P.mode == 0) {
    status = minimum_norm(c.rows, c.rhs, P, hard, hard_rhs, wrench, kept, forces, c.projectors,
                          c.particular, c.state);
  } else {
    const std::int64_t cfs_start = HEADER + K + P.layout[1] + 3;
    const std::int64_t free_start = cfs_start + P.layout[2];
    status = partitioned_solve(c.rows, c.rhs, P, cfs_start, free_start, hard, hard_rhs, wrench,
                               kept, forces);
  }
  if (status == 0 && constraint_error(c.rows, c.rhs, hard, hard_rhs, forces, p, n) > CONSTRAINT_TOL)
    status = 2;  // an ill-conditioned elimination lost an exact row: numpy decides
  if (status != 0) {
    d.status = status;
    return d;
  }
  for (std::int64_t i = 0; i < p; ++i) {
    const std::int64_t k_i = P.chain(i, K_COLS);
    for (std::int64_t j = 0; j < k_i; ++j) {
      const std::int64_t v = P.chain(i, HEADER + j);
      double acc = 0.0;
      for (std::int64_t a = 0; a < n; ++a) acc += jac_t(a, v) * forces[i * n + a];
      tau[v] += P.chain_signs[i * K + j] * acc * P.springs[5 * v + 4];
    }
    for (std::int64_t a = 0; a < n; ++a) produced[a] += forces[i * n + a];
  }
  close_norms(P.keep, n, wrench, forces, p * n, produced, requested, d);
  if (!(std::isfinite(d.residual) && std::isfinite(d.rounding))) {
    d.residual = d.scale = d.rounding = 0.0;
    d.status = 3;
  }
  return d;
}

}  // namespace va
