// The orientation half of the legged state estimator (legged_estimator.hpp): an error-state
// Kalman filter over the base's rotation R (world <- base), the gyro's bias b and the
// accelerometer's bias c.
//
// State error (9): R = R^ Exp(dtheta) (dtheta in base axes), b = b^ + db, c = c^ + dc.
// Propagation with the gyro w_m (base axes): w = w_m - b^, R^ <- R^ Exp(w dt),
//   dtheta' = Exp(-w dt) dtheta - dt db - dt n_g,  db' = db + n_b,  dc' = dc + n_c,
//   Q = diag(gyro_noise^2 dt^2 I, bias_walk^2 dt I, accel_bias_walk^2 dt I).
// Three measurements:
// - gravity: the accelerometer f_m = R^T (a - g) + c + noise, a the base's world acceleration
//   as the position filter's velocity gives it (a lagging estimate); with u = R^^T (a - g):
//   y = f_m - u - c^ = [u]x dtheta + dc + noise (noise: accel_noise^2 + acceleration^2 per
//   axis, the latter what a misses). Readings whose | |f_m - c^| - |a - g| | exceeds the gate
//   are not used.
// - the stance feet's rate: two feet i, j that do not move in the world keep R (r_i - r_j)
//   constant, so (w_m - b) x r + r' = 0 for r = r_i - r_j, r' its rate from the joints (base
//   axes): y = (w_m - b^) x r + r' = db x r = -[r]x db + noise. The gyro's bias, yaw's
//   included, is observable whenever two feet stand apart. A pair whose residual is beyond
//   STANCE_GATE (a foot taken for standing while it lifts, lands or slips) is skipped: the
//   few such ticks per step otherwise steer the bias.
// - level feet (on level ground): two stance feet at the same level have z^T R r = 0, so
//   y = -z^T R^ r = -z^T R^ [r]x dtheta + noise. With gravity it separates the tilt from the
//   accelerometer's bias, which gravity alone cannot tell apart.
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
  double accel_bias_walk;  // [m/s^2/sqrt(s)]
  double level;            // [m] two stance feet's height difference (the ground's, the legs')
};

constexpr int ATTITUDE_STATES = 9;
// The stance pairs' outlier gate: chi-square, 3 degrees of freedom, 1 in 1000 [-].
constexpr double STANCE_GATE = 16.27;

struct AttitudeFilter {
  so3::Mat3 rotation;                           // R^ (world <- base)
  double bias[3];                               // b^ [rad/s], base axes
  double accel_bias[3];                         // c^ [m/s^2], base axes
  double P[ATTITUDE_STATES * ATTITUDE_STATES];  // covariance of (dtheta, db, dc)

