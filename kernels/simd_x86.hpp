// Internal: the x86 family of the arch layer (docs/ARCHITECTURE.md, "The arch layer"): what
// xsimd 8.1 cannot express exactly or fast on SSE4.1, AVX2 + FMA and AVX-512, written with
// intrinsics per register width. Every method's SIMD twin is written once against these names
// and xsimd; another processor family provides the same names in its own file.
//
// Each function serves the widths of the translation unit that includes it (kernels/arch_<set>.cpp,
// compiled with that set's flags): a branch exists only where the TU's flags define its macro
// (__AVX512F__, __AVX2__, __FMA__, __F16C__), and SSE4.1 takes the portable fallback.
//
// GCC and Clang only for now: MSVC has no __AVX2__-style macros per translation unit (it defines
// __AVX2__ only with /arch:AVX2 for the whole build) and no __attribute__; a Windows build would
// set these from CMake per file and spell REPROJECT_ALWAYS_INLINE as __forceinline.
#pragma once

#include <immintrin.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <type_traits>
#include <xsimd/xsimd.hpp>

#include "kernels/codes.hpp"
#include "kernels/fma.hpp"

namespace reproject::detail {
namespace {  // one copy per arch TU (kernels/fma.hpp)

// The FMA policy on vectors (kernels/fma.hpp). The fused form names the instruction for each
// width instead of calling xsimd::fma: xsimd 8.1 has no fma kernel for avx512f, and there
// xsimd::fma falls back to the generic x * y + z (two roundings under -ffp-contract=off). A width
// without an FMA instruction in this TU does not compile. tests/check_object_code.cmake holds
// every fused object to vector FMAs of its width.
template <class Fma, class F>
F vmadd(const F& a, const F& b, const F& c) {
  if constexpr (!std::is_same<Fma, Fused>::value) {
    return a * b + c;
#if defined(__AVX512F__)
  } else if constexpr (sizeof(F) == 64) {
    return _mm512_fmadd_ps(a, b, c);
#endif
#if defined(__FMA__)
  } else if constexpr (sizeof(F) == 32) {
    return _mm256_fmadd_ps(a, b, c);
  } else if constexpr (sizeof(F) == 16) {
    return _mm_fmadd_ps(a, b, c);
#endif
  } else {
    static_assert(!std::is_same<F, F>::value, "the fused policy needs an FMA instruction of this width");
  }
}

// floor, min, max and rounding to an integer with one defined answer on every family: x86's
// roundps, minps/maxps (min(a, b) = a < b ? a : b, so b on equal values and when either is NaN;
// max likewise) and cvtps2dq (to nearest, ties to even, in the default rounding mode), which
// xsimd 8.1 calls on these widths.
template <class F>
F vfloor(const F& x) {
  return xsimd::floor(x);
}
template <class F>
F vmin(const F& a, const F& b) {
  return xsimd::min(a, b);
}
template <class F>
F vmax(const F& a, const F& b) {
  return xsimd::max(a, b);
}
// A float's bits as an integer lane and back.
template <class Arch>
xsimd::batch<std::int32_t, Arch> bits_of(const xsimd::batch<float, Arch>& v) {
  return xsimd::bitwise_cast<xsimd::batch<std::int32_t, Arch>>(v);
}
template <class Arch>
xsimd::batch<float, Arch> float_bits(const xsimd::batch<std::int32_t, Arch>& v) {
  return xsimd::bitwise_cast<xsimd::batch<float, Arch>>(v);
}

// Byte `Byte` (0: the lowest address) of each 32-bit lane, zero-extended (an RGBA8 pixel's
// channel): an and, a logical shift, or one byte shuffle (SSSE3, in every set here), instead of a
// shift and a mask.
template <int Byte, class Arch>
xsimd::batch<std::int32_t, Arch> byte_lanes(const xsimd::batch<std::int32_t, Arch>& w) {
  using I = xsimd::batch<std::int32_t, Arch>;
  static_assert(Byte >= 0 && Byte < 4, "a 32-bit lane has four bytes");
  if constexpr (Byte == 0) {
    return w & I(0xff);
  } else {
    constexpr char z = -128;  // a shuffle index with its top bit set writes zero
    const __m128i pick = _mm_setr_epi8(Byte, z, z, z, Byte + 4, z, z, z, Byte + 8, z, z, z, Byte + 12, z, z, z);
#if defined(__AVX512F__)
    if constexpr (sizeof(I) == 64) {
      return Byte == 3 ? _mm512_srli_epi32(w, 24) : _mm512_shuffle_epi8(w, _mm512_broadcast_i32x4(pick));
    }
#endif
#if defined(__AVX2__)
    if constexpr (sizeof(I) == 32) {
      return Byte == 3 ? _mm256_srli_epi32(w, 24) : _mm256_shuffle_epi8(w, _mm256_broadcastsi128_si256(pick));
    }
#endif
    if constexpr (sizeof(I) == 16) return Byte == 3 ? _mm_srli_epi32(w, 24) : _mm_shuffle_epi8(w, pick);
  }
}

// Correctly rounded division (divps on every width).
template <class F>
F vdiv(const F& a, const F& b) {
  return a / b;
}
template <class Arch>
xsimd::batch<std::int32_t, Arch> round_to_int(const xsimd::batch<float, Arch>& x) {
  return xsimd::nearbyint_as_int(x);
}

// base[index] per lane. xsimd 8.1's batch::gather is a scalar loop, so use the hardware gather
// where there is one.
template <class Arch>
xsimd::batch<float, Arch> gather(const float* base, const xsimd::batch<std::int32_t, Arch>& index) {
#if defined(__AVX512F__)
  if constexpr (std::is_base_of<xsimd::avx512f, Arch>::value) {
    return _mm512_i32gather_ps(index, base, 4);
  }
#endif
#if defined(__AVX2__)
  if constexpr (std::is_base_of<xsimd::avx2, Arch>::value) {
    return _mm256_i32gather_ps(base, index, 4);
  }
#endif
  constexpr int L = static_cast<int>(xsimd::batch<float, Arch>::size);
  alignas(64) std::int32_t at[L];
  alignas(64) float value[L];
  index.store_aligned(at);
  // memcpy: `base` may be a row of 32-bit pixels (rgba8) at any byte address.
  for (int i = 0; i < L; ++i) std::memcpy(&value[i], base + at[i], sizeof(float));
  return xsimd::batch<float, Arch>::load_aligned(value);
}

// Horizontal minimum (Max false) or maximum (Max true) of a vector, with the min/max instructions
// themselves. (The maximum is not written -lane_min(-v): xsimd 8.1's avx512f negation is 0 - x,
// which turns a +0 lane into +0 instead of -0. Which zero a reduction of +0 and -0 returns depends
// on the order; set_near_key makes the frame's nearest key +0 in that case.)
template <class Arch, bool Max>
float lane_extreme(const xsimd::batch<float, Arch>& v) {
#if defined(__AVX512F__)
  if constexpr (std::is_base_of<xsimd::avx512f, Arch>::value) return Max ? _mm512_reduce_max_ps(v) : _mm512_reduce_min_ps(v);
#endif
#if defined(__AVX2__)
  if constexpr (std::is_base_of<xsimd::avx2, Arch>::value) {
    auto op = [](__m256 x, __m256 y) { return Max ? _mm256_max_ps(x, y) : _mm256_min_ps(x, y); };
    __m256 m = op(v, _mm256_permute2f128_ps(v, v, 1));
    m = op(m, _mm256_shuffle_ps(m, m, _MM_SHUFFLE(1, 0, 3, 2)));
    m = op(m, _mm256_shuffle_ps(m, m, _MM_SHUFFLE(2, 3, 0, 1)));
    return _mm256_cvtss_f32(m);
  }
#endif
  constexpr int L = static_cast<int>(xsimd::batch<float, Arch>::size);
  alignas(64) float lanes[L];
  v.store_aligned(lanes);
  return Max ? *std::max_element(lanes, lanes + L) : *std::min_element(lanes, lanes + L);
}

// Lane 0 of a vector, and permutes across lanes (lane i takes v[index[i]]), for the widths that
// have a variable permute instruction (AVX2: 8 lanes, AVX-512: 16). SSE4.1 has none: the column
// fetch gathers there (kernels/simd.hpp).
template <class Arch>
constexpr bool kHasPermute =
#if defined(__AVX512F__)
    std::is_base_of<xsimd::avx512f, Arch>::value ||
#endif
#if defined(__AVX2__)
    std::is_base_of<xsimd::avx2, Arch>::value ||
#endif
    false;

template <class Arch>
float first_lane(const xsimd::batch<float, Arch>& v) {
  static_assert(kHasPermute<Arch>, "first_lane() serves the AVX2 and AVX-512 fetch plans");
#if defined(__AVX512F__)
  if constexpr (sizeof(v) == 64) {
    return _mm512_cvtss_f32(v);
  } else
#endif
  {
    return _mm256_cvtss_f32(v);
  }
}

// A column set's lanes as each fetch mode takes them (kernels/simd.hpp, ColumnFetch): the lane
// indices (gathers take them as they are, and so does AVX2's and AVX-512's one-register permute),
// and for AVX2's two-register permute the lanes that come from the second register. Set once per
// column set, used for any number of rows.
template <class Arch>
struct LaneIndex {
  xsimd::batch<std::int32_t, Arch> index;
  xsimd::batch<float, Arch> from_high;  // AVX2, two registers: all ones where index >= L
};
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
  lanes.index = index;
#if defined(__AVX2__)
  if constexpr (sizeof(index) == 32 && kHasPermute<Arch>) {
    lanes.from_high = _mm256_castsi256_ps(_mm256_cmpgt_epi32(index, _mm256_set1_epi32(7)));
  }
#endif
}

// Lane i takes v[index[i]] (one register), or (low, high)[index[i]] with index < 2L (two).
template <class Arch>
xsimd::batch<float, Arch> permute([[maybe_unused]] const xsimd::batch<float, Arch>& v,
                                  [[maybe_unused]] const LaneIndex<Arch>& lanes) {
  static_assert(kHasPermute<Arch>, "permute() needs AVX2 or AVX-512");
#if defined(__AVX512F__)
  if constexpr (sizeof(v) == 64) return _mm512_permutexvar_ps(lanes.index, v);
#endif
#if defined(__AVX2__)
  if constexpr (sizeof(v) == 32) return _mm256_permutevar8x32_ps(v, lanes.index);
#endif
}
template <class Arch>
xsimd::batch<float, Arch> permute_two_registers([[maybe_unused]] const xsimd::batch<float, Arch>& low,
                                                [[maybe_unused]] const xsimd::batch<float, Arch>& high,
                                                [[maybe_unused]] const LaneIndex<Arch>& lanes) {
  static_assert(kHasPermute<Arch>, "permute_two_registers() needs AVX2 or AVX-512");
#if defined(__AVX512F__)
  if constexpr (sizeof(low) == 64) return _mm512_permutex2var_ps(low, lanes.index, high);
#endif
#if defined(__AVX2__)
  if constexpr (sizeof(low) == 32) {
    // AVX2's permute reaches one register: permute both, then take each lane's own.
    return _mm256_blendv_ps(permute<Arch>(low, lanes), permute<Arch>(high, lanes), lanes.from_high);
  }
#endif
}

// Stores the first `count` lanes of `value` (count >= 0; all of them when count >= L) and leaves
// the memory after them untouched: a hardware masked store on AVX2 and AVX-512.
template <class Arch>
void store_first_lanes(const xsimd::batch<float, Arch>& value, float* out, int count) {
  using F = xsimd::batch<float, Arch>;
  constexpr int L = static_cast<int>(F::size);
  if (count >= L) return value.store_unaligned(out);
#if defined(__AVX512F__)
  if constexpr (sizeof(value) == 64) {
    return _mm512_mask_storeu_ps(out, static_cast<__mmask16>((1u << count) - 1u), value);
  }
#endif
#if defined(__AVX2__)
  if constexpr (sizeof(value) == 32) {
    const __m256i lanes = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
    return _mm256_maskstore_ps(out, _mm256_cmpgt_epi32(_mm256_set1_epi32(count), lanes), value);
  }
#endif
  alignas(64) float offsets[L];
  for (int i = 0; i < L; ++i) offsets[i] = static_cast<float>(i);
  xsimd::select(F::load_aligned(offsets) < F(static_cast<float>(count)), value, F::load_unaligned(out)).store_unaligned(out);
}

// Stores small non-negative integral floats (the PixelStatus values) as bytes.
template <class Arch>
void store_bytes(const xsimd::batch<float, Arch>& value, std::uint8_t* out) {
#if defined(__AVX512F__)
  if constexpr (std::is_base_of<xsimd::avx512f, Arch>::value) {
    _mm_storeu_si128(reinterpret_cast<__m128i*>(out), _mm512_cvtusepi32_epi8(_mm512_cvttps_epi32(value)));
    return;
  }
#endif
#if defined(__AVX2__)
  if constexpr (std::is_base_of<xsimd::avx2, Arch>::value) {
    const __m256i words = _mm256_cvttps_epi32(value);
    const __m128i halves = _mm_packus_epi32(_mm256_castsi256_si128(words), _mm256_extracti128_si256(words, 1));
    _mm_storel_epi64(reinterpret_cast<__m128i*>(out), _mm_packus_epi16(halves, halves));
    return;
  }
#endif
  constexpr int L = static_cast<int>(xsimd::batch<float, Arch>::size);
  alignas(64) float lanes[L];
  value.store_aligned(lanes);
  for (int i = 0; i < L; ++i) out[i] = static_cast<std::uint8_t>(lanes[i]);
}

// L consecutive 16-bit codes, zero-extended.
template <class Arch>
xsimd::batch<std::int32_t, Arch> load_u16(const std::uint8_t* p) {
  using I = xsimd::batch<std::int32_t, Arch>;
#if defined(__AVX512F__)
  if constexpr (sizeof(I) == 64) return _mm512_cvtepu16_epi32(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(p)));
#endif
#if defined(__AVX2__)
  if constexpr (sizeof(I) == 32) return _mm256_cvtepu16_epi32(_mm_loadu_si128(reinterpret_cast<const __m128i*>(p)));
#endif
  if constexpr (sizeof(I) == 16) {
    return _mm_cvtepu16_epi32(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(p)));
  } else {
    constexpr int L = static_cast<int>(I::size);
    alignas(64) std::int32_t codes[L];
    for (int i = 0; i < L; ++i) {
      std::uint16_t code;
      std::memcpy(&code, p + 2 * i, 2);
      codes[i] = code;
    }
    return I::load_aligned(codes);
  }
}

