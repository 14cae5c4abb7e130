// Internal: the x86 family of the arch layer (contracts: kernels/arch_layer.hpp, which includes
// this file): SSE4.1, AVX2 + FMA and AVX-512, written with intrinsics where xsimd 8.1 cannot
// express a contract exactly or fast.
//
// One mechanism for the register width: X86Set<Arch> holds everything that depends on it, one
// block per instruction set, and the primitives below call the block of their set. A set without
// a block does not compile (the primary template's static_assert). A block exists only where the
// translation unit's flags define its macro (__AVX512F__, __AVX2__; kernels/arch_<set>.cpp is
// compiled with its set's flags alone), and the SSE4.1 block is the baseline every x86 TU has.
//
// MSVC: cmake/kernels.cmake gives each set's files /arch:AVX2 or /arch:AVX512, which define
// __AVX2__ and __AVX512F__/__AVX512BW__ there; FMA3 comes with them (REPROJECT_FMA3,
// kernels/fma.hpp) and REPROJECT_ALWAYS_INLINE is __forceinline (kernels/arch_layer.hpp).
#pragma once

#include <immintrin.h>

#include <cstdint>
#include <cstring>
#include <type_traits>
#include <xsimd/xsimd.hpp>

#include "kernels/codes.hpp"
#include "kernels/fma.hpp"

