// The compiled machine: a lowered StateMachine and Controller run as one tick.
//
// What a declaration fixes is data here: the states (their attachments, limp joints, entry and
// update programs, exits), the attachments (their sensor, the programs of their components and
// how their wrench becomes efforts), the registers and the ops (plan_ops.hpp). A tick is
// MachineController.compute's order: the kinematics pass, at most one transition (its target's
// entry program), the state's update program, the components' resets of a state just entered,
// every active attachment, the sum, the limp joints and the clip.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <vector>

#include "attachment.hpp"
#include "contact_rows.hpp"
#include "distribute.hpp"
#include "gravity.hpp"
#include "kinematics.hpp"
#include "plan_ops.hpp"

namespace va::plan {

// A parallel attachment's distribution run by an object the bindings give (the QP on its last
// certified active set): the efforts and the produced wrench of a wrench, or false (the
// attachment's Python piece decides that tick).
class Solver {
 public:
  virtual ~Solver() = default;
  virtual bool solve(const double* jacobian_world, const double* frames, const double* q,
                     const double* wrench, double* tau, double* produced) = 0;
};

// How an attachment's wrench becomes efforts.
enum Mapping : std::int64_t {
  SERIAL = 0,       // J^T w over the sensor's chain
  PARTITIONED = 1,  // the parallel actuator's packed distribution
  JOINTS = 2,       // a joint-space term: the wrench is the efforts of its joints
  PYTHON = 3,       // a Python piece (the program `efforts_program`) writes the efforts
  SOLVER = 4,       // the attachment's Solver, else its Python piece
  GRAVITY = 5,      // generalized gravity on the columns (floats: masses, levers, gravity)
};

struct Yield {  // contact_limits.enforce_unilateral's tables (a partitioned attachment)
  std::vector<std::int64_t> mask, orientation_rows, axis_rows, minima_axes;
  std::vector<double> points, lows;
  std::int64_t np = 0;
};

struct Attachment {
  // sensing: a serial sensor of the frame table, or joints (q rows, v columns)
  bool joints = false;
  std::vector<std::int64_t> axis_rows, rows, columns, q_rows;
  std::vector<double> signs;
  serial::SensorTables sensor{};
  std::int64_t n = 0, position = 0, velocity = 0, wrench = 0, produced = 0;
  std::vector<std::int64_t> programs, resets;  // the components' wrench and reset programs
  Mapping mapping = SERIAL;
  std::int64_t efforts_program = -1;  // PYTHON: the piece that writes `efforts`
  std::vector<std::int64_t> ints;
  std::vector<double> floats;
  Packed packed{};
  bool yields = false;
  Yield yield;
  std::shared_ptr<Solver> solver;
  // per tick
  std::vector<double> jacobian, efforts, out, base_out, values, at_base;
  Distributed solved{};  // the last distribution's norms and status (0: solved)
};

struct Transition {
  std::int64_t program, result, target;
};

struct State {
  std::vector<std::int64_t> attachments, limp;
  std::int64_t enter = -1, update = -1;
  std::vector<Transition> exits;
};

// The registers every plan has: the tick's time, the time in the current state, the machine's
// state (its index, when it was entered, whether the machine started).
enum Register : std::int64_t {
  TIME = 0,
  TIME_IN_STATE = 1,
  STATE = 2,
  ENTERED_AT = 3,
  STARTED = 4
};

// The tick's outcome. FAILED and INVALID leave the registers as they were before the tick.
enum Outcome : std::int64_t { TICKED = 0, ENTERED = 1, FAILED = 2, INVALID = 3 };

class Machine {
 public:
  Machine(std::shared_ptr<const Tree> tree, std::int64_t nq, std::vector<double> registers,
          std::vector<Op> ops, std::vector<std::int64_t> bounds, std::vector<double> lower,
          std::vector<double> upper, std::vector<std::int64_t> unit_bounds)
      : tree_(std::move(tree)),
        nq_(nq),
        nv_(tree_->tables().nv),
        registers_(std::move(registers)),
        ops_(std::move(ops)),
        bounds_(std::move(bounds)),
        lower_(std::move(lower)),
        upper_(std::move(upper)),
        unit_bounds_(std::move(unit_bounds)) {
    pass_.resize(static_cast<std::size_t>(tree_->size(true)));
    tau_.resize(static_cast<std::size_t>(nv_));
    backup_ = registers_;
  }

