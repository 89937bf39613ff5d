// The QP distribution's Python object QP (qp.hpp, exact.hpp), bound in bind_qp.cpp with its free
// kernels, and the workspace checks and per-thread scratch they share; a compiled machine runs
// its QP attachments through one (QP::again_raw, bind_plan_qp.hpp).
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include "bind_common.hpp"
#include "bind_kinematics.hpp"
#include "distribute.hpp"
#include "exact.hpp"
#include "qp.hpp"

namespace va::py {

// The views of a workspace's buffer after checking its layout (qp.compiled.Workspace): the ten
// arrays back to back from 0, then free, rows_eq, m_in and design.
inline va::QPViews checked_views(const MF1& buffer, const I1& layout, std::int64_t pn,
                                 std::int64_t nv) {
  require(len(layout) == va::QP_LAYOUT, "layout must have 14 entries");
  const std::int64_t* L = layout.data();
  const std::int64_t free = L[10], rows_eq = L[11], m_in = L[12], design = L[13];
  require(pn >= 0 && nv >= 0 && free >= 0 && rows_eq >= 0 && m_in >= 0 && design >= 0 &&
              design <= rows_eq,
          "layout: negative sizes, or more design rows than equality rows");
  const std::int64_t sizes[10] = {pn * free, pn,   rows_eq * free, rows_eq, m_in * free,
                                  m_in,      m_in, nv * free,      nv,      nv};
  std::int64_t at = 0;
  for (int k = 0; k < 10; ++k) {
    require(L[k] == at, "layout: offsets do not match the sizes");
    at += sizes[k];
  }
  require(length(buffer) == at, "buffer: length does not match the layout");
  return va::QPViews(buffer.data(), L);
}

inline nb::tuple norms_tuple(std::int64_t count, const va::Distributed& d) {
  return nb::make_tuple(count, nb::make_tuple(d.residual, d.scale, d.rounding));
}

// keep as 0/1 integers into out (resized; its capacity kept).
inline void keep_ints(const B1& keep, std::int64_t n, std::vector<std::int64_t>& out) {
  require(static_cast<std::int64_t>(keep.shape(0)) == n, "keep must be (n,)");
  out.resize(static_cast<std::size_t>(n));
  for (std::int64_t a = 0; a < n; ++a) out[a] = keep.data()[a] ? 1 : 0;
}

// A QP tick's arrays, one set per thread: a warm tick allocates nothing.
struct TickScratch {
  std::vector<std::int64_t> keep;
  std::vector<double> z, multipliers, kinematics;
};

inline TickScratch& tick_scratch() {
  thread_local TickScratch scratch;
  return scratch;
}

// What a QP declaration fixes (qp.compiled.CompiledQPMatrices), owned: a tick passes the
// snapshot's arrays, the request and its workspace.
class QP {
 public:
  QP(const I1& axis_rows, const I1& frame_rows, const I2& chain_ints, const F2& chain_signs,
     const F2& springs, const F3& const_rows, const F1& const_rhs, const F2& normals_world,
     const I1& frame_normals, const F1& settings, const F2& soles, const I1& limited_v,
     const F1& limits)
      : axis_rows_(copy<std::int64_t>(axis_rows)),
        frame_rows_(copy<std::int64_t>(frame_rows)),
        chain_ints_(copy<std::int64_t>(chain_ints)),
        chain_signs_(copy<double>(chain_signs)),
        springs_(copy<double>(springs)),
        const_rows_(copy<double>(const_rows)),
        const_rhs_(copy<double>(const_rhs)),
        normals_world_(copy<double>(normals_world)),
        frame_normals_(copy<std::int64_t>(frame_normals)),
        settings_(copy<double>(settings)),
        soles_(copy<double>(soles)),
        limited_v_(copy<std::int64_t>(limited_v)),
        limits_(copy<double>(limits)) {
    va::QPTables& T = t_;
    T.n = len(axis_rows);
    T.p = static_cast<std::int64_t>(chain_ints.shape(0));
    T.nv = static_cast<std::int64_t>(springs.shape(0));
    T.K = static_cast<std::int64_t>(chain_signs.shape(1));
    T.C = static_cast<std::int64_t>(chain_ints.shape(1)) - va::QP_HEADER - T.K - 3;
    T.s = static_cast<std::int64_t>(const_rows.shape(0));
    T.t = len(limited_v);
    require(T.n >= 1 && T.n <= 6, "axis_rows must have 1 to 6 entries");
    for (std::int64_t a = 0; a < T.n; ++a)
      require(axis_rows_[a] >= 0 && axis_rows_[a] < 6, "axis_rows must be in 0..5");
    require(T.p >= 1 && len(frame_rows) == 2 + T.p, "frame_rows must be (2 + p,)");
    for (std::int64_t r = 0; r < 2 + T.p; ++r)
      require(frame_rows_[r] >= 0, "frame_rows must be >= 0");
    require(static_cast<std::int64_t>(chain_signs.shape(0)) == T.p && T.C >= 0,
            "chain_ints must be (p, 3 + K + C + 3), chain_signs (p, K)");
    require(springs.shape(1) == 5, "springs must be (nv, 5)");
    require(static_cast<std::int64_t>(const_rows.shape(1)) == T.p &&
                static_cast<std::int64_t>(const_rows.shape(2)) == T.n && length(const_rhs) == T.s,
            "const_rows must be (s, p, n), const_rhs (s,)");
    require(static_cast<std::int64_t>(normals_world.shape(0)) == T.p &&
                normals_world.shape(1) == 3 && len(frame_normals) == T.p,
            "normals_world must be (p, 3), frame_normals (p,)");
    require(length(settings) == 4, "settings must be (4,)");
    require(static_cast<std::int64_t>(soles.shape(0)) == T.p && soles.shape(1) == 3,
            "soles must be (p, 3)");
    require(length(limits) == T.t, "limits must be (t,) like limited_v");
    for (std::int64_t t = 0; t < T.t; ++t)
      require(limited_v_[t] >= 0 && limited_v_[t] < T.nv, "limited_v out of range");
    const std::int64_t width = T.width();
    for (std::int64_t i = 0; i < T.p; ++i) {
      const std::int64_t* row = chain_ints_.data() + i * width;
      const std::int64_t k_i = row[0], c_i = row[1], nb = row[2];
      require(k_i >= 0 && k_i <= T.K && c_i >= 0 && c_i <= T.C && c_i <= k_i && nb >= 0 && nb <= 3,
              "chain_ints: chain header");
      for (std::int64_t j = 0; j < k_i; ++j)
        require(row[va::QP_HEADER + j] >= 0 && row[va::QP_HEADER + j] < T.nv,
                "chain_ints: chain columns");
      for (std::int64_t j = 0; j < c_i; ++j)
        require(row[va::QP_HEADER + T.K + j] >= 0 && row[va::QP_HEADER + T.K + j] < k_i,
                "chain_ints: constrained joints");
      for (std::int64_t j = 0; j < nb; ++j)
        require(row[va::QP_HEADER + T.K + T.C + j] >= 0 && row[va::QP_HEADER + T.K + T.C + j] < 3,
                "chain_ints: ball axes");
      free_ += k_i - c_i;
    }
    max_q_ = -1;
    for (std::int64_t v = 0; v < T.nv; ++v) {
      const double* sp = springs_.data() + 5 * v;
      require(sp[2] < 0 || sp[2] >= 0, "springs: NaN index");
      if (sp[2] >= 0)
        max_q_ = std::max(max_q_, static_cast<std::int64_t>(sp[2]) + (sp[3] > 0 ? 1 : 0));
    }
    max_frame_ = *std::max_element(frame_rows_.begin(), frame_rows_.end());
    T.axis_rows = axis_rows_.data();
    T.frame_rows = frame_rows_.data();
    T.chain_ints = chain_ints_.data();
    T.chain_signs = chain_signs_.data();
    T.springs = springs_.data();
    T.const_rows = const_rows_.data();
    T.const_rhs = const_rhs_.data();
    T.normals_world = normals_world_.data();
    T.frame_normals = frame_normals_.data();
    T.settings = settings_.data();
    T.soles = soles_.data();
    T.limited_v = limited_v_.data();
    T.limits = limits_.data();
  }

