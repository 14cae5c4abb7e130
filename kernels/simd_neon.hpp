// Internal: the AArch64 family of the arch layer (contracts: kernels/arch_layer.hpp, which
// includes this file): Advanced SIMD (xsimd's neon64, 4 float lanes), which every AArch64
// processor has, and the only set this family serves. Each function follows the contract its x86
// twin follows, so the neon table equals the scalar reference and the AVX2 and AVX-512 tables.
//
// Where xsimd 8.1 would be wrong or slow here, the intrinsic is named:
//  * floor: neon64 has no floor kernel in xsimd 8.1, and the generic one (convert to integer and
//    back) turns -0 into +0 where x86's roundps keeps -0: vrndmq_f32 keeps it.
//  * min/max: vminq_f32/vmaxq_f32 return NaN if either operand is NaN and order -0 below +0;
//    x86's minps(a, b) is a < b ? a : b (b on ties and NaN): written so, with a compare and a
//    bit select.
//  * rounding to an integer: xsimd 8.1's nearbyint_as_int is a scalar lroundf loop on neon64
//    (ties away from zero); vcvtnq_s32_f32 rounds ties to even, as cvtps2dq.
//  * gathers: NEON has none. Four scalar loads into the lanes (memcpy: rows of 32-bit pixels may
//    start at any byte address) replace it. The column fetch (kernels/simd.hpp) only gathers when
//    a vector's columns spread over more than 8 floats; within that range it uses the table
//    look-ups below (vqtbl1q_u8 / vqtbl2q_u8) instead, as x86 uses its permutes.
//  * division: xsimd 8.1's is a reciprocal estimate and two Newton steps; vdivq_f32 is IEEE.
//  * bit casts: xsimd 8.1's bitwise_cast goes through wrapper functions that GCC calls out of
//    line in the row loops; vreinterpretq is free.
//  * FMA: vfmaq_f32 (one rounding), as the fused policy requires.
// GCC and Clang (arm_neon.h); MSVC's ARM64 arm_neon.h has the same intrinsics.
#pragma once

#include <arm_neon.h>

#include <cstdint>
#include <cstring>
#include <type_traits>
#include <xsimd/xsimd.hpp>

#include "kernels/codes.hpp"
#include "kernels/fma.hpp"

