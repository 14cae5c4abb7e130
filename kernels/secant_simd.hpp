// SIMD twin of kernels/secant.cpp (`secant`).
#pragma once

#include "kernels/secant.hpp"
#include "kernels/search_simd.hpp"

namespace reproject::detail {
namespace {  // one copy per arch TU (kernels/fma.hpp)

// Scalar twin: search_row_secant.

template <class Arch, class Fma>
void simd_secant(const Frame& f, RowScratch& scratch) {
  REPROJECT_LANE_TYPES(Arch);
  static_assert(kSecantTile % L == 0, "a tile holds whole vectors");
  const float* parallax = scratch.parallax;
  const F s(f.s), zero(0.0f), lanes = lane_offsets<Arch>();
  build_block_table(f, scratch);
  int tile = 0;
  for (; tile + kSecantTile <= f.target_width; tile += kSecantTile) {
    const TileRay ray = tile_ray(f, scratch, tile);
    const float o_start = -ray.p_start;
    const float o_end = -ray.p_end;
    const float step = (ray.p_end - ray.p_start) / static_cast<float>(f.secant_max_steps);
    for (int t = tile; t < tile + kSecantTile; t += L) {
      const int target0 = t + f.guard;
      const F gap_start = s * (F(-o_start) - parallax_at_offset_v<Arch, Fma>(parallax, target0, o_start));
      const B behind_or_on = gap_start <= zero;
      F offset(o_start);
      if (!xsimd::all(behind_or_on)) {
        if (ray.column_steps) {
          offset = simd_march_columns<Arch, Fma>(f, parallax, target0, o_start, gap_start, behind_or_on, offset, o_end);
        } else {
          // Fixed steps (lane-invariant offsets: contiguous loads); each bracket is refined per
          // lane by the scalar reference's own secant iteration.
          B done = behind_or_on;
          F gap_prev = gap_start;
          float o_prev = o_start;
          alignas(64) float front[L], behind[L], out[L];
          offset.store_aligned(out);
          for (int k = 1; k <= f.secant_max_steps && !xsimd::all(done); ++k) {
            const float o_k = -(k == f.secant_max_steps ? ray.p_end : madd<Fma>(static_cast<float>(k), step, ray.p_start));
            const F gap = s * (F(-o_k) - parallax_at_offset_v<Arch, Fma>(parallax, target0, o_k));
            const B hit = (gap <= zero) & ~done;
            if (xsimd::any(hit)) {
              alignas(64) float hit_lane[L];
              xsimd::select(hit, F(1.0f), zero).store_aligned(hit_lane);
              gap_prev.store_aligned(front);
              gap.store_aligned(behind);
              for (int i = 0; i < L; ++i) {
                if (hit_lane[i] != 0.0f) out[i] = secant_refine<Fma>(f, parallax, target0 + i, o_prev, front[i], o_k, behind[i]);
              }
              done = done | hit;
            }
            o_prev = o_k;
            gap_prev = gap;
          }
          offset = xsimd::select(done, F::load_aligned(out), F(o_end));
        }
      }
      (F(static_cast<float>(target0)) + lanes + offset).store_unaligned(scratch.source_x.data() + t);
      store_flags<Arch>((gap_start < zero) & B(ray.starts_at_near_end), scratch.clipped.data() + t);
    }
  }
  search_row_secant<Fma>(f, scratch, tile, f.target_width);
}

}  // namespace
}  // namespace reproject::detail