  // The reduced QP into the workspace: (status, worst ratio, scale).
  nb::tuple reduced(const F2& jacobian_world, const F2& frames, const F1& q, const F1& wrench,
                    const I1& kept, MF1 buffer, const I1& layout) const {
    check_snapshot(jacobian_world, frames);
    check(q, wrench, kept, buffer, layout);
    va::Reduced r;
    {
      nb::gil_scoped_release release;
      r = va::reduced_qp(jacobian_world.data(), frames.data(), q.data(), wrench.data(), kept.data(),
                         len(kept), t_, buffer.data(), length(buffer), layout.data());
    }
    return nb::make_tuple(r.status, r.worst, r.scale);
  }

  // again: the matrices, the exact step on guess's active set (guess replaced
  // by the new multipliers when certified), the read-out: (count, (residual, scale, rounding)),
  // count -1 when not certified.
  nb::tuple again(const F2& jacobian_world, const F2& frames, const F1& q, const F1& wrench,
                  const I1& kept, MF1 buffer, const I1& layout, const B1& keep, const F1& weights,
                  MF1 guess, double active_tol, double exact_tol, double accuracy, MF1 out,
                  MI1 active) const {
    check_snapshot(jacobian_world, frames);
    const va::QPViews V = check(q, wrench, kept, buffer, layout);
    return again_on(
        [&](const double*& jac, const double*& fr) {
          jac = jacobian_world.data();
          fr = frames.data();
        },
        V, q, wrench, kept, buffer, layout, keep, weights, guess, active_tol, exact_tol, accuracy,
        out, active);
  }

