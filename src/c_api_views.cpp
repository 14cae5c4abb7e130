// The C interface's structs of images and buffers as the C++ views (src/c_api_internal.hpp).
#include "reproject/reproject.h"

#include <cstddef>
#include <cstdint>

#include "src/c_api_internal.hpp"

namespace reproject {
namespace c_abi {
namespace {

// The C strides are int64_t; where ptrdiff_t is narrower (32-bit targets) a stride beyond it
// becomes PTRDIFF_MIN, which the validation refuses as shorter than the row, instead of being
// truncated to a plausible wrong pitch.
std::ptrdiff_t stride_of(std::int64_t stride) noexcept {
  if constexpr (sizeof(std::ptrdiff_t) < sizeof(std::int64_t)) {
    if (stride > PTRDIFF_MAX || stride < PTRDIFF_MIN) return PTRDIFF_MIN;
  }
  return static_cast<std::ptrdiff_t>(stride);
}

FloatPlane view(const reproject_plane& p) noexcept { return FloatPlane{p.data, p.width, p.height, stride_of(p.stride)}; }
MutableFloatPlane view(const reproject_mut_plane& p) noexcept {
  return MutableFloatPlane{p.data, p.width, p.height, stride_of(p.stride)};
}
BytePlane view(const reproject_byte_plane& p) noexcept {
  return BytePlane{p.data, p.width, p.height, stride_of(p.stride)};
}

// The C structs to the C++ views: one function per struct, shared by the float-only calls (whose
// structs are lifted into the _buffers ones) and the _buffers calls. Values that C++ keeps in 8-bit
// enums (layout, formats) are range-checked before the cast, as a cast of an unknown value could
// wrap onto a known one; sizes, strides, channel counts and the rest are the C++ validation's.
template <class CColor, class CPixels, class View>
Status color_of(const CColor& c, const CPixels& p, const char* name, View* out) noexcept {
  if (c.layout != REPROJECT_LAYOUT_PLANAR && c.layout != REPROJECT_LAYOUT_INTERLEAVED_RGBA)
    return Status(StatusCode::invalid_option, "%s color.layout %d is not a known layout (REPROJECT_LAYOUT_*)", name,
                  static_cast<int>(c.layout));
  if (p.format < 0 || p.format >= kColorFormatCount)
    return Status(StatusCode::invalid_option, "%s pixels.format %d is not a known colour format (REPROJECT_COLOR_*)",
                  name, static_cast<int>(p.format));
  if (p.reserved != 0)  // kept 0 now, so that a later version may give it a meaning
    return Status(StatusCode::invalid_option, "%s pixels.reserved is %d; it must be 0", name, static_cast<int>(p.reserved));
  View v;
  if (p.format == REPROJECT_COLOR_FLOAT32) {
    if (p.data != nullptr)
      return Status(StatusCode::invalid_option, "%s pixels.data is set but pixels.format is float32: float colour "
                    "goes in color, packed pixels need their REPROJECT_COLOR_* format", name);
    v.layout = static_cast<ColorLayout>(c.layout);
    v.channels = c.channels;
    for (int i = 0; i < 4; ++i) v.plane[i] = view(c.plane[i]);
  } else {
    bool planes = c.channels != 0;
    for (int i = 0; i < 4; ++i) planes = planes || c.plane[i].data != nullptr;
    if (planes)
      return Status(StatusCode::invalid_option, "%s: both color (float planes) and pixels (%s) are set; set one", name,
                    to_string(static_cast<ColorFormat>(p.format)));
    v = View::packed(static_cast<ColorFormat>(p.format), p.data, p.width, p.height, stride_of(p.stride));
  }
  *out = v;
  return Status();
}

template <class CBuffer, class Buffer>
Status depth_buffer_of(const CBuffer& d, const char* name, Buffer* out) noexcept {
  if (d.format < 0 || d.format >= kDepthFormatCount)
    return Status(StatusCode::invalid_option,
                  "%s depth_buffer.format %d is not a known depth format (REPROJECT_DEPTH_FORMAT_*)", name,
                  static_cast<int>(d.format));
  if (d.reserved != 0)
    return Status(StatusCode::invalid_option, "%s depth_buffer.reserved is %d; it must be 0", name,
                  static_cast<int>(d.reserved));
  Buffer b = Buffer::of(static_cast<DepthFormat>(d.format), d.data, d.width, d.height, stride_of(d.stride));
  b.linear_near = d.linear_near;
  b.linear_far = d.linear_far;
  *out = b;
  return Status();
}

}  // namespace

// Both depths are passed on as given: the C++ validation refuses a view with both set.
Status source_of(const reproject_source_buffers& s, const char* name, SourceView* out) noexcept {
  SourceView v;
  Status status = color_of(s.color, s.pixels, name, &v.color);
  if (status.ok()) status = depth_buffer_of(s.depth_buffer, name, &v.depth_buffer);
  v.depth = view(s.depth);
  *out = v;
  return status;
}
Status target_of(const reproject_target_buffers& t, const char* name, TargetView* out) noexcept {
  TargetView v;
  Status status = color_of(t.color, t.pixels, name, &v.color);
  if (status.ok()) status = depth_buffer_of(t.depth_buffer, name, &v.depth_buffer);
  v.depth = view(t.depth);
  v.status = view(t.status);
  v.source_x = view(t.source_x);
  *out = v;
  return status;
}

// The float-only structs are the _buffers ones with no pixels and no depth buffer.
reproject_source_buffers buffers_of(const reproject_source& s) noexcept {
  reproject_source_buffers b{};
  b.color = s.color;
  b.depth = s.depth;
  return b;
}
reproject_target_buffers buffers_of(const reproject_target& t) noexcept {
  reproject_target_buffers b{};
  b.color = t.color;
  b.depth = t.depth;
  b.status = t.status;
  b.source_x = t.source_x;
  return b;
}

}  // namespace c_abi
}  // namespace reproject
