// `exact` (DESIGN §5): the forward sweep. Source segments are walked in occlusion-compatible
// order (j upwards when b < 0, downwards when b > 0) and each non-fold segment is rasterised onto
// the target pixels it covers; later writes are nearer and overwrite earlier ones. The two edge
// extensions (outside) are painted first and last. O(width) per row.
#include <algorithm>
#include <cmath>
#include <limits>

#include "kernels/frame.hpp"

namespace reproject {
namespace detail {
namespace {

// Target pixels t' covered by [q0, q1) (b < 0) or (q0, q1] (b > 0), as a half-open range of
// target indices t = t' - guard, clipped to the row. The side that is closed matches the
// gather definition: a ray that reaches the surface exactly at a column end hits there.
struct Span {
  int begin;
  int end;
};
Span covered(const Frame& f, float q0, float q1) {
  float lo, hi;
  if (f.s < 0.0f) {
    lo = std::ceil(q0);
    hi = std::ceil(q1);
  } else {
    lo = std::floor(q0) + 1.0f;
    hi = std::floor(q1) + 1.0f;
  }
  const float g = static_cast<float>(f.guard);
  const float width = static_cast<float>(f.target_width);
  return Span{static_cast<int>(std::clamp(lo - g, 0.0f, width)), static_cast<int>(std::clamp(hi - g, 0.0f, width))};
}

}  // namespace

void search_row_exact(const Frame& f, RowScratch& scratch) {
  const float* parallax = scratch.parallax;
  float* xs = scratch.source_x.data();
  const int last = f.source_width - 1;
  const float guard = static_cast<float>(f.guard);
  const float infinity = std::numeric_limits<float>::infinity();

  // With a near limit tighter than the data, parts of the surface are nearer than any ray may
  // start; those are not painted, and rays that start behind the surface are clipped afterwards.
  float nearest_key = f.key_far;
  for (int j = 0; j <= last; ++j) nearest_key = std::max(nearest_key, f.s * parallax[j]);
  const bool may_clip = nearest_key > f.key_near;
  if (may_clip) {
    for (int t = 0; t < f.target_width; ++t) xs[t] = static_cast<float>(t) + guard - f.p_far;
  }

  // An edge extension: beyond the row the surface keeps the edge column's parallax.
  auto paint_extension = [&](int column, float q0, float q1) {
    const float p = parallax[column];
    if (may_clip && f.s * p > f.key_near) return;
    const Span span = covered(f, q0, q1);
    for (int t = span.begin; t < span.end; ++t) xs[t] = static_cast<float>(t) + guard - p;
  };
  auto paint_segment = [&](int j) {
    const float p0 = parallax[j];
    const float p1 = parallax[j + 1];
    const float q0 = static_cast<float>(j) + p0;
    const float q1 = static_cast<float>(j + 1) + p1;
    if (!(q1 > q0)) return;  // fold-over: a back face
    const Span span = covered(f, q0, q1);
    // frac = (t' - q0) / (q1 - q0), arranged so that (t' - j) and (p1 - p0) are exact: one
    // rounding on each side of the division instead of three.
    const float length = 1.0f + (p1 - p0);
    for (int t = span.begin; t < span.end; ++t) {
      const float frac = ((static_cast<float>(t + f.guard - j)) - p0) / length;
      if (may_clip && f.s * std::fma(frac, p1 - p0, p0) > f.key_near) continue;
      xs[t] = static_cast<float>(j) + frac;
    }
  };

  const float left_end = parallax[0];                            // q(0)
  const float right_end = static_cast<float>(last) + parallax[last];  // q(Ws - 1)
  if (f.s < 0.0f) {
    paint_extension(0, -infinity, left_end);
    for (int j = 0; j < last; ++j) paint_segment(j);
    paint_extension(last, right_end, infinity);
  } else {
    paint_extension(last, right_end, infinity);
    for (int j = last - 1; j >= 0; --j) paint_segment(j);
    paint_extension(0, -infinity, left_end);
  }

  for (int t = 0; t < f.target_width; ++t) scratch.clipped[t] = 0;
  if (may_clip) {
    for (int t = 0; t < f.target_width; ++t) {
      const float target = static_cast<float>(t) + guard;
      const float x_near = target - f.p_near;
      if (ray_gap(f, target, x_near, parallax_at(parallax, x_near)) < 0.0f) {
        xs[t] = x_near;
        scratch.clipped[t] = 1;
      }
    }
  }
}

}  // namespace detail
}  // namespace reproject
