// The hexapod's native tick, bound in bind_native_hexapod.cpp. NativeHexapod holds what a
// HexapodWalker's declaration fixes (the kinematic tree, the support attachments' sensors and QP
// workspaces, the swing legs' SpringTick, the states' attachments and limp joints, the effort
// limits) and the gait's memory; tick() runs the kinematics pass, the state machine and its
// callbacks (hexapod_tick.hpp), every active attachment (the body's components and its QP on the
// last certified active set, the swing legs' spring-dampers), the sums, the limp joints and the
// clipping: Gait.compute's arithmetic, bit for bit (gaits/hexapod/native.py,
// tests/test_native_hexapod.py). It answers DEFER, committing nothing, for a tick it does not
// decide (a tripod's entry, a QP whose active set changed, a value not finite).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "bind_attachment.hpp"
#include "bind_common.hpp"
#include "bind_gait_efforts.hpp"
#include "bind_kinematics.hpp"
#include "bind_qp.hpp"
#include "hexapod_tick.hpp"
#include "kinematics.hpp"
#include "sensor.hpp"

namespace va::py {

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
    parameters_ =
        va::hexapod::Parameters{p[0], p[1], p[2], p[3], p[4], nominal_.data(), shape_.data()};
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
    a.tables = va::serial::SensorTables{a.axis_rows.data(),   6,
                                        a.sensor_rows.data(), a.columns.data(),
                                        a.signs.data(),       len(columns)};
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
    body_ = va::hexapod::Body{b[0],         b[1],         b[2],         b[3],
                              {b[4], b[5]}, {b[6], b[7]}, {b[8], b[9]}, {b[10], b[11], b[12]},
                              b[13],        b[14]};
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
  std::int64_t tick(
      const F1& q, const F1& v, double time, const F1& command, const I1& contacts, const MF1& tau,
      const nb::ndarray<double, nb::numpy, nb::ndim<2>, nb::c_contig, nb::device::cpu>& readings) {
    require(length(q) == nq_ && length(v) == nv_ && length(tau) == nv_,
            "q must be (nq,), v and tau (nv,)");
    require(length(command) == 3, "command: vx, vy, yaw rate");
    require(len(contacts) == 0 || len(contacts) == 6, "contacts: six switches or none");
    require(static_cast<std::int64_t>(readings.shape(0)) ==
                    static_cast<std::int64_t>(attachments_.size()) &&
                readings.shape(1) == 18,
            "readings must be (attachments, 18)");
    require(efforts_.states() == 4, "the four states must be declared");
    const va::hexapod::Inputs in{{command.data()[0], command.data()[1]},
                                 command.data()[2],
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
        jw, frames, q, a.wrench, a.kept.data(), static_cast<std::int64_t>(a.kept.size()), *a.views,
        a.buffer, a.buffer_size, a.layout.data(), a.keep.data(), a.weights.data(), a.guess,
        tolerances_[0], tolerances_[1], tolerances_[2], a.out.data(), a.active.data(), a.z,
        a.multipliers, d);
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

}  // namespace va::py
