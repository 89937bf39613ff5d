// What the hexapod's native tick (bind_native_hexapod.cpp) does after its
// attachments: GaitEfforts.
#pragma once

#include <cstdint>
#include <vector>

#include "bind_common.hpp"
#include "kinematics.hpp"

namespace va::py {

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
      require(attachments.data()[k] >= 0 && attachments.data()[k] < count, "unknown attachment");
    for (std::int64_t k = 0; k < len(limp); ++k)
      require(limp.data()[k] >= 0 && limp.data()[k] < nv_, "limp index out of range");
    require(len(attachments) >= 1, "a state runs at least one attachment");
    states_.push_back(State{copy<std::int64_t>(attachments), copy<std::int64_t>(limp)});
  }

  const State& state(std::int64_t index) const { return states_[static_cast<std::size_t>(index)]; }
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

}  // namespace va::py