  // again() from q alone: the tree's kinematics first, in the same call (no snapshot).
  nb::tuple again_tick(const Tree& tree, const F1& q, const F1& wrench, const I1& kept, MF1 buffer,
                       const I1& layout, const B1& keep, const F1& weights, MF1 guess,
                       double active_tol, double exact_tol, double accuracy, MF1 out,
                       MI1 active) const {
    const va::Tree& t = *tree.tree();
    require(t.tables().nv == t_.nv, "the tree's nv differs from the QP's");
    require(t.tables().nf > max_frame_, "the tree's frame table lacks rows the QP reads");
    require(length(q) >= tree.nq(), "q is shorter than the tree's configuration");
    const va::QPViews V = check(q, wrench, kept, buffer, layout);
    std::vector<double>& kinematics = tick_scratch().kinematics;
    kinematics.assign(static_cast<std::size_t>(t.size(false)), 0.0);
    return again_on(
        [&](const double*& jac, const double*& fr) {
          t.compute(q.data(), nullptr, kinematics.data());
          jac = kinematics.data() + t.jacobian_offset();
          fr = kinematics.data() + t.frames_offset();
        },
        V, q, wrench, kept, buffer, layout, keep, weights, guess, active_tol, exact_tol, accuracy,
        out, active);
  }

  // again() on raw pointers, unchecked (a C++ caller that checked the workspace once with
  // views()): the read-out's count, -1 when not certified; out zeroed, keep (n) 0/1 ints, z and
  // multipliers scratch. No Python object is touched: callable without the GIL.
  std::int64_t again_raw(const double* jacobian_world, const double* frames, const double* q,
                         const double* wrench, const std::int64_t* kept, std::int64_t nkept,
                         const va::QPViews& V, double* buffer, std::int64_t buffer_size,
                         const std::int64_t* layout, const std::int64_t* keep,
                         const double* weights, double* guess, double active_tol, double exact_tol,
                         double accuracy, double* out, std::int64_t* active, std::vector<double>& z,
                         std::vector<double>& multipliers, va::Distributed& d) const {
    const va::Reduced r = va::reduced_qp(jacobian_world, frames, q, wrench, kept, nkept, t_, buffer,
                                         buffer_size, layout);
    if (r.status != 0) return -1;
    z.assign(static_cast<std::size_t>(V.free), 0.0);
    multipliers.assign(static_cast<std::size_t>(V.m_in), 0.0);
    if (!va::exact_step(V.rows(weights), guess, true, active_tol, exact_tol, va::EXACT_STEPS,
                        z.data(), multipliers.data()))
      return -1;
    std::copy(multipliers.begin(), multipliers.end(), guess);
    return va::read_out(V, t_.p * t_.n, t_.nv, z.data(), V.free, multipliers.data(), V.m_in,
                        r.scale, wrench, t_.n, keep, active_tol, accuracy, out, active, d);
  }

  // The workspace's views, checked against this QP (again()'s checks).
  va::QPViews views(const F1& q, const F1& wrench, const I1& kept, const MF1& buffer,
                    const I1& layout) const {
    return check(q, wrench, kept, buffer, layout);
  }
  std::int64_t max_frame_row() const { return max_frame_; }
  std::int64_t n() const { return t_.n; }
  std::int64_t chains() const { return t_.p; }

