// SIMD twin of kernels/single.cpp (`single`).
#pragma once

#include "kernels/search_simd.hpp"

namespace reproject::detail {
namespace {  // one copy per arch TU (kernels/fma.hpp)

// Scalar twin: search_row_single.

template <class Arch, class Fma>
void simd_single(const Frame& f, RowScratch& scratch) {
  REPROJECT_LANE_TYPES(Arch);
  const float* parallax = scratch.parallax;
  const int probe_offset = point_offset(f.probe);
  const F s(f.s), key_near(f.key_near), lanes = lane_offsets<Arch>();
  int t = 0;
  for (; t + L <= f.target_width; t += L) {
    const int target0 = t + f.guard;
    const F surface = F::load_unaligned(parallax + target0 + probe_offset);
    (F(static_cast<float>(target0)) + lanes - surface).store_unaligned(scratch.source_x.data() + t);
    store_flags<Arch>(s * surface > key_near, scratch.clipped.data() + t);
  }
  search_row_single<Fma>(f, scratch, t, f.target_width);
}

}  // namespace
}  // namespace reproject::detail
