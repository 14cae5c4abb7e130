// Validation and view normalisation, once at a call's entry (src/validate.hpp; the checks and
// their order: docs/ERRORS.md). Nothing here touches a pixel; sizes and strides are checked for
// overflow (src/view_bounds.hpp) before any byte count is formed from them.
#include "src/validate.hpp"

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <type_traits>

#include "src/view_bounds.hpp"

namespace reproject {
namespace detail {
namespace {

// Widths above this would make integer column coordinates inexact in float.
constexpr int kMaxWidth = 1 << 22;

// A view's rows as bytes (view_bounds.hpp), with the name its messages use.
struct NamedView {
  detail::ViewBytes bytes;
  const char* name = "";
};

template <class T>
NamedView named(const PlaneView<T>& plane, int per_pixel, const char* name) {
  return NamedView{detail::view_bytes(plane, per_pixel), name};
}
template <class Byte>
NamedView named(const DepthBufferT<Byte>& depth, const char* name) {
  return named(PlaneView<Byte>{depth.data, depth.width, depth.height, depth.stride}, bytes_per_pixel(depth.format), name);
}
template <class T>
int color_views(const ColorViewT<T>& color, NamedView* out, const char* name) {
  if (color.format != ColorFormat::float32) {
    out[0] = named(color.pixels, bytes_per_pixel(color.format), name);
    return 1;
  }
  const bool interleaved = color.layout == ColorLayout::interleaved_rgba;
  for (int c = 0; c < (interleaved ? 1 : color.channels); ++c) out[c] = named(color.plane[c], interleaved ? 4 : 1, name);
  return interleaved ? 1 : color.channels;
}

// The source depth's size, without forming its stride in bytes (normalised_source below does,
// which must wait until the stride is checked).
struct Size {
  int width = 0;
  int height = 0;
};
Size depth_size(const SourceView& source) {
  if (source.depth_buffer.data != nullptr) return Size{source.depth_buffer.width, source.depth_buffer.height};
  return Size{source.depth.width, source.depth.height};
}

template <class T>
Status check_plane(const PlaneView<T>& plane, int width, int height, int elements_per_pixel, const char* name,
                   const char* unit = "elements") {
  if (plane.data == nullptr) return Status(StatusCode::null_pointer, "%s: data is null", name);
  if (plane.width < 0 || plane.height < 0)
    return Status(StatusCode::invalid_size, "%s: negative size %dx%d", name, plane.width, plane.height);
  if (plane.width != width || plane.height != height)
    return Status(StatusCode::size_mismatch, "%s: size %dx%d, expected %dx%d", name, plane.width, plane.height, width, height);
  return detail::check_view_bytes(plane, elements_per_pixel, name, unit);
}

template <class T>
Status check_color(const ColorViewT<T>& color, int width, int height, const char* name) {
  if (color.layout != ColorLayout::planar && color.layout != ColorLayout::interleaved_rgba)
    return Status(StatusCode::invalid_option, "%s: unknown colour layout %d", name, static_cast<int>(color.layout));
  if (static_cast<unsigned>(color.format) >= static_cast<unsigned>(kColorFormatCount))
    return Status(StatusCode::invalid_option, "%s: unknown colour format %d", name, static_cast<int>(color.format));
  const bool interleaved = color.layout == ColorLayout::interleaved_rgba;
  if (color.format != ColorFormat::float32) {
    // Packed RGBA pixels in an engine format (ColorView::packed).
    if (!interleaved || color.channels != 4)
      return Status(StatusCode::size_mismatch, "%s: %s is interleaved RGBA (4 channels); this view says %d %s", name,
                    to_string(color.format), color.channels, interleaved ? "interleaved" : "planar");
    if (Status status = check_plane(color.pixels, width, height, bytes_per_pixel(color.format), "pixels", "bytes"); !status.ok())
      return Status(status.code(), "%s %s %s", name, to_string(color.format), status.message());
    return Status();
  }
  if (interleaved ? color.channels != 4 : (color.channels < 1 || color.channels > 4))
    return Status(StatusCode::size_mismatch, "%s: %d channels (planar takes 1..4, interleaved RGBA 4)", name, color.channels);
  static const char* const kPlaneNames[4] = {"plane 0", "plane 1", "plane 2", "plane 3"};
  for (int c = 0; c < (interleaved ? 1 : color.channels); ++c) {
    if (Status status = check_plane(color.plane[c], width, height, interleaved ? 4 : 1, kPlaneNames[c]); !status.ok())
      return Status(status.code(), "%s %s", name, status.message());
  }
  return Status();
}

// A depth buffer (source or output) of the frame's size; strides in bytes.
// A source's rgba8_packed_linear range is checked; a target's is not read (the output is stored
// with the source's range).
template <class Byte>
Status check_depth_buffer(const DepthBufferT<Byte>& depth, int width, int height, const char* name) {
  if (static_cast<unsigned>(depth.format) >= static_cast<unsigned>(kDepthFormatCount))
    return Status(StatusCode::invalid_option, "%s: unknown depth format %d", name, static_cast<int>(depth.format));
  const PlaneView<Byte> bytes{depth.data, depth.width, depth.height, depth.stride};
  if (Status status = check_plane(bytes, width, height, bytes_per_pixel(depth.format), name, "bytes"); !status.ok())
    return Status(status.code(), "%s (%s)", status.message(), to_string(depth.format));
  if (depth.format == DepthFormat::float32 &&
      (reinterpret_cast<std::uintptr_t>(depth.data) % alignof(float) != 0 || depth.stride % 4 != 0))
    return Status(StatusCode::invalid_stride, "%s: float32 depth rows must start on 4-byte boundaries (data 0x%llx, stride %td bytes)",
                  name, static_cast<unsigned long long>(reinterpret_cast<std::uintptr_t>(depth.data)), depth.stride);
  if (std::is_const<Byte>::value && depth.format == DepthFormat::rgba8_packed_linear &&
      !(std::isfinite(depth.linear_near) && std::isfinite(depth.linear_far) && depth.linear_far != depth.linear_near &&
        std::isfinite(depth.linear_far - depth.linear_near)))
    return Status(StatusCode::invalid_option, "%s: rgba8_packed_linear range [%g, %g] must be finite, not empty, "
                  "and its length a finite float", name, depth.linear_near, depth.linear_far);
  return Status();
}

// Depth is given once: the float plane or the depth buffer.
template <class View>
Status check_one_depth(const View& view, const char* name) {
  if (view.depth.data != nullptr && view.depth_buffer.data != nullptr)
    return Status(StatusCode::invalid_option, "%s: both depth (a float plane) and depth_buffer are set; set one", name);
  return Status();
}

}  // namespace

Status check_options(const Options& options) {
  if (static_cast<unsigned>(options.method) >= static_cast<unsigned>(kMethodCount))
    return Status(StatusCode::invalid_option, "method: unknown value %d", static_cast<int>(options.method));
  if (options.hole_fill != HoleFill::background && options.hole_fill != HoleFill::foreground && options.hole_fill != HoleFill::none)
    return Status(StatusCode::invalid_option, "hole_fill: unknown value %d", static_cast<int>(options.hole_fill));
  if (static_cast<unsigned>(options.edge) > static_cast<unsigned>(EdgeMode::mirror))
    return Status(StatusCode::invalid_option, "edge: unknown value %d", static_cast<int>(options.edge));
  if (!(options.hole_threshold >= 0.0f) || !std::isfinite(options.hole_threshold))
    return Status(StatusCode::invalid_option, "hole_threshold: %g is not a finite value >= 0", options.hole_threshold);
  if (options.guard < 0) return Status(StatusCode::invalid_option, "guard: %d is negative", options.guard);
  if (options.march_steps < 1 || options.march_steps > 1024)
    return Status(StatusCode::invalid_option, "march_steps: %d is outside 1..1024", options.march_steps);
  if (options.secant_max_steps < 1 || options.secant_max_steps > 4096)
    return Status(StatusCode::invalid_option, "secant_max_steps: %d is outside 1..4096", options.secant_max_steps);
  if (options.max_negative_parallax &&
      (!(*options.max_negative_parallax >= 0.0f) || !std::isfinite(*options.max_negative_parallax)))
    return Status(StatusCode::invalid_option, "max_negative_parallax: %g is not a finite value >= 0",
                  *options.max_negative_parallax);
  if (options.probe_parallax && !std::isfinite(*options.probe_parallax))
    return Status(StatusCode::invalid_option, "probe_parallax: %g is not finite", *options.probe_parallax);
  if (options.arch && !arch_supported(*options.arch))
    return Status(StatusCode::invalid_option, "arch: %s is not supported by this build and CPU", to_string(*options.arch));
  if (options.threads < 0) return Status(StatusCode::invalid_option, "threads: %d is negative", options.threads);
  return Status();
}

Status check_jobs(const ParallelFor& jobs) {
  if (jobs.run == nullptr) return Status(StatusCode::invalid_option, "jobs: ParallelFor::run is null");
  return Status();
}

namespace {

// A depth buffer or float plane that is not used must be empty: one with its size or format set
// and no data is a buffer the caller meant to give and did not (docs/ERRORS.md, null_pointer).
Status check_unused_depth(const SourceView& source) {
  const DepthBuffer& buffer = source.depth_buffer;
  if (buffer.data == nullptr && (buffer.width != 0 || buffer.height != 0 || buffer.format != DepthFormat::float32))
    return Status(StatusCode::null_pointer, "source depth_buffer: data is null, but its size (%dx%d) and format (%s) are "
                  "set: give its data, or zero it and give depth", buffer.width, buffer.height, to_string(buffer.format));
  if (buffer.data != nullptr && source.depth.data == nullptr && (source.depth.width != 0 || source.depth.height != 0))
    return Status(StatusCode::null_pointer, "source depth: data is null, but its size (%dx%d) is set, beside "
                  "depth_buffer: zero it", source.depth.width, source.depth.height);
  return Status();
}

// Everything but the target: the decoder, the model, the options and the source.
Status check_inputs(const SourceView& source, const DepthDecoder& decoder, const ParallaxModel& model,
                    const Options& options) {
  if (Status status = decoder.validate(); !status.ok()) return status;
  if (Status status = model.validate(); !status.ok()) return status;
  if (Status status = check_options(options); !status.ok()) return status;
  if (Status status = check_one_depth(source, "source"); !status.ok()) return status;
  if (Status status = check_unused_depth(source); !status.ok()) return status;
  const Size depth = depth_size(source);
  if (depth.width < 0 || depth.height < 0)
    return Status(StatusCode::invalid_size, "source depth: negative size %dx%d", depth.width, depth.height);
  if (depth.width > kMaxWidth)
    return Status(StatusCode::invalid_size, "source depth: width %d is above the maximum %d", depth.width, kMaxWidth);
  if (depth.width == 0 || depth.height == 0) {
    // An empty frame, unless no depth was given at all beside a colour of some size: then the
    // depth is missing, not empty.
    const int color_width = source.color.width(), color_height = source.color.height();
    if (source.depth.data == nullptr && source.depth_buffer.data == nullptr && color_width > 0 && color_height > 0)
      return Status(StatusCode::null_pointer, "source depth: data is null (neither depth nor depth_buffer has any) "
                    "for a %dx%d colour", color_width, color_height);
    return Status();
  }
  if (Status status = source.depth_buffer.data == nullptr
                          ? check_plane(source.depth, depth.width, depth.height, 1, "source depth")
                          : check_depth_buffer(source.depth_buffer, depth.width, depth.height, "source depth_buffer");
      !status.ok())
    return status;
  if (Status status = check_color(source.color, depth.width, depth.height, "source colour"); !status.ok()) return status;
  if (depth.width - 2 * static_cast<long long>(options.guard) < 1)
    return Status(StatusCode::invalid_size, "guard: %d columns on each side leave no target columns of a %d-wide source",
                  options.guard, depth.width);
  return Status();
}

DepthFormat source_depth_format(const SourceView& source) {
  return source.depth_buffer.data != nullptr ? source.depth_buffer.format : DepthFormat::float32;
}

Status check_target(const SourceView& source, const Options& options, const TargetView& target, const char* name) {
  const Size source_size = depth_size(source);
  const int width = source_size.width - 2 * options.guard;
  const int height = source_size.height;
  const DepthFormat depth_format = source_depth_format(source);
  char label[64];
  std::snprintf(label, sizeof label, "%s colour", name);
  if (Status status = check_color(target.color, width, height, label); !status.ok()) return status;
  if (target.color.format != source.color.format)
    return Status(StatusCode::size_mismatch, "%s: format %s, the source's is %s", label, to_string(target.color.format),
                  to_string(source.color.format));
  if (target.color.layout != source.color.layout || target.color.channels != source.color.channels)
    return Status(StatusCode::size_mismatch, "%s: %d channels %s, the source has %d %s", label, target.color.channels,
                  target.color.layout == ColorLayout::planar ? "planar" : "interleaved",
                  source.color.channels, source.color.layout == ColorLayout::planar ? "planar" : "interleaved");
  if (Status status = check_one_depth(target, name); !status.ok()) return status;
  if (target.depth.data) {
    std::snprintf(label, sizeof label, "%s depth", name);
    if (depth_format != DepthFormat::float32)
      return Status(StatusCode::size_mismatch, "%s: a float plane, but the source depth is %s: output depth goes to "
                    "depth_buffer in the source's format", label, to_string(depth_format));
    if (Status status = check_plane(target.depth, width, height, 1, label); !status.ok()) return status;
  }
  if (target.depth_buffer.data) {
    std::snprintf(label, sizeof label, "%s depth_buffer", name);
    if (target.depth_buffer.format != depth_format)
      return Status(StatusCode::size_mismatch, "%s: format %s, the source depth is %s", label,
                    to_string(target.depth_buffer.format), to_string(depth_format));
    if (Status status = check_depth_buffer(target.depth_buffer, width, height, label); !status.ok()) return status;
  }
  if (target.status.data) {
    std::snprintf(label, sizeof label, "%s status", name);
    if (Status status = check_plane(target.status, width, height, 1, label); !status.ok()) return status;
  }
  if (target.source_x.data) {
    std::snprintf(label, sizeof label, "%s source_x", name);
    if (Status status = check_plane(target.source_x, width, height, 1, label); !status.ok()) return status;
  }
  return Status();
}

// Outputs may share a byte neither with an input nor with each other; the bytes between rows
// are no one's, so the halves of one side-by-side buffer may be an input and an output.
Status check_aliasing(const SourceView& source, const TargetView* const* targets, const char* const* names,
                      int target_count) {
  NamedView inputs[5];
  int input_count = 0;
  inputs[input_count++] = source.depth_buffer.data != nullptr ? named(source.depth_buffer, "source depth_buffer")
                                                              : named(source.depth, 1, "source depth");
  input_count += color_views(source.color, inputs + input_count, "source colour");

  // Per target: its name and the names of its outputs, for the messages.
  char labels[2][4][32];
  NamedView outputs[18];
  int output_count = 0;
  for (int i = 0; i < target_count; ++i) {
    const TargetView& target = *targets[i];
    static const char* const kFields[4] = {"colour", "depth", "status", "source_x"};
    for (int f = 0; f < 4; ++f) std::snprintf(labels[i][f], sizeof labels[i][f], "%s %s", names[i], kFields[f]);
    output_count += color_views(target.color, outputs + output_count, labels[i][0]);
    outputs[output_count++] = target.depth_buffer.data != nullptr ? named(target.depth_buffer, labels[i][1])
                                                                  : named(target.depth, 1, labels[i][1]);
    outputs[output_count++] = named(target.status, 1, labels[i][2]);
    outputs[output_count++] = named(target.source_x, 1, labels[i][3]);
  }
  for (int o = 0; o < output_count; ++o) {
    for (int i = 0; i < input_count; ++i)
      if (detail::views_touch(outputs[o].bytes, inputs[i].bytes))
        return Status(StatusCode::aliasing, "%s overlaps %s", outputs[o].name, inputs[i].name);
    for (int p = o + 1; p < output_count; ++p)
      if (detail::views_touch(outputs[o].bytes, outputs[p].bytes))
        return Status(StatusCode::aliasing, "%s overlaps %s", outputs[o].name, outputs[p].name);
  }
  return Status();
}

// A validated source with its depth as a depth buffer (a float plane is float32 with its stride
// in bytes) and the depth view it does not use cleared.
SourceView normalised_source(const SourceView& source) {
  SourceView clean = source;
  if (clean.depth_buffer.data == nullptr) {
    clean.depth_buffer = DepthBuffer::of(DepthFormat::float32, source.depth.data, source.depth.width, source.depth.height,
                                         source.depth.stride * static_cast<std::ptrdiff_t>(sizeof(float)));
  }
  clean.depth = FloatPlane{};
  return clean;
}

// A validated target with the outputs it does not want (null data) cleared, since their other
// fields were never checked, and its output depth, if any, as a depth buffer.
TargetView normalised_target(const TargetView& target) {
  TargetView clean = target;
  if (clean.depth.data != nullptr) {
    clean.depth_buffer = MutableDepthBuffer::of(DepthFormat::float32, target.depth.data, target.depth.width, target.depth.height,
                                                target.depth.stride * static_cast<std::ptrdiff_t>(sizeof(float)));
  } else if (clean.depth_buffer.data == nullptr) {
    clean.depth_buffer = MutableDepthBuffer{};
  }
  clean.depth = MutableFloatPlane{};
  if (clean.status.data == nullptr) clean.status = BytePlane{};
  if (clean.source_x.data == nullptr) clean.source_x = MutableFloatPlane{};
  return clean;
}

}  // namespace

Status check_call(const SourceView& source, const DepthDecoder& decoder, const ParallaxModel& model,
                  const Options& options, const TargetView* const* targets, const char* const* names, int target_count,
                  CallViews* views) {
  if (Status status = check_inputs(source, decoder, model, options); !status.ok()) return status;
  const Size size = depth_size(source);
  views->empty = size.width == 0 || size.height == 0;
  if (views->empty) return Status();
  for (int i = 0; i < target_count; ++i)
    if (Status status = check_target(source, options, *targets[i], names[i]); !status.ok()) return status;
  if (Status status = check_aliasing(source, targets, names, target_count); !status.ok()) return status;
  views->source = normalised_source(source);
  views->target_count = target_count;
  for (int i = 0; i < target_count; ++i) views->targets[i] = normalised_target(*targets[i]);
  return Status();
}

}  // namespace detail
}  // namespace reproject
