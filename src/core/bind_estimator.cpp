// The legged state estimator's binding (legged_estimator.hpp): LeggedFilter, built once per
// estimator by virtual_actuators.estimation.LeggedEstimator, updated once per reading.
#include <nanobind/stl/string.h>
#include <nanobind/stl/vector.h>

#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "bind_common.hpp"
#include "bind_kinematics.hpp"
#include "legged_estimator.hpp"

namespace va::py {
namespace {

constexpr std::int64_t TUNING_SIZE = 31;

va::EstimatorTuning tuning_of(const F1& v) {
  require(length(v) == TUNING_SIZE, "tuning must have 31 entries");
  const double* t = v.data();
  va::EstimatorTuning out{};
  out.attitude = {t[0], t[1], t[2], t[3], t[4], t[5], t[27], t[28]};
  out.leg = {t[6], t[7], t[8], t[9], t[10], t[11], t[12], t[13], t[14]};
  out.contact = {t[15], t[16], t[17], t[18], t[19], t[20], t[21], t[22]};
  out.tilt_sigma = t[23];
  out.yaw_sigma = t[24];
  out.bias_sigma = t[25];
  out.accel_bias_sigma = t[29];
  out.output_rate_time = t[30];
  out.level_ground = t[26] != 0.0;
  return out;
}

class LeggedFilter {
 public:
  LeggedFilter(const Tree& tree, const I1& foot_rows, std::int64_t imu_row, const I1& leg_offsets,
               const I1& leg_columns, const I1& gravity_columns, const F1& masses, const F2& levers,
               const F2& spheres, const F1& gravity, double weight_per_foot, const F1& tuning,
               const std::vector<std::string>& feet) {
    const va::TreeTables& t = tree.tree()->tables();
    const std::int64_t nf = len(foot_rows);
    require(nf >= 1 && nf <= 64, "foot_rows must have 1 to 64 entries");
    require(static_cast<std::int64_t>(feet.size()) == nf, "feet must name every foot row");
    for (const std::string& name : feet) feet_.push_back(nb::str(name.c_str()));
    for (std::int64_t f = 0; f < nf; ++f)
      require(foot_rows.data()[f] >= 0 && foot_rows.data()[f] < t.nf, "foot_rows out of range");
    require(imu_row >= 0 && imu_row < t.nf, "imu_row out of range");
    require(len(leg_offsets) == nf + 1 && leg_offsets.data()[0] == 0 &&
                leg_offsets.data()[nf] == len(leg_columns),
            "leg_offsets must be (nf + 1,) offsets into leg_columns");
    for (std::int64_t k = 0; k < len(leg_columns); ++k)
      require(leg_columns.data()[k] >= 0 && leg_columns.data()[k] < t.nv,
              "leg_columns out of range");
    for (std::int64_t k = 0; k < len(gravity_columns); ++k)
      require(gravity_columns.data()[k] >= 0 && gravity_columns.data()[k] < t.nv,
              "gravity_columns out of range");
    require(length(masses) == t.njoints && levers.shape(0) == static_cast<size_t>(t.njoints) &&
                levers.shape(1) == 3,
            "masses must be (njoints,), levers (njoints, 3)");
    require(length(gravity) == 3 && weight_per_foot > 0.0, "gravity (3,), weight_per_foot > 0");
    va::EstimatorTables tables;
    tables.tree = tree.tree();
    tables.foot_rows = copy<std::int64_t>(foot_rows);
    tables.imu_row = imu_row;
    tables.leg_offsets = copy<std::int64_t>(leg_offsets);
    tables.leg_columns = copy<std::int64_t>(leg_columns);
    tables.gravity_columns = copy<std::int64_t>(gravity_columns);
    tables.masses = copy<double>(masses);
    tables.levers = copy<double>(levers);
    require(spheres.shape(0) == static_cast<size_t>(nf) && spheres.shape(1) == 4,
            "spheres must be (nf, 4)");
    tables.spheres = copy<double>(spheres);
    for (int i = 0; i < 3; ++i) tables.gravity[i] = gravity.data()[i];
    tables.weight_per_foot = weight_per_foot;
    nq_ = tree.nq();
    nv_ = t.nv;
    q_.assign(static_cast<size_t>(nq_), 0.0);  // estimate() before any reading: the joints at 0
    q_[6] = 1.0;
    core_ = std::make_unique<va::LeggedEstimatorCore>(std::move(tables), tuning_of(tuning));
  }

  void reset(const F1& q_local, const F1& position, const F2& rotation, const F1& velocity) {
    require(length(q_local) == nq_, "q_local must be (nq,)");
    require(length(position) == 3 && length(velocity) == 3, "position, velocity must be (3,)");
    require(rotation.shape(0) == 3 && rotation.shape(1) == 3, "rotation must be (3, 3)");
    va::so3::Mat3 r;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) r[i][j] = rotation.data()[3 * i + j];
    core_->reset(q_local.data(), position.data(), r, velocity.data());
    q_.assign(q_local.data(), q_local.data() + nq_);
  }