namespace reproject::detail {
namespace {  // one copy per arch TU (kernels/fma.hpp)

template <class Arch>
constexpr bool has_arch_block() {
  return std::is_same<Arch, xsimd::neon64>::value;
}

template <class Fma, class F>
F vmadd(const F& a, const F& b, const F& c) {
  if constexpr (std::is_same<Fma, Fused>::value) {
    return vfmaq_f32(c, a, b);  // c + a b, one rounding
  } else {
    return a * b + c;
  }
}

template <class F>
F vfloor(const F& x) {
  return vrndmq_f32(x);
}
template <class F>
F vmin(const F& a, const F& b) {
  return vbslq_f32(vcltq_f32(a, b), a, b);  // a < b ? a : b
}
template <class F>
F vmax(const F& a, const F& b) {
  return vbslq_f32(vcgtq_f32(a, b), a, b);  // a > b ? a : b
}
// A float's bits as an integer lane and back (xsimd 8.1's bitwise_cast is not inlined here).
template <class Arch>
xsimd::batch<std::int32_t, Arch> bits_of(const xsimd::batch<float, Arch>& v) {
  return vreinterpretq_s32_f32(v);
}
template <class Arch>
xsimd::batch<float, Arch> float_bits(const xsimd::batch<std::int32_t, Arch>& v) {
  return vreinterpretq_f32_s32(v);
}

// Byte `Byte` (0: the lowest address) of each 32-bit lane, zero-extended (an RGBA8 pixel's
// channel): an and, a logical shift, or one table look-up (indices past the table give zero).
template <int Byte, class Arch>
xsimd::batch<std::int32_t, Arch> byte_lanes(const xsimd::batch<std::int32_t, Arch>& w) {
  static_assert(Byte >= 0 && Byte < 4, "a 32-bit lane has four bytes");
  if constexpr (Byte == 0) {
    return vandq_s32(w, vdupq_n_s32(0xff));
  } else if constexpr (Byte == 3) {
    return vreinterpretq_s32_u32(vshrq_n_u32(vreinterpretq_u32_s32(w), 24));
  } else {
    constexpr std::uint8_t z = 0xff;
    alignas(16) static const std::uint8_t pick[16] = {Byte, z, z, z, Byte + 4, z, z, z, Byte + 8, z, z, z, Byte + 12, z, z, z};
    return vreinterpretq_s32_u8(vqtbl1q_u8(vreinterpretq_u8_s32(w), vld1q_u8(pick)));
  }
}

// RGBA8 blended in fixed point: channels widened to 16 bits (pixels 0-1, then 2-3), each pixel's
// weight copied to its channels by a table look-up, vqrdmulh (floor((2 d w + 2^15) / 2^16), the
// same as pmulhrsw's rounding; no operand here can saturate), narrowed back.
template <class Arch>
xsimd::batch<std::int32_t, Arch> blend_rgba8_q15(const xsimd::batch<std::int32_t, Arch>& c0,
                                                 const xsimd::batch<std::int32_t, Arch>& c1,
                                                 const xsimd::batch<std::int32_t, Arch>& weight) {
  alignas(16) static const std::uint8_t first[16] = {0, 1, 0, 1, 0, 1, 0, 1, 4, 5, 4, 5, 4, 5, 4, 5};
  alignas(16) static const std::uint8_t second[16] = {8, 9, 8, 9, 8, 9, 8, 9, 12, 13, 12, 13, 12, 13, 12, 13};
  const uint8x16_t a = vreinterpretq_u8_s32(c0), b = vreinterpretq_u8_s32(c1), w = vreinterpretq_u8_s32(weight);
  const int16x8_t a0 = vreinterpretq_s16_u16(vmovl_u8(vget_low_u8(a))), a1 = vreinterpretq_s16_u16(vmovl_u8(vget_high_u8(a)));
  const int16x8_t d0 = vsubq_s16(vreinterpretq_s16_u16(vmovl_u8(vget_low_u8(b))), a0);
  const int16x8_t d1 = vsubq_s16(vreinterpretq_s16_u16(vmovl_u8(vget_high_u8(b))), a1);
  const int16x8_t w0 = vreinterpretq_s16_u8(vqtbl1q_u8(w, vld1q_u8(first)));
  const int16x8_t w1 = vreinterpretq_s16_u8(vqtbl1q_u8(w, vld1q_u8(second)));
  const uint8x8_t r0 = vqmovun_s16(vaddq_s16(a0, vqrdmulhq_s16(d0, w0)));
  const uint8x8_t r1 = vqmovun_s16(vaddq_s16(a1, vqrdmulhq_s16(d1, w1)));
  return vreinterpretq_s32_u8(vcombine_u8(r0, r1));
}

// Bytes: |c1 - c0| beyond ((min + 4) >> 3) + 10, the alpha bytes cleared.
template <class Arch>
xsimd::batch<std::int32_t, Arch> srgb_far_pairs(const xsimd::batch<std::int32_t, Arch>& c0,
                                                const xsimd::batch<std::int32_t, Arch>& c1) {
  const uint8x16_t a = vreinterpretq_u8_s32(c0), b = vreinterpretq_u8_s32(c1);
  const uint8x16_t limit = vaddq_u8(vshrq_n_u8(vqaddq_u8(vminq_u8(a, b), vdupq_n_u8(4)), 3), vdupq_n_u8(10));
  const uint8x16_t far = vandq_u8(vcgtq_u8(vabdq_u8(a, b), limit), vreinterpretq_u8_u32(vdupq_n_u32(0x00ffffffu)));
  return vreinterpretq_s32_u8(far);
}

// Correctly rounded division: xsimd 8.1's float division on neon64 is a reciprocal estimate
// refined by two Newton steps (not correctly rounded); vdivq_f32 is IEEE division.
template <class F>
F vdiv(const F& a, const F& b) {
  return vdivq_f32(a, b);
}
template <class Arch>
xsimd::batch<std::int32_t, Arch> round_to_int(const xsimd::batch<float, Arch>& x) {
  return vcvtnq_s32_f32(x);
}

// base[index] per lane: four loads (see the top of this file).
template <class Arch>
xsimd::batch<float, Arch> gather(const float* base, const xsimd::batch<std::int32_t, Arch>& index) {
  alignas(16) std::int32_t at[4];
  alignas(16) float value[4];
  index.store_aligned(at);
  for (int i = 0; i < 4; ++i) std::memcpy(&value[i], base + at[i], sizeof(float));
  return xsimd::batch<float, Arch>::load_aligned(value);
}

// IEEE totalOrder through signed integers (a negative float's magnitude bits flipped; the map is
// its own inverse), reduced with the across-lanes integer minimum or maximum.
template <class Arch, bool Max>
float lane_extreme(const xsimd::batch<float, Arch>& v) {
  const int32x4_t bits = vreinterpretq_s32_f32(v);
  const int32x4_t key = veorq_s32(bits, vandq_s32(vshrq_n_s32(bits, 31), vdupq_n_s32(0x7fffffff)));
  const std::int32_t extreme = Max ? vmaxvq_s32(key) : vminvq_s32(key);
  return float_of_bits(static_cast<std::uint32_t>(extreme ^ ((extreme >> 31) & 0x7fffffff)));
}

// Permutes across lanes with the byte table look-up: lane i takes v[index[i]], index < 4 (one
// register) or < 8 (two). Prepared once per index vector as byte indices 4 index + 0..3.
template <class Arch>
constexpr bool has_permute() {
  return true;
}

template <class Arch>
float first_lane(const xsimd::batch<float, Arch>& v) {
  return vgetq_lane_f32(v, 0);
}

template <class Arch>
xsimd::batch<float, Arch> shift_in_first(const xsimd::batch<float, Arch>& v, float first) {
  return vextq_f32(vdupq_n_f32(first), v, 3);  // lane 3 of first's, then v's 0..2
}

// A column set's lanes as each fetch mode takes them (kernels/simd.hpp, ColumnFetch): the lane
// indices for gathers, and for both permutes the byte indices 4 index + 0..3 of the table look-up
// (one register: index < 4; two: index < 8). Set once per column set.
template <class Arch>
struct LaneIndex {
  xsimd::batch<std::int32_t, Arch> index;
  uint8x16_t bytes;
};
template <class Arch>
void index_for_gather(LaneIndex<Arch>& lanes, const xsimd::batch<std::int32_t, Arch>& index) {
  lanes.index = index;
}
template <class Arch>
void index_for_permute(LaneIndex<Arch>& lanes, const xsimd::batch<std::int32_t, Arch>& index) {
  const uint32x4_t first_byte = vshlq_n_u32(vreinterpretq_u32_s32(index), 2);               // 4 index
  const uint32x4_t in_each_byte = vmulq_n_u32(first_byte, 0x01010101u);                     // ... in all four bytes
  lanes.bytes = vreinterpretq_u8_u32(vaddq_u32(in_each_byte, vdupq_n_u32(0x03020100u)));  // + 0, 1, 2, 3
}
template <class Arch>
void index_for_two_registers(LaneIndex<Arch>& lanes, const xsimd::batch<std::int32_t, Arch>& index) {
  index_for_permute(lanes, index);
}

// Lane i takes v[index[i]] (one register), or (low, high)[index[i]] with index < 8 (two).
template <class Arch>
xsimd::batch<float, Arch> permute(const xsimd::batch<float, Arch>& v, const LaneIndex<Arch>& lanes) {
  return vreinterpretq_f32_u8(vqtbl1q_u8(vreinterpretq_u8_f32(v), lanes.bytes));
}
template <class Arch>
xsimd::batch<float, Arch> permute_two_registers(const xsimd::batch<float, Arch>& low, const xsimd::batch<float, Arch>& high,
                                                const LaneIndex<Arch>& lanes) {
  uint8x16x2_t table;
  table.val[0] = vreinterpretq_u8_f32(low);
  table.val[1] = vreinterpretq_u8_f32(high);
  return vreinterpretq_f32_u8(vqtbl2q_u8(table, lanes.bytes));
}

// Stores the first `count` lanes of `value` (count >= 0) and leaves the memory after them as it
// was: NEON has no masked store, so the vector is merged with what is there (the caller's buffer
// holds a whole vector at `out`, as on SSE4.1).
template <class Arch>
void store_first_lanes(const xsimd::batch<float, Arch>& value, float* out, int count) {
  using F = xsimd::batch<float, Arch>;
  if (count >= 4) return value.store_unaligned(out);
  alignas(16) static const float lanes[4] = {0, 1, 2, 3};
  xsimd::select(F::load_aligned(lanes) < F(static_cast<float>(count)), value, F::load_unaligned(out)).store_unaligned(out);
}

// Stores small non-negative integral floats (the PixelStatus values) as bytes.
template <class Arch>
void store_bytes(const xsimd::batch<float, Arch>& value, std::uint8_t* out) {
  const uint16x4_t halves = vmovn_u32(vcvtq_u32_f32(value));
  const uint8x8_t bytes = vmovn_u16(vcombine_u16(halves, halves));
  const std::uint32_t four = vget_lane_u32(vreinterpret_u32_u8(bytes), 0);
  std::memcpy(out, &four, 4);
}

// 4 consecutive 16-bit codes, zero-extended.
template <class Arch>
xsimd::batch<std::int32_t, Arch> load_u16(const std::uint8_t* p) {
  std::uint64_t codes;
  std::memcpy(&codes, p, 8);
  return vreinterpretq_s32_u32(vmovl_u16(vcreate_u16(codes)));
}

// Stores 4 16-bit codes (each <= 65535); with `masked`, only the lanes in `write`.
template <class Arch>
void store_u16(const xsimd::batch<std::int32_t, Arch>& codes, const xsimd::batch_bool<float, Arch>& write, bool masked,
               std::uint8_t* out) {
  uint16x4_t packed = vmovn_u32(vreinterpretq_u32_s32(codes));
  if (masked) {
    std::uint64_t before;
    std::memcpy(&before, out, 8);
    packed = vbsl_u16(vmovn_u32(static_cast<uint32x4_t>(write)), packed, vcreate_u16(before));
  }
  const std::uint64_t after = vget_lane_u64(vreinterpret_u64_u16(packed), 0);
  std::memcpy(out, &after, 8);
}

// ---- one RGBA pixel per 128-bit register (float RGBA and rgba16f colour) ----

using Pixel4 = float32x4_t;

inline Pixel4 pixel4_splat(float value) { return vdupq_n_f32(value); }
inline Pixel4 pixel4_zero() { return vdupq_n_f32(0.0f); }
inline Pixel4 load_float4(const std::uint8_t* p) { return vld1q_f32(reinterpret_cast<const float*>(p)); }
inline void store_float4(std::uint8_t* p, Pixel4 v) { vst1q_f32(reinterpret_cast<float*>(p), v); }

// c0 + frac (c1 - c0) per channel with the table's FMA policy.
template <class Fma>
Pixel4 lerp4(Pixel4 frac, Pixel4 c0, Pixel4 c1) {
  if constexpr (std::is_same<Fma, Fused>::value) {
    return vfmaq_f32(c0, frac, vsubq_f32(c1, c0));
  } else {
    return vaddq_f32(vmulq_f32(frac, vsubq_f32(c1, c0)), c0);
  }
}

// Four halves to floats and back, with the ARMv8 conversions (FCVTL/FCVTN: exact widening;
// narrowing rounded to nearest even in the default FPCR mode, NaNs made quiet with their top
// payload bits, overflow to infinity), which give the bits of F16C and of the scalar conversions.
inline Pixel4 load_half4(const std::uint8_t* p) {
  std::uint64_t halves;
  std::memcpy(&halves, p, 8);
  return vcvt_f32_f16(vreinterpret_f16_u64(vcreate_u64(halves)));
}
inline void store_half4(std::uint8_t* p, Pixel4 value) {
  const std::uint64_t halves = vget_lane_u64(vreinterpret_u64_f16(vcvt_f16_f32(value)), 0);
  std::memcpy(p, &halves, 8);
}

}  // namespace
}  // namespace reproject::detail
