// Bindings of the compiled machine (plan_machine.hpp, plan_ops.hpp): control.plan lowers a
// StateMachine and a Controller into a Machine, whose tick() runs them; the registers, the
// attachments' efforts and the distribution buffers are numpy views of the Machine's memory
// (one owner: the core).
#include <nanobind/stl/optional.h>
#include <nanobind/stl/vector.h>

#include <cstdint>
#include <memory>
#include <vector>

#include "bind_common.hpp"
#include "bind_plan_qp.hpp"
#include "plan_machine.hpp"

namespace va::py {
namespace {

// A view of the machine's memory, kept alive by the machine (owner): not a copy.
using View = nb::ndarray<nb::numpy, double, nb::ndim<1>>;

using va::py::length;  // the F1 overloads, beside this file's I1 one
std::int64_t length(const I1& a) { return len(a); }

// A Machine and the Python callables its CALL ops run.
class PlanMachine {
 public:
  PlanMachine(const I2& joint_ints, const F2& joint_floats, const I1& velocity_joint,
              const F2& velocity_subspace, const I1& frame_parents, const F2& frame_floats,
              std::int64_t nq, const F1& registers, const I2& ops, const I2& bounds,
              const F1& lower, const F1& upper, const I2& unit_bounds) {
    require(joint_ints.shape(1) == 3 && joint_floats.shape(1) == 27, "bad joint tables");
    require(velocity_subspace.shape(1) == 6 && frame_floats.shape(1) == 12, "bad tables");
    require(ops.shape(1) == 5 && bounds.shape(1) == 2, "ops (k, 5) and bounds (p, 2)");
    auto tree = std::make_shared<const va::Tree>(
        copy<std::int64_t>(joint_ints), copy<double>(joint_floats),
        copy<std::int64_t>(velocity_joint), copy<double>(velocity_subspace),
        copy<std::int64_t>(frame_parents), copy<double>(frame_floats));
    const std::int64_t nv = tree->tables().nv;
    require(length(lower) == nv && length(upper) == nv, "limits must be (nv,)");
    std::vector<va::plan::Op> table(ops.shape(0));
    for (std::size_t k = 0; k < table.size(); ++k) {
      const std::int64_t* row = ops.data() + 5 * k;
      table[k] = va::plan::Op{row[0], row[1], row[2], row[3], row[4]};
    }
    const auto registers_count = static_cast<std::int64_t>(registers.shape(0));
    require(registers_count >= 5, "registers must hold the time, the time in state, the state");
    const std::vector<std::int64_t> spans = copy<std::int64_t>(bounds);
    for (std::size_t p = 0; p < spans.size(); p += 2)
      require(0 <= spans[p] && spans[p] <= spans[p + 1] &&
                  spans[p + 1] <= static_cast<std::int64_t>(table.size()),
              "program bounds out of range");
    require(unit_bounds.shape(1) == 2, "unit_bounds must be (m, 2)");
    const std::vector<std::int64_t> units = copy<std::int64_t>(unit_bounds);
    for (std::size_t s = 0; s < units.size(); s += 2)
      require(0 <= units[s] && units[s] <= units[s + 1] && units[s + 1] <= nq,
              "unit_bounds out of range");
    ops_ = table;
    machine_ =
        std::make_unique<va::plan::Machine>(tree, nq, copy<double>(registers), std::move(table),
                                            spans, copy<double>(lower), copy<double>(upper), units);
    machine_->set_callback(&PlanMachine::trampoline, this);
  }

  // A GRAVITY term's bodies: masses (njoints,), levers (njoints, 3), the model's gravity (3,).
  void set_gravity(std::int64_t index, const F1& masses, const F2& levers, const F1& gravity) {
    require(index >= 0 && index < static_cast<std::int64_t>(machine_->attachments().size()),
            "no such attachment");
    va::plan::Attachment& a = machine_->attachments()[index];
    const std::int64_t nj = machine_->joints();
    require(a.mapping == va::plan::GRAVITY, "set_gravity: the attachment does not map GRAVITY");
    require(length(masses) == nj && levers.shape(0) == masses.shape(0) && levers.shape(1) == 3 &&
                length(gravity) == 3,
            "masses (njoints,), levers (njoints, 3), gravity (3,)");
    a.floats = copy<double>(masses);
    const std::vector<double> l = copy<double>(levers), g = copy<double>(gravity);
    a.floats.insert(a.floats.end(), l.begin(), l.end());
    a.floats.insert(a.floats.end(), g.begin(), g.end());
    a.values.assign(static_cast<std::size_t>(4 * nj), 0.0);
  }

