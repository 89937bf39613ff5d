// Turkey walking's state machine and state callbacks (VMC 2001, section 5, Table 1) in C++: a
// line-by-line port of virtual_actuators.gaits.turkey.walker.TurkeyWalker's transitions
// (_machine, control.events.after / ahead_of, Gait._front_is), its callbacks (_enter_double,
// _update_double, _enter_single, _update_single, _update_ground) on gaits.planar's smoothstep
// and lift_profile (scalar.hpp), with control.state_machine.StateMachine.update's order (the
// first transition whose event fires, then the current state's on_update). The same
// floating-point operations in the same order, so that a native tick and the Python one agree
// bit for bit (tests/test_native_turkey.py). An edit of the reference goes with the same edit here.
#pragma once

#include <cmath>
#include <cstdint>

#include "scalar.hpp"

namespace va::turkey {

// The machine's states, in StateMachine.names order (gaits.planar.biped_states).
enum State : std::int64_t {
  DOUBLE = 0,
  LEFT = 1,
  LEFT_2 = 2,
  RIGHT = 3,
  RIGHT_2 = 4,
};
enum Side : std::int64_t { LEFT_SIDE = 0, RIGHT_SIDE = 1 };

// TurkeyParameters' gait variables the machine and the callbacks read.
struct Parameters {
  double over_distance, away_distance, buffer_delay, height, foot_radius;
  double swing_reach, lift_peak, lift, touchdown_depth;
};

// Rows of the frames in the snapshot's frame table (nf, 12): rotation, then position.
struct Rows {
  std::int64_t body, feet[2];
};

// What the gait remembers between ticks (TurkeyWalker's and its machine's attributes).
struct Memory {
  std::int64_t state = LEFT;
  double entered_at = 0.0;  // [s]
  std::int64_t front = LEFT_SIDE;
  double swing_start[2] = {0.0, 0.0};  // swing foot relative to the body at lift-off [m]
  double progress_start = 0.0;         // body x minus stance x at lift-off [m]
  double ground = 0.0;                 // [m]
  double granny_height = 0.0;          // the granny walker's height set point [m]
  double swing_setpoint[2][2] = {{0.0, 0.0}, {0.0, 0.0}};  // per side (x, z) [m]
  bool placed[2] = {false, false};  // the side's linkage was placed this tick
};

inline double coordinate(const double* frames, std::int64_t row, int axis) {
  return frames[12 * row + 9 + axis];
}

inline bool is_single(std::int64_t state) { return state != DOUBLE; }
inline std::int64_t stance_of(std::int64_t state) {
  return state == LEFT || state == LEFT_2 ? LEFT_SIDE : RIGHT_SIDE;
}
inline bool is_buffer(std::int64_t state) { return state == LEFT_2 || state == RIGHT_2; }

// _update_ground: the ground under the feet in support, the granny walker's height from it.
inline void update_ground(const Parameters& p, const double* frames, const Rows& r, Memory& m) {
  if (m.state == DOUBLE) {
    // sum(heights) / len(heights): Python's sum starts from 0
    const double heights =
        0.0 + coordinate(frames, r.feet[0], 2) + coordinate(frames, r.feet[1], 2);
    m.ground = heights / 2.0 - p.foot_radius;
  } else {
    m.ground = (0.0 + coordinate(frames, r.feet[stance_of(m.state)], 2)) / 1.0 - p.foot_radius;
  }
  m.granny_height = m.ground + p.height;
}

// StateMachine._enter's callback of the state entered (the buffer states have none).
inline void enter(const double* frames, const Rows& r, Memory& m) {
  if (m.state == DOUBLE) {  // _enter_double
    const double x_left = coordinate(frames, r.feet[0], 0);
    const double x_right = coordinate(frames, r.feet[1], 0);
    m.front = x_left > x_right ? LEFT_SIDE : RIGHT_SIDE;
  } else if (!is_buffer(m.state)) {  // _enter_single
    const std::int64_t stance = stance_of(m.state), swing = 1 - stance;
    const double body_x = coordinate(frames, r.body, 0), body_z = coordinate(frames, r.body, 2);
    m.swing_start[0] = coordinate(frames, r.feet[swing], 0) - body_x;
    m.swing_start[1] = coordinate(frames, r.feet[swing], 2) - body_z;
    m.progress_start = body_x - coordinate(frames, r.feet[stance], 0);
  }
}

// The first transition of the current state whose event fires (Table 1), or -1.
inline std::int64_t transition(const Parameters& p, const double* frames, const Rows& r,
                               double time, const Memory& m) {
  const double body_x = coordinate(frames, r.body, 0);
  switch (m.state) {
    case DOUBLE:
      for (std::int64_t side = LEFT_SIDE; side <= RIGHT_SIDE; ++side)
        if (m.front == side && body_x - coordinate(frames, r.feet[side], 0) > p.over_distance)
          return side == LEFT_SIDE ? static_cast<std::int64_t>(LEFT)
                                   : static_cast<std::int64_t>(RIGHT);
      return -1;
    case LEFT:
    case RIGHT:
      if (body_x - coordinate(frames, r.feet[stance_of(m.state)], 0) > p.away_distance)
        return static_cast<std::int64_t>(m.state + 1);
      return -1;
    default:  // the buffer states: after(buffer_delay)
      return time - m.entered_at >= p.buffer_delay ? static_cast<std::int64_t>(DOUBLE) : -1;
  }
}

// StateMachine.update on a started machine: the transition (and its callback), then the state's
// on_update. Returns whether a state was entered.
inline bool update(const Parameters& p, const double* frames, const Rows& r, double time,
                   Memory& m) {
  const std::int64_t target = transition(p, frames, r, time, m);
  if (target >= 0) {
    m.state = target;
    m.entered_at = time;
    enter(frames, r, m);
  }
  m.placed[0] = m.placed[1] = false;
  update_ground(p, frames, r, m);
  if (m.state == DOUBLE || is_buffer(m.state)) return target >= 0;
  // _update_single: the swing foot's set point relative to the body
  const std::int64_t stance = stance_of(m.state), swing = 1 - stance;
  const double body_x = coordinate(frames, r.body, 0), body_z = coordinate(frames, r.body, 2);
  const double progress = body_x - coordinate(frames, r.feet[stance], 0);
  const double span = py_max(p.away_distance - m.progress_start, 1e-3);
  const double phase = py_min(py_max((progress - m.progress_start) / span, 0.0), 1.0);
  const double x_rel =
      m.swing_start[0] + (p.swing_reach - m.swing_start[0]) * smoothstep(1.6 * phase);
  const double foot_height = lift_profile(phase, p.lift_peak) * p.lift - p.touchdown_depth * phase;
  const double z_rel = m.ground + p.foot_radius + foot_height - body_z;
  m.swing_setpoint[swing][0] = x_rel;
  m.swing_setpoint[swing][1] = z_rel;
  m.placed[swing] = true;
  return target >= 0;
}

}  // namespace va::turkey
