// virtual_actuators._core: the Python bindings of the compiled kernels (nanobind), built at
// install by scikit-build-core (CMakeLists.txt). The only file of src/core that knows Python:
// the kernels are header-only C++17 (kinematics.hpp, linalg.hpp, batch.hpp, solves.hpp,
// distribute.hpp). Arguments are checked here; the GIL is released while a kernel runs.
//
// Objects hold what a declaration fixes (Tree: the kinematic tables; Distribution: the packed
// tables of one distribution mode), so that a tick passes only q (v) and the wrench.
#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>
#include <nanobind/stl/optional.h>
#include <nanobind/stl/vector.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <stdexcept>
#include <vector>

#include "daqp_stage.hpp"
#include "distribute.hpp"
#include "kinematics.hpp"
#include "qp.hpp"
#include "sensor.hpp"

namespace nb = nanobind;
using namespace nb::literals;

namespace {

using F1 = nb::ndarray<const double, nb::numpy, nb::ndim<1>, nb::c_contig, nb::device::cpu>;
using F2 = nb::ndarray<const double, nb::numpy, nb::ndim<2>, nb::c_contig, nb::device::cpu>;
using I1 = nb::ndarray<const std::int64_t, nb::numpy, nb::ndim<1>, nb::c_contig, nb::device::cpu>;
using I2 = nb::ndarray<const std::int64_t, nb::numpy, nb::ndim<2>, nb::c_contig, nb::device::cpu>;
using F3 = nb::ndarray<const double, nb::numpy, nb::ndim<3>, nb::c_contig, nb::device::cpu>;
using B1 = nb::ndarray<const bool, nb::numpy, nb::ndim<1>, nb::c_contig, nb::device::cpu>;
// Arrays the kernels write into: never converted (a converted copy would take the writes).
using MF1 = nb::ndarray<double, nb::numpy, nb::ndim<1>, nb::c_contig, nb::device::cpu>;
using MI1 = nb::ndarray<std::int64_t, nb::numpy, nb::ndim<1>, nb::c_contig, nb::device::cpu>;
using Owned = nb::ndarray<nb::numpy, double, nb::ndim<1>>;
// Any array (Distribution.checked_tick casts its arguments without converting them).
using Any = nb::ndarray<nb::ro, nb::device::cpu>;

void require(bool ok, const char* what) {
  if (!ok) throw std::invalid_argument(what);
}

std::int64_t length(const F1& a) { return static_cast<std::int64_t>(a.shape(0)); }
std::int64_t length(const MF1& a) { return static_cast<std::int64_t>(a.shape(0)); }

// A new numpy array of `size` doubles that owns `data` (allocated with new[]).
Owned owned(std::unique_ptr<double[]> data, std::size_t size) {
  double* raw = data.release();
  nb::capsule owner(raw, [](void* p) noexcept { delete[] static_cast<double*>(p); });
  return Owned(raw, {size}, owner);
}

template <typename T, typename A>
std::vector<T> copy(const A& a) {
  return std::vector<T>(a.data(), a.data() + a.size());
}

// -- kinematics ------------------------------------------------------------------------------

// The declaration-time tables of a kinematic tree (KinematicTree builds one per frame table).
class Tree {
 public:
  Tree(const I2& joint_ints, const F2& joint_floats, const I1& velocity_joint,
       const F2& velocity_subspace, const I1& frame_parents, const F2& frame_floats,
       const I2& unit_bounds) {
    require(joint_ints.shape(0) >= 1 && joint_ints.shape(1) == 3,
            "joint_ints must be (njoints, 3)");
    require(joint_floats.shape(0) == joint_ints.shape(0) && joint_floats.shape(1) == 27,
            "joint_floats must be (njoints, 27)");
    require(velocity_subspace.shape(0) == velocity_joint.shape(0) &&
                velocity_subspace.shape(1) == 6,
            "velocity_subspace must be (nv, 6)");
    require(frame_floats.shape(0) == frame_parents.shape(0) && frame_floats.shape(1) == 12,
            "frame_floats must be (nf, 12)");
    const auto njoints = static_cast<std::int64_t>(joint_ints.shape(0));
    nq_ = 0;
    for (std::int64_t j = 1; j < njoints; ++j) {
      const std::int64_t kind = joint_ints.data()[3 * j + 1];
      const std::int64_t iq = joint_ints.data()[3 * j + 2];
      require(kind >= va::REVOLUTE && kind <= va::SPHERICAL, "unsupported joint kind");
      require(joint_ints.data()[3 * j] >= 0 && joint_ints.data()[3 * j] < j,
              "a joint's parent must come before it");
      const std::int64_t width = kind == va::REVOLUTE || kind == va::PRISMATIC ? 1
                                 : kind == va::REVOLUTE_UNBOUNDED             ? 2
                                 : kind == va::FREE_FLYER                     ? 7
                                                                              : 4;
      nq_ = std::max(nq_, iq + width);
    }
    for (std::size_t v = 0; v < velocity_joint.shape(0); ++v)
      require(velocity_joint.data()[v] >= 1 && velocity_joint.data()[v] < njoints,
              "velocity_joint out of range");
    for (std::size_t f = 0; f < frame_parents.shape(0); ++f)
      require(frame_parents.data()[f] >= 0 && frame_parents.data()[f] < njoints,
              "frame_parents out of range");
    require(unit_bounds.shape(1) == 2, "unit_bounds must be (m, 2)");
    for (std::size_t s = 0; s < unit_bounds.shape(0); ++s)
      require(unit_bounds.data()[2 * s] >= 0 &&
                  unit_bounds.data()[2 * s] <= unit_bounds.data()[2 * s + 1] &&
                  unit_bounds.data()[2 * s + 1] <= nq_,
              "unit_bounds out of range");
    unit_bounds_ = copy<std::int64_t>(unit_bounds);
    tree_ = std::make_shared<const va::Tree>(
        copy<std::int64_t>(joint_ints), copy<double>(joint_floats),
        copy<std::int64_t>(velocity_joint), copy<double>(velocity_subspace),
        copy<std::int64_t>(frame_parents), copy<double>(frame_floats));
  }

  // One buffer: joints (njoints, 12), Jacobian (6, nv), frames (nf, 12), [velocities (nf, 3)].
  Owned compute(const F1& q, std::optional<F1> v) const {
    require(length(q) >= nq_, "q is shorter than the tree's configuration");
    const va::TreeTables& t = tree_->tables();
    require(!v || length(*v) == t.nv, "v must be (nv,)");
    const auto size = static_cast<std::size_t>(tree_->size(v.has_value()));
    std::unique_ptr<double[]> buffer(new double[size]);
    {
      nb::gil_scoped_release release;
      tree_->compute(q.data(), v ? v->data() : nullptr, buffer.get());
    }
    return owned(std::move(buffer), size);
  }

  std::int64_t size(bool with_velocity) const { return tree_->size(with_velocity); }
  std::int64_t nq() const { return nq_; }
  std::int64_t nf() const { return tree_->tables().nf; }
  const std::shared_ptr<const va::Tree>& tree() const { return tree_; }

  // Whether q is a finite float64 (nq,) vector whose unit-norm groups (quaternions, (cos, sin)
  // pairs) are within 1e-12 of norm 1: what KinematicTree.check_configuration returns unchanged.
  bool accepts(const Any& q) const {
    if (!(q.dtype() == nb::dtype<double>() && q.ndim() == 1 &&
          static_cast<std::int64_t>(q.shape(0)) == nq_ && (nq_ <= 1 || q.stride(0) == 1)))
      return false;
    const double error =
        va::unit_norm_error(static_cast<const double*>(q.data()), nq_, unit_bounds_.data(),
                            static_cast<std::int64_t>(unit_bounds_.size() / 2));
    return 0.0 <= error && error <= 1e-12;
  }

 private:
  std::shared_ptr<const va::Tree> tree_;
  std::int64_t nq_ = 0;
  std::vector<std::int64_t> unit_bounds_;  // (m, 2) flat: [start, stop) of each unit group
};

double unit_norm_error(const F1& q, const I2& bounds) {
  require(bounds.shape(1) == 2, "bounds must be (m, 2)");
  const auto m = static_cast<std::int64_t>(bounds.shape(0));
  for (std::int64_t s = 0; s < m; ++s)
    require(bounds.data()[2 * s] >= 0 && bounds.data()[2 * s] <= bounds.data()[2 * s + 1] &&
                bounds.data()[2 * s + 1] <= length(q),
            "bounds out of range");
  return va::unit_norm_error(q.data(), length(q), bounds.data(), m);
}

bool all_finite(const F1& values) { return va::all_finite(values.data(), length(values)); }

nb::tuple point_velocity(const F2& jacobian_world, const F1& v, const I1& columns, double x,
                         double y, double z) {
  require(jacobian_world.shape(0) == 6, "jacobian_world must be (6, nv)");
  const auto nv = static_cast<std::int64_t>(jacobian_world.shape(1));
  require(length(v) == nv, "v must be (nv,)");
  for (std::size_t j = 0; j < columns.shape(0); ++j)
    require(columns.data()[j] >= 0 && columns.data()[j] < nv, "columns out of range");
  double out[3];
  va::point_velocity(jacobian_world.data(), nv, v.data(), columns.data(),
                     static_cast<std::int64_t>(columns.shape(0)), x, y, z, out);
  return nb::make_tuple(out[0], out[1], out[2]);
}

// -- distribution ----------------------------------------------------------------------------

// The tick's buffer and norms, as the reference kernel's Distributed (a NamedTuple in Python).
nb::tuple distributed(Owned out, const va::Distributed& d) {
  return nb::make_tuple(out, d.residual, d.scale, d.rounding, d.status, d.worst, d.worst_chain);
}

// The packed tables of one distribution mode (kernel_tables.pack_arguments), owned.
class Distribution {
 public:
  Distribution(const I1& ints, const F1& floats, std::int64_t nv)
      : ints_(copy<std::int64_t>(ints)), floats_(copy<double>(floats)), nv_(nv) {
    require(nv >= 0, "nv must be >= 0");
    packed_ = va::Packed::checked(ints_, floats_, nv);
  }

  // One tick from the snapshot's arrays: jacobian_world (6, nv), frames (nf, 12), q, wrench (n).
  nb::tuple solve(const F2& jacobian_world, const F2& frames, const F1& q,
                  const F1& wrench) const {
    require(jacobian_world.shape(0) == 6 &&
                static_cast<std::int64_t>(jacobian_world.shape(1)) == nv_,
            "jacobian_world must be (6, nv)");
    require(frames.shape(1) == 12 &&
                static_cast<std::int64_t>(frames.shape(0)) > packed_.max_frame_row(),
            "frames must be (nf, 12) with every row the distribution reads");
    check_tick(q, wrench);
    const auto size = static_cast<std::size_t>(packed_.out_size(nv_));
    std::unique_ptr<double[]> out(new double[size]());
    va::Distributed d;
    {
      nb::gil_scoped_release release;
      d = va::distribute(jacobian_world.data(), nv_, frames.data(), q.data(), wrench.data(),
                         packed_, out.get());
    }
    return distributed(owned(std::move(out), size), d);
  }

  // Kinematics and distribution in one call: the tick of a solve from q and the wrench.
  nb::tuple tick(const Tree& tree, const F1& q, const F1& wrench) const {
    const va::Tree& t = *tree.tree();
    require(t.tables().nv == nv_, "the tree's nv differs from the distribution's");
    require(t.tables().nf > packed_.max_frame_row(),
            "the tree's frame table lacks rows the distribution reads");
    require(length(q) >= tree.nq(), "q is shorter than the tree's configuration");
    check_tick(q, wrench);
    return run(t, q.data(), wrench.data());
  }

  // tick() on arguments no one has checked: status UNCHECKED, nothing computed, unless q is
  // what KinematicTree.check_configuration returns unchanged (Tree::accepts) and the wrench a
  // finite float64 (n,) vector, the tree has the frame rows and the springs' q indices are in
  // q. The caller's checks then raise their typed errors (or normalise q) and solve as usual.
  nb::tuple checked_tick(const Tree& tree, nb::handle q_object, nb::handle wrench_object) const {
    const va::Tree& t = *tree.tree();
    Any q, wrench;  // unconverted: a list, a copy or another dtype is the caller's to check
    const bool ok = nb::try_cast(q_object, q, false) &&
                    nb::try_cast(wrench_object, wrench, false) && t.tables().nv == nv_ &&
                    t.tables().nf > packed_.max_frame_row() &&
                    tree.accepts(q) && tree.nq() > packed_.max_q_index() &&
                    wrench.dtype() == nb::dtype<double>() && wrench.ndim() == 1 &&
                    static_cast<std::int64_t>(wrench.shape(0)) == packed_.n &&
                    (packed_.n <= 1 || wrench.stride(0) == 1) &&
                    va::all_finite(static_cast<const double*>(wrench.data()), packed_.n);
    if (!ok) {
      va::Distributed d;
      d.status = UNCHECKED;
      return distributed(owned(std::unique_ptr<double[]>(new double[1]), 0), d);
    }
    return run(t, static_cast<const double*>(q.data()),
               static_cast<const double*>(wrench.data()));
  }

  // checked_tick's status for arguments it leaves to the caller's checks
  static constexpr std::int64_t UNCHECKED = 4;

 private:
  nb::tuple run(const va::Tree& t, const double* q, const double* wrench) const {
    const auto size = static_cast<std::size_t>(packed_.out_size(nv_));
    std::unique_ptr<double[]> out(new double[size]());
    va::Distributed d;
    {
      nb::gil_scoped_release release;
      std::vector<double> kinematics(static_cast<std::size_t>(t.size(false)));
      t.compute(q, nullptr, kinematics.data());
      d = va::distribute(kinematics.data() + t.jacobian_offset(), nv_,
                         kinematics.data() + t.frames_offset(), q, wrench, packed_, out.get());
    }
    return distributed(owned(std::move(out), size), d);
  }

