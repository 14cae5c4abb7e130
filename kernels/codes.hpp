// Internal: the exact conversions between stored codes and floats that the pixel formats share
// (docs/BEHAVIOUR.md "Pixel formats"): bit casts, unaligned 16- and 32-bit loads and stores, round
// to nearest even, UNORM codes and IEEE half floats. Each is an exact function of its inputs:
// integer arithmetic, correctly rounded float operations and rounding written out, so that no
// rounding mode, library or CPU changes a bit. Their SIMD twins: kernels/codes_simd.hpp.
#pragma once

#include <cstdint>
#include <cstring>

namespace reproject::detail {
namespace {  // one copy per translation unit (kernels/fma.hpp)

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
inline std::uint16_t load_u16_at(const std::uint8_t* p) noexcept {
  std::uint16_t v;
  std::memcpy(&v, p, 2);
  return v;
}
inline void store_u16_at(std::uint8_t* p, std::uint16_t v) noexcept { std::memcpy(p, &v, 2); }

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

// ---- 8-bit channels blended in fixed point (docs/BEHAVIOUR.md "Pixel formats") ----

// The blend weight as a 15-bit fraction: floor(frac 2^15) for frac in [0, 1), so 0..32767 (the
// scale by a power of two is exact; the conversion truncates).
inline std::int32_t weight_q15(float frac) noexcept { return static_cast<std::int32_t>(frac * 32768.0f); }
// c0 + (c1 - c0) w / 2^15 rounded half up: floor(((c1 - c0) w + 2^14) / 2^15), the rounding of
// pmulhrsw and vqrdmulh. Always between c0 and c1, so no clamp.
inline std::uint8_t blend_u8_q15(std::uint8_t c0, std::uint8_t c1, std::int32_t w) noexcept {
  const std::int32_t d = static_cast<std::int32_t>(c1) - static_cast<std::int32_t>(c0);
  return static_cast<std::uint8_t>(c0 + ((d * w + 16384) >> 15));
}
// rgba8_srgb: whether two bytes of a channel are near enough that their blend_u8_q15, the blend of
// the bytes themselves, is within one code of the sRGB-correct byte (the one nearest the blend of
// their linear values) at every weight: |c1 - c0| <= 10 + (min(c0, c1) + 4) / 8. The sRGB curve
// bends less where it is brighter, so brighter pairs may lie further apart. The bound is the
// largest of its form that holds for all 65,536 pairs at every weight; tests/test_pixel_formats.cpp
// checks it over all pairs (docs/BEHAVIOUR.md "Pixel formats"). The SIMD twins saturate the + 4 at
// 255, which changes no answer: from 252 up no two bytes differ by more than 3.
inline bool srgb_pair_near(std::uint8_t c0, std::uint8_t c1) noexcept {
  const int low = c0 < c1 ? c0 : c1, high = c0 < c1 ? c1 : c0;
  return high - low <= 10 + ((low + 4) >> 3);
}
// rgba8_srgb, a pair that is not near: whether srgb_second_order_blend is within one code of the
// sRGB-correct byte at every frac: |c1 - c0| <= min(c0, c1) + 9, i.e. the brighter byte at most
// twice the darker plus 9. The largest bound of the form min + k that holds for all pairs (checked
// as srgb_pair_near is).
inline bool srgb_pair_second_order(std::uint8_t c0, std::uint8_t c1) noexcept {
  const int low = c0 < c1 ? c0 : c1, high = c0 < c1 ? c1 : c0;
  return high - low <= low + 9;
}
// The bytes' blend with the sRGB curve's bend to second order: with d = c1 - c0 and x = c0 + frac d,
// x + 0.7 frac (1 - frac) d^2 / (x + 14.025), rounded to the nearest byte (ties to even). The
// curve's power part is ((c + 14.025) / 269.025)^2.4 in codes c, whose second derivative over its
// first is 1.4 / (c + 14.025): a blend in linear light lies above the bytes' blend by half that
// times frac (1 - frac) d^2, to second order. Each operation rounded to float, in this order
// (the SIMD twin's, with no FMA anywhere); the result lies between c0 and c1 for every
// srgb_pair_second_order pair (tests/test_pixel_formats.cpp).
inline std::uint8_t srgb_second_order_blend(std::uint8_t c0, std::uint8_t c1, float frac) noexcept {
  const float a = static_cast<float>(c0), d = static_cast<float>(c1) - a;
  const float x = a + frac * d;
  const float bend = (frac - frac * frac) * (d * d) * 0.7f / (x + 14.025f);
  return static_cast<std::uint8_t>(round_even(x + bend));
}

// UNORM: the value code / max (max = 2^bits - 1) correctly rounded, and the code of a value.
inline float unorm_value(std::uint32_t code, float max) noexcept { return static_cast<float>(code) / max; }
inline std::uint32_t unorm_code(float d, float max) noexcept {
  return static_cast<std::uint32_t>(round_even(clamp_code(d * max, max)));
}

// ---- IEEE 754 half floats ----

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

}  // namespace
}  // namespace reproject::detail
