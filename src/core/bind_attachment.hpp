// The spring-damper attachments' Python objects (attachment.hpp): SpringTick holds a sensor's
// tables and its spring-dampers' entries, and tick() runs attachment_kernel.spring_tick;
// SpringSolve adds a parallel actuator's distribution. Bound in bind_attachment.cpp.
#pragma once

#include <algorithm>
#include <cstdint>
#include <memory>
#include <vector>

#include "attachment.hpp"
#include "bind_common.hpp"
#include "distribute.hpp"
#include "sensor.hpp"
#include "tables.hpp"

namespace va::py {

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
      require(
          axis_rows_[i] >= 0 && axis_rows_[i] < 6 && (i == 0 || axis_rows_[i - 1] < axis_rows_[i]),
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
                                       signs_.data(),     m};
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
    require(
        jacobian_world.shape(0) == 6 && static_cast<std::int64_t>(jacobian_world.shape(1)) == nv_,
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
        require(length(parameters[c + k]) == size, "a component's parameters must be one per axis");
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
    return va::serial::spring_tick(jacobian_world.data(), nv_, frames.data(), v.data(), tables_, p,
                                   jacobian.data(), out);
  }

  std::int64_t size() const { return nv_ + 3 * tables_.n + 1; }
  std::int64_t nv() const { return nv_; }
  std::int64_t n() const { return tables_.n; }
  bool efforts() const { return efforts_; }

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

  // tick()'s status when nothing was distributed
  static constexpr std::int64_t NOT_RUN = -1;

 private:
  const SpringTick* spring_;  // kept alive by the binding (keep_alive)
  std::vector<std::int64_t> ints_;
  std::vector<double> floats_;
  va::Packed packed_;
};

}  // namespace va::py