  void check_tick(const F1& q, const F1& wrench) const {
    require(length(wrench) == packed_.n, "wrench must be (n,)");
    require(length(q) > packed_.max_q_index(), "q is shorter than the springs' indices");
  }

  std::vector<std::int64_t> ints_;
  std::vector<double> floats_;
  std::int64_t nv_;
  va::Packed packed_;
};

// -- the QP distribution ---------------------------------------------------------------------

std::int64_t len(const I1& a) { return static_cast<std::int64_t>(a.shape(0)); }

// The views of a workspace's buffer after checking its layout (qp.compiled.Workspace): the ten
// arrays back to back from 0, then free, rows_eq, m_in and design.
va::QPViews checked_views(const MF1& buffer, const I1& layout, std::int64_t pn, std::int64_t nv) {
  require(len(layout) == va::QP_LAYOUT, "layout must have 14 entries");
  const std::int64_t* L = layout.data();
  const std::int64_t free = L[10], rows_eq = L[11], m_in = L[12], design = L[13];
  require(pn >= 0 && nv >= 0 && free >= 0 && rows_eq >= 0 && m_in >= 0 && design >= 0 &&
              design <= rows_eq,
          "layout: negative sizes, or more design rows than equality rows");
  const std::int64_t sizes[10] = {pn * free, pn, rows_eq * free, rows_eq, m_in * free,
                                  m_in,      m_in, nv * free,     nv,      nv};
  std::int64_t at = 0;
  for (int k = 0; k < 10; ++k) {
    require(L[k] == at, "layout: offsets do not match the sizes");
    at += sizes[k];
  }
  require(length(buffer) == at, "buffer: length does not match the layout");
  return va::QPViews(buffer.data(), L);
}

nb::tuple norms_tuple(std::int64_t count, const va::Distributed& d) {
  return nb::make_tuple(count, nb::make_tuple(d.residual, d.scale, d.rounding));
}

// keep as 0/1 integers into out (resized; its capacity kept).
void keep_ints(const B1& keep, std::int64_t n, std::vector<std::int64_t>& out) {
  require(static_cast<std::int64_t>(keep.shape(0)) == n, "keep must be (n,)");
  out.resize(static_cast<std::size_t>(n));
  for (std::int64_t a = 0; a < n; ++a) out[a] = keep.data()[a] ? 1 : 0;
}

// A QP tick's arrays, one set per thread: a warm tick allocates nothing.
struct TickScratch {
  std::vector<std::int64_t> keep;
  std::vector<double> z, multipliers, kinematics;
};

TickScratch& tick_scratch() {
  thread_local TickScratch scratch;
  return scratch;
}

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
  const va::ExactRows rows{equality.data(), equality_rhs.data(), k, size, design,
                           weights.data(), inequality.data(), lows.data(), uppers.data(), m};
  std::unique_ptr<double[]> x(new double[static_cast<std::size_t>(size)]());
  std::unique_ptr<double[]> z(new double[static_cast<std::size_t>(m)]());
  bool ok;
  {
    nb::gil_scoped_release release;
    ok = va::exact_step(rows, guess.data(), exact, active_tol, tol, max_steps, x.get(),
                        z.get());
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

// Forces, torques and norms of an answer (qp.kernel_answer.read_out).
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

// What a QP declaration fixes (qp.compiled.CompiledQPMatrices), owned: a tick passes the
// snapshot's arrays, the request and its workspace.
class QP {
 public:
  QP(const I1& axis_rows, const I1& frame_rows, const I2& chain_ints, const F2& chain_signs,
     const F2& springs, const F3& const_rows, const F1& const_rhs, const F2& normals_world,
     const I1& frame_normals, const F1& settings, const F2& soles, const I1& limited_v,
     const F1& limits)
      : axis_rows_(copy<std::int64_t>(axis_rows)), frame_rows_(copy<std::int64_t>(frame_rows)),
        chain_ints_(copy<std::int64_t>(chain_ints)), chain_signs_(copy<double>(chain_signs)),
        springs_(copy<double>(springs)), const_rows_(copy<double>(const_rows)),
        const_rhs_(copy<double>(const_rhs)), normals_world_(copy<double>(normals_world)),
        frame_normals_(copy<std::int64_t>(frame_normals)), settings_(copy<double>(settings)),
        soles_(copy<double>(soles)), limited_v_(copy<std::int64_t>(limited_v)),
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
                static_cast<std::int64_t>(const_rows.shape(2)) == T.n &&
                length(const_rhs) == T.s,
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
      require(k_i >= 0 && k_i <= T.K && c_i >= 0 && c_i <= T.C && c_i <= k_i && nb >= 0 &&
                  nb <= 3,
              "chain_ints: chain header");
      for (std::int64_t j = 0; j < k_i; ++j)
        require(row[va::QP_HEADER + j] >= 0 && row[va::QP_HEADER + j] < T.nv,
                "chain_ints: chain columns");
      for (std::int64_t j = 0; j < c_i; ++j)
        require(row[va::QP_HEADER + T.K + j] >= 0 && row[va::QP_HEADER + T.K + j] < k_i,
                "chain_ints: constrained joints");
      for (std::int64_t j = 0; j < nb; ++j)
        require(row[va::QP_HEADER + T.K + T.C + j] >= 0 &&
                    row[va::QP_HEADER + T.K + T.C + j] < 3,
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

  // qp.kernels.reduced_qp into the workspace: (status, worst ratio, scale).
  nb::tuple reduced(const F2& jacobian_world, const F2& frames, const F1& q, const F1& wrench,
                    const I1& kept, MF1 buffer, const I1& layout) const {
    check_snapshot(jacobian_world, frames);
    check(q, wrench, kept, buffer, layout);
    va::Reduced r;
    {
      nb::gil_scoped_release release;
      r = va::reduced_qp(jacobian_world.data(), frames.data(), q.data(), wrench.data(),
                         kept.data(), len(kept), t_, buffer.data(), length(buffer),
                         layout.data());
    }
    return nb::make_tuple(r.status, r.worst, r.scale);
  }

  // qp.kernel_answer.again: the matrices, the exact step on guess's active set (guess replaced
  // by the new multipliers when certified), the read-out: (count, (residual, scale, rounding)),
  // count -1 when not certified.
  nb::tuple again(const F2& jacobian_world, const F2& frames, const F1& q, const F1& wrench,
                  const I1& kept, MF1 buffer, const I1& layout, const B1& keep,
                  const F1& weights, MF1 guess, double active_tol, double exact_tol,
                  double accuracy, MF1 out, MI1 active) const {
    check_snapshot(jacobian_world, frames);
    const va::QPViews V = check(q, wrench, kept, buffer, layout);
    return again_on(
        [&](const double*& jac, const double*& fr) {
          jac = jacobian_world.data();
          fr = frames.data();
        },
        V, q, wrench, kept, buffer, layout, keep, weights, guess, active_tol, exact_tol,
        accuracy, out, active);
  }

  // again() from q alone: the tree's kinematics first, in the same call (no snapshot).
  nb::tuple again_tick(const Tree& tree, const F1& q, const F1& wrench, const I1& kept,
                       MF1 buffer, const I1& layout, const B1& keep, const F1& weights,
                       MF1 guess, double active_tol, double exact_tol, double accuracy, MF1 out,
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
        V, q, wrench, kept, buffer, layout, keep, weights, guess, active_tol, exact_tol,
        accuracy, out, active);
  }

  // again() on raw pointers, unchecked (a C++ caller that checked the workspace once with
  // views()): the read-out's count, -1 when not certified; out zeroed, keep (n) 0/1 ints, z and
  // multipliers scratch. No Python object is touched: callable without the GIL.
  std::int64_t again_raw(const double* jacobian_world, const double* frames, const double* q,
                         const double* wrench, const std::int64_t* kept, std::int64_t nkept,
                         const va::QPViews& V, double* buffer, std::int64_t buffer_size,
                         const std::int64_t* layout, const std::int64_t* keep,
                         const double* weights, double* guess, double active_tol,
                         double exact_tol, double accuracy, double* out,
                         std::int64_t* active, std::vector<double>& z,
                         std::vector<double>& multipliers, va::Distributed& d) const {
    const va::Reduced r = va::reduced_qp(jacobian_world, frames, q, wrench, kept, nkept, t_,
                                         buffer, buffer_size, layout);
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
      const va::Reduced r = va::reduced_qp(jacobian_world, frames, q.data(), wrench.data(),
                                           kept.data(), len(kept), t_, buffer.data(),
                                           length(buffer), layout.data());
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
                               wrench.data(), n, keep_i.data(), active_tol, accuracy,
                               out.data(), active.data(), d);
        }
      }
    }
    if (count < 0) return norms_tuple(-1, va::Distributed{0.0, 0.0, 0.0});
    return norms_tuple(count, d);
  }

  void check_snapshot(const F2& jacobian_world, const F2& frames) const {
    require(jacobian_world.shape(0) == 6 &&
                static_cast<std::int64_t>(jacobian_world.shape(1)) == t_.nv,
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

// -- sensors ---------------------------------------------------------------------------------

// sensor_kernels.relative_sensor: one buffer, jacobian (n, nv), position (n), velocity (n).
Owned relative_sensor(const F2& jacobian_world, const F2& frames, const F1& v,
                      const I1& axis_rows, const I1& rows, const I1& columns, const F1& signs) {
  require(jacobian_world.shape(0) == 6, "jacobian_world must be (6, nv)");
  const auto nv = static_cast<std::int64_t>(jacobian_world.shape(1));
  const std::int64_t n = len(axis_rows), nc = len(columns);
  require(n >= 1 && n <= 6, "axis_rows must have 1 to 6 entries");
  for (std::int64_t a = 0; a < n; ++a)
    require(axis_rows.data()[a] >= 0 && axis_rows.data()[a] < 6, "axis_rows must be in 0..5");
  require(len(rows) == 3 && frames.shape(1) == 12, "rows must be (3,), frames (nf, 12)");
  for (std::int64_t r = 0; r < 3; ++r)
    require(rows.data()[r] >= 0 && rows.data()[r] < static_cast<std::int64_t>(frames.shape(0)),
            "rows out of the frame table");
  require(length(signs) == nc, "signs must be like columns");
  for (std::int64_t j = 0; j < nc; ++j)
    require(columns.data()[j] >= 0 && columns.data()[j] < nv, "columns out of range");
  require(length(v) == 0 || length(v) == nv, "v must be (nv,) or empty");
  const auto size = static_cast<std::size_t>(n * nv + 2 * n);
  std::unique_ptr<double[]> buffer(new double[size]());
  {
    nb::gil_scoped_release release;
    va::relative_sensor(jacobian_world.data(), nv, frames.data(), length(v) ? v.data() : nullptr,
                        axis_rows.data(), n, rows.data(), columns.data(), signs.data(), nc,
                        buffer.get());
  }
  return owned(std::move(buffer), size);
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
  const auto [k, size, m] = daqp_rows(equality, equality_rhs, inequality, lows, uppers,
                                      iter_limit);
  return daqp_tuple(size, m, [&, k = k, size = size, m = m](double* x, double* lam) {
    return va::daqp_least_norm(equality.data(), equality_rhs.data(), k, size,
                               inequality.data(), lows.data(), uppers.data(), m, iter_limit, x,
                               lam);
  });
}

// The QP's closest-wrench stages on DAQP from cold, regularised: (exitflag, x, lam,
// iterations).
nb::tuple daqp_closest(const F2& equality, const F1& equality_rhs, std::int64_t design,
                       const F1& weights, const F2& inequality, const F1& lows,
                       const F1& uppers, int iter_limit, double eps) {
  const auto [k, size, m] = daqp_rows(equality, equality_rhs, inequality, lows, uppers,
                                      iter_limit);
  require(design >= 0 && design < k, "design must be in 0..k-1 (a request row at least)");
  require(length(weights) == k - design, "weights must be (k - design,)");
  for (std::int64_t i = 0; i < k - design; ++i)
    require(weights.data()[i] > 0.0, "weights must be > 0");
  require(eps > 0.0, "eps must be > 0");
  return daqp_tuple(size, m, [&, k = k, size = size, m = m](double* x, double* lam) {
    return va::daqp_closest(equality.data(), equality_rhs.data(), k, design, size,
                            weights.data(), inequality.data(), lows.data(), uppers.data(), m,
                            iter_limit, eps, x, lam);
  });
}

// -- contact margins (the controller's yield policy) -----------------------------------------

// The margins' arguments checked; returns the number of rows.
std::int64_t margin_rows(const F2& frames, const I1& orientation_rows, const F2& forces,
                         const F2& points, const I1& axis_rows, const I1& minima_axes,
                         const F1& lows) {
  const auto p = static_cast<std::int64_t>(forces.shape(0));
  const auto n = static_cast<std::int64_t>(forces.shape(1));
  require(n >= 1 && n <= 6 && len(axis_rows) == n, "forces must be (p, n), axis_rows (n,)");
  for (std::int64_t a = 0; a < n; ++a)
    require(axis_rows.data()[a] >= 0 && axis_rows.data()[a] < 6, "axis_rows must be in 0..5");
  for (std::int64_t m = 0; m < len(minima_axes); ++m)
    require(minima_axes.data()[m] >= 0 && minima_axes.data()[m] < n, "minima_axes out of range");
  const auto np = static_cast<std::int64_t>(points.shape(0));
  require((np == 0 || np == p) && points.shape(1) == 7, "points must be (p, 7) or (0, 7)");
  require(frames.shape(1) == 12 && len(orientation_rows) >= 1 + (np ? p : 0),
          "frames must be (nf, 12), orientation_rows ({O}, then each reaction frame)");
  for (std::int64_t r = 0; r < (np ? 1 + p : 0); ++r)
    require(orientation_rows.data()[r] >= 0 &&
                orientation_rows.data()[r] < static_cast<std::int64_t>(frames.shape(0)),
            "orientation_rows out of the frame table");
  std::int64_t rows = len(minima_axes) * p;
  for (std::int64_t c = 0; c < np; ++c) {
    const double* row = points.data() + 7 * c;
    rows += (row[2] > 0.0 ? 1 : 0) + (row[0] < 0.0 ? 0 : 4);
  }
  require(length(lows) == rows, "lows must have one entry per contact row");
  return rows;
}

double contact_least_margin(const F2& frames, const I1& orientation_rows, const F2& forces,
                            const F2& points, const I1& axis_rows, const I1& minima_axes,
                            const F1& lows) {
  const std::int64_t rows =
      margin_rows(frames, orientation_rows, forces, points, axis_rows, minima_axes, lows);
  std::vector<double> values(static_cast<std::size_t>(rows));
  nb::gil_scoped_release release;
  va::contact_margins(frames.data(), orientation_rows.data(), forces.data(),
                      static_cast<std::int64_t>(forces.shape(0)), len(axis_rows), points.data(),
                      static_cast<std::int64_t>(points.shape(0)), axis_rows.data(),
                      minima_axes.data(), len(minima_axes), values.data());
  return va::contact_least_margin(values.data(), lows.data(), rows);
}

double contact_largest_scale(const F2& frames, const I1& orientation_rows, const F2& full,
                             const F2& base, const F2& points, const I1& axis_rows,
                             const I1& minima_axes, const F1& lows) {
  const std::int64_t rows =
      margin_rows(frames, orientation_rows, full, points, axis_rows, minima_axes, lows);
  require(base.shape(0) == full.shape(0) && base.shape(1) == full.shape(1),
          "base must be shaped like full");
  std::vector<double> at_full(static_cast<std::size_t>(rows)), at_base(at_full.size());
  const auto p = static_cast<std::int64_t>(full.shape(0));
  const auto np = static_cast<std::int64_t>(points.shape(0));
  nb::gil_scoped_release release;
  va::contact_margins(frames.data(), orientation_rows.data(), full.data(), p, len(axis_rows),
                      points.data(), np, axis_rows.data(), minima_axes.data(), len(minima_axes),
                      at_full.data());
  va::contact_margins(frames.data(), orientation_rows.data(), base.data(), p, len(axis_rows),
                      points.data(), np, axis_rows.data(), minima_axes.data(), len(minima_axes),
                      at_base.data());
  return va::contact_largest_scale(at_full.data(), at_base.data(), lows.data(), rows);
}

}  // namespace

NB_MODULE(_core, m) {
  m.doc() = "Compiled kernels of virtual_actuators (C++, built at install); see "
            "virtual_actuators.native.";
  // Trees and distributions live in the robots' caches (module-level registries) until the
  // interpreter's teardown, which may free the module first: not a leak worth a report.
  nb::set_leak_warnings(false);
  void bind_attachment(nb::module_ & m);  // the spring attachments' block, at the end of the file
  bind_attachment(m);
  void bind_gait(nb::module_&);  // the gait's kernels: the block at the end of this file
  bind_gait(m);
  void bind_simulation(nb::module_&);  // the simulation's kernel: the last block of this file
  bind_simulation(m);
  void bind_native(nb::module_&);  // the native gaits: the last block of this file
  bind_native(m);
  void bind_native_hexapod(nb::module_&);  // the hexapod's native tick: the last block
  bind_native_hexapod(m);
  void bind_contacts(nb::module_&);  // MuJoCo's contacts read in place: the last block
  bind_contacts(m);
  void bind_plan(nb::module_&);  // the compiled machine (bind_plan.cpp)
  bind_plan(m);

  nb::class_<Tree>(m, "Tree",
                   "A kinematic tree's tables (KinematicTree): forward kinematics per tick.")
      .def(nb::init<const I2&, const F2&, const I1&, const F2&, const I1&, const F2&,
                    const I2&>(),
           "joint_ints"_a, "joint_floats"_a, "velocity_joint"_a, "velocity_subspace"_a,
           "frame_parents"_a, "frame_floats"_a, "unit_bounds"_a)
      .def("compute", &Tree::compute, "q"_a, "v"_a = nb::none(),
           "Joint placements, world joint Jacobian, frame placements (and velocities) in one "
           "buffer: kinematics.kernels.forward_kinematics.")
      .def("size", &Tree::size, "with_velocity"_a, "Length of compute()'s buffer.")
      .def_prop_ro("nf", &Tree::nf, "Number of frames compute() places.")
      .def_prop_ro("nq", &Tree::nq, "Length of the configurations the tree accepts.");

  m.def("unit_norm_error", &unit_norm_error, "q"_a, "bounds"_a,
        "kinematics.kernels.unit_norm_error: largest | ||q[a:b]|| - 1 | (-1: q not finite).");
  m.def("all_finite", &all_finite, "values"_a,
        "kinematics.kernels.all_finite: no NaN, no infinity.");
  m.def("point_velocity", &point_velocity, "jacobian_world"_a, "v"_a, "columns"_a, "x"_a,
        "y"_a, "z"_a, "kinematics.kernels.point_velocity: a body point's linear velocity.");

  nb::class_<Distribution>(m, "Distribution",
                           "The packed tables of one distribution mode (CompiledDistribution).")
      .def(nb::init<const I1&, const F1&, std::int64_t>(), "ints"_a, "floats"_a, "nv"_a)
      .def("solve", &Distribution::solve, "jacobian_world"_a, "frames"_a, "q"_a, "wrench"_a,
           "partitioned.kernels.distribute on the snapshot's arrays: (out, residual, scale, "
           "rounding, status, worst, worst_chain).")
      .def("tick", &Distribution::tick, "tree"_a, "q"_a, "wrench"_a,
           "Forward kinematics and the distribution in one call (q as the tree needs it).")
      .def("checked_tick", &Distribution::checked_tick, "tree"_a, "q"_a, "wrench"_a,
           "tick() on unchecked arguments: status 4 (nothing computed) unless q is a finite "
           "(nq,) float64 vector with unit norms within 1e-12 and the wrench a finite (n,) one.")
      .def_ro_static("UNCHECKED", &Distribution::UNCHECKED);

  m.def("exact_step", &exact_step, "equality"_a, "equality_rhs"_a, "design"_a, "weights"_a,
        "inequality"_a, "lows"_a, "uppers"_a, "guess"_a, "exact"_a, "active_tol"_a, "tol"_a,
        "max_steps"_a,
        "qp.exact.exact_step: the QP's answer on the active set guess names, (ok, x, z).");
  m.def("qp_violation", &qp_violation, "buffer"_a.noconvert(), "layout"_a, "pn"_a, "nv"_a,
        "z"_a, "equalities"_a, "qp.kernel_answer.violation: the largest miss of z.");
  m.def("qp_read_out", &qp_read_out, "buffer"_a.noconvert(), "layout"_a, "pn"_a, "nv"_a,
        "z"_a, "multipliers"_a, "scale"_a, "wrench"_a, "keep"_a, "active_tol"_a,
        "accuracy"_a, "out"_a.noconvert(), "active"_a.noconvert(),
        "qp.kernel_answer.read_out: (count of active rows, (residual, scale, rounding)).");

  nb::class_<QP>(m, "QP", "What a QP declaration fixes (CompiledQPMatrices).")
      .def(nb::init<const I1&, const I1&, const I2&, const F2&, const F2&, const F3&,
                    const F1&, const F2&, const I1&, const F1&, const F2&, const I1&,
                    const F1&>(),
           "axis_rows"_a, "frame_rows"_a, "chain_ints"_a, "chain_signs"_a, "springs"_a,
           "const_rows"_a, "const_rhs"_a, "normals_world"_a, "frame_normals"_a, "settings"_a,
           "soles"_a, "limited_v"_a, "limits"_a)
      .def("reduced", &QP::reduced, "jacobian_world"_a, "frames"_a, "q"_a, "wrench"_a,
           "kept"_a, "buffer"_a.noconvert(), "layout"_a,
           "qp.kernels.reduced_qp into buffer: (status, worst ratio, scale).")
      .def("again", &QP::again, "jacobian_world"_a, "frames"_a, "q"_a, "wrench"_a, "kept"_a,
           "buffer"_a.noconvert(), "layout"_a, "keep"_a, "weights"_a, "guess"_a.noconvert(),
           "active_tol"_a, "exact_tol"_a, "accuracy"_a, "out"_a.noconvert(),
           "active"_a.noconvert(),
           "qp.kernel_answer.again: (count, (residual, scale, rounding)), count -1: not "
           "certified.")
      .def("again_tick", &QP::again_tick, "tree"_a, "q"_a, "wrench"_a, "kept"_a,
           "buffer"_a.noconvert(), "layout"_a, "keep"_a, "weights"_a, "guess"_a.noconvert(),
           "active_tol"_a, "exact_tol"_a, "accuracy"_a, "out"_a.noconvert(),
           "active"_a.noconvert(),
           "again() from q alone: the tree's forward kinematics in the same call.");
  m.def("relative_sensor", &relative_sensor, "jacobian_world"_a, "frames"_a, "v"_a,
        "axis_rows"_a, "rows"_a, "columns"_a, "signs"_a,
        "kinematics.sensor_kernels.relative_sensor: jacobian, position, velocity in one buffer.");
  m.def("daqp_least_norm", &daqp_least_norm, "equality"_a, "equality_rhs"_a,
        "inequality"_a, "lows"_a, "uppers"_a, "iter_limit"_a,
        "The QP's first stage on DAQP (vendored, MIT) from cold, min |x|^2 on the rows: "
        "(exitflag, x, inequality multipliers, iterations).");
  m.def("daqp_closest", &daqp_closest, "equality"_a, "equality_rhs"_a, "design"_a,
        "weights"_a, "inequality"_a, "lows"_a, "uppers"_a, "iter_limit"_a, "eps"_a,
        "The QP's closest-wrench stages on DAQP from cold, min |x|^2 / 2 + the weighted miss "
        "/ (2 eps): (exitflag, x, inequality multipliers, iterations).");
  m.def("contact_least_margin", &contact_least_margin, "frames"_a, "orientation_rows"_a,
        "forces"_a, "points"_a, "axis_rows"_a, "minima_axes"_a, "lows"_a,
        "contacts.contact_set.least_margin: smallest G @ forces.ravel() - lows.");
  m.def("contact_largest_scale", &contact_largest_scale, "frames"_a, "orientation_rows"_a,
        "full"_a, "base"_a, "points"_a, "axis_rows"_a, "minima_axes"_a, "lows"_a,
        "contacts.contact_set.largest_scale: the largest alpha in [0, 1] meeting the rows.");
}

// == spring-damper attachments (attachment.hpp) =============================================
// One block, bound by bind_attachment (called from NB_MODULE above): SpringTick holds a sensor's
// tables and its spring-dampers' entries; tick() runs attachment_kernel.spring_tick.
#include "attachment.hpp"

namespace {

class SpringTick {
 public:
  SpringTick(const I1& axis_rows, const I1& rows, const I1& columns, const F1& signs,
             const I1& targets, const I1& rotations, std::int64_t summed, std::int64_t efforts,
             std::int64_t nv)
      : axis_rows_(copy<std::int64_t>(axis_rows)),
        rows_(copy<std::int64_t>(rows)),
        columns_(copy<std::int64_t>(columns)),
        signs_(copy<double>(signs)),
        targets_(copy<std::int64_t>(targets)),
        rotations_(copy<std::int64_t>(rotations)),
        summed_(summed != 0),
        efforts_(efforts != 0),
        nv_(nv) {
    const auto n = static_cast<std::int64_t>(axis_rows_.size());
    require(n >= 1 && n <= 6, "axis_rows must hold 1 to 6 axes");
    for (std::int64_t i = 0; i < n; ++i)
      require(axis_rows_[i] >= 0 && axis_rows_[i] < 6 &&
                  (i == 0 || axis_rows_[i - 1] < axis_rows_[i]),
              "axis_rows must be increasing rows in [0, 6)");
    require(rows_.size() == 3 && rows_[0] >= 0 && rows_[1] >= 0 && rows_[2] >= 0,
            "rows must be 3 frame-table rows ({B}, {O}, {A})");
    require(signs_.size() == columns_.size(), "signs must be one per column");
    require(nv >= 0, "nv must be >= 0");
    for (const std::int64_t c : columns_) require(c >= 0 && c < nv, "columns out of range");
    require(!targets_.empty() && rotations_.size() == targets_.size(),
            "targets and rotations must be one per entry (at least one)");
    for (const std::int64_t t : targets_) require(t >= 0 && t < n, "targets must be axes");
    for (const std::int64_t r : rotations_) require(r == 0 || r == 1, "rotations must be 0 or 1");
    require(summed_ || static_cast<std::int64_t>(targets_.size()) == n,
            "without summed, one entry per axis");
    rows_end_ = std::max(rows_[0], std::max(rows_[1], rows_[2])) + 1;
    const auto m = static_cast<std::int64_t>(columns_.size());
    tables_ = va::serial::SensorTables{axis_rows_.data(), n, rows_.data(), columns_.data(),
                                       signs_.data(), m};
  }

  // effort (nv), position (n), velocity (n), wrench (n), flag: spring_tick's buffer.
  // parameters: six arrays per component (stiffness, damping, setpoint, velocity setpoint,
  // force, limit), component after component, their lengths its number of axes.
  Owned tick(const F2& jacobian_world, const F2& frames, const F1& v,
             const std::vector<F1>& parameters) const {
    const auto size = static_cast<std::size_t>(this->size());
    std::unique_ptr<double[]> out(new double[size]());
    run(jacobian_world, frames, v, parameters, out.get());
    return owned(std::move(out), size);
  }

  // tick() into out (size() doubles, zeroed): the kernel's flag (false: the general path runs).
  bool run(const F2& jacobian_world, const F2& frames, const F1& v,
           const std::vector<F1>& parameters, double* out) const {
    const std::int64_t n = tables_.n;
    const auto e = static_cast<std::int64_t>(targets_.size());
    require(jacobian_world.shape(0) == 6 &&
                static_cast<std::int64_t>(jacobian_world.shape(1)) == nv_,
            "jacobian_world must be (6, nv)");
    require(frames.shape(1) == 12 && static_cast<std::int64_t>(frames.shape(0)) >= rows_end_,
            "frames must be (nf, 12) with the sensor's rows");
    require(length(v) == nv_, "v must be (nv,)");
    require(parameters.size() % 6 == 0, "parameters must be six arrays per component");
    std::vector<double> table(static_cast<std::size_t>(6 * e));  // spring_tick's (6, e)
    std::int64_t at = 0;
    for (std::size_t c = 0; c < parameters.size(); c += 6) {
      const std::int64_t size = length(parameters[c]);
      require(at + size <= e, "the parameters hold more entries than the tables");
      for (std::size_t k = 0; k < 6; ++k) {
        require(length(parameters[c + k]) == size,
                "a component's parameters must be one per axis");
        const double* data = parameters[c + k].data();
        for (std::int64_t i = 0; i < size; ++i) table[k * e + at + i] = data[i];
      }
      at += size;
    }
    require(at == e, "the parameters must hold one entry per table entry");
    nb::gil_scoped_release release;
    std::vector<double> jacobian(static_cast<std::size_t>(tables_.m * n));
    const va::serial::SpringEntries p{targets_.data(), rotations_.data(), e,
                                      summed_,         efforts_,          table.data()};
    return va::serial::spring_tick(jacobian_world.data(), nv_, frames.data(), v.data(), tables_,
                                   p, jacobian.data(), out);
  }

  std::int64_t size() const { return nv_ + 3 * tables_.n + 1; }
  std::int64_t nv() const { return nv_; }
  std::int64_t n() const { return tables_.n; }
  bool efforts() const { return efforts_; }

  // run() on raw pointers, unchecked (a C++ caller that checked the shapes once): table is
  // spring_tick's (6, entries()) parameters, jacobian a scratch of jacobian_size() doubles, out
  // size() doubles, zeroed. No Python object is touched: callable without the GIL.
  bool run_raw(const double* jacobian_world, const double* frames, const double* v,
               const double* table, double* jacobian, double* out) const {
    const va::serial::SpringEntries p{targets_.data(), rotations_.data(), entries(),
                                      summed_,         efforts_,          table};
    return va::serial::spring_tick(jacobian_world, nv_, frames, v, tables_, p, jacobian, out);
  }
  std::int64_t entries() const { return static_cast<std::int64_t>(targets_.size()); }
  std::int64_t rows_end() const { return rows_end_; }
  std::int64_t jacobian_size() const { return tables_.m * tables_.n; }
  // The sensor's reading on its axes (sense().position): position (n).
  void position(const double* frames, double* position) const {
    va::sensor_pose(frames + 12 * rows_[0], frames + 12 * rows_[1], frames + 12 * rows_[2],
                    axis_rows_.data(), tables_.n, position);
  }

 private:
  std::vector<std::int64_t> axis_rows_, rows_, columns_;
  std::vector<double> signs_;
  std::vector<std::int64_t> targets_, rotations_;
  bool summed_, efforts_;
  std::int64_t nv_, rows_end_ = 0;
  va::serial::SensorTables tables_{};
};

// A parallel actuator's spring-damper attachment: its SpringTick, then the distribution of the
// wrench it wrote (the packed tables of one mode, as Distribution holds them), in one call.
class SpringSolve {
 public:
  SpringSolve(const SpringTick& spring, const I1& ints, const F1& floats)
      : spring_(&spring), ints_(copy<std::int64_t>(ints)), floats_(copy<double>(floats)) {
    require(!spring.efforts(), "the spring tick must leave the efforts to the distribution");
    packed_ = va::Packed::checked(ints_, floats_, spring.nv());
    require(packed_.n == spring.n(), "the distribution's axes must be the sensor's");
  }

  // (spring buffer, distribution buffer, residual, scale, rounding, status): SpringTick.tick's
  // buffer, then Distribution.solve's on its wrench, or status NOT_RUN (nothing distributed)
  // when the spring tick hands the tick on or the frames lack the distribution's rows.
  nb::tuple tick(const F2& jacobian_world, const F2& frames, const F1& v, const F1& q,
                 const std::vector<F1>& parameters) const {
    const std::int64_t nv = spring_->nv(), n = spring_->n();
    require(length(q) > packed_.max_q_index(), "q is shorter than the springs' indices");
    const auto size = static_cast<std::size_t>(spring_->size());
    const auto out_size = static_cast<std::size_t>(packed_.out_size(nv));
    std::unique_ptr<double[]> buffer(new double[size]());
    std::unique_ptr<double[]> out(new double[out_size]());
    va::Distributed d;
    d.status = NOT_RUN;
    if (spring_->run(jacobian_world, frames, v, parameters, buffer.get()) &&
        static_cast<std::int64_t>(frames.shape(0)) > packed_.max_frame_row()) {
      nb::gil_scoped_release release;
      d = va::distribute(jacobian_world.data(), nv, frames.data(), q.data(),
                         buffer.get() + nv + 2 * n, packed_, out.get());
    }
    return nb::make_tuple(owned(std::move(buffer), size), owned(std::move(out), out_size),
                          d.residual, d.scale, d.rounding, d.status);
  }

  // The distribution of wrench (n) into out (out_size() doubles, zeroed), unchecked: tick()'s
  // second half for a C++ caller that checked the shapes once. No Python object is touched.
  va::Distributed distribute_raw(const double* jacobian_world, const double* frames,
                                 const double* q, const double* wrench, double* out) const {
    return va::distribute(jacobian_world, spring_->nv(), frames, q, wrench, packed_, out);
  }
  const SpringTick& spring() const { return *spring_; }
  std::int64_t out_size() const { return packed_.out_size(spring_->nv()); }
  std::int64_t chains() const { return packed_.p; }
  std::int64_t max_frame_row() const { return packed_.max_frame_row(); }
  std::int64_t max_q_index() const { return packed_.max_q_index(); }

  // tick()'s status when nothing was distributed
  static constexpr std::int64_t NOT_RUN = -1;

 private:
  const SpringTick* spring_;  // kept alive by the binding (keep_alive)
  std::vector<std::int64_t> ints_;
  std::vector<double> floats_;
  va::Packed packed_;
};

}  // namespace

void bind_attachment(nb::module_& m) {
  nb::class_<SpringTick>(m, "SpringTick",
                         "A sensor's tables and its spring-dampers' entries (control.attachment_"
                         "kernel.SpringTick): one spring-damper attachment's tick per call.")
      .def(nb::init<const I1&, const I1&, const I1&, const F1&, const I1&, const I1&,
                    std::int64_t, std::int64_t, std::int64_t>(),
           "axis_rows"_a, "rows"_a, "columns"_a, "signs"_a, "targets"_a, "rotations"_a,
           "summed"_a, "efforts"_a, "nv"_a)
      .def("tick", &SpringTick::tick, "jacobian_world"_a, "frames"_a, "v"_a, "parameters"_a,
           "attachment_kernel.spring_tick: effort (nv), position, velocity, wrench (n) and the "
           "flag (1.0, or 0.0: the general path runs) in one buffer.");
  nb::class_<SpringSolve>(m, "SpringSolve",
                          "A parallel actuator's spring-damper attachment (attachment_kernel."
                          "SpringTick with a distribution): the spring tick, then the "
                          "distribution of its wrench, in one call.")
      .def(nb::init<const SpringTick&, const I1&, const F1&>(), "spring"_a, "ints"_a,
           "floats"_a, nb::keep_alive<1, 2>())
      .def("tick", &SpringSolve::tick, "jacobian_world"_a, "frames"_a, "v"_a, "q"_a,
           "parameters"_a,
           "(spring buffer, distribution buffer, residual, scale, rounding, status): "
           "SpringTick.tick, then Distribution.solve on its wrench (status -1: not run).")
      .def_ro_static("NOT_RUN", &SpringSolve::NOT_RUN);
}
// == end of the spring-damper attachments' block ======================================

// -- the gait's kernels (gait.hpp): legged walks and the centre of mass ---------------------
// One block, bound by bind_gait (called from NB_MODULE above).
#include "gait.hpp"
#include "hexapod.hpp"

namespace {

using GF2 = nb::ndarray<double, nb::numpy, nb::ndim<2>, nb::c_contig, nb::device::cpu>;

std::int64_t rows_of(const F2& a) { return static_cast<std::int64_t>(a.shape(0)); }

// kinematics.kernels.center_of_mass: (x, y, z).
nb::tuple gait_center_of_mass(const F2& joints, const F1& masses, const F2& levers) {
  const std::int64_t n = rows_of(joints);
  require(joints.shape(1) == 12, "joints must be (njoints, 12)");
  require(length(masses) == n && rows_of(levers) == n && levers.shape(1) == 3,
          "masses must be (njoints,), levers (njoints, 3)");
  double out[3];
  {
    nb::gil_scoped_release release;
    va::center_of_mass(joints.data(), masses.data(), levers.data(), n, out);
  }
  return nb::make_tuple(out[0], out[1], out[2]);
}

// gaits.legged.body.body_wrench: the wrench into out, returns the yaw.
double gait_body_wrench(const F2& rotation, const F1& position, const F1& velocity,
                        const F1& gains, const F1& setpoints, const MF1& out) {
  require(rotation.shape(0) == 3 && rotation.shape(1) == 3, "rotation must be (3, 3)");
  require(length(position) >= 3 && length(velocity) == 6, "position (6,), velocity (6,)");
  require(length(gains) == 11 && length(setpoints) == 8, "gains (11,), setpoints (8,)");
  require(length(out) == 6, "out must be (6,)");
  nb::gil_scoped_release release;
  return va::body_wrench(rotation.data(), position.data(), velocity.data(), gains.data(),
                         setpoints.data(), out.data());
}

// gaits.legged.footholds.swing_setpoints: swing and out written in place.
void gait_swing_setpoints(const I1& feet, const GF2& swing, const F2& nominal, const F1& body,
                          const F1& motion, double dt, const F1& shape, const GF2& out) {
  const auto f = static_cast<std::int64_t>(swing.shape(0));
  const auto k = static_cast<std::int64_t>(feet.shape(0));
  require(swing.shape(1) == 9 && rows_of(nominal) == f && nominal.shape(1) == 2,
          "swing must be (f, 9), nominal (f, 2)");
  require(length(body) == 12 && length(motion) == 8 && length(shape) == 8,
          "body (12,), motion (8,), shape (8,)");
  require(static_cast<std::int64_t>(out.shape(0)) >= k && out.shape(1) == 6,
          "out must be (>= k, 6)");
  for (std::int64_t j = 0; j < k; ++j)
    require(feet.data()[j] >= 0 && feet.data()[j] < f, "feet out of range");
  nb::gil_scoped_release release;
  va::swing_setpoints(feet.data(), k, swing.data(), nominal.data(), body.data(), motion.data(),
                      dt, shape.data(), out.data());
}

// actuators.producible._two_points: (36,), or empty (coincident contacts, a row not in frames).
Owned gait_two_points(const F2& frames, const I1& rows) {
  require(frames.shape(1) == 12 && len(rows) == 4, "frames must be (nf, 12), rows (4,)");
  for (std::int64_t r = 0; r < 4; ++r) {
    require(rows.data()[r] >= 0, "rows must be >= 0");
    if (rows.data()[r] >= rows_of(frames)) return owned(std::unique_ptr<double[]>(new double[1]), 0);
  }
  std::unique_ptr<double[]> buffer(new double[36]());
  bool found;
  {
    nb::gil_scoped_release release;
    found = va::two_points(frames.data(), rows.data(), buffer.get());
  }
  if (!found) return owned(std::unique_ptr<double[]>(new double[1]), 0);
  return owned(std::move(buffer), 36);
}

// actuators.producible._give_way_one: out written when True.
bool gait_give_way_one(const F1& wrench, const F2& yielding, const F2& missing, const MF1& out) {
  const std::int64_t n = length(wrench);
  const auto m = static_cast<std::int64_t>(yielding.shape(1));
  require(rows_of(yielding) == n && rows_of(missing) == n && missing.shape(1) >= 1,
          "yielding must be (n, m), missing (n, >= 1)");
  require(length(out) == n, "out must be (n,)");
  std::vector<double> across(static_cast<std::size_t>(m));
  std::vector<double> column(static_cast<std::size_t>(n));  // missing[:, 0]
  const auto width = static_cast<std::int64_t>(missing.shape(1));
  for (std::int64_t r = 0; r < n; ++r) column[r] = missing.data()[width * r];
  nb::gil_scoped_release release;
  return va::give_way_one(wrench.data(), yielding.data(), n, m, column.data(), out.data(),
                          across.data());
}

// gaits.hexapod.kernel.tripod_setpoints: swing and state written in place.
void gait_tripod_setpoints(const F2& frames, const I1& frame_rows, const I1& rows,
                           const F2& nominal, const F1& motion, const F1& shape,
                           const GF2& swing, const MF1& state) {
  require(frames.shape(1) == 12 && len(frame_rows) == 7,
          "frames must be (nf, 12), frame_rows (7,)");
  for (std::int64_t j = 0; j < 7; ++j)
    require(frame_rows.data()[j] >= 0 && frame_rows.data()[j] < rows_of(frames),
            "frame_rows out of range");
  require(rows_of(nominal) == 6 && nominal.shape(1) == 3, "nominal must be (6, 3)");
  require(len(rows) == 6 && length(motion) == 10 && length(shape) == 11,
          "rows (6,), motion (10,), shape (11,)");
  require(swing.shape(0) == 3 && swing.shape(1) == 9 && length(state) == 5,
          "swing must be (3, 9), state (5,)");
  for (std::int64_t j = 0; j < 6; ++j)
    require(rows.data()[j] >= 0 && rows.data()[j] < 6, "rows out of range");
  nb::gil_scoped_release release;
  va::tripod_setpoints(frames.data(), frame_rows.data(), rows.data(), nominal.data(),
                       motion.data(), shape.data(), swing.data(), state.data());
}

}  // namespace

void bind_gait(nb::module_& m) {
  m.def("tripod_setpoints", &gait_tripod_setpoints, "frames"_a, "frame_rows"_a, "rows"_a,
        "nominal"_a, "motion"_a, "shape"_a, "swing"_a.noconvert(), "state"_a.noconvert(),
        "gaits.hexapod.kernel.tripod_setpoints: the swing tripod's set points, in place.");
  m.def("center_of_mass", &gait_center_of_mass, "joints"_a, "masses"_a, "levers"_a,
        "kinematics.kernels.center_of_mass: the bodies' centre of mass (x, y, z).");
  m.def("body_wrench", &gait_body_wrench, "rotation"_a, "position"_a, "velocity"_a, "gains"_a,
        "setpoints"_a, "out"_a.noconvert(),
        "gaits.legged.body.body_wrench: the body model's wrench into out; the yaw.");
  m.def("swing_setpoints", &gait_swing_setpoints, "feet"_a, "swing"_a.noconvert(), "nominal"_a,
        "body"_a, "motion"_a, "dt"_a, "shape"_a, "out"_a.noconvert(),
        "gaits.legged.footholds.swing_setpoints: swing feet's set points into swing and out.");
  m.def("two_points", &gait_two_points, "frames"_a, "rows"_a,
        "actuators.producible._two_points: producible (6, 5) and missing (6, 1) row by row.");
  m.def("give_way_one", &gait_give_way_one, "wrench"_a, "yielding"_a, "missing"_a,
        "out"_a.noconvert(),
        "actuators.producible._give_way_one: the request given way along one direction.");
}
// -- end of the gait's kernels --------------------------------------------------------------

// -- the simulation's kernel (simulation.hpp): efforts into MuJoCo's controls ---------------
// One block, bound by bind_simulation (called from NB_MODULE above).
#include "simulation.hpp"

namespace {

// simulation.actuation.efforts_to_ctrl: 0 (ctrl written), 1 (an effort not finite), 2 (an
// unactuated effort beyond the tolerance).
std::int64_t simulation_efforts_to_ctrl(const F1& tau, const I1& direct, const I1& unactuated,
                                        double tolerance, const MF1& ctrl) {
  const std::int64_t nv = length(tau), nu = static_cast<std::int64_t>(direct.shape(0));
  const std::int64_t count = static_cast<std::int64_t>(unactuated.shape(0));
  require(length(ctrl) == nu, "ctrl must have one entry per direct index");
  for (std::int64_t k = 0; k < nu; ++k)
    require(direct.data()[k] >= 0 && direct.data()[k] < nv, "direct index out of range");
  for (std::int64_t k = 0; k < count; ++k)
    require(unactuated.data()[k] >= 0 && unactuated.data()[k] < nv,
            "unactuated index out of range");
  nb::gil_scoped_release release;
  return va::efforts_to_ctrl(tau.data(), nv, direct.data(), nu, unactuated.data(), count,
                             tolerance, ctrl.data());
}

}  // namespace

void bind_simulation(nb::module_& m) {
  m.def("efforts_to_ctrl", &simulation_efforts_to_ctrl, "tau"_a, "direct"_a, "unactuated"_a,
        "tolerance"_a, "ctrl"_a.noconvert(),
        "simulation.actuation.efforts_to_ctrl: efforts into ctrl in place; 0, 1 or 2.");
}
// -- end of the simulation's kernel ---------------------------------------------------------

// -- native gaits (turkey.hpp): a whole gait tick in one call ------------------------------
// One block, bound by bind_native (called from NB_MODULE above). NativeTurkey holds what a
// TurkeyWalker's declaration fixes (the kinematic tree, its attachments' SpringTick and
// SpringSolve, the states' attachments and limp joints, the effort limits) and the gait's
// memory; tick() runs the kinematics pass, the state machine and its callbacks, the components'
// resets, every active attachment, the sums, the limp joints and the clipping: Gait.compute's
// arithmetic, bit for bit (gaits/turkey/native.py, tests/test_native_turkey.py).
#include "turkey.hpp"

namespace {

// What a native gait's tick does after its attachments, whatever the gait: the states' tables
// (their attachments in order, their limp joints), the sum of the attachments' efforts, then
// Controller.compute_checked's end: limp joints zeroed, np.minimum(np.maximum(tau, lower), upper).
class GaitEfforts {
 public:
  struct State {
    std::vector<std::int64_t> attachments, limp;
  };

  GaitEfforts(const F1& lower, const F1& upper, std::int64_t nv) : nv_(nv) {
    require(length(lower) == nv && length(upper) == nv, "limits must be (nv,)");
    lower_ = copy<double>(lower);
    upper_ = copy<double>(upper);
    tau_.resize(static_cast<std::size_t>(nv));
  }

  // A state, in StateMachine.names order: its attachments (among count) and limp indices.
  void add_state(const I1& attachments, const I1& limp, std::int64_t count) {
    for (std::int64_t k = 0; k < len(attachments); ++k)
      require(attachments.data()[k] >= 0 && attachments.data()[k] < count,
              "unknown attachment");
    for (std::int64_t k = 0; k < len(limp); ++k)
      require(limp.data()[k] >= 0 && limp.data()[k] < nv_, "limp index out of range");
    require(len(attachments) >= 1, "a state runs at least one attachment");
    states_.push_back(State{copy<std::int64_t>(attachments), copy<std::int64_t>(limp)});
  }

  const State& state(std::int64_t index) const {
    return states_[static_cast<std::size_t>(index)];
  }
  std::int64_t states() const { return static_cast<std::int64_t>(states_.size()); }

  // TickSums.add: the first attachment's efforts, then the sum.
  void add(const double* effort, bool first) {
    for (std::int64_t i = 0; i < nv_; ++i) tau_[i] = first ? effort[i] : tau_[i] + effort[i];
  }

  // The sum's limp joints zeroed and clipped into out; false (out untouched) when not finite.
  bool close(const State& state, double* out) {
    if (!va::all_finite(tau_.data(), nv_)) return false;
    for (const std::int64_t i : state.limp) tau_[i] = 0.0;
    for (std::int64_t i = 0; i < nv_; ++i) {
      const double low = tau_[i] < lower_[i] ? lower_[i] : tau_[i];
      out[i] = low > upper_[i] ? upper_[i] : low;
    }
    return true;
  }

 private:
  std::int64_t nv_;
  std::vector<double> lower_, upper_, tau_;
  std::vector<State> states_;
};

class NativeTurkey {
 public:
  // Component slots' roles: what the gait's memory sets in them before a tick.
  enum Role : std::int64_t { PLAIN = 0, GRANNY = 1, BUNNY = 2, LEFT_SWING = 3, RIGHT_SWING = 4 };
  // tick()'s answers
  static constexpr std::int64_t DEFER = -1, TICKED = 0, ENTERED = 1;

  NativeTurkey(const Tree& tree, const I1& rows, const F1& parameters, const F1& lower,
               const F1& upper)
      : tree_(tree.tree()), nq_(tree.nq()), efforts_(lower, upper, tree.tree()->tables().nv) {
    const va::TreeTables& t = tree_->tables();
    nv_ = t.nv;
    require(len(rows) == 3, "rows must be (body, left foot, right foot) rows");
    for (std::int64_t k = 0; k < 3; ++k)
      require(rows.data()[k] >= 0 && rows.data()[k] < t.nf, "rows out of the frame table");
    rows_ = va::turkey::Rows{rows.data()[0], {rows.data()[1], rows.data()[2]}};
    require(length(parameters) == 9, "parameters must be the 9 gait variables");
    const double* p = parameters.data();
    parameters_ = va::turkey::Parameters{p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7], p[8]};
    pass_.resize(static_cast<std::size_t>(tree_->size(true)));
  }

  // A component's six parameter arrays (6 * size values, row k its parameter k); its index.
  std::int64_t add_slot(const F1& values, std::int64_t role) {
    require(length(values) % 6 == 0 && length(values) > 0, "values must be 6 * size floats");
    require(role >= PLAIN && role <= RIGHT_SWING, "unknown role");
    slots_.push_back(Slot{copy<double>(values), length(values) / 6, role});
    return static_cast<std::int64_t>(slots_.size()) - 1;
  }

  // A slot's values now (6 * size floats).
  Owned slot(std::int64_t slot) const {
    require(slot >= 0 && slot < static_cast<std::int64_t>(slots_.size()), "unknown slot");
    const std::vector<double>& values = slots_[slot].values;
    std::unique_ptr<double[]> out(new double[values.size()]);
    std::copy(values.begin(), values.end(), out.get());
    return owned(std::move(out), values.size());
  }

  // A slot's values again (the gait's components read at a synchronisation).
  void set_slot(std::int64_t slot, const F1& values) {
    require(slot >= 0 && slot < static_cast<std::int64_t>(slots_.size()), "unknown slot");
    require(length(values) == 6 * slots_[slot].size, "values must be 6 * the slot's size");
    slots_[slot].values = copy<double>(values);
  }

  // An attachment: its spring tick (and distribution: None for a serial one with its efforts),
  // its components' slots in order, per slot the sensor axis a bunny resets on (-1: none), and
  // the contact rows its yield axes (a 0/1 mask) keep feasible (yields false: none).
  std::int64_t add_attachment(const SpringTick& tick, const SpringSolve* solve, const I1& slots,
                              const I1& reset_axes, bool yields, const I1& yield_mask,
                              const I1& orientation_rows,
                              const F2& points, const I1& axis_rows, const I1& minima_axes,
                              const F1& lows) {
    require(tick.nv() == nv_, "the spring tick's nv must be the tree's");
    require(tick.rows_end() <= tree_->tables().nf, "the sensor's rows must be in the table");
    require((solve == nullptr) == tick.efforts(),
            "a serial attachment computes its efforts, a parallel one is distributed");
    require(len(slots) == len(reset_axes), "one reset axis per slot");
    std::int64_t entries = 0;
    for (std::int64_t k = 0; k < len(slots); ++k) {
      const std::int64_t s = slots.data()[k];
      require(s >= 0 && s < static_cast<std::int64_t>(slots_.size()), "unknown slot");
      require(reset_axes.data()[k] >= -1 && reset_axes.data()[k] < tick.n(), "bad reset axis");
      require((reset_axes.data()[k] >= 0) == (slots_[s].role == BUNNY),
              "the bunnies, and only they, reset on an axis");
      entries += slots_[s].size;
    }
    require(entries == tick.entries(), "the slots must fill the spring tick's entries");
    Attachment a;
    a.tick = &tick;
    a.solve = solve;
    a.slots = copy<std::int64_t>(slots);
    a.reset_axes = copy<std::int64_t>(reset_axes);
    a.buffer.resize(static_cast<std::size_t>(tick.size()));
    a.jacobian.resize(static_cast<std::size_t>(tick.jacobian_size()));
    a.table.resize(static_cast<std::size_t>(6 * entries));
    if (solve != nullptr) {
      require(solve->max_frame_row() < tree_->tables().nf, "the distribution's rows");
      require(solve->max_q_index() < nq_, "the distribution's q indices");
      a.out.resize(static_cast<std::size_t>(solve->out_size()));
    }
    a.yields = yields;
    if (yields) {
      require(solve != nullptr, "only a distribution yields");
      const std::int64_t n = tick.n(), p = solve->chains();
      require(len(axis_rows) == n && points.shape(1) == 7, "axis_rows (n,), points (np, 7)");
      const auto np = static_cast<std::int64_t>(points.shape(0));
      require(np == 0 || np == p, "points must be (p, 7) or (0, 7)");
      require(len(orientation_rows) >= 1 + (np ? p : 0), "orientation_rows");
      for (std::int64_t r = 0; r < len(orientation_rows); ++r)
        require(orientation_rows.data()[r] >= 0 &&
                    orientation_rows.data()[r] < tree_->tables().nf,
                "orientation_rows out of the frame table");
      for (std::int64_t m = 0; m < len(minima_axes); ++m)
        require(minima_axes.data()[m] >= 0 && minima_axes.data()[m] < n, "minima_axes");
      std::int64_t rows = len(minima_axes) * p;
      for (std::int64_t c = 0; c < np; ++c) {
        const double* row = points.data() + 7 * c;
        rows += (row[2] > 0.0 ? 1 : 0) + (row[0] < 0.0 ? 0 : 4);
      }
      require(length(lows) == rows, "lows must have one entry per contact row");
      a.orientation_rows = copy<std::int64_t>(orientation_rows);
      a.points = copy<double>(points);
      a.np = np;
      a.axis_rows = copy<std::int64_t>(axis_rows);
      a.minima_axes = copy<std::int64_t>(minima_axes);
      a.lows = copy<double>(lows);
      a.values.resize(static_cast<std::size_t>(rows));
      a.at_base.resize(static_cast<std::size_t>(rows));
      a.fallback.resize(static_cast<std::size_t>(solve->out_size()));
      a.scaled.resize(static_cast<std::size_t>(nv_));
      require(len(yield_mask) == n, "yield_mask must be (n,)");
      a.yield_mask = copy<std::int64_t>(yield_mask);
    }
    attachments_.push_back(std::move(a));
    return static_cast<std::int64_t>(attachments_.size()) - 1;
  }

  // The states in StateMachine.names order: their attachments (in order) and limp indices.
  void add_state(const I1& attachments, const I1& limp) {
    efforts_.add_state(attachments, limp, static_cast<std::int64_t>(attachments_.size()));
  }

  // The gait's memory as MEMORY floats (see memory_names in gaits/turkey/native.py).
  Owned memory() const {
    std::unique_ptr<double[]> out(new double[MEMORY]);
    const va::turkey::Memory& m = memory_;
    const double values[MEMORY] = {
        static_cast<double>(m.state), m.entered_at, static_cast<double>(m.front),
        m.swing_start[0], m.swing_start[1], m.progress_start, m.ground, m.granny_height,
        bunny_position_, bunny_time_, m.swing_setpoint[0][0], m.swing_setpoint[0][1],
        m.swing_setpoint[1][0], m.swing_setpoint[1][1], bunny_setpoint_};
    std::copy(values, values + MEMORY, out.get());
    return owned(std::move(out), MEMORY);
  }

  void set_memory(const F1& values) {
    require(length(values) == MEMORY, "memory must be MEMORY floats");
    const double* v = values.data();
    require(v[0] >= 0 && v[0] < static_cast<double>(efforts_.states()) && v[0] == std::floor(v[0]),
            "memory's state must be a state index");
    require(v[2] == 0.0 || v[2] == 1.0, "memory's front must be 0 (left) or 1 (right)");
    va::turkey::Memory& m = memory_;
    m.state = static_cast<std::int64_t>(v[0]);
    m.entered_at = v[1];
    m.front = static_cast<std::int64_t>(v[2]);
    m.swing_start[0] = v[3];
    m.swing_start[1] = v[4];
    m.progress_start = v[5];
    m.ground = v[6];
    m.granny_height = v[7];
    bunny_position_ = v[8];
    bunny_time_ = v[9];
    m.swing_setpoint[0][0] = v[10];
    m.swing_setpoint[0][1] = v[11];
    m.swing_setpoint[1][0] = v[12];
    m.swing_setpoint[1][1] = v[13];
    bunny_setpoint_ = v[14];
  }

  // One tick at (q, v, time): ENTERED or TICKED with tau (nv), each active attachment's
  // position, velocity and wrench (its row of readings (attachments + 1, 18)) and the granny
  // walker's height set point (readings[-1, 0]) written, or DEFER with
  // nothing written and the memory unchanged (the Python tick decides: a non-finite state, a
  // kernel handing the tick on, a yield that must scale the request).
  std::int64_t tick(const F1& q, const F1& v, double time, const MF1& tau,
                    const nb::ndarray<double, nb::numpy, nb::ndim<2>, nb::c_contig,
                                      nb::device::cpu>& readings) {
    require(length(q) == nq_ && length(v) == nv_, "q must be (nq,), v (nv,)");
    require(length(tau) == nv_, "tau must be (nv,)");
    require(static_cast<std::int64_t>(readings.shape(0)) ==
                    static_cast<std::int64_t>(attachments_.size()) + 1 &&
                readings.shape(1) == 18,
            "readings must be (attachments + 1, 18)");
    require(efforts_.states() == 5, "the five states must be declared");
    nb::gil_scoped_release release;
    return run(q.data(), v.data(), time, tau.data(), readings.data());
  }

  std::int64_t nv() const { return nv_; }
  std::int64_t state() const { return memory_.state; }

  static constexpr std::int64_t MEMORY = 15;

 private:
  struct Slot {
    std::vector<double> values;  // (6, size): stiffness, damping, setpoint, velocity set
                                 // point, force, limit
    std::int64_t size;
    std::int64_t role;
  };
  struct Attachment {
    const SpringTick* tick = nullptr;
    const SpringSolve* solve = nullptr;
    std::vector<std::int64_t> slots, reset_axes;
    std::vector<double> buffer, jacobian, table, out;
    bool yields = false;
    std::vector<std::int64_t> orientation_rows, axis_rows, minima_axes, yield_mask;
    std::vector<double> points, lows, values, at_base, fallback, scaled;
    std::int64_t np = 0;
  };

  // The attachment's spring tick (and distribution) with the memory m's set points at time:
  // its efforts (nullptr: DEFER).
  const double* run_attachment(Attachment& a, const double* jw, const double* frames,
                               const double* v, const double* q, double time,
                               const va::turkey::Memory& m, double bunny_position,
                               double bunny_time) {
    const std::int64_t e = a.tick->entries();
    std::int64_t at = 0;
    for (const std::int64_t s : a.slots) {
      const Slot& slot = slots_[s];
      for (std::int64_t k = 0; k < 6; ++k)
        for (std::int64_t i = 0; i < slot.size; ++i)
          a.table[k * e + at + i] = slot.values[k * slot.size + i];
      double* setpoint = a.table.data() + 2 * e + at;
      double* velocity_setpoint = a.table.data() + 3 * e + at;
      switch (slot.role) {
        case GRANNY:
          setpoint[0] = m.granny_height;
          break;
        case BUNNY:  // DogtrackBunny.position_at(time), its speed the velocity set point
          bunny_setpoint_next_ = bunny_position + velocity_setpoint[0] * (time - bunny_time);
          setpoint[0] = bunny_setpoint_next_;
          break;
        case LEFT_SWING:
        case RIGHT_SWING: {
          const std::int64_t side = slot.role - LEFT_SWING;
          for (std::int64_t i = 0; i < slot.size && i < 2; ++i) {
            setpoint[i] = m.swing_setpoint[side][i];
            if (m.placed[side]) velocity_setpoint[i] = 0.0;
          }
          break;
        }
        default:
          break;
      }
      at += slot.size;
    }
    std::fill(a.buffer.begin(), a.buffer.end(), 0.0);
    if (!a.tick->run_raw(jw, frames, v, a.table.data(), a.jacobian.data(), a.buffer.data()))
      return nullptr;
    if (a.solve == nullptr) return a.buffer.data();  // a serial actuator's efforts
    std::fill(a.out.begin(), a.out.end(), 0.0);
    const std::int64_t n = a.tick->n(), p = a.solve->chains();
    const va::Distributed d =
        a.solve->distribute_raw(jw, frames, q, a.buffer.data() + nv_ + 2 * n, a.out.data());
    if (d.status != 0) return nullptr;
    if (a.yields) return enforce_unilateral(a, jw, frames, q);
    return a.out.data() + p * n;  // the distribution's tau
  }

  // contact_limits.enforce_unilateral on the distribution in a.out: its tau when every contact
  // row holds, else the request scaled on the yield axes (the solution of base + alpha (wrench
  // - base), base the request without its yield axes, interpolated between the two solutions).
  const double* enforce_unilateral(Attachment& a, const double* jw, const double* frames,
                                   const double* q) {
    const std::int64_t n = a.tick->n(), p = a.solve->chains();
    const auto rows = static_cast<std::int64_t>(a.lows.size());
    const auto minima = static_cast<std::int64_t>(a.minima_axes.size());
    va::contact_margins(frames, a.orientation_rows.data(), a.out.data(), p, n, a.points.data(),
                        a.np, a.axis_rows.data(), a.minima_axes.data(), minima, a.values.data());
    const double least = va::contact_least_margin(a.values.data(), a.lows.data(), rows);
    const double* tau = a.out.data() + p * n;
    if (least >= -1e-9) return tau;  // the usual tick: nothing to scale
    if (std::isnan(least)) return nullptr;
    const double* wrench = a.buffer.data() + nv_ + 2 * n;
    double base[6];
    for (std::int64_t i = 0; i < n; ++i) base[i] = a.yield_mask[i] ? 0.0 : wrench[i];
    std::fill(a.fallback.begin(), a.fallback.end(), 0.0);
    if (a.solve->distribute_raw(jw, frames, q, base, a.fallback.data()).status != 0) return nullptr;
    va::contact_margins(frames, a.orientation_rows.data(), a.fallback.data(), p, n,
                        a.points.data(), a.np, a.axis_rows.data(), a.minima_axes.data(), minima,
                        a.at_base.data());
    const double alpha = va::contact_largest_scale(a.values.data(), a.at_base.data(),
                                                   a.lows.data(), rows);
    const double* start = a.fallback.data() + p * n;
    if (alpha <= 0.0) return start;
    for (std::int64_t i = 0; i < nv_; ++i)  // contact_limits.interpolate's tau
      a.scaled[i] = start[i] + alpha * (tau[i] - start[i]);
    return a.scaled.data();
  }

  std::int64_t run(const double* q, const double* v, double time, double* tau_out,
                   double* readings) {
    if (!va::all_finite(q, nq_) || !va::all_finite(v, nv_) || !std::isfinite(time))
      return DEFER;
    tree_->compute(q, v, pass_.data());
    const double* jw = pass_.data() + tree_->jacobian_offset();
    const double* frames = pass_.data() + tree_->frames_offset();
    va::turkey::Memory m = memory_;
    const bool entered = va::turkey::update(parameters_, frames, rows_, time, m);
    const GaitEfforts::State& state = efforts_.state(m.state);
    double bunny_position = bunny_position_, bunny_time = bunny_time_;
    if (entered) {  // Controller.reset: the bunnies of the state's attachments start here
      for (const std::int64_t index : state.attachments) {
        const Attachment& a = attachments_[static_cast<std::size_t>(index)];
        for (std::size_t k = 0; k < a.slots.size(); ++k) {
          if (a.reset_axes[k] < 0) continue;
          double position[6];
          a.tick->position(frames, position);
          bunny_position = position[a.reset_axes[k]];
          bunny_time = time;
        }
      }
    }
    bunny_setpoint_next_ = bunny_setpoint_;
    bool first = true;
    for (const std::int64_t index : state.attachments) {
      Attachment& a = attachments_[static_cast<std::size_t>(index)];
      const double* effort =
          run_attachment(a, jw, frames, v, q, time, m, bunny_position, bunny_time);
      if (effort == nullptr) return DEFER;
      efforts_.add(effort, first);
      first = false;
    }
    if (!efforts_.close(state, tau_out)) return DEFER;
    for (const std::int64_t index : state.attachments) {  // position, velocity, wrench
      const Attachment& a = attachments_[static_cast<std::size_t>(index)];
      const std::int64_t n = a.tick->n();
      double* row = readings + 18 * index;
      for (std::int64_t k = 0; k < 3; ++k)
        for (std::int64_t i = 0; i < n; ++i) row[6 * k + i] = a.buffer[nv_ + k * n + i];
    }
    readings[18 * static_cast<std::int64_t>(attachments_.size())] = m.granny_height;
    // commit: the slots keep the set points the callbacks placed
    for (Slot& slot : slots_) {
      if (slot.role != LEFT_SWING && slot.role != RIGHT_SWING) continue;
      const std::int64_t side = slot.role - LEFT_SWING;
      if (!m.placed[side]) continue;
      for (std::int64_t i = 0; i < slot.size && i < 2; ++i) {
        slot.values[2 * slot.size + i] = m.swing_setpoint[side][i];
        slot.values[3 * slot.size + i] = 0.0;
      }
    }
    memory_ = m;
    bunny_position_ = bunny_position;
    bunny_time_ = bunny_time;
    bunny_setpoint_ = bunny_setpoint_next_;
    return entered ? ENTERED : TICKED;
  }

  std::shared_ptr<const va::Tree> tree_;
  std::int64_t nq_ = 0, nv_ = 0;
  va::turkey::Rows rows_{};
  va::turkey::Parameters parameters_{};
  std::vector<double> pass_;
  std::vector<Slot> slots_;
  std::vector<Attachment> attachments_;
  GaitEfforts efforts_;
  va::turkey::Memory memory_;
  double bunny_position_ = 0.0, bunny_time_ = 0.0, bunny_setpoint_ = 0.0;
  double bunny_setpoint_next_ = 0.0;
};

}  // namespace

