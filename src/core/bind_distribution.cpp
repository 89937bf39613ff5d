// The partitioned distribution's bindings (distribute.hpp, tables.hpp): Distribution, the packed
// tables of one distribution mode, solved from a snapshot's arrays or from q with a Tree.
#include <cstdint>
#include <memory>
#include <vector>

#include "bind_common.hpp"
#include "bind_kinematics.hpp"
#include "distribute.hpp"
#include "tables.hpp"

namespace va::py {
namespace {

// The tick's buffer and norms (TickResult.from_buffer reads them).
nb::tuple distributed(Owned out, const va::Distributed& d) {
  return nb::make_tuple(out, d.residual, d.scale, d.rounding, d.status, d.worst, d.worst_chain);
}

// The packed tables of one distribution mode (partitioned.compiled), owned.
class Distribution {
 public:
  Distribution(const I1& ints, const F1& floats, std::int64_t nv)
      : ints_(copy<std::int64_t>(ints)), floats_(copy<double>(floats)), nv_(nv) {
    require(nv >= 0, "nv must be >= 0");
    packed_ = va::Packed::checked(ints_, floats_, nv);
  }

  // One tick from the snapshot's arrays: jacobian_world (6, nv), frames (nf, 12), q, wrench (n).
  nb::tuple solve(const F2& jacobian_world, const F2& frames, const F1& q, const F1& wrench) const {
    require(
        jacobian_world.shape(0) == 6 && static_cast<std::int64_t>(jacobian_world.shape(1)) == nv_,
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
                    t.tables().nf > packed_.max_frame_row() && tree.accepts(q) &&
                    tree.nq() > packed_.max_q_index() && wrench.dtype() == nb::dtype<double>() &&
                    wrench.ndim() == 1 && static_cast<std::int64_t>(wrench.shape(0)) == packed_.n &&
                    (packed_.n <= 1 || wrench.stride(0) == 1) &&
                    va::all_finite(static_cast<const double*>(wrench.data()), packed_.n);
    if (!ok) {
      va::Distributed d;
      d.status = UNCHECKED;
      return distributed(owned(std::unique_ptr<double[]>(new double[1]), 0), d);
    }
    return run(t, static_cast<const double*>(q.data()), static_cast<const double*>(wrench.data()));
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

}  // namespace

void bind_distribution(nb::module_& m) {
  nb::class_<Distribution>(m, "Distribution",
                           "The packed tables of one distribution mode (CompiledDistribution).")
      .def(nb::init<const I1&, const F1&, std::int64_t>(), "ints"_a, "floats"_a, "nv"_a)
      .def("solve", &Distribution::solve, "jacobian_world"_a, "frames"_a, "q"_a, "wrench"_a,
           "One tick on the snapshot's arrays: (out, residual, scale, "
           "rounding, status, worst, worst_chain).")
      .def("tick", &Distribution::tick, "tree"_a, "q"_a, "wrench"_a,
           "Forward kinematics and the distribution in one call (q as the tree needs it).")
      .def("checked_tick", &Distribution::checked_tick, "tree"_a, "q"_a, "wrench"_a,
           "tick() on unchecked arguments: status 4 (nothing computed) unless q is a finite "
           "(nq,) float64 vector with unit norms within 1e-12 and the wrench a finite (n,) one.")
      .def_ro_static("UNCHECKED", &Distribution::UNCHECKED);
}

}  // namespace va::py
