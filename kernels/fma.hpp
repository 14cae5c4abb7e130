// Internal: the FMA policy (docs/DESIGN.md §8). Every multiply-add of the kernels is written
// madd<Fma>(a, b, c) (vmadd<Fma> on vectors, kernels/simd.hpp), so that a scalar reference and its
// SIMD twin round alike: Fused for the instruction sets with an FMA instruction (and the default
// scalar reference), Unfused for SSE4.1, which has none. The build sets -ffp-contract=off, so the
// compiler never fuses on its own and Unfused really is two roundings.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>
#include <type_traits>

// Whether this translation unit may use the FMA instruction (FMA3). GCC and Clang define __FMA__
// for it; MSVC defines no such macro, and its /arch:AVX2 and /arch:AVX512 bring FMA3
// (cmake/kernels.cmake).
#if defined(__FMA__) || (defined(_MSC_VER) && !defined(__clang__) && defined(__AVX2__))
#define REPROJECT_FMA3 1
#else
#define REPROJECT_FMA3 0
#endif

namespace reproject::detail {

struct Fused {};
struct Unfused {};

// In an anonymous namespace, like every helper compiled into both the baseline translation units
// and the per-arch ones: each translation unit keeps its own copy, built with its own flags, so
// the linker can never hand a baseline caller an AVX-512 body (docs/ARCHITECTURE.md, "One copy
// per translation unit").
namespace {

// a b + c rounded once, without the C library (docs/DESIGN.md §8, "fma without the C library").
// The product of two floats is exact in a double; the sum is rounded to double "to odd" (to
// nearest, then, if inexact and even, one unit toward the exact value), which makes the final
// conversion to float the only rounding. Infinities and NaNs come out of the double arithmetic as
// IEEE says.
inline float fma_in_software(float a, float b, float c) noexcept {
  const double product = static_cast<double>(a) * static_cast<double>(b);
  const double addend = c;
  const double sum = product + addend;
  if (!std::isfinite(sum)) return static_cast<float>(sum);
  const double product_part = sum - addend;  // TwoSum: the sum's rounding error, exactly
  const double error = (product - product_part) + (addend - (sum - product_part));
  std::uint64_t bits;
  std::memcpy(&bits, &sum, sizeof bits);
  if (error != 0.0 && (bits & 1u) == 0) bits += (error > 0.0) == (sum > 0.0) ? 1 : -1;
  double odd;
  std::memcpy(&odd, &bits, sizeof odd);
  return static_cast<float>(odd);
}

// a b + c rounded once: the instruction where this translation unit has one, and the software
// form elsewhere, where std::fma would call the C library, which is slow and, on some platforms
// (MinGW-w64's), does not round once.
inline float fused_madd(float a, float b, float c) noexcept {
#if REPROJECT_FMA3 || defined(__aarch64__) || defined(_M_ARM64)
  return std::fma(a, b, c);
#else
  return fma_in_software(a, b, c);
#endif
}

template <class Fma>
inline float madd(float a, float b, float c) noexcept {
  if constexpr (std::is_same<Fma, Fused>::value) {
    return fused_madd(a, b, c);
  } else {
    return a * b + c;
  }
}

}  // namespace
}  // namespace reproject::detail
