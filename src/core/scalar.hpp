// Scalar helpers the kernels share, each once: Python's max and min on floats, and gaits.planar's
// smoothstep and lift_profile. The kernels are ports of Python code, operation by operation, so
// these keep Python's semantics to the bit.
#pragma once

#include <cmath>

namespace va {

// Python's max(a, b) and min(a, b) on floats: a unless b is larger (smaller). The order of the
// arguments matters with a NaN (max(nan, 1.0) is nan, max(1.0, nan) is 1.0) and on a tie of 0.0
// and -0.0 (a is returned): the ports keep the reference's order.
inline double py_max(double a, double b) { return b > a ? b : a; }
inline double py_min(double a, double b) { return b < a ? b : a; }

// gaits.planar.smoothstep.
inline double smoothstep(double s) {
  s = py_min(py_max(s, 0.0), 1.0);
  return s * s * (3.0 - 2.0 * s);
}

// gaits.planar.lift_profile (math.pi as pi below: the same double as M_PI).
inline double lift_profile(double phase, double peak) {
  constexpr double pi = 3.141592653589793;
  static_assert(pi == M_PI, "math.pi is the double nearest to pi");
  phase = py_min(py_max(phase, 0.0), 1.0);
  if (phase < peak) return std::sin(0.5 * pi * phase / peak);
  return std::cos(0.5 * pi * (phase - peak) / (1.0 - peak));
}

// Python's math.hypot(x, y) (CPython's vector_norm: an error-free sum of the squares and a
// differential correction of the square root), which may differ from libm's hypot in the last
// bit. An infinite argument gives inf, a NaN (without one) NaN, as Python's.
inline double py_hypot(double x, double y) {
  if (!std::isfinite(x) || !std::isfinite(y)) return std::hypot(x, y);
  const double values[2] = {std::fabs(x), std::fabs(y)};
  const double max = values[1] > values[0] ? values[1] : values[0];
  if (max == 0.0) return max;
  int max_e;
  std::frexp(max, &max_e);
  if (max_e < -1023) {  // subnormal: scaled to normals first
    const double tiny = 2.2250738585072014e-308;
    return tiny * py_hypot(x / tiny, y / tiny);
  }
  const double scale = std::ldexp(1.0, -max_e);
  double csum = 1.0, frac1 = 0.0, frac2 = 0.0;
  for (const double value : values) {
    const double v = value * scale;
    const double hi = v * v, lo = std::fma(v, v, -hi);  // the exact square
    const double sum = csum + hi;
    frac2 += (csum - sum) + hi;
    csum = sum;
    frac1 += lo;
  }
  double h = std::sqrt(csum - 1.0 + (frac1 + frac2));
  const double hi = -h * h, lo = std::fma(-h, h, -hi);
  const double sum = csum + hi;
  frac2 += (csum - sum) + hi;
  csum = sum;
  frac1 += lo;
  const double correction = csum - 1.0 + (frac1 + frac2);
  h += correction / (2.0 * h);
  return h / scale;
}

}  // namespace va
