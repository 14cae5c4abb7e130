// Internal: SIMD twins of kernels/codes.hpp's conversions, lane by lane the same bits.
#pragma once

#include <cstdint>
#include <type_traits>

#include "kernels/codes.hpp"
#include "kernels/simd.hpp"

namespace reproject::detail {
namespace {  // one copy per arch TU (kernels/fma.hpp)

template <class Arch>
using IntLanes = typename Lanes<Arch>::I;

// Twins of round_even and clamp_code.
template <class Arch>
xsimd::batch<float, Arch> round_even_v(const xsimd::batch<float, Arch>& x) {
  using F = typename Lanes<Arch>::F;
  const F magic(8388608.0f);
  return xsimd::select(x < magic, (x + magic) - magic, x);
}
template <class Arch>
xsimd::batch<float, Arch> clamp_code_v(const xsimd::batch<float, Arch>& x, float max) {
  using F = typename Lanes<Arch>::F;
  const F positive = xsimd::select(x > F(0.0f), x, F(0.0f));
  return xsimd::select(positive < F(max), positive, F(max));
}

// u / (2^Bits - 1) correctly rounded (scalar twin: unorm_value, a division). Where the table has
// an FMA, without the division: with x = u 2^-Bits (exact), fma(x, c, x) for c the float just
// above 2^-Bits is the correctly rounded quotient for every 16- and 24-bit code (u / (2^b - 1) =
// x (1 + 2^-b + 2^-2b + ...); checked exhaustively by PixelFormats.UnormDecodeEveryCodeEveryArch).
template <class Arch, class Fma, int Bits>
xsimd::batch<float, Arch> unorm_values(const IntLanes<Arch>& code) {
  using F = typename Lanes<Arch>::F;
  constexpr float kMax = Bits == 16 ? 65535.0f : 16777215.0f;
  if constexpr (std::is_same<Fma, Fused>::value) {
    constexpr float kUnit = Bits == 16 ? 0x1p-16f : 0x1p-24f;
    constexpr float kAbove = Bits == 16 ? 0x1.000002p-16f : 0x1.000002p-24f;
    const F x = xsimd::to_float(code) * F(kUnit);
    return vmadd<Fma>(x, F(kAbove), x);
  } else {
    return vdiv(xsimd::to_float(code), F(kMax));
  }
}
// Scalar twin: unorm_code.
template <class Arch>
IntLanes<Arch> unorm_code_v(const xsimd::batch<float, Arch>& d, float max) {
  using F = typename Lanes<Arch>::F;
  return xsimd::to_int(round_even_v<Arch>(clamp_code_v<Arch>(d * F(max), max)));
}

}  // namespace
}  // namespace reproject::detail
