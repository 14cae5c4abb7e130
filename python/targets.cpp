#include "targets.hpp"

#include <pybind11/numpy.h>

#include <cstdint>
#include <string>
#include <vector>

#include "arguments.hpp"
#include "arrays.hpp"
#include "outputs.hpp"

namespace reproject::python {

namespace {

py::array new_array(std::initializer_list<py::ssize_t> shape, bool bytes = false) {
  if (bytes) return py::array_t<std::uint8_t>(std::vector<py::ssize_t>(shape));
  return py::array_t<float>(std::vector<py::ssize_t>(shape));
}

// A new colour output in the source's form and dtype. Packed H x W x C float colour with C != 4
// is returned as an H x W x C view of C planes (numpy.moveaxis), which the library writes without
// a copy.
py::array new_color(const Source& s, int height, int width) {
  if (s.color_format != ColorFormat::float32) return py::array(dtype_of(s.color_format), {height, width, 4});
  switch (s.form) {
    case ColorForm::plane: return new_array({height, width});
    case ColorForm::chw: return new_array({s.channels, height, width});
    case ColorForm::hwc:
      if (s.rgba) return new_array({height, width, 4});
      return py::module_::import("numpy").attr("moveaxis")(new_array({s.channels, height, width}), 0, -1);
  }
  return py::array();
}

// A new depth output in the source's dtype: (H, W), or (H, W, 4) for packed RGBA8 depth.
py::array new_depth(const Source& s, int height, int width) {
  if (depth_has_channels(s.depth_format)) return py::array(dtype_of(s.depth_format), {height, width, 4});
  return py::array(dtype_of(s.depth_format), {height, width});
}

// An output in an engine format: a writable array of the source's dtype, of shape (H, W), or
// (H, W, 4) when its pixels have channels, as bytes (any row stride).
PlaneView<std::uint8_t> output_pixels(const py::object& o, const py::dtype& dtype, bool channels, int height,
                                      int width, const std::string& label) {
  const std::vector<py::ssize_t> shape = channels ? std::vector<py::ssize_t>{height, width, 4}
                                                  : std::vector<py::ssize_t>{height, width};
  return pixel_rows(output_array(o, dtype, shape, label), label.c_str());
}

// The shape of the source's colour form (what new_color makes).
std::vector<py::ssize_t> color_shape(const Source& s, int height, int width) {
  if (s.color_format != ColorFormat::float32) return {height, width, 4};
  switch (s.form) {
    case ColorForm::plane: return {height, width};
    case ColorForm::chw: return {s.channels, height, width};
    case ColorForm::hwc: return {height, width, s.channels};
  }
  return {};
}

// A float colour output: float32, laid out like the source colour.
MutableColorView float_color_output(const Source& s, const py::object& o, int height, int width,
                                    const std::string& label) {
  const py::array color = output_array(o, dtype_of(ColorFormat::float32), color_shape(s, height, width), label,
                                       "laid out like the source colour");
  MutableColorView view;
  if (!color_view(color, s.form, label.c_str(), &view)) {
    throw py::value_error(label + ": " + describe(color) +
                          " packs its pixels, which the library cannot write in place: pass the Result of an earlier "
                          "call, or numpy.moveaxis of a (C, H, W) array");
  }
  return view;
}

}  // namespace

Target target_from(const Source& s, int height, int width, const py::object& out, const char* name) {
  Target t;
  if (out.is_none()) {
    t.result.color = new_color(s, height, width);
    t.result.depth = new_depth(s, height, width);
    t.result.status = new_array({height, width}, true);
    t.result.source_x = new_array({height, width});
  } else if (py::isinstance<Result>(out)) {
    t.result = out.cast<Result>();
  } else if (py::isinstance<py::array>(out)) {
    t.result.color = out;
  } else {
    throw py::type_error(std::string(name) + ": got " + short_value(out) + "; it takes a Result of an earlier call, "
                         "a colour array or None");
  }
  const std::string prefix = std::string(name) + ".";
  if (s.color_format == ColorFormat::float32) {
    t.view.color = float_color_output(s, t.result.color, height, width, prefix + "color");
  } else {
    const PlaneView<std::uint8_t> rows =
        output_pixels(t.result.color, dtype_of(s.color_format), true, height, width, prefix + "color");
    t.view.color = MutableColorView::packed(s.color_format, rows.data, rows.width, rows.height, rows.stride);
  }
  auto float_plane = [&](const py::object& o, const char* field) {
    MutableFloatPlane plane;
    if (o.is_none()) return plane;
    const std::string label = prefix + field;
    const py::array a = output_array(o, dtype_of(DepthFormat::float32), {height, width}, label);
    return plane_view<float>(a, 0, 1, 0, label.c_str());
  };
  if (s.depth_format == DepthFormat::float32) {
    t.view.depth = float_plane(t.result.depth, "depth");
  } else if (!t.result.depth.is_none()) {
    // Written in the source's format (packed depth with the source's range: the library reads no other).
    const PlaneView<std::uint8_t> rows = output_pixels(t.result.depth, dtype_of(s.depth_format),
                                                       depth_has_channels(s.depth_format), height, width,
                                                       prefix + "depth");
    t.view.depth_buffer = MutableDepthBuffer::of(s.depth_format, rows.data, rows.width, rows.height, rows.stride);
  }
  t.view.source_x = float_plane(t.result.source_x, "source_x");
  if (!t.result.status.is_none()) {
    const std::string label = prefix + "status";
    const py::array a = output_array(t.result.status, py::dtype::of<std::uint8_t>(), {height, width}, label);
    t.view.status = plane_view<std::uint8_t>(a, 0, 1, 0, label.c_str());
  }
  return t;
}

int target_width(const Source& s, int guard) {
  if (guard < 0) throw py::value_error("guard: " + std::to_string(guard) + " is negative: pass 0 or more columns");
  if (s.width == 0) return 0;
  const long long width = static_cast<long long>(s.width) - 2LL * guard;
  if (width < 1) {
    throw py::value_error("guard: " + std::to_string(guard) + " columns on each side leave no target columns of a source " +
                          std::to_string(s.width) + " wide: pass at most " + std::to_string((s.width - 1) / 2));
  }
  return static_cast<int>(width);
}

}  // namespace reproject::python