void bind_native(nb::module_& m) {
  nb::class_<NativeTurkey>(m, "NativeTurkey",
                           "A TurkeyWalker's whole tick in one call (gaits.turkey.native): the "
                           "kinematics, the state machine and its callbacks, the attachments, "
                           "the sums, the limp joints and the clipping.")
      .def(nb::init<const Tree&, const I1&, const F1&, const F1&, const F1&>(), "tree"_a,
           "rows"_a, "parameters"_a, "lower"_a, "upper"_a, nb::keep_alive<1, 2>())
      .def("add_slot", &NativeTurkey::add_slot, "values"_a, "role"_a)
      .def("slot", &NativeTurkey::slot, "slot"_a)
      .def("set_slot", &NativeTurkey::set_slot, "slot"_a, "values"_a)
      .def("add_attachment", &NativeTurkey::add_attachment, "tick"_a, "solve"_a.none(),
           "slots"_a, "reset_axes"_a, "yields"_a, "yield_mask"_a, "orientation_rows"_a, "points"_a,
           "axis_rows"_a, "minima_axes"_a, "lows"_a, nb::keep_alive<1, 2>(),
           nb::keep_alive<1, 3>())
      .def("add_state", &NativeTurkey::add_state, "attachments"_a, "limp"_a)
      .def("memory", &NativeTurkey::memory)
      .def("set_memory", &NativeTurkey::set_memory, "values"_a)
      .def("tick", &NativeTurkey::tick, "q"_a, "v"_a, "time"_a, "tau"_a.noconvert(),
           "readings"_a.noconvert())
      .def_prop_ro("state", &NativeTurkey::state)
      .def_prop_ro("nv", &NativeTurkey::nv)
      .def_ro_static("MEMORY", &NativeTurkey::MEMORY)
      .def_ro_static("DEFER", &NativeTurkey::DEFER)
      .def_ro_static("TICKED", &NativeTurkey::TICKED)
      .def_ro_static("ENTERED", &NativeTurkey::ENTERED);
}
// -- end of the native gaits ----------------------------------------------------------------