  // The bodies' masses and levers (KinematicTree.masses, .levers) for the centre-of-mass op.
  void set_masses(const F1& masses, const F2& levers) {
    require(length(masses) == machine_->joints() && levers.shape(0) == masses.shape(0) &&
                levers.shape(1) == 3,
            "masses (njoints,) and levers (njoints, 3)");
    machine_->set_masses(copy<double>(masses), copy<double>(levers));
  }

  // The callables of the CALL ops; checks every op's operands.
  void set_callbacks(nb::list callbacks) {
    callbacks_ = callbacks;
    const auto registers = static_cast<std::int64_t>(machine_->registers().size());
    for (const va::plan::Op& o : ops_)
      require(va::plan::valid(o, registers, machine_->frames(), machine_->nq(), machine_->nv(),
                              static_cast<std::int64_t>(nb::len(callbacks))),
              "an op's operand is out of range");
    checked_ = true;
  }

  std::int64_t add_state(const I1& attachments, const I1& limp, std::int64_t enter,
                         std::int64_t update) {
    va::plan::State s;
    s.attachments = copy<std::int64_t>(attachments);
    s.limp = copy<std::int64_t>(limp);
    s.enter = enter;
    s.update = update;
    for (const std::int64_t a : s.attachments)
      require(a >= 0 && a < static_cast<std::int64_t>(machine_->attachments().size()),
              "unknown attachment");
    for (const std::int64_t i : s.limp) require(i >= 0 && i < machine_->nv(), "limp index");
    require(program_or_none(enter) && program_or_none(update), "unknown program");
    machine_->states().push_back(std::move(s));
    return static_cast<std::int64_t>(machine_->states().size()) - 1;
  }

  void add_exit(std::int64_t state, std::int64_t program, std::int64_t result,
                std::int64_t target) {
    auto& states = machine_->states();
    const auto count = static_cast<std::int64_t>(states.size());
    require(state >= 0 && state < count && target >= 0 && target < count, "unknown state");
    require(program_or_none(program) && program >= 0, "unknown program");
    require(result >= 0 && result < static_cast<std::int64_t>(machine_->registers().size()),
            "result register out of range");
    states[static_cast<std::size_t>(state)].exits.push_back({program, result, target});
  }