namespace reproject::detail {
namespace {  // one copy per arch TU (kernels/fma.hpp)

template <class Arch>
struct X86Set {
  static_assert(sizeof(Arch) == 0, "the x86 arch layer has no block for this instruction set (kernels/simd_x86.hpp)");
};

// IEEE totalOrder as signed integers (kernels/arch_layer.hpp, lane_extreme): a negative float's
// magnitude bits are flipped so that larger magnitudes compare smaller; the map is its own inverse.
template <class I>
I total_order_key(const I& bits) {
  return bits ^ ((bits >> 31) & I(0x7fffffff));
}

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
  template <int Byte>
  static I byte_lanes(const I& w) {
    if constexpr (Byte == 3) return _mm256_srli_epi32(w, 24);
    constexpr char z = -128;
    const __m128i pick = _mm_setr_epi8(Byte, z, z, z, Byte + 4, z, z, z, Byte + 8, z, z, z, Byte + 12, z, z, z);
    return _mm256_shuffle_epi8(w, _mm256_broadcastsi128_si256(pick));
  }
  static float first_lane(const F& v) { return _mm256_cvtss_f32(v); }
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
  template <int Byte>
  static I byte_lanes(const I& w) {
    if constexpr (Byte == 3) return _mm512_srli_epi32(w, 24);
    constexpr char z = -128;
    const __m128i pick = _mm_setr_epi8(Byte, z, z, z, Byte + 4, z, z, z, Byte + 8, z, z, z, Byte + 12, z, z, z);
    return _mm512_shuffle_epi8(w, _mm512_broadcast_i32x4(pick));
  }
  static float first_lane(const F& v) { return _mm512_cvtss_f32(v); }
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

// ---- The primitives (contracts: kernels/arch_layer.hpp) ----

template <class Arch>
constexpr bool has_arch_block() {
  return sizeof(X86Set<Arch>) > 0;
}
template <class F>
using X86SetOf = X86Set<typename F::arch_type>;

template <class Fma, class F>
F vmadd(const F& a, const F& b, const F& c) {
  if constexpr (std::is_same<Fma, Fused>::value) {
    static_assert(X86SetOf<F>::kHasFma, "the fused policy needs an FMA instruction of this width");
    return X86SetOf<F>::fmadd(a, b, c);
  } else {
    return a * b + c;
  }
}
// divps on every width (xsimd's operator/ is the instruction in every release). floor, min, max
// and rounding are each set's instruction, named: roundps with the floor mode, minps/maxps with
// the operands in this order (a < b ? a : b; xsimd 14 calls them with the operands swapped, which
// moves NaNs and zeros to the other side), cvtps2dq (nearest even in the default mode).
template <class F>
F vdiv(const F& a, const F& b) {
  return a / b;
}
template <class F>
F vfloor(const F& x) {
  return X86SetOf<F>::floor(x);
}
template <class F>
F vmin(const F& a, const F& b) {
  return X86SetOf<F>::min(a, b);
}
template <class F>
F vmax(const F& a, const F& b) {
  return X86SetOf<F>::max(a, b);
}
template <class Arch>
xsimd::batch<std::int32_t, Arch> round_to_int(const xsimd::batch<float, Arch>& x) {
  return X86Set<Arch>::round_to_int(x);
}

// The register casts themselves (free), not xsimd::bitwise_cast, whose template parameters
// changed in xsimd 11 (a batch type before, the element type after).
template <class Arch>
xsimd::batch<std::int32_t, Arch> bits_of(const xsimd::batch<float, Arch>& v) {
  return X86Set<Arch>::bits_of(v);
}
template <class Arch>
xsimd::batch<float, Arch> float_bits(const xsimd::batch<std::int32_t, Arch>& v) {
  return X86Set<Arch>::float_bits(v);
}
// Byte 0 is an and; byte 3 a logical shift, bytes 1 and 2 one byte shuffle (SSSE3, in every set).
template <int Byte, class Arch>
xsimd::batch<std::int32_t, Arch> byte_lanes(const xsimd::batch<std::int32_t, Arch>& w) {
  static_assert(Byte >= 0 && Byte < 4, "a 32-bit lane has four bytes");
  if constexpr (Byte == 0) {
    return w & xsimd::batch<std::int32_t, Arch>(0xff);
  } else {
    return X86Set<Arch>::template byte_lanes<Byte>(w);
  }
}

template <class Arch>
xsimd::batch<float, Arch> gather(const float* base, const xsimd::batch<std::int32_t, Arch>& index) {
  return X86Set<Arch>::gather(base, index);
}
template <class Arch, bool Max>
float lane_extreme(const xsimd::batch<float, Arch>& v) {
  const std::int32_t key = X86Set<Arch>::template lane_extreme_key<Max>(total_order_key(bits_of<Arch>(v)));
  return float_of_bits(static_cast<std::uint32_t>(key ^ ((key >> 31) & 0x7fffffff)));
}

template <class Arch>
constexpr bool has_permute() {
  return X86Set<Arch>::kHasPermute;
}
template <class Arch>
float first_lane(const xsimd::batch<float, Arch>& v) {
  return X86Set<Arch>::first_lane(v);
}
template <class Arch>
struct LaneIndex : X86Set<Arch>::LaneIndex {};
template <class Arch>
void index_for_gather(LaneIndex<Arch>& lanes, const xsimd::batch<std::int32_t, Arch>& index) {
  lanes.index = index;
}
template <class Arch>
void index_for_permute(LaneIndex<Arch>& lanes, const xsimd::batch<std::int32_t, Arch>& index) {
  lanes.index = index;
}
template <class Arch>
void index_for_two_registers(LaneIndex<Arch>& lanes, const xsimd::batch<std::int32_t, Arch>& index) {
  X86Set<Arch>::index_for_two_registers(lanes, index);
}
template <class Arch>
xsimd::batch<float, Arch> permute(const xsimd::batch<float, Arch>& v, const LaneIndex<Arch>& lanes) {
  return X86Set<Arch>::permute(v, lanes);
}
template <class Arch>
xsimd::batch<float, Arch> permute_two_registers(const xsimd::batch<float, Arch>& low,
                                                const xsimd::batch<float, Arch>& high, const LaneIndex<Arch>& lanes) {
  return X86Set<Arch>::permute_two_registers(low, high, lanes);
}

template <class Arch>
void store_first_lanes(const xsimd::batch<float, Arch>& value, float* out, int count) {
  if (count >= static_cast<int>(xsimd::batch<float, Arch>::size)) return value.store_unaligned(out);
  X86Set<Arch>::store_first_lanes(value, out, count);
}
template <class Arch>
void store_bytes(const xsimd::batch<float, Arch>& value, std::uint8_t* out) {
  X86Set<Arch>::store_bytes(value, out);
}
template <class Arch>
xsimd::batch<std::int32_t, Arch> load_u16(const std::uint8_t* p) {
  return X86Set<Arch>::load_u16(p);
}
template <class Arch>
void store_u16(const xsimd::batch<std::int32_t, Arch>& codes, const xsimd::batch_bool<float, Arch>& write, bool masked,
               std::uint8_t* out) {
  X86Set<Arch>::store_u16(codes, write, masked, out);
}

// ---- One RGBA pixel per 128-bit register ----

inline Pixel4 pixel4_splat(float value) { return _mm_set1_ps(value); }
inline Pixel4 pixel4_zero() { return _mm_setzero_ps(); }
inline Pixel4 load_float4(const std::uint8_t* p) { return _mm_loadu_ps(reinterpret_cast<const float*>(p)); }
inline void store_float4(std::uint8_t* p, Pixel4 v) { _mm_storeu_ps(reinterpret_cast<float*>(p), v); }

template <class Fma>
Pixel4 lerp4(Pixel4 frac, Pixel4 c0, Pixel4 c1) {
  if constexpr (std::is_same<Fma, Fused>::value) {
#if REPROJECT_FMA3
    return _mm_fmadd_ps(frac, _mm_sub_ps(c1, c0), c0);
#else
    static_assert(!std::is_same<Fma, Fma>::value, "the fused policy needs an FMA instruction set");
#endif
  } else {
    return _mm_add_ps(_mm_mul_ps(frac, _mm_sub_ps(c1, c0)), c0);
  }
}

// F16C where the TU has it; the exact scalar conversions of kernels/codes.hpp elsewhere (SSE4.1
// CPUs may lack F16C).
inline Pixel4 load_half4(const std::uint8_t* p) {
#if defined(__F16C__)
  return _mm_cvtph_ps(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(p)));
#else
  alignas(16) float v[4];
  for (int c = 0; c < 4; ++c) v[c] = half_to_float(load_u16_at(p + 2 * c));
  return _mm_load_ps(v);
#endif
}
inline void store_half4(std::uint8_t* p, Pixel4 value) {
#if defined(__F16C__)
  _mm_storel_epi64(reinterpret_cast<__m128i*>(p), _mm_cvtps_ph(value, _MM_FROUND_TO_NEAREST_INT | _MM_FROUND_NO_EXC));
#else
  alignas(16) float v[4];
  _mm_store_ps(v, value);
  for (int c = 0; c < 4; ++c) store_u16_at(p + 2 * c, float_to_half(v[c]));
#endif
}

}  // namespace
}  // namespace reproject::detail
