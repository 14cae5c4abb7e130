// The Python module `reproject` (pybind11): the library over NumPy arrays.
//
// Arrays are passed to the library as views (src/python/arrays.hpp); outputs are new arrays or the
// caller's (`out=`). The library's own validation decides what is valid, and its message becomes
// a ValueError; wrong dtypes are TypeErrors. The GIL is released while the kernels run.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <limits>
#include <mutex>
#include <optional>
#include <string>

#include "arguments.hpp"
#include "arrays.hpp"
#include "bindings.hpp"
#include "interrupt.hpp"
#include "outputs.hpp"
#include "reproject/reproject.hpp"

namespace reproject::python {

void raise_if_failed(const Status& status) {
  if (!status.ok()) throw py::value_error(status.message());
}

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// ---------------------------------------------------------------------------------------------
// Names <-> enums: the library's parsers where it has them.

template <class Enum>
Enum parse_name(const std::string& name, bool (*parse)(const char*, Enum*), const char* what) {
  Enum value{};
  if (!parse(name.c_str(), &value)) throw py::value_error("unknown " + std::string(what) + " '" + name + "'");
  return value;
}

HoleFill parse_fill(const std::string& name) {
  if (name == "background") return HoleFill::background;
  if (name == "foreground") return HoleFill::foreground;
  if (name == "none") return HoleFill::none;
  throw py::value_error("unknown hole_fill '" + name + "' (background, foreground, none)");
}

EdgeMode parse_edge(const std::string& name) {
  if (name == "clamp") return EdgeMode::clamp;
  if (name == "none") return EdgeMode::none;
  if (name == "black") return EdgeMode::black;
  if (name == "mirror") return EdgeMode::mirror;
  throw py::value_error("unknown edge '" + name + "' (clamp, none, black, mirror)");
}

// ---------------------------------------------------------------------------------------------
// Test-only counters: how many calls are inside the GIL-released region at once, and an optional
// rendezvous that holds each call there until `want` calls are inside (or a timeout passes), so a
// test can prove two Python threads run the kernels together without measuring time.

struct Concurrency {
  std::mutex mutex;
  std::condition_variable changed;
  int inside = 0;
  int max_inside = 0;
  int rendezvous = 0;  // 0: off
  double timeout_seconds = 0.0;
};
Concurrency& concurrency() {
  static Concurrency c;
  return c;
}

// Runs `work` (GIL released), counted by the test-only counters.
template <class Work>
Status counted(Work& work) {
  Concurrency& c = concurrency();
  {
    std::unique_lock<std::mutex> lock(c.mutex);
    ++c.inside;
    c.max_inside = std::max(c.max_inside, c.inside);
    c.changed.notify_all();
    if (c.rendezvous > 0) {
      c.changed.wait_for(lock, std::chrono::duration<double>(c.timeout_seconds),
                         [&c] { return c.inside >= c.rendezvous; });
    }
  }
  const Status status = work();
  {
    std::lock_guard<std::mutex> lock(c.mutex);
    --c.inside;
  }
  return status;
}

// Runs `work` with the GIL released, counted: on the main thread, Ctrl-C (any signal handler that
// raises) sets `cancel` and raises KeyboardInterrupt within a poll and a block of rows
// (interrupt.hpp).
template <class Work>
Status run_without_gil(Work&& work, std::atomic<bool>& cancel) {
  return run_interruptible([&work] { return counted(work); }, cancel);
}

// ---------------------------------------------------------------------------------------------
// Results

struct Result {
  py::object color = py::none();
  py::object depth = py::none();
  py::object status = py::none();
  py::object source_x = py::none();
};

struct PairResult {
  Result left;
  Result right;
};

// ---------------------------------------------------------------------------------------------
// The decoder and the model from warp's keyword arguments.

DepthDecoder decoder_from(const std::optional<DepthDecoder>& decoder, const std::optional<std::string>& encoding,
                          std::optional<double> near_plane, std::optional<double> far_plane) {
  if (decoder) {
    if (encoding || near_plane || far_plane) {
      throw py::value_error("decoder= cannot be used with encoding=, near= or far=");
    }
    return *decoder;
  }
  const DepthEncoding e = parse_name<DepthEncoding>(encoding.value_or("linear"), parse_encoding, "encoding");
  if (e == DepthEncoding::linear || e == DepthEncoding::disparity) {
    if (near_plane || far_plane) {
      throw py::value_error(std::string("near= and far= cannot be used with the ") + to_string(e) + " encoding");
    }
  }
  return DepthDecoder::from_near_far(e, near_plane.value_or(kNaN), far_plane.value_or(kNaN));
}

ParallaxModel model_from(const std::optional<ParallaxModel>& model, const DepthDecoder& decoder,
                         std::optional<double> separation, std::optional<double> convergence,
                         const std::optional<std::string>& direction, int width, bool pair) {
  if (model) {
    if (separation || convergence || direction) {
      throw py::value_error("model= cannot be used with separation=, convergence= or direction=");
    }
    return *model;
  }
  if (decoder.encoding() == DepthEncoding::disparity) {
    if (pair) throw py::value_error("a disparity map belongs to one eye: warp_pair needs depth, not disparity");
    if (separation || convergence) {
      throw py::value_error("separation= and convergence= cannot be used with a disparity map (p = -/+ disparity)");
    }
    return ParallaxModel::from_disparity(
        parse_name<EyeDirection>(direction.value_or("left-to-right"), parse_direction, "direction"));
  }
  if (!convergence) throw py::value_error("convergence= is required (or model=, or a disparity map)");
  const EyeDirection d = pair ? EyeDirection::centre_to_right
                              : parse_name<EyeDirection>(direction.value_or("centre-to-right"), parse_direction,
                                                         "direction");
  if (pair && direction) throw py::value_error("warp_pair makes both eyes from the centre: no direction=");
  // An empty frame (width 0) is valid and writes nothing; its model is made for one column so that
  // separation and convergence are still checked (a stereo model needs a width >= 1).
  return ParallaxModel::from_stereo(separation.value_or(0.03), *convergence, std::max(width, 1), d);
}

Options options_from(const std::string& method, std::optional<double> max_negative_parallax, double hole_threshold,
                     const std::string& hole_fill, const std::string& edge, int guard,
                     std::optional<double> probe_parallax, int march_steps, int secant_max_steps,
                     const std::optional<std::string>& arch, int threads) {
  Options o;
  o.method = parse_name<Method>(method, parse_method, "method");
  if (max_negative_parallax) o.max_negative_parallax = float_argument(*max_negative_parallax, "max_negative_parallax");
  o.hole_threshold = float_argument(hole_threshold, "hole_threshold");
  o.hole_fill = parse_fill(hole_fill);
  o.edge = parse_edge(edge);
  o.guard = guard;
  if (probe_parallax) o.probe_parallax = float_argument(*probe_parallax, "probe_parallax");
  o.march_steps = march_steps;
  o.secant_max_steps = secant_max_steps;
  if (arch) o.arch = parse_name<Arch>(*arch, parse_arch, "arch");
  o.threads = threads;
  return o;
}

// ---------------------------------------------------------------------------------------------
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
    const DepthFormat format = parse_name<DepthFormat>(*depth_format, parse_depth_format, "depth_format");
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

// ---------------------------------------------------------------------------------------------
// Inputs and outputs as views

struct Source {
  SourceView view;
  int width = 0;
  int height = 0;
  ColorForm form = ColorForm::plane;
  int channels = 0;
  bool rgba = false;  // colour is interleaved RGBA
  ColorFormat color_format = ColorFormat::float32;
  DepthFormat depth_format = DepthFormat::float32;
  py::object keep;    // the planar copy of packed H x W x 2/3 colour, kept alive for the call
};

// Packed RGBA8 depth is (H, W, 4) bytes; every other depth format one element a pixel.
bool depth_has_channels(DepthFormat format) { return format == DepthFormat::rgba8_packed_linear; }

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

// The outputs of one eye: the arrays of `out` (a Result, an array for colour alone, or None:
// all four new) as a TargetView.
struct Target {
  TargetView view;
  Result result;
};

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

// The target's width: the source's less the guard band on each side, in 64 bits (2 guard
// overflows int near its limit, and a wrapped width would be allocated). An empty source makes
// an empty target, as the library does.
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

// ---------------------------------------------------------------------------------------------
// warp and warp_pair

#define REPROJECT_WARP_PARAMETERS                                                                                 \
  const std::string &color_space, const std::optional<std::string>&depth_format,                                  \
      const std::optional<std::pair<double, double>>&linear_range, const std::optional<std::string>&encoding,     \
      std::optional<double> near_plane, std::optional<double> far_plane,                                          \
      const std::optional<DepthDecoder>&decoder, std::optional<double> separation,                                \
      std::optional<double> convergence, const std::optional<std::string>&direction,                              \
      const std::optional<ParallaxModel>&model, const std::string &method,                                        \
      std::optional<double> max_negative_parallax, double hole_threshold, const std::string &hole_fill,           \
      const std::string &edge, int guard, std::optional<double> probe_parallax, int march_steps,                  \
      int secant_max_steps, const std::optional<std::string>&arch, int threads

Result warp(const py::array& color, const py::array& depth, REPROJECT_WARP_PARAMETERS, const py::object& out) {
  const Source s = source_from(color, depth, color_space, depth_format, linear_range);
  const DepthDecoder d = decoder_from(decoder, encoding, near_plane, far_plane);
  const Options o = options_from(method, max_negative_parallax, hole_threshold, hole_fill, edge, guard, probe_parallax,
                                 march_steps, secant_max_steps, arch, threads);
  const int width = target_width(s, guard);
  const ParallaxModel m = model_from(model, d, separation, convergence, direction, width, false);
  Target t = target_from(s, s.height, width, out, "out");
  std::atomic<bool> cancel{false};
  Options cancellable = o;
  cancellable.cancel = &cancel;
  raise_if_failed(run_without_gil([&] { return reproject::reproject(s.view, d, m, cancellable, t.view); }, cancel));
  return t.result;
}

PairResult warp_pair(const py::array& color, const py::array& depth, REPROJECT_WARP_PARAMETERS,
                     const py::object& out_left, const py::object& out_right) {
  const Source s = source_from(color, depth, color_space, depth_format, linear_range);
  const DepthDecoder d = decoder_from(decoder, encoding, near_plane, far_plane);
  const Options o = options_from(method, max_negative_parallax, hole_threshold, hole_fill, edge, guard, probe_parallax,
                                 march_steps, secant_max_steps, arch, threads);
  const int width = target_width(s, guard);
  const ParallaxModel m = model_from(model, d, separation, convergence, direction, width, true);
  Target left = target_from(s, s.height, width, out_left, "out_left");
  Target right = target_from(s, s.height, width, out_right, "out_right");
  std::atomic<bool> cancel{false};
  Options cancellable = o;
  cancellable.cancel = &cancel;
  raise_if_failed(run_without_gil(
      [&] { return reproject::reproject_pair(s.view, d, m, cancellable, left.view, right.view); }, cancel));
  return PairResult{left.result, right.result};
}

const char* kWarpDoc = R"doc(warp(color, depth, *, encoding, near, far, separation, convergence, direction, method, ...) -> Result

Synthesises another eye from one view (colour + depth): reproject() of reproject.hpp.

color: float32, (H, W), (H, W, C) or (C, H, W) with C = 1..4. Planes and (H, W, 4) arrays whose
  columns are consecutive are read in place (any row stride, crops included); packed (H, W, 2|3)
  colour (Pillow's layout) is copied once into planes, since the library has no such layout.
  Anything else (e.g. a[:, ::2]) raises ValueError.
  Engine colour, (H, W, 4) RGBA read in place (any row stride; each pixel's 4 channels consecutive):
  uint8 is rgba8, blended as the byte values (color_space='linear', the default), or rgba8_srgb
  with color_space='srgb' (R, G, B decoded from sRGB, blended in linear light, encoded back);
  float16 is rgba16f.
depth: float32 (H, W), read in place under the same rule. Engine depth buffers, read in place with
  any row stride: uint16 (H, W) is D16 (unorm16); uint32 (H, W) is D24S8 and needs
  depth_format='unorm24_s8' (depth in bits 0-23: D3D, Vulkan) or 's8_unorm24' (depth in bits 8-31:
  OpenGL); uint8 (H, W, 4) needs depth_format='rgba8_packed_linear' and linear_range=(near, far)
  (linear depth packed in R, G, B; use it with the linear encoding, the default).
  depth_format= may name any format; it must fit the dtype.
Depth decoder: encoding= (linear, standard, gl_ndc, reversed, reversed_infinite, infinite,
  disparity) with near=, far=; or decoder=Decoder. It decodes the value each format stores
  (u / 65535, u / 16777215, or the packed linear depth).
Parallax: separation= (default 0.03), convergence=, direction= (default centre-to-right; for a
  disparity map p = -d, left-to-right); or model=ParallaxModel.
Options as keyword arguments with the C++ names and defaults: method='exact',
  max_negative_parallax=None, hole_threshold=1.0, hole_fill='background', edge='clamp', guard=0,
  probe_parallax=None, march_steps=16, secant_max_steps=256, arch=None, threads=0.
out: None (new arrays), a Result of an earlier call (written in place: no allocation), or a colour
  array (then only colour is written). Its arrays must have the source's dtypes and shapes.
Returns a Result: color (the source's form and dtype), depth (the source depth's dtype and
format: stencil bits and the packed format's alpha are copied from the source pixel the output
interpolates from), status (uint8: 0 hit, 1 hole, 2 outside, 3 clipped), source_x (float32). The
GIL is released while the kernels run. Ctrl-C (KeyboardInterrupt, or any signal handler that
raises) stops a call made from the main thread within about 10 ms plus a block of rows; the
outputs it was writing are then unspecified.
Errors: TypeError for an argument of the wrong type or dtype (naming it and what it takes);
ValueError with the library's message for everything else.)doc";

// Adds the keyword arguments shared by warp and warp_pair, in the same order as the parameters.
template <class Function, class... Extra>
void def_warp(py::module_& m, const char* name, Function function, const char* doc, Extra... extra) {
  def_function(m, name, function, py::arg("color"), py::arg("depth"), py::kw_only(), py::arg("color_space") = "linear",
        py::arg("depth_format") = py::none(), py::arg("linear_range") = py::none(), py::arg("encoding") = py::none(),
        py::arg("near") = py::none(), py::arg("far") = py::none(), py::arg("decoder") = py::none(),
        py::arg("separation") = py::none(), py::arg("convergence") = py::none(), py::arg("direction") = py::none(),
        py::arg("model") = py::none(), py::arg("method") = "exact", py::arg("max_negative_parallax") = py::none(),
        py::arg("hole_threshold") = 1.0, py::arg("hole_fill") = "background", py::arg("edge") = "clamp",
        py::arg("guard") = 0, py::arg("probe_parallax") = py::none(), py::arg("march_steps") = 16,
        py::arg("secant_max_steps") = 256, py::arg("arch") = py::none(), py::arg("threads") = 0, extra..., doc);
}

}  // namespace

void bind_core(py::module_& m) {
  py::class_<Result>(m, "Result", "One eye's outputs: color, depth, status (uint8), source_x (float32).")
      .def(py::init<>())
      .def_readwrite("color", &Result::color)
      .def_readwrite("depth", &Result::depth)
      .def_readwrite("status", &Result::status)
      .def_readwrite("source_x", &Result::source_x)
      .def("__repr__", [](const Result& r) {
        // Shapes and dtypes, not the pixels.
        auto field = [](const char* name, const py::object& o) {
          if (o.is_none()) return std::string(name) + "=None";
          return std::string(name) + "=<" + py::str(o.attr("dtype")).cast<std::string>() + " " +
                 py::str(o.attr("shape")).cast<std::string>() + ">";
        };
        return "Result(" + field("color", r.color) + ", " + field("depth", r.depth) + ", " +
               field("status", r.status) + ", " + field("source_x", r.source_x) + ")";
      });
  py::class_<PairResult>(m, "PairResult", "Both eyes' Results; unpacks as (left, right).")
      .def_readwrite("left", &PairResult::left)
      .def_readwrite("right", &PairResult::right)
      .def("__iter__", [](const PairResult& p) { return py::iter(py::make_tuple(p.left, p.right)); });

  def_warp(m, "warp", &warp, kWarpDoc, py::arg("out") = py::none());
  def_warp(m, "warp_pair", &warp_pair,
           "warp_pair(color, depth, *, ...) -> PairResult\n\nThe centre view to both eyes in one call "
           "(reproject_pair): the right eye with sigma = +1/2 of the stereo camera (or model=, the centre-to-right "
           "model), the left with its mirror. Arguments as warp(); direction= is refused (ValueError), since the "
           "eyes are always the left and the right one of the centre view, and so is a disparity map (it belongs "
           "to one eye). out_left=, out_right= as out=. Ctrl-C stops the call as it stops warp().",
           py::arg("out_left") = py::none(), py::arg("out_right") = py::none());

  def_function(m, "arch_supported",
               [](const std::string& arch) { return arch_supported(parse_name<Arch>(arch, parse_arch, "arch")); },
               py::arg("arch"), "Whether the kernels for `arch` (one of `arches`) are compiled in and this CPU runs them.");
  m.def("selected_arch", [] { return std::string(to_string(selected_arch())); },
        "The instruction set calls use when arch= is unset (REPROJECT_FORCE_ARCH overrides the choice).");
  m.attr("methods") = py::make_tuple("scanline", "march16", "single", "secant", "exact");
  // Every instruction set the library names, whether or not this build and CPU run it.
  py::tuple arches(kArchCount);
  for (int a = 0; a < kArchCount; ++a) arches[a] = to_string(static_cast<Arch>(a));
  m.attr("arches") = arches;

  m.def("_debug_max_concurrent_calls", [] {
    std::lock_guard<std::mutex> lock(concurrency().mutex);
    return concurrency().max_inside;
  }, "Test only: the most calls that were inside the library (GIL released) at once since the last reset.");
  m.def("_debug_reset_counters", [](int rendezvous, double timeout_seconds) {
    std::lock_guard<std::mutex> lock(concurrency().mutex);
    concurrency().max_inside = concurrency().inside;
    concurrency().rendezvous = rendezvous;
    concurrency().timeout_seconds = timeout_seconds;
  }, py::arg("rendezvous") = 0, py::arg("timeout_seconds") = 0.0,
        "Test only: resets the counter; with rendezvous = n, each call waits (GIL released, at most timeout_seconds) "
        "until n calls are inside.");
}

}  // namespace reproject::python

PYBIND11_MODULE(reproject, m) {
  m.doc() = "reproject: horizontal stereo reprojection (synthesise the other eye from colour + depth) over NumPy arrays.";
  reproject::python::bind_models(m);
  reproject::python::bind_core(m);
  reproject::python::bind_stereo(m);
  reproject::python::bind_scenes(m);
  reproject::python::bind_metrics(m.def_submodule("metrics", "Image quality: PSNR and SSIM"));
}
