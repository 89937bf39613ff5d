// The QP distribution's bindings (qp.hpp, exact.hpp, daqp_stage.hpp): QP (bind_qp.hpp), the
// exact step on an active set, the workspace's violation and read-out, and the DAQP stages.
#include "bind_qp.hpp"

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "bind_common.hpp"
#include "daqp_stage.hpp"
#include "exact.hpp"
#include "qp.hpp"

namespace va::py {
namespace {

// The QP's answer on an active set (qp.exact.exact_step): (ok, x, z).
nb::tuple exact_step(const F2& equality, const F1& equality_rhs, std::int64_t design,
                     const F1& weights, const F2& inequality, const F1& lows, const F1& uppers,
                     const F1& guess, bool exact, double active_tol, double tol,
                     std::int64_t max_steps) {
  const auto k = static_cast<std::int64_t>(equality.shape(0));
  const auto size = static_cast<std::int64_t>(equality.shape(1));
  const auto m = static_cast<std::int64_t>(inequality.shape(0));
  require(length(equality_rhs) == k, "equality_rhs must be (k,)");
  require(design >= 0 && design <= k, "design must be in [0, k]");
  require(length(weights) >= k - design, "weights must have k - design entries");
  require(m == 0 || static_cast<std::int64_t>(inequality.shape(1)) == size,
          "inequality must be (m, d)");
  require(length(lows) == m && length(uppers) == m && length(guess) == m,
          "lows, uppers and guess must be (m,)");
  require(max_steps >= 0, "max_steps must be >= 0");
  const va::ExactRows rows{equality.data(), equality_rhs.data(), k,           size,          design,
                           weights.data(),  inequality.data(),   lows.data(), uppers.data(), m};
  std::unique_ptr<double[]> x(new double[static_cast<std::size_t>(size)]());
  std::unique_ptr<double[]> z(new double[static_cast<std::size_t>(m)]());
  bool ok;
  {
    nb::gil_scoped_release release;
    ok = va::exact_step(rows, guess.data(), exact, active_tol, tol, max_steps, x.get(), z.get());
  }
  return nb::make_tuple(ok, owned(std::move(x), static_cast<std::size_t>(size)),
                        owned(std::move(z), static_cast<std::size_t>(m)));
}

double qp_violation(const MF1& buffer, const I1& layout, std::int64_t pn, std::int64_t nv,
                    const F1& z, std::int64_t equalities) {
  const va::QPViews V = checked_views(buffer, layout, pn, nv);
  require(length(z) == V.free, "z must be (d,)");
  require(equalities >= 0 && equalities <= V.rows_eq, "equalities out of range");
  return va::violation(V, z.data(), length(z), equalities);
}

// Forces, torques and norms of an answer (the read-out).
nb::tuple qp_read_out(const MF1& buffer, const I1& layout, std::int64_t pn, std::int64_t nv,
                      const F1& z, const F1& multipliers, double scale, const F1& wrench,
                      const B1& keep, double active_tol, double accuracy, MF1 out, MI1 active) {
  const va::QPViews V = checked_views(buffer, layout, pn, nv);
  const std::int64_t n = length(wrench);
  require(n >= 1 && pn % n == 0, "wrench must be (n,) with pn a multiple of n");
  require(length(z) == V.free, "z must be (d,)");
  require(length(multipliers) == V.m_in, "multipliers must be (m,)");
  require(length(out) == pn + 2 * nv + 2 * n, "out must be (pn + 2 nv + 2 n,)");
  require(static_cast<std::int64_t>(active.shape(0)) >= V.m_in, "active must be (m,)");
  std::vector<std::int64_t>& kept = tick_scratch().keep;
  keep_ints(keep, n, kept);
  va::Distributed d;
  std::int64_t count;
  {
    nb::gil_scoped_release release;
    count = va::read_out(V, pn, nv, z.data(), length(z), multipliers.data(), V.m_in, scale,
                         wrench.data(), n, kept.data(), active_tol, accuracy, out.data(),
                         active.data(), d);
  }
  return norms_tuple(count, d);
}

// -- DAQP ------------------------------------------------------------------------------------

// The rows of a DAQP stage checked (its iteration limit too); returns (k, size, m).
std::array<std::int64_t, 3> daqp_rows(const F2& equality, const F1& equality_rhs,
                                      const F2& inequality, const F1& lows, const F1& uppers,
                                      int iter_limit) {
  const auto k = static_cast<std::int64_t>(equality.shape(0));
  const auto size = static_cast<std::int64_t>(equality.shape(1));
  const auto m = static_cast<std::int64_t>(inequality.shape(0));
  require(size >= 1, "at least one variable");
  require(length(equality_rhs) == k, "equality_rhs must be (k,)");
  require(m == 0 || static_cast<std::int64_t>(inequality.shape(1)) == size,
          "inequality must be (m, d)");
  require(length(lows) == m && length(uppers) == m, "lows and uppers must be (m,)");
  require(iter_limit >= 1, "iter_limit must be >= 1");
  return {k, size, m};
}

// solve(x, lam) without the GIL: (exitflag, x, lam, iterations).
template <class Solve>
nb::tuple daqp_tuple(std::int64_t size, std::int64_t m, Solve solve) {
  std::unique_ptr<double[]> x(new double[static_cast<std::size_t>(size)]());
  std::unique_ptr<double[]> lam(new double[static_cast<std::size_t>(m)]());
  va::DaqpAnswer answer;
  {
    nb::gil_scoped_release release;
    answer = solve(x.get(), lam.get());
  }
  return nb::make_tuple(answer.exitflag, owned(std::move(x), static_cast<std::size_t>(size)),
                        owned(std::move(lam), static_cast<std::size_t>(m)), answer.iterations);
}

// The QP's first stage on DAQP from cold: (exitflag, x, lam, iterations).
nb::tuple daqp_least_norm(const F2& equality, const F1& equality_rhs, const F2& inequality,
                          const F1& lows, const F1& uppers, int iter_limit) {
  const auto [k, size, m] = daqp_rows(equality, equality_rhs, inequality, lows, uppers, iter_limit);
  return daqp_tuple(size, m, [&, k = k, size = size, m = m](double* x, double* lam) {
    return va::daqp_least_norm(equality.data(), equality_rhs.data(), k, size, inequality.data(),
                               lows.data(), uppers.data(), m, iter_limit, x, lam);
  });
}

// The QP's closest-wrench stages on DAQP from cold, regularised: (exitflag, x, lam,
// iterations).
nb::tuple daqp_closest(const F2& equality, const F1& equality_rhs, std::int64_t design,
                       const F1& weights, const F2& inequality, const F1& lows, const F1& uppers,
                       int iter_limit, double eps) {
  const auto [k, size, m] = daqp_rows(equality, equality_rhs, inequality, lows, uppers, iter_limit);
  require(design >= 0 && design < k, "design must be in 0..k-1 (a request row at least)");
  require(length(weights) == k - design, "weights must be (k - design,)");
  for (std::int64_t i = 0; i < k - design; ++i)
    require(weights.data()[i] > 0.0, "weights must be > 0");
  require(eps > 0.0, "eps must be > 0");
  return daqp_tuple(size, m, [&, k = k, size = size, m = m](double* x, double* lam) {
    return va::daqp_closest(equality.data(), equality_rhs.data(), k, design, size, weights.data(),
                            inequality.data(), lows.data(), uppers.data(), m, iter_limit, eps, x,
                            lam);
  });
}

}  // namespace

void bind_qp(nb::module_& m) {
  m.def("exact_step", &exact_step, "equality"_a, "equality_rhs"_a, "design"_a, "weights"_a,
        "inequality"_a, "lows"_a, "uppers"_a, "guess"_a, "exact"_a, "active_tol"_a, "tol"_a,
        "max_steps"_a,
        "qp.exact.exact_step: the QP's answer on the active set guess names, (ok, x, z).");
  m.def("qp_violation", &qp_violation, "buffer"_a.noconvert(), "layout"_a, "pn"_a, "nv"_a, "z"_a,
        "equalities"_a, "The largest miss of z.");
  m.def("qp_read_out", &qp_read_out, "buffer"_a.noconvert(), "layout"_a, "pn"_a, "nv"_a, "z"_a,
        "multipliers"_a, "scale"_a, "wrench"_a, "keep"_a, "active_tol"_a, "accuracy"_a,
        "out"_a.noconvert(), "active"_a.noconvert(),
        "The read-out: (count of active rows, (residual, scale, rounding)).");

  nb::class_<QP>(m, "QP", "What a QP declaration fixes (CompiledQPMatrices).")
      .def(nb::init<const I1&, const I1&, const I2&, const F2&, const F2&, const F3&, const F1&,
                    const F2&, const I1&, const F1&, const F2&, const I1&, const F1&>(),
           "axis_rows"_a, "frame_rows"_a, "chain_ints"_a, "chain_signs"_a, "springs"_a,
           "const_rows"_a, "const_rhs"_a, "normals_world"_a, "frame_normals"_a, "settings"_a,
           "soles"_a, "limited_v"_a, "limits"_a)
      .def("reduced", &QP::reduced, "jacobian_world"_a, "frames"_a, "q"_a, "wrench"_a, "kept"_a,
           "buffer"_a.noconvert(), "layout"_a,
           "The reduced QP into buffer: (status, worst ratio, scale).")
      .def("again", &QP::again, "jacobian_world"_a, "frames"_a, "q"_a, "wrench"_a, "kept"_a,
           "buffer"_a.noconvert(), "layout"_a, "keep"_a, "weights"_a, "guess"_a.noconvert(),
           "active_tol"_a, "exact_tol"_a, "accuracy"_a, "out"_a.noconvert(), "active"_a.noconvert(),
           "again: (count, (residual, scale, rounding)), count -1: not "
           "certified.")
      .def("again_tick", &QP::again_tick, "tree"_a, "q"_a, "wrench"_a, "kept"_a,
           "buffer"_a.noconvert(), "layout"_a, "keep"_a, "weights"_a, "guess"_a.noconvert(),
           "active_tol"_a, "exact_tol"_a, "accuracy"_a, "out"_a.noconvert(), "active"_a.noconvert(),
           "again() from q alone: the tree's forward kinematics in the same call.");
  m.def("daqp_least_norm", &daqp_least_norm, "equality"_a, "equality_rhs"_a, "inequality"_a,
        "lows"_a, "uppers"_a, "iter_limit"_a,
        "The QP's first stage on DAQP (vendored, MIT) from cold, min |x|^2 on the rows: "
        "(exitflag, x, inequality multipliers, iterations).");
  m.def("daqp_closest", &daqp_closest, "equality"_a, "equality_rhs"_a, "design"_a, "weights"_a,
        "inequality"_a, "lows"_a, "uppers"_a, "iter_limit"_a, "eps"_a,
        "The QP's closest-wrench stages on DAQP from cold, min |x|^2 / 2 + the weighted miss "
        "/ (2 eps): (exitflag, x, inequality multipliers, iterations).");
}

}  // namespace va::py
