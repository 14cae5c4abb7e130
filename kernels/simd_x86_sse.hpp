// Internal: the SSE4.1 block of the x86 arch layer (kernels/simd_x86.hpp, which includes this file
// after X86Set's primary template; contracts: kernels/arch_layer.hpp).
#pragma once

#include <immintrin.h>

#include <cstdint>
#include <cstring>
#include <xsimd/xsimd.hpp>

namespace reproject::detail {
namespace {  // one copy per arch TU (kernels/fma.hpp)

// ---- SSE4.1: 4 lanes, no FMA, no variable permute ----
template <>
struct X86Set<xsimd::sse4_1> {
  using F = xsimd::batch<float, xsimd::sse4_1>;
  using I = xsimd::batch<std::int32_t, xsimd::sse4_1>;
  using B = xsimd::batch_bool<float, xsimd::sse4_1>;
  static constexpr bool kHasFma = false;
  static constexpr bool kHasPermute = false;
  struct LaneIndex {
    I index;
  };

  static I bits_of(const F& v) { return _mm_castps_si128(v); }
  static F float_bits(const I& v) { return _mm_castsi128_ps(v); }
  static F floor(const F& x) { return _mm_round_ps(x, _MM_FROUND_FLOOR); }
  static F min(const F& a, const F& b) { return _mm_min_ps(a, b); }
  static F max(const F& a, const F& b) { return _mm_max_ps(a, b); }
  static I round_to_int(const F& x) { return _mm_cvtps_epi32(x); }
  static F gather(const float* base, const I& index) {  // four loads (memcpy: any byte address)
    alignas(16) std::int32_t at[4];
    alignas(16) float value[4];
    index.store_aligned(at);
    for (int i = 0; i < 4; ++i) std::memcpy(&value[i], base + at[i], sizeof(float));
    return F::load_aligned(value);
  }
  template <bool Max>
  static std::int32_t lane_extreme_key(__m128i k) {
    auto op = [](__m128i x, __m128i y) { return Max ? _mm_max_epi32(x, y) : _mm_min_epi32(x, y); };
    k = op(k, _mm_shuffle_epi32(k, _MM_SHUFFLE(1, 0, 3, 2)));
    k = op(k, _mm_shuffle_epi32(k, _MM_SHUFFLE(2, 3, 0, 1)));
    return _mm_cvtsi128_si32(k);
  }
  template <int Byte>
  static I byte_lanes(const I& w) {
    if constexpr (Byte == 3) return _mm_srli_epi32(w, 24);
    constexpr char z = -128;  // a shuffle index with its top bit set writes zero
    return _mm_shuffle_epi8(w, _mm_setr_epi8(Byte, z, z, z, Byte + 4, z, z, z, Byte + 8, z, z, z, Byte + 12, z, z, z));
  }
  // Channels widened to 16 bits (pixels 0-1, then 2-3 of each 128-bit lane), each pixel's weight
  // copied to its four channels, one multiply-high with rounding per eight channels, packed back.
  static I blend_rgba8_q15(const I& c0, const I& c1, const I& weight) {
    const __m128i zero = _mm_setzero_si128();
    const __m128i first = _mm_setr_epi8(0, 1, 0, 1, 0, 1, 0, 1, 4, 5, 4, 5, 4, 5, 4, 5);
    const __m128i second = _mm_setr_epi8(8, 9, 8, 9, 8, 9, 8, 9, 12, 13, 12, 13, 12, 13, 12, 13);
    const __m128i a0 = _mm_unpacklo_epi8(c0, zero), a1 = _mm_unpackhi_epi8(c0, zero);
    const __m128i d0 = _mm_sub_epi16(_mm_unpacklo_epi8(c1, zero), a0), d1 = _mm_sub_epi16(_mm_unpackhi_epi8(c1, zero), a1);
    const __m128i r0 = _mm_add_epi16(a0, _mm_mulhrs_epi16(d0, _mm_shuffle_epi8(weight, first)));
    const __m128i r1 = _mm_add_epi16(a1, _mm_mulhrs_epi16(d1, _mm_shuffle_epi8(weight, second)));
    return _mm_packus_epi16(r0, r1);
  }
  // Bytes: the difference max - min beyond the limit ((min + 4) >> 3) + 10 (a 16-bit shift, its
  // bits from the next byte masked off), by a saturating subtraction that is zero unless beyond.
  static I srgb_far_pairs(const I& c0, const I& c1) {
    const __m128i low = _mm_min_epu8(c0, c1), difference = _mm_sub_epi8(_mm_max_epu8(c0, c1), low);
    const __m128i limit = _mm_add_epi8(
        _mm_and_si128(_mm_srli_epi16(_mm_adds_epu8(low, _mm_set1_epi8(4)), 3), _mm_set1_epi8(0x1f)), _mm_set1_epi8(10));
    const __m128i near = _mm_cmpeq_epi8(_mm_subs_epu8(difference, limit), _mm_setzero_si128());
    return _mm_andnot_si128(near, _mm_set1_epi32(0x00ffffff));
  }
  static F shift_in_first(const F& v, __m128 first) {  // bytes 12..15 of `first`'s broadcast, then v's 0..11
    return _mm_castsi128_ps(_mm_alignr_epi8(_mm_castps_si128(v), _mm_castps_si128(_mm_shuffle_ps(first, first, 0)), 12));
  }
  static void store_first_lanes(const F& value, float* out, int count) {  // read, merge, write
    const I lanes = _mm_setr_epi32(0, 1, 2, 3);
    const __m128 write = _mm_castsi128_ps(_mm_cmpgt_epi32(_mm_set1_epi32(count), lanes));
    _mm_storeu_ps(out, _mm_blendv_ps(_mm_loadu_ps(out), value, write));
  }
  static void store_bytes(const F& value, std::uint8_t* out) {
    const __m128i words = _mm_cvttps_epi32(value);
    const __m128i halves = _mm_packus_epi32(words, words);
    const std::uint32_t four = static_cast<std::uint32_t>(_mm_cvtsi128_si32(_mm_packus_epi16(halves, halves)));
    std::memcpy(out, &four, 4);
  }
  static I load_u16(const std::uint8_t* p) { return _mm_cvtepu16_epi32(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(p))); }
  static void store_u16(const I& codes, const B& write, bool masked, std::uint8_t* out) {
    __m128i packed = _mm_packus_epi32(codes, codes);
    if (masked) {
      const __m128i m = _mm_castps_si128(static_cast<__m128>(write));
      packed = _mm_blendv_epi8(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(out)), packed, _mm_packs_epi32(m, m));
    }
    _mm_storel_epi64(reinterpret_cast<__m128i*>(out), packed);
  }
};

}  // namespace
}  // namespace reproject::detail
