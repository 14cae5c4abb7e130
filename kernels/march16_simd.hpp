// SIMD twin of kernels/march16.cpp (`march16`).
#pragma once

#include <limits>
#include <type_traits>

#include "kernels/search_simd.hpp"

namespace reproject::detail {
namespace {  // one copy per arch TU (kernels/fma.hpp)

// Scalar twin: search_row_march16.
// The samples' offsets and parallaxes are the same for every pixel, so they are tabled once per
// row. Samples run in chunks: inside a chunk, backwards and branch-free (the last select is the
// first hit, as in the scalar early exit); between chunks, an early exit once every lane has hit.

constexpr int kMarchChunk = 16;

template <class Arch, class Fma, bool Positive>
void simd_march16_row(const Frame& f, RowScratch& scratch, const int* sample_offset, const float* sample_parallax) {
  REPROJECT_LANE_TYPES(Arch);
  // Locals, not f's or scratch's fields: the stores below go through float pointers, which may
  // alias them, so fields would be reloaded after each store.
  const int width = f.target_width;
  const int samples = f.march_steps + 1;
  const float* row0 = scratch.parallax + f.guard;  // lane t's samples: row0 + t + sample_offset[k]
  float* source_x = scratch.source_x.data();
  float* clipped = scratch.clipped.data();
  const F key_near(f.key_near), s(f.s), p_far(f.p_far), step(static_cast<float>(L));
  const F nan(std::numeric_limits<float>::quiet_NaN());
  // s * surface >= s * p without the multiplies (s is +-1, so they are exact anyway).
  auto on_or_behind = [](const F& surface, float ray_parallax) {
    if constexpr (Positive) return surface >= F(ray_parallax);
    else return surface <= F(ray_parallax);
  };
  // The parallax of the first of samples [first, first + count) on or behind the surface, NaN if
  // none (decoded parallax is never NaN): backwards and branch-free, so the last select is the
  // first hit, as in the scalar early exit. A whole chunk has a constant count: unrolled.
  auto chunk = [&](const float* row, int first, auto count) {
    const int* offset = sample_offset + first;
    const float* ray = sample_parallax + first;
    F hit = nan;
    for (int k = count - 1; k >= 0; --k) {
      // The k-th sample of every lane is at the same offset: one contiguous load.
      const F surface = F::load_unaligned(row + offset[k]);
      hit = xsimd::select(on_or_behind(surface, ray[k]), surface, hit);
    }
    return hit;
  };
  F target = F(static_cast<float>(f.guard)) + lane_offsets<Arch>();  // t + guard: exact small integers
  int t = 0;
  for (; t + L <= width; t += L) {
    const float* row = row0 + t;
    store_flags<Arch>(s * F::load_unaligned(row + sample_offset[0]) > key_near, clipped + t);
    // The parallax of the first sample on or behind the surface; no hit: the far end.
    F hit_parallax = p_far;
    B done(false);
    for (int first = 0; first < samples; first += kMarchChunk) {
      const F chunk_parallax = first + kMarchChunk <= samples
                                   ? chunk(row, first, std::integral_constant<int, kMarchChunk>{})
                                   : chunk(row, first, samples - first);
      const B chunk_hit = chunk_parallax == chunk_parallax;
      hit_parallax = xsimd::select(chunk_hit & ~done, chunk_parallax, hit_parallax);
      done = done | chunk_hit;
      if (xsimd::all(done)) break;
    }
    (target - hit_parallax).store_unaligned(source_x + t);
    target = target + step;
  }
  search_row_march16<Fma>(f, scratch, t, width);
}

template <class Arch, class Fma>
void simd_march16(const Frame& f, RowScratch& scratch) {
  // At most 1025 samples (Options::march_steps <= 1024).
  int sample_offset[1025];
  float sample_parallax[1025];
  for (int k = 0; k <= f.march_steps; ++k) {
    sample_parallax[k] = madd<Fma>(static_cast<float>(k), f.march_step, f.p_near);
    sample_offset[k] = point_offset(sample_parallax[k]);
  }
  if (f.s > 0.0f) simd_march16_row<Arch, Fma, true>(f, scratch, sample_offset, sample_parallax);
  else simd_march16_row<Arch, Fma, false>(f, scratch, sample_offset, sample_parallax);
}

}  // namespace
}  // namespace reproject::detail