// -- the hexapod's native tick -----------------------------------------------------------------
// One block, bound by bind_native_hexapod (called from NB_MODULE above). NativeHexapod holds what
// a HexapodWalker's declaration fixes (the kinematic tree, the support attachments' sensors and
// QP workspaces, the swing legs' SpringTick, the states' attachments and limp joints, the effort
// limits) and the gait's memory; tick() runs the kinematics pass, the state machine and its
// callbacks (hexapod_tick.hpp), every active attachment (the body's components and its QP on the
// last certified active set, the swing legs' spring-dampers), the sums, the limp joints and the
// clipping: Gait.compute's arithmetic, bit for bit (gaits/hexapod/native.py,
// tests/test_native_hexapod.py). It answers DEFER, committing nothing, for a tick it does not
// decide (a tripod's entry, a QP whose active set changed, a value not finite).
#include "hexapod_tick.hpp"

namespace {

class NativeHexapod {
 public:
  static constexpr std::int64_t DEFER = -1, TICKED = 0, ENTERED = 1;
  static constexpr std::int64_t MEMORY = 62;
  static constexpr std::int64_t BODY = 15;  // Body's constants

  NativeHexapod(const Tree& tree, const I1& rows, const F1& parameters, const F2& nominal,
                const F1& shape, const F1& body, const F1& tolerances, const F1& lower,
                const F1& upper)
      : tree_(tree.tree()), nq_(tree.nq()), efforts_(lower, upper, tree.tree()->tables().nv) {
    const va::TreeTables& t = tree_->tables();
    nv_ = t.nv;
    require(len(rows) == 7, "rows must be the body's, then the six feet's");
    for (std::int64_t k = 0; k < 7; ++k) {
      require(rows.data()[k] >= 0 && rows.data()[k] < t.nf, "rows out of the frame table");
      rows_.frames[k] = rows.data()[k];
    }
    require(length(parameters) == 5, "parameters must be the 5 gait variables");
    require(nominal.shape(0) == 6 && nominal.shape(1) == 3, "nominal must be (6, 3)");
    require(length(shape) == 11, "shape must be (11,)");
    nominal_.assign(nominal.data(), nominal.data() + 18);
    shape_ = copy<double>(shape);
    const double* p = parameters.data();
    parameters_ = va::hexapod::Parameters{p[0], p[1], p[2], p[3], p[4], nominal_.data(),
                                          shape_.data()};
    set_body(body);
    require(length(tolerances) == 3, "tolerances: active, exact, accuracy");
    tolerances_[0] = tolerances.data()[0];
    tolerances_[1] = tolerances.data()[1];
    tolerances_[2] = tolerances.data()[2];
    pass_.resize(static_cast<std::size_t>(tree_->size(true)));
  }