  std::vector<double>& registers() { return registers_; }
  std::vector<Attachment>& attachments() { return attachments_; }
  std::vector<State>& states() { return states_; }
  const std::vector<double>& pass() const { return pass_; }
  std::int64_t nv() const { return nv_; }
  std::int64_t nq() const { return nq_; }
  std::int64_t frames() const { return tree_->tables().nf; }
  std::int64_t joints() const { return tree_->tables().njoints; }
  std::int64_t programs() const { return static_cast<std::int64_t>(bounds_.size() / 2); }
  // The machine's state lives in registers 2, 3 and 4 (the state's index, when it was entered,
  // whether the machine started): StateMachine reads them there (one owner).
  std::int64_t state() const { return static_cast<std::int64_t>(registers_[STATE]); }
  void set_initial(std::int64_t state) { initial_ = state; }
  // The bodies' masses (njoints) and centres of mass in their joints' frames (njoints, 3), for
  // the centre-of-mass op.
  void set_masses(std::vector<double> masses, std::vector<double> levers) {
    masses_ = std::move(masses);
    levers_ = std::move(levers);
  }
  void set_callback(Callback callback, void* owner) {
    callback_ = callback;
    owner_ = owner;
  }

  // One tick: tau_out (nv) the clipped efforts. `contacts`: the switches' registers already
  // written by the caller. FAILED: a piece failed (a non-finite sum, a distribution the core
  // does not decide left to Python by its program); nothing is committed but the registers.
  Outcome tick(const double* q, const double* v, double time, double* tau_out) {
    // what KinematicTree's checks accept unchanged: finite, unit groups within 1e-12 of 1
    const double error = unit_norm_error(q, nq_, unit_bounds_.data(),
                                         static_cast<std::int64_t>(unit_bounds_.size() / 2));
    if (!(0.0 <= error && error <= 1e-12) || !all_finite(v, nv_) || !std::isfinite(time))
      return INVALID;
    std::copy(registers_.begin(), registers_.end(), backup_.begin());
    const Outcome outcome = run_tick(q, v, time, tau_out);
    if (outcome == FAILED) std::copy(backup_.begin(), backup_.end(), registers_.begin());
    return outcome;
  }

  // The unclipped sum of the last tick (Controller's tau_requested).
  const std::vector<double>& requested() const { return tau_; }

 private:
  Outcome run_tick(const double* q, const double* v, double time, double* tau_out) {
    tree_->compute(q, v, pass_.data());
    Inputs in;
    in.frames = pass_.data() + tree_->frames_offset();
    in.velocities = in.frames + 12 * tree_->tables().nf;
    in.q = q;
    in.v = v;
    in.joints = pass_.data();
    in.njoints = tree_->tables().njoints;
    if (!masses_.empty()) {
      in.masses = masses_.data();
      in.levers = levers_.data();
    }
    double* r = registers_.data();
    r[TIME] = time;
    bool entered = false;
    if (r[STARTED] == 0.0) {
      r[STARTED] = 1.0;
      if (!enter(initial_, time, in, r)) return FAILED;
      entered = true;
    }
    r[TIME_IN_STATE] = time - r[ENTERED_AT];
    const State& current = states_[static_cast<std::size_t>(r[STATE])];
    for (const Transition& exit : current.exits) {
      if (!program(exit.program, in, r)) return FAILED;
      if (r[exit.result] != 0.0) {
        if (!enter(exit.target, time, in, r)) return FAILED;
        entered = true;
        break;
      }
    }
    const State& state = states_[static_cast<std::size_t>(r[STATE])];
    if (state.update >= 0 && !program(state.update, in, r)) return FAILED;
    const double* jw = pass_.data() + tree_->jacobian_offset();
    if (entered) {  // Controller.reset: each component's reset, on its sensor's reading
      for (const std::int64_t index : state.attachments) {
        Attachment& a = attachments_[static_cast<std::size_t>(index)];
        if (a.resets.empty()) continue;
        sense(a, jw, in, r);
        for (const std::int64_t p : a.resets)
          if (!program(p, in, r)) return FAILED;
      }
    }
    bool first = true;
    for (const std::int64_t index : state.attachments) {
      Attachment& a = attachments_[static_cast<std::size_t>(index)];
      if (!run(a, jw, in, r)) return FAILED;
      for (std::int64_t i = 0; i < nv_; ++i)
        tau_[i] = first ? a.efforts[i] : tau_[i] + a.efforts[i];
      first = false;
    }
    if (first) std::fill(tau_.begin(), tau_.end(), 0.0);
    if (!all_finite(tau_.data(), nv_)) return FAILED;
    for (const std::int64_t i : state.limp) tau_[i] = 0.0;
    for (std::int64_t i = 0; i < nv_; ++i) {  // np.minimum(np.maximum(tau, lower), upper)
      const double low = tau_[i] < lower_[i] ? lower_[i] : tau_[i];
      tau_out[i] = low > upper_[i] ? upper_[i] : low;
    }
    return entered ? ENTERED : TICKED;
  }

