// `secant`'s shared pieces: the per-row block table and the per-tile ray limits, used alike by
// the scalar reference (secant.cpp) and its SIMD twin.
#pragma once

#include "kernels/frame.hpp"

namespace reproject {
namespace detail {

constexpr int kSecantTile = 16;   // target pixels that share one step plan, whatever the SIMD width
constexpr int kSecantBlock = 8;   // source columns per entry of the min/max table
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

inline namespace REPROJECT_SCALAR_COPY {  // compiled with each scalar copy (frame.hpp)

// Per block of kSecantBlock source columns, the lowest and highest key s * p.
void build_block_table(const Frame& f, RowScratch& scratch);

TileRay tile_ray(const Frame& f, const RowScratch& scratch, int tile_begin);

// Secant refinement (Illinois) of a bracket in offsets from target column t': g(o_front) > 0,
// g(o_behind) <= 0; returns the crossing's offset to kSecantTolerance.
template <class Fma>
float secant_refine(const Frame& f, const float* parallax, int target, float o_front, float gap_front,
                    float o_behind, float gap_behind);

}  // inline namespace REPROJECT_SCALAR_COPY
}  // namespace detail
}  // namespace reproject
