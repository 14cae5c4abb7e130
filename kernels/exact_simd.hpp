// SIMD twin of kernels/exact.cpp (`exact`): the sweep of kernels/exact.hpp.
#pragma once

#include <cmath>

#include "kernels/exact.hpp"
#include "kernels/simd.hpp"

namespace reproject::detail {
namespace {  // one copy per arch TU (kernels/fma.hpp)

// Scalar twin: sweep_row.
// Two passes. The sweep itself (sequential: later segments occlude earlier ones) records only
// which segment or extension paints each target pixel (its code, below). Then each pixel's
// source x is computed from its code across the lanes, with the scalar sweep's arithmetic.
//
// Pass 1 has two forms. Without clipping (the row's surface is nowhere nearer than the near
// limit: always so with the frame's own limit) every segment stores whole vectors without a
// branch: a store's spill lies at or beyond the next segment's start in sweep order, and the
// rest of the sweep always paints it again. With clipping, the scalar sweep skips the pixels a
// segment paints nearer than the limit, so the previous painter must survive there: stores are
// masked to the segment's span and to the pixels that are not too near.

constexpr float kLeftExtension = -1.0f;  // codes of the two edge extensions
constexpr float kRightExtension = -2.0f;
constexpr float kFarDefault = -3.0f;  // with clipping: not painted, x = t' - p_far (the scalar default)

// Source x of target pixel t painted by code `owner` (the scalar sweep's arithmetic), for the tail.
inline float exact_x_from_owner(const Frame& f, const float* parallax, int t, float owner) {
  if (owner == kFarDefault) return static_cast<float>(t) + static_cast<float>(f.guard) - f.p_far;
  if (owner < 0.0f) return extension_x(f, t, parallax[owner == kLeftExtension ? 0 : f.source_width - 1]);
  const int j = static_cast<int>(owner);
  const float p0 = parallax[j];
  return owner + segment_frac(f, t, j, p0, 1.0f + (parallax[j + 1] - p0));
}

// segment_frac across the lanes: `target` is t + guard (t' as a float, exact), `j` the segment.
template <class Arch>
xsimd::batch<float, Arch> segment_frac_v(const xsimd::batch<float, Arch>& target, const xsimd::batch<float, Arch>& j,
                                         const xsimd::batch<float, Arch>& p0, const xsimd::batch<float, Arch>& length) {
  using F = xsimd::batch<float, Arch>;
  const F zero(0.0f), one(1.0f);
  const F ratio = vdiv(target - j - p0, length);
  return xsimd::select(ratio < zero, zero, xsimd::select(one < ratio, one, ratio));  // std::clamp
}

// Pass 1 without clipping: whole-vector stores, each spilling past its span on the far side of
// the sweep (above it upwards, below it downwards), where the rest of the sweep paints again.
template <class Arch, bool Upwards>
struct WholeVectorPaint {
  using F = typename Lanes<Arch>::F;
  static constexpr int L = Lanes<Arch>::size;
  float* owner;

