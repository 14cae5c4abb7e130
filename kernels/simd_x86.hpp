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

}  // namespace
}  // namespace reproject::detail

// One block per instruction set, each in a file of its own; a block exists only where this
// translation unit's flags define its macros (the block files check them).
#include "kernels/simd_x86_sse.hpp"
#include "kernels/simd_x86_avx2.hpp"
#include "kernels/simd_x86_avx512.hpp"

namespace reproject::detail {
namespace {  // one copy per arch TU (kernels/fma.hpp)

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
xsimd::batch<std::int32_t, Arch> blend_rgba8_q15(const xsimd::batch<std::int32_t, Arch>& c0,
                                                 const xsimd::batch<std::int32_t, Arch>& c1,
                                                 const xsimd::batch<std::int32_t, Arch>& weight) {
  return X86Set<Arch>::blend_rgba8_q15(c0, c1, weight);
}
template <class Arch>
xsimd::batch<std::int32_t, Arch> srgb_far_pairs(const xsimd::batch<std::int32_t, Arch>& c0,
                                                const xsimd::batch<std::int32_t, Arch>& c1) {
  return X86Set<Arch>::srgb_far_pairs(c0, c1);
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
xsimd::batch<float, Arch> shift_in_first(const xsimd::batch<float, Arch>& v, float first) {
  return X86Set<Arch>::shift_in_first(v, _mm_set_ss(first));
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