  // A sensor of the frame table (joints false: SpringTick's tables) or of joints (q rows and
  // v columns), its registers, its components' programs and how its wrench becomes efforts.
  std::int64_t add_attachment(bool joints, const I1& axis_rows, const I1& rows, const I1& columns,
                              const F1& signs, const I1& q_rows, std::int64_t position,
                              std::int64_t velocity, std::int64_t wrench, std::int64_t produced,
                              const I1& programs, const I1& resets, std::int64_t mapping,
                              std::int64_t efforts_program) {
    va::plan::Attachment a;
    a.joints = joints;
    a.axis_rows = copy<std::int64_t>(axis_rows);
    a.rows = copy<std::int64_t>(rows);
    a.columns = copy<std::int64_t>(columns);
    a.signs = copy<double>(signs);
    a.q_rows = copy<std::int64_t>(q_rows);
    a.n = joints ? length(columns) : length(axis_rows);
    const std::int64_t nv = machine_->nv();
    require(a.n >= 1 && (joints || a.n <= 6), "an attachment has 1 to 6 axes (a posture any)");
    for (const std::int64_t c : a.columns) require(c >= 0 && c < nv, "columns out of range");
    if (joints) {
      require(length(q_rows) == a.n, "q_rows must be one per joint");
      for (const std::int64_t i : a.q_rows) require(i >= 0 && i < machine_->nq(), "q_rows");
    } else {
      require(a.rows.size() == 3 && a.signs.size() == a.columns.size(), "bad sensor tables");
      for (const std::int64_t row : a.rows)
        require(row >= 0 && row < machine_->frames(), "sensor rows outside the frame table");
      a.sensor =
          va::serial::SensorTables{a.axis_rows.data(), a.n,
                                   a.rows.data(),      a.columns.data(),
                                   a.signs.data(),     static_cast<std::int64_t>(a.columns.size())};
    }
    const auto registers = static_cast<std::int64_t>(machine_->registers().size());
    for (const std::int64_t base : {position, velocity, wrench, produced})
      require(base >= 0 && base + a.n <= registers, "register block out of range");
    a.position = position;
    a.velocity = velocity;
    a.wrench = wrench;
    a.produced = produced;
    a.programs = copy<std::int64_t>(programs);
    a.resets = copy<std::int64_t>(resets);
    for (const std::int64_t p : a.programs) require(program_or_none(p) && p >= 0, "program");
    for (const std::int64_t p : a.resets) require(program_or_none(p) && p >= 0, "program");
    require(mapping >= va::plan::SERIAL && mapping <= va::plan::GRAVITY, "unknown mapping");
    require(!(joints && mapping == va::plan::SERIAL), "a joint-space term maps JOINTS");
    a.mapping = static_cast<va::plan::Mapping>(mapping);
    require(program_or_none(efforts_program), "unknown program");
    a.efforts_program = efforts_program;
    a.jacobian.resize(static_cast<std::size_t>(a.n * std::max<std::int64_t>(a.columns.size(), 1)));
    a.efforts.resize(static_cast<std::size_t>(nv));
    machine_->attachments().push_back(std::move(a));
    return static_cast<std::int64_t>(machine_->attachments().size()) - 1;
  }

  // A PARTITIONED attachment's packed distribution tables (distribute.hpp).
  void set_distribution(std::int64_t index, const I1& ints, const F1& floats) {
    va::plan::Attachment& a = attachment(index);
    a.ints = copy<std::int64_t>(ints);
    a.floats = copy<double>(floats);
    a.packed = va::Packed::checked(a.ints, a.floats, machine_->nv());
    require(a.packed.n == a.n, "the distribution's axes must be the sensor's");
    require(a.packed.max_frame_row() < machine_->frames(), "distribution rows outside the table");
    require(a.packed.max_q_index() < machine_->nq(), "distribution q index out of range");
    a.out.assign(static_cast<std::size_t>(a.packed.out_size(machine_->nv())), 0.0);
    a.base_out = a.out;
  }

  // Its yield policy's tables (contact_limits.enforce_unilateral's compiled margins).
  void set_yield(std::int64_t index, const I1& mask, const I1& orientation_rows, const F2& points,
                 const I1& axis_rows, const I1& minima_axes, const F1& lows) {
    va::plan::Attachment& a = attachment(index);
    require(!a.out.empty(), "set the distribution first");
    require(length(mask) == a.n && points.shape(1) == 7, "bad yield tables");
    a.yields = true;
    a.yield = va::plan::Yield{copy<std::int64_t>(mask),
                              copy<std::int64_t>(orientation_rows),
                              copy<std::int64_t>(axis_rows),
                              copy<std::int64_t>(minima_axes),
                              copy<double>(points),
                              copy<double>(lows),
                              static_cast<std::int64_t>(points.shape(0))};
    for (const std::int64_t row : a.yield.orientation_rows)
      require(row >= 0 && row < machine_->frames(), "orientation rows outside the table");
    a.values.assign(a.yield.lows.size(), 0.0);
    a.at_base = a.values;
  }

  // A parallel attachment's QP (its Python piece runs the ticks the core does not decide).
  void set_qp(std::int64_t index, const QP& qp, const F1& q, MF1 buffer, const I1& layout,
              const I1& kept, const I1& keep, const F1& weights, const F1& tolerances) {
    va::plan::Attachment& a = attachment(index);
    require(a.mapping == va::plan::SOLVER, "the attachment does not map through a solver");
    require(qp.n() == a.n && qp.max_frame_row() < machine_->frames(), "the QP's axes and rows");
    auto solver = std::make_shared<QPSolver>(qp, q, buffer, layout, kept, keep, weights, tolerances,
                                             machine_->nv());
    solvers_.resize(machine_->attachments().size());
    solvers_[static_cast<std::size_t>(index)] = solver;
    a.solver = solver;
  }
  void set_guess(std::int64_t index, std::optional<MF1> guess) { qp(index).set_guess(guess); }
  // (out, active, count, norms) of the QP attachment's last tick (out and active: views)
  nb::tuple qp_answer(nb::handle self, std::int64_t index) {
    QPSolver& s = qp(index);
    nb::tuple counts = s.answer();
    const View out(s.out().data(), {s.out().size()}, self);
    using IView = nb::ndarray<nb::numpy, std::int64_t, nb::ndim<1>>;
    const IView active(s.active().data(), {s.active().size()}, self);
    return nb::make_tuple(out, active, counts[0], counts[1]);
  }

