// SIMD twins of kernels/pixel_formats.hpp's loads and stores (docs/BEHAVIOUR.md "Pixel formats"):
// the same integer arithmetic and correctly rounded float operations, lane by lane, so every arch
// stores the same bits as the scalar reference. Used by kernels/stages_simd.hpp only.
#pragma once

#include <cstring>
#include <type_traits>

#include "kernels/pixel_formats.hpp"
#include "kernels/simd.hpp"

namespace reproject {
namespace detail {
namespace {  // one copy per arch TU (kernels/simd.hpp)

template <class Arch>
using IntLanes = typename Lanes<Arch>::I;

template <class Arch>
IntLanes<Arch> bits_of(const xsimd::batch<float, Arch>& v) {
  return xsimd::bitwise_cast<IntLanes<Arch>>(v);
}
template <class Arch>
xsimd::batch<float, Arch> float_bits(const IntLanes<Arch>& v) {
  return xsimd::bitwise_cast<xsimd::batch<float, Arch>>(v);
}

// Calls body(tag) with a compile-time tag of the depth format, so that the row loops are
// compiled once per format (no branch per vector).
template <DepthFormat Format>
using DepthFormatTag = std::integral_constant<DepthFormat, Format>;
template <class Body>
void with_depth_format(DepthFormat format, const Body& body) {
  switch (format) {
    case DepthFormat::unorm16: return body(DepthFormatTag<DepthFormat::unorm16>{});
    case DepthFormat::unorm24_s8: return body(DepthFormatTag<DepthFormat::unorm24_s8>{});
    case DepthFormat::s8_unorm24: return body(DepthFormatTag<DepthFormat::s8_unorm24>{});
    case DepthFormat::rgba8_packed_linear: return body(DepthFormatTag<DepthFormat::rgba8_packed_linear>{});
    case DepthFormat::float32: break;
  }
  body(DepthFormatTag<DepthFormat::float32>{});
}

// L consecutive 16-bit codes, zero-extended.
template <class Arch>
IntLanes<Arch> load_u16(const std::uint8_t* p) {
#if defined(__AVX512F__)
  if constexpr (sizeof(IntLanes<Arch>) == 64) return _mm512_cvtepu16_epi32(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(p)));
#endif
#if defined(__AVX2__)
  if constexpr (sizeof(IntLanes<Arch>) == 32) return _mm256_cvtepu16_epi32(_mm_loadu_si128(reinterpret_cast<const __m128i*>(p)));
#endif
  if constexpr (sizeof(IntLanes<Arch>) == 16) {
    return _mm_cvtepu16_epi32(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(p)));
  } else {
    constexpr int L = Lanes<Arch>::size;
    alignas(64) std::int32_t codes[L];
    for (int i = 0; i < L; ++i) {
      std::uint16_t code;
      std::memcpy(&code, p + 2 * i, 2);
      codes[i] = code;
    }
    return IntLanes<Arch>::load_aligned(codes);
  }
}

// u / (2^Bits - 1) correctly rounded (scalar twin: unorm_value, a division). Where the table has
// an FMA, without the division: with x = u 2^-Bits (exact), fma(x, c, x) for c the float just
// above 2^-Bits is the correctly rounded quotient for every 16- and 24-bit code (u / (2^b - 1) =
// x (1 + 2^-b + 2^-2b + ...); checked exhaustively by PixelFormats.UnormDecodeEveryCodeEveryArch).
template <class Arch, class Fma, int Bits>
xsimd::batch<float, Arch> unorm_values(const IntLanes<Arch>& code) {
  using F = typename Lanes<Arch>::F;
  constexpr float kMax = Bits == 16 ? kUnorm16Max : kUnorm24Max;
  if constexpr (std::is_same<Fma, Fused>::value) {
    constexpr float kUnit = Bits == 16 ? 0x1p-16f : 0x1p-24f;
    constexpr float kAbove = Bits == 16 ? 0x1.000002p-16f : 0x1.000002p-24f;
    const F x = xsimd::to_float(code) * F(kUnit);
    return vmadd<Fma>(x, F(kAbove), x);
  } else {
    return xsimd::to_float(code) / F(kMax);
  }
}

// The stored values d of L depth words of a 32-bit integer format (scalar twin: depth_value).
template <class Arch, class Fma, DepthFormat Format>
xsimd::batch<float, Arch> depth_values_of_words(const Frame& f, const IntLanes<Arch>& word) {
  using F = typename Lanes<Arch>::F;
  using I = IntLanes<Arch>;
  static_assert(Format != DepthFormat::float32 && Format != DepthFormat::unorm16, "32-bit integer words only");
  if constexpr (Format == DepthFormat::unorm24_s8) return unorm_values<Arch, Fma, 24>(word & I(0xffffff));
  if constexpr (Format == DepthFormat::s8_unorm24) return unorm_values<Arch, Fma, 24>((word >> 8) & I(0xffffff));
  if constexpr (Format == DepthFormat::rgba8_packed_linear) {
    const I code = (word & I(0xff)) * I(65025) + ((word >> 8) & I(0xff)) * I(255) + ((word >> 16) & I(0xff));
    return (xsimd::to_float(code) / F(kPackedMax)) * F(f.packed_range) + F(f.packed_near);  // never fused
  }
}
template <class Arch, class Fma>
__attribute__((always_inline)) inline xsimd::batch<float, Arch> depth_values_of_words(const Frame& f,
                                                                                    const IntLanes<Arch>& word) {
  switch (f.depth.format) {
    case DepthFormat::unorm24_s8: return depth_values_of_words<Arch, Fma, DepthFormat::unorm24_s8>(f, word);
    case DepthFormat::s8_unorm24: return depth_values_of_words<Arch, Fma, DepthFormat::s8_unorm24>(f, word);
    case DepthFormat::rgba8_packed_linear: return depth_values_of_words<Arch, Fma, DepthFormat::rgba8_packed_linear>(f, word);
    case DepthFormat::unorm16:
    case DepthFormat::float32: break;
  }
  return float_bits<Arch>(word);
}

// The stored values d of columns [i, i + L) of a depth row (scalar twin: depth_value).
template <class Arch, class Fma, DepthFormat Format>
xsimd::batch<float, Arch> load_depth_values(const Frame& f, const std::uint8_t* row, int i) {
  using F = typename Lanes<Arch>::F;
  using I = IntLanes<Arch>;
  if constexpr (Format == DepthFormat::float32) {
    return F::load_unaligned(reinterpret_cast<const float*>(row) + i);
  } else if constexpr (Format == DepthFormat::unorm16) {
    return unorm_values<Arch, Fma, 16>(load_u16<Arch>(row + 2 * static_cast<std::ptrdiff_t>(i)));
  } else {
    const I word = I::load_unaligned(reinterpret_cast<const std::int32_t*>(row + 4 * static_cast<std::ptrdiff_t>(i)));
    return depth_values_of_words<Arch, Fma, Format>(f, word);
  }
}

// Twins of round_even and clamp_code.
template <class Arch>
xsimd::batch<float, Arch> round_even_v(const xsimd::batch<float, Arch>& x) {
  using F = typename Lanes<Arch>::F;
  const F magic(8388608.0f);
  return xsimd::select(x < magic, (x + magic) - magic, x);
}
template <class Arch>
xsimd::batch<float, Arch> clamp_code_v(const xsimd::batch<float, Arch>& x, float max) {
  using F = typename Lanes<Arch>::F;
  const F positive = xsimd::select(x > F(0.0f), x, F(0.0f));
  return xsimd::select(positive < F(max), positive, F(max));
}
template <class Arch>
IntLanes<Arch> unorm_code_v(const xsimd::batch<float, Arch>& d, float max) {
  using F = typename Lanes<Arch>::F;
  return xsimd::to_int(round_even_v<Arch>(clamp_code_v<Arch>(d * F(max), max)));
}

// The words that store depth d (scalar twin: depth_word); `kept` as there.
template <class Arch>
__attribute__((always_inline)) inline IntLanes<Arch> depth_words(const Frame& f, const xsimd::batch<float, Arch>& d, const IntLanes<Arch>& kept) {
  using F = typename Lanes<Arch>::F;
  using I = IntLanes<Arch>;
  switch (f.depth.format) {
    case DepthFormat::unorm16: return unorm_code_v<Arch>(d, kUnorm16Max);
    case DepthFormat::unorm24_s8: return unorm_code_v<Arch>(d, kUnorm24Max) | (kept & I(static_cast<std::int32_t>(0xff000000u)));
    case DepthFormat::s8_unorm24: return (unorm_code_v<Arch>(d, kUnorm24Max) << 8) | (kept & I(0xff));
    case DepthFormat::rgba8_packed_linear: {
      const F v = (d - F(f.packed_near)) / F(f.packed_range);
      const I n = xsimd::to_int(round_even_v<Arch>(clamp_code_v<Arch>(v * F(kPackedMax), kPackedMax - 1.0f)));
      // Exact quotients from correctly rounded float divisions: n < 2^24, and each true quotient
      // lies at least 1/65025 (1/255) below the next integer, more than the division's rounding.
      const I r = xsimd::to_int(xsimd::to_float(n) / F(65025.0f));
      const I rest = n - r * I(65025);
      const I g = xsimd::to_int(xsimd::to_float(rest) / F(255.0f));
      return r | (g << 8) | ((rest - g * I(255)) << 16) | (kept & I(static_cast<std::int32_t>(0xff000000u)));
    }
    case DepthFormat::float32: break;
  }
  return bits_of<Arch>(d);
}

// Stores L 16-bit codes; with `masked`, only the lanes in `write`.
template <class Arch>
void store_u16(const IntLanes<Arch>& codes, const xsimd::batch_bool<float, Arch>& write, bool masked, std::uint8_t* out) {
  using F = typename Lanes<Arch>::F;
  constexpr int L = Lanes<Arch>::size;
#if defined(__AVX512F__)
  if constexpr (L == 16) {
    const __mmask16 lanes = masked ? static_cast<__mmask16>(write) : static_cast<__mmask16>(0xffff);
    return _mm512_mask_cvtepi32_storeu_epi16(out, lanes, codes);
  }
#endif
#if defined(__AVX2__)
  if constexpr (L == 8) {
    const __m256i c = codes;
    __m128i packed = _mm_packus_epi32(_mm256_castsi256_si128(c), _mm256_extracti128_si256(c, 1));  // codes <= 65535
    if (masked) {
      const __m256i m = _mm256_castps_si256(static_cast<__m256>(write));
      const __m128i keep = _mm_packs_epi32(_mm256_castsi256_si128(m), _mm256_extracti128_si256(m, 1));
      packed = _mm_blendv_epi8(_mm_loadu_si128(reinterpret_cast<const __m128i*>(out)), packed, keep);
    }
    return _mm_storeu_si128(reinterpret_cast<__m128i*>(out), packed);
  }
#endif
  alignas(64) std::int32_t code[L];
  alignas(64) float written[L];
  codes.store_aligned(code);
  xsimd::select(write, F(1.0f), F(0.0f)).store_aligned(written);
  for (int i = 0; i < L; ++i) {
    if (masked && written[i] == 0.0f) continue;
    const std::uint16_t value = static_cast<std::uint16_t>(code[i]);
    std::memcpy(out + 2 * i, &value, 2);
  }
}

// rgba8 / rgba8_srgb: L pixels' words blended channel by channel (scalar twin: ColorRow::write).
// The rgba8 blend of two bytes lies between them (frac is in [0, 1] and both ends are floats),
// so the scalar reference's clamp never acts and the rounding is the conversion instruction's
// (round to nearest even, the default mode the scalar (x + 2^23) - 2^23 relies on too).
template <class Arch, class Fma, bool Srgb>
__attribute__((always_inline)) inline IntLanes<Arch> blend_rgba8(const Frame& f, const IntLanes<Arch>& w0,
                                                                 const IntLanes<Arch>& w1,
                                                                 const xsimd::batch<float, Arch>& frac) {
  using F = typename Lanes<Arch>::F;
  using I = IntLanes<Arch>;
  I out(0);
  for (int c = 0; c < 4; ++c) {
    // (A shift of 24 leaves the sign bits of an arithmetic shift: masked like the others.)
    const I b0 = c == 0 ? w0 & I(0xff) : (w0 >> (8 * c)) & I(0xff);
    const I b1 = c == 0 ? w1 & I(0xff) : (w1 >> (8 * c)) & I(0xff);
    I byte;
    if (Srgb && c < 3) {
      const F l0 = gather<Arch>(f.srgb->to_linear, b0);
      const F l1 = gather<Arch>(f.srgb->to_linear, b1);
      const F linear = vmadd<Fma>(frac, l1 - l0, l0);
      // srgb_encode: the bucket's byte, plus one at or beyond its threshold.
      const F lowest(float_of_bits(kSrgbFirstBucket << kSrgbBucketShift));
      F l = xsimd::select(linear > lowest, linear, lowest);
      l = xsimd::select(l < F(1.0f), l, F(1.0f));
      const I bucket = (bits_of<Arch>(l) >> kSrgbBucketShift) - I(static_cast<std::int32_t>(kSrgbFirstBucket));
      const I first = bits_of<Arch>(gather<Arch>(reinterpret_cast<const float*>(f.srgb->bucket_byte), bucket));
      const F next = gather<Arch>(f.srgb->bucket_next, bucket);
      byte = first + xsimd::to_int(xsimd::select(l >= next, F(1.0f), F(0.0f)));
    } else {
      // float(b1 - b0) is float(b1) - float(b0) exactly (small integers): one conversion fewer.
      byte = xsimd::nearbyint_as_int(vmadd<Fma>(frac, xsimd::to_float(b1 - b0), xsimd::to_float(b0)));
    }
    out = out | (byte << (8 * c));
  }
  return out;
}

// rgba16f, one pixel per 128-bit vector (scalar twin: ColorRow::write): F16C where the TU has
// it, the exact scalar conversions elsewhere.
inline __m128 load_half4(const std::uint8_t* p) {
#if defined(__F16C__)
  return _mm_cvtph_ps(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(p)));
#else
  alignas(16) float v[4];
  for (int c = 0; c < 4; ++c) {
    std::uint16_t h;
    std::memcpy(&h, p + 2 * c, 2);
    v[c] = half_to_float(h);
  }
  return _mm_load_ps(v);
#endif
}
inline void store_half4(std::uint8_t* p, __m128 value) {
#if defined(__F16C__)
  _mm_storel_epi64(reinterpret_cast<__m128i*>(p), _mm_cvtps_ph(value, _MM_FROUND_TO_NEAREST_INT | _MM_FROUND_NO_EXC));
#else
  alignas(16) float v[4];
  _mm_store_ps(v, value);
  for (int c = 0; c < 4; ++c) {
    const std::uint16_t h = float_to_half(v[c]);
    std::memcpy(p + 2 * c, &h, 2);
  }
#endif
}

}  // namespace
}  // namespace detail
}  // namespace reproject
