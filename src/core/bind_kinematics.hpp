// The kinematic tree's declaration-time tables (kinematics.hpp) as the Python object Tree,
// bound in bind_kinematics.cpp; the distributions, the QP and the compiled machine take one.
#pragma once

#include <algorithm>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "bind_common.hpp"
#include "kinematics.hpp"

namespace va::py {

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
    require(
        velocity_subspace.shape(0) == velocity_joint.shape(0) && velocity_subspace.shape(1) == 6,
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
                                 : kind == va::REVOLUTE_UNBOUNDED              ? 2
                                 : kind == va::FREE_FLYER                      ? 7
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

}  // namespace va::py
