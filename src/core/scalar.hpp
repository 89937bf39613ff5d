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

}  // namespace va
