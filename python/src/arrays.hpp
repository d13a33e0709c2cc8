// numpy arrays in and out of the module. Columns arrive as 1-D arrays of float32 or float64 with
// any stride (a column of a C-order 2-D array is a strided view), and are converted once, into the
// float64 columns the library's problems hold; results leave as numpy arrays that own their data.
#pragma once

#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>

#include <cstring>
#include <string>
#include <vector>

#include "shaderfit/core/error.hpp"

namespace shaderfit::python {

namespace nb = nanobind;

// A 1-D CPU array of any dtype and stride; read-only arrays are accepted.
using Column = nb::ndarray<nb::ndim<1>, nb::device::cpu, nb::ro>;
using OutArray = nb::ndarray<nb::numpy, double, nb::ndim<1>>;

// The column as float64: the one copy a column costs. Throws Error located at `where` for a
// dtype other than float32 and float64 (the Python layer converts the others first).
inline std::vector<double> to_doubles(const Column& a, const std::string& where) {
  const std::size_t n = a.shape(0);
  const std::int64_t stride = a.stride(0);
  std::vector<double> out(n);
  if (a.dtype() == nb::dtype<double>()) {
    const auto* p = static_cast<const double*>(a.data());
    if (stride == 1 && n > 0) {
      std::memcpy(out.data(), p, n * sizeof(double));
    } else {
      for (std::size_t i = 0; i < n; ++i) out[i] = p[static_cast<std::int64_t>(i) * stride];
    }
  } else if (a.dtype() == nb::dtype<float>()) {
    const auto* p = static_cast<const float*>(a.data());
    for (std::size_t i = 0; i < n; ++i) out[i] = p[static_cast<std::int64_t>(i) * stride];
  } else {
    throw Error("expected float32 or float64 values", {where});
  }
  return out;
}

inline std::vector<std::vector<double>> to_columns(const std::vector<Column>& columns,
                                                   const std::vector<std::string>& names) {
  std::vector<std::vector<double>> out;
  out.reserve(columns.size());
  for (std::size_t i = 0; i < columns.size(); ++i)
    out.push_back(to_doubles(columns[i], i < names.size() ? names[i] : "X"));
  return out;
}

// A numpy array that owns `values`.
inline OutArray to_numpy(std::vector<double> values) {
  auto* owned = new std::vector<double>(std::move(values));
  nb::capsule owner(owned, [](void* p) noexcept { delete static_cast<std::vector<double>*>(p); });
  return OutArray(owned->data(), {owned->size()}, owner);
}

}  // namespace shaderfit::python
