// Internal: the scalar loads, blends and stores of the colour formats (reproject/formats.hpp
// ColorFormat, docs/BEHAVIOUR.md "Pixel formats"): float planes and RGBA, rgba8, rgba8_srgb through
// exact sRGB tables, rgba16f. The resolve stage writes colour through ColorRow only; its SIMD
// twins are in kernels/color_formats_simd.hpp, the sRGB tables are built in color_formats.cpp.
#pragma once

#include <cstddef>
#include <cstdint>

#include "kernels/codes.hpp"
#include "kernels/fma.hpp"
#include "kernels/frame.hpp"

namespace reproject::detail {

// sRGB tables, built once (color_formats.cpp). Encoding a linear value looks up its bucket by
// the float's top bits (kSrgbBucketShift): each bucket holds at most one rounding threshold, so
// the byte is the bucket's first byte, plus one at or beyond that threshold. One word per bucket
// holds both (one load, one gather in the SIMD twin): the byte above kSrgbStepBits, and below it
// the threshold's low 16 bits (a positive float in the bucket orders as those bits do), or
// kSrgbNoStep when the next byte's threshold lies past the bucket.
constexpr int kSrgbBucketShift = 16;
constexpr std::uint32_t kSrgbFirstBucket = 0x391fu;  // bits >> 16 of the first threshold (~1.5e-4)
constexpr std::uint32_t kSrgbLastBucket = 0x3f80u;   // bits >> 16 of 1.0f
constexpr int kSrgbBuckets = static_cast<int>(kSrgbLastBucket - kSrgbFirstBucket + 1);
// The encoder's estimate (kernels/color_formats_simd.hpp srgb_estimate_lanes, on sets whose vector
// holds sixteen lanes): 255 encode(l) for l = m 2^e (m in [1, 2), e in [-9, 0]) is
// 255 (1.055 m^(5/12) 2^(5e/12) - 0.055), with m^(5/12) a degree-6 polynomial in m - 1 (least
// squares at Chebyshev nodes) and 255 * 1.055 * 2^(5e/12) from encode_scale[e + 9]; below
// kSrgbLinearEnd the curve's linear part, 255 * 12.92 l. Evaluated in float (fused or not) it is
// within 7.5e-5 of 255 encode(l) for every float in [kSrgbFirstBucket's, 1]: a lane whose
// estimate + 1/2 is at least kSrgbEstimateMargin from an integer therefore rounds to the exact
// byte; the rgba8_srgb blend takes the table for a vector with any other lane, in any channel
// (the same bytes either way; the test EverySet/ArchLayer.srgb_encode compares every float of
// that range where the set estimates).
constexpr float kSrgbPolynomial[7] = {-0x1.67bafcp-9f, 0x1.b96a5cp-7f, -0x1.0e6ce2p-5f, 0x1.f8ddf4p-5f,
                                      -0x1.f03aecp-4f, 0x1.aaa4e4p-2f, 0x1.000004p+0f};  // highest power first
constexpr float kSrgbLinearEnd = 0.0031308f;
constexpr float kSrgbOffsetCodes = static_cast<float>(255 * 0.055);  // the power part's - 0.055, in codes
constexpr float kSrgbSlopeCodes = static_cast<float>(255 * 12.92);   // the linear part's slope, in codes
constexpr float kSrgbEstimateMargin = 0x1p-13f;  // 1.2e-4 codes
constexpr int kSrgbLowestScaleExponent = -9;     // 2^-9 <= kSrgbLinearEnd < 2^-8
struct SrgbTables {
  alignas(64) float to_linear[256];  // the exact linear value of each byte, rounded to float
  std::int32_t bucket[kSrgbBuckets];  // byte << kSrgbStepBits | the next byte's step (see above)
  alignas(64) float encode_scale[16];  // [e + 9]: 255 * 1.055 * 2^(5e/12) for e in [-9, 0]; then 0
};
constexpr std::uint32_t kSrgbLowMask = (1u << kSrgbBucketShift) - 1;  // a float's bits within its bucket
constexpr int kSrgbStepBits = kSrgbBucketShift + 1;
constexpr std::int32_t kSrgbStepMask = (1 << kSrgbStepBits) - 1;
constexpr std::int32_t kSrgbNoStep = 1 << kSrgbBucketShift;  // above every low part: never reached
const SrgbTables& srgb_tables();

// How a SIMD set looks the sRGB tables up: gathers (every set), or, on sets with sixteen lanes
// and permutes (AVX-512), without gathers: a permuted decode and an estimated encode
// (kernels/color_formats_simd.hpp). The same bytes either way; which is faster depends on the
// processor, so the choice is made at run time (KernelTable::srgb_lookup, kernels/dispatch.hpp).
enum class SrgbLookup : unsigned char { gathers, permutes };

namespace {  // one copy per translation unit (kernels/fma.hpp)

// rgba8_srgb: the byte whose sRGB value is nearest to a linear value (reproject::formats).
inline std::uint8_t srgb_encode(const SrgbTables& tables, float linear) noexcept {
  // NaN first, on its own: clang for AArch64 folds the clamp below into fmaxnm, which turns a
  // signalling NaN into a quiet one instead of `lowest` (then clamped to 1: byte 255).
  if (linear != linear) return 0;
  const float lowest = float_of_bits(kSrgbFirstBucket << kSrgbBucketShift);
  float l = linear > lowest ? linear : lowest;
  l = l < 1.0f ? l : 1.0f;
  const std::uint32_t bits = bits_of_float(l);
  const std::int32_t word = tables.bucket[(bits >> kSrgbBucketShift) - kSrgbFirstBucket];
  const std::int32_t low = static_cast<std::int32_t>(bits & kSrgbLowMask);
  return static_cast<std::uint8_t>((word >> kSrgbStepBits) + (low >= (word & kSrgbStepMask) ? 1 : 0));
}

// rgba8_srgb: an R, G or B byte of two pixels blended at `frac` (ColorRow::write). Where the two
// bytes are near (srgb_pair_near), the bytes themselves blended as rgba8's; else where the pair
// allows it (srgb_pair_second_order), the bytes' blend bent as the curve bends it; both within one
// code of the byte nearest the exact blend (docs/BEHAVIOUR.md "Pixel formats"). Any other pair
// (an edge): the two bytes' linear values blended (madd with the table's FMA policy) and encoded
// exactly.
template <class Fma>
std::uint8_t blend_srgb_byte(const SrgbTables& tables, std::uint8_t c0, std::uint8_t c1, float frac) noexcept {
  if (srgb_pair_near(c0, c1)) return blend_u8_q15(c0, c1, weight_q15(frac));
  if (srgb_pair_second_order(c0, c1)) return srgb_second_order_blend(c0, c1, frac);
  return srgb_encode(tables, madd<Fma>(frac, tables.to_linear[c1] - tables.to_linear[c0], tables.to_linear[c0]));
}

// A row's colour in its format: writes target pixel t as source columns j0 and j1 blended at
// `frac` (c0 + frac (c1 - c0) per channel with the table's FMA policy), or as zeros (`black`).
// Float values are blended as they are; rgba8 as the byte values, rgba8_srgb's R, G, B as their
// linear values (blend_srgb_byte), rgba16f as the halves' values; then each is stored in the
// format, rounded to nearest even (docs/BEHAVIOUR.md "Pixel formats").
template <class Fma>
struct ColorRow {
  ColorFormat format;
  const SrgbTables* srgb;
  const float* src[4];
  float* dst[4];
  int channels;
  int pixel_step;  // floats: 1 planar, 4 interleaved
  const std::uint8_t* src_bytes;
  std::uint8_t* dst_bytes;

