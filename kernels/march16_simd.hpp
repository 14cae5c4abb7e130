// SIMD twin of kernels/march16.cpp (`march16`).
#pragma once

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
  const float* parallax = scratch.parallax;
  const int samples = f.march_steps + 1;
  const F key_near(f.key_near), s(f.s), lanes = lane_offsets<Arch>();
  // s * surface >= s * p without the multiplies (s is +-1, so they are exact anyway).
  auto on_or_behind = [](const F& surface, float ray_parallax) {
    if constexpr (Positive) return surface >= F(ray_parallax);
    else return surface <= F(ray_parallax);
  };
  int t = 0;
  for (; t + L <= f.target_width; t += L) {
    const int target0 = t + f.guard;
    const float* row = parallax + target0;
    const F target = F(static_cast<float>(target0)) + lanes;
    const F first = F::load_unaligned(row + sample_offset[0]);
    store_flags<Arch>(s * first > key_near, scratch.clipped.data() + t);
    // The parallax of the first sample on or behind the surface; no hit: the far end.
    F hit_parallax(f.p_far);
    B done(false);
    for (int chunk = 0; chunk < samples; chunk += kMarchChunk) {
      // NaN until a sample of the chunk hits (decoded parallax is never NaN).
      F chunk_parallax(std::numeric_limits<float>::quiet_NaN());
      for (int k = std::min(chunk + kMarchChunk, samples) - 1; k >= chunk; --k) {
        // The k-th sample of every lane is at the same offset: one contiguous load.
        const F surface = F::load_unaligned(row + sample_offset[k]);
        chunk_parallax = xsimd::select(on_or_behind(surface, sample_parallax[k]), surface, chunk_parallax);
      }
      const B chunk_hit = chunk_parallax == chunk_parallax;
      hit_parallax = xsimd::select(chunk_hit & ~done, chunk_parallax, hit_parallax);
      done = done | chunk_hit;
      if (xsimd::all(done)) break;
    }
    (target - hit_parallax).store_unaligned(scratch.source_x.data() + t);
  }
  search_row_march16<Fma>(f, scratch, t, f.target_width);
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