  void reset(const so3::Mat3 r, double tilt_sigma, double yaw_sigma, double bias_sigma,
             double accel_bias_sigma) {
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) rotation[i][j] = r[i][j];
    for (int i = 0; i < 3; ++i) bias[i] = accel_bias[i] = 0.0;
    for (double& p : P) p = 0.0;
    const double diagonal[ATTITUDE_STATES] = {tilt_sigma,       tilt_sigma,       yaw_sigma,
                                              bias_sigma,       bias_sigma,       bias_sigma,
                                              accel_bias_sigma, accel_bias_sigma, accel_bias_sigma};
    for (int i = 0; i < ATTITUDE_STATES; ++i)
      P[(ATTITUDE_STATES + 1) * i] = diagonal[i] * diagonal[i];
  }

  // The angular velocity the gyro's reading w_m (base axes) stands for: w_m - b^.
  void rate(const double* w_m, double* w) const {
    for (int i = 0; i < 3; ++i) w[i] = w_m[i] - bias[i];
  }

  // The specific force the accelerometer's reading f_m stands for: f_m - c^.
  void force(const double* f_m, double* f) const {
    for (int i = 0; i < 3; ++i) f[i] = f_m[i] - accel_bias[i];
  }

  void propagate(const double* w_m, double dt, const AttitudeNoise& noise) {
    constexpr int N = ATTITUDE_STATES;
    double w[3], step[3];
    rate(w_m, w);
    for (int i = 0; i < 3; ++i) step[i] = -w[i] * dt;
    so3::Mat3 e;  // Exp(-w dt)
    so3::exp(step, e);
    // F = [[E, -dt I, 0], [0, I, 0], [0, 0, I]] (E = Exp(-w dt)): only the rows of dtheta
    // change, T = E P_theta,: - dt P_b,: (3 x N); then P_theta,theta = T_:,theta E^T - dt T_:,b
    // and P_theta,(b, c) = T_:,(b, c) (mirrored); the (b, c) blocks stay.
    double t[3][N];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < N; ++j) {
        double sum = -dt * P[N * (3 + i) + j];
        for (int k = 0; k < 3; ++k) sum += e[i][k] * P[N * k + j];
        t[i][j] = sum;
      }
    double block[3][3];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        double sum = -dt * t[i][3 + j];
        for (int k = 0; k < 3; ++k) sum += t[i][k] * e[j][k];
        block[i][j] = sum;
      }
    for (int i = 0; i < 3; ++i) {  // in place: every entry written was read above
      for (int j = 0; j < 3; ++j) P[N * i + j] = 0.5 * (block[i][j] + block[j][i]);
      for (int j = 3; j < N; ++j) P[N * i + j] = P[N * j + i] = t[i][j];
    }
    const double qa = noise.gyro * noise.gyro * dt * dt;
    const double qb = noise.bias_walk * noise.bias_walk * dt;
    const double qc = noise.accel_bias_walk * noise.accel_bias_walk * dt;
    for (int i = 0; i < 3; ++i) {
      P[(N + 1) * i] += qa;
      P[(N + 1) * (i + 3)] += qb;
      P[(N + 1) * (i + 6)] += qc;
    }
    for (int i = 0; i < 3; ++i) step[i] = w[i] * dt;
    so3::rotate_body(rotation, step);
  }

  // The tilt from the accelerometer f_m (base axes), the base's acceleration accel_world and
  // gravity_world (e.g. (0, 0, -9.81)), world axes. Returns whether the reading was used.
  bool update_gravity(const double* f_m, const double* accel_world, const double* gravity_world,
                      const AttitudeNoise& noise) {
    constexpr int N = ATTITUDE_STATES;
    double up[3], u[3], f[3];
    for (int i = 0; i < 3; ++i) up[i] = accel_world[i] - gravity_world[i];
    force(f_m, f);
    const double g = so3::norm(up), norm = so3::norm(f);
    if (norm - g > noise.gravity_gate || g - norm > noise.gravity_gate) return false;
    so3::apply_transposed(rotation, up, u);
    so3::Mat3 ux;
    so3::skew(u, ux);
    double H[3 * N] = {}, R[9] = {}, y[3];
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) H[N * i + j] = ux[i][j];
      H[N * i + 6 + i] = 1.0;
      R[4 * i] = noise.accel * noise.accel + noise.acceleration * noise.acceleration;
      y[i] = f[i] - u[i];
    }
    return correct(H, R, y, 3);
  }

  // The bias from two stance feet: r = r_i - r_j and its rate r' (base axes).
  bool update_stance(const double* w_m, const double* r, const double* r_rate,
                     const AttitudeNoise& noise) {
    constexpr int N = ATTITUDE_STATES;
    double w[3], wr[3];
    rate(w_m, w);
    so3::cross(w, r, wr);
    so3::Mat3 rx;
    so3::skew(r, rx);
    const double lever = so3::norm(r);
    const double variance =
        noise.gyro * noise.gyro * lever * lever + noise.stance_velocity * noise.stance_velocity;
    double H[3 * N] = {}, R[9] = {}, y[3];
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) H[N * i + 3 + j] = -rx[i][j];
      R[4 * i] = variance;
      y[i] = wr[i] + r_rate[i];
    }
    return correct(H, R, y, 3, STANCE_GATE);
  }

  // The tilt from two stance feet r = r_i - r_j apart (base axes) whose levels differ by rise
  // (world z of i minus j).
  bool update_level(const double* r, double rise, const AttitudeNoise& noise) {
    constexpr int N = ATTITUDE_STATES;
    double world[3];
    so3::apply(rotation, r, world);
    so3::Mat3 rx;
    so3::skew(r, rx);
    double H[N] = {};
    for (int j = 0; j < 3; ++j) {  // -z^T R^ [r]x
      double sum = 0.0;
      for (int k = 0; k < 3; ++k) sum += rotation[2][k] * rx[k][j];
      H[j] = -sum;
    }
    const double R = noise.level * noise.level, y = rise - world[2];
    return correct(H, &R, &y, 1);
  }

 private:
  // The error-state update, then the error injected into R^, b^ and c^ (and reset to zero).
  bool correct(const double* H, const double* R, const double* y, int m, double gate = INFINITY) {
    constexpr int N = ATTITUDE_STATES;
    double dx[N] = {}, scratch[N * 3];
    if (!kalman::update(dx, P, N, H, R, m, y, scratch, gate)) return false;
    so3::rotate_body(rotation, dx);
    for (int i = 0; i < 3; ++i) bias[i] += dx[3 + i], accel_bias[i] += dx[6 + i];
    return true;
  }
};

}  // namespace va