  // Whole vectors from the sweep's near side of [begin, end); nothing when it is empty.
  void fill(const F& code, int begin, int end) const {
    if constexpr (Upwards) {
      for (int t = begin; t < end; t += L) code.store_unaligned(owner + t);
    } else {
      for (int t = end; t > begin; t -= L) code.store_unaligned(owner + t - L);
    }
  }
  void extension(int column, int begin, int end) const {
    fill(F(column == 0 ? kLeftExtension : kRightExtension), begin, end);
  }
  // Every segment, even an empty one (a fold), stores one vector at its near end.
  void segment(int j, int begin, int end) const {
    const F code(static_cast<float>(j));
    if constexpr (Upwards) {
      code.store_unaligned(owner + begin);
      fill(code, begin + L, end);  // a stretched segment
    } else {
      code.store_unaligned(owner + end - L);
      fill(code, begin, end - L);
    }
  }
};

template <class Arch, bool Upwards>
void exact_paint(const Frame& f, const float* parallax, float* owner) {
  const WholeVectorPaint<Arch, Upwards> paint{owner};
  sweep_in_order<Upwards>(
      f, parallax, [&](int column, int begin, int end) { paint.extension(column, begin, end); },
      [&](int j, int begin, int end) { paint.segment(j, begin, end); });
}

// The clipping sweep's margins, from the frame: every decoded |p| is at most L = Ws + 2
// (kernels/decode.cpp clamps it there).
//  * `segment`: a segment whose nearer endpoint's key plus it stays below key_near is nowhere
//    nearer than the limit, wherever the scalar sweep interpolates it (frac in [0, 1]):
//    madd(frac, p1 - p0, p0) exceeds the nearer endpoint's key by at most 2^-23 (|p0| + |p1|)
//    (one rounding in p1 - p0, one in the madd; two more without FMA stay below 2^-21 (|p0| +
//    |p1|)), which is below 2^-19 L; and the float sum is below key_near only if the exact one is
//    (rounding is monotone, key_near is a float). The same bound the other way: a segment whose
//    farther endpoint's key minus it is above key_near is too near everywhere.
//  * `column`: also covers pass 2's test of where a ray starts, x_near = t' - p_near, against the
//    surface there: x_near and (t' - x_near) are each within 2^-24 (Ws + 2 L) of their exact
//    values, so a ray can start behind the surface only where an endpoint's key exceeds key_near -
//    segment - 2^-23 (Ws + 2 L); 2^-21 (Ws + 2 L) is four times that.
struct ClipMargins {
  float segment;
  float column;
};
inline ClipMargins clip_margins(const Frame& f) {
  const float segment = 0x1p-19f * f.limit;
  return ClipMargins{segment, segment + 0x1p-21f * (static_cast<float>(f.source_width) + 2.0f * f.limit)};
}

// Columns [lo, hi] of a row whose key may reach the near limit: every other column c has
// s p[c] + margins.column < key_near (up to the rounding of that bound, see exact_may_clip), so no
// segment between two of them and no extension at one is too near, nor does a ray start behind
// the surface between two of them (simd_exact's pass 2).
struct NearColumns {
  int lo;
  int hi;
};

// Pass 1 with clipping: the sweep of sweep_row, where a surface nearer than the limit paints
// nothing. Segments and extensions that touch `near` columns (the middle of the sweep) take
// masked stores of their span: nearly all of those are plain (nowhere too near, by the segment
// margin), some too near everywhere (nothing painted), the rest take the scalar sweep's own
// per-pixel test, per lane. The others are plain and take exact_paint's whole-vector stores
// where their spill is painted again: after the middle, always (the rest of the sweep paints
// every target from the next span on); before it, when the spill stays short of the middle's
// first span, because the spans in between cover every target from the next span to there (they
// are consecutive intervals).
template <class Arch, class Fma, bool Upwards>
void exact_paint_clipping(const Frame& f, const float* parallax, float* owner, float margin, NearColumns near) {
  REPROJECT_LANE_TYPES(Arch);
  const WholeVectorPaint<Arch, Upwards> whole{owner};
  const int last = f.source_width - 1;
  const int width = f.target_width;
  for (int t = 0; t < width; t += L) F(kFarDefault).store_unaligned(owner + t);
  // Where the middle's first span (in sweep order) begins upwards, ends downwards: whole-vector
  // stores before the middle must stay short of it. A span's stores reach at most L targets past
  // its far end (or past its start when it is empty).
  const int middle_start = Upwards ? (near.lo >= 1 ? reach_of<true>(parallax, near.lo - 1, f.guard, width) : 0)
                                   : (near.hi < last ? reach_of<false>(parallax, near.hi + 1, f.guard, width) : width);
  auto whole_stores_fit = [&](int begin, int end) {
    if constexpr (Upwards) return std::max(begin, end) + L <= middle_start;
    else return std::min(begin, end) - L >= middle_start;
  };
  // Code `code` onto targets [begin, end).
  auto paint = [&](float code, int begin, int end) {
    const F value(code);
    for (int t = begin; t < end; t += L) store_first_lanes<Arch>(value, owner + t, end - t);
  };
  auto paint_extension = [&](int column, int begin, int end) {
    if (column < near.lo || column > near.hi) {  // plain: after the middle, or before it and short of it
      const bool after = Upwards == (column == last);
      if (after || whole_stores_fit(begin, end)) return whole.extension(column, begin, end);
    } else if (f.s * parallax[column] > f.key_near) {
      return;  // the whole extension is too near
    }
    paint(column == 0 ? kLeftExtension : kRightExtension, begin, end);
  };
  const F lanes = lane_offsets<Arch>(), s(f.s), key_near(f.key_near), guard(static_cast<float>(f.guard));
  // Plain segments (neither end is near) before and after the middle.
  auto paint_before = [&](int j, int begin, int end) {
    if (whole_stores_fit(begin, end)) return whole.segment(j, begin, end);
    paint(static_cast<float>(j), begin, end);
  };
  auto paint_after = [&](int j, int begin, int end) { whole.segment(j, begin, end); };
  auto paint_middle = [&](int j, int begin, int end) {
    if (begin >= end) return;  // a fold
    const float p0 = parallax[j];
    const float p1 = parallax[j + 1];
    const float k0 = f.s * p0, k1 = f.s * p1;
    if (std::max(k0, k1) + margin < f.key_near) return paint(static_cast<float>(j), begin, end);
    if (std::min(k0, k1) - margin > f.key_near) return;  // nearer everywhere: every pixel skipped
    // The scalar sweep's test, per lane; the lanes it skips keep their code.
    const F p0_v(p0), dp(p1 - p0), length(1.0f + (p1 - p0)), j_v(static_cast<float>(j)), end_v(static_cast<float>(end));
    for (int t = begin; t < end; t += L) {
      const F target = F(static_cast<float>(t)) + lanes;  // exact: small integers
      const F frac = segment_frac_v<Arch>(target + guard, j_v, p0_v, length);
      const B write = (target < end_v) & ~(s * vmadd<Fma>(frac, dp, p0_v) > key_near);
      xsimd::select(write, j_v, F::load_unaligned(owner + t)).store_unaligned(owner + t);
    }
  };
  // The segments with a near end: [near.lo - 1, near.hi] within the row's.
  sweep_in_order<Upwards>(f, parallax, paint_extension, paint_before, paint_middle, paint_after, std::max(near.lo - 1, 0),
                          std::min(near.hi, last - 1));
}

// Whether the row clips (sweep_row's may_clip: a column's key is beyond key_near), and if so its
// near columns: those with s p >= key_near - margins.column (rounded: still more than the margin
// of NearColumns, whose bound has four times what it needs). Every column beyond key_near is near,
// so only rows with near columns are searched for one.
template <class Arch>
bool exact_may_clip(const Frame& f, const float* parallax, float column_margin, NearColumns* near) {
  REPROJECT_LANE_TYPES(Arch);
  if (f.near_from_frame) return false;  // the frame's own nearest: nothing is clipped
  const int width = f.source_width;
  const float near_key = f.key_near - column_margin;
  auto near_at = [&](int c) { return f.s * parallax[c] >= near_key; };
  const F s(f.s), near_key_v(near_key);
  int first = -1, last = -1;  // the first and last vectors with a near column
  int j = 0;
  for (; j + L <= width; j += L) {
    if (xsimd::any(s * F::load_unaligned(parallax + j) >= near_key_v)) {
      if (first < 0) first = j;
      last = j;
    }
  }
  int hi = width - 1;
  while (hi >= j && !near_at(hi)) --hi;  // the tail
  if (hi < j) {
    if (last < 0) return false;  // no near column
    hi = last + L - 1;
    while (!near_at(hi)) --hi;
  }
  int lo = first >= 0 ? first : j;
  while (!near_at(lo)) ++lo;
  *near = NearColumns{lo, hi};
  for (int c = lo; c <= hi; ++c)
    if (f.s * parallax[c] > f.key_near) return true;
  return false;
}

template <class Arch, class Fma>
void simd_exact(const Frame& f, RowScratch& scratch) {
  REPROJECT_LANE_TYPES(Arch);
  const int last = f.source_width - 1;
  const int width = f.target_width;
  if (last < 1 || width < L) {
    sweep_row<Fma>(f, scratch);
    return;
  }
  const float* parallax = scratch.parallax;
  float* owner = scratch.owner_storage.data() + kOwnerPad;
  const ClipMargins margins = clip_margins(f);
  NearColumns near{0, -1};
  const bool may_clip = exact_may_clip<Arch>(f, parallax, margins.column, &near);
  if (!may_clip && f.s < 0.0f) exact_paint<Arch, true>(f, parallax, owner);
  else if (!may_clip) exact_paint<Arch, false>(f, parallax, owner);
  else if (f.s < 0.0f) exact_paint_clipping<Arch, Fma, true>(f, parallax, owner, margins.segment, near);
  else exact_paint_clipping<Arch, Fma, false>(f, parallax, owner, margins.segment, near);

  // Pass 2: source x across the lanes, then (with clipping) sweep_row's clipped test.
  const F zero(0.0f), one(1.0f), guard(static_cast<float>(f.guard)), lanes = lane_offsets<Arch>();
  const F left_parallax(parallax[0]), right_parallax(parallax[last]), p_far(f.p_far), p_near(f.p_near), s(f.s);
  float* xs = scratch.source_x.data();
  float* clipped = scratch.clipped.data();
  // Whether the rays of targets [t, t + L) start between columns of which one may be near: their
  // x_near grow with t, and the padding repeats the edge columns.
  auto ray_starts_may_be_near = [&](int t) {
    const float first = std::floor(static_cast<float>(t + f.guard) - f.p_near);
    const float after = std::floor(static_cast<float>(t + L - 1 + f.guard) - f.p_near) + 1.0f;
    const float lo = std::clamp(first, 0.0f, static_cast<float>(last));
    const float hi = std::clamp(after, 0.0f, static_cast<float>(last));
    return !(hi < static_cast<float>(near.lo) || lo > static_cast<float>(near.hi));
  };
  int t = 0;
  for (; t + L <= width; t += L) {
    const F code = F::load_unaligned(owner + t);
    const B extension = code < zero;
    const F j = xsimd::select(extension, zero, code);
    const F target = (F(static_cast<float>(t)) + lanes) + guard;  // t + guard, as in the scalar sweep
    F p0, p1;
    ColumnFetch<Arch>(j, j + one, f.source_width).fetch(parallax, p0, p1);
    const F frac = segment_frac_v<Arch>(target, j, p0, one + (p1 - p0));
    const F edge_parallax = xsimd::select(code == F(kLeftExtension), left_parallax,
                                          xsimd::select(code == F(kRightExtension), right_parallax, p_far));
    F x = xsimd::select(extension, target - edge_parallax, j + frac);
    B clip(false);
    if (may_clip && ray_starts_may_be_near(t)) {
      // Rays that start behind the surface at the near end: x_near, clipped (parallax_at<Fma>).
      const F x_near = target - p_near;
      const F column = vfloor(x_near);
      F q0, q1;
      ColumnFetch<Arch>(column, column + one, f.source_width + f.pad_right).fetch(parallax, q0, q1);
      clip = s * ((target - x_near) - vmadd<Fma>(x_near - column, q1 - q0, q0)) < zero;
      x = xsimd::select(clip, x_near, x);
    }
    x.store_unaligned(xs + t);
    store_flags<Arch>(clip, clipped + t);
  }
  for (; t < width; ++t) {
    xs[t] = exact_x_from_owner(f, parallax, t, owner[t]);
    clipped[t] = 0.0f;
    if (may_clip) {
      const float target = static_cast<float>(t) + static_cast<float>(f.guard);
      const float x_near = target - f.p_near;
      if (f.s * ((target - x_near) - parallax_at<Fma>(parallax, x_near)) < 0.0f) {
        xs[t] = x_near;
        clipped[t] = 1.0f;
      }
    }
  }
}

}  // namespace
}  // namespace reproject::detail
