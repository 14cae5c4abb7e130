// Internal: the scalar loads and stores of the engine-native pixel formats (reproject/formats.hpp,
// docs/BEHAVIOUR.md "Pixel formats"). The shared decode and resolve stages use these and only
// these; their SIMD twins (kernels/pixel_formats_simd.hpp) compute the same bits. Every rule
// here is an exact function of its inputs: integer arithmetic, correctly rounded float
// operations, and round-to-nearest-even written out (no rounding-mode or library dependence).
#pragma once

#include <cstdint>
#include <cstring>

#include "reproject/formats.hpp"

namespace reproject {
namespace detail {

// sRGB tables, built once (pixel_formats.cpp). Encoding a linear value looks up its bucket by
// the float's top bits (kSrgbBucketShift): each bucket holds at most one rounding threshold, so
// the byte is the bucket's first byte, plus one at or beyond that threshold.
constexpr int kSrgbBucketShift = 16;
constexpr std::uint32_t kSrgbFirstBucket = 0x391fu;  // bits >> 16 of the first threshold (~1.5e-4)
constexpr std::uint32_t kSrgbLastBucket = 0x3f80u;   // bits >> 16 of 1.0f
constexpr int kSrgbBuckets = static_cast<int>(kSrgbLastBucket - kSrgbFirstBucket + 1);
struct SrgbTables {
  float to_linear[256];              // the exact linear value of each byte, rounded to float
  std::int32_t bucket_byte[kSrgbBuckets];  // the byte of the bucket's lowest float
  float bucket_next[kSrgbBuckets];   // the smallest float of the next byte (may lie past the bucket)
};
const SrgbTables& srgb_tables();

constexpr float kUnorm16Max = 65535.0f;
constexpr float kUnorm24Max = 16777215.0f;
constexpr float kPackedMax = 16581375.0f;  // 255^3: v = (65025 R + 255 G + B) / 255^3

namespace {  // one copy per translation unit (frame.hpp, "ODR")

inline float float_of_bits(std::uint32_t bits) noexcept {
  float f;
  std::memcpy(&f, &bits, 4);
  return f;
}
inline std::uint32_t bits_of_float(float f) noexcept {
  std::uint32_t bits;
  std::memcpy(&bits, &f, 4);
  return bits;
}
inline std::uint32_t load_u32(const std::uint8_t* p) noexcept {
  std::uint32_t v;
  std::memcpy(&v, p, 4);
  return v;
}
inline void store_u32(std::uint8_t* p, std::uint32_t v) noexcept { std::memcpy(p, &v, 4); }

// Round to nearest, ties to even, for 0 <= x <= 2^24: adding 2^23 leaves no fraction bits
// below x < 2^23, and from 2^23 on every float is already an integer. (-ffp-contract=off.)
inline float round_even(float x) noexcept {
  constexpr float kMagic = 8388608.0f;  // 2^23
  return x < kMagic ? (x + kMagic) - kMagic : x;
}
// x clamped to [0, max]; NaN gives 0.
inline float clamp_code(float x, float max) noexcept {
  x = x > 0.0f ? x : 0.0f;
  return x < max ? x : max;
}

// ---- half floats (rgba16f) ----

inline float half_to_float(std::uint16_t h) noexcept {
  const std::uint32_t sign = static_cast<std::uint32_t>(h & 0x8000u) << 16;
  const std::uint32_t exponent = (h >> 10) & 0x1fu;
  const std::uint32_t mantissa = h & 0x3ffu;
  if (exponent == 0x1fu) {  // infinity, or NaN: made quiet, payload kept (as vcvtph2ps)
    return float_of_bits(sign | 0x7f800000u | (mantissa != 0 ? 0x400000u | (mantissa << 13) : 0u));
  }
  if (exponent != 0) return float_of_bits(sign | ((exponent + 112u) << 23) | (mantissa << 13));
  // Zero or subnormal: mantissa * 2^-24, exact in float.
  const float magnitude = static_cast<float>(mantissa) * 5.9604644775390625e-8f;
  return float_of_bits(sign | bits_of_float(magnitude));
}

// Round to nearest even, as vcvtps2ph with _MM_FROUND_TO_NEAREST_INT: overflow gives infinity, a
// NaN keeps its sign and top payload bits and is made quiet.
inline std::uint16_t float_to_half(float value) noexcept {
  const std::uint32_t bits = bits_of_float(value);
  const std::uint16_t sign = static_cast<std::uint16_t>((bits >> 16) & 0x8000u);
  const std::uint32_t magnitude = bits & 0x7fffffffu;
  if (magnitude >= 0x7f800000u) {  // inf or NaN
    if (magnitude == 0x7f800000u) return static_cast<std::uint16_t>(sign | 0x7c00u);
    return static_cast<std::uint16_t>(sign | 0x7e00u | ((magnitude >> 13) & 0x3ffu));
  }
  if (magnitude >= 0x477ff000u) return static_cast<std::uint16_t>(sign | 0x7c00u);  // rounds past 65504
  if (magnitude < 0x38800000u) {
    // Below the smallest normal half (2^-14): a multiple of 2^-24, rounded to nearest even by
    // the float addition itself (the sum's unit in the last place is 2^-24 here).
    const float rounded = float_of_bits(magnitude) + 0.5f;  // ulp(0.5) = 2^-24
    return static_cast<std::uint16_t>(sign | (bits_of_float(rounded) - 0x3f000000u));
  }
  // Normal: rebias, then round the 13 dropped bits to nearest even (a carry may raise the exponent).
  const std::uint32_t odd = (magnitude >> 13) & 1u;
  const std::uint32_t rounded = magnitude + 0xfffu + odd;
  return static_cast<std::uint16_t>(sign | ((rounded - 0x38000000u) >> 13));
}

// ---- sRGB (rgba8_srgb) ----

inline std::uint8_t srgb_encode(const SrgbTables& tables, float linear) noexcept {
  const float lowest = float_of_bits(kSrgbFirstBucket << kSrgbBucketShift);
  float l = linear > lowest ? linear : lowest;  // NaN too
  l = l < 1.0f ? l : 1.0f;
  const int bucket = static_cast<int>((bits_of_float(l) >> kSrgbBucketShift) - kSrgbFirstBucket);
  return static_cast<std::uint8_t>(tables.bucket_byte[bucket] + (l >= tables.bucket_next[bucket] ? 1 : 0));
}

// ---- depth codes ----

inline float unorm_value(std::uint32_t code, float max) noexcept { return static_cast<float>(code) / max; }
inline std::uint32_t unorm_code(float d, float max) noexcept {
  return static_cast<std::uint32_t>(round_even(clamp_code(d * max, max)));
}
// The 24-bit integer n = 65025 R + 255 G + B of a packed word (bytes R, G, B, A in memory order).
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

}  // namespace
}  // namespace detail
}  // namespace reproject
