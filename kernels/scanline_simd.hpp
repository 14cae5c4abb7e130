// SIMD twin of kernels/scanline.cpp (`scanline`).
#pragma once

#include "kernels/search_simd.hpp"

namespace reproject::detail {
namespace {  // one copy per arch TU (kernels/fma.hpp)

// Scalar twin: search_row_scanline.

template <class Arch, class Fma>
void simd_scanline(const Frame& f, RowScratch& scratch) {
  REPROJECT_LANE_TYPES(Arch);
  const float* parallax = scratch.parallax;
  const float o_near = -f.p_near;
  const float o_far = -f.p_far;
  const F s(f.s), zero(0.0f), lanes = lane_offsets<Arch>();
  int t = 0;
  for (; t + L <= f.target_width; t += L) {
    const int target0 = t + f.guard;
    const F gap_near = s * (F(-o_near) - parallax_at_offset_v<Arch, Fma>(parallax, target0, o_near));
    const B behind_or_on = gap_near <= zero;
    F offset(o_near);
    if (!xsimd::all(behind_or_on))
      offset = simd_march_columns<Arch, Fma>(f, parallax, target0, o_near, gap_near, behind_or_on, offset, o_far);
    (F(static_cast<float>(target0)) + lanes + offset).store_unaligned(scratch.source_x.data() + t);
    store_flags<Arch>(gap_near < zero, scratch.clipped.data() + t);
  }
  search_row_scanline<Fma>(f, scratch, t, f.target_width);
}

}  // namespace
}  // namespace reproject::detail