  // A support attachment: its sensor's tables (the body in the world on x y z rx ry rz), its
  // QP and this thread's workspace (buffer, layout, kept: kept alive by the caller), the
  // prescribed axes (0/1) and their weights.
  std::int64_t add_body(const I1& axis_rows, const I1& sensor_rows, const I1& columns,
                        const F1& signs, const QP& qp, const F1& q, MF1 buffer, const I1& layout,
                        const I1& kept, const I1& keep, const F1& weights) {
    require(len(axis_rows) == 6, "the body's sensor reads its six axes");
    for (std::int64_t i = 0; i < 6; ++i) require(axis_rows.data()[i] == i, "axes x y z rx ry rz");
    require(len(sensor_rows) == 3, "sensor_rows: {B}, {O}, {A}");
    for (std::int64_t k = 0; k < 3; ++k)
      require(sensor_rows.data()[k] >= 0 && sensor_rows.data()[k] < tree_->tables().nf,
              "sensor rows out of the frame table");
    require(len(columns) == length(signs), "signs: one per column");
    for (std::int64_t j = 0; j < len(columns); ++j)
      require(columns.data()[j] >= 0 && columns.data()[j] < nv_, "columns out of range");
    require(qp.n() == 6 && qp.max_frame_row() < tree_->tables().nf, "the QP's rows and axes");
    require(length(q) == nq_, "q must be (nq,)");
    require(len(keep) == 6 && length(weights) >= len(kept), "keep (6,), weights (k,)");
    Attachment a;
    a.body = true;
    a.axis_rows = copy<std::int64_t>(axis_rows);
    a.sensor_rows = copy<std::int64_t>(sensor_rows);
    a.columns = copy<std::int64_t>(columns);
    a.signs = copy<double>(signs);
    a.tables = va::serial::SensorTables{a.axis_rows.data(), 6, a.sensor_rows.data(),
                                        a.columns.data(), a.signs.data(), len(columns)};
    a.qp = &qp;
    std::vector<double> zeros(6, 0.0);
    const F1 wrench(zeros.data(), {6});
    a.views = std::make_shared<va::QPViews>(qp.views(q, wrench, kept, buffer, layout));
    a.buffer = buffer.data();
    a.buffer_size = length(buffer);
    a.layout = copy<std::int64_t>(layout);
    a.kept = copy<std::int64_t>(kept);
    a.keep = copy<std::int64_t>(keep);
    a.weights = copy<double>(weights);
    a.jacobian.resize(static_cast<std::size_t>(6 * len(columns)));
    a.out.resize(static_cast<std::size_t>(qp.chains() * 6 + 2 * nv_ + 12));
    a.active.resize(static_cast<std::size_t>(a.views->m_in));
    a.guess_size = a.views->m_in;
    attachments_.push_back(std::move(a));
    return static_cast<std::int64_t>(attachments_.size()) - 1;
  }

