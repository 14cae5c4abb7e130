// Internal: the FMA policy (docs/DESIGN.md §8). Every multiply-add of the kernels is written
// madd<Fma>(a, b, c) (vmadd<Fma> on vectors, kernels/simd.hpp), so that a scalar reference and its
// SIMD twin round alike: Fused for the instruction sets with an FMA instruction (and the default
// scalar reference), Unfused for SSE4.1, which has none. The build sets -ffp-contract=off, so the
// compiler never fuses on its own and Unfused really is two roundings.
#pragma once

#include <cmath>
#include <type_traits>

namespace reproject::detail {

struct Fused {};
struct Unfused {};

// In an anonymous namespace, like every helper compiled into both the baseline translation units
// and the per-arch ones: each translation unit keeps its own copy, built with its own flags, so
// the linker can never hand a baseline caller an AVX-512 body (docs/ARCHITECTURE.md, "One copy
// per translation unit").
namespace {

template <class Fma>
inline float madd(float a, float b, float c) noexcept {
  if constexpr (std::is_same<Fma, Fused>::value) {
    return std::fma(a, b, c);
  } else {
    return a * b + c;
  }
}

}  // namespace
}  // namespace reproject::detail
