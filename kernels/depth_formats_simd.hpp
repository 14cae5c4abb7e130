// Internal: SIMD twins of kernels/depth_formats.hpp's depth loads and stores (docs/BEHAVIOUR.md
// "Pixel formats"): the same integer arithmetic and correctly rounded float operations, lane by
// lane, so every arch stores the same bits as the scalar reference.
#pragma once

#include <type_traits>

#include "kernels/codes_simd.hpp"
#include "kernels/depth_formats.hpp"

namespace reproject::detail {
namespace {  // one copy per arch TU (kernels/fma.hpp)

// Calls body(tag) with a compile-time tag of the depth format, so that the row loops are
// compiled once per format (no branch per vector).
template <DepthFormat Format>
using DepthFormatTag = std::integral_constant<DepthFormat, Format>;
template <class Body>
void with_depth_format(DepthFormat format, const Body& body) {
  switch (format) {
    case DepthFormat::unorm16: return body(DepthFormatTag<DepthFormat::unorm16>{});
    case DepthFormat::unorm24_s8: return body(DepthFormatTag<DepthFormat::unorm24_s8>{});
    case DepthFormat::s8_unorm24: return body(DepthFormatTag<DepthFormat::s8_unorm24>{});
    case DepthFormat::rgba8_packed_linear: return body(DepthFormatTag<DepthFormat::rgba8_packed_linear>{});
    case DepthFormat::float32: break;
  }
  body(DepthFormatTag<DepthFormat::float32>{});
}

// The stored values d of L depth words of a 32-bit integer format (scalar twin: depth_value).
template <class Arch, class Fma, DepthFormat Format>
REPROJECT_ALWAYS_INLINE inline xsimd::batch<float, Arch> depth_values_of_words(const Frame& f, const IntLanes<Arch>& word) {
  using F = typename Lanes<Arch>::F;
  using I = IntLanes<Arch>;
  static_assert(Format != DepthFormat::float32 && Format != DepthFormat::unorm16, "32-bit integer words only");
  if constexpr (Format == DepthFormat::unorm24_s8) return unorm_values<Arch, Fma, 24>(word & I(0xffffff));
  if constexpr (Format == DepthFormat::s8_unorm24) return unorm_values<Arch, Fma, 24>((word >> 8) & I(0xffffff));
  if constexpr (Format == DepthFormat::rgba8_packed_linear) {
    const I code = (word & I(0xff)) * I(65025) + ((word >> 8) & I(0xff)) * I(255) + ((word >> 16) & I(0xff));
    return vdiv(xsimd::to_float(code), F(kPackedMax)) * F(f.packed_range) + F(f.packed_near);  // never fused
  }
}
template <class Arch, class Fma>
REPROJECT_ALWAYS_INLINE inline xsimd::batch<float, Arch> depth_values_of_words(const Frame& f, const IntLanes<Arch>& word) {
  switch (f.depth.format) {
    case DepthFormat::unorm24_s8: return depth_values_of_words<Arch, Fma, DepthFormat::unorm24_s8>(f, word);
    case DepthFormat::s8_unorm24: return depth_values_of_words<Arch, Fma, DepthFormat::s8_unorm24>(f, word);
    case DepthFormat::rgba8_packed_linear: return depth_values_of_words<Arch, Fma, DepthFormat::rgba8_packed_linear>(f, word);
    case DepthFormat::unorm16:
    case DepthFormat::float32: break;
  }
  return float_bits<Arch>(word);
}

// The stored values d of columns [i, i + L) of a depth row (scalar twin: depth_value).
template <class Arch, class Fma, DepthFormat Format>
xsimd::batch<float, Arch> load_depth_values(const Frame& f, const std::uint8_t* row, int i) {
  using F = typename Lanes<Arch>::F;
  using I = IntLanes<Arch>;
  if constexpr (Format == DepthFormat::float32) {
    return F::load_unaligned(reinterpret_cast<const float*>(row) + i);
  } else if constexpr (Format == DepthFormat::unorm16) {
    return unorm_values<Arch, Fma, 16>(load_u16<Arch>(row + 2 * static_cast<std::ptrdiff_t>(i)));
  } else {
    const I word = I::load_unaligned(reinterpret_cast<const std::int32_t*>(row + 4 * static_cast<std::ptrdiff_t>(i)));
    return depth_values_of_words<Arch, Fma, Format>(f, word);
  }
}

// The words that store depth d (scalar twin: depth_word); `kept` as there.
template <class Arch>
REPROJECT_ALWAYS_INLINE inline IntLanes<Arch> depth_words(const Frame& f, const xsimd::batch<float, Arch>& d,
                                                          const IntLanes<Arch>& kept) {
  using F = typename Lanes<Arch>::F;
  using I = IntLanes<Arch>;
  switch (f.depth.format) {
    case DepthFormat::unorm16: return unorm_code_v<Arch>(d, kUnorm16Max);
    case DepthFormat::unorm24_s8: return unorm_code_v<Arch>(d, kUnorm24Max) | (kept & I(static_cast<std::int32_t>(0xff000000u)));
    case DepthFormat::s8_unorm24: return (unorm_code_v<Arch>(d, kUnorm24Max) << 8) | (kept & I(0xff));
    case DepthFormat::rgba8_packed_linear: {
      const F v = vdiv(d - F(f.packed_near), F(f.packed_range));
      const I n = xsimd::to_int(round_even_v<Arch>(clamp_code_v<Arch>(v * F(kPackedMax), kPackedMax - 1.0f)));
      // Exact quotients from correctly rounded float divisions: n < 2^24, and each true quotient
      // lies at least 1/65025 (1/255) below the next integer, more than the division's rounding.
      const I r = xsimd::to_int(vdiv(xsimd::to_float(n), F(65025.0f)));
      const I rest = n - r * I(65025);
      const I g = xsimd::to_int(vdiv(xsimd::to_float(rest), F(255.0f)));
      return r | (g << 8) | ((rest - g * I(255)) << 16) | (kept & I(static_cast<std::int32_t>(0xff000000u)));
    }
    case DepthFormat::float32: break;
  }
  return bits_of<Arch>(d);
}

}  // namespace
}  // namespace reproject::detail