  // A support attachment's warm start (the QP's multipliers of its last certified answer, kept
  // alive by the caller and updated in place), or None (the Python tick solves from cold).
  void set_guess(std::int64_t index, std::optional<MF1> guess) {
    Attachment& a = attachment(index);
    require(a.body, "only a support attachment has a warm start");
    if (!guess) {
      a.guess = nullptr;
      return;
    }
    require(length(*guess) == a.guess_size, "guess must be (m,)");
    a.guess = guess->data();
  }

  // The body's components' constants again (BODY floats: the height's stiffness, damping,
  // velocity set point and force, the planar damper's damping and force, the attitude's
  // stiffness, damping, roll and pitch set points).
  void set_body(const F1& body) {
    require(length(body) == BODY, "body must be the 15 constants");
    const double* b = body.data();
    body_ = va::hexapod::Body{b[0], b[1], b[2], b[3], {b[4], b[5]}, {b[6], b[7]},
                              {b[8], b[9]}, {b[10], b[11], b[12]}, b[13], b[14]};
  }

  // A swing leg's six parameters on its three axes again (its set points are the memory's).
  void set_swing(std::int64_t index, const F1& values) {
    Attachment& a = attachment(index);
    require(a.tick != nullptr && length(values) == 18, "a swing leg's 18 values");
    a.table = copy<double>(values);
  }

