// What the binding files (bind_*.hpp, bind_*.cpp) share: the numpy array types the kernels read
// and write, the argument check that raises ValueError, and numpy arrays made of C++ buffers.
// Only the binding files know Python; the kernels (the other headers) are plain C++17.
//
// The bindings live in va::py, a named namespace and not an anonymous one: a class bound in one
// file (Tree, QP, SpringTick) is an argument in another's bindings, and nanobind finds a bound
// class by its C++ type, which must then be the same type in every file.
#pragma once

#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>

#include <cstdint>
#include <memory>
#include <stdexcept>
#include <vector>

namespace nb = nanobind;

namespace va::py {

using namespace nb::literals;

using F1 = nb::ndarray<const double, nb::numpy, nb::ndim<1>, nb::c_contig, nb::device::cpu>;
using F2 = nb::ndarray<const double, nb::numpy, nb::ndim<2>, nb::c_contig, nb::device::cpu>;
using I1 = nb::ndarray<const std::int64_t, nb::numpy, nb::ndim<1>, nb::c_contig, nb::device::cpu>;
using I2 = nb::ndarray<const std::int64_t, nb::numpy, nb::ndim<2>, nb::c_contig, nb::device::cpu>;
using F3 = nb::ndarray<const double, nb::numpy, nb::ndim<3>, nb::c_contig, nb::device::cpu>;
using B1 = nb::ndarray<const bool, nb::numpy, nb::ndim<1>, nb::c_contig, nb::device::cpu>;
// Arrays the kernels write into: never converted (a converted copy would take the writes).
using MF1 = nb::ndarray<double, nb::numpy, nb::ndim<1>, nb::c_contig, nb::device::cpu>;
using MI1 = nb::ndarray<std::int64_t, nb::numpy, nb::ndim<1>, nb::c_contig, nb::device::cpu>;
using Owned = nb::ndarray<nb::numpy, double, nb::ndim<1>>;
using Owned2 = nb::ndarray<nb::numpy, double, nb::ndim<2>>;
// Any array (Distribution.checked_tick casts its arguments without converting them).
using Any = nb::ndarray<nb::ro, nb::device::cpu>;

inline void require(bool ok, const char* what) {
  if (!ok) throw std::invalid_argument(what);
}
inline std::int64_t length(const F1& a) { return static_cast<std::int64_t>(a.shape(0)); }
inline std::int64_t length(const MF1& a) { return static_cast<std::int64_t>(a.shape(0)); }
inline std::int64_t len(const I1& a) { return static_cast<std::int64_t>(a.shape(0)); }

// A new numpy array of `size` doubles that owns `data` (allocated with new[]).
inline Owned owned(std::unique_ptr<double[]> data, std::size_t size) {
  double* raw = data.release();
  nb::capsule owner(raw, [](void* p) noexcept { delete[] static_cast<double*>(p); });
  return Owned(raw, {size}, owner);
}

template <typename T, typename A>
std::vector<T> copy(const A& a) {
  return std::vector<T>(a.data(), a.data() + a.size());
}
}  // namespace va::py