  bool program(std::int64_t index, const Inputs& in, double* r) {
    const std::int64_t start = bounds_[2 * index], stop = bounds_[2 * index + 1];
    return va::plan::run(ops_.data(), start, stop, r, in, callback_, owner_);
  }

  bool enter(std::int64_t target, double time, const Inputs& in, double* r) {
    r[STATE] = static_cast<double>(target);
    r[ENTERED_AT] = time;
    r[TIME_IN_STATE] = 0.0;
    const State& s = states_[static_cast<std::size_t>(target)];
    return s.enter < 0 || program(s.enter, in, r);
  }

  void sense(Attachment& a, const double* jw, const Inputs& in, double* r) {
    if (a.joints) {
      for (std::int64_t i = 0; i < a.n; ++i) {
        r[a.position + i] = in.q[a.q_rows[i]];
        r[a.velocity + i] = in.v[a.columns[i]];
      }
      return;
    }
    double position[6], velocity[6];
    serial::relative_sensor(jw, nv_, in.frames, in.v, a.sensor, a.jacobian.data(), position,
                            velocity);
    for (std::int64_t i = 0; i < a.n; ++i) {
      r[a.position + i] = position[i];
      r[a.velocity + i] = velocity[i];
    }
  }

  bool run(Attachment& a, const double* jw, const Inputs& in, double* r) {
    sense(a, jw, in, r);
    for (std::int64_t i = 0; i < a.n; ++i) r[a.wrench + i] = 0.0;
    for (const std::int64_t p : a.programs)
      if (!program(p, in, r)) return false;
    const double* wrench = r + a.wrench;
    std::fill(a.efforts.begin(), a.efforts.end(), 0.0);
    switch (a.mapping) {
      case SERIAL:
        for (std::int64_t j = 0; j < a.sensor.m; ++j) {
          double acc = 0.0;
          for (std::int64_t i = 0; i < a.n; ++i) acc += a.jacobian[j * a.n + i] * wrench[i];
          a.efforts[a.columns[j]] = acc;
        }
        for (std::int64_t i = 0; i < a.n; ++i) r[a.produced + i] = wrench[i];
        return true;
      case JOINTS:
        for (std::int64_t i = 0; i < a.n; ++i) {
          a.efforts[a.columns[i]] = wrench[i];
          r[a.produced + i] = wrench[i];
        }
        return true;
      case PARTITIONED:
        if (distribute_partitioned(a, jw, in, r)) return true;
        [[fallthrough]];  // a tick the core does not decide: the Python piece, if any
      case SOLVER:
        if (a.mapping == SOLVER && a.solver != nullptr &&
            a.solver->solve(jw, in.frames, in.q, wrench, a.efforts.data(), r + a.produced))
          return true;
        [[fallthrough]];
      case PYTHON: return a.efforts_program >= 0 && program(a.efforts_program, in, r);
      case GRAVITY: {
        const std::int64_t nj = tree_->tables().njoints;
        if (a.floats.size() != static_cast<std::size_t>(4 * nj + 3)) return false;  // no bodies
        const double* f = a.floats.data();
        generalized_gravity(tree_->tables(), in.joints, jw, f, f + nj, f + 4 * nj, a.columns.data(),
                            a.n, a.values.data(), a.efforts.data());
        for (std::int64_t i = 0; i < a.n; ++i) r[a.produced + i] = a.efforts[a.columns[i]];
        return true;
      }
    }
    return false;
  }

