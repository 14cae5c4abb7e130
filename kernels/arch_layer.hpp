// Internal: the arch layer's vocabulary (docs/ARCHITECTURE.md, "The arch layer"). Every primitive
// the SIMD twins use beyond plain xsimd arithmetic is declared here once, with its contract above
// it; each processor family's file defines all of them (kernels/simd_x86.hpp: SSE4.1, AVX2 + FMA,
// AVX-512; kernels/simd_neon.hpp: AArch64 Advanced SIMD) and follows these contracts lane for lane,
// so a twin gives the same bits on every family. tests/test_arch_layer.cpp holds every primitive of
// every compiled set to a scalar statement of its contract, special values in every lane.
//
// Words used below: L is the number of float lanes; "quieted" NaN: the same sign and payload
// with the quiet bit (0x00400000) set; "bit for bit": the lane's 32 bits unchanged, signalling
// NaNs included. A NaN that arithmetic creates (0/0, inf - inf) is positive on AArch64 and
// negative on x86 (docs/BEHAVIOUR.md, "Instruction sets and FMA policy"): contracts say where that
// can show.
#pragma once

#include <cstdint>
#include <xsimd/xsimd.hpp>

#include "kernels/fma.hpp"

#if defined(__aarch64__) || defined(_M_ARM64)
#include <arm_neon.h>
#elif defined(__x86_64__) || defined(__i386__) || defined(_M_X64) || defined(_M_IX86)
#include <immintrin.h>
#else
#error "no arch layer for this processor: CMake compiles no SIMD table here (REPROJECT_SIMD)"
#endif

// Forces inlining where the compiler's heuristics keep a per-vector helper out of line in the
// row loops; keeps a function out of line; asks for the cache line at an address. MSVC (not
// clang-cl, which takes GCC's spellings) has its own words for the three.
#if defined(_MSC_VER) && !defined(__clang__)
#define REPROJECT_ALWAYS_INLINE __forceinline
#define REPROJECT_NOINLINE __declspec(noinline)
#if defined(_M_ARM64)
#define REPROJECT_PREFETCH(address) __prefetch(address)
#else
#define REPROJECT_PREFETCH(address) _mm_prefetch(reinterpret_cast<const char*>(address), _MM_HINT_T0)
#endif
#else
#define REPROJECT_ALWAYS_INLINE __attribute__((always_inline))
#define REPROJECT_NOINLINE __attribute__((noinline))
#define REPROJECT_PREFETCH(address) __builtin_prefetch(address)
#endif

