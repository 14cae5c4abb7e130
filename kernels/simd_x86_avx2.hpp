// Internal: the AVX2 + FMA block of the x86 arch layer (kernels/simd_x86.hpp, which includes this file
// after X86Set's primary template; contracts: kernels/arch_layer.hpp).
#pragma once

#include <immintrin.h>

#include <cstdint>
#include <cstring>
#include <xsimd/xsimd.hpp>

#include "kernels/fma.hpp"  // REPROJECT_FMA3: MSVC defines no __FMA__

namespace reproject::detail {
namespace {  // one copy per arch TU (kernels/fma.hpp)

#if defined(__AVX2__) && REPROJECT_FMA3
// ---- AVX2 + FMA: 8 lanes; the permute reaches one register, so two-register permutes blend ----
template <>
struct X86Set<xsimd::fma3<xsimd::avx2>> {
  using F = xsimd::batch<float, xsimd::fma3<xsimd::avx2>>;
  using I = xsimd::batch<std::int32_t, xsimd::fma3<xsimd::avx2>>;
  using B = xsimd::batch_bool<float, xsimd::fma3<xsimd::avx2>>;
  static constexpr bool kHasFma = true;
  static constexpr bool kHasPermute = true;
  struct LaneIndex {
    I index;
    __m256 from_high;  // two registers: all ones where index >= 8
  };

