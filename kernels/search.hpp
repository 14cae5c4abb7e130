// Internal: the search math the methods share (docs/DESIGN.md §5, docs/BEHAVIOUR.md "The exact
// answer"): the gap between a ray and the surface, linear intersection, the interpolated
// parallax at a position or an offset, the point sample, and the column march of `scanline` and
// `secant`. Scalar; the SIMD twins are in kernels/search_simd.hpp.
#pragma once

#include <cmath>

#include "kernels/fma.hpp"
#include "kernels/frame.hpp"

namespace reproject::detail {
namespace {  // one copy per translation unit (kernels/fma.hpp)

// g = s ((t' - x) - P(x)): > 0 while the ray is in front of the surface (docs/BEHAVIOUR.md).
// Linear intersection of g between a sample in front (gap_front > 0) and one on or behind.
template <class Fma>
inline float intersect(float x_front, float gap_front, float x_behind, float gap_behind) noexcept {
  const float t = gap_front / (gap_front - gap_behind);
  return madd<Fma>(t, x_behind - x_front, x_front);
}

// Interpolated parallax at a continuous source position inside the padded row.
template <class Fma>
inline float parallax_at(const float* parallax, float x) noexcept {
  const float column = std::floor(x);
  const int j = static_cast<int>(column);
  return madd<Fma>(x - column, parallax[j + 1] - parallax[j], parallax[j]);
}

// The marching methods work in *offsets* o = x - t' from the target column: a fixed-step
// sample then has the same offset, integer part and fraction in every lane, so a SIMD twin reads
// it with contiguous loads and gets the same bits as this scalar reference. t' - x = -o exactly.

// Parallax at offset o from target column t' (o's integer part and fraction are lane-invariant).
template <class Fma>
inline float parallax_at_offset(const float* parallax, int target, float offset) noexcept {
  const float whole = std::floor(offset);
  const float* p = parallax + target + static_cast<int>(whole);
  return madd<Fma>(offset - whole, p[1] - p[0], p[0]);
}
inline float gap_at_offset(const Frame& f, float offset, float surface_parallax) noexcept {
  return f.s * (-offset - surface_parallax);
}

// Point sample of march16 / single at ray parallax p: column floor(t' - p + 0.5) = t' + floor(0.5 - p);
// the padded row makes it the clamped read.
inline int point_offset(float ray_parallax) noexcept {
  return static_cast<int>(std::floor(0.5f - ray_parallax));
}

// The integer offsets strictly between o_start and o_end, walked in direction s: [first, end).
struct ColumnWalk {
  int first;
  int end;
  int step;
};
inline ColumnWalk column_walk(const Frame& f, float o_start, float o_end) noexcept {
  if (f.s > 0.0f) return ColumnWalk{static_cast<int>(std::floor(o_start)) + 1, static_cast<int>(std::ceil(o_end)), 1};
  return ColumnWalk{static_cast<int>(std::ceil(o_start)) - 1, static_cast<int>(std::floor(o_end)), -1};
}
inline bool walking(const ColumnWalk& walk, int o) noexcept { return walk.step > 0 ? o < walk.end : o > walk.end; }

// The column march shared by `scanline` and `secant`: from offset o_start (gap_start > 0), visit
// every integer offset strictly between o_start and o_end in direction s, then o_end; return the
// offset of the first crossing (linear on its segment), or o_end if none is found by rounding.
template <class Fma>
inline float march_columns(const Frame& f, const float* parallax, int target, float o_start, float gap_start,
                    float o_end) noexcept {
  const ColumnWalk walk = column_walk(f, o_start, o_end);
  float o_prev = o_start;
  float gap_prev = gap_start;
  for (int o = walk.first; walking(walk, o); o += walk.step) {
    const float offset = static_cast<float>(o);
    const float gap = gap_at_offset(f, offset, parallax[target + o]);
    if (gap <= 0.0f) return intersect<Fma>(o_prev, gap_prev, offset, gap);
    o_prev = offset;
    gap_prev = gap;
  }
  const float gap = gap_at_offset(f, o_end, parallax_at_offset<Fma>(parallax, target, o_end));
  return gap <= 0.0f ? intersect<Fma>(o_prev, gap_prev, o_end, gap) : o_end;
}

}  // namespace
}  // namespace reproject::detail
