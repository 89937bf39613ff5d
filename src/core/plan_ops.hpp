// The plan's ops: the straight-line programs a lowered declaration runs every tick.
//
// A program is a run of ops over one array of registers (the plan's blackboard). Each op reads
// registers (or, for the reads of the tick's kinematics, immediates: a frame row and a column)
// and writes one register. The arithmetic is Python's on floats, operation by operation: the
// C library's functions (those CPython's math calls), Python's min and max (scalar.hpp: the
// first operand unless the second is strictly smaller / larger), comparisons giving 1.0 or 0.0.
// The names are exported to Python (_core.PLAN_OPS), which the lowering reads: the table exists
// once, here.
#pragma once

#include <cmath>
#include <cstdint>

#include "gait.hpp"
#include "scalar.hpp"

namespace va::plan {

#define VA_PLAN_OPS(X)                                                                             \
  X(COPY, "copy")                                                                                  \
  X(STORE, "store")                                                                                \
  X(ADD, "add")                                                                                    \
  X(SUB, "sub")                                                                                    \
  X(MUL, "mul")                                                                                    \
  X(DIV, "div")                                                                                    \
  X(NEG, "neg")                                                                                    \
  X(ABS, "abs")                                                                                    \
  X(SQRT, "sqrt")                                                                                  \
  X(SIN, "sin")                                                                                    \
  X(COS, "cos")                                                                                    \
  X(TAN, "tan")                                                                                    \
  X(ASIN, "asin")                                                                                  \
  X(ACOS, "acos")                                                                                  \
  X(EXP, "exp")                                                                                    \
  X(ATAN2, "atan2")                                                                                \
  X(HYPOT, "hypot")                                                                                \
  X(REMAINDER, "remainder")                                                                        \
  X(MIN, "min")                                                                                    \
  X(MAX, "max")                                                                                    \
  X(LT, "lt")                                                                                      \
  X(LE, "le")                                                                                      \
  X(EQ, "eq")                                                                                      \
  X(NE, "ne")                                                                                      \
  X(NOT, "not")                                                                                    \
  X(AND, "and")                                                                                    \
  X(OR, "or")                                                                                      \
  X(SELECT, "select")                                                                              \
  X(FRAME, "frame")                                                                                \
  X(FRAME_VELOCITY, "frame_velocity")                                                              \
  X(Q, "q")                                                                                        \
  X(V, "v")                                                                                        \
  X(COM, "center_of_mass")                                                                         \
  X(CALL, "call")

enum Code : std::int64_t {
#define VA_PLAN_ENUM(code, name) code,
  VA_PLAN_OPS(VA_PLAN_ENUM)
#undef VA_PLAN_ENUM
      OP_COUNT
};

// code, out, a, b, c: one row of the ops table.
struct Op {
  std::int64_t code, out, a, b, c;
};

// What a program reads besides its registers: the tick's kinematics pass and state.
struct Inputs {
  const double* frames = nullptr;      // (nf, 12): rotation row by row, then position
  const double* velocities = nullptr;  // (nf, 3): the frames' origins' linear velocities
  const double* q = nullptr;
  const double* v = nullptr;
  const double* joints = nullptr;  // (njoints, 12): the joints' placements
  const double* masses = nullptr;  // (njoints,): each joint's body's mass (null: not given)
  const double* levers = nullptr;  // (njoints, 3): its centre of mass in the joint's frame
  std::int64_t njoints = 0;
};

// A Python piece of a program: CALL(index) runs the owner's callbacks[index] (the plan's owner
// holds the callables; a nonzero return stops the program and the tick; an exception unwinds).
using Callback = int (*)(void* owner, std::int64_t index);

// Whether an op's operands are in range: registers below `registers`, the reads' immediates in
// their tables. The plan checks every op once, when it is built.
inline bool valid(const Op& o, std::int64_t registers, std::int64_t frames, std::int64_t nq,
                  std::int64_t nv, std::int64_t callbacks) {
  auto reg = [registers](std::int64_t i) { return i >= 0 && i < registers; };
  if (o.code < 0 || o.code >= OP_COUNT || !reg(o.out)) return false;
  switch (o.code) {
    case FRAME: return o.a >= 0 && o.a < frames && o.b >= 0 && o.b < 12;
    case FRAME_VELOCITY: return o.a >= 0 && o.a < frames && o.b >= 0 && o.b < 3;
    case Q: return o.a >= 0 && o.a < nq;
    case V: return o.a >= 0 && o.a < nv;
    case CALL: return o.a >= 0 && o.a < callbacks;
    case COM: return o.out + 2 < registers;  // out, out + 1, out + 2: x, y, z
    case SELECT: return reg(o.a) && reg(o.b) && reg(o.c);
    default: return reg(o.a) && reg(o.b);
  }
}

inline double truth(bool value) { return value ? 1.0 : 0.0; }

// Run ops [start, stop) over registers r; false when a callback failed (the tick stops).
inline bool run(const Op* ops, std::int64_t start, std::int64_t stop, double* r, const Inputs& in,
                Callback callback, void* owner) {
  for (std::int64_t k = start; k < stop; ++k) {
    const Op& o = ops[k];
    double& out = r[o.out];
    switch (o.code) {  // register operands are read in their case (the immediates are not)
#define A r[o.a]
#define B r[o.b]
      case COPY: out = A; break;
      case STORE: out = A; break;  // out: a declared slot
      case ADD: out = A + B; break;
      case SUB: out = A - B; break;
      case MUL: out = A * B; break;
      case DIV: out = A / B; break;
      case NEG: out = -A; break;
      case ABS: out = std::fabs(A); break;
      case SQRT: out = std::sqrt(A); break;
      case SIN: out = std::sin(A); break;
      case COS: out = std::cos(A); break;
      case TAN: out = std::tan(A); break;
      case ASIN: out = std::asin(A); break;
      case ACOS: out = std::acos(A); break;
      case EXP: out = std::exp(A); break;
      case ATAN2: out = std::atan2(A, B); break;
      case HYPOT: out = py_hypot(A, B); break;
      case REMAINDER: out = std::remainder(A, B); break;
      case MIN: out = py_min(A, B); break;
      case MAX: out = py_max(A, B); break;
      case LT: out = truth(A < B); break;
      case LE: out = truth(A <= B); break;
      case EQ: out = truth(A == B); break;
      case NE: out = truth(A != B); break;
      case NOT: out = truth(A == 0.0); break;
      case AND: out = truth(A != 0.0 && B != 0.0); break;
      case OR: out = truth(A != 0.0 || B != 0.0); break;
      case SELECT: out = A != 0.0 ? B : r[o.c]; break;
#undef A
#undef B
      case FRAME: out = in.frames[12 * o.a + o.b]; break;
      case FRAME_VELOCITY: out = in.velocities[3 * o.a + o.b]; break;
      case Q: out = in.q[o.a]; break;
      case V: out = in.v[o.a]; break;
      case COM: {  // the robot's centre of mass, world [m]: three registers from out
        if (in.masses == nullptr) return false;
        double com[3];
        center_of_mass(in.joints, in.masses, in.levers, in.njoints, com);
        r[o.out] = com[0];
        r[o.out + 1] = com[1];
        r[o.out + 2] = com[2];
        break;
      }
      case CALL:
        if (callback(owner, o.a) != 0) return false;
        break;
      default: return false;
    }
  }
  return true;
}

}  // namespace va::plan