  static F fmadd(const F& a, const F& b, const F& c) { return _mm256_fmadd_ps(a, b, c); }
  static I bits_of(const F& v) { return _mm256_castps_si256(v); }
  static F float_bits(const I& v) { return _mm256_castsi256_ps(v); }
  static F floor(const F& x) { return _mm256_round_ps(x, _MM_FROUND_FLOOR); }
  static F min(const F& a, const F& b) { return _mm256_min_ps(a, b); }
  static F max(const F& a, const F& b) { return _mm256_max_ps(a, b); }
  static I round_to_int(const F& x) { return _mm256_cvtps_epi32(x); }
  static F gather(const float* base, const I& index) { return _mm256_i32gather_ps(base, index, 4); }
  template <bool Max>
  static std::int32_t lane_extreme_key(__m256i k) {
    auto op = [](__m128i x, __m128i y) { return Max ? _mm_max_epi32(x, y) : _mm_min_epi32(x, y); };
    return X86Set<xsimd::sse4_1>::lane_extreme_key<Max>(op(_mm256_castsi256_si128(k), _mm256_extracti128_si256(k, 1)));
  }
  // A constant whose every 128-bit part holds the words a, b, c, d (folded to one constant load;
  // a 128-bit constant broadcast is rebuilt in the loop by GCC 12).
  static __m256i each_128_bits(int a, int b, int c, int d) { return _mm256_setr_epi32(a, b, c, d, a, b, c, d); }
  // (Only rgba8_srgb's decode uses it. Its shuffle control is a 128-bit constant broadcast, which
  // GCC 12 rebuilds in the loop: on the Intel Xeon, rgba8_srgb ran 1.16x slower with the whole-
  // register constant (each_128_bits) and as fast with two shifts as with that, docs/PERFORMANCE.md
  // "Measured design choices".)
  template <int Byte>
  static I byte_lanes(const I& w) {
    if constexpr (Byte == 3) return _mm256_srli_epi32(w, 24);
    constexpr char z = -128;  // a shuffle index with its top bit set writes zero
    const __m128i pick = _mm_setr_epi8(Byte, z, z, z, Byte + 4, z, z, z, Byte + 8, z, z, z, Byte + 12, z, z, z);
    return _mm256_shuffle_epi8(w, _mm256_broadcastsi128_si256(pick));
  }
  static float first_lane(const F& v) { return _mm256_cvtss_f32(v); }
  static F shift_in_first(const F& v, __m128 first) {
    const F up = _mm256_permutevar8x32_ps(v, _mm256_setr_epi32(0, 0, 1, 2, 3, 4, 5, 6));
    return _mm256_blend_ps(up, _mm256_castps128_ps256(first), 1);
  }
  static I blend_rgba8_q15(const I& c0, const I& c1, const I& weight) {  // as SSE4.1's, per 128-bit lane
    const __m256i zero = _mm256_setzero_si256();
    // Each pixel's weight (bytes 0-1 of its lane) beside each of its four 16-bit channels.
    const __m256i first = each_128_bits(0x01000100, 0x01000100, 0x05040504, 0x05040504);
    const __m256i second = each_128_bits(0x09080908, 0x09080908, 0x0d0c0d0c, 0x0d0c0d0c);
    const __m256i a0 = _mm256_unpacklo_epi8(c0, zero), a1 = _mm256_unpackhi_epi8(c0, zero);
    const __m256i d0 = _mm256_sub_epi16(_mm256_unpacklo_epi8(c1, zero), a0);
    const __m256i d1 = _mm256_sub_epi16(_mm256_unpackhi_epi8(c1, zero), a1);
    const __m256i r0 = _mm256_add_epi16(a0, _mm256_mulhrs_epi16(d0, _mm256_shuffle_epi8(weight, first)));
    const __m256i r1 = _mm256_add_epi16(a1, _mm256_mulhrs_epi16(d1, _mm256_shuffle_epi8(weight, second)));
    return _mm256_packus_epi16(r0, r1);
  }
  static I srgb_far_pairs(const I& c0, const I& c1) {  // as SSE4.1's
    const __m256i low = _mm256_min_epu8(c0, c1), difference = _mm256_sub_epi8(_mm256_max_epu8(c0, c1), low);
    const __m256i limit = _mm256_add_epi8(
        _mm256_and_si256(_mm256_srli_epi16(_mm256_adds_epu8(low, _mm256_set1_epi8(4)), 3), _mm256_set1_epi8(0x1f)),
        _mm256_set1_epi8(10));
    const __m256i near = _mm256_cmpeq_epi8(_mm256_subs_epu8(difference, limit), _mm256_setzero_si256());
    return _mm256_andnot_si256(near, _mm256_set1_epi32(0x00ffffff));
  }
  static void index_for_two_registers(LaneIndex& lanes, const I& index) {
    lanes.index = index;
    lanes.from_high = _mm256_castsi256_ps(_mm256_cmpgt_epi32(index, _mm256_set1_epi32(7)));
  }
  static F permute(const F& v, const LaneIndex& lanes) { return _mm256_permutevar8x32_ps(v, lanes.index); }
  static F permute_two_registers(const F& low, const F& high, const LaneIndex& lanes) {
    return _mm256_blendv_ps(permute(low, lanes), permute(high, lanes), lanes.from_high);
  }
  static void store_first_lanes(const F& value, float* out, int count) {  // a masked store
    const __m256i lanes = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
    _mm256_maskstore_ps(out, _mm256_cmpgt_epi32(_mm256_set1_epi32(count), lanes), value);
  }
  static void store_bytes(const F& value, std::uint8_t* out) {
    const __m256i words = _mm256_cvttps_epi32(value);
    const __m128i halves = _mm_packus_epi32(_mm256_castsi256_si128(words), _mm256_extracti128_si256(words, 1));
    _mm_storel_epi64(reinterpret_cast<__m128i*>(out), _mm_packus_epi16(halves, halves));
  }
  static I load_u16(const std::uint8_t* p) { return _mm256_cvtepu16_epi32(_mm_loadu_si128(reinterpret_cast<const __m128i*>(p))); }
  static void store_u16(const I& codes, const B& write, bool masked, std::uint8_t* out) {
    const __m256i c = codes;
    __m128i packed = _mm_packus_epi32(_mm256_castsi256_si128(c), _mm256_extracti128_si256(c, 1));
    if (masked) {
      const __m256i m = _mm256_castps_si256(static_cast<__m256>(write));
      const __m128i keep = _mm_packs_epi32(_mm256_castsi256_si128(m), _mm256_extracti128_si256(m, 1));
      packed = _mm_blendv_epi8(_mm_loadu_si128(reinterpret_cast<const __m128i*>(out)), packed, keep);
    }
    _mm_storeu_si128(reinterpret_cast<__m128i*>(out), packed);
  }
};
#endif

}  // namespace
}  // namespace reproject::detail