  // One reading in the reading's own order: joints scattered into q and v by index_q and
  // index_v (from LeggedEstimator's name map), tau (nv) or, empty, effort scattered by index_v;
  // switches (nf: 1 closed, 0 open, -1 none) or empty.
  // 0: updated; 1: the gyro beyond gyro_range; 2: the accelerometer beyond accel_range; 3: tau
  // not finite; 4: the estimate would not be finite (or its covariance not positive). Only 0
  // changes the filter.
  int update_reading(const F1& position, const F1& velocity, const F1& effort, const I1& index_q,
                     const I1& index_v, const F1& gyro, const F1& accel, const F1& tau, double time,
                     double gyro_range, double accel_range, const F1& switches) {
    const std::int64_t n = length(position);
    require(length(velocity) == n && length(effort) == n && len(index_q) == n && len(index_v) == n,
            "position, velocity, effort, index_q and index_v must have one entry per joint");
    require(length(gyro) == 3 && length(accel) == 3, "gyro, accel must be (3,)");
    require(length(tau) == 0 || length(tau) == nv_, "tau must be (nv,) or empty");
    require(length(switches) == 0 || length(switches) == core_->feet(),
            "switches must be (nf,) or empty");
    for (std::int64_t k = 0; k < n; ++k)
      require(index_q.data()[k] >= 7 && index_q.data()[k] < nq_ && index_v.data()[k] >= 6 &&
                  index_v.data()[k] < nv_,
              "index_q, index_v out of range");
    for (int i = 0; i < 3; ++i) {
      if (!(std::abs(gyro.data()[i]) <= gyro_range)) return 1;
      if (!(std::abs(accel.data()[i]) <= accel_range)) return 2;
    }
    q_.assign(static_cast<size_t>(nq_), 0.0);
    v_.assign(static_cast<size_t>(nv_), 0.0);
    tau_.assign(static_cast<size_t>(nv_), 0.0);
    q_[6] = 1.0;
    for (std::int64_t k = 0; k < n; ++k) {
      q_[index_q.data()[k]] = position.data()[k];
      v_[index_v.data()[k]] = velocity.data()[k];
    }
    if (length(tau) == 0) {
      for (std::int64_t k = 0; k < n; ++k) tau_[index_v.data()[k]] = effort.data()[k];
    } else {
      for (std::int64_t k = 0; k < nv_; ++k) tau_[k] = tau.data()[k];
      if (!va::all_finite(tau_.data(), nv_)) return 3;
    }
    nb::gil_scoped_release release;
    const double* closed = length(switches) ? switches.data() : nullptr;
    const bool ok =
        core_->update(q_.data(), v_.data(), gyro.data(), accel.data(), tau_.data(), time, closed);
    return ok ? 0 : 4;
  }

  // The estimate in Pinocchio's conventions: (q (nq), v (nv: the base's velocity in its axes,
  // the low-passed rates), {foot: probability}, {foot: in contact}, the (6, 6) covariance of
  // position and velocity (world axes)); the feet by their names.
  nb::tuple estimate() const {
    const va::EstimatorState& s = core_->state();
    const std::int64_t nf = core_->feet(), n = s.leg.n;
    std::unique_ptr<double[]> q(new double[static_cast<std::size_t>(nq_)]);
    std::unique_ptr<double[]> v(new double[static_cast<std::size_t>(nv_)]);
    std::unique_ptr<double[]> covariance(new double[36]);
    for (std::int64_t k = 0; k < nq_; ++k) q[k] = q_[k];
    for (int i = 0; i < 3; ++i) q[i] = s.leg.x[i];
    va::so3::to_quaternion(s.attitude.rotation, q.get() + 3);
    va::so3::apply_transposed(s.attitude.rotation, s.leg.x.data() + 3, v.get());
    for (std::int64_t k = 3; k < nv_; ++k) v[k] = s.rates[k];
    for (int i = 0; i < 6; ++i)
      for (int j = 0; j < 6; ++j) covariance[6 * i + j] = s.leg.P[i * n + j];
    nb::dict contact, in_contact;
    for (std::int64_t f = 0; f < nf; ++f) {
      contact[feet_[f]] = s.probability[f];
      in_contact[feet_[f]] = static_cast<bool>(s.in_contact[f]);
    }
    double* raw = covariance.release();
    nb::capsule owner(raw, [](void* p) noexcept { delete[] static_cast<double*>(p); });
    Owned2 square(raw, {6, 6}, owner);
    return nb::make_tuple(owned(std::move(q), static_cast<std::size_t>(nq_)),
                          owned(std::move(v), static_cast<std::size_t>(nv_)), contact, in_contact,
                          square);
  }

 private:
  std::unique_ptr<va::LeggedEstimatorCore> core_;
  std::int64_t nq_ = 0, nv_ = 0;
  std::vector<double> q_, v_, tau_;  // the last reading's joints, scattered
  std::vector<nb::str> feet_;        // the feet's names: the keys of estimate's dicts
};

}  // namespace

void bind_estimator(nb::module_& m) {
  nb::class_<LeggedFilter>(m, "LeggedFilter",
                           "estimation.LeggedEstimator's filter: orientation, position, velocity "
                           "and contacts from an IMU, encoders and efforts.")
      .def(nb::init<const Tree&, const I1&, std::int64_t, const I1&, const I1&, const I1&,
                    const F1&, const F2&, const F2&, const F1&, double, const F1&,
                    const std::vector<std::string>&>(),
           "tree"_a, "foot_rows"_a, "imu_row"_a, "leg_offsets"_a, "leg_columns"_a,
           "gravity_columns"_a, "masses"_a, "levers"_a, "spheres"_a, "gravity"_a,
           "weight_per_foot"_a, "tuning"_a, "feet"_a)
      .def("reset", &LeggedFilter::reset, "q_local"_a, "position"_a, "rotation"_a, "velocity"_a)
      .def("update_reading", &LeggedFilter::update_reading, "position"_a, "velocity"_a, "effort"_a,
           "index_q"_a, "index_v"_a, "gyro"_a, "accel"_a, "tau"_a, "time"_a, "gyro_range"_a,
           "accel_range"_a, "switches"_a)
      .def("estimate", &LeggedFilter::estimate);
}

}  // namespace va::py
