// Internal: the per-call plan every method shares (DESIGN §3–§6, docs/BEHAVIOUR.md), the per-row
// parallax decode, the resolve stage and the row driver. Not installed.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>
#include <type_traits>
#include <vector>

#include "kernels/pixel_formats.hpp"
#include "reproject/reproject.hpp"

namespace reproject {
namespace detail {

// Everything a row needs, computed once per call after validation.
struct Frame {
  SourceView source;
  TargetView target;
  // Depth in its format (DepthFormat; a float plane is float32 with its stride in bytes), and the
  // output depth (null when not asked for), in the same format.
  DepthBuffer depth;
  MutableDepthBuffer depth_out;
  ColorFormat color_format = ColorFormat::float32;
  const SrgbTables* srgb = nullptr;  // rgba8_srgb
  // rgba8_packed_linear: d = near + v (far - near).
  float packed_near = 0.0f;
  float packed_range = 1.0f;
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
  bool near_from_frame = false;  // p_near is the frame's nearest parallax (the default)

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

constexpr int kOwnerPad = 16;  // the widest vector

// Scratch for one row, reused across rows and calls (no allocation once large enough).
struct RowScratch {
  std::vector<float> parallax_storage;
  std::vector<float> source_x;
  std::vector<float> clipped;  // 1 or 0 per target pixel: a float, so SIMD reads it with one load
  // `exact`'s SIMD sweep: per target pixel, the code of what paints it (exact_simd.hpp), with
  // kOwnerPad entries before and after for whole-vector stores. Codes are exact small floats.
  std::vector<float> owner_storage;
  std::vector<float> block_min;  // `secant`: min/max key per block of columns (secant.hpp)
  std::vector<float> block_max;
  // The stored depth values d of a D16 row (when the output depth is asked for): the SIMD
  // decode writes them, the SIMD resolve interpolates them (16-bit columns do not fit its plan).
  std::vector<float> stored_depth;
  const float* parallax = nullptr;  // column 0 of the padded row
};

// The FMA policy, as tag types. Every multiply-add of the kernels is written madd<Fma>(a, b, c),
// so a scalar reference and its SIMD twin round alike: Fused for the FMA instruction sets (and
// the default scalar reference), Unfused for the SSE baseline, which has no FMA. The build sets
// -ffp-contract=off, so Unfused really is two roundings.
struct Fused {};
struct Unfused {};

// The helpers below are compiled into both the baseline translation units and the per-arch ones
// (with AVX2 or AVX-512 flags). They live in an anonymous namespace so that each translation unit
// keeps its own copy: with external linkage the linker could keep an AVX-512 body for a caller
// on the baseline path (STYLE.md, "ODR").
namespace {

template <class Fma>
inline float madd(float a, float b, float c) noexcept {
  if constexpr (std::is_same<Fma, Fused>::value) {
    return std::fma(a, b, c);
  } else {
    return a * b + c;
  }
}

// The stored depth value d of column i of a depth row in the frame's format (DepthFormat): a
// function of the bytes alone (no FMA policy).
inline float depth_value(const Frame& f, const std::uint8_t* row, int i) noexcept {
  switch (f.depth.format) {
    case DepthFormat::unorm16: {
      std::uint16_t code;
      std::memcpy(&code, row + 2 * static_cast<std::ptrdiff_t>(i), 2);
      return unorm_value(code, kUnorm16Max);
    }
    case DepthFormat::unorm24_s8: return unorm_value(load_u32(row + 4 * static_cast<std::ptrdiff_t>(i)) & 0xffffffu, kUnorm24Max);
    case DepthFormat::s8_unorm24: return unorm_value(load_u32(row + 4 * static_cast<std::ptrdiff_t>(i)) >> 8, kUnorm24Max);
    case DepthFormat::rgba8_packed_linear: {
      // Never fused, on any arch: the stored value is a function of the bytes alone.
      const float v = unorm_value(packed_code(load_u32(row + 4 * static_cast<std::ptrdiff_t>(i))), kPackedMax);
      return v * f.packed_range + f.packed_near;
    }
    case DepthFormat::float32: break;
  }
  return float_of_bits(load_u32(row + 4 * static_cast<std::ptrdiff_t>(i)));
}

// D16: the decode keeps the row's stored values in RowScratch::stored_depth for the SIMD resolve
// (16-bit columns do not fit its column plan); the 32-bit formats' words are read there directly.
inline bool depth_row_kept(const Frame& f) noexcept { return f.depth.format == DepthFormat::unorm16; }

// The word (or code) that stores depth d in the frame's format; `kept` is the source word whose
// other bits (D24S8's stencil, the packed format's A byte) go with it.
inline std::uint32_t depth_word(const Frame& f, float d, std::uint32_t kept) noexcept {
  switch (f.depth.format) {
    case DepthFormat::unorm16: return unorm_code(d, kUnorm16Max);
    case DepthFormat::unorm24_s8: return unorm_code(d, kUnorm24Max) | (kept & 0xff000000u);
    case DepthFormat::s8_unorm24: return (unorm_code(d, kUnorm24Max) << 8) | (kept & 0xffu);
    case DepthFormat::rgba8_packed_linear:
      return packed_word(packed_code_of((d - f.packed_near) / f.packed_range)) | (kept & 0xff000000u);
    case DepthFormat::float32: break;
  }
  return bits_of_float(d);
}

// The decoded parallax of a stored depth value, made total (BEHAVIOUR.md "Non-finite and
// out-of-range depth"): NaN or farther than infinity -> p_far; nearer than L -> s * L.
template <class Fma>
inline float raw_parallax(const Frame& f, float depth) noexcept {
  return f.affine ? madd<Fma>(f.decode_scale, depth, f.decode_offset) : madd<Fma>(f.b, 1.0f / depth, f.a);
}
inline float clean_parallax(const Frame& f, float p) noexcept {
  const float key = f.s * p;
  if (!(key >= f.key_far)) return f.p_far;  // also NaN
  if (key > f.limit) return f.s * f.limit;
  return p;
}
// + 0: a zero parallax is +0, never -0, so that a pair's left eye (the mirror model) can take the
// right eye's row as 0 - p bit for bit (run_pair_rows); no output depends on the sign of a zero.
template <class Fma>
inline float decode_parallax(const Frame& f, float depth) noexcept {
  return clean_parallax(f, raw_parallax<Fma>(f, depth)) + 0.0f;
}

// g = s ((t' - x) - P(x)): > 0 while the ray is in front of the surface (BEHAVIOUR.md).
// Linear intersection of g between a sample in front (gap_front > 0) and one on or behind.
template <class Fma>
inline float intersect(float x_front, float gap_front, float x_behind, float gap_behind) noexcept {
  const float t = gap_front / (gap_front - gap_behind);
  return madd<Fma>(t, x_behind - x_front, x_front);
}

// Interpolated parallax at a continuous source position inside the padded row.
template <class Fma>
inline float parallax_at(const float* parallax, float x) noexcept {
  const float column = std::floor(x);
  const int j = static_cast<int>(column);
  return madd<Fma>(x - column, parallax[j + 1] - parallax[j], parallax[j]);
}

// The marching methods work in *offsets* o = x - t' from the target column: a fixed-step
// sample then has the same offset, integer part and fraction in every lane, so a SIMD twin reads
// it with contiguous loads and gets the same bits as this scalar reference. t' - x = -o exactly.

// Parallax at offset o from target column t' (o's integer part and fraction are lane-invariant).
template <class Fma>
inline float parallax_at_offset(const float* parallax, int target, float offset) noexcept {
  const float whole = std::floor(offset);
  const float* p = parallax + target + static_cast<int>(whole);
  return madd<Fma>(offset - whole, p[1] - p[0], p[0]);
}
inline float gap_at_offset(const Frame& f, float offset, float surface_parallax) noexcept {
  return f.s * (-offset - surface_parallax);
}

// Point sample of march16 / single at ray parallax p: column floor(t' - p + 0.5) = t' + floor(0.5 - p);
// the padded row makes it the clamped read.
inline int point_offset(float ray_parallax) noexcept {
  return static_cast<int>(std::floor(0.5f - ray_parallax));
}

// The integer offsets strictly between o_start and o_end, walked in direction s: [first, end).
struct ColumnWalk {
  int first;
  int end;
  int step;
};
inline ColumnWalk column_walk(const Frame& f, float o_start, float o_end) noexcept {
  if (f.s > 0.0f) return ColumnWalk{static_cast<int>(std::floor(o_start)) + 1, static_cast<int>(std::ceil(o_end)), 1};
  return ColumnWalk{static_cast<int>(std::ceil(o_start)) - 1, static_cast<int>(std::floor(o_end)), -1};
}
inline bool walking(const ColumnWalk& walk, int o) noexcept { return walk.step > 0 ? o < walk.end : o > walk.end; }

// The column march shared by `scanline` and `secant`: from offset o_start (gap_start > 0), visit
// every integer offset strictly between o_start and o_end in direction s, then o_end; return the
// offset of the first crossing (linear on its segment), or o_end if none is found by rounding.
template <class Fma>
inline float march_columns(const Frame& f, const float* parallax, int target, float o_start, float gap_start,
                    float o_end) noexcept {
  const ColumnWalk walk = column_walk(f, o_start, o_end);
  float o_prev = o_start;
  float gap_prev = gap_start;
  for (int o = walk.first; walking(walk, o); o += walk.step) {
    const float offset = static_cast<float>(o);
    const float gap = gap_at_offset(f, offset, parallax[target + o]);
    if (gap <= 0.0f) return intersect<Fma>(o_prev, gap_prev, offset, gap);
    o_prev = offset;
    gap_prev = gap;
  }
  const float gap = gap_at_offset(f, o_end, parallax_at_offset<Fma>(parallax, target, o_end));
  return gap <= 0.0f ? intersect<Fma>(o_prev, gap_prev, o_end, gap) : o_end;
}

}  // namespace

// One instruction set's kernels: every stage of every method.
// A depth row in the frame's format; `stored` (null: not needed) receives the stored values d.
using DecodeRow = void (*)(const Frame& f, const std::uint8_t* depth, float* parallax, float* stored);
using SearchRow = void (*)(const Frame& f, RowScratch& scratch);
using ResolveRow = void (*)(const Frame& f, int y, const RowScratch& scratch);
using NearestKey = float (*)(const Frame& f, const std::uint8_t* depth);  // max of key_far and s * p over a row
// How many vectors the calling thread's SIMD resolve has read in each column-fetch mode
// (consecutive, shifted, spanning, gather), per table: the bit-identity test reads them to show
// that every mode ran. Scalar tables have none.
struct FetchModeCounts {
  std::uint64_t vectors[4];
};
using FetchModeCountsOfThread = FetchModeCounts* (*)();

struct KernelTable {
  const char* name;
  DecodeRow decode;
  NearestKey nearest_key;
  SearchRow search[kMethodCount];
  ResolveRow resolve;
  FetchModeCountsOfThread fetch_mode_counts;  // null for the scalar references
};

// The scalar references are compiled twice (CMakeLists.txt): with the baseline flags, and with
// the AVX2 + FMA flags into namespace `host`, so that Arch::scalar on a CPU that has them runs
// single-instruction std::fma and std::floor instead of library calls (as a user's own scalar
// code built with -march=native would). Each translation unit sees its own copy as an inline
// namespace; the two copies give the same bits (-ffp-contract=off; fma and floor are exact).
#ifndef REPROJECT_SCALAR_COPY
#define REPROJECT_SCALAR_COPY baseline
#endif
inline namespace REPROJECT_SCALAR_COPY {

// Each method's scalar reference over target pixels [t_begin, t_end) of the current row: writes
// x (source columns) and the clipped flag per target pixel. The resolve stage turns them into
// outputs. (exact sweeps the whole row: it ignores the range.)
template <class Fma> void search_row_scanline(const Frame& f, RowScratch& scratch, int t_begin, int t_end);
template <class Fma> void search_row_march(const Frame& f, RowScratch& scratch, int t_begin, int t_end);
template <class Fma> void search_row_single(const Frame& f, RowScratch& scratch, int t_begin, int t_end);
template <class Fma> void search_row_secant(const Frame& f, RowScratch& scratch, int t_begin, int t_end);
template <class Fma> void search_row_exact(const Frame& f, RowScratch& scratch, int t_begin, int t_end);

// The shared stages' scalar references: decode columns [begin, end) of a row (no padding), and
// resolve target pixels [t_begin, t_end) of row y.
template <class Fma> void decode_parallax_columns(const Frame& f, const std::uint8_t* depth, float* parallax, float* stored, int begin, int end);
template <class Fma> float nearest_key_in_columns(const Frame& f, const std::uint8_t* depth, int begin, int end, float nearest);
template <class Fma> void resolve_pixels(const Frame& f, int y, const RowScratch& scratch, int t_begin, int t_end);

// The scalar references as a table, with either FMA policy.
const KernelTable& scalar_kernels(bool fused);

}  // inline namespace REPROJECT_SCALAR_COPY

// The source's depth, or a target's output depth, as a depth buffer: `depth_buffer` when its
// data is set, else the float plane as float32 with its stride in bytes (validation allows one).
DepthBuffer depth_buffer_of(const SourceView& view);
MutableDepthBuffer depth_buffer_of(const TargetView& view);

// Builds the plan from validated inputs (including the default p_near pass over the depth).
Frame make_frame(const SourceView& source, const DepthDecoder& decoder, const ParallaxModel& model,
                 const Options& options, const TargetView& target, const KernelTable& kernels);
// Runs rows [row_begin, row_end) of the frame with the given kernels.
void run_rows(const Frame& f, const KernelTable& kernels, int row_begin, int row_end);

}  // namespace detail
}  // namespace reproject