 private:
  // The matrices, the exact step on guess's active set, the read-out (GIL released);
  // kinematics(jac, frames) points both at the tick's arrays (computing them if need be).
  template <typename Kinematics>
  nb::tuple again_on(Kinematics kinematics, const va::QPViews& V, const F1& q, const F1& wrench,
                     const I1& kept, MF1& buffer, const I1& layout, const B1& keep,
                     const F1& weights, MF1& guess, double active_tol, double exact_tol,
                     double accuracy, MF1& out, MI1& active) const {
    const std::int64_t n = t_.n, pn = t_.p * t_.n, nv = t_.nv;
    require(length(weights) >= len(kept), "weights must be (k,)");
    require(length(guess) == V.m_in, "guess must be (m,)");
    require(length(out) == pn + 2 * nv + 2 * n, "out must be (pn + 2 nv + 2 n,)");
    require(static_cast<std::int64_t>(active.shape(0)) >= V.m_in, "active must be (m,)");
    TickScratch& scratch = tick_scratch();
    keep_ints(keep, n, scratch.keep);
    const std::vector<std::int64_t>& keep_i = scratch.keep;
    va::Distributed d;
    std::int64_t count = -1;
    {
      nb::gil_scoped_release release;
      const double* jacobian_world = nullptr;
      const double* frames = nullptr;
      kinematics(jacobian_world, frames);
      const va::Reduced r =
          va::reduced_qp(jacobian_world, frames, q.data(), wrench.data(), kept.data(), len(kept),
                         t_, buffer.data(), length(buffer), layout.data());
      if (r.status == 0) {
        std::vector<double>& z = scratch.z;
        std::vector<double>& multipliers = scratch.multipliers;
        z.assign(static_cast<std::size_t>(V.free), 0.0);
        multipliers.assign(static_cast<std::size_t>(V.m_in), 0.0);
        const bool certified =
            va::exact_step(V.rows(weights.data()), guess.data(), true, active_tol, exact_tol,
                           va::EXACT_STEPS, z.data(), multipliers.data());
        if (certified) {
          std::copy(multipliers.begin(), multipliers.end(), guess.data());
          count = va::read_out(V, pn, nv, z.data(), V.free, multipliers.data(), V.m_in, r.scale,
                               wrench.data(), n, keep_i.data(), active_tol, accuracy, out.data(),
                               active.data(), d);
        }
      }
    }
    if (count < 0) return norms_tuple(-1, va::Distributed{0.0, 0.0, 0.0});
    return norms_tuple(count, d);
  }

  void check_snapshot(const F2& jacobian_world, const F2& frames) const {
    require(
        jacobian_world.shape(0) == 6 && static_cast<std::int64_t>(jacobian_world.shape(1)) == t_.nv,
        "jacobian_world must be (6, nv)");
    require(frames.shape(1) == 12 && static_cast<std::int64_t>(frames.shape(0)) > max_frame_,
            "frames must be (nf, 12) with every row the QP reads");
  }

  va::QPViews check(const F1& q, const F1& wrench, const I1& kept, const MF1& buffer,
                    const I1& layout) const {
    const va::QPTables& T = t_;
    require(length(q) > max_q_, "q is shorter than the springs' indices");
    require(length(wrench) == T.n, "wrench must be (n,)");
    for (std::int64_t r = 0; r < len(kept); ++r)
      require(kept.data()[r] >= 0 && kept.data()[r] < T.n, "kept out of range");
    const va::QPViews V = checked_views(buffer, layout, T.p * T.n, T.nv);
    require(V.free == free_, "layout: free must be the chains' free columns");
    require(V.rows_eq == T.s + len(kept) && V.design == T.s,
            "layout: equality rows must be the design rows and the kept axes");
    std::int64_t force_axes = 0, moment_axes = 0, soles = 0;
    for (std::int64_t a = 0; a < T.n; ++a) {
      force_axes += T.axis_rows[a] < 3;
      moment_axes += T.axis_rows[a] >= 3;
    }
    for (std::int64_t i = 0; i < T.p; ++i) soles += T.soles[3 * i] > 0.0;
    const bool with_normal = T.settings[2] > 0.0;
    const std::int64_t faces =
        force_axes ? (with_normal ? 1 : 0) + (T.settings[0] >= 0.0 ? 4 : 0) : 0;
    require(V.m_in >= T.p * faces + (moment_axes ? 6 * soles : 0) + T.t,
            "layout: fewer inequality rows than the contacts and limits give");
    return V;
  }

  std::vector<std::int64_t> axis_rows_, frame_rows_, chain_ints_;
  std::vector<double> chain_signs_, springs_, const_rows_, const_rhs_, normals_world_;
  std::vector<std::int64_t> frame_normals_;
  std::vector<double> settings_, soles_;
  std::vector<std::int64_t> limited_v_;
  std::vector<double> limits_;
  va::QPTables t_;
  std::int64_t free_ = 0, max_q_ = -1, max_frame_ = 0;
};

}  // namespace va::py
