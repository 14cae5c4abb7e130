// Internal: SIMD twins of kernels/decode.cpp: the per-row parallax decode and the near limit's
// pass over the depth.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstring>
#include <type_traits>

#include "kernels/depth_formats_simd.hpp"
#include "kernels/simd.hpp"

namespace reproject::detail {
namespace {  // one copy per arch TU (kernels/fma.hpp)

// Calls body(tag) with the decode's shape as a compile-time tag (true: affine, p = fma(scale, d,
// offset); false: reciprocal, p = fma(b, 1/d, a)), so that a row loop branches on it once.
template <class Body>
void with_decode_shape(const Frame& f, const Body& body) {
  if (f.affine) body(std::true_type{});
  else body(std::false_type{});
}

// The decode's key s * p of stored depth values d, clamped as clean_parallax clamps it (scalar
// twins: raw_parallax, clean_parallax), in fewer operations and with the same bits except for a
// zero's sign: s = +-1 and a sign flip commutes with rounding, so the key is the decode with s
// folded into its constants; clean_parallax is then a clamp of the key to [key_far, limit] (vmax
// gives key_far for a NaN, and key_far <= limit), no compare and select. Only a sum that cancels
// can give a zero of the other sign (+0 either way); decode_parallax's + 0 makes every zero +0.
template <class Arch, class Fma>
struct ClampedKeys {
  using F = typename Lanes<Arch>::F;
  F scale, offset, a, b, key_far, limit;
  explicit ClampedKeys(const Frame& f)
      : scale(f.s * f.decode_scale), offset(f.s * f.decode_offset), a(f.s * f.a), b(f.s * f.b), key_far(f.key_far),
        limit(f.limit) {}
  template <bool Affine>
  REPROJECT_ALWAYS_INLINE F of(const F& d) const {
    const F key = Affine ? vmadd<Fma>(scale, d, offset) : vmadd<Fma>(b, vdiv(F(1.0f), d), a);
    return vmin(vmax(key, key_far), limit);
  }
};

// Scalar twin: decode_parallax_columns: p = s * key, exact, the + 0 fused into that product.
template <class Arch, class Fma>
void simd_decode(const Frame& f, const std::uint8_t* depth, float* parallax, float* stored) {
  REPROJECT_LANE_TYPES(Arch);
  const ClampedKeys<Arch, Fma> keys(f);
  const F s(f.s), zero(0.0f);
  const int width = f.source_width;  // a local: the stores may alias f's fields
  int i = 0;
  // One loop per depth format and decode shape, without a branch per vector for either.
  with_depth_format(f.depth.format, [&](auto format) {
    with_decode_shape(f, [&](auto affine) {
      for (; i + L <= width; i += L) {
        const F d = load_depth_values<Arch, Fma, decltype(format)::value>(f, depth, i);
        if (stored) d.store_unaligned(stored + i);
        vmadd<Fma>(s, keys.template of<decltype(affine)::value>(d), zero).store_unaligned(parallax + i);
      }
    });
  });
  decode_parallax_columns<Fma>(f, depth, parallax, stored, i, width);
}

// The UNORM codes of columns [i, i + L) of a depth row in Format.
template <class Arch, DepthFormat Format>
REPROJECT_ALWAYS_INLINE inline IntLanes<Arch> load_depth_codes(const std::uint8_t* row, int i) {
  using I = IntLanes<Arch>;
  static_assert(has_unorm_codes(Format), "UNORM formats only");
  if constexpr (Format == DepthFormat::unorm16) {
    return load_u16<Arch>(row + 2 * static_cast<std::ptrdiff_t>(i));
  } else {
    const I word = I::load_unaligned(reinterpret_cast<const std::int32_t*>(row + 4 * static_cast<std::ptrdiff_t>(i)));
    if constexpr (Format == DepthFormat::unorm24_s8) return word & I(0xffffff);
    else return (word >> 8) & I(0xffffff);
  }
}

// The key of a column holding `code` in the frame's UNORM format, from the scalar reference
// itself (nearest_key_in_columns on that one column), at least `nearest`.
template <class Fma>
float nearest_key_of_code(const Frame& f, std::uint32_t code, float nearest) {
  alignas(4) std::uint8_t column[4] = {};
  const std::uint32_t word = f.depth.format == DepthFormat::s8_unorm24 ? code << 8 : code;
  if (f.depth.format == DepthFormat::unorm16) {
    const std::uint16_t half = static_cast<std::uint16_t>(word);
    std::memcpy(column, &half, sizeof half);
  } else {
    std::memcpy(column, &word, sizeof word);
  }
  return nearest_key_in_columns<Fma>(f, column, 0, 1, nearest);
}

// The default near end's pass (scalar twin: nearest_key_in_columns): the same decode, reduced
// with max (order-independent, and no NaN survives the decode, so any order gives the same bits).
// A UNORM row (near_pass_by_codes) reduces its codes instead, with integer min and max, and only
// its lowest and highest codes are decoded: the same key.
template <class Arch, class Fma>
float simd_nearest_key(const Frame& f, const std::uint8_t* depth) {
  REPROJECT_LANE_TYPES(Arch);
  const ClampedKeys<Arch, Fma> clamped_keys(f);
  const int width = f.source_width;
  float nearest = f.key_far;
  int i = 0;
  with_depth_format(f.depth.format, [&](auto format_tag) {
    constexpr DepthFormat kFormat = decltype(format_tag)::value;
    if constexpr (has_unorm_codes(kFormat)) {
      if (width >= L && near_pass_by_codes(f)) {
        I lowest = load_depth_codes<Arch, kFormat>(depth, 0), highest = lowest;
        for (i = L; i + L <= width; i += L) {
          const I code = load_depth_codes<Arch, kFormat>(depth, i);
          lowest = xsimd::min(lowest, code);
          highest = xsimd::max(highest, code);
        }
        alignas(64) std::int32_t low[L], high[L];
        lowest.store_aligned(low);
        highest.store_aligned(high);
        const std::int32_t low_code = *std::min_element(low, low + L), high_code = *std::max_element(high, high + L);
        nearest = nearest_key_of_code<Fma>(f, static_cast<std::uint32_t>(low_code), nearest);
        nearest = nearest_key_of_code<Fma>(f, static_cast<std::uint32_t>(high_code), nearest);
        return;
      }
    }
    F keys(f.key_far);
    with_decode_shape(f, [&](auto affine) {
      for (; i + L <= width; i += L) {
        const F d = load_depth_values<Arch, Fma, kFormat>(f, depth, i);
        keys = vmax(keys, clamped_keys.template of<decltype(affine)::value>(d));
      }
    });
    nearest = lane_max<Arch>(keys);
  });
  return nearest_key_in_columns<Fma>(f, depth, i, width, nearest);
}

}  // namespace
}  // namespace reproject::detail