  std::int64_t tick(const F1& q, const F1& v, double time, MF1 tau) {
    require(checked_, "set_callbacks() before the first tick");
    require(length(q) == machine_->nq() && length(v) == machine_->nv(), "q (nq,), v (nv,)");
    require(static_cast<std::int64_t>(tau.shape(0)) == machine_->nv(), "tau must be (nv,)");
    return machine_->tick(q.data(), v.data(), time, tau.data());
  }

  View registers(nb::handle self) {
    return view(machine_->registers().data(), machine_->registers().size(), self);
  }
  View efforts(nb::handle self, std::int64_t index) {
    auto& a = attachment(index);
    return view(a.efforts.data(), a.efforts.size(), self);
  }
  View out(nb::handle self, std::int64_t index) {
    auto& a = attachment(index);
    require(!a.out.empty(), "not a partitioned attachment");
    return view(a.out.data(), a.out.size(), self);
  }
  View jacobian(nb::handle self, std::int64_t index) {
    auto& a = attachment(index);
    return view(a.jacobian.data(), a.jacobian.size(), self);
  }
  View requested(nb::handle self) {
    auto& tau = const_cast<std::vector<double>&>(machine_->requested());
    return view(tau.data(), tau.size(), self);
  }
  View pass(nb::handle self) {
    auto& buffer = const_cast<std::vector<double>&>(machine_->pass());
    return view(buffer.data(), buffer.size(), self);
  }
  // (residual, scale, rounding, status) of the attachment's last distribution
  nb::tuple solved(std::int64_t index) {
    const va::Distributed& d = attachment(index).solved;
    return nb::make_tuple(d.residual, d.scale, d.rounding, d.status);
  }
  std::int64_t state() const { return machine_->state(); }
  void set_initial(std::int64_t state) {
    require(state >= 0 && state < static_cast<std::int64_t>(machine_->states().size()),
            "unknown state");
    machine_->set_initial(state);
  }

 private:
  static int trampoline(void* owner, std::int64_t index) {
    auto* self = static_cast<PlanMachine*>(owner);
    nb::object result = self->callbacks_[static_cast<std::size_t>(index)]();
    return result.is_none() || nb::cast<bool>(result) ? 0 : 1;  // False: the piece failed
  }

  bool program_or_none(std::int64_t p) const { return p >= -1 && p < machine_->programs(); }

  va::plan::Attachment& attachment(std::int64_t index) {
    require(index >= 0 && index < static_cast<std::int64_t>(machine_->attachments().size()),
            "unknown attachment");
    return machine_->attachments()[static_cast<std::size_t>(index)];
  }

  static View view(double* data, std::size_t size, nb::handle owner) {
    return View(data, {size}, owner);
  }

  QPSolver& qp(std::int64_t index) {
    attachment(index);
    require(static_cast<std::size_t>(index) < solvers_.size() && solvers_[index] != nullptr,
            "not a QP attachment");
    return *solvers_[static_cast<std::size_t>(index)];
  }

