// Generalized gravity from the tick's kinematics pass: the efforts that hold bodies against
// gravity, on some velocity columns (components/gravity.py, Pinocchio's
// computeGeneralizedGravity on the same model: its oracle, tests/test_plan.py).
//
// A velocity column c of joint j moves every body of j's subtree: the body i's centre of mass
// c_i at lin_c + ang_c x c_i (the world Jacobian's column, spatial at the world's origin). Its
// weight m_i g (g the model's gravity, e.g. (0, 0, -9.81)) takes the power m_i g . (lin_c +
// ang_c x c_i) from the column, so holding the subtree takes
//   tau_c = -g . (M_j lin_c + ang_c x S_j),   M_j = sum m_i,   S_j = sum m_i c_i (subtree of j).
#pragma once

#include <cstdint>

#include "kinematics.hpp"

namespace va {

// tau[columns[k]] for k < ncolumns. joints (njoints, 12) and jacobian (6, nv) of the pass;
// masses (njoints), levers (njoints, 3) in the joints' frames; gravity (3); subtree: scratch of
// 4 njoints doubles.
inline void generalized_gravity(const TreeTables& t, const double* joints, const double* jacobian,
                                const double* masses, const double* levers, const double* gravity,
                                const std::int64_t* columns, std::int64_t ncolumns, double* subtree,
                                double* tau) {
  const std::int64_t njoints = t.njoints, nv = t.nv;
  for (std::int64_t j = 0; j < njoints; ++j) {  // each body's mass and mass-weighted centre
    const double* J = joints + 12 * j;
    const double m = masses[j], cx = levers[3 * j], cy = levers[3 * j + 1], cz = levers[3 * j + 2];
    double* s = subtree + 4 * j;
    s[0] = m;
    s[1] = m * (J[0] * cx + J[1] * cy + J[2] * cz + J[9]);
    s[2] = m * (J[3] * cx + J[4] * cy + J[5] * cz + J[10]);
    s[3] = m * (J[6] * cx + J[7] * cy + J[8] * cz + J[11]);
  }
  for (std::int64_t j = njoints - 1; j > 0; --j) {  // children after parents: sum upwards
    const std::int64_t parent = t.joint_ints[3 * j];
    if (parent <= 0) continue;
    for (int k = 0; k < 4; ++k) subtree[4 * parent + k] += subtree[4 * j + k];
  }
  for (std::int64_t k = 0; k < ncolumns; ++k) {
    const std::int64_t c = columns[k];
    const double* s = subtree + 4 * t.velocity_joint[c];
    const double lx = jacobian[c], ly = jacobian[nv + c], lz = jacobian[2 * nv + c];
    const double ax = jacobian[3 * nv + c], ay = jacobian[4 * nv + c], az = jacobian[5 * nv + c];
    const double px = s[0] * lx + (ay * s[3] - az * s[2]);  // M lin + ang x S
    const double py = s[0] * ly + (az * s[1] - ax * s[3]);
    const double pz = s[0] * lz + (ax * s[2] - ay * s[1]);
    tau[c] = -(gravity[0] * px + gravity[1] * py + gravity[2] * pz);
  }
}

}  // namespace va
