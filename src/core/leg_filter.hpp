// The position half of the legged state estimator (legged_estimator.hpp): a linear Kalman
// filter over the base's position p and velocity v and the feet's positions s_i, all in world
// axes (the design of legged_control's LinearKalmanFilter and of MIT Cheetah's
// PositionVelocityEstimator), with noise derived from the sensors' rather than tuned per robot.
//
// State (6 + 3 nf): p, v, s_1 ... s_nf. Prediction with the world acceleration
// a = R^ f + g (f the accelerometer, base axes):
//   p <- p + v dt + a dt^2 / 2,  v <- v + a dt,  s_i <- s_i,
//   Q = diag((accel dt^2 / 2)^2, accel^2 dt^2, slip^2 dt or swing^2 dt per foot).
// Measurements of foot i, r_i its position from the base by the leg's kinematics (base axes):
// - always: s_i - p = R^ r_i (noise: encoders through the leg's Jacobian, the attitude's error
//   through [r_i]x, and a floor for the model's errors);
// - in stance (a foot that does not move): v = -R^ (w x r_i + r_i') (noise: encoder rates
//   through the Jacobian, the gyro through [r_i]x, a floor for slip and rolling);
// - in stance on level ground: s_i,z = h_i, the foot's height when the filter was reset.
#pragma once

#include <cstdint>
#include <vector>

#include "kalman.hpp"
#include "so3.hpp"

namespace va {

struct LegNoise {
  double accel;          // [m/s^2] per reading (the accelerometer, and what R^ misses of g)
  double slip;           // [m/sqrt(s)] a stance foot's random walk
  double swing;          // [m/sqrt(s)] a swinging foot's random walk
  double encoder;        // [rad] per reading
  double encoder_rate;   // [rad/s] per reading
  double gyro;           // [rad/s] per reading
  double kinematics;     // [m] floor of a foot's position from the legs
  double foot_velocity;  // [m/s] floor of a stance foot's velocity (slip, rolling)
  double height;         // [m] a stance foot's height above its level
};

struct LegFilter {
  std::int64_t nf = 0, n = 6;
  std::vector<double> x, P, level, scratch;

  void resize(std::int64_t feet) {
    nf = feet;
    n = 6 + 3 * feet;
    x.assign(static_cast<size_t>(n), 0.0);
    P.assign(static_cast<size_t>(n * n), 0.0);
    level.assign(static_cast<size_t>(feet), 0.0);
    scratch.assign(static_cast<size_t>(n * kalman::MAX_BLOCK), 0.0);
  }

  // Start at base position p, velocity v (world) and feet positions feet (nf x 3, world),
  // whose heights become the feet's levels; sigma_p, sigma_v [m, m/s].
  void reset(const double* p, const double* v, const double* feet, double sigma_p, double sigma_v,
             double sigma_feet) {
    for (int i = 0; i < 3; ++i) x[i] = p[i], x[3 + i] = v[i];
    for (std::int64_t k = 0; k < 3 * nf; ++k) x[6 + k] = feet[k];
    for (std::int64_t f = 0; f < nf; ++f) level[f] = feet[3 * f + 2];
    for (double& e : P) e = 0.0;
    for (std::int64_t i = 0; i < n; ++i)
      P[i * n + i] = i < 3   ? sigma_p * sigma_p
                     : i < 6 ? sigma_v * sigma_v
                             : sigma_feet * sigma_feet;
  }

  void predict(const double* accel_world, double dt, const bool* stance, const LegNoise& noise) {
    for (int i = 0; i < 3; ++i) {
      x[i] += x[3 + i] * dt + 0.5 * accel_world[i] * dt * dt;
      x[3 + i] += accel_world[i] * dt;
    }
    for (int i = 0; i < 3; ++i)  // rows, then columns: F P F^T for F = I + dt (p <- v)
      for (std::int64_t j = 0; j < n; ++j) P[i * n + j] += dt * P[(3 + i) * n + j];
    for (std::int64_t r = 0; r < n; ++r)
      for (int i = 0; i < 3; ++i) P[r * n + i] += dt * P[r * n + 3 + i];
    const double qp = 0.25 * noise.accel * noise.accel * dt * dt * dt * dt;
    const double qv = noise.accel * noise.accel * dt * dt;
    for (int i = 0; i < 3; ++i) P[i * n + i] += qp, P[(3 + i) * n + 3 + i] += qv;
    for (std::int64_t f = 0; f < nf; ++f) {
      const double walk = stance[f] ? noise.slip : noise.swing;
      for (int i = 0; i < 3; ++i) {
        const std::int64_t k = 6 + 3 * f + i;
        P[k * n + k] += walk * walk * dt;
      }
    }
  }

  // Foot f's measurements in one block: its position from the base, world axes (offset =
  // R^ r_f) with its 3x3 noise; in stance also the base's velocity it gives (velocity, world
  // axes, nullptr: none) with its 3x3 noise, and its height at its level (height_sigma [m],
  // <= 0: none). The noises are independent: one block is the sequence of three updates.
  bool update_foot(std::int64_t f, const double* offset, const double* position_covariance,
                   const double* velocity, const double* velocity_covariance, double height_sigma) {
    const int m = 3 + (velocity != nullptr ? 3 : 0) + (height_sigma > 0.0 ? 1 : 0);
    std::int64_t index[2 * kalman::MAX_BLOCK];
    double coef[2 * kalman::MAX_BLOCK], y[kalman::MAX_BLOCK];
    double R[kalman::MAX_BLOCK * kalman::MAX_BLOCK] = {};  // m x m, block-diagonal
    for (int i = 0; i < 3; ++i) {                          // s_f - p = offset
      index[2 * i] = 6 + 3 * f + i, coef[2 * i] = 1.0;
      index[2 * i + 1] = i, coef[2 * i + 1] = -1.0;
      y[i] = offset[i] - (x[6 + 3 * f + i] - x[i]);
      for (int j = 0; j < 3; ++j) R[i * m + j] = position_covariance[3 * i + j];
    }
    int row = 3;
    if (velocity != nullptr) {
      for (int i = 0; i < 3; ++i, ++row) {  // v = velocity
        index[2 * row] = index[2 * row + 1] = 3 + i, coef[2 * row] = 1.0, coef[2 * row + 1] = 0.0;
        y[row] = velocity[i] - x[3 + i];
        for (int j = 0; j < 3; ++j) R[row * m + 3 + j] = velocity_covariance[3 * i + j];
      }
    }
    if (height_sigma > 0.0) {  // s_f,z = level
      const std::int64_t k = 6 + 3 * f + 2;
      index[2 * row] = index[2 * row + 1] = k, coef[2 * row] = 1.0, coef[2 * row + 1] = 0.0;
      y[row] = level[f] - x[k];
      R[row * m + row] = height_sigma * height_sigma;
    }
    return kalman::update_sparse(x.data(), P.data(), n, index, coef, R, m, y, scratch.data());
  }
};

}  // namespace va
