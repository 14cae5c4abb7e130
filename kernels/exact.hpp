// `exact` (DESIGN §5): the forward sweep. Source segments are walked in occlusion-compatible
// order (j upwards when b < 0, downwards when b > 0) and each non-fold segment is rasterised onto
// the target pixels it covers; later writes are nearer and overwrite earlier ones. The two edge
// extensions (outside) are painted first and last. O(width) per row.
// The sweep lives in this header (in an anonymous namespace) so that the baseline scalar table
// and each instruction set's table compile their own copy with their own flags.
#pragma once

#include <algorithm>
#include <cmath>

#include "kernels/search.hpp"

namespace reproject::detail {
namespace {

// The first target column t' that a surface point at integer column j with parallax p reaches
// or passes: t' >= j + p when b < 0, t' > j + p when b > 0 (segments cover [q(j), q(j+1)) and
// (q(j), q(j+1)] respectively). Decided on the integer t' - j against p, so it is exact and agrees
// bit for bit with the gather's sign test (t' - j) - p at a column.
// `Upwards`: b < 0 (the sweep walks columns upwards).
template <bool Upwards>
inline int first_target_reached(int column, float p) {
  return column + static_cast<int>(Upwards ? std::ceil(p) : std::floor(p) + 1.0f);
}

// Where the surface point at `column` first reaches, as a target pixel clamped to [0, Wt]: the
// boundary between the spans of sweep_in_order.
template <bool Upwards>
inline int reach_of(const float* parallax, int column, int guard, int width) {
  return std::clamp(first_target_reached<Upwards>(column, parallax[column]) - guard, 0, width);
}

// The sweep's order, written once for the scalar sweep and its SIMD twins: the near extension,
// the segments towards the far side, the far extension (b < 0, `Upwards`: columns 0 -> last).
// Each is handed its span as target pixels [begin, end): where a column's surface point first
// reaches, clamped to [0, Wt], so the spans are already clipped to the row (clamping is monotone)
// and each column's reach is computed once; a segment's span is empty for a fold-over (a back
// face). extension(column, begin, end) is the edge column's; segment(j, begin, end) is [j, j+1]'s.
//
// This form hands the segments to three painters: those of [middle_lo, middle_hi] to `middle`,
// those before them in sweep order to `before` (upwards j < middle_lo, downwards j > middle_hi),
// the rest to `after` (0 <= middle_lo <= middle_hi + 1 <= last).
template <bool Upwards, class Extension, class Before, class Middle, class After>
inline void sweep_in_order(const Frame& f, const float* parallax, const Extension& extension, const Before& before,
                           const Middle& middle, const After& after, int middle_lo, int middle_hi) {
  const int last = f.source_width - 1;
  const int width = f.target_width;
  const int guard = f.guard;
  auto reach = [&](int column) { return reach_of<Upwards>(parallax, column, guard, width); };
  if constexpr (Upwards) {
    // Segments [from, to) from `begin` on; returns where the next one begins.
    auto run = [&](int from, int to, int begin, const auto& segment) {
      for (int j = from; j < to; ++j) {
        const int end = reach(j + 1);
        segment(j, begin, end);
        begin = end;
      }
      return begin;
    };
    int begin = reach(0);
    extension(0, 0, begin);
    begin = run(0, middle_lo, begin, before);
    begin = run(middle_lo, middle_hi + 1, begin, middle);
    begin = run(middle_hi + 1, last, begin, after);
    extension(last, begin, width);
  } else {
    // Segments from, from - 1, ... down to (not including) `to`, from `end` down; returns where
    // the next one ends.
    auto run = [&](int from, int to, int end, const auto& segment) {
      for (int j = from; j > to; --j) {
        const int begin = reach(j);
        segment(j, begin, end);
        end = begin;
      }
      return end;
    };
    int end = reach(last);
    extension(last, end, width);
    end = run(last - 1, middle_hi, end, before);
    end = run(middle_hi, middle_lo - 1, end, middle);
    end = run(middle_lo - 1, -1, end, after);
    extension(0, 0, end);
  }
}

// Every segment to one painter.
template <bool Upwards, class Extension, class Segment>
inline void sweep_in_order(const Frame& f, const float* parallax, const Extension& extension, const Segment& segment) {
  sweep_in_order<Upwards>(f, parallax, extension, segment, segment, segment, 0, f.source_width - 2);
}

// Source x of target pixel t painted by an edge extension whose surface has parallax p.
inline float extension_x(const Frame& f, int t, float p) {
  return static_cast<float>(t) + static_cast<float>(f.guard) - p;
}
// Fraction along segment [j, j+1] (parallax p0 at j, length = 1 + (p1 - p0)) of target pixel t:
// frac = (t' - q0) / (q1 - q0) with q = column + p, arranged so that (t' - j) and (p1 - p0) are
// exact: one rounding on each side of the division. Clamped, for the degenerate case where the
// length rounds to 0.
inline float segment_frac(const Frame& f, int t, int j, float p0, float length) {
  return std::clamp((static_cast<float>(t + f.guard - j) - p0) / length, 0.0f, 1.0f);
}

template <class Fma>
inline void sweep_row(const Frame& f, RowScratch& scratch) {
  const float* parallax = scratch.parallax;
  float* xs = scratch.source_x.data();
  const int last = f.source_width - 1;
  const float guard = static_cast<float>(f.guard);

  // With a near limit tighter than the data, parts of the surface are nearer than any ray may
  // start; those are not painted, and rays that start behind the surface are clipped afterwards.
  bool may_clip = false;
  if (!f.near_from_frame) {  // the default near end is the frame's nearest: nothing is clipped
    float nearest_key = f.key_far;
    for (int j = 0; j <= last; ++j) nearest_key = std::max(nearest_key, f.s * parallax[j]);
    may_clip = nearest_key > f.key_near;
  }
  if (may_clip) {
    for (int t = 0; t < f.target_width; ++t) xs[t] = static_cast<float>(t) + guard - f.p_far;
  }

  // An edge extension: beyond the row the surface keeps the edge column's parallax.
  auto paint_extension = [&](int column, int begin, int end) {
    const float p = parallax[column];
    if (may_clip && f.s * p > f.key_near) return;
    for (int t = begin; t < end; ++t) xs[t] = extension_x(f, t, p);
  };
  auto paint_segment = [&](int j, int begin, int end) {
    const float p0 = parallax[j];
    const float p1 = parallax[j + 1];
    const float length = 1.0f + (p1 - p0);
    for (int t = begin; t < end; ++t) {
      const float frac = segment_frac(f, t, j, p0, length);
      if (may_clip && f.s * madd<Fma>(frac, p1 - p0, p0) > f.key_near) continue;
      xs[t] = static_cast<float>(j) + frac;
    }
  };
  if (f.s < 0.0f) sweep_in_order<true>(f, parallax, paint_extension, paint_segment);
  else sweep_in_order<false>(f, parallax, paint_extension, paint_segment);

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

}  // namespace
}  // namespace reproject::detail