  bool distribute_partitioned(Attachment& a, const double* jw, const Inputs& in, double* r) {
    std::fill(a.out.begin(), a.out.end(), 0.0);
    const Distributed d =
        distribute(jw, nv_, in.frames, in.q, r + a.wrench, a.packed, a.out.data());
    a.solved = d;
    if (d.status != 0) return false;
    const std::int64_t pn = a.packed.p * a.n;
    const double* tau = a.out.data() + pn;
    const double* produced = a.out.data() + pn + 2 * nv_;
    if (a.yields && !enforce_yield(a, jw, in, r, tau, produced)) return false;
    if (!a.yields || tau != nullptr) {
      std::copy(tau, tau + nv_, a.efforts.begin());
      for (std::int64_t i = 0; i < a.n; ++i) r[a.produced + i] = produced[i];
    }
    return true;
  }

  // contact_limits.enforce_unilateral: the request scaled on the yield axes when a contact row
  // would break (the solution of base + alpha (wrench - base), interpolated between the two).
  bool enforce_yield(Attachment& a, const double* jw, const Inputs& in, double* r,
                     const double*& tau, const double*& produced) {
    const Yield& y = a.yield;
    const std::int64_t n = a.n, p = a.packed.p;
    const auto rows = static_cast<std::int64_t>(y.lows.size());
    const auto minima = static_cast<std::int64_t>(y.minima_axes.size());
    contact_margins(in.frames, y.orientation_rows.data(), a.out.data(), p, n, y.points.data(), y.np,
                    y.axis_rows.data(), y.minima_axes.data(), minima, a.values.data());
    const double least = contact_least_margin(a.values.data(), y.lows.data(), rows);
    if (least >= -1e-9) return true;  // the usual tick: nothing to scale
    if (std::isnan(least)) return false;
    double base[6];
    const double* wrench = r + a.wrench;
    for (std::int64_t i = 0; i < n; ++i) base[i] = y.mask[i] ? 0.0 : wrench[i];
    std::fill(a.base_out.begin(), a.base_out.end(), 0.0);
    if (distribute(jw, nv_, in.frames, in.q, base, a.packed, a.base_out.data()).status != 0)
      return false;
    contact_margins(in.frames, y.orientation_rows.data(), a.base_out.data(), p, n, y.points.data(),
                    y.np, y.axis_rows.data(), y.minima_axes.data(), minima, a.at_base.data());
    const double alpha =
        contact_largest_scale(a.values.data(), a.at_base.data(), y.lows.data(), rows);
    const double* start = a.base_out.data() + p * n;
    const double* start_produced = a.base_out.data() + p * n + 2 * nv_;
    if (alpha <= 0.0) {
      tau = start;
      produced = start_produced;
      return true;
    }
    for (std::int64_t i = 0; i < nv_; ++i)  // contact_limits.interpolate
      a.efforts[i] = start[i] + alpha * (tau[i] - start[i]);
    for (std::int64_t i = 0; i < n; ++i)
      r[a.produced + i] = start_produced[i] + alpha * (produced[i] - start_produced[i]);
    tau = nullptr;  // written already
    return true;
  }

  std::shared_ptr<const Tree> tree_;
  std::int64_t nq_, nv_;
  std::vector<double> registers_;
  std::vector<Op> ops_;
  std::vector<std::int64_t> bounds_;
  std::vector<double> lower_, upper_;
  std::vector<std::int64_t> unit_bounds_;  // (m, 2) flat: [start, stop) of each unit group
  std::vector<double> backup_;             // the registers before the tick running
  std::vector<Attachment> attachments_;
  std::vector<State> states_;
  std::vector<double> pass_, tau_, masses_, levers_;
  std::int64_t initial_ = 0;
  Callback callback_ = nullptr;
  void* owner_ = nullptr;
};

}  // namespace va::plan
