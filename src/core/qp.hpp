// One tick of the QP distribution in the chains' free coordinates: the reduced QP's matrices
// (the natural rows eliminated), the answer's violation and read-out, and the tick on the last
// certified active set, into the buffer of virtual_actuators.distribution.qp.compiled.Workspace.
// The numpy QP (all rows as equalities) is its oracle (tests/test_qp_paths.py).
#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

#include "contact_rows.hpp"
#include "distribute.hpp"
#include "exact.hpp"
#include "linalg.hpp"

namespace va {

// Columns of the per-chain integer table, entries of the layout (qp.compiled).
constexpr std::int64_t QP_K_COLS = 0, QP_C_CON = 1, QP_NB_BALL = 2, QP_HEADER = 3, QP_LAYOUT = 14;
constexpr double QP_INFINITY = 1e20;  // tolerances.INFINITY
constexpr double RANK_TOL = 1e-7;

// What a declaration fixes (qp.compiled.CompiledQPMatrices), as views of owned arrays.
struct QPTables {
  std::int64_t n = 0, p = 0, nv = 0, K = 0, C = 0, s = 0, t = 0;
  const std::int64_t* axis_rows = nullptr;      // (n,)
  const std::int64_t* frame_rows = nullptr;     // (2 + p,)
  const std::int64_t* chain_ints = nullptr;     // (p, QP_HEADER + K + C + 3)
  const double* chain_signs = nullptr;          // (p, K)
  const double* springs = nullptr;              // (nv, 5)
  const double* const_rows = nullptr;           // (s, p, n)
  const double* const_rhs = nullptr;            // (s,)
  const double* normals_world = nullptr;        // (p, 3)
  const std::int64_t* frame_normals = nullptr;  // (p,)
  const double* settings = nullptr;             // (4,)
  const double* soles = nullptr;                // (p, 3)
  const std::int64_t* limited_v = nullptr;      // (t,)
  const double* limits = nullptr;               // (t,)
  std::int64_t width() const { return QP_HEADER + K + C + 3; }
  std::int64_t chain(std::int64_t i, std::int64_t column) const {
    return chain_ints[i * width() + column];
  }
};

// The arrays of reduced_qp in its buffer (qp.compiled.Workspace's views).
struct QPViews {
  double *basis, *x0, *equality, *equality_rhs, *inequality, *lows, *uppers, *tmap, *tau0, *passive;
  std::int64_t free, rows_eq, m_in, design;
  QPViews(double* buffer, const std::int64_t* layout)
      : basis(buffer + layout[0]),
        x0(buffer + layout[1]),
        equality(buffer + layout[2]),
        equality_rhs(buffer + layout[3]),
        inequality(buffer + layout[4]),
        lows(buffer + layout[5]),
        uppers(buffer + layout[6]),
        tmap(buffer + layout[7]),
        tau0(buffer + layout[8]),
        passive(buffer + layout[9]),
        free(layout[QP_LAYOUT - 4]),
        rows_eq(layout[QP_LAYOUT - 3]),
        m_in(layout[QP_LAYOUT - 2]),
        design(layout[QP_LAYOUT - 1]) {}
  ExactRows rows(const double* weights) const {
    return {equality, equality_rhs, rows_eq, free, design, weights, inequality, lows, uppers, m_in};
  }
};

// Scratch of reduced_qp, one per thread (qp_scratch): a warm tick allocates nothing.
struct QPScratch {
  Arr jac_t, columns, r_mat;
  std::vector<double> targets;
};

inline QPScratch& qp_scratch() {
  thread_local QPScratch scratch;
  return scratch;
}

struct Reduced {
  std::int64_t status = 0;
  double worst = INF, scale = 1.0;
};

// Modified Gram-Schmidt, twice, on columns[:count] (rows of n entries) in place; R into r.
// Returns the smallest pivot over the largest column norm (0 when a column vanishes).
inline double orthonormalise(Arr& columns, std::int64_t count, Arr& r) {
  const std::int64_t n = columns.d1;
  double largest = 0.0;
  for (std::int64_t j = 0; j < count; ++j) {
    double norm = 0.0;
    for (std::int64_t a = 0; a < n; ++a) norm += columns(j, a) * columns(j, a);
    largest = py_max(largest, std::sqrt(norm));
  }
  double worst = INF;
  for (std::int64_t j = 0; j < count; ++j) {
    for (std::int64_t b = 0; b < j + 1; ++b) r(b, j) = 0.0;
    for (int sweep = 0; sweep < 2; ++sweep)
      for (std::int64_t b = 0; b < j; ++b) {
        double dot = 0.0;
        for (std::int64_t a = 0; a < n; ++a) dot += columns(b, a) * columns(j, a);
        r(b, j) += dot;
        for (std::int64_t a = 0; a < n; ++a) columns(j, a) -= dot * columns(b, a);
      }
    double norm = 0.0;
    for (std::int64_t a = 0; a < n; ++a) norm += columns(j, a) * columns(j, a);
    norm = std::sqrt(norm);
    r(j, j) = norm;
    if (!(norm > 0.0 && largest > 0.0)) return 0.0;
    worst = py_min(worst, norm / largest);
    for (std::int64_t a = 0; a < n; ++a) columns(j, a) /= norm;
  }
  return worst;
}

// One tick's QP in free coordinates (QP.reduced): jacobian_world (6, nv), frames
// (nf, 12), q, wrench (n), kept (nk) the prescribed axes; buffer (size) at layout, overwritten.
inline Reduced reduced_qp(const double* jacobian_world, const double* frames, const double* q,
                          const double* wrench, const std::int64_t* kept, std::int64_t nk,
                          const QPTables& T, double* buffer, std::int64_t buffer_size,
                          const std::int64_t* layout) {
  const std::int64_t n = T.n, p = T.p, nv = T.nv, K = T.K, C = T.C, s = T.s;
  const double friction = T.settings[0], min_normal = T.settings[1];
  const bool with_normal = T.settings[2] > 0.0;
  std::int64_t force_axes = 0, moment_axes = 0;
  for (std::int64_t a = 0; a < n; ++a) {
    force_axes += T.axis_rows[a] < 3;
    moment_axes += T.axis_rows[a] >= 3;
  }
  std::int64_t faces = 0;
  if (force_axes) faces = (with_normal ? 1 : 0) + (friction >= 0.0 ? 4 : 0);
  for (std::int64_t e = 0; e < buffer_size; ++e) buffer[e] = 0.0;
  QPViews V(buffer, layout);
  const std::int64_t free = V.free, m_in = V.m_in;
  for (std::int64_t r = 0; r < m_in; ++r) V.uppers[r] = QP_INFINITY;
  // -- the Jacobian in {O} at {B}'s origin, the springs ----
  const std::int64_t b = T.frame_rows[0], o = T.frame_rows[1];
  double rot_o[3][3], transform[6][6];  // {O}'s rotation (row-major), the map
  wrench_transform(frames, b, o, rot_o, transform);
  QPScratch& S = qp_scratch();
  Arr& jac_t = zeroed(S.jac_t, n, nv);
  for (std::int64_t a = 0; a < n; ++a) {
    const double* t = transform[T.axis_rows[a]];
    for (int w = 0; w < 6; ++w)
      if (t[w] != 0.0)
        for (std::int64_t v = 0; v < nv; ++v) jac_t(a, v) += t[w] * jacobian_world[w * nv + v];
  }
  for (std::int64_t v = 0; v < nv; ++v) {
    const double* sp = T.springs + 5 * v;
    if (sp[2] >= 0) {
      const auto iq = static_cast<std::int64_t>(sp[2]);
      const double angle = sp[3] > 0 ? std::atan2(q[iq + 1], q[iq]) : q[iq];
      V.passive[v] = -sp[0] * (angle - sp[1]);
    }
  }
  // -- per chain: free basis, particular solution, its rows ---------------------------------
  Arr& columns = zeroed(S.columns, K + 3, n);
  Arr& r_mat = zeroed(S.r_mat, K + 3, K + 3);
  double* targets = zeroed(S.targets, K + 3);
  double face_o[5][3];
  double normal_w[3];
  Reduced result;
  double worst = INF;
  std::int64_t start = 0, sole_row = p * faces;
  for (std::int64_t i = 0; i < p; ++i) {
    const std::int64_t k_i = T.chain(i, QP_K_COLS), c_i = T.chain(i, QP_C_CON),
                       nb = T.chain(i, QP_NB_BALL);
    const std::int64_t d_i = k_i - c_i;
    const std::int64_t a_row = T.frame_rows[2 + i];

    const double dx = frames[12 * b + 9] - frames[12 * a_row + 9];
    const double dy = frames[12 * b + 10] - frames[12 * a_row + 10];
    const double dz = frames[12 * b + 11] - frames[12 * a_row + 11];
    const double d0 = rot_o[0][0] * dx + rot_o[1][0] * dy + rot_o[2][0] * dz;
    const double d1 = rot_o[0][1] * dx + rot_o[1][1] * dy + rot_o[2][1] * dz;
    const double d2 = rot_o[0][2] * dx + rot_o[1][2] * dy + rot_o[2][2] * dz;
    std::int64_t at = c_i + nb;
    for (std::int64_t j = 0; j < k_i; ++j) {
      const std::int64_t v = T.chain(i, QP_HEADER + j);
      const double sign = T.chain_signs[i * K + j];
      std::int64_t slot = -1;
      for (std::int64_t jj = 0; jj < c_i; ++jj)
        if (T.chain(i, QP_HEADER + K + jj) == j) slot = jj;
      if (slot < 0) {
        slot = at;
        ++at;
      } else {
        targets[slot] = V.passive[v];
      }
      for (std::int64_t a = 0; a < n; ++a) columns(slot, a) = jac_t(a, v) * sign;
    }
    for (std::int64_t j = 0; j < nb; ++j) {
      const std::int64_t axis = T.chain(i, QP_HEADER + K + C + j);
      targets[c_i + j] = 0.0;
      for (std::int64_t a = 0; a < n; ++a)
        columns(c_i + j, a) = ball_entry(axis, T.axis_rows[a], d0, d1, d2);
    }
    const double ratio = orthonormalise(columns, k_i + nb, r_mat);
    worst = py_min(worst, ratio);
    if (!(ratio >= RANK_TOL)) {
      result.status = 1;
      result.worst = worst;
      result.scale = 1.0;
      return result;
    }
    const std::int64_t m_c = c_i + nb;
    for (std::int64_t j = 0; j < m_c; ++j) {  // R_CC^T y = t, forward; x0 = Q_C y
      double acc = targets[j];
      for (std::int64_t jj = 0; jj < j; ++jj) acc -= r_mat(jj, j) * targets[jj];
      targets[j] = acc / r_mat(j, j);
      for (std::int64_t a = 0; a < n; ++a) V.x0[i * n + a] += targets[j] * columns(j, a);
    }
    for (std::int64_t j = 0; j < d_i; ++j)
      for (std::int64_t a = 0; a < n; ++a)
        V.basis[(i * n + a) * free + start + j] = columns(m_c + j, a);
    const double* chain_x0 = V.x0 + i * n;
    const BasisView chain_basis{V.basis + i * n * free + start, free};
    for (std::int64_t j = 0; j < k_i; ++j) {  // torques at the chain's joints
      const std::int64_t v = T.chain(i, QP_HEADER + j);
      const double sign = T.chain_signs[i * K + j] * T.springs[5 * v + 4];
      if (sign == 0.0) continue;
      double acc = 0.0;
      for (std::int64_t a = 0; a < n; ++a) acc += jac_t(a, v) * chain_x0[a];
      V.tau0[v] += sign * acc;
      for (std::int64_t jj = 0; jj < d_i; ++jj) {
        acc = 0.0;
        for (std::int64_t a = 0; a < n; ++a) acc += jac_t(a, v) * chain_basis(a, jj);
        V.tmap[v * free + start + jj] += sign * acc;
      }
    }
    for (std::int64_t r = 0; r < nk; ++r) {  // the request and the design rows
      const std::int64_t a = kept[r];
      for (std::int64_t jj = 0; jj < d_i; ++jj)
        V.equality[(s + r) * free + start + jj] = chain_basis(a, jj);
      V.equality_rhs[s + r] -= chain_x0[a];
    }
    for (std::int64_t t = 0; t < s; ++t) {
      const double* row = T.const_rows + (t * p + i) * n;
      for (std::int64_t jj = 0; jj < d_i; ++jj) {
        double acc = 0.0;
        for (std::int64_t a = 0; a < n; ++a) acc += row[a] * chain_basis(a, jj);
        V.equality[t * free + start + jj] = acc;
      }
      double acc = 0.0;
      for (std::int64_t a = 0; a < n; ++a) acc += row[a] * chain_x0[a];
      V.equality_rhs[t] -= acc;
    }
    for (int c = 0; c < 3; ++c)
      normal_w[c] =
          T.frame_normals[i] ? frames[12 * a_row + 3 * c + 2] : T.normals_world[3 * i + c];
    if (faces) {
      to_o(rot_o, face_o, face_rows(normal_w, friction, with_normal, face_o));
      for (std::int64_t f = 0; f < faces; ++f) {
        const std::int64_t row = i * faces + f;
        force_row(face_o[f], T.axis_rows, n, chain_x0, chain_basis, d_i,
                  V.inequality + row * free + start, V.lows, row,
                  with_normal && f == 0 ? min_normal : 0.0);
      }
    }
    if (moment_axes && T.soles[3 * i] > 0.0) {
      const double offset[3] = {d0, d1, d2};
      sole_rows(frames + 12 * a_row, rot_o, T.soles + 3 * i, friction, offset, T.axis_rows, n,
                chain_x0, chain_basis, d_i, V.inequality + sole_row * free + start, free,
                V.lows + sole_row);
      sole_row += 6;
    }
    start += d_i;
  }
  double scale = T.settings[3];
  for (std::int64_t r = 0; r < nk; ++r) {
    V.equality_rhs[s + r] += wrench[kept[r]];
    scale = py_max(scale, std::abs(wrench[kept[r]]));
  }
  for (std::int64_t t = 0; t < s; ++t) V.equality_rhs[t] += T.const_rhs[t];
  for (std::int64_t v = 0; v < nv; ++v) scale = py_max(scale, std::abs(V.passive[v]));
  for (std::int64_t t = 0; t < T.t; ++t) {  // -limit <= tau0 + T z <= limit
    const std::int64_t v = T.limited_v[t];
    const std::int64_t row = m_in - T.t + t;
    for (std::int64_t j = 0; j < free; ++j) V.inequality[row * free + j] = V.tmap[v * free + j];
    V.lows[row] = -T.limits[t] - V.tau0[v];
    V.uppers[row] = T.limits[t] - V.tau0[v];
  }
  scale = py_max(scale, 1e-300);
  for (std::int64_t r = 0; r < V.rows_eq; ++r) V.equality_rhs[r] /= scale;
  for (std::int64_t r = 0; r < m_in; ++r) {
    V.lows[r] = py_max(V.lows[r] / scale, -QP_INFINITY);
    V.uppers[r] =
        V.uppers[r] < QP_INFINITY ? py_min(V.uppers[r] / scale, QP_INFINITY) : QP_INFINITY;
  }
  result.status = 0;
  result.worst = worst;
  result.scale = scale;
  return result;
}

// Largest miss of z (scaled) on the first `equalities` equality rows and every inequality row
// (-inf for none; a non-finite z gives inf).
inline double violation(const QPViews& V, const double* z, std::int64_t nz,
                        std::int64_t equalities) {
  double worst = -INF;
  for (std::int64_t r = 0; r < equalities; ++r) {
    double acc = -V.equality_rhs[r];
    for (std::int64_t j = 0; j < nz; ++j) acc += V.equality[r * V.free + j] * z[j];
    worst = py_max(worst, std::abs(acc));
  }
  for (std::int64_t r = 0; r < V.m_in; ++r) {
    double acc = 0.0;
    for (std::int64_t j = 0; j < nz; ++j) acc += V.inequality[r * V.free + j] * z[j];
    worst = py_max(py_max(worst, V.lows[r] - acc), acc - V.uppers[r]);
  }
  for (std::int64_t j = 0; j < nz; ++j)
    if (!std::isfinite(z[j])) return INF;
  return worst;
}

// Forces, torques and norms of the answer z (scaled) into out (zeros: forces, tau, passive,
// produced, requested) and active (the active rows first): returns their count; the norms in
// d (residual, scale, rounding incl. the solver's accuracy).
inline std::int64_t read_out(const QPViews& V, std::int64_t pn, std::int64_t nv, const double* z,
                             std::int64_t nz, const double* multipliers, std::int64_t m,
                             double scale, const double* wrench, std::int64_t n,
                             const std::int64_t* keep, double active_tol, double accuracy,
                             double* out, std::int64_t* active, Distributed& d) {
  double* forces = out;
  double* tau = out + pn;
  double* produced = out + pn + 2 * nv;
  double* requested = out + pn + 2 * nv + n;
  for (std::int64_t r = 0; r < pn; ++r) {
    double acc = 0.0;
    for (std::int64_t j = 0; j < nz; ++j) acc += V.basis[r * V.free + j] * z[j];
    forces[r] = V.x0[r] + acc * scale;
    produced[r % n] += forces[r];
  }
  for (std::int64_t v = 0; v < nv; ++v) {
    double acc = 0.0;
    for (std::int64_t j = 0; j < nz; ++j) acc += V.tmap[v * V.free + j] * z[j];
    tau[v] = V.tau0[v] + acc * scale;
    out[pn + nv + v] = V.passive[v];
  }
  close_norms(keep, n, wrench, forces, pn, produced, requested, d);
  d.rounding = d.rounding + accuracy * 10.0 * scale;
  std::int64_t count = 0;
  for (std::int64_t r = 0; r < m; ++r)
    if (std::abs(multipliers[r]) > active_tol) active[count++] = r;
  return count;
}

}  // namespace va
