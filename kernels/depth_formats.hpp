// Internal: the scalar loads and stores of the depth formats (reproject/formats.hpp DepthFormat,
// docs/BEHAVIOUR.md "Pixel formats"): the stored value d of a column in the frame's format, and
// the word that stores a d back. The decode and resolve stages read and write depth through
// these only; their SIMD twins are in kernels/depth_formats_simd.hpp.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>

#include "kernels/codes.hpp"
#include "kernels/frame.hpp"

namespace reproject::detail {

constexpr float kUnorm16Max = 65535.0f;
constexpr float kUnorm24Max = 16777215.0f;
constexpr float kPackedMax = 16581375.0f;  // 255^3: v = (65025 R + 255 G + B) / 255^3

namespace {  // one copy per translation unit (kernels/fma.hpp)

// rgba8_packed_linear: the 24-bit integer n = 65025 R + 255 G + B of a word (bytes R, G, B, A in
// memory order), the n of a value v in [0, 1), and the word of n.
inline std::uint32_t packed_code(std::uint32_t word) noexcept {
  return (word & 0xffu) * 65025u + ((word >> 8) & 0xffu) * 255u + ((word >> 16) & 0xffu);
}
inline std::uint32_t packed_code_of(float v) noexcept {
  return static_cast<std::uint32_t>(round_even(clamp_code(v * kPackedMax, kPackedMax - 1.0f)));
}
inline std::uint32_t packed_word(std::uint32_t n) noexcept {
  const std::uint32_t r = n / 65025u;
  const std::uint32_t rest = n - r * 65025u;
  const std::uint32_t g = rest / 255u;
  return r | (g << 8) | ((rest - g * 255u) << 16);
}

// The stored depth value d of column i of a depth row in the frame's format: a function of the
// bytes alone (no FMA policy).
inline float depth_value(const Frame& f, const std::uint8_t* row, int i) noexcept {
  const std::ptrdiff_t column = i;
  switch (f.depth.format) {
    case DepthFormat::unorm16: return unorm_value(load_u16_at(row + 2 * column), kUnorm16Max);
    case DepthFormat::unorm24_s8: return unorm_value(load_u32(row + 4 * column) & 0xffffffu, kUnorm24Max);
    case DepthFormat::s8_unorm24: return unorm_value(load_u32(row + 4 * column) >> 8, kUnorm24Max);
    case DepthFormat::rgba8_packed_linear: {
      // Never fused, on any arch: the stored value is a function of the bytes alone.
      const float v = unorm_value(packed_code(load_u32(row + 4 * column)), kPackedMax);
      return v * f.packed_range + f.packed_near;
    }
    case DepthFormat::float32: break;
  }
  return float_of_bits(load_u32(row + 4 * column));
}

// D16: the decode keeps the row's stored values in RowScratch::stored_depth for the SIMD resolve
// (16-bit columns do not fit its column plan); the 32-bit formats' words are read there directly.
inline bool depth_row_kept(const Frame& f) noexcept { return f.depth.format == DepthFormat::unorm16; }

// Whether the near pass may reduce a row's UNORM codes instead of its keys (kernels/
// decode_simd.hpp, simd_nearest_key): a column's key is then a monotone function of its code.
// Each step of the decode is monotone in d = code / max (kernels/decode.cpp decode_parallax: an
// affine map, or a reciprocal and an affine map, each correctly rounded, then s * p, exact, and
// clean_parallax's clamps), in one direction for every code when the frame's constants are
// finite. The one NaN, a reciprocal's 0 * inf at code 0 with b = +-0, becomes key_far beside one
// key for every other code: the larger of the two ends is still the row's nearest key.
// The formats whose stored value is a UNORM code alone, d = code / max (not the packed format's
// affine map, not floats).
constexpr bool has_unorm_codes(DepthFormat format) noexcept {
  return format == DepthFormat::unorm16 || format == DepthFormat::unorm24_s8 || format == DepthFormat::s8_unorm24;
}
inline bool near_pass_by_codes(const Frame& f) noexcept {
  const bool finite = f.affine ? std::isfinite(f.decode_scale) && std::isfinite(f.decode_offset)
                               : std::isfinite(f.a) && std::isfinite(f.b);
  return has_unorm_codes(f.depth.format) && finite;
}

// The word (or code) that stores depth d in the frame's format; `kept` is the source word whose
// other bits (D24S8's stencil, the packed format's A byte) go with it.
inline std::uint32_t depth_word(const Frame& f, float d, std::uint32_t kept) noexcept {
  switch (f.depth.format) {
    case DepthFormat::unorm16: return unorm_code(d, kUnorm16Max);
    case DepthFormat::unorm24_s8: return unorm_code(d, kUnorm24Max) | (kept & 0xff000000u);
    case DepthFormat::s8_unorm24: return (unorm_code(d, kUnorm24Max) << 8) | (kept & 0xffu);
    case DepthFormat::rgba8_packed_linear:
      return packed_word(packed_code_of((d - f.packed_near) / f.packed_range)) | (kept & 0xff000000u);
    case DepthFormat::float32: break;
  }
  return bits_of_float(d);
}

}  // namespace
}  // namespace reproject::detail
