// Internal: SIMD twins of kernels/color_formats.hpp's colour blends (ColorRow::write;
// docs/BEHAVIOUR.md "Pixel formats"): the same integer arithmetic and correctly rounded float
// operations, lane by lane, so every arch stores the same bits as the scalar reference. Used by
// kernels/resolve_row_simd.hpp.
#pragma once

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <type_traits>

#include "kernels/codes_simd.hpp"
#include "kernels/color_formats.hpp"

namespace reproject::detail {
namespace {  // one copy per arch TU (kernels/fma.hpp)

// Sets whose vector has sixteen lanes and permutes (AVX-512) can also decode and encode sRGB
// without gathers (SrgbLookup::permutes: srgb_decode_lanes, srgb_estimate_lanes). Faster than
// their gathers on one processor, slower on another (docs/PERFORMANCE.md "Measured design
// choices"), so such a set's table times both once (faster_srgb_lookup). AVX2's eight lanes
// would need twice the permutes: measured slower there, it only gathers.
template <class Arch>
constexpr bool has_srgb_permutes() {
  return Lanes<Arch>::size >= 16 && has_permute<Arch>();
}

// srgb_encode's clamp in every lane: [lowest, 1], a NaN to lowest (the first bucket's float).
template <class Arch>
REPROJECT_ALWAYS_INLINE inline xsimd::batch<float, Arch> srgb_clamp_lanes(const xsimd::batch<float, Arch>& linear) {
  REPROJECT_LANE_TYPES(Arch);
  const F lowest(float_of_bits(kSrgbFirstBucket << kSrgbBucketShift));
  const F l = xsimd::select(linear > lowest, linear, lowest);  // NaN too
  const F clamped = xsimd::select(l < F(1.0f), l, F(1.0f));
#if defined(__aarch64__) || defined(_M_ARM64)
  // clang for AArch64 may fold the two selects into fmaxnm and fminnm, which turn a signalling NaN
  // into 1 instead of lowest (as srgb_encode says of the scalar twin): NaN lanes are found by
  // their bits, which it cannot fold. (No blend makes a NaN; the contract holds for any input.)
  const I magnitude = bits_of<Arch>(linear) & I(0x7fffffff);
  return float_bits<Arch>(xsimd::select(magnitude > I(0x7f800000), bits_of<Arch>(lowest), bits_of<Arch>(clamped)));
#else
  return clamped;
#endif
}

// srgb_encode of clamped values through the table: the scalar encoder's steps, with one gather of
// the bucket words. The bucket's byte, plus one at or beyond its threshold: (low - step) >> 31 is
// -1 below it.
template <class Arch>
REPROJECT_ALWAYS_INLINE inline IntLanes<Arch> srgb_table_lanes(const SrgbTables& tables, const xsimd::batch<float, Arch>& l) {
  REPROJECT_LANE_TYPES(Arch);
  const I bits = bits_of<Arch>(l);
  const I word = bits_of<Arch>(gather<Arch>(reinterpret_cast<const float*>(tables.bucket),
                                            (bits >> kSrgbBucketShift) - I(static_cast<std::int32_t>(kSrgbFirstBucket))));
  const I below = ((bits & I(static_cast<std::int32_t>(kSrgbLowMask))) - (word & I(kSrgbStepMask))) >> 31;
  return (word >> kSrgbStepBits) + I(1) + below;
}

// srgb_encode of clamped values estimated without a gather (SrgbLookup::permutes; kernels/
// color_formats.hpp kSrgbPolynomial): `code` gets each lane's estimate, and the lanes that are set
// in the result lie within kSrgbEstimateMargin of a rounding boundary, where the estimate may be
// wrong; every other lane's estimate is the table's byte. (blend_rgba8 takes the table for every
// channel of a vector with any such lane.)
template <class Arch, class Fma>
REPROJECT_ALWAYS_INLINE inline xsimd::batch_bool<float, Arch> srgb_estimate_lanes(const SrgbTables& tables,
                                                                                 const xsimd::batch<float, Arch>& l,
                                                                                 IntLanes<Arch>& code) {
  REPROJECT_LANE_TYPES(Arch);
  static_assert(has_srgb_permutes<Arch>());
  const I bits = bits_of<Arch>(l);
  // l = m 2^e: m - 1 from the mantissa bits, e + 9 (at least 0) from the exponent's.
  const F t = float_bits<Arch>((bits & I(0x7fffff)) | I(0x3f800000)) - F(1.0f);
  F power(kSrgbPolynomial[0]);
  for (int k = 1; k < 7; ++k) power = vmadd<Fma>(power, t, F(kSrgbPolynomial[k]));
  const I scale_index = (bits >> 23) - I(127 + kSrgbLowestScaleExponent);
  LaneIndex<Arch> lanes;
  index_for_permute<Arch>(lanes, xsimd::select(scale_index > I(0), scale_index, I(0)));
  const F scale = permute<Arch>(F::load_aligned(tables.encode_scale), lanes);
  F estimate = vmadd<Fma>(power, scale, F(-kSrgbOffsetCodes));
  estimate = xsimd::select(l <= F(kSrgbLinearEnd), l * F(kSrgbSlopeCodes), estimate);
  const F half_up = estimate + F(0.5f);
  code = xsimd::to_int(half_up);
  const F past = half_up - xsimd::to_float(code);  // exact: where half_up lies between code and code + 1
  return (past < F(kSrgbEstimateMargin)) | (past > F(1.0f - kSrgbEstimateMargin));
}

// The linear value of each lane's byte (0..255), bit for bit tables.to_linear[byte]: a gather, or
// with SrgbLookup::permutes (sixteen lanes) the 256 entries as sixteen registers, a lane's entry
// picked by eight two-register permutes (the byte's low five bits) and a tree of selects on its
// bits 5, 6 and 7.
template <class Arch, SrgbLookup Lookup = SrgbLookup::gathers>
REPROJECT_ALWAYS_INLINE inline xsimd::batch<float, Arch> srgb_decode_lanes(const SrgbTables& tables,
                                                                           const IntLanes<Arch>& bytes) {
  REPROJECT_LANE_TYPES(Arch);
  static_assert(Lookup == SrgbLookup::gathers || has_srgb_permutes<Arch>());
  if constexpr (Lookup == SrgbLookup::permutes) {
    LaneIndex<Arch> lanes;
    index_for_two_registers<Arch>(lanes, bytes & I(31));
    I part[8];  // part[k]: entry 32 k + (byte & 31)
    for (int k = 0; k < 8; ++k) {
      part[k] = bits_of<Arch>(permute_two_registers<Arch>(F::load_aligned(tables.to_linear + 32 * k),
                                                          F::load_aligned(tables.to_linear + 32 * k + 16), lanes));
    }
    const auto bit5 = (bytes & I(32)) != I(0), bit6 = (bytes & I(64)) != I(0), bit7 = (bytes & I(128)) != I(0);
    const I low = xsimd::select(bit6, xsimd::select(bit5, part[3], part[2]), xsimd::select(bit5, part[1], part[0]));
    const I high = xsimd::select(bit6, xsimd::select(bit5, part[7], part[6]), xsimd::select(bit5, part[5], part[4]));
    return float_bits<Arch>(xsimd::select(bit7, high, low));
  } else {
    return gather<Arch>(tables.to_linear, bytes);
  }
}

// rgba8_srgb's channel C (0..2) of L pixels' words blended in linear light through the sRGB
// tables (scalar twin: blend_srgb_byte's last case, a pair neither near nor second-order): each
// lane's byte, 0..255. Consecutive: the caller's words are consecutive pixels, w1's lane i being w0's lane
// i + 1 (the column fetch's consecutive mode), so w0's linear values are w1's moved up one lane
// with w0's lane 0 looked up alone: one gather saved, the same values. Lookup: how the sRGB tables
// are read (the same bytes).
template <int C, class Arch, class Fma, bool Consecutive, SrgbLookup Lookup>
REPROJECT_ALWAYS_INLINE inline IntLanes<Arch> blend_srgb_channel(const Frame& f, const IntLanes<Arch>& w0,
                                                                 const IntLanes<Arch>& w1,
                                                                 const xsimd::batch<float, Arch>& frac) {
  using F = typename Lanes<Arch>::F;
  using I = IntLanes<Arch>;
  const F l1 = srgb_decode_lanes<Arch, Lookup>(*f.srgb, byte_lanes<C, Arch>(w1));
  F l0;
  if constexpr (Consecutive) {
    const std::uint32_t first_word = bits_of_float(first_lane<Arch>(float_bits<Arch>(w0)));
    l0 = shift_in_first<Arch>(l1, f.srgb->to_linear[(first_word >> (8 * C)) & 0xffu]);
  } else {
    l0 = srgb_decode_lanes<Arch, Lookup>(*f.srgb, byte_lanes<C, Arch>(w0));
  }
  const F linear = srgb_clamp_lanes<Arch>(vmadd<Fma>(frac, l1 - l0, l0));
  if constexpr (Lookup == SrgbLookup::permutes) {
    I code;
    if (!xsimd::any(srgb_estimate_lanes<Arch, Fma>(*f.srgb, linear, code))) return code;
  }
  return srgb_table_lanes<Arch>(*f.srgb, linear);
}

// rgba8_srgb's channel C of L pixels' words as srgb_second_order_blend (kernels/codes.hpp) blends
// it, the same float operations in the same order; `beyond` gets the lanes whose pair is not
// srgb_pair_second_order (|d| > min + 9, compared squared: exact, the values small integers).
template <int C, class Arch>
REPROJECT_ALWAYS_INLINE inline IntLanes<Arch> blend_srgb_second_order(const IntLanes<Arch>& w0, const IntLanes<Arch>& w1,
                                                                      const xsimd::batch<float, Arch>& frac,
                                                                      xsimd::batch_bool<float, Arch>& beyond) {
  using F = typename Lanes<Arch>::F;
  const F a = xsimd::to_float(byte_lanes<C, Arch>(w0)), b = xsimd::to_float(byte_lanes<C, Arch>(w1));
  const F d = b - a;
  const F limit = vmin(a, b) + F(9.0f);
  beyond = d * d > limit * limit;
  const F x = a + frac * d;
  const F bend = vdiv((frac - frac * frac) * (d * d) * F(0.7f), x + F(14.025f));
  return round_to_int<Arch>(x + bend);
}

// rgba8 / rgba8_srgb: L pixels' words blended (scalar twin: ColorRow::write). The bytes in fixed
// point, every channel of every pixel at once (the arch layer's blend_rgba8_q15: the same integers
// as blend_u8_q15, so every set stores the same bytes): all of rgba8, and of rgba8_srgb the alpha
// and each R, G, B byte whose pair is near (srgb_far_pairs). A channel with a far pair in some
// lane takes, in those lanes, the second-order blend (blend_srgb_second_order), or where even that
// is too far, the blend in linear light (blend_srgb_channel), which only such a channel computes.
template <class Arch, class Fma, bool Srgb, bool Consecutive = false, SrgbLookup Lookup = SrgbLookup::gathers>
REPROJECT_ALWAYS_INLINE inline IntLanes<Arch> blend_rgba8(const Frame& f, const IntLanes<Arch>& w0,
                                                          const IntLanes<Arch>& w1, const xsimd::batch<float, Arch>& frac) {
  using F = typename Lanes<Arch>::F;
  using I = IntLanes<Arch>;
  const I fixed = blend_rgba8_q15<Arch>(w0, w1, xsimd::to_int(frac * F(32768.0f)));  // weight_q15
  if constexpr (!Srgb) {
    return fixed;
  } else {
    const I far = srgb_far_pairs<Arch>(w0, w1);
    if (!xsimd::any(far != I(0))) return fixed;
    I out = fixed;
    auto channel = [&](auto c_tag) {
      constexpr int c = decltype(c_tag)::value;
      const I far_c = far & I(0xff << (8 * c));
      if (!xsimd::any(far_c != I(0))) return;
      typename Lanes<Arch>::B beyond;
      I code = blend_srgb_second_order<c, Arch>(w0, w1, frac, beyond);
      if (xsimd::any(beyond)) {
        const I linear = blend_srgb_channel<c, Arch, Fma, Consecutive, Lookup>(f, w0, w1, frac);
        code = bits_of<Arch>(xsimd::select(beyond, float_bits<Arch>(linear), float_bits<Arch>(code)));
      }
      out = (out & ~far_c) | ((code << (8 * c)) & far_c);
    };
    channel(std::integral_constant<int, 0>{});
    channel(std::integral_constant<int, 1>{});
    channel(std::integral_constant<int, 2>{});
    return out;
  }
}

// Read after the clock starts and written before it stops (time_srgb_lookups), so that the
// compiler can move none of the timed work out of the timed span.
volatile float srgb_timing_weight = 0.375f;
volatile std::uint32_t srgb_timing_sink = 0;

// Which SrgbLookup is faster on this processor, for a set with both (has_srgb_permutes): the
// rgba8_srgb blend in linear light of consecutive pixels (what the resolve runs on a channel with
// a pair beyond the second-order blend) timed with each in turn, best of five, on 1024 pixels of
// pseudo-random bytes, the tables in cache as in a frame. About 0.2 ms. Noise can only cost speed,
// never change a byte: both lookups give the same bytes.
template <class Arch, class Fma>
SrgbLookup time_srgb_lookups() {
  REPROJECT_LANE_TYPES(Arch);
  constexpr int kVectors = 64, kPasses = 4, kRounds = 5;
  alignas(64) std::int32_t words[kVectors * L + L];
  std::uint32_t state = 0x2545f491u;
  for (std::int32_t& w : words) {
    state = state * 1664525u + 1013904223u;
    w = static_cast<std::int32_t>(state);
  }
  Frame f;
  f.srgb = &srgb_tables();
  auto seconds = [&](auto lookup_tag) {
    constexpr SrgbLookup kLookup = decltype(lookup_tag)::value;
    const auto start = std::chrono::steady_clock::now();
    I mixed(0);
    for (int pass = 0; pass < kPasses; ++pass) {
      const F frac(srgb_timing_weight);  // read once per pass: no pass can be folded into another
      for (int v = 0; v < kVectors; ++v) {
        const I w0 = I::load_aligned(words + v * L), w1 = I::load_unaligned(words + v * L + 1);
        mixed = mixed + blend_srgb_channel<0, Arch, Fma, true, kLookup>(f, w0, w1, frac) +
                blend_srgb_channel<1, Arch, Fma, true, kLookup>(f, w0, w1, frac) +
                blend_srgb_channel<2, Arch, Fma, true, kLookup>(f, w0, w1, frac);
      }
    }
    alignas(64) std::int32_t lanes[L];
    mixed.store_aligned(lanes);
    std::uint32_t folded = 0;  // unsigned: the sum wraps (the vector sum above wraps too)
    for (std::int32_t lane : lanes) folded += static_cast<std::uint32_t>(lane);
    srgb_timing_sink = folded;
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };
  double best[2] = {1e30, 1e30};
  for (int round = 0; round < kRounds; ++round) {
    best[0] = std::min(best[0], seconds(std::integral_constant<SrgbLookup, SrgbLookup::gathers>{}));
    best[1] = std::min(best[1], seconds(std::integral_constant<SrgbLookup, SrgbLookup::permutes>{}));
  }
  return best[1] < best[0] ? SrgbLookup::permutes : SrgbLookup::gathers;
}

// time_srgb_lookups once per process (per table: KernelTable::srgb_lookup).
template <class Arch, class Fma>
SrgbLookup faster_srgb_lookup() {
  static const SrgbLookup faster = time_srgb_lookups<Arch, Fma>();
  return faster;
}

// Float RGBA and rgba16f: a pixel's four channels are one 128-bit register, so each lane's pixel
// is interpolated with one load per endpoint (no gathers); the same operations per channel as
// ColorRow (lerp4: c0 + frac (c1 - c0) with the table's FMA policy). A pixel is 16 bytes (float)
// or 8 (halves, converted exactly by the arch layer).
struct FloatRgbaPixel {
  static constexpr int kBytes = 16;
  static Pixel4 load(const std::uint8_t* p) { return load_float4(p); }
  static void store(std::uint8_t* p, Pixel4 v) { store_float4(p, v); }
};
struct HalfRgbaPixel {
  static constexpr int kBytes = 8;
  static Pixel4 load(const std::uint8_t* p) { return load_half4(p); }
  static void store(std::uint8_t* p, Pixel4 v) { store_half4(p, v); }
};

// The L pixels of one vector: interpolated between columns j0 and j1 at frac; lanes with
// `keep` set are left to the caller, lanes with `black` set are written as zeros.
template <class Arch, class Fma, class Pixel>
REPROJECT_ALWAYS_INLINE inline void resolve_rgba_pixels(const std::uint8_t* source, std::uint8_t* target,
                                                        const xsimd::batch<float, Arch>& j0,
                                                        const xsimd::batch<float, Arch>& j1,
                                                        const xsimd::batch<float, Arch>& frac,
                                                        const xsimd::batch_bool<float, Arch>& keep,
                                                        const xsimd::batch_bool<float, Arch>& black, bool any_special) {
  REPROJECT_LANE_TYPES(Arch);
  alignas(64) std::int32_t first[L], second[L];
  alignas(64) float weight[L];
  (xsimd::to_int(j0) * I(Pixel::kBytes)).store_aligned(first);
  (xsimd::to_int(j1) * I(Pixel::kBytes)).store_aligned(second);
  frac.store_aligned(weight);
  auto blend = [&](int i) {
    return lerp4<Fma>(pixel4_splat(weight[i]), Pixel::load(source + first[i]), Pixel::load(source + second[i]));
  };
  if (!any_special) {
    for (int i = 0; i < L; ++i) Pixel::store(target + Pixel::kBytes * i, blend(i));
    return;
  }
  alignas(64) float kept[L], blacked[L];
  xsimd::select(keep, F(1.0f), F(0.0f)).store_aligned(kept);
  xsimd::select(black, F(1.0f), F(0.0f)).store_aligned(blacked);
  for (int i = 0; i < L; ++i) {
    if (kept[i] != 0.0f) continue;
    Pixel::store(target + Pixel::kBytes * i, blacked[i] != 0.0f ? pixel4_zero() : blend(i));
  }
}

}  // namespace
}  // namespace reproject::detail