  ColorRow(const Frame& f, int y) : format(f.color_format), srgb(f.srgb) {
    channels = f.source.color.channels;
    if (format != ColorFormat::float32) {
      src_bytes = f.source.color.pixels.row(y);
      dst_bytes = f.target.color.pixels.row(y);
      return;
    }
    const bool interleaved = f.source.color.layout == ColorLayout::interleaved_rgba;
    pixel_step = interleaved ? 4 : 1;
    for (int c = 0; c < channels; ++c) {
      const int plane = interleaved ? 0 : c;
      const int offset = interleaved ? c : 0;
      src[c] = f.source.color.plane[plane].row(y) + offset;
      dst[c] = f.target.color.plane[plane].row(y) + offset;
    }
  }
  static float blend(float frac, float c0, float c1) { return madd<Fma>(frac, c1 - c0, c0); }

  void write(int t, int j0, int j1, float frac, bool black) const {
    const std::ptrdiff_t a = j0, b = j1, out = t;
    switch (format) {
      case ColorFormat::float32:
        for (int c = 0; c < channels; ++c)
          dst[c][out * pixel_step] = black ? 0.0f : blend(frac, src[c][a * pixel_step], src[c][b * pixel_step]);
        return;
      case ColorFormat::rgba8:
      case ColorFormat::rgba8_srgb:
        for (int c = 0; c < 4; ++c) {
          const std::uint8_t c0 = src_bytes[4 * a + c], c1 = src_bytes[4 * b + c];
          std::uint8_t value = 0;
          if (black) {
          } else if (format == ColorFormat::rgba8_srgb && c < 3) {
            value = blend_srgb_byte<Fma>(*srgb, c0, c1, frac);
          } else {
            value = blend_u8_q15(c0, c1, weight_q15(frac));
          }
          dst_bytes[4 * out + c] = value;
        }
        return;
      case ColorFormat::rgba16f:
        for (int c = 0; c < 4; ++c) {
          const std::uint16_t h0 = load_u16_at(src_bytes + 8 * a + 2 * c), h1 = load_u16_at(src_bytes + 8 * b + 2 * c);
          store_u16_at(dst_bytes + 8 * out + 2 * c, black ? 0 : float_to_half(blend(frac, half_to_float(h0), half_to_float(h1))));
        }
        return;
    }
  }
};

}  // namespace
}  // namespace reproject::detail