namespace reproject::detail {
namespace {  // one copy per arch TU (kernels/fma.hpp)

// ---- The instruction sets a family serves ----

// True for each set the family file has a block for. Instantiating the layer (kernels/simd.hpp,
// Lanes) for any other set is a compile error, never a silent scalar fallback.
template <class Arch> constexpr bool has_arch_block();

// ---- Arithmetic, rounded as IEEE 754 says ----

// a b + c with the FMA policy (kernels/fma.hpp): Fused rounds once (std::fma), and a set without
// an FMA instruction does not compile with it; Unfused rounds the product, then the sum. The
// result is NaN exactly when the IEEE operation's is; with exactly one NaN operand (and a b not
// inf times 0) it is that operand quieted; otherwise which NaN is not specified.
template <class Fma, class F> F vmadd(const F& a, const F& b, const F& c);

// a / b correctly rounded (IEEE division, never a reciprocal estimate). NaNs as vmadd.
template <class F> F vdiv(const F& a, const F& b);

// The largest integral float <= x: -0 stays -0, -0.25 gives -1, +0.25 gives +0, infinities stay,
// a NaN is quieted.
template <class F> F vfloor(const F& x);

// a < b ? a : b, bit for bit: b when the two are equal (vmin(-0, +0) = +0, vmin(+0, -0) = -0) and
// whenever either is NaN (b's bits unchanged, even a signalling NaN). This is x86's minps order,
// not IEEE minNum.
template <class F> F vmin(const F& a, const F& b);
// a > b ? a : b, bit for bit, likewise (b on equal values and on NaN).
template <class F> F vmax(const F& a, const F& b);

// Nearest integer, ties to even, for -2^31 <= x < 2^31. Any other lane (NaN, infinity, out of
// range) is not specified (x86 gives INT_MIN, AArch64 saturates and gives 0 for NaN): callers keep
// x in range.
template <class Arch>
xsimd::batch<std::int32_t, Arch> round_to_int(const xsimd::batch<float, Arch>& x);

// ---- Bits ----

// A float lane's 32 bits as an integer lane and back, bit for bit.
template <class Arch>
xsimd::batch<std::int32_t, Arch> bits_of(const xsimd::batch<float, Arch>& v);
template <class Arch>
xsimd::batch<float, Arch> float_bits(const xsimd::batch<std::int32_t, Arch>& v);

// Byte `Byte` of each 32-bit lane (0: the lowest address, bits 0-7 of the value), zero-extended
// to [0, 255]: an RGBA8 pixel's channel.
template <int Byte, class Arch>
xsimd::batch<std::int32_t, Arch> byte_lanes(const xsimd::batch<std::int32_t, Arch>& w);

// RGBA8 pixels (a 32-bit word per lane, a channel per byte) blended in fixed point: each channel
// c0 + floor(((c1 - c0) w + 2^14) / 2^15) of the lane's weight w in [0, 32767] (kernels/codes.hpp
// blend_u8_q15: the rounding of pmulhrsw and vqrdmulh), every byte of every lane. Any other weight
// is not specified.
template <class Arch>
xsimd::batch<std::int32_t, Arch> blend_rgba8_q15(const xsimd::batch<std::int32_t, Arch>& c0,
                                                 const xsimd::batch<std::int32_t, Arch>& c1,
                                                 const xsimd::batch<std::int32_t, Arch>& weight);

// RGBA8 pixels' channel pairs too far apart for rgba8_srgb to blend the bytes themselves: 0xff in
// each R, G and B byte whose c0 and c1 are not srgb_pair_near (kernels/codes.hpp:
// |c1 - c0| > 10 + (min(c0, c1) + 4) / 8, the + 4 saturating at 255), 0 in every other byte
// (alpha included).
template <class Arch>
xsimd::batch<std::int32_t, Arch> srgb_far_pairs(const xsimd::batch<std::int32_t, Arch>& c0,
                                                const xsimd::batch<std::int32_t, Arch>& c1);

// ---- Reading a row at data-dependent columns ----

// Lane i is the 4 bytes at base + index[i] (in floats), bit for bit. `base` may sit at any byte
// address (a row of 32-bit pixels); every index must address readable memory.
template <class Arch>
xsimd::batch<float, Arch> gather(const float* base, const xsimd::batch<std::int32_t, Arch>& index);

// The least (Max: greatest) lane in IEEE 754 totalOrder: -NaN < -inf < ... < -0 < +0 < ... <
// +inf < +NaN, NaNs ordered by payload. The result is that lane's bits: a vector holding both
// zeros gives -0 (Max: +0), whatever lanes they sit in.
template <class Arch, bool Max>
float lane_extreme(const xsimd::batch<float, Arch>& v);

// Whether the set has variable permutes across lanes (AVX2, AVX-512, NEON's table look-ups; not
// SSE4.1, where the column fetch gathers). first_lane, permute and permute_two_registers exist
// only where it is true.
template <class Arch> constexpr bool has_permute();

// Lane 0, bit for bit.
template <class Arch>
float first_lane(const xsimd::batch<float, Arch>& v);

// The lanes [first, v[0], ..., v[L-2]], bit for bit: v moved up one lane (its last lane
// dropped) and `first` put into lane 0. Every set has it (a byte shift on SSE4.1).
template <class Arch>
xsimd::batch<float, Arch> shift_in_first(const xsimd::batch<float, Arch>& v, float first);

// A column set's lanes, prepared once for the fetch that reads them (defined by each family:
// the index, plus what its permute instruction needs).
template <class Arch> struct LaneIndex;
// For gather(base, lanes.index): any index.
template <class Arch>
void index_for_gather(LaneIndex<Arch>& lanes, const xsimd::batch<std::int32_t, Arch>& index);
// For permute: every index in [0, L).
template <class Arch>
void index_for_permute(LaneIndex<Arch>& lanes, const xsimd::batch<std::int32_t, Arch>& index);
// For permute_two_registers: every index in [0, 2L).
template <class Arch>
void index_for_two_registers(LaneIndex<Arch>& lanes, const xsimd::batch<std::int32_t, Arch>& index);

// Lane i takes v[index[i]], bit for bit.
template <class Arch>
xsimd::batch<float, Arch> permute(const xsimd::batch<float, Arch>& v, const LaneIndex<Arch>& lanes);
// Lane i takes lane index[i] of the 2L lanes low[0..L) high[0..L), bit for bit.
template <class Arch>
xsimd::batch<float, Arch> permute_two_registers(const xsimd::batch<float, Arch>& low,
                                                const xsimd::batch<float, Arch>& high, const LaneIndex<Arch>& lanes);

// ---- Narrow and partial stores, 16-bit loads ----

// Stores lanes [0, min(count, L)) of `value` at out, bit for bit (count >= 0); the floats out[count,
// L) keep their values and nothing outside out[0, L) is touched. out[0, L) must be addressable:
// sets without a masked store read the vector there and write it back merged.
template <class Arch>
void store_first_lanes(const xsimd::batch<float, Arch>& value, float* out, int count);

// Stores the L lanes of `value` as the bytes out[0, L): each lane an integral float in [0, 255]
// (the PixelStatus values; any other lane is not specified). Nothing else is written.
template <class Arch>
void store_bytes(const xsimd::batch<float, Arch>& value, std::uint8_t* out);

// The L little-endian 16-bit codes at p (any byte address), zero-extended; reads 2L bytes.
template <class Arch>
xsimd::batch<std::int32_t, Arch> load_u16(const std::uint8_t* p);

// Stores each lane's code (in [0, 65535]) as 16 little-endian bits at out + 2 i (any byte
// address), every lane, or with `masked` only the lanes set in `write`; the other bytes of
// out[0, 2L) keep their values, and nothing outside them is touched.
template <class Arch>
void store_u16(const xsimd::batch<std::int32_t, Arch>& codes, const xsimd::batch_bool<float, Arch>& write, bool masked,
               std::uint8_t* out);

// ---- One RGBA pixel per 128-bit register (float RGBA and rgba16f colour) ----

#if defined(__aarch64__) || defined(_M_ARM64)
using Pixel4 = float32x4_t;
#else
using Pixel4 = __m128;
#endif

// Four copies of `value`; four +0.
inline Pixel4 pixel4_splat(float value);
inline Pixel4 pixel4_zero();
// Four floats (16 bytes) at p, any byte address, bit for bit.
inline Pixel4 load_float4(const std::uint8_t* p);
inline void store_float4(std::uint8_t* p, Pixel4 v);
// Per channel c0 + frac (c1 - c0) with the FMA policy: Fused fma(frac, c1 - c0, c0); Unfused
// (frac (c1 - c0)) + c0, each operation rounded.
template <class Fma>
Pixel4 lerp4(Pixel4 frac, Pixel4 c0, Pixel4 c1);
// Four IEEE binary16 values (8 bytes at p, any byte address) to floats and back, each exactly as
// kernels/codes.hpp's half_to_float and float_to_half: widening exact (a NaN quieted), narrowing
// to nearest even, overflow to infinity, a NaN quieted with its sign and top payload bits.
inline Pixel4 load_half4(const std::uint8_t* p);
inline void store_half4(std::uint8_t* p, Pixel4 value);

// ---- xsimd as the twins use it directly ----
//
// Beyond the primitives above, the twins call xsimd itself, and rely on this much of it
// (tests/test_arch_layer.cpp checks each, as ArchLayer.xsimd_*):
//  * select(mask, a, b): each lane a or b, bit for bit;
//  * <, <=, >, >=, ==: IEEE (false with a NaN operand); != only where neither operand is NaN
//    (xsimd 8.1's != is false with a NaN on AVX and AVX-512 and true on SSE4.1 and NEON): the
//    twins use it on flags only (load_flags);
//  * masks: batch_bool(bool) broadcasts, ~, &, | lane by lane, any() and all();
//  * to_int truncates toward zero and to_float rounds to nearest even, within the int32 range;
//  * integer +, -, * wrap around, &, |, ^, >> is arithmetic, << logical; <, > signed; ==, !=;
//  * float +, -, * as IEEE (NaNs as vmadd); unary - flips the sign of lanes that are neither
//    zero nor NaN (xsimd 8.1's AVX-512 negation is 0 - x, which keeps +0 as +0).
// Not used: bitwise_andnot(x, y), which xsimd 8.1 computes as ~x & y on x86 (andnps's operand
// order) and as x & ~y on NEON (bic's); the twins write a & ~b.

}  // namespace
}  // namespace reproject::detail

// The definitions: the family of the processor this translation unit is compiled for.
#if defined(__aarch64__) || defined(_M_ARM64)
#include "kernels/simd_neon.hpp"
#else
#include "kernels/simd_x86.hpp"
#endif
