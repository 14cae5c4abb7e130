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

// Secant refinement of a bracket: g(x_front) > 0, g(x_behind) <= 0.
float refine(const Frame& f, const float* parallax, float target, float x_front, float gap_front,
             float x_behind, float gap_behind) {
  float x = intersect(x_front, gap_front, x_behind, gap_behind);
  int last_side = 0;
  for (int iteration = 0; iteration < kSecantIterations; ++iteration) {
    const float gap = ray_gap(f, target, x, parallax_at(parallax, x));
    if (gap > 0.0f) {
      x_front = x;
      gap_front = gap;
      if (last_side > 0) gap_behind *= 0.5f;  // Illinois: the other end has not moved twice
      last_side = 1;
    } else {
      x_behind = x;
      gap_behind = gap;
      if (last_side < 0) gap_front *= 0.5f;
      last_side = -1;
    }
    const float next = intersect(x_front, gap_front, x_behind, gap_behind);
    const bool converged = std::fabs(next - x) <= kSecantTolerance;
    x = next;
    if (converged) break;
  }
  return x;
}

}  // namespace

void search_row_secant(const Frame& f, RowScratch& scratch) {
  const float* parallax = scratch.parallax;
  const int direction = f.s > 0.0f ? 1 : -1;
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
    const float step = (p_end - p_start) / static_cast<float>(f.secant_max_steps);

    for (int t = t_begin; t < t_end; ++t) {
      const float target = static_cast<float>(t + f.guard);
      const float x_start = target - p_start;
      const float x_end = target - p_end;
      float x_prev = x_start;
      float gap_prev = ray_gap(f, target, x_start, parallax_at(parallax, x_start));
      scratch.clipped[t] = gap_prev < 0.0f && starts_at_near_end;
      if (gap_prev <= 0.0f) {
        scratch.source_x[t] = x_start;
        continue;
      }
      float x = x_end;
      bool found = false;
      if (column_steps) {
        const int first = direction < 0 ? static_cast<int>(std::ceil(x_start)) - 1 : static_cast<int>(std::floor(x_start)) + 1;
        const int end = direction < 0 ? static_cast<int>(std::floor(x_end)) : static_cast<int>(std::ceil(x_end));
        for (int j = first; !found && (direction < 0 ? j > end : j < end); j += direction) {
          const float column = static_cast<float>(j);
          const float gap = ray_gap(f, target, column, parallax[j]);
          if (gap <= 0.0f) {
            x = intersect(x_prev, gap_prev, column, gap);
            found = true;
          }
          x_prev = column;
          gap_prev = gap;
        }
        if (!found) {
          const float gap = ray_gap(f, target, x_end, parallax_at(parallax, x_end));
          if (gap <= 0.0f) x = intersect(x_prev, gap_prev, x_end, gap);
        }
      } else {
        for (int k = 1; !found && k <= f.secant_max_steps; ++k) {
          const float ray_parallax = k == f.secant_max_steps ? p_end : std::fma(static_cast<float>(k), step, p_start);
          const float x_k = target - ray_parallax;
          const float gap = ray_gap(f, target, x_k, parallax_at(parallax, x_k));
          if (gap <= 0.0f) {
            x = refine(f, parallax, target, x_prev, gap_prev, x_k, gap);
            found = true;
          }
          x_prev = x_k;
          gap_prev = gap;
        }
      }
      scratch.source_x[t] = x;
    }
  }
}

}  // namespace detail
}  // namespace reproject
