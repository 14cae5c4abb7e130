// Internal: the AVX-512 block of the x86 arch layer (kernels/simd_x86.hpp, which includes this file
// after X86Set's primary template; contracts: kernels/arch_layer.hpp).
#pragma once

#include <immintrin.h>

#include <cstdint>
#include <cstring>
#include <xsimd/xsimd.hpp>

namespace reproject::detail {
namespace {  // one copy per arch TU (kernels/fma.hpp)

#if defined(__AVX512F__) && defined(__AVX512BW__)
// ---- AVX-512 (F, CD, DQ, BW): 16 lanes, masked stores, two-register permutes in one instruction ----
template <>
struct X86Set<xsimd::avx512bw> {
  using F = xsimd::batch<float, xsimd::avx512bw>;
  using I = xsimd::batch<std::int32_t, xsimd::avx512bw>;
  using B = xsimd::batch_bool<float, xsimd::avx512bw>;
  static constexpr bool kHasFma = true;
  static constexpr bool kHasPermute = true;
  struct LaneIndex {
    I index;
  };

  // Named, not xsimd::fma: xsimd 8.1 has no fma kernel for avx512f and falls back to x * y + z.
  static F fmadd(const F& a, const F& b, const F& c) { return _mm512_fmadd_ps(a, b, c); }
  static I bits_of(const F& v) { return _mm512_castps_si512(v); }
  static F float_bits(const I& v) { return _mm512_castsi512_ps(v); }
  static F floor(const F& x) { return _mm512_roundscale_ps(x, _MM_FROUND_TO_NEG_INF); }
  static F min(const F& a, const F& b) { return _mm512_min_ps(a, b); }
  static F max(const F& a, const F& b) { return _mm512_max_ps(a, b); }
  static I round_to_int(const F& x) { return _mm512_cvtps_epi32(x); }
  static F gather(const float* base, const I& index) { return _mm512_i32gather_ps(index, base, 4); }
  template <bool Max>
  static std::int32_t lane_extreme_key(__m512i k) {
    return Max ? _mm512_reduce_max_epi32(k) : _mm512_reduce_min_epi32(k);
  }
  // A constant whose every 128-bit part holds the words a, b, c, d (folded to one constant load;
  // a 128-bit constant broadcast is rebuilt in the loop by GCC 12).
  static __m512i each_128_bits(int a, int b, int c, int d) { return _mm512_setr4_epi32(a, b, c, d); }
  // Two shifts, no constant (only rgba8_srgb's decode uses it): on the Intel Xeon 1.15x faster
  // rgba8_srgb than a shuffle by a whole-register constant (docs/PERFORMANCE.md "Measured design
  // choices").
  template <int Byte>
  static I byte_lanes(const I& w) {
    if constexpr (Byte == 3) return _mm512_srli_epi32(w, 24);
    return _mm512_srli_epi32(_mm512_slli_epi32(w, 24 - 8 * Byte), 24);
  }
  static float first_lane(const F& v) { return _mm512_cvtss_f32(v); }
  static F shift_in_first(const F& v, __m128 first) {  // lane 15 of `first`'s broadcast, then v's 0..14
    const __m512i low = _mm512_castps_si512(_mm512_broadcastss_ps(first));
    return _mm512_castsi512_ps(_mm512_alignr_epi32(_mm512_castps_si512(v), low, 15));
  }
  static I blend_rgba8_q15(const I& c0, const I& c1, const I& weight) {  // as SSE4.1's, per 128-bit lane
    const __m512i zero = _mm512_setzero_si512();
    // Each pixel's weight (bytes 0-1 of its lane) beside each of its four 16-bit channels.
    const __m512i first = each_128_bits(0x01000100, 0x01000100, 0x05040504, 0x05040504);
    const __m512i second = each_128_bits(0x09080908, 0x09080908, 0x0d0c0d0c, 0x0d0c0d0c);
    const __m512i a0 = _mm512_unpacklo_epi8(c0, zero), a1 = _mm512_unpackhi_epi8(c0, zero);
    const __m512i d0 = _mm512_sub_epi16(_mm512_unpacklo_epi8(c1, zero), a0);
    const __m512i d1 = _mm512_sub_epi16(_mm512_unpackhi_epi8(c1, zero), a1);
    const __m512i r0 = _mm512_add_epi16(a0, _mm512_mulhrs_epi16(d0, _mm512_shuffle_epi8(weight, first)));
    const __m512i r1 = _mm512_add_epi16(a1, _mm512_mulhrs_epi16(d1, _mm512_shuffle_epi8(weight, second)));
    return _mm512_packus_epi16(r0, r1);
  }
  // As SSE4.1's, the comparison into a mask register that holds only the R, G, B bytes' bits.
  static I srgb_far_pairs(const I& c0, const I& c1) {
    const __m512i low = _mm512_min_epu8(c0, c1), difference = _mm512_sub_epi8(_mm512_max_epu8(c0, c1), low);
    const __m512i limit = _mm512_add_epi8(
        _mm512_and_si512(_mm512_srli_epi16(_mm512_adds_epu8(low, _mm512_set1_epi8(4)), 3), _mm512_set1_epi8(0x1f)),
        _mm512_set1_epi8(10));
    return _mm512_movm_epi8(_mm512_mask_cmpgt_epu8_mask(0x7777777777777777ull, difference, limit));
  }
  static void index_for_two_registers(LaneIndex& lanes, const I& index) { lanes.index = index; }
  static F permute(const F& v, const LaneIndex& lanes) { return _mm512_permutexvar_ps(lanes.index, v); }
  static F permute_two_registers(const F& low, const F& high, const LaneIndex& lanes) {
    return _mm512_permutex2var_ps(low, lanes.index, high);
  }
  static void store_first_lanes(const F& value, float* out, int count) {
    _mm512_mask_storeu_ps(out, static_cast<__mmask16>((1u << count) - 1u), value);
  }
  static void store_bytes(const F& value, std::uint8_t* out) {
    _mm_storeu_si128(reinterpret_cast<__m128i*>(out), _mm512_cvtusepi32_epi8(_mm512_cvttps_epi32(value)));
  }
  static I load_u16(const std::uint8_t* p) { return _mm512_cvtepu16_epi32(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(p))); }
  static void store_u16(const I& codes, const B& write, bool masked, std::uint8_t* out) {
    _mm512_mask_cvtepi32_storeu_epi16(out, masked ? static_cast<__mmask16>(write) : static_cast<__mmask16>(0xffff), codes);
  }
};
#endif

}  // namespace
}  // namespace reproject::detail