// Stores L 16-bit codes (each <= 65535); with `masked`, only the lanes in `write`.
template <class Arch>
void store_u16(const xsimd::batch<std::int32_t, Arch>& codes, const xsimd::batch_bool<float, Arch>& write, bool masked,
               std::uint8_t* out) {
  using F = xsimd::batch<float, Arch>;
  constexpr int L = static_cast<int>(F::size);
#if defined(__AVX512F__)
  if constexpr (L == 16) {
    const __mmask16 lanes = masked ? static_cast<__mmask16>(write) : static_cast<__mmask16>(0xffff);
    return _mm512_mask_cvtepi32_storeu_epi16(out, lanes, codes);
  }
#endif
#if defined(__AVX2__)
  if constexpr (L == 8) {
    const __m256i c = codes;
    __m128i packed = _mm_packus_epi32(_mm256_castsi256_si128(c), _mm256_extracti128_si256(c, 1));
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

// ---- one RGBA pixel per 128-bit register (float RGBA and rgba16f colour) ----

using Pixel4 = __m128;

inline Pixel4 pixel4_splat(float value) { return _mm_set1_ps(value); }
inline Pixel4 pixel4_zero() { return _mm_setzero_ps(); }
inline Pixel4 load_float4(const std::uint8_t* p) { return _mm_loadu_ps(reinterpret_cast<const float*>(p)); }
inline void store_float4(std::uint8_t* p, Pixel4 v) { _mm_storeu_ps(reinterpret_cast<float*>(p), v); }

// c0 + frac (c1 - c0) per channel with the table's FMA policy.
template <class Fma>
Pixel4 lerp4(Pixel4 frac, Pixel4 c0, Pixel4 c1) {
  if constexpr (std::is_same<Fma, Fused>::value) {
#if defined(__FMA__)
    return _mm_fmadd_ps(frac, _mm_sub_ps(c1, c0), c0);
#else
    static_assert(!std::is_same<Fma, Fma>::value, "the fused policy needs an FMA instruction set");
#endif
  } else {
    return _mm_add_ps(_mm_mul_ps(frac, _mm_sub_ps(c1, c0)), c0);
  }
}

// Four halves to floats and back (round to nearest even): F16C where the TU has it, the exact
// scalar conversions of kernels/color_formats.hpp elsewhere (SSE4.1 CPUs may lack F16C).
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