  // A swing leg (0-based) on its serial spring tick (one SpringDamper on x y z).
  std::int64_t add_swing(const SpringTick& tick, std::int64_t leg, const F1& values) {
    require(tick.nv() == nv_ && tick.efforts() && tick.n() == 3 && tick.entries() == 3,
            "a swing leg: a serial spring tick on three axes");
    require(tick.rows_end() <= tree_->tables().nf, "the sensor's rows must be in the table");
    require(leg >= 0 && leg < 6, "leg must be in 0..5");
    require(length(values) == 18, "values: the six parameters on three axes");
    Attachment a;
    a.tick = &tick;
    a.leg = leg;
    a.table = copy<double>(values);
    a.spring.resize(static_cast<std::size_t>(tick.size()));
    a.jacobian.resize(static_cast<std::size_t>(tick.jacobian_size()));
    attachments_.push_back(std::move(a));
    return static_cast<std::int64_t>(attachments_.size()) - 1;
  }

  // The states in StateMachine.names order: their attachments (in order) and limp indices.
  void add_state(const I1& attachments, const I1& limp) {
    efforts_.add_state(attachments, limp, static_cast<std::int64_t>(attachments_.size()));
  }

  // The gait's memory as MEMORY floats (gaits/hexapod/native.py's MEMORY names them).
  Owned memory() const {
    std::unique_ptr<double[]> out(new double[MEMORY]);
    const va::hexapod::Memory& m = memory_;
    double* o = out.get();
    *o++ = static_cast<double>(m.state);
    *o++ = m.entered_at;
    *o++ = static_cast<double>(m.support);
    *o++ = m.phase;
    *o++ = m.ground;
    for (const double x : m.kernel) *o++ = x;
    *o++ = m.target_time;
    *o++ = m.filter_time;
    for (const double x : m.velocity_body) *o++ = x;
    for (const double x : m.velocity_filtered) *o++ = x;
    for (const double x : m.setpoint) *o++ = x;
    for (const double x : m.acceleration) *o++ = x;
    for (const double x : m.planar_velocity) *o++ = x;
    *o++ = m.planar_yaw;
    *o++ = m.attitude_yaw;
    *o++ = m.attitude_yaw_rate;
    *o++ = m.height_setpoint;
    for (int leg = 0; leg < 6; ++leg)
      for (int i = 0; i < 3; ++i) *o++ = m.leg_setpoint[leg][i];
    for (int leg = 0; leg < 6; ++leg)
      for (int i = 0; i < 3; ++i) *o++ = m.leg_velocity[leg][i];
    return owned(std::move(out), MEMORY);
  }

  // The swing tripod's kernel state (HexapodWalker._swing, (3, 9)) is memory too: 27 floats.
  Owned swing() const {
    std::unique_ptr<double[]> out(new double[27]);
    std::copy(memory_.swing, memory_.swing + 27, out.get());
    return owned(std::move(out), 27);
  }

  void set_memory(const F1& values, const F1& swing) {
    require(length(values) == MEMORY && length(swing) == 27, "memory (MEMORY,), swing (27,)");
    const double* v = values.data();
    require(v[0] >= 0 && v[0] < 4 && v[0] == std::floor(v[0]), "memory's state: 0 to 3");
    require(v[2] == 0.0 || v[2] == 1.0, "memory's support: 0 (a) or 1 (b)");
    va::hexapod::Memory& m = memory_;
    m.state = static_cast<std::int64_t>(v[0]);
    m.entered_at = *++v;
    m.support = static_cast<std::int64_t>(*++v);
    m.phase = *++v;
    m.ground = *++v;
    for (double& x : m.kernel) x = *++v;
    m.target_time = *++v;
    m.filter_time = *++v;
    for (double& x : m.velocity_body) x = *++v;
    for (double& x : m.velocity_filtered) x = *++v;
    for (double& x : m.setpoint) x = *++v;
    for (double& x : m.acceleration) x = *++v;
    for (double& x : m.planar_velocity) x = *++v;
    m.planar_yaw = *++v;
    m.attitude_yaw = *++v;
    m.attitude_yaw_rate = *++v;
    m.height_setpoint = *++v;
    for (int leg = 0; leg < 6; ++leg)
      for (int i = 0; i < 3; ++i) m.leg_setpoint[leg][i] = *++v;
    for (int leg = 0; leg < 6; ++leg)
      for (int i = 0; i < 3; ++i) m.leg_velocity[leg][i] = *++v;
    std::copy(swing.data(), swing.data() + 27, m.swing);
  }

  // One tick at (q, v, time) with the command (vx, vy, yaw rate) and the feet's contact switches
  // (6 ints, or none): ENTERED or TICKED with tau (nv) and each active attachment's position,
  // velocity and wrench (rows of readings (attachments, 18)) written, or DEFER with nothing
  // committed.
  std::int64_t tick(const F1& q, const F1& v, double time, const F1& command,
                    const I1& contacts, const MF1& tau,
                    const nb::ndarray<double, nb::numpy, nb::ndim<2>, nb::c_contig,
                                      nb::device::cpu>& readings) {
    require(length(q) == nq_ && length(v) == nv_ && length(tau) == nv_,
            "q must be (nq,), v and tau (nv,)");
    require(length(command) == 3, "command: vx, vy, yaw rate");
    require(len(contacts) == 0 || len(contacts) == 6, "contacts: six switches or none");
    require(static_cast<std::int64_t>(readings.shape(0)) ==
                    static_cast<std::int64_t>(attachments_.size()) &&
                readings.shape(1) == 18,
            "readings must be (attachments, 18)");
    require(efforts_.states() == 4, "the four states must be declared");
    const va::hexapod::Inputs in{{command.data()[0], command.data()[1]}, command.data()[2],
                                 len(contacts) ? contacts.data() : nullptr};
    nb::gil_scoped_release release;
    return run(q.data(), v.data(), time, in, tau.data(), readings.data());
  }

  std::int64_t nv() const { return nv_; }
  std::int64_t state() const { return memory_.state; }

 private:
  struct Attachment {
    bool body = false;
    // a support attachment's sensor and QP
    std::vector<std::int64_t> axis_rows, sensor_rows, columns;
    std::vector<double> signs;
    va::serial::SensorTables tables{};
    const QP* qp = nullptr;
    std::shared_ptr<va::QPViews> views;
    double* buffer = nullptr;
    std::int64_t buffer_size = 0, guess_size = 0;
    double* guess = nullptr;
    std::vector<std::int64_t> layout, kept, keep, active;
    std::vector<double> weights, out, z, multipliers, saved;
    double position[6], velocity[6], wrench[6];
    // a swing leg's spring tick
    const SpringTick* tick = nullptr;
    std::int64_t leg = -1;
    std::vector<double> table, spring;
    std::vector<double> jacobian;
  };

