// SIMD twin of kernels/exact.cpp (`exact`): the sweep of kernels/exact_sweep.hpp.
#pragma once

#include "kernels/exact_sweep.hpp"
#include "kernels/simd.hpp"

namespace reproject {
namespace detail {
namespace {  // one copy per arch TU (kernels/simd.hpp)

// ---- exact (scalar twin: sweep_row) ----
// Two passes. The sweep itself (sequential: later segments occlude earlier ones) records only
// which segment paints each target pixel, with whole-vector stores: a segment's store may spill
// past its end (behind it, in sweep order), but every pixel's last write comes from the segment
// that really covers it, so the spills are always painted over. Then each pixel's source x is
// computed from its segment across the lanes, with the scalar sweep's arithmetic. The rare
// clipping case (a near limit tighter than the data) runs the scalar sweep.

constexpr int kLeftExtension = -1;   // owner codes of the two edge extensions
constexpr int kRightExtension = -2;

// Source x of target pixel t painted by `owner` (the scalar sweep's arithmetic), for the tail.
inline float exact_x_from_owner(const Frame& f, const float* parallax, int t, int owner) {
  if (owner < 0) return extension_x(f, t, parallax[owner == kLeftExtension ? 0 : f.source_width - 1]);
  const float p0 = parallax[owner];
  return static_cast<float>(owner) + segment_frac(f, t, owner, p0, 1.0f + (parallax[owner + 1] - p0));
}

template <class Arch, class Fma>
void simd_exact(const Frame& f, RowScratch& scratch) {
  using F = typename Lanes<Arch>::F;
  using I = typename Lanes<Arch>::I;
  using B = typename Lanes<Arch>::B;
  constexpr int L = Lanes<Arch>::size;
  const int last = f.source_width - 1;
  const int width = f.target_width;
  if (!f.near_from_frame || last < 1 || width < L) {
    sweep_row<Fma>(f, scratch);
    return;
  }
  const float* parallax = scratch.parallax;
  std::int32_t* owner = scratch.owner_storage.data() + kOwnerPad;

  // Pass 1: the sweep of exact_sweep.hpp, painting segment numbers. Every segment, even an empty
  // one (a fold), stores one whole vector at its start without a branch: a store's spill covers
  // pixels at or beyond the next segment's start (in sweep order), which the rest of the sweep
  // always paints again (the reaches from there run on to the far extension).
  const I left_code(kLeftExtension), right_code(kRightExtension);
  if (f.s < 0.0f) {  // columns upwards; spills land above a segment
    auto reach = [&](int column) {
      return std::clamp(first_target_reached<true>(column, parallax[column]) - f.guard, 0, width);
    };
    int begin = reach(0);
    for (int t = 0; t < begin; t += L) left_code.store_unaligned(owner + t);
    for (int j = 0; j < last; ++j) {
      const int end = reach(j + 1);
      const I code(j);
      code.store_unaligned(owner + begin);
      for (int t = begin + L; t < end; t += L) code.store_unaligned(owner + t);  // a stretched segment
      begin = end;
    }
    for (int t = begin; t < width; t += L) right_code.store_unaligned(owner + t);
  } else {  // columns downwards; spills land below a segment
    auto reach = [&](int column) {
      return std::clamp(first_target_reached<false>(column, parallax[column]) - f.guard, 0, width);
    };
    int end = reach(last);
    for (int t = width; t > end; t -= L) right_code.store_unaligned(owner + t - L);
    for (int j = last - 1; j >= 0; --j) {
      const int begin = reach(j);
      const I code(j);
      code.store_unaligned(owner + end - L);
      for (int t = end - L; t > begin; t -= L) code.store_unaligned(owner + t - L);
      end = begin;
    }
    for (int t = end; t > 0; t -= L) left_code.store_unaligned(owner + t - L);
  }

  // Pass 2: source x across the lanes.
  const F zero(0.0f), one(1.0f), guard(static_cast<float>(f.guard)), lanes = lane_offsets<Arch>();
  const F left_parallax(parallax[0]), right_parallax(parallax[last]);
  float* xs = scratch.source_x.data();
  int t = 0;
  for (; t + L <= width; t += L) {
    const F code = xsimd::to_float(I::load_unaligned(owner + t));
    const B extension = code < zero;
    const F j = xsimd::select(extension, zero, code);
    const F target = F(static_cast<float>(t)) + lanes;  // exact: small integers
    F p0, p1;
    ColumnFetch<Arch>(j, j + one, f.source_width).fetch(parallax, p0, p1);
    const F length = one + (p1 - p0);
    const F ratio = ((target + guard) - j - p0) / length;
    const F frac = xsimd::select(ratio < zero, zero, xsimd::select(one < ratio, one, ratio));  // std::clamp
    const F edge_parallax = xsimd::select(code == F(static_cast<float>(kLeftExtension)), left_parallax, right_parallax);
    xsimd::select(extension, (target + guard) - edge_parallax, j + frac).store_unaligned(xs + t);
    zero.store_unaligned(scratch.clipped.data() + t);
  }
  for (; t < width; ++t) {
    xs[t] = exact_x_from_owner(f, parallax, t, owner[t]);
    scratch.clipped[t] = 0.0f;
  }
}

}  // namespace
}  // namespace detail
}  // namespace reproject
