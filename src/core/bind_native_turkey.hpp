// The native turkey (turkey.hpp): a whole gait tick in one call, bound in bind_native_turkey.cpp.
// NativeTurkey holds what a TurkeyWalker's declaration fixes (the kinematic tree, its attachments'
// SpringTick and SpringSolve, the states' attachments and limp joints, the effort limits) and the
// gait's memory; tick() runs the kinematics pass, the state machine and its callbacks, the
// components' resets, every active attachment, the sums, the limp joints and the clipping:
// Gait.compute's arithmetic, bit for bit (gaits/turkey/native.py, tests/test_native_turkey.py).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <vector>

#include "bind_attachment.hpp"
#include "bind_common.hpp"
#include "bind_gait_efforts.hpp"
#include "bind_kinematics.hpp"
#include "contact_rows.hpp"
#include "distribute.hpp"
#include "kinematics.hpp"
#include "turkey.hpp"

namespace va::py {

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
                              const I1& orientation_rows, const F2& points, const I1& axis_rows,
                              const I1& minima_axes, const F1& lows) {
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
        require(orientation_rows.data()[r] >= 0 && orientation_rows.data()[r] < tree_->tables().nf,
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
    const double values[MEMORY] = {static_cast<double>(m.state),
                                   m.entered_at,
                                   static_cast<double>(m.front),
                                   m.swing_start[0],
                                   m.swing_start[1],
                                   m.progress_start,
                                   m.ground,
                                   m.granny_height,
                                   bunny_position_,
                                   bunny_time_,
                                   m.swing_setpoint[0][0],
                                   m.swing_setpoint[0][1],
                                   m.swing_setpoint[1][0],
                                   m.swing_setpoint[1][1],
                                   bunny_setpoint_};
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
  std::int64_t tick(
      const F1& q, const F1& v, double time, const MF1& tau,
      const nb::ndarray<double, nb::numpy, nb::ndim<2>, nb::c_contig, nb::device::cpu>& readings) {
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
        case GRANNY: setpoint[0] = m.granny_height; break;
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
        default: break;
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
    va::contact_margins(frames, a.orientation_rows.data(), a.fallback.data(), p, n, a.points.data(),
                        a.np, a.axis_rows.data(), a.minima_axes.data(), minima, a.at_base.data());
    const double alpha =
        va::contact_largest_scale(a.values.data(), a.at_base.data(), a.lows.data(), rows);
    const double* start = a.fallback.data() + p * n;
    if (alpha <= 0.0) return start;
    for (std::int64_t i = 0; i < nv_; ++i)  // contact_limits.interpolate's tau
      a.scaled[i] = start[i] + alpha * (tau[i] - start[i]);
    return a.scaled.data();
  }

  std::int64_t run(const double* q, const double* v, double time, double* tau_out,
                   double* readings) {
    if (!va::all_finite(q, nq_) || !va::all_finite(v, nv_) || !std::isfinite(time)) return DEFER;
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

}  // namespace va::py