  Attachment& attachment(std::int64_t index) {
    require(index >= 0 && index < static_cast<std::int64_t>(attachments_.size()),
            "unknown attachment");
    return attachments_[static_cast<std::size_t>(index)];
  }

  // A support attachment: the sensor, the components' wrench, the QP on the last certified
  // active set; its efforts (nullptr: DEFER).
  const double* run_body(Attachment& a, const double* jw, const double* frames, const double* v,
                         const double* q, const va::hexapod::Memory& m, double& attitude_yaw) {
    if (a.guess == nullptr) return nullptr;  // no certified answer yet: DAQP / ProxQP decide
    a.saved.assign(a.guess, a.guess + a.guess_size);  // put back if the tick is handed on
    va::serial::relative_sensor(jw, nv_, frames, v, a.tables, a.jacobian.data(), a.position,
                                a.velocity);
    if (!va::hexapod::body_wrench(body_, m, a.position, a.velocity, a.wrench, attitude_yaw))
      return nullptr;
    std::fill(a.out.begin(), a.out.end(), 0.0);
    va::Distributed d;
    const std::int64_t count = a.qp->again_raw(
        jw, frames, q, a.wrench, a.kept.data(), static_cast<std::int64_t>(a.kept.size()),
        *a.views, a.buffer, a.buffer_size, a.layout.data(), a.keep.data(), a.weights.data(),
        a.guess, tolerances_[0], tolerances_[1], tolerances_[2], a.out.data(), a.active.data(),
        a.z, a.multipliers, d);
    if (count < 0) return nullptr;
    return a.out.data() + a.qp->chains() * 6;  // the distribution's tau
  }

  // A swing leg: its spring tick with the memory's set points; its efforts (nullptr: DEFER).
  const double* run_swing(Attachment& a, const double* jw, const double* frames, const double* v,
                          const va::hexapod::Memory& m) {
    for (int i = 0; i < 3; ++i) {
      a.table[6 + i] = m.leg_setpoint[a.leg][i];
      a.table[9 + i] = m.leg_velocity[a.leg][i];
    }
    std::fill(a.spring.begin(), a.spring.end(), 0.0);
    if (!a.tick->run_raw(jw, frames, v, a.table.data(), a.jacobian.data(), a.spring.data()))
      return nullptr;
    return a.spring.data();
  }

  // DEFER after the state's attachments ran: the warm starts they certified put back (the
  // Python tick starts from the same ones).
  std::int64_t defer(const GaitEfforts::State& state) {
    for (const std::int64_t index : state.attachments) {
      Attachment& a = attachments_[static_cast<std::size_t>(index)];
      if (a.body && a.guess != nullptr && !a.saved.empty())
        std::copy(a.saved.begin(), a.saved.end(), a.guess);
    }
    return DEFER;
  }

  std::int64_t run(const double* q, const double* v, double time, const va::hexapod::Inputs& in,
                   double* tau_out, double* readings) {
    if (!va::all_finite(q, nq_) || !va::all_finite(v, nv_) || !std::isfinite(time) ||
        !va::all_finite(in.command, 2) || !std::isfinite(in.yaw_rate))
      return DEFER;
    tree_->compute(q, v, pass_.data());
    const double* jw = pass_.data() + tree_->jacobian_offset();
    const double* frames = pass_.data() + tree_->frames_offset();
    va::hexapod::Memory m = memory_;
    const va::hexapod::Update update =
        va::hexapod::update(parameters_, frames, rows_, v, time, in, m);
    if (update == va::hexapod::DEFER) return DEFER;
    const GaitEfforts::State& state = efforts_.state(m.state);
    for (const std::int64_t index : state.attachments)
      attachments_[static_cast<std::size_t>(index)].saved.clear();
    bool first = true;
    for (const std::int64_t index : state.attachments) {
      Attachment& a = attachments_[static_cast<std::size_t>(index)];
      const double* effort = a.body ? run_body(a, jw, frames, v, q, m, m.attitude_yaw)
                                    : run_swing(a, jw, frames, v, m);
      if (effort == nullptr) return defer(state);
      efforts_.add(effort, first);
      first = false;
    }
    if (!efforts_.close(state, tau_out)) return defer(state);
    for (const std::int64_t index : state.attachments) {  // position, velocity, wrench
      const Attachment& a = attachments_[static_cast<std::size_t>(index)];
      double* row = readings + 18 * index;
      if (a.body) {
        for (int i = 0; i < 6; ++i) {
          row[i] = a.position[i];
          row[6 + i] = a.velocity[i];
          row[12 + i] = a.wrench[i];
        }
      } else {
        for (int k = 0; k < 3; ++k)
          for (int i = 0; i < 3; ++i) row[6 * k + i] = a.spring[nv_ + 3 * k + i];
      }
    }
    memory_ = m;
    return update == va::hexapod::ENTERED ? ENTERED : TICKED;
  }

  std::shared_ptr<const va::Tree> tree_;
  std::int64_t nq_ = 0, nv_ = 0;
  va::hexapod::Rows rows_{};
  va::hexapod::Parameters parameters_{};
  va::hexapod::Body body_{};
  std::vector<double> nominal_, shape_;
  double tolerances_[3] = {0.0, 0.0, 0.0};
  std::vector<double> pass_;
  std::vector<Attachment> attachments_;
  GaitEfforts efforts_;
  va::hexapod::Memory memory_;
};

}  // namespace

void bind_native_hexapod(nb::module_& m) {
  nb::class_<NativeHexapod>(m, "NativeHexapod",
                            "A HexapodWalker's whole tick in one call (gaits.hexapod.native): "
                            "the kinematics, the state machine and its callbacks, the body's "
                            "components and QP, the swing legs, the sums, the limp joints and "
                            "the clipping.")
      .def(nb::init<const Tree&, const I1&, const F1&, const F2&, const F1&, const F1&,
                    const F1&, const F1&, const F1&>(),
           "tree"_a, "rows"_a, "parameters"_a, "nominal"_a, "shape"_a, "body"_a, "tolerances"_a,
           "lower"_a, "upper"_a, nb::keep_alive<1, 2>())
      .def("add_body", &NativeHexapod::add_body, "axis_rows"_a, "sensor_rows"_a, "columns"_a,
           "signs"_a, "qp"_a, "q"_a, "buffer"_a.noconvert(), "layout"_a, "kept"_a, "keep"_a,
           "weights"_a, nb::keep_alive<1, 6>(), nb::keep_alive<1, 8>())
      .def("set_guess", &NativeHexapod::set_guess, "index"_a, "guess"_a.noconvert().none())
      .def("set_body", &NativeHexapod::set_body, "body"_a)
      .def("set_swing", &NativeHexapod::set_swing, "index"_a, "values"_a)
      .def("add_swing", &NativeHexapod::add_swing, "tick"_a, "leg"_a, "values"_a,
           nb::keep_alive<1, 2>())
      .def("add_state", &NativeHexapod::add_state, "attachments"_a, "limp"_a)
      .def("memory", &NativeHexapod::memory)
      .def("swing", &NativeHexapod::swing)
      .def("set_memory", &NativeHexapod::set_memory, "values"_a, "swing"_a)
      .def("tick", &NativeHexapod::tick, "q"_a, "v"_a, "time"_a, "command"_a, "contacts"_a,
           "tau"_a.noconvert(), "readings"_a.noconvert())
      .def_prop_ro("state", &NativeHexapod::state)
      .def_prop_ro("nv", &NativeHexapod::nv)
      .def_ro_static("MEMORY", &NativeHexapod::MEMORY)
      .def_ro_static("DEFER", &NativeHexapod::DEFER)
      .def_ro_static("TICKED", &NativeHexapod::TICKED)
      .def_ro_static("ENTERED", &NativeHexapod::ENTERED);
}
// -- end of the hexapod's native tick ----------------------------------------------------------

// -- MuJoCo's contacts read in place (contacts_view.hpp) ------------------------------------
// One block, bound by bind_contacts (called from NB_MODULE above), compiled when MuJoCo's
// headers were found at build time (VA_MUJOCO); MJ_VERSION is then their mjVERSION_HEADER (0
// without them: simulation.contact_queries keeps its Python scan).
#ifdef VA_MUJOCO
#include <mujoco/mujoco.h>

#include "contacts_view.hpp"
#endif

namespace {

#ifdef VA_MUJOCO
// A simulation's mjModel and mjData (their addresses: mujoco.MjModel._address, MjData._address),
// the roles of its geoms and the running library's mj_contactForce (its address, 0: none). The
// caller keeps both alive as long as the view (Simulator holds them).
class ContactView {
 public:
  // mj_contactForce's signature (the function's address comes from the running library).
  using ContactForce = void (*)(const mjModel*, const mjData*, int, mjtNum[6]);

  ContactView(std::uintptr_t model, std::uintptr_t address, std::int64_t version,
              const I1& roles, std::uintptr_t contact_force)
      : model_(reinterpret_cast<const mjModel*>(model)),
        data_(reinterpret_cast<const mjData*>(address)),
        contact_force_(reinterpret_cast<ContactForce>(contact_force)) {
    require(version == mjVERSION_HEADER, "MuJoCo's version must be the headers' (MJ_VERSION)");
    require(model != 0 && address != 0, "the MjModel's and MjData's addresses must not be null");
    roles_.reserve(roles.shape(0));
    for (std::size_t g = 0; g < roles.shape(0); ++g) {
      const std::int64_t role = roles.data()[g];
      require(role >= va::mj::OTHER && role <= va::mj::ROBOT, "roles must be 0, 1 or 2");
      roles_.push_back(static_cast<std::int8_t>(role));
    }
  }

  // (contact index, robot geom, sign) rows into out ((>= ncon, 3)); their number.
  std::int64_t scan(const nb::ndarray<std::int64_t, nb::numpy, nb::ndim<2>, nb::c_contig,
                                      nb::device::cpu>& out) const {
    require(out.shape(1) == 3 && static_cast<std::int64_t>(out.shape(0)) >= data_->ncon,
            "out must be (>= ncon, 3)");
    return va::mj::terrain_contacts(data_, roles_.data(),
                                    static_cast<std::int64_t>(roles_.size()), out.data());
  }

  // Whether a robot geom whose flag in allowed (one per geom) is 0 touches the terrain.
  bool touches_outside(const nb::ndarray<const std::int8_t, nb::numpy, nb::ndim<1>,
                                         nb::c_contig, nb::device::cpu>& allowed) const {
    require(allowed.shape(0) == roles_.size(), "allowed must hold one flag per geom");
    return va::mj::touches_outside(data_, roles_.data(), allowed.data(),
                                   static_cast<std::int64_t>(roles_.size()));
  }

  // Per robot-terrain contact on a geom of a group (groups: one per geom, -1 none), in contact
  // order: (group, normal force, tangential force 1, 2) [N] in the contact's frame
  // (mj_contactForce) into out ((>= ncon, 4)); their number. -1 without mj_contactForce.
  std::int64_t forces(const I1& groups,
                      const nb::ndarray<double, nb::numpy, nb::ndim<2>, nb::c_contig,
                                        nb::device::cpu>& out) const {
    require(groups.shape(0) == roles_.size(), "groups must hold one entry per geom");
    require(out.shape(1) == 4 && static_cast<std::int64_t>(out.shape(0)) >= data_->ncon,
            "out must be (>= ncon, 4)");
    if (contact_force_ == nullptr) return -1;
    const auto ngeom = static_cast<std::int64_t>(roles_.size());
    std::int64_t count = 0;
    int sign = 0;
    mjtNum force[6];
    for (int i = 0; i < data_->ncon; ++i) {
      const int geom = va::mj::robot_geom(data_->contact[i], roles_.data(), ngeom, &sign);
      if (geom < 0 || groups.data()[geom] < 0) continue;
      contact_force_(model_, data_, i, force);
      double* row = out.data() + 4 * count++;
      row[0] = static_cast<double>(groups.data()[geom]);
      row[1] = force[0], row[2] = force[1], row[3] = force[2];
    }
    return count;
  }

  std::int64_t ncon() const { return data_->ncon; }

 private:
  const mjModel* model_;
  const mjData* data_;
  ContactForce contact_force_;
  std::vector<std::int8_t> roles_;
};
#endif

}  // namespace

void bind_contacts(nb::module_& m) {
#ifdef VA_MUJOCO
  m.attr("MJ_VERSION") = static_cast<std::int64_t>(mjVERSION_HEADER);
  nb::class_<ContactView>(m, "ContactView",
                          "MuJoCo's contact list read in place (simulation.contact_queries): "
                          "the robot-terrain contacts, and whether a geom outside a set "
                          "touches the terrain.")
      .def(nb::init<std::uintptr_t, std::uintptr_t, std::int64_t, const I1&, std::uintptr_t>(),
           "model"_a, "address"_a, "version"_a, "roles"_a, "contact_force"_a)
      .def("scan", &ContactView::scan, "out"_a.noconvert(),
           "ContactQueries._scan_contacts: (contact index, robot geom, sign) rows; their number.")
      .def("forces", &ContactView::forces, "groups"_a, "out"_a.noconvert(),
           "(group, normal, tangent 1, tangent 2) rows of the contacts on grouped geoms (-1: "
           "no mj_contactForce).")
      .def("touches_outside", &ContactView::touches_outside, "allowed"_a,
           "Whether a robot geom not allowed (flag 0) touches the terrain.")
      .def_prop_ro("ncon", &ContactView::ncon);
#else
  m.attr("MJ_VERSION") = static_cast<std::int64_t>(0);
#endif
}
// -- end of MuJoCo's contacts ---------------------------------------------------------------
