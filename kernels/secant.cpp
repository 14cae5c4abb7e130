// `secant` (DESIGN §6): adaptive. Per tile of 16 target pixels, a per-row table of block
// minima/maxima bounds the parallax that the tile's rays can reach; each ray marches only the
// part of its range where a crossing is possible.
//  * When that span is at most `secant_max_steps` pixels, the march visits every integer column
//    of it (as scanline does) and the crossing is the linear intersection on its segment: exact.
//  * Otherwise it takes `secant_max_steps` equal steps and refines the bracketed crossing with
//    secant steps (Illinois variant, so one stuck end cannot stall it) to 1e-3 px.
// The tile (16 pixels, whatever the SIMD width) is part of the definition, so every
// implementation takes the same steps.
#include <algorithm>
#include <cmath>
#include <limits>

#include "kernels/frame.hpp"

namespace reproject {
namespace detail {
namespace {

constexpr int kSecantTile = 16;
constexpr int kSecantBlock = 8;
constexpr int kSecantIterations = 8;
constexpr float kSecantTolerance = 1e-3f;

void build_block_table(const Frame& f, RowScratch& scratch) {
  const int blocks = (f.source_width + kSecantBlock - 1) / kSecantBlock;
  if (scratch.block_min.size() < static_cast<std::size_t>(blocks)) {
    scratch.block_min.resize(blocks);
    scratch.block_max.resize(blocks);
  }
  for (int k = 0; k < blocks; ++k) {
    const int begin = k * kSecantBlock;
    const int end = std::min(begin + kSecantBlock, f.source_width);
    float lo = std::numeric_limits<float>::infinity();
    float hi = -lo;
    for (int j = begin; j < end; ++j) {
      const float key = f.s * scratch.parallax[j];
      lo = std::min(lo, key);
      hi = std::max(hi, key);
    }
    scratch.block_min[k] = lo;
    scratch.block_max[k] = hi;
  }
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
  for (int k = column_lo / kSecantBlock; column_lo <= column_hi && k <= column_hi / kSecantBlock; ++k) {
    include(scratch.block_min[k]);
    include(scratch.block_max[k]);
  }
  return bounds;
}

// Secant refinement of a bracket in offsets: g(o_front) > 0, g(o_behind) <= 0.
float refine(const Frame& f, const float* parallax, int target, float o_front, float gap_front, float o_behind,
             float gap_behind) {
  float offset = intersect(o_front, gap_front, o_behind, gap_behind);
  int last_side = 0;
  for (int iteration = 0; iteration < kSecantIterations; ++iteration) {
    const float gap = gap_at_offset(f, offset, parallax_at_offset(parallax, target, offset));
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
    const float next = intersect(o_front, gap_front, o_behind, gap_behind);
    const bool converged = std::fabs(next - offset) <= kSecantTolerance;
    offset = next;
    if (converged) break;
  }
  return offset;
}

// The fixed-step march of a span wider than secant_max_steps, then refinement.
float march_steps(const Frame& f, const float* parallax, int target, float p_start, float gap_start, float p_end) {
  const float step = (p_end - p_start) / static_cast<float>(f.secant_max_steps);
  float o_prev = -p_start;
  float gap_prev = gap_start;
  for (int k = 1; k <= f.secant_max_steps; ++k) {
    const float offset = -(k == f.secant_max_steps ? p_end : std::fma(static_cast<float>(k), step, p_start));
    const float gap = gap_at_offset(f, offset, parallax_at_offset(parallax, target, offset));
    if (gap <= 0.0f) return refine(f, parallax, target, o_prev, gap_prev, offset, gap);
    o_prev = offset;
    gap_prev = gap;
  }
  return -p_end;
}

}  // namespace

void search_row_secant(const Frame& f, RowScratch& scratch) {
  const float* parallax = scratch.parallax;
  build_block_table(f, scratch);

  for (int t_begin = 0; t_begin < f.target_width; t_begin += kSecantTile) {
    const int t_end = std::min(t_begin + kSecantTile, f.target_width);
    const KeyBounds reach = reachable_keys(f, scratch, t_begin, t_end);
    // The ray's keys run from key_near down to key_far; a crossing has a reachable key.
    const float key_start = std::min(f.key_near, reach.highest);
    const float key_end = std::min(std::max(f.key_far, reach.lowest), key_start);
    const float p_start = f.s * key_start;
    const float p_end = f.s * key_end;
    const bool starts_at_near_end = key_start == f.key_near;
    const bool column_steps = key_start - key_end <= static_cast<float>(f.secant_max_steps);

    for (int t = t_begin; t < t_end; ++t) {
      const int target = t + f.guard;
      const float o_start = -p_start;
      const float gap_start = gap_at_offset(f, o_start, parallax_at_offset(parallax, target, o_start));
      scratch.clipped[t] = gap_start < 0.0f && starts_at_near_end;
      float offset = o_start;  // behind or on at the start
      if (gap_start > 0.0f) {
        offset = column_steps ? march_columns(f, parallax, target, o_start, gap_start, -p_end)
                              : march_steps(f, parallax, target, p_start, gap_start, p_end);
      }
      scratch.source_x[t] = static_cast<float>(target) + offset;
    }
  }
}

}  // namespace detail
}  // namespace reproject
