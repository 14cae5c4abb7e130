// Internal: SIMD twins of the shared search math of kernels/search.hpp.
#pragma once

#include <cmath>

#include "kernels/search.hpp"
#include "kernels/simd.hpp"

namespace reproject::detail {
namespace {  // one copy per arch TU (kernels/fma.hpp)

// Parallax at a lane-invariant offset from each lane's target column: two contiguous loads
// (scalar twin: parallax_at_offset).
template <class Arch, class Fma>
xsimd::batch<float, Arch> parallax_at_offset_v(const float* parallax, int target0, float offset) {
  using F = typename Lanes<Arch>::F;
  const float whole = std::floor(offset);
  const float* p = parallax + target0 + static_cast<int>(whole);
  const F p0 = F::load_unaligned(p);
  const F p1 = F::load_unaligned(p + 1);
  return vmadd<Fma>(F(offset - whole), p1 - p0, p0);
}

// Scalar twin: intersect.
template <class Arch, class Fma>
xsimd::batch<float, Arch> intersect_v(const xsimd::batch<float, Arch>& x_front, const xsimd::batch<float, Arch>& gap_front,
                                      const xsimd::batch<float, Arch>& x_behind, const xsimd::batch<float, Arch>& gap_behind) {
  const auto t = vdiv(gap_front, gap_front - gap_behind);
  return vmadd<Fma>(t, x_behind - x_front, x_front);
}

// The column march of scanline and secant (scalar twin: march_columns). Lanes in `done` keep
// `offset`; the others get the offset of their first crossing.
template <class Arch, class Fma>
xsimd::batch<float, Arch> simd_march_columns(const Frame& f, const float* parallax, int target0, float o_start,
                                             xsimd::batch<float, Arch> gap_prev, xsimd::batch_bool<float, Arch> done,
                                             xsimd::batch<float, Arch> offset, float o_end) {
  REPROJECT_LANE_TYPES(Arch);
  const F s(f.s), zero(0.0f);
  const ColumnWalk walk = column_walk(f, o_start, o_end);
  float o_prev = o_start;
  for (int o = walk.first; walking(walk, o); o += walk.step) {
    const float column = static_cast<float>(o);
    const F gap = s * (F(-column) - F::load_unaligned(parallax + target0 + o));
    const B hit = (gap <= zero) & ~done;
    if (xsimd::any(hit)) {
      offset = xsimd::select(hit, intersect_v<Arch, Fma>(F(o_prev), gap_prev, F(column), gap), offset);
      done = done | hit;
      if (xsimd::all(done)) return offset;
    }
    o_prev = column;
    gap_prev = gap;
  }
  const F gap = s * (F(-o_end) - parallax_at_offset_v<Arch, Fma>(parallax, target0, o_end));
  const B hit = (gap <= zero) & ~done;
  offset = xsimd::select(hit, intersect_v<Arch, Fma>(F(o_prev), gap_prev, F(o_end), gap), offset);
  return xsimd::select(done | hit, offset, F(o_end));
}

}  // namespace
}  // namespace reproject::detail
