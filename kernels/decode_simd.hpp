// Internal: SIMD twins of kernels/decode.cpp: the per-row parallax decode and the near limit's
// pass over the depth.
#pragma once

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

// Scalar twin: decode_parallax_columns.
template <class Arch, class Fma>
void simd_decode(const Frame& f, const std::uint8_t* depth, float* parallax, float* stored) {
  REPROJECT_LANE_TYPES(Arch);
  const F scale(f.decode_scale), offset(f.decode_offset), a(f.a), b(f.b), s(f.s);
  const F key_far(f.key_far), p_far(f.p_far), limit(f.limit), near_bound(f.s * f.limit), one(1.0f);
  const int width = f.source_width;  // a local: the stores may alias f's fields
  int i = 0;
  // One loop per depth format and decode shape, without a branch per vector for either.
  with_depth_format(f.depth.format, [&](auto format) {
    with_decode_shape(f, [&](auto affine) {
      for (; i + L <= width; i += L) {
        const F d = load_depth_values<Arch, Fma, decltype(format)::value>(f, depth, i);
        if (stored) d.store_unaligned(stored + i);
        F p = decltype(affine)::value ? vmadd<Fma>(scale, d, offset) : vmadd<Fma>(b, vdiv(one, d), a);
        const F key = s * p;
        p = xsimd::select(key >= key_far, p, p_far);  // NaN and farther than infinity: infinity
        p = xsimd::select(key > limit, near_bound, p);
        (p + F(0.0f)).store_unaligned(parallax + i);  // -0 -> +0, as decode_parallax
      }
    });
  });
  decode_parallax_columns<Fma>(f, depth, parallax, stored, i, width);
}

// The default near end's pass (scalar twin: nearest_key_in_columns): the same decode, reduced
// with max (order-independent, and no NaN survives the decode, so any order gives the same bits).
template <class Arch, class Fma>
float simd_nearest_key(const Frame& f, const std::uint8_t* depth) {
  REPROJECT_LANE_TYPES(Arch);
  const F scale(f.decode_scale), offset(f.decode_offset), a(f.a), b(f.b), s(f.s);
  const F key_far(f.key_far), limit(f.limit), one(1.0f);
  const int width = f.source_width;
  F nearest = key_far;
  int i = 0;
  with_depth_format(f.depth.format, [&](auto format) {
    with_decode_shape(f, [&](auto affine) {
      for (; i + L <= width; i += L) {
        const F d = load_depth_values<Arch, Fma, decltype(format)::value>(f, depth, i);
        const F p = decltype(affine)::value ? vmadd<Fma>(scale, d, offset) : vmadd<Fma>(b, vdiv(one, d), a);
        const F key = s * p;
        // clean_parallax on keys: NaN and farther than infinity -> key_far; beyond L -> L.
        nearest = vmax(nearest, xsimd::select(key >= key_far, vmin(key, limit), key_far));
      }
    });
  });
  return nearest_key_in_columns<Fma>(f, depth, i, width, lane_max<Arch>(nearest));
}

}  // namespace
}  // namespace reproject::detail
