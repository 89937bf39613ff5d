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

#include <algorithm>
#include <cstdint>
#include <memory>
#include <optional>
#include <stdexcept>
#include <vector>

#include "distribute.hpp"
#include "kinematics.hpp"

namespace nb = nanobind;
using namespace nb::literals;

namespace {

using F1 = nb::ndarray<const double, nb::numpy, nb::ndim<1>, nb::c_contig, nb::device::cpu>;
using F2 = nb::ndarray<const double, nb::numpy, nb::ndim<2>, nb::c_contig, nb::device::cpu>;
using I1 = nb::ndarray<const std::int64_t, nb::numpy, nb::ndim<1>, nb::c_contig, nb::device::cpu>;
using I2 = nb::ndarray<const std::int64_t, nb::numpy, nb::ndim<2>, nb::c_contig, nb::device::cpu>;
using Owned = nb::ndarray<nb::numpy, double, nb::ndim<1>>;

void require(bool ok, const char* what) {
  if (!ok) throw std::invalid_argument(what);
}

std::int64_t length(const F1& a) { return static_cast<std::int64_t>(a.shape(0)); }

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
       const F2& velocity_subspace, const I1& frame_parents, const F2& frame_floats) {
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

 private:
  std::shared_ptr<const va::Tree> tree_;
  std::int64_t nq_ = 0;
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
    const auto size = static_cast<std::size_t>(packed_.out_size(nv_));
    std::unique_ptr<double[]> out(new double[size]());
    va::Distributed d;
    {
      nb::gil_scoped_release release;
      std::vector<double> kinematics(static_cast<std::size_t>(t.size(false)));
      t.compute(q.data(), nullptr, kinematics.data());
      d = va::distribute(kinematics.data() + t.jacobian_offset(), nv_,
                         kinematics.data() + t.frames_offset(), q.data(), wrench.data(), packed_,
                         out.get());
    }
    return distributed(owned(std::move(out), size), d);
  }

 private:
  void check_tick(const F1& q, const F1& wrench) const {
    require(length(wrench) == packed_.n, "wrench must be (n,)");
    require(length(q) > packed_.max_q_index(), "q is shorter than the springs' indices");
  }

  std::vector<std::int64_t> ints_;
  std::vector<double> floats_;
  std::int64_t nv_;
  va::Packed packed_;
};

}  // namespace

NB_MODULE(_core, m) {
  m.doc() = "Compiled kernels of virtual_actuators (C++, built at install); see "
            "virtual_actuators.native.";
  // Trees and distributions live in the robots' caches (module-level registries) until the
  // interpreter's teardown, which may free the module first: not a leak worth a report.
  nb::set_leak_warnings(false);
  void bind_attachment(nb::module_ & m);  // the serial attachment's block, at the end of the file
  bind_attachment(m);

  nb::class_<Tree>(m, "Tree",
                   "A kinematic tree's tables (KinematicTree): forward kinematics per tick.")
      .def(nb::init<const I2&, const F2&, const I1&, const F2&, const I1&, const F2&>(),
           "joint_ints"_a, "joint_floats"_a, "velocity_joint"_a, "velocity_subspace"_a,
           "frame_parents"_a, "frame_floats"_a)
      .def("compute", &Tree::compute, "q"_a, "v"_a = nb::none(),
           "Joint placements, world joint Jacobian, frame placements (and velocities) in one "
           "buffer: kinematics.kernels.forward_kinematics.")
      .def("size", &Tree::size, "with_velocity"_a, "Length of compute()'s buffer.")
      .def_prop_ro("nf", &Tree::nf, "Number of frames compute() places.");

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
           "Forward kinematics and the distribution in one call (q as the tree needs it).");
}

// == serial spring-damper attachments (attachment.hpp) ======================================
// One block, bound by bind_attachment (called from NB_MODULE above): SerialSpring holds a serial
// actuator's sensor tables; tick() runs attachment_kernel.spring_damper_tick.
#include "attachment.hpp"

namespace {

class SerialSpring {
 public:
  SerialSpring(const I1& axis_rows, const I1& rows, const I1& columns, const F1& signs,
               std::int64_t rotation, std::int64_t nv)
      : axis_rows_(copy<std::int64_t>(axis_rows)),
        rows_(copy<std::int64_t>(rows)),
        columns_(copy<std::int64_t>(columns)),
        signs_(copy<double>(signs)),
        rotation_(rotation),
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
    require(rotation >= -1 && rotation < n, "rotation must be -1 or an axis index");
    rows_end_ = std::max(rows_[0], std::max(rows_[1], rows_[2])) + 1;
    const auto m = static_cast<std::int64_t>(columns_.size());
    tables_ = va::serial::SensorTables{axis_rows_.data(), n, rows_.data(), columns_.data(),
                                       signs_.data(), m};
  }

  // effort (nv), position (n), velocity (n), wrench (n), flag: spring_damper_tick's buffer.
  Owned tick(const F2& jacobian_world, const F2& frames, const F1& v, const F1& stiffness,
             const F1& damping, const F1& setpoint, const F1& velocity_setpoint, const F1& force,
             const F1& limit) const {
    const std::int64_t n = tables_.n;
    require(jacobian_world.shape(0) == 6 &&
                static_cast<std::int64_t>(jacobian_world.shape(1)) == nv_,
            "jacobian_world must be (6, nv)");
    require(frames.shape(1) == 12 && static_cast<std::int64_t>(frames.shape(0)) >= rows_end_,
            "frames must be (nf, 12) with the sensor's rows");
    require(length(v) == nv_, "v must be (nv,)");
    for (const F1* a : {&stiffness, &damping, &setpoint, &velocity_setpoint, &force, &limit})
      require(length(*a) == n, "the spring-damper's parameters must be one per axis");
    const auto size = static_cast<std::size_t>(nv_ + 3 * n + 1);
    std::unique_ptr<double[]> out(new double[size]());
    {
      nb::gil_scoped_release release;
      std::vector<double> jacobian(static_cast<std::size_t>(tables_.m * n));
      const va::serial::SpringParameters p{stiffness.data(), damping.data(),
                                           setpoint.data(),  velocity_setpoint.data(),
                                           force.data(),     limit.data()};
      va::serial::spring_damper_tick(jacobian_world.data(), nv_, frames.data(), v.data(),
                                     tables_, rotation_, p, jacobian.data(), out.get());
    }
    return owned(std::move(out), size);
  }

 private:
  std::vector<std::int64_t> axis_rows_, rows_, columns_;
  std::vector<double> signs_;
  std::int64_t rotation_, nv_, rows_end_ = 0;
  va::serial::SensorTables tables_{};
};

}  // namespace

void bind_attachment(nb::module_& m) {
  nb::class_<SerialSpring>(m, "SerialSpring",
                           "A serial actuator's sensor tables (control.attachment_kernel.Serial"
                           "SpringTick): one spring-damper attachment's tick per call.")
      .def(nb::init<const I1&, const I1&, const I1&, const F1&, std::int64_t, std::int64_t>(),
           "axis_rows"_a, "rows"_a, "columns"_a, "signs"_a, "rotation"_a, "nv"_a)
      .def("tick", &SerialSpring::tick, "jacobian_world"_a, "frames"_a, "v"_a, "stiffness"_a,
           "damping"_a, "setpoint"_a, "velocity_setpoint"_a, "force"_a, "limit"_a,
           "attachment_kernel.spring_damper_tick: effort (nv), position, velocity, wrench (n) "
           "and the flag (1.0, or 0.0: the general path runs) in one buffer.");
}
// == end of the serial spring-damper attachments' block ======================================
