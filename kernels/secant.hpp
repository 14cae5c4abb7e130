// `secant`'s shared pieces: the per-row block table and the per-tile ray limits, used alike by
// the scalar reference (secant.cpp) and its SIMD twin.
#pragma once

#include "kernels/kernel_table.hpp"

namespace reproject::detail {

constexpr int kSecantTile = 16;   // target pixels that share one step plan, whatever the SIMD width
constexpr int kSecantBlock = 8;   // source columns per entry of the min/max table

// Size of the block table (a sparse table: level l holds, per block b, the bounds over blocks
// [b, b + 2^l)) for a row of `columns` source columns: levels * blocks entries.
inline std::size_t secant_table_size(int columns) {
  const int blocks = (columns + kSecantBlock - 1) / kSecantBlock;
  int levels = 1;
  while ((2 << (levels - 1)) <= blocks) ++levels;
  return static_cast<std::size_t>(levels) * static_cast<std::size_t>(blocks);
}
constexpr int kSecantIterations = 8;
constexpr float kSecantTolerance = 1e-3f;

// The part of the ray that tile [tile_begin, tile_begin + 16) marches: a crossing has a key
// the tile can reach, so the march runs from p_start to p_end only.
struct TileRay {
  float p_start;
  float p_end;
  bool starts_at_near_end;  // p_start == p_near: a ray behind the surface there is clipped
  bool column_steps;        // the span fits secant_max_steps: walk every column (exact)
};

inline namespace REPROJECT_SCALAR_COPY {  // compiled with each scalar copy (kernels/kernel_table.hpp)

// Per block of kSecantBlock source columns, the lowest and highest key s * p, with the coarser
// levels of the sparse table, so that tile_ray() bounds any range of blocks with two lookups
// (its cost stays flat as the separation, and so the range a tile's rays span, grows).
void build_block_table(const Frame& f, RowScratch& scratch);

TileRay tile_ray(const Frame& f, const RowScratch& scratch, int tile_begin);

// Secant refinement (Illinois) of a bracket in offsets from target column t': g(o_front) > 0,
// g(o_behind) <= 0; returns the crossing's offset to kSecantTolerance.
template <class Fma>
float secant_refine(const Frame& f, const float* parallax, int target, float o_front, float gap_front,
                    float o_behind, float gap_behind);

}  // inline namespace REPROJECT_SCALAR_COPY
}  // namespace reproject::detail
