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

// The first target column t' that a surface point at integer column j with parallax p reaches
// or passes: t' >= j + p when b < 0, t' > j + p when b > 0 (segments cover [q(j), q(j+1)) and
// (q(j), q(j+1)] respectively). Decided on the integer t' - j against p, so it is exact and agrees
// bit for bit with the gather's sign test (t' - j) - p at a column.
int first_target_reached(const Frame& f, int column, float p) {
  return column + static_cast<int>(f.s < 0.0f ? std::ceil(p) : std::floor(p) + 1.0f);
}

// Target indices t = t' - guard in [begin, end), clipped to the row.
struct Span {
  int begin;
  int end;
};
Span target_span(const Frame& f, long long first, long long end) {
  const long long lo = std::clamp<long long>(first - f.guard, 0, f.target_width);
  const long long hi = std::clamp<long long>(end - f.guard, 0, f.target_width);
  return Span{static_cast<int>(lo), static_cast<int>(hi)};
}

}  // namespace

template <class Fma>
void search_row_exact(const Frame& f, RowScratch& scratch, int, int) {
  const float* parallax = scratch.parallax;
  float* xs = scratch.source_x.data();
  const int last = f.source_width - 1;
  const float guard = static_cast<float>(f.guard);

  // With a near limit tighter than the data, parts of the surface are nearer than any ray may
  // start; those are not painted, and rays that start behind the surface are clipped afterwards.
  float nearest_key = f.key_far;
  for (int j = 0; j <= last; ++j) nearest_key = std::max(nearest_key, f.s * parallax[j]);
  const bool may_clip = nearest_key > f.key_near;
  if (may_clip) {
    for (int t = 0; t < f.target_width; ++t) xs[t] = static_cast<float>(t) + guard - f.p_far;
  }

  // An edge extension: beyond the row the surface keeps the edge column's parallax.
  constexpr long long kUnbounded = 1LL << 40;
  auto paint_extension = [&](int column, const Span& span) {
    const float p = parallax[column];
    if (may_clip && f.s * p > f.key_near) return;
    for (int t = span.begin; t < span.end; ++t) xs[t] = static_cast<float>(t) + guard - p;
  };
  auto paint_segment = [&](int j) {
    const float p0 = parallax[j];
    const float p1 = parallax[j + 1];
    // Empty for a fold-over (p1 - p0 < -1): a back face.
    const Span span = target_span(f, first_target_reached(f, j, p0), first_target_reached(f, j + 1, p1));
    // frac = (t' - q0) / (q1 - q0) with q = column + p, arranged so that (t' - j) and (p1 - p0)
    // are exact: one rounding on each side of the division. Clamped, for the degenerate case
    // where the length rounds to 0.
    const float length = 1.0f + (p1 - p0);
    for (int t = span.begin; t < span.end; ++t) {
      const float frac = std::clamp((static_cast<float>(t + f.guard - j) - p0) / length, 0.0f, 1.0f);
      if (may_clip && f.s * Fma::madd(frac, p1 - p0, p0) > f.key_near) continue;
      xs[t] = static_cast<float>(j) + frac;
    }
  };

  const Span left_extension = target_span(f, -kUnbounded, first_target_reached(f, 0, parallax[0]));
  const Span right_extension = target_span(f, first_target_reached(f, last, parallax[last]), kUnbounded);
  if (f.s < 0.0f) {
    paint_extension(0, left_extension);
    for (int j = 0; j < last; ++j) paint_segment(j);
    paint_extension(last, right_extension);
  } else {
    paint_extension(last, right_extension);
    for (int j = last - 1; j >= 0; --j) paint_segment(j);
    paint_extension(0, left_extension);
  }

  for (int t = 0; t < f.target_width; ++t) scratch.clipped[t] = 0;
  if (may_clip) {
    for (int t = 0; t < f.target_width; ++t) {
      const float target = static_cast<float>(t) + guard;
      const float x_near = target - f.p_near;
      if (f.s * ((target - x_near) - parallax_at<Fma>(parallax, x_near)) < 0.0f) {
        xs[t] = x_near;
        scratch.clipped[t] = 1;
      }
    }
  }
}

template void search_row_exact<Fused>(const Frame&, RowScratch&, int, int);
template void search_row_exact<Unfused>(const Frame&, RowScratch&, int, int);

}  // namespace detail
}  // namespace reproject
