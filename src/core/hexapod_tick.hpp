// The hexapod's tripod gait per tick in C++: a line-by-line port of
// virtual_actuators.gaits.hexapod.walker.HexapodWalker's transitions (_machine: _stance_over,
// control.events.after), its callbacks (_body_state without a pendulum on a free-flyer body,
// _update_double, _update_tripod with the tripod kernel of hexapod.hpp) and of the body's
// components (gaits.hexapod.body.HeadingAttitude and HeadingDamper's compute_wrench_floats with
// gaits.attitude.rotation_vector_angles, the height's SpringDamper.compute_wrench_floats, summed
// like control.attachment.Attachment.wrench_floats), with
// control.state_machine.StateMachine.update's order. The same floating-point operations in the
// same order, so that a native tick and the Python one agree bit for bit
// (tests/test_native_hexapod.py). A tripod's entry (_enter_tripod) is not ported: that tick runs
// in Python (update answers DEFER). An edit of the reference goes with the same edit here.
#pragma once

#include <cmath>
#include <cstdint>

#include "hexapod.hpp"
#include "scalar.hpp"

namespace va::hexapod {

// The machine's states, in StateMachine.names order (HexapodWalker._machine).
enum State : std::int64_t { TRIPOD_A = 0, DOUBLE_A = 1, TRIPOD_B = 2, DOUBLE_B = 3 };

// HexapodParameters' values the tick reads, and the tripod kernel's fixed arrays.
struct Parameters {
  double velocity_filter, acceleration, height, touchdown_phase, double_support_time;
  const double* nominal;  // (6, 3) the feet's nominal places (HexapodWalker._nominal_feet)
  const double* shape;    // (11,) HexapodWalker._shape
};

// Rows of the body and the feet in the frame table (HexapodWalker._frame_rows).
struct Rows {
  std::int64_t frames[7];
};

// The body's components' constants (their gains, and the height's force and velocity set point).
struct Body {
  double height_stiffness, height_damping, height_velocity, height_force;
  double planar_damping[2], planar_force[2];
  double attitude_stiffness[2], attitude_damping[3], attitude_roll, attitude_pitch;
};

// What the gait remembers between ticks (HexapodWalker's, its components' and its machine's).
struct Memory {
  std::int64_t state = DOUBLE_A;
  double entered_at = 0.0;   // [s]
  std::int64_t support = 0;  // 0: tripod a, 1: tripod b
  double phase = 0.0, ground = 0.0;
  double kernel[5] = {0.0, 0.0, 0.0, 0.0, 0.0};  // HexapodWalker._state
  double swing[27] = {};                         // HexapodWalker._swing (3, 9)
  double target_time = 0.0, filter_time = 0.0;
  double velocity_body[2] = {0.0, 0.0}, velocity_filtered[2] = {0.0, 0.0};
  double setpoint[2] = {0.0, 0.0}, acceleration[2] = {0.0, 0.0};
  double planar_velocity[2] = {0.0, 0.0};  // planar.velocity (velocity_setpoint)
  double planar_yaw = 0.0, attitude_yaw = 0.0, attitude_yaw_rate = 0.0;
  double height_setpoint = 0.0;
  double leg_setpoint[6][3] = {}, leg_velocity[6][3] = {};  // swing_1 ... swing_6's set points
};

// The tick's inputs besides the kinematics: set_command's and the contact switches.
struct Inputs {
  double command[2], yaw_rate;
  const std::int64_t* contacts;  // (6,) per foot 0/1, or nullptr (no switches)
};

inline bool is_tripod(std::int64_t state) { return state == TRIPOD_A || state == TRIPOD_B; }

// The tripod legs (0-based) of tripod 0 (a: 1, 3, 5) and 1 (b: 2, 4, 6).
inline std::int64_t tripod_leg(std::int64_t tripod, int k) { return 2 * k + tripod; }

// _body_state (no pendulum, the body the free flyer's frame): the body's height.
inline double body_state(const Parameters& p, const double* frames, const Rows& rows,
                         const double* v, double time, const Inputs& in, Memory& m) {
  const double* body = frames + 12 * rows.frames[0];
  const double* r = body;  // r[3 i + j]: rotation[i][j]
  const double yaw = std::atan2(r[3], r[0]);
  const double c = std::cos(yaw), s = std::sin(yaw);
  const double u = v[0], w_v = v[1], w = v[2];
  const double world_x = r[0] * u + r[1] * w_v + r[2] * w;
  const double world_y = r[3] * u + r[4] * w_v + r[5] * w;
  const double vx = c * world_x + s * world_y, vy = -s * world_x + c * world_y;
  m.velocity_body[0] = vx;
  m.velocity_body[1] = vy;
  const double dt = py_max(time - m.filter_time, 0.0);
  m.filter_time = time;
  const double blend = py_min(1.0, dt / p.velocity_filter);
  const double fx = m.velocity_filtered[0], fy = m.velocity_filtered[1];
  m.velocity_filtered[0] = fx + blend * (vx - fx);
  m.velocity_filtered[1] = fy + blend * (vy - fy);
  const double cx = in.command[0], cy = in.command[1];
  const double sx = m.setpoint[0], sy = m.setpoint[1];
  if (cx != sx || cy != sy) {
    const double ex = cx - sx, ey = cy - sy;
    const double size = py_hypot(ex, ey), most = p.acceleration * dt;
    const double scale = size <= most ? 1.0 : most / size;
    m.setpoint[0] = sx + scale * ex;
    m.setpoint[1] = sy + scale * ey;
    m.planar_velocity[0] = m.setpoint[0];
    m.planar_velocity[1] = m.setpoint[1];
    if (dt > 0.0) {
      m.acceleration[0] = scale * ex / dt;
      m.acceleration[1] = scale * ey / dt;
    }
  } else if (dt > 0.0) {
    m.acceleration[0] = 0.0;
    m.acceleration[1] = 0.0;
  }
  m.planar_yaw = yaw;
  m.attitude_yaw_rate = in.yaw_rate;
  return body[11];
}

// _update_tripod: the ground plane, the phase and the swing set points (the tripod kernel).
inline void update_tripod(const Parameters& p, const double* frames, const Rows& rows,
                          const double* v, double time, double time_in_state, const Inputs& in,
                          Memory& m) {
  const double height = body_state(p, frames, rows, v, time, in, m);
  const double motion[10] = {
      height,        m.velocity_filtered[0], m.velocity_filtered[1], m.setpoint[0],
      m.setpoint[1], m.acceleration[0],      m.acceleration[1],      in.yaw_rate,
      time_in_state, time - m.target_time};
  // HexapodWalker._kernel_rows: the support tripod's feet, then the swing tripod's
  std::int64_t kernel_rows[6];
  for (int k = 0; k < 3; ++k) {
    kernel_rows[k] = tripod_leg(m.support, k);
    kernel_rows[3 + k] = tripod_leg(1 - m.support, k);
  }
  va::tripod_setpoints(frames, rows.frames, kernel_rows, p.nominal, motion, p.shape, m.swing,
                       m.kernel);
  m.target_time = time;
  m.phase = m.kernel[3];
  m.ground = m.kernel[4];
  m.height_setpoint = m.ground + p.height;
  for (int k = 0; k < 3; ++k) {
    const std::int64_t leg = tripod_leg(1 - m.support, k);
    for (int i = 0; i < 3; ++i) {
      m.leg_setpoint[leg][i] = m.swing[9 * k + 3 + i];
      m.leg_velocity[leg][i] = m.swing[9 * k + 6 + i];
    }
  }
}

// _stance_over in tripod `tripod`: the body has travelled a step, or the swing feet are down.
inline bool stance_over(const Parameters& p, const Inputs& in, const Memory& m,
                        std::int64_t tripod) {
  if (m.phase >= 1.0) return true;
  if (in.contacts == nullptr || m.phase < p.touchdown_phase) return false;
  for (int k = 0; k < 3; ++k)
    if (!in.contacts[tripod_leg(1 - tripod, k)]) return false;
  return true;
}

// What update() did.
enum Update : std::int64_t { DEFER = -1, STAYED = 0, ENTERED = 1 };

// StateMachine.update at time: the first transition whose event fires, then the current state's
// on_update. DEFER (m partly written: the caller drops it) when a tripod is entered.
inline Update update(const Parameters& p, const double* frames, const Rows& rows, const double* v,
                     double time, const Inputs& in, Memory& m) {
  const double time_in_state = time - m.entered_at;
  Update result = STAYED;
  switch (m.state) {
    case TRIPOD_A:
    case TRIPOD_B: {
      const std::int64_t tripod = m.state == TRIPOD_A ? 0 : 1;
      if (stance_over(p, in, m, tripod)) {  // -> the other tripod's double support
        m.state = tripod == 0 ? DOUBLE_B : DOUBLE_A;
        m.entered_at = time;
        result = ENTERED;
      }
      break;
    }
    default:
      if (time_in_state >= p.double_support_time) return DEFER;  // _enter_tripod: Python's
  }
  if (is_tripod(m.state))
    update_tripod(p, frames, rows, v, time, time_in_state, in, m);
  else
    body_state(p, frames, rows, v, time, in, m);  // _update_double
  return result;
}

// gaits.attitude.rotation_vector_angles: (yaw, pitch, roll) of the rotation vector (x, y, z).
inline void rotation_vector_angles(double x, double y, double z, double angles[3]) {
  constexpr double eps = 2.220446049250313e-16;
  static const double taylor = std::pow(eps, 0.25);  // attitude._TAYLOR
  const double t2 = x * x + y * y + z * z + eps * eps;
  const double t = std::sqrt(t2);
  double outer, cross, cos;
  if (t > taylor) {
    cos = std::cos(t);
    outer = (1 - cos) / t2;
    cross = std::sin(t) / t;
  } else {
    outer = 0.5 - t2 / 24;
    cross = 1 - t2 / 6;
    cos = 1 - t2 / 2;
  }
  const double r00 = outer * x * x + cos;
  const double r10 = outer * y * x + cross * z;
  const double r20 = outer * z * x - cross * y;
  const double r21 = outer * z * y + cross * x;
  const double r22 = outer * z * z + cos;
  angles[0] = std::atan2(r10, r00);
  angles[1] = std::asin(py_max(-1.0, py_min(1.0, -r20)));
  angles[2] = std::atan2(r21, r22);
}

// The body attachment's wrench on x y z rx ry rz from its sensor's position and velocity:
// Attachment.wrench_floats over (height on z, planar on x y, attitude on rx ry rz), each axis
// 0.0 + its component's share. False when the sum is not finite (the Python tick decides).
inline bool body_wrench(const Body& b, const Memory& m, const double* position,
                        const double* velocity, double wrench[6], double& attitude_yaw) {
  double total[6] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
  // height: SpringDamper.compute_wrench_floats on z (no limit)
  total[2] += b.height_stiffness * (m.height_setpoint - position[2]) +
              b.height_damping * (b.height_velocity - velocity[2]) + b.height_force;
  {  // planar: HeadingDamper.compute_wrench_floats on x y
    const double c = std::cos(m.planar_yaw), s = std::sin(m.planar_yaw);
    const double v0 = velocity[0], v1 = velocity[1];
    const double vx = c * v0 + s * v1;
    const double vy = -s * v0 + c * v1;
    const double fx = b.planar_damping[0] * (m.planar_velocity[0] - vx) + b.planar_force[0];
    const double fy = b.planar_damping[1] * (m.planar_velocity[1] - vy) + b.planar_force[1];
    total[0] += c * fx - s * fy;
    total[1] += s * fx + c * fy;
  }
  {  // attitude: HeadingAttitude.compute_wrench_floats on rx ry rz
    double angles[3];
    rotation_vector_angles(position[3], position[4], position[5], angles);
    const double yaw = angles[0], pitch = angles[1], roll = angles[2];
    attitude_yaw = yaw;
    const double c = std::cos(yaw), s = std::sin(yaw);
    const double v0 = velocity[3], v1 = velocity[4], v2 = velocity[5];
    const double wx = c * v0 + s * v1;
    const double wy = -s * v0 + c * v1;
    const double mx =
        b.attitude_stiffness[0] * (b.attitude_roll - roll) - b.attitude_damping[0] * wx;
    const double my =
        b.attitude_stiffness[1] * (b.attitude_pitch - pitch) - b.attitude_damping[1] * wy;
    const double mz = b.attitude_damping[2] * (m.attitude_yaw_rate - v2);
    total[3] += c * mx - s * my;
    total[4] += s * mx + c * my;
    total[5] += mz;
  }
  double sum = 0.0;  // Python's sum(total), from 0
  for (int i = 0; i < 6; ++i) sum += total[i];
  if (!std::isfinite(sum)) return false;
  for (int i = 0; i < 6; ++i) wrench[i] = total[i];
  return true;
}

}  // namespace va::hexapod
