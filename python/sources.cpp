#include "sources.hpp"

#include <cstdint>

#include "arguments.hpp"
#include "names.hpp"

namespace reproject::python {

// Engine-native formats (formats.hpp) as NumPy dtypes. Their buffers are read and written in
// place: the library converts in registers, so the module never converts a pixel.

py::dtype dtype_of(ColorFormat format) {
  switch (format) {
    case ColorFormat::float32: return py::dtype::of<float>();
    case ColorFormat::rgba8:
    case ColorFormat::rgba8_srgb: return py::dtype::of<std::uint8_t>();
    case ColorFormat::rgba16f: return py::dtype("float16");
  }
  return py::dtype::of<float>();
}

py::dtype dtype_of(DepthFormat format) {
  switch (format) {
    case DepthFormat::float32: return py::dtype::of<float>();
    case DepthFormat::unorm16: return py::dtype::of<std::uint16_t>();
    case DepthFormat::unorm24_s8:
    case DepthFormat::s8_unorm24: return py::dtype::of<std::uint32_t>();
    case DepthFormat::rgba8_packed_linear: return py::dtype::of<std::uint8_t>();
  }
  return py::dtype::of<float>();
}

namespace {

std::string name_of(const py::dtype& dtype) { return py::str(dtype.attr("name")).cast<std::string>(); }

// How to get from `a`'s dtype to an accepted one, when there is a lossless way: the same type in
// the other byte order (e.g. '>u2' from a file) only needs the native order. Anything else needs
// the caller to know what the values mean (a cast of integer depth codes to float would read the
// codes as depths), so no conversion is suggested.
std::string dtype_hint(const py::array& a) {
  const py::dtype native = a.dtype().attr("newbyteorder")("=").cast<py::dtype>();
  if (native.equal(a.dtype())) return "";
  // The dtypes taken are those of the formats (dtype_of), float32 among them.
  bool taken = false;
  for (int f = 0; f < kColorFormatCount; ++f) taken = taken || native.equal(dtype_of(static_cast<ColorFormat>(f)));
  for (int f = 0; f < kDepthFormatCount; ++f) taken = taken || native.equal(dtype_of(static_cast<DepthFormat>(f)));
  return taken ? "; its byte order is not the machine's: pass a.astype(a.dtype.newbyteorder('='))" : "";
}

// The colour's format: its dtype, and for bytes the colour space they hold.
ColorFormat color_format_of(const py::array& color, const std::string& color_space) {
  if (color_space != "linear" && color_space != "srgb") {
    throw py::value_error("unknown color_space '" + color_space + "' (linear, srgb)");
  }
  const bool srgb = color_space == "srgb";
  if (has_dtype(color, dtype_of(ColorFormat::rgba8))) return srgb ? ColorFormat::rgba8_srgb : ColorFormat::rgba8;
  ColorFormat format = ColorFormat::float32;
  if (has_dtype(color, dtype_of(ColorFormat::rgba16f))) {
    format = ColorFormat::rgba16f;
  } else if (!has_dtype(color, dtype_of(ColorFormat::float32))) {
    throw py::type_error("color: expected a float32 array, got " + describe(color) +
                         "; the accepted dtypes are float32, and uint8 or float16 as (H, W, 4) RGBA" +
                         dtype_hint(color));
  }
  // Float values are linear already; only bytes are sRGB-encoded.
  if (srgb) throw py::value_error("color: color_space='srgb' is for uint8 colour, got " + describe(color));
  return format;
}

// The depth's format: named by depth_format=, or decided by the dtype where only one fits.
DepthFormat depth_format_of(const py::array& depth, const std::optional<std::string>& depth_format) {
  if (depth_format) {
    const DepthFormat format = parse_name(*depth_format, parse_depth_format, kDepthFormatCount, "depth_format");
    if (!has_dtype(depth, dtype_of(format))) {
      throw py::type_error("depth: depth_format='" + *depth_format + "' reads a " + name_of(dtype_of(format)) +
                           " array in the machine's byte order, got " + describe(depth) + dtype_hint(depth));
    }
    return format;
  }
  if (has_dtype(depth, dtype_of(DepthFormat::float32))) return DepthFormat::float32;
  if (has_dtype(depth, dtype_of(DepthFormat::unorm16))) return DepthFormat::unorm16;
  if (has_dtype(depth, dtype_of(DepthFormat::unorm24_s8))) {
    // D24S8 words come in two layouts, and nothing in the data tells them apart.
    throw py::value_error("depth: a uint32 array is D24S8 depth, whose layouts differ: pass "
                          "depth_format='unorm24_s8' (depth in bits 0-23, stencil in bits 24-31: D3D's and Vulkan's "
                          "D24_UNORM_S8_UINT) or depth_format='s8_unorm24' (stencil in bits 0-7, depth in bits 8-31: "
                          "OpenGL's GL_UNSIGNED_INT_24_8)");
  }
  if (has_dtype(depth, dtype_of(DepthFormat::rgba8_packed_linear))) {
    throw py::value_error("depth: a uint8 array is read as packed RGBA8 linear depth only when asked: pass "
                          "depth_format='rgba8_packed_linear' and linear_range=(near, far)");
  }
  throw py::type_error("depth: expected a float32 array, got " + describe(depth) +
                       "; the accepted dtypes are float32 (the stored depth value), uint16 (D16 codes) and uint32 "
                       "(D24S8 words) as (H, W), and uint8 as (H, W, 4) packed linear depth" + dtype_hint(depth));
}

}  // namespace

Source source_from(const py::array& color, const py::array& depth, const std::string& color_space,
                   const std::optional<std::string>& depth_format,
                   const std::optional<std::pair<double, double>>& linear_range) {
  Source s;
  s.color_format = color_format_of(color, color_space);
  s.depth_format = depth_format_of(depth, depth_format);
  if (depth_has_channels(s.depth_format)) {
    if (depth.ndim() != 3 || depth.shape(2) != 4) {
      throw py::value_error("depth: rgba8_packed_linear depth is an (H, W, 4) array, got " + describe(depth));
    }
    if (!linear_range) {
      throw py::value_error("depth: rgba8_packed_linear needs linear_range=(near, far), the linear depths its "
                            "values 0 and 1 stand for");
    }
  } else {
    if (depth.ndim() != 2) throw py::value_error("depth: expected an (H, W) array, got " + describe(depth));
    if (linear_range) throw py::value_error("linear_range= is for depth_format='rgba8_packed_linear' only");
  }
  if (s.depth_format == DepthFormat::float32) {
    s.view.depth = plane_view<const float>(depth, 0, 1, 0, "depth");
    s.width = s.view.depth.width;
    s.height = s.view.depth.height;
  } else {
    const PlaneView<std::uint8_t> rows = pixel_rows(depth, "depth");
    s.view.depth_buffer = DepthBuffer::of(s.depth_format, rows.data, rows.width, rows.height, rows.stride);
    if (linear_range) {  // checked by the library (finite, not empty)
      s.view.depth_buffer.linear_near = float_argument(linear_range->first, "linear_range");
      s.view.depth_buffer.linear_far = float_argument(linear_range->second, "linear_range");
    }
    s.width = rows.width;
    s.height = rows.height;
  }
  if (s.color_format != ColorFormat::float32) {
    if (color.ndim() != 3 || color.shape(0) != s.height || color.shape(1) != s.width || color.shape(2) != 4) {
      throw py::value_error(std::string("color: ") + name_of(color.dtype()) + " colour is RGBA: expected shape (" +
                            std::to_string(s.height) + ", " + std::to_string(s.width) + ", 4), got " +
                            describe(color) + " (Pillow: Image.convert('RGBA'))");
    }
    const PlaneView<std::uint8_t> rows = pixel_rows(color, "color");
    s.view.color = ColorView::packed(s.color_format, rows.data, rows.width, rows.height, rows.stride);
    s.form = ColorForm::hwc;
    s.channels = 4;
    s.rgba = true;
    return s;
  }
  s.form = color_form(color, s.height, s.width, "color");
  s.channels = channel_count(color, s.form);
  if (!color_view(color, s.form, "color", &s.view.color)) {
    // Packed H x W x 2 or 3: the library reads planes or RGBA, so this one layout is copied.
    py::module_ np = py::module_::import("numpy");
    py::array planes = np.attr("ascontiguousarray")(np.attr("moveaxis")(color, -1, 0));
    s.keep = planes;
    color_view(planes, ColorForm::chw, "color", &s.view.color);
  }
  s.rgba = s.view.color.layout == ColorLayout::interleaved_rgba;
  return s;
}

}  // namespace reproject::python
