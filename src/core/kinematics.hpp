// The kinematics kernels: forward kinematics (joint and frame placements, the world Jacobian,
// the frames' velocities), unit_norm_error, all_finite, point_velocity, on the tables of
// virtual_actuators.kinematics.kernels, into the buffer KinematicTree.core_pass describes.
// Pinocchio is their oracle (tests/test_realtime.py); the compiler must not contract a*b+c into
// an FMA (CMakeLists.txt sets -ffp-contract=off), so the bits do not depend on the machine.
// Plain pointers and std::vector, no Python: usable from a C++ controller.
#pragma once

#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

namespace va {

enum JointKind : std::int64_t {
  REVOLUTE = 1,
  REVOLUTE_UNBOUNDED = 2,
  PRISMATIC = 3,
  FREE_FLYER = 4,
  SPHERICAL = 5,
};

// Row-major views of the declaration's tables (their meaning: virtual_actuators.kinematics
// .kernels.read_joints).
struct TreeTables {
  const std::int64_t* joint_ints;      // (njoints, 3): parent, kind, idx_q
  const double* joint_floats;          // (njoints, 27)
  const std::int64_t* velocity_joint;  // (nv,)
  const double* velocity_subspace;     // (nv, 6)
  const std::int64_t* frame_parents;   // (nf,)
  const double* frame_floats;          // (nf, 12)
  std::int64_t njoints, nv, nf;
};

inline std::int64_t buffer_size(const TreeTables& t, bool with_velocity) {
  return t.njoints * 12 + 6 * t.nv + t.nf * 12 + (with_velocity ? t.nf * 3 : 0);
}

inline void quaternion_rotation(double x, double y, double z, double w, double* out) {
  out[0] = 1.0 - 2.0 * (y * y + z * z);
  out[1] = 2.0 * (x * y - z * w);
  out[2] = 2.0 * (x * z + y * w);
  out[3] = 2.0 * (x * y + z * w);
  out[4] = 1.0 - 2.0 * (x * x + z * z);
  out[5] = 2.0 * (y * z - x * w);
  out[6] = 2.0 * (x * z - y * w);
  out[7] = 2.0 * (y * z + x * w);
  out[8] = 1.0 - 2.0 * (x * x + y * y);
}

// Joint placements (njoints, 12), world joint Jacobian (6, nv), frame placements (nf, 12) and,
// with a velocity, the frames' linear velocities (nf, 3), one after the other in `buffer`
// (buffer_size(t, velocity != nullptr) doubles). velocity: (nv,) or nullptr; twists: scratch of
// 6 njoints doubles when velocity != nullptr.
inline void forward_kinematics(const TreeTables& t, const double* q, const double* velocity,
                               double* buffer, double* twists) {
  const std::int64_t njoints = t.njoints, nv = t.nv, nf = t.nf;
  const std::int64_t* ji = t.joint_ints;
  const double* jf = t.joint_floats;
  double* joints = buffer;
  for (int k = 0; k < 12; ++k) joints[k] = 0.0;
  joints[0] = 1.0;
  joints[4] = 1.0;
  joints[8] = 1.0;
  double motion[9];
  double local[12];
  for (std::int64_t j = 1; j < njoints; ++j) {
    const std::int64_t parent = ji[3 * j], kind = ji[3 * j + 1], iq = ji[3 * j + 2];
    const double* f = jf + 27 * j;
    if (kind == REVOLUTE || kind == REVOLUTE_UNBOUNDED) {
      double c, s;
      if (kind == REVOLUTE) {
        c = std::cos(q[iq]);
        s = std::sin(q[iq]);
      } else {
        c = q[iq];
        s = q[iq + 1];
      }
      const double tt = 1.0 - c;
      const double ax = f[12], ay = f[13], az = f[14];
      for (int r = 0; r < 3; ++r) {
        const double tu = tt * f[24 + r];
        local[3 * r] = c * f[3 * r] + s * f[15 + 3 * r] + tu * ax;
        local[3 * r + 1] = c * f[3 * r + 1] + s * f[16 + 3 * r] + tu * ay;
        local[3 * r + 2] = c * f[3 * r + 2] + s * f[17 + 3 * r] + tu * az;
        local[9 + r] = f[9 + r];
      }
    } else {
      const double ax = f[12], ay = f[13], az = f[14];
      double tx = 0.0, ty = 0.0, tz = 0.0;
      if (kind == PRISMATIC) {
        for (int k = 0; k < 9; ++k) motion[k] = 0.0;
        motion[0] = motion[4] = motion[8] = 1.0;
        tx = ax * q[iq];
        ty = ay * q[iq];
        tz = az * q[iq];
      } else if (kind == FREE_FLYER) {
        tx = q[iq];
        ty = q[iq + 1];
        tz = q[iq + 2];
        quaternion_rotation(q[iq + 3], q[iq + 4], q[iq + 5], q[iq + 6], motion);
      } else {  // SPHERICAL
        quaternion_rotation(q[iq], q[iq + 1], q[iq + 2], q[iq + 3], motion);
      }
      for (int r = 0; r < 3; ++r) {
        const double p0 = f[3 * r], p1 = f[3 * r + 1], p2 = f[3 * r + 2];
        for (int c = 0; c < 3; ++c)
          local[3 * r + c] = p0 * motion[c] + p1 * motion[3 + c] + p2 * motion[6 + c];
        local[9 + r] = p0 * tx + p1 * ty + p2 * tz + f[9 + r];
      }
    }
    const double* pj = joints + 12 * parent;
    double* wj = joints + 12 * j;
    for (int r = 0; r < 3; ++r) {
      const double p0 = pj[3 * r], p1 = pj[3 * r + 1], p2 = pj[3 * r + 2];
      for (int c = 0; c < 3; ++c)
        wj[3 * r + c] = p0 * local[c] + p1 * local[3 + c] + p2 * local[6 + c];
      wj[9 + r] = p0 * local[9] + p1 * local[10] + p2 * local[11] + pj[9 + r];
    }
  }
  double* jac = buffer + njoints * 12;  // (6, nv)
  for (std::int64_t v = 0; v < nv; ++v) {
    const double* wj = joints + 12 * t.velocity_joint[v];
    const double* S = t.velocity_subspace + 6 * v;
    for (int r = 0; r < 3; ++r) {
      jac[r * nv + v] = wj[3 * r] * S[0] + wj[3 * r + 1] * S[1] + wj[3 * r + 2] * S[2];
      jac[(3 + r) * nv + v] = wj[3 * r] * S[3] + wj[3 * r + 1] * S[4] + wj[3 * r + 2] * S[5];
    }
    const double px = wj[9], py = wj[10], pz = wj[11];
    const double wx = jac[3 * nv + v], wy = jac[4 * nv + v], wz = jac[5 * nv + v];
    jac[v] += py * wz - pz * wy;
    jac[nv + v] += pz * wx - px * wz;
    jac[2 * nv + v] += px * wy - py * wx;
  }
  double* frames = jac + 6 * nv;
  for (std::int64_t fr = 0; fr < nf; ++fr) {
    const double* wj = joints + 12 * t.frame_parents[fr];
    const double* ff = t.frame_floats + 12 * fr;
    double* out = frames + 12 * fr;
    for (int r = 0; r < 3; ++r) {
      const double p0 = wj[3 * r], p1 = wj[3 * r + 1], p2 = wj[3 * r + 2];
      for (int c = 0; c < 3; ++c) out[3 * r + c] = p0 * ff[c] + p1 * ff[3 + c] + p2 * ff[6 + c];
      out[9 + r] = p0 * ff[9] + p1 * ff[10] + p2 * ff[11] + wj[9 + r];
    }
  }
  if (velocity == nullptr) return;
  for (int k = 0; k < 6; ++k) twists[k] = 0.0;
  std::int64_t column = 0;
  for (std::int64_t j = 1; j < njoints; ++j) {
    const std::int64_t parent = ji[3 * j];
    for (int k = 0; k < 6; ++k) twists[6 * j + k] = twists[6 * parent + k];
    while (column < nv && t.velocity_joint[column] == j) {
      const double rate = velocity[column];
      for (int k = 0; k < 6; ++k) twists[6 * j + k] += jac[k * nv + column] * rate;
      ++column;
    }
  }
  double* velocities = frames + 12 * nf;
  for (std::int64_t fr = 0; fr < nf; ++fr) {
    const double* tw = twists + 6 * t.frame_parents[fr];
    const double x = frames[12 * fr + 9], y = frames[12 * fr + 10], z = frames[12 * fr + 11];
    const double wx = tw[3], wy = tw[4], wz = tw[5];
    velocities[3 * fr] = tw[0] + wy * z - wz * y;
    velocities[3 * fr + 1] = tw[1] + wz * x - wx * z;
    velocities[3 * fr + 2] = tw[2] + wx * y - wy * x;
  }
}

// Largest | ||q[a:b]|| - 1 | over the (m, 2) slices `bounds`; -1 when q is not finite.
inline double unit_norm_error(const double* q, std::int64_t nq, const std::int64_t* bounds,
                              std::int64_t m) {
  for (std::int64_t i = 0; i < nq; ++i)
    if (!std::isfinite(q[i])) return -1.0;
  double worst = 0.0;
  for (std::int64_t s = 0; s < m; ++s) {
    double acc = 0.0;
    for (std::int64_t i = bounds[2 * s]; i < bounds[2 * s + 1]; ++i) acc += q[i] * q[i];
    const double error = std::abs(std::sqrt(acc) - 1.0);
    worst = error > worst ? error : worst;  // Python's max(worst, error)
  }
  return worst;
}

// Whether every entry is finite (no NaN, no infinity).
// (e * 0 is 0 for a finite e and NaN for an infinite or NaN one: four sums of them, branch-free,
// tell in a quarter of the latency of a test per entry.)
inline bool all_finite(const double* values, std::int64_t count) {
  double zero[4] = {0.0, 0.0, 0.0, 0.0};
  std::int64_t i = 0;
  for (; i + 4 <= count; i += 4)
    for (int k = 0; k < 4; ++k) zero[k] += values[i + k] * 0.0;
  for (; i < count; ++i) zero[0] += values[i] * 0.0;
  return zero[0] + zero[1] + zero[2] + zero[3] == 0.0;
}

// Linear velocity in world axes of the point (x, y, z) fixed to a body moved by the velocity
// indices `columns` (its support): the twist J[:, columns] v[columns] at the world origin, then
// v + w x p. jacobian_world (6, nv) row-major.
inline void point_velocity(const double* jacobian_world, std::int64_t nv, const double* v,
                           const std::int64_t* columns, std::int64_t count, double x, double y,
                           double z, double* out) {
  double vx = 0.0, vy = 0.0, vz = 0.0, wx = 0.0, wy = 0.0, wz = 0.0;
  for (std::int64_t j = 0; j < count; ++j) {
    const std::int64_t c = columns[j];
    const double rate = v[c];
    vx += jacobian_world[c] * rate;
    vy += jacobian_world[nv + c] * rate;
    vz += jacobian_world[2 * nv + c] * rate;
    wx += jacobian_world[3 * nv + c] * rate;
    wy += jacobian_world[4 * nv + c] * rate;
    wz += jacobian_world[5 * nv + c] * rate;
  }
  out[0] = vx + wy * z - wz * y;
  out[1] = vy + wz * x - wx * z;
  out[2] = vz + wx * y - wy * x;
}

// A kinematic tree's tables, owned (built once at declaration); compute() is re-entrant.
class Tree {
 public:
  Tree(std::vector<std::int64_t> joint_ints, std::vector<double> joint_floats,
       std::vector<std::int64_t> velocity_joint, std::vector<double> velocity_subspace,
       std::vector<std::int64_t> frame_parents, std::vector<double> frame_floats)
      : ints_(std::move(joint_ints)),
        floats_(std::move(joint_floats)),
        vjoint_(std::move(velocity_joint)),
        subspace_(std::move(velocity_subspace)),
        fparents_(std::move(frame_parents)),
        ffloats_(std::move(frame_floats)) {
    t_ = TreeTables{ints_.data(),
                    floats_.data(),
                    vjoint_.data(),
                    subspace_.data(),
                    fparents_.data(),
                    ffloats_.data(),
                    static_cast<std::int64_t>(ints_.size() / 3),
                    static_cast<std::int64_t>(vjoint_.size()),
                    static_cast<std::int64_t>(fparents_.size())};
  }
  Tree(const Tree&) = delete;
  Tree& operator=(const Tree&) = delete;

  const TreeTables& tables() const { return t_; }
  std::int64_t size(bool with_velocity) const { return buffer_size(t_, with_velocity); }
  // offsets in the buffer of the Jacobian and the frame placements
  std::int64_t jacobian_offset() const { return 12 * t_.njoints; }
  std::int64_t frames_offset() const { return 12 * t_.njoints + 6 * t_.nv; }

  // out: size(velocity != nullptr) doubles; velocity: (nv,) or nullptr.
  void compute(const double* q, const double* velocity, double* out) const {
    if (velocity == nullptr) {
      forward_kinematics(t_, q, nullptr, out, nullptr);
      return;
    }
    std::vector<double> twists(static_cast<size_t>(6 * t_.njoints));
    forward_kinematics(t_, q, velocity, out, twists.data());
  }

 private:
  std::vector<std::int64_t> ints_;
  std::vector<double> floats_;
  std::vector<std::int64_t> vjoint_;
  std::vector<double> subspace_;
  std::vector<std::int64_t> fparents_;
  std::vector<double> ffloats_;
  TreeTables t_{};
};

}  // namespace va
