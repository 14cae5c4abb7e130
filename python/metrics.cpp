// reproject.metrics: PSNR and SSIM (include/reproject/metrics.hpp) over NumPy arrays, documented
// on the package's wrappers (python/reproject/metrics.py).
//
// The arrays are read in place, whatever their strides (the library takes a row, a pixel and a
// channel stride), as long as the strides are whole, positive numbers of elements; anything else
// (a[::-1], a broadcast array) raises ValueError naming the fix. The GIL is released while the
// library computes.
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <cstdint>
#include <optional>
#include <string>

#include "arrays.hpp"
#include "bindings.hpp"
#include "counters.hpp"
#include "reproject/metrics.hpp"

namespace reproject::python {

namespace {

CallCounter& metric_calls() {
  static CallCounter counter;
  return counter;
}

template <class Work>
Status run_without_gil(Work&& work) {
  py::gil_scoped_release release;
  return metric_calls().count(work);
}

// ---------------------------------------------------------------------------------------------
// Arrays as the library's views.

[[noreturn]] void needs_copy(const py::array& a, const char* name, const char* why) {
  throw py::value_error(std::string(name) + ": " + describe(a) + " cannot be read in place (" + why +
                        "); pass numpy.ascontiguousarray(" + name + ")");
}

template <class T>
SampleView<T> samples_of(const py::array& a, const char* name) {
  if (a.ndim() != 2 && a.ndim() != 3) {
    throw py::value_error(std::string(name) + ": expected an (H, W) or (H, W, C) array, got " + describe(a));
  }
  const std::ptrdiff_t item = static_cast<std::ptrdiff_t>(sizeof(T));
  std::ptrdiff_t strides[3] = {0, 0, 0};
  int extents[3] = {1, 1, 1};
  for (py::ssize_t axis = 0; axis < a.ndim(); ++axis) {
    if (a.shape(axis) > INT32_MAX) throw py::value_error(std::string(name) + ": " + describe(a) + " is too large");
    extents[axis] = static_cast<int>(a.shape(axis));
    // An axis of one entry (or an empty array) reads no stride: numpy may give it any value.
    if (a.shape(axis) <= 1 || a.size() == 0) continue;
    const std::ptrdiff_t bytes = a.strides(axis);
    if (bytes <= 0) needs_copy(a, name, "a stride is negative or 0");
    if (bytes % item != 0) needs_copy(a, name, "a stride is not a whole number of elements");
    strides[axis] = bytes / item;
  }
  if (reinterpret_cast<std::uintptr_t>(a.data()) % alignof(T) != 0) needs_copy(a, name, "its data is not aligned");
  SampleView<T> view;
  view.data = static_cast<const T*>(a.data());
  view.height = extents[0];
  view.width = extents[1];
  view.channels = extents[2];
  view.row_stride = strides[0];
  view.pixel_stride = strides[1];
  view.channel_stride = strides[2];
  return view;
}

PlaneView<const std::uint8_t> mask_of(const py::object& mask, int height, int width) {
  if (mask.is_none()) return {};
  py::array m = py::array::ensure(mask);
  if (!m) throw py::type_error("mask: expected a bool or uint8 array");
  if (!has_dtype(m, py::dtype::of<bool>()) && !has_dtype(m, py::dtype::of<std::uint8_t>())) {
    throw py::type_error("mask: expected a bool or uint8 array, got " + describe(m));
  }
  if (m.ndim() != 2 || m.shape(0) != height || m.shape(1) != width) {
    throw py::value_error("mask: expected shape (" + std::to_string(height) + ", " + std::to_string(width) +
                          "), the images' height and width, got " + describe(m));
  }
  const PlaneView<std::uint8_t> rows = plane_view<std::uint8_t>(m, 0, 1, 0, "mask");
  return PlaneView<const std::uint8_t>{rows.data, rows.width, rows.height, rows.stride};
}

using Metric = Status (*)(const FloatSamples&, const FloatSamples&, const QualityOptions&, double*) noexcept;
using ByteMetric = Status (*)(const ByteSamples&, const ByteSamples&, const QualityOptions&, double*) noexcept;

double measure(Metric metric, ByteMetric byte_metric, const py::array& a, const py::array& b, const py::object& mask,
               std::optional<double> data_range) {
  const bool bytes = has_dtype(a, py::dtype::of<std::uint8_t>());
  if (!bytes && !has_dtype(a, py::dtype::of<float>())) {
    throw py::type_error("a: expected a float32 or uint8 array, got " + describe(a));
  }
  if (!has_dtype(b, a.dtype())) {
    throw py::type_error("b: expected a " + std::string(bytes ? "uint8" : "float32") + " array like a, got " + describe(b));
  }
  if (a.ndim() != b.ndim() || !std::equal(a.shape(), a.shape() + a.ndim(), b.shape())) {
    throw py::value_error("a and b differ in shape: a is " + describe(a) + ", b is " + describe(b));
  }
  QualityOptions options;
  options.data_range = data_range;
  options.mask = mask_of(mask, a.ndim() >= 1 ? static_cast<int>(a.shape(0)) : 0,
                         a.ndim() >= 2 ? static_cast<int>(a.shape(1)) : 0);
  double result = 0.0;
  Status status;
  if (bytes) {
    const ByteSamples va = samples_of<std::uint8_t>(a, "a"), vb = samples_of<std::uint8_t>(b, "b");
    status = run_without_gil([&] { return byte_metric(va, vb, options, &result); });
  } else {
    const FloatSamples va = samples_of<float>(a, "a"), vb = samples_of<float>(b, "b");
    status = run_without_gil([&] { return metric(va, vb, options, &result); });
  }
  raise_if_failed(status);
  return result;
}

}  // namespace

void bind_metrics(py::module_ m) {
  m.def(
      "psnr",
      [](const py::array& a, const py::array& b, const py::object& mask, std::optional<double> data_range) {
        return measure(&reproject::psnr, &reproject::psnr, a, b, mask, data_range);
      },
      py::arg("a"), py::arg("b"), py::arg("mask") = py::none(), py::arg("data_range") = py::none(),
      "The compiled reproject.metrics.psnr (documented there).");
  m.def(
      "ssim",
      [](const py::array& a, const py::array& b, const py::object& mask, std::optional<double> data_range) {
        return measure(&reproject::ssim, &reproject::ssim, a, b, mask, data_range);
      },
      py::arg("a"), py::arg("b"), py::arg("mask") = py::none(), py::arg("data_range") = py::none(),
      "The compiled reproject.metrics.ssim (documented there).");
  metric_calls().bind(m, "metric calls");
}

}  // namespace reproject::python
