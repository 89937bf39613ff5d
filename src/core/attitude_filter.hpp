// The orientation half of the legged state estimator (legged_estimator.hpp): an error-state
// Kalman filter over the base's rotation R (world <- base) and the gyro's bias b.
//
// State error (6): R = R^ Exp(dtheta) (dtheta in base axes), b = b^ + db.
// Propagation with the gyro w_m (base axes): w = w_m - b^, R^ <- R^ Exp(w dt),
//   dtheta' = Exp(-w dt) dtheta - dt db - dt n_g,  db' = db + n_b,
//   Q = diag(gyro_noise^2 dt^2 I, bias_walk^2 dt I).
// Two measurements:
// - gravity: the accelerometer f_m = R^T (a - g) + noise, a the base's world acceleration as
//   the position filter's velocity gives it (a lagging estimate); with u = R^^T (a - g):
//   y = f_m - u = [u]x dtheta + noise (noise: accel_noise^2 + acceleration^2 per axis, the
//   latter what a misses). Readings whose | |f_m| - |a - g| | exceeds the gate are not used.
// - the stance feet: two feet i, j that do not move in the world keep R (r_i - r_j) constant,
//   so (w_m - b) x r + r' = 0 for r = r_i - r_j, r' its rate from the joints (base axes):
//   y = (w_m - b^) x r + r' = db x r = -[r]x db + noise. This makes the gyro's bias, yaw's
//   included, observable whenever two feet stand apart.
#pragma once

#include <cstdint>

#include "kalman.hpp"
#include "so3.hpp"

namespace va {

struct AttitudeNoise {
  double gyro;             // [rad/s] per reading
  double bias_walk;        // [rad/s/sqrt(s)]
  double accel;            // [m/s^2] per reading
  double acceleration;     // [m/s^2] the base's own acceleration, unmodelled in the tilt update
  double gravity_gate;     // [m/s^2]
  double stance_velocity;  // [m/s] per axis of r' between two stance feet (encoders, slip)
};

struct AttitudeFilter {
  so3::Mat3 rotation;  // R^ (world <- base)
  double bias[3];      // b^ [rad/s], base axes
  double P[36];        // covariance of (dtheta, db)

  void reset(const so3::Mat3 r, double tilt_sigma, double yaw_sigma, double bias_sigma) {
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) rotation[i][j] = r[i][j];
    for (double& b : bias) b = 0.0;
    for (double& p : P) p = 0.0;
    P[0] = P[7] = tilt_sigma * tilt_sigma;
    P[14] = yaw_sigma * yaw_sigma;
    P[21] = P[28] = P[35] = bias_sigma * bias_sigma;
  }

  // The angular velocity the gyro's reading w_m (base axes) stands for: w_m - b^.
  void rate(const double* w_m, double* w) const {
    for (int i = 0; i < 3; ++i) w[i] = w_m[i] - bias[i];
  }

  void propagate(const double* w_m, double dt, const AttitudeNoise& noise) {
    double w[3], step[3];
    rate(w_m, w);
    for (int i = 0; i < 3; ++i) step[i] = -w[i] * dt;
    so3::Mat3 e;  // Exp(-w dt)
    so3::exp(step, e);
    double F[36] = {};
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) F[6 * i + j] = e[i][j];
      F[6 * i + 3 + i] = -dt;
      F[6 * (3 + i) + 3 + i] = 1.0;
    }
    double fp[36] = {}, next[36] = {};
    for (int i = 0; i < 6; ++i)
      for (int j = 0; j < 6; ++j)
        for (int k = 0; k < 6; ++k) fp[6 * i + j] += F[6 * i + k] * P[6 * k + j];
    for (int i = 0; i < 6; ++i)
      for (int j = 0; j < 6; ++j)
        for (int k = 0; k < 6; ++k) next[6 * i + j] += fp[6 * i + k] * F[6 * j + k];
    const double qa = noise.gyro * noise.gyro * dt * dt,
                 qb = noise.bias_walk * noise.bias_walk * dt;
    for (int i = 0; i < 3; ++i) next[7 * i] += qa, next[7 * (i + 3)] += qb;
    for (int i = 0; i < 36; ++i) P[i] = next[i];
    for (int i = 0; i < 3; ++i) step[i] = w[i] * dt;
    so3::rotate_body(rotation, step);
  }

  // The tilt from the accelerometer f_m (base axes), the base's acceleration accel_world and
  // gravity_world (e.g. (0, 0, -9.81)), world axes.
  // Returns whether the reading was used.
  bool update_gravity(const double* f_m, const double* accel_world, const double* gravity_world,
                      const AttitudeNoise& noise) {
    double up[3], u[3];
    for (int i = 0; i < 3; ++i) up[i] = accel_world[i] - gravity_world[i];
    const double g = so3::norm(up);
    const double f = so3::norm(f_m);
    if (f - g > noise.gravity_gate || g - f > noise.gravity_gate) return false;
    so3::apply_transposed(rotation, up, u);
    so3::Mat3 ux;
    so3::skew(u, ux);
    double H[18] = {}, R[9] = {}, y[3];
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) H[6 * i + j] = ux[i][j];
      R[4 * i] = noise.accel * noise.accel + noise.acceleration * noise.acceleration;
      y[i] = f_m[i] - u[i];
    }
    return correct(H, R, y);
  }

  // The bias from two stance feet: r = r_i - r_j and its rate r' (base axes).
  bool update_stance(const double* w_m, const double* r, const double* r_rate,
                     const AttitudeNoise& noise) {
    double w[3], wr[3];
    rate(w_m, w);
    so3::cross(w, r, wr);
    so3::Mat3 rx;
    so3::skew(r, rx);
    const double lever = so3::norm(r);
    const double variance =
        noise.gyro * noise.gyro * lever * lever + noise.stance_velocity * noise.stance_velocity;
    double H[18] = {}, R[9] = {}, y[3];
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) H[6 * i + 3 + j] = -rx[i][j];
      R[4 * i] = variance;
      y[i] = wr[i] + r_rate[i];
    }
    return correct(H, R, y);
  }

 private:
  // The error-state update, then the error injected into R^ and b^ (and reset to zero).
  bool correct(const double* H, const double* R, const double* y) {
    double dx[6] = {}, scratch[2 * 6 * 3 + 6];
    if (!kalman::update(dx, P, 6, H, R, 3, y, scratch)) return false;
    so3::rotate_body(rotation, dx);
    for (int i = 0; i < 3; ++i) bias[i] += dx[3 + i];
    return true;
  }
};

}  // namespace va