  std::unique_ptr<va::plan::Machine> machine_;
  std::vector<std::shared_ptr<QPSolver>> solvers_;
  std::vector<va::plan::Op> ops_;
  nb::list callbacks_;
  bool checked_ = false;
};

}  // namespace

void bind_plan(nb::module_& m) {
  nb::dict codes;
  std::int64_t code = 0;
#define VA_PLAN_NAME(symbol, name) codes[name] = code++;
  VA_PLAN_OPS(VA_PLAN_NAME)
#undef VA_PLAN_NAME
  m.attr("PLAN_OPS") = codes;
  nb::class_<PlanMachine>(m, "PlanMachine",
                          "A lowered StateMachine and Controller (control.plan): one tick per "
                          "call; registers and buffers are views of its memory.")
      .def(nb::init<const I2&, const F2&, const I1&, const F2&, const I1&, const F2&, std::int64_t,
                    const F1&, const I2&, const I2&, const F1&, const F1&, const I2&>(),
           "joint_ints"_a, "joint_floats"_a, "velocity_joint"_a, "velocity_subspace"_a,
           "frame_parents"_a, "frame_floats"_a, "nq"_a, "registers"_a, "ops"_a, "bounds"_a,
           "lower"_a, "upper"_a, "unit_bounds"_a)
      .def("set_callbacks", &PlanMachine::set_callbacks, "callbacks"_a)
      .def("add_state", &PlanMachine::add_state, "attachments"_a, "limp"_a, "enter"_a, "update"_a)
      .def("add_exit", &PlanMachine::add_exit, "state"_a, "program"_a, "result"_a, "target"_a)
      .def("add_attachment", &PlanMachine::add_attachment, "joints"_a, "axis_rows"_a, "rows"_a,
           "columns"_a, "signs"_a, "q_rows"_a, "position"_a, "velocity"_a, "wrench"_a, "produced"_a,
           "programs"_a, "resets"_a, "mapping"_a, "efforts_program"_a)
      .def("set_distribution", &PlanMachine::set_distribution, "index"_a, "ints"_a, "floats"_a)
      .def("set_qp", &PlanMachine::set_qp, "index"_a, "qp"_a, "q"_a, "buffer"_a.noconvert(),
           "layout"_a, "kept"_a, "keep"_a, "weights"_a, "tolerances"_a, nb::keep_alive<1, 3>())
      .def("set_guess", &PlanMachine::set_guess, "index"_a, "guess"_a.noconvert().none())
      .def(
          "qp_answer",
          [](nb::handle self, std::int64_t i) {
            return nb::cast<PlanMachine&>(self).qp_answer(self, i);
          },
          "index"_a)
      .def("set_yield", &PlanMachine::set_yield, "index"_a, "mask"_a, "orientation_rows"_a,
           "points"_a, "axis_rows"_a, "minima_axes"_a, "lows"_a)
      .def("tick", &PlanMachine::tick, "q"_a, "v"_a, "time"_a, "tau"_a.noconvert())
      .def("registers",
           [](nb::handle self) { return nb::cast<PlanMachine&>(self).registers(self); })
      .def(
          "efforts",
          [](nb::handle self, std::int64_t i) {
            return nb::cast<PlanMachine&>(self).efforts(self, i);
          },
          "index"_a)
      .def(
          "out",
          [](nb::handle self, std::int64_t i) { return nb::cast<PlanMachine&>(self).out(self, i); },
          "index"_a)
      .def(
          "jacobian",
          [](nb::handle self, std::int64_t i) {
            return nb::cast<PlanMachine&>(self).jacobian(self, i);
          },
          "index"_a)
      .def("requested",
           [](nb::handle self) { return nb::cast<PlanMachine&>(self).requested(self); })
      .def("pass_buffer", [](nb::handle self) { return nb::cast<PlanMachine&>(self).pass(self); })
      .def("solved", &PlanMachine::solved, "index"_a)
      .def("set_initial", &PlanMachine::set_initial, "state"_a)
      .def("set_masses", &PlanMachine::set_masses, "masses"_a, "levers"_a)
      .def("set_gravity", &PlanMachine::set_gravity, "index"_a, "masses"_a, "levers"_a, "gravity"_a)
      .def_prop_ro("state", &PlanMachine::state);
  m.attr("PLAN_TICKED") = static_cast<std::int64_t>(va::plan::TICKED);
  m.attr("PLAN_ENTERED") = static_cast<std::int64_t>(va::plan::ENTERED);
  m.attr("PLAN_FAILED") = static_cast<std::int64_t>(va::plan::FAILED);
  m.attr("PLAN_INVALID") = static_cast<std::int64_t>(va::plan::INVALID);
}

}  // namespace va::py
