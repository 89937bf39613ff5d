// Rotations as row-major 3x3 arrays for the state estimator (attitude_filter.hpp,
// legged_estimator.hpp): products, the exponential map, re-orthonormalisation and the unit
// quaternion (x, y, z, w) of a rotation, Pinocchio's free-flyer convention.
#pragma once

#include <cmath>

namespace va::so3 {

using Mat3 = double[3][3];

inline void identity(Mat3 out) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) out[i][j] = i == j ? 1.0 : 0.0;
}

// out = a b (out may not alias a or b).
inline void mul(const Mat3 a, const Mat3 b, Mat3 out) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      out[i][j] = a[i][0] * b[0][j] + a[i][1] * b[1][j] + a[i][2] * b[2][j];
}

// out = a x (out may not alias x); transposed: out = a^T x.
inline void apply(const Mat3 a, const double* x, double* out) {
  for (int i = 0; i < 3; ++i) out[i] = a[i][0] * x[0] + a[i][1] * x[1] + a[i][2] * x[2];
}
inline void apply_transposed(const Mat3 a, const double* x, double* out) {
  for (int i = 0; i < 3; ++i) out[i] = a[0][i] * x[0] + a[1][i] * x[1] + a[2][i] * x[2];
}

inline void cross(const double* a, const double* b, double* out) {
  out[0] = a[1] * b[2] - a[2] * b[1];
  out[1] = a[2] * b[0] - a[0] * b[2];
  out[2] = a[0] * b[1] - a[1] * b[0];
}

inline double norm(const double* a) { return std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]); }

// [w]x, the matrix of w x (.).
inline void skew(const double* w, Mat3 out) {
  out[0][0] = 0.0, out[0][1] = -w[2], out[0][2] = w[1];
  out[1][0] = w[2], out[1][1] = 0.0, out[1][2] = -w[0];
  out[2][0] = -w[1], out[2][1] = w[0], out[2][2] = 0.0;
}

// Exp(w): the rotation by |w| about w (Rodrigues), exact to rounding for small angles.
inline void exp(const double* w, Mat3 out) {
  const double theta2 = w[0] * w[0] + w[1] * w[1] + w[2] * w[2];
  const double theta = std::sqrt(theta2);
  double a, b;  // sin(t)/t and (1 - cos t)/t^2
  if (theta < 1e-4) {
    a = 1.0 - theta2 / 6.0;
    b = 0.5 - theta2 / 24.0;
  } else {
    a = std::sin(theta) / theta;
    b = (1.0 - std::cos(theta)) / theta2;
  }
  Mat3 k, k2;
  skew(w, k);
  mul(k, k, k2);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) out[i][j] = (i == j ? 1.0 : 0.0) + a * k[i][j] + b * k2[i][j];
}

// r <- r Exp(w): a rotation perturbed in its own (body) axes, re-orthonormalised.
void orthonormalise(Mat3 r);
inline void rotate_body(Mat3 r, const double* w) {
  Mat3 e, out;
  exp(w, e);
  mul(r, e, out);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) r[i][j] = out[i][j];
  orthonormalise(r);
}

// The nearest rotation, by Gram-Schmidt on the columns (r is a rotation to within rounding).
inline void orthonormalise(Mat3 r) {
  double x[3] = {r[0][0], r[1][0], r[2][0]}, y[3] = {r[0][1], r[1][1], r[2][1]}, z[3];
  double n = norm(x);
  for (double& c : x) c /= n;
  const double d = x[0] * y[0] + x[1] * y[1] + x[2] * y[2];
  for (int i = 0; i < 3; ++i) y[i] -= d * x[i];
  n = norm(y);
  for (double& c : y) c /= n;
  cross(x, y, z);
  for (int i = 0; i < 3; ++i) r[i][0] = x[i], r[i][1] = y[i], r[i][2] = z[i];
}

// The unit quaternion (x, y, z, w) of a rotation, w >= 0 (Shepperd's method).
inline void to_quaternion(const Mat3 r, double* q) {
  const double trace = r[0][0] + r[1][1] + r[2][2];
  if (trace > 0.0) {
    const double s = 2.0 * std::sqrt(trace + 1.0);
    q[3] = 0.25 * s;
    q[0] = (r[2][1] - r[1][2]) / s;
    q[1] = (r[0][2] - r[2][0]) / s;
    q[2] = (r[1][0] - r[0][1]) / s;
  } else if (r[0][0] > r[1][1] && r[0][0] > r[2][2]) {
    const double s = 2.0 * std::sqrt(1.0 + r[0][0] - r[1][1] - r[2][2]);
    q[3] = (r[2][1] - r[1][2]) / s;
    q[0] = 0.25 * s;
    q[1] = (r[0][1] + r[1][0]) / s;
    q[2] = (r[0][2] + r[2][0]) / s;
  } else if (r[1][1] > r[2][2]) {
    const double s = 2.0 * std::sqrt(1.0 + r[1][1] - r[0][0] - r[2][2]);
    q[3] = (r[0][2] - r[2][0]) / s;
    q[0] = (r[0][1] + r[1][0]) / s;
    q[1] = 0.25 * s;
    q[2] = (r[1][2] + r[2][1]) / s;
  } else {
    const double s = 2.0 * std::sqrt(1.0 + r[2][2] - r[0][0] - r[1][1]);
    q[3] = (r[1][0] - r[0][1]) / s;
    q[0] = (r[0][2] + r[2][0]) / s;
    q[1] = (r[1][2] + r[2][1]) / s;
    q[2] = 0.25 * s;
  }
  const double n = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  const double sign = q[3] < 0.0 ? -1.0 : 1.0;
  for (int i = 0; i < 4; ++i) q[i] *= sign / n;
}

}  // namespace va::so3
