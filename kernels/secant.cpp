// `secant` (DESIGN §6): adaptive. Per tile of 16 target pixels, a per-row table of block
// minima/maxima bounds the parallax that the tile's rays can reach; each ray marches only the
// part of its range where a crossing is possible.
//  * When that span is at most `secant_max_steps` pixels, the march visits every integer column
//    of it (as scanline does) and the crossing is the linear intersection on its segment: exact.
//  * Otherwise it takes `secant_max_steps` equal steps and refines the bracketed crossing with
//    secant steps (Illinois variant, so one stuck end cannot stall it) to 1e-3 px.
// The tile (16 pixels, whatever the SIMD width) is part of the definition, so every
// implementation takes the same steps.
// Its SIMD twin: kernels/secant_simd.hpp.
#include <algorithm>
#include <cmath>
#include <limits>
#if defined(_MSC_VER) && !defined(__clang__)
#include <intrin.h>  // _BitScanReverse
#endif

#include "kernels/search.hpp"
#include "kernels/secant.hpp"

namespace reproject::detail {
inline namespace REPROJECT_SCALAR_COPY {  // compiled twice (kernels/kernel_table.hpp)

void build_block_table(const Frame& f, RowScratch& scratch) {
  const int blocks = (f.source_width + kSecantBlock - 1) / kSecantBlock;
  // prepare_scratch sized the table for this width before any row ran.
  float* lowest = scratch.block_min.data();
  float* highest = scratch.block_max.data();
  for (int k = 0; k < blocks; ++k) {
    // A whole block has a fixed trip count, which the compiler unrolls (the last may be partial).
    const int begin = k * kSecantBlock;
    const int count = std::min(kSecantBlock, f.source_width - begin);
    const float* parallax = scratch.parallax + begin;
    float lo = std::numeric_limits<float>::infinity();
    float hi = -lo;
    if (count == kSecantBlock) {
      for (int j = 0; j < kSecantBlock; ++j) {
        lo = std::min(lo, f.s * parallax[j]);
        hi = std::max(hi, f.s * parallax[j]);
      }
    } else {
      for (int j = 0; j < count; ++j) {
        lo = std::min(lo, f.s * parallax[j]);
        hi = std::max(hi, f.s * parallax[j]);
      }
    }
    lowest[k] = lo;
    highest[k] = hi;
  }
  // Level l, block b: the bounds of blocks [b, b + 2^l) from two halves of level l - 1.
  for (int span = 1; 2 * span <= blocks; span *= 2) {
    const float* lowest_below = lowest;
    const float* highest_below = highest;
    lowest += blocks;
    highest += blocks;
    for (int k = 0; k + 2 * span <= blocks; ++k) {
      lowest[k] = std::min(lowest_below[k], lowest_below[k + span]);
      highest[k] = std::max(highest_below[k], highest_below[k + span]);
    }
  }
}

namespace {

// floor(log2(count)), count >= 1. MSVC has no __builtin_clz.
inline int floor_log2(unsigned count) {
#if defined(_MSC_VER) && !defined(__clang__)
  unsigned long top;
  _BitScanReverse(&top, count);
  return static_cast<int>(top);
#else
  return 31 - __builtin_clz(count);
#endif
}

// Keys [lowest, highest] of the surface over source columns the tile's rays can touch.
struct KeyBounds {
  float lowest;
  float highest;
};
KeyBounds reachable_keys(const Frame& f, const RowScratch& scratch, int t_begin, int t_end) {
  const int last = f.source_width - 1;
  const float x_lo = static_cast<float>(t_begin + f.guard) - std::max(f.p_near, f.p_far);
  const float x_hi = static_cast<float>(t_end - 1 + f.guard) - std::min(f.p_near, f.p_far);
  int column_lo = static_cast<int>(std::floor(x_lo));
  int column_hi = static_cast<int>(std::floor(x_hi)) + 1;
  KeyBounds bounds{std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::infinity()};
  auto include = [&](float key) {
    bounds.lowest = std::min(bounds.lowest, key);
    bounds.highest = std::max(bounds.highest, key);
  };
  if (column_lo < 0) include(f.s * scratch.parallax[0]);  // the edge extensions
  if (column_hi > last) include(f.s * scratch.parallax[last]);
  column_lo = std::max(column_lo, 0);
  column_hi = std::min(column_hi, last);
  if (column_lo <= column_hi) {
    // Blocks [first, last_block] are covered by two (overlapping) runs of 2^level blocks.
    const int blocks = (f.source_width + kSecantBlock - 1) / kSecantBlock;
    const int first = column_lo / kSecantBlock;
    const int last_block = column_hi / kSecantBlock;
    const int level = floor_log2(static_cast<unsigned>(last_block - first + 1));
    const std::size_t row = static_cast<std::size_t>(level) * static_cast<std::size_t>(blocks);
    for (const int k : {first, last_block + 1 - (1 << level)}) {
      include(scratch.block_min[row + k]);
      include(scratch.block_max[row + k]);
    }
  }
  return bounds;
}

}  // namespace

TileRay tile_ray(const Frame& f, const RowScratch& scratch, int tile_begin) {
  const int tile_end = std::min(tile_begin + kSecantTile, f.target_width);
  const KeyBounds reach = reachable_keys(f, scratch, tile_begin, tile_end);
  // The ray's keys run from key_near down to key_far; a crossing has a reachable key.
  const float key_start = std::min(f.key_near, reach.highest);
  const float key_end = std::min(std::max(f.key_far, reach.lowest), key_start);
  TileRay ray;
  ray.p_start = f.s * key_start;
  ray.p_end = f.s * key_end;
  ray.starts_at_near_end = key_start == f.key_near;
  ray.column_steps = key_start - key_end <= static_cast<float>(f.secant_max_steps);
  return ray;
}

template <class Fma>
float secant_refine(const Frame& f, const float* parallax, int target, float o_front, float gap_front, float o_behind,
             float gap_behind) {
  float offset = intersect<Fma>(o_front, gap_front, o_behind, gap_behind);
  int last_side = 0;
  for (int iteration = 0; iteration < kSecantIterations; ++iteration) {
    const float gap = gap_at_offset(f, offset, parallax_at_offset<Fma>(parallax, target, offset));
    if (gap > 0.0f) {
      o_front = offset;
      gap_front = gap;
      if (last_side > 0) gap_behind *= 0.5f;  // Illinois: the other end has not moved twice
      last_side = 1;
    } else {
      o_behind = offset;
      gap_behind = gap;
      if (last_side < 0) gap_front *= 0.5f;
      last_side = -1;
    }
    const float next = intersect<Fma>(o_front, gap_front, o_behind, gap_behind);
    const bool converged = std::fabs(next - offset) <= kSecantTolerance;
    offset = next;
    if (converged) break;
  }
  return offset;
}

template float secant_refine<Fused>(const Frame&, const float*, int, float, float, float, float);
template float secant_refine<Unfused>(const Frame&, const float*, int, float, float, float, float);

namespace {

// The fixed-step march of a span wider than secant_max_steps, then refinement.
template <class Fma>
float march_steps(const Frame& f, const float* parallax, int target, float p_start, float gap_start, float p_end) {
  const float step = (p_end - p_start) / static_cast<float>(f.secant_max_steps);
  float o_prev = -p_start;
  float gap_prev = gap_start;
  for (int k = 1; k <= f.secant_max_steps; ++k) {
    const float offset = -(k == f.secant_max_steps ? p_end : madd<Fma>(static_cast<float>(k), step, p_start));
    const float gap = gap_at_offset(f, offset, parallax_at_offset<Fma>(parallax, target, offset));
    if (gap <= 0.0f) return secant_refine<Fma>(f, parallax, target, o_prev, gap_prev, offset, gap);
    o_prev = offset;
    gap_prev = gap;
  }
  return -p_end;
}

}  // namespace

template <class Fma>
void search_row_secant(const Frame& f, RowScratch& scratch, int t_begin, int t_end) {
  const float* parallax = scratch.parallax;
  if (t_begin == 0) build_block_table(f, scratch);
  TileRay ray{};
  for (int t = t_begin; t < t_end; ++t) {
    if (t == t_begin || t % kSecantTile == 0) ray = tile_ray(f, scratch, t - t % kSecantTile);
    const int target = t + f.guard;
    const float o_start = -ray.p_start;
    const float gap_start = gap_at_offset(f, o_start, parallax_at_offset<Fma>(parallax, target, o_start));
    scratch.clipped[t] = gap_start < 0.0f && ray.starts_at_near_end;
    float offset = o_start;  // behind or on at the start
    if (gap_start > 0.0f) {
      offset = ray.column_steps ? march_columns<Fma>(f, parallax, target, o_start, gap_start, -ray.p_end)
                                : march_steps<Fma>(f, parallax, target, ray.p_start, gap_start, ray.p_end);
    }
    scratch.source_x[t] = static_cast<float>(target) + offset;
  }
}

REPROJECT_INSTANTIATE_SEARCH(search_row_secant);

}  // inline namespace REPROJECT_SCALAR_COPY
}  // namespace reproject::detail
