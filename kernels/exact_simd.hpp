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

// Pass 1 with clipping: the sweep of sweep_row, painting codes with masked stores. `margin` is
// 2^-19 times the row's largest |p| (exact_may_clip): a segment whose nearer endpoint's key plus
// it stays below key_near is nowhere nearer than the limit, wherever the scalar sweep
// interpolates it (frac in [0, 1]): madd(frac, p1 - p0, p0) exceeds the nearer endpoint's key by
// at most 2^-23 (|p0| + |p1|) (one rounding in p1 - p0, one in the madd), which is below 2^-20
// (|p0| + |p1|) <= margin; and the float sum is below key_near only if the exact one is (rounding
// is monotone, key_near is a float). Such segments (nearly all) take plain masked stores; those
// whose farther endpoint's key minus the margin is above key_near are too near everywhere (the
// same bound the other way) and paint nothing; the rest take the scalar sweep's own per-pixel
// test, per lane.
template <class Arch, class Fma, bool Upwards>
void exact_paint_clipping(const Frame& f, const float* parallax, float* owner, float margin) {
  REPROJECT_LANE_TYPES(Arch);
  for (int t = 0; t < f.target_width; t += L) F(kFarDefault).store_unaligned(owner + t);
  // Code `code` onto targets [begin, end).
  auto paint = [&](float code, int begin, int end) {
    const F value(code);
    for (int t = begin; t < end; t += L) store_first_lanes<Arch>(value, owner + t, end - t);
  };
  auto paint_extension = [&](int column, int begin, int end) {
    if (f.s * parallax[column] > f.key_near) return;  // the whole extension is too near
    paint(column == 0 ? kLeftExtension : kRightExtension, begin, end);
  };
  const F lanes = lane_offsets<Arch>(), s(f.s), key_near(f.key_near), guard(static_cast<float>(f.guard));
  auto paint_segment = [&](int j, int begin, int end) {
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
  sweep_in_order<Upwards>(f, parallax, paint_extension, paint_segment);
}

// Pass 1 without clipping: whole-vector stores (see above), each spilling past its span on the
// far side of the sweep (above it upwards, below it downwards).
template <class Arch, bool Upwards>
void exact_paint(const Frame& f, const float* parallax, float* owner) {
  REPROJECT_LANE_TYPES(Arch);
  // Whole vectors from the sweep's near side of [begin, end); nothing when it is empty.
  auto fill = [&](const F& code, int begin, int end) {
    if constexpr (Upwards) {
      for (int t = begin; t < end; t += L) code.store_unaligned(owner + t);
    } else {
      for (int t = end; t > begin; t -= L) code.store_unaligned(owner + t - L);
    }
  };
  auto paint_extension = [&](int column, int begin, int end) {
    fill(F(column == 0 ? kLeftExtension : kRightExtension), begin, end);
  };
  // Every segment, even an empty one (a fold), stores one vector at its near end.
  auto paint_segment = [&](int j, int begin, int end) {
    const F code(static_cast<float>(j));
    if constexpr (Upwards) {
      code.store_unaligned(owner + begin);
      fill(code, begin + L, end);  // a stretched segment
    } else {
      code.store_unaligned(owner + end - L);
      fill(code, begin, end - L);
    }
  };
  sweep_in_order<Upwards>(f, parallax, paint_extension, paint_segment);
}

// The row's nearest key against the near limit (sweep_row's may_clip), with the vector max; and
// exact_paint_clipping's margin, from the row's largest |p|.
template <class Arch>
bool exact_may_clip(const Frame& f, const float* parallax, float* margin) {
  REPROJECT_LANE_TYPES(Arch);
  if (f.near_from_frame) return false;  // the frame's own nearest: nothing is clipped
  const F s(f.s);
  F nearest(f.key_far), largest(0.0f);
  int j = 0;
  for (; j + L <= f.source_width; j += L) {
    const F p = F::load_unaligned(parallax + j);
    nearest = vmax(nearest, s * p);
    largest = vmax(largest, xsimd::abs(p));
  }
  float key = lane_max<Arch>(nearest);
  float magnitude = lane_max<Arch>(largest);
  for (; j < f.source_width; ++j) {
    key = std::max(key, f.s * parallax[j]);
    magnitude = std::max(magnitude, std::fabs(parallax[j]));
  }
  *margin = magnitude * 0x1p-19f;
  return key > f.key_near;  // max is exact: only the order of equal keys differs, not the test
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
  float margin = 0.0f;
  const bool may_clip = exact_may_clip<Arch>(f, parallax, &margin);
  if (!may_clip && f.s < 0.0f) exact_paint<Arch, true>(f, parallax, owner);
  else if (!may_clip) exact_paint<Arch, false>(f, parallax, owner);
  else if (f.s < 0.0f) exact_paint_clipping<Arch, Fma, true>(f, parallax, owner, margin);
  else exact_paint_clipping<Arch, Fma, false>(f, parallax, owner, margin);

  // Pass 2: source x across the lanes, then (with clipping) sweep_row's clipped test.
  const F zero(0.0f), one(1.0f), guard(static_cast<float>(f.guard)), lanes = lane_offsets<Arch>();
  const F left_parallax(parallax[0]), right_parallax(parallax[last]), p_far(f.p_far), p_near(f.p_near), s(f.s);
  float* xs = scratch.source_x.data();
  float* clipped = scratch.clipped.data();
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
    if (may_clip) {
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
