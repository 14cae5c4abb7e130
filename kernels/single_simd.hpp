// SIMD twin of kernels/single.cpp (`single`).
#pragma once

#include "kernels/search_simd.hpp"

namespace reproject::detail {
namespace {  // one copy per arch TU (kernels/fma.hpp)

// Scalar twin: search_row_single.

template <class Arch, class Fma>
void simd_single(const Frame& f, RowScratch& scratch) {
  REPROJECT_LANE_TYPES(Arch);
  // Locals, not f's fields: the stores below go through float pointers, which may alias the
  // Frame's floats, so fields would be reloaded after each store.
  const int width = f.target_width;
  const float* probe_row = scratch.parallax + f.guard + point_offset(f.probe);  // lane t reads t + guard + offset
  float* source_x = scratch.source_x.data();
  float* clipped = scratch.clipped.data();
  const F s(f.s), key_near(f.key_near), step(static_cast<float>(L));
  F target = F(static_cast<float>(f.guard)) + lane_offsets<Arch>();  // t + guard: exact small integers
  int t = 0;
  for (; t + L <= width; t += L) {
    const F surface = F::load_unaligned(probe_row + t);
    (target - surface).store_unaligned(source_x + t);
    store_flags<Arch>(s * surface > key_near, clipped + t);
    target = target + step;
  }
  search_row_single<Fma>(f, scratch, t, width);
}

}  // namespace
}  // namespace reproject::detail
