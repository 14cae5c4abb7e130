// Internal: the per-call plan every method shares (DESIGN §3–§6, docs/BEHAVIOUR.md), the per-row
// parallax decode, the resolve stage and the row driver. Not installed.
#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

#include "reproject/reproject.hpp"

namespace reproject {
namespace detail {

// Everything a row needs, computed once per call after validation.
struct Frame {
  SourceView source;
  TargetView target;
  int source_width = 0;  // Ws, guard band included
  int target_width = 0;  // Wt = Ws - 2 guard
  int height = 0;
  int guard = 0;

  // Parallax decode: affine p = fma(decode_scale, d, decode_offset) (b A and a + b B, §4);
  // reciprocal p = fma(b, 1/d, a).
  bool affine = true;
  float decode_scale = 0.0f;
  float decode_offset = 0.0f;
  float a = 0.0f;
  float b = 0.0f;

  // s = sign(b) (-1 when b <= 0): the key s * p grows towards the viewer, and the ray marches
  // in direction s along x (from x_near = t' - p_near to x_far = t' - p_far).
  float s = -1.0f;
  float limit = 0.0f;  // L = Ws + 2: parallax beyond it lands off the row whatever its value
  float p_far = 0.0f;  // a clamped to [-L, L]
  float p_near = 0.0f;
  float key_far = 0.0f;   // s * p_far
  float key_near = 0.0f;  // s * p_near

  float hole_threshold = 1.0f;
  HoleFill hole_fill = HoleFill::background;
  EdgeMode edge = EdgeMode::clamp;
  Method method = Method::exact;
  int march_steps = 16;
  float march_step = 0.0f;  // (p_far - p_near) / march_steps
  float probe = 0.0f;       // `single`
  int secant_max_steps = 64;

  // The padded parallax row holds columns [-pad_left, Ws + pad_right) with the edge values
  // repeated, so every position a search visits reads without bounds checks.
  int pad_left = 0;
  int pad_right = 0;
};

// Scratch for one row, reused across rows and calls (no allocation once large enough).
struct RowScratch {
  std::vector<float> parallax_storage;
  std::vector<float> source_x;
  std::vector<std::uint8_t> clipped;
  std::vector<float> block_min;  // `secant`: per block of kSecantBlock columns, min/max key
  std::vector<float> block_max;
  const float* parallax = nullptr;  // column 0 of the padded row
};

// The decoded parallax of a stored depth value, made total (BEHAVIOUR.md "Non-finite and
// out-of-range depth"): NaN or farther than infinity -> p_far; nearer than L -> s * L.
inline float raw_parallax(const Frame& f, float depth) noexcept {
  return f.affine ? std::fma(f.decode_scale, depth, f.decode_offset) : std::fma(f.b, 1.0f / depth, f.a);
}
inline float clean_parallax(const Frame& f, float p) noexcept {
  const float key = f.s * p;
  if (!(key >= f.key_far)) return f.p_far;  // also NaN
  if (key > f.limit) return f.s * f.limit;
  return p;
}
inline float decode_parallax(const Frame& f, float depth) noexcept {
  return clean_parallax(f, raw_parallax(f, depth));
}

// Interpolated parallax at a continuous source position inside the padded row.
inline float parallax_at(const float* parallax, float x) noexcept {
  const float column = std::floor(x);
  const int j = static_cast<int>(column);
  const float frac = x - column;
  return std::fma(frac, parallax[j + 1] - parallax[j], parallax[j]);
}

// g(x) = s ((t' - x) - P(x)): > 0 while the ray is in front of the surface (BEHAVIOUR.md).
inline float ray_gap(const Frame& f, float target, float x, float surface_parallax) noexcept {
  return f.s * ((target - x) - surface_parallax);
}

// Linear intersection of g between a sample in front (gap_front > 0) and one on or behind.
inline float intersect(float x_front, float gap_front, float x_behind, float gap_behind) noexcept {
  const float t = gap_front / (gap_front - gap_behind);
  return std::fma(t, x_behind - x_front, x_front);
}

// The marching methods work in *offsets* o = x - t' from the target column: a fixed-step
// sample then has the same offset, integer part and fraction in every lane, so a SIMD twin reads
// it with contiguous loads and gets the same bits as this scalar reference. t' - x = -o exactly.

// Parallax at offset o from target column t' (o's integer part and fraction are lane-invariant).
inline float parallax_at_offset(const float* parallax, int target, float offset) noexcept {
  const float whole = std::floor(offset);
  const float frac = offset - whole;
  const float* p = parallax + target + static_cast<int>(whole);
  return std::fma(frac, p[1] - p[0], p[0]);
}
inline float gap_at_offset(const Frame& f, float offset, float surface_parallax) noexcept {
  return f.s * (-offset - surface_parallax);
}

// Point sample of march16 / single at ray parallax p: column floor(t' - p + 0.5) = t' + floor(0.5 - p);
// the padded row makes it the clamped read.
inline int point_offset(float ray_parallax) noexcept {
  return static_cast<int>(std::floor(0.5f - ray_parallax));
}

// The column march shared by `scanline` and `secant`: from offset o_start (gap_start > 0), visit
// every integer offset strictly between o_start and o_end in direction s, then o_end; return the
// offset of the first crossing (linear on its segment), or o_end if none is found by rounding.
inline float march_columns(const Frame& f, const float* parallax, int target, float o_start, float gap_start,
                           float o_end) noexcept {
  const bool upwards = f.s > 0.0f;
  const int first = upwards ? static_cast<int>(std::floor(o_start)) + 1 : static_cast<int>(std::ceil(o_start)) - 1;
  const int end = upwards ? static_cast<int>(std::ceil(o_end)) : static_cast<int>(std::floor(o_end));
  const int step = upwards ? 1 : -1;
  float o_prev = o_start;
  float gap_prev = gap_start;
  for (int o = first; upwards ? o < end : o > end; o += step) {
    const float offset = static_cast<float>(o);
    const float gap = gap_at_offset(f, offset, parallax[target + o]);
    if (gap <= 0.0f) return intersect(o_prev, gap_prev, offset, gap);
    o_prev = offset;
    gap_prev = gap;
  }
  const float gap = gap_at_offset(f, o_end, parallax_at_offset(parallax, target, o_end));
  return gap <= 0.0f ? intersect(o_prev, gap_prev, o_end, gap) : o_end;
}

// Each method's search over one row: writes x (source columns) and the clipped flag per target
// pixel. The resolve stage turns them into outputs.
void search_row_scanline(const Frame& f, RowScratch& scratch);
void search_row_march(const Frame& f, RowScratch& scratch);
void search_row_single(const Frame& f, RowScratch& scratch);
void search_row_secant(const Frame& f, RowScratch& scratch);
void search_row_exact(const Frame& f, RowScratch& scratch);

// Builds the plan from validated inputs (including the default p_near pass over the depth).
Frame make_frame(const SourceView& source, const DepthDecoder& decoder, const ParallaxModel& model,
                 const Options& options, const TargetView& target);
// Runs rows [row_begin, row_end) of the frame.
void run_rows(const Frame& f, int row_begin, int row_end);

}  // namespace detail
}  // namespace reproject
