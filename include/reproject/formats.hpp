// Engine-native pixel formats (docs/BEHAVIOUR.md "Pixel formats"): what an engine's colour and
// depth buffers hold, and the exact conversions the kernels use to read and write them. A format
// only changes how values are loaded and stored; every method searches the same way on all of them.
#pragma once

#include <cstddef>
#include <cstdint>
#include <type_traits>

namespace reproject {

// How colour values are stored. The packed formats are interleaved R, G, B, A in memory order.
enum class ColorFormat : std::uint8_t {
  float32,     // floats: 1..4 planes or interleaved RGBA (ColorLayout)
  rgba8,       // one UNORM byte per channel; blended as the byte values, rounded to nearest even
  rgba8_srgb,  // the same bytes, R, G, B sRGB-encoded (alpha linear): blended in linear light, within one code
  rgba16f,     // one IEEE 754 half per channel (8 bytes per pixel, the machine's byte order)
};
constexpr int kColorFormatCount = 4;

// How depth values are stored. Each yields a stored value d that the DepthDecoder then decodes
// (every encoding of DESIGN §3 applies to it); output depth is written back in the same format.
enum class DepthFormat : std::uint8_t {
  float32,     // one float per pixel: d as stored
  unorm16,     // D16: d = u / 65535
  unorm24_s8,  // a 32-bit word, depth in bits 0-23, stencil in bits 24-31: d = u / 16777215.
               // D3D's D24_UNORM_S8_UINT and Vulkan's D24_UNORM_S8_UINT / X8_D24_UNORM_PACK32.
  s8_unorm24,  // a 32-bit word, stencil in bits 0-7, depth in bits 8-31 (OpenGL's
               // GL_UNSIGNED_INT_24_8 read-back): d = u / 16777215
  rgba8_packed_linear,  // R, G, B bytes hold v = (65025 R + 255 G + B) / 16581375 in [0, 1) (the
                        // shader packing v = R' + G'/255 + B'/65025 of UNORM channels); d is the
                        // linear depth near + v (far - near) of the view's range. A is not depth.
};
constexpr int kDepthFormatCount = 5;

// Short stable names ("rgba8_srgb", "unorm24_s8", ...); the parsers accept the same names (names
// and parsers behave as reproject.hpp says before to_string(Method)).
const char* to_string(ColorFormat format) noexcept;
const char* to_string(DepthFormat format) noexcept;
bool parse_color_format(const char* name, ColorFormat* out) noexcept;
bool parse_depth_format(const char* name, DepthFormat* out) noexcept;

// Bytes per pixel; 0 for float32 colour (its layout decides) and for unknown values.
int bytes_per_pixel(ColorFormat format) noexcept;
int bytes_per_pixel(DepthFormat format) noexcept;

// A depth buffer in any DepthFormat: its bytes, row y at data + y * stride (bytes). Byte is
// `const std::uint8_t` (a source) or `std::uint8_t` (an output).
template <class Byte>
struct DepthBufferT {
  using Pointer = typename std::conditional<std::is_const<Byte>::value, const void*, void*>::type;

  DepthFormat format = DepthFormat::float32;
  Byte* data = nullptr;
  int width = 0;
  int height = 0;
  std::ptrdiff_t stride = 0;  // bytes between row starts, >= width * bytes_per_pixel(format)
  // rgba8_packed_linear only: the linear depth range v in [0, 1) spans (d = near + v (far - near)).
  // Read from the source (finite, far != near, far - near finite); an output uses the source's.
  float linear_near = 0.0f;
  float linear_far = 1.0f;

  static DepthBufferT of(DepthFormat format, Pointer data, int width, int height, std::ptrdiff_t stride_bytes) noexcept {
    DepthBufferT view;
    view.format = format;
    view.data = static_cast<Byte*>(data);
    view.width = width;
    view.height = height;
    view.stride = stride_bytes;
    return view;
  }
  static DepthBufferT packed_linear(Pointer data, int width, int height, std::ptrdiff_t stride_bytes,
                                    float near_depth, float far_depth) noexcept {
    DepthBufferT view = of(DepthFormat::rgba8_packed_linear, data, width, height, stride_bytes);
    view.linear_near = near_depth;
    view.linear_far = far_depth;
    return view;
  }
  Byte* row(int y) const noexcept { return data + static_cast<std::ptrdiff_t>(y) * stride; }
};
using DepthBuffer = DepthBufferT<const std::uint8_t>;
using MutableDepthBuffer = DepthBufferT<std::uint8_t>;

// The conversions the kernels use, exposed so that callers and tests can make and check buffers.
// All are exact functions of their inputs (no rounding-mode or CPU dependence).
namespace formats {

float half_to_float(std::uint16_t half) noexcept;   // exact (every half is a float)
std::uint16_t float_to_half(float value) noexcept;  // round to nearest even, as F16C's vcvtps2ph
float srgb_to_linear(std::uint8_t byte) noexcept;   // the exact value rounded to float
// The byte whose sRGB value is nearest to `linear` (ties: away from zero on the 255 scale, which
// the exact sRGB curve never meets at a float); values outside [0, 1] and NaN clamp (NaN to 0).
std::uint8_t linear_to_srgb(float linear) noexcept;
// UNORM codes of 1..24 bits (8: a colour byte, 16: D16, 24: D24): the value code / (2^bits - 1),
// correctly rounded, and the code of a value (value * (2^bits - 1) rounded to nearest even,
// clamped to [0, 2^bits - 1]; NaN gives 0). Other `bits` give NaN and 0.
float unorm_to_float(std::uint32_t code, int bits) noexcept;
std::uint32_t float_to_unorm(float value, int bits) noexcept;
// rgba8_packed_linear: v of the R, G, B bytes, and the bytes of v (round to nearest 1/16581375,
// clamped to [0, 16581374/16581375]).
float packed_linear_value(const std::uint8_t rgb[3]) noexcept;
void pack_linear_value(float v, std::uint8_t rgb[3]) noexcept;

}  // namespace formats

}  // namespace reproject
