// Internal: a call's plan (Frame: everything a row needs, computed once per call after
// validation, docs/DESIGN.md §3–§5) and the per-thread row scratch. Not installed.
// frame.cpp implements what this header declares.
#pragma once

#include <cstdint>

#include "kernels/memory.hpp"
#include "reproject/reproject.hpp"

namespace reproject::detail {

struct SrgbTables;                       // kernels/color_formats.hpp
enum class SrgbLookup : unsigned char;  // kernels/color_formats.hpp

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
  SrgbLookup srgb_lookup{};          // rgba8_srgb on sets with two ways (gathers: 0)
  // rgba8_packed_linear: d = near + v (far - near).
  float packed_near = 0.0f;
  float packed_range = 1.0f;
  int source_width = 0;  // Ws, guard band included
  int target_width = 0;  // Wt = Ws - 2 guard
  int height = 0;
  int guard = 0;

  // Parallax decode: affine p = fma(decode_scale, d, decode_offset) (b A and a + b B, DESIGN §3–§4);
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

// Scratch for one row, reused across rows and calls (no allocation once large enough), in the
// library's memory (kernels/memory.hpp: the host's allocator, 64-byte aligned).
struct RowScratch {
  Buffer<float> parallax_storage;
  Buffer<float> source_x;
  Buffer<float> clipped;  // 1 or 0 per target pixel: a float, so SIMD reads it with one load
  // `exact`'s SIMD sweep: per target pixel, the code of what paints it (exact_simd.hpp), with
  // kOwnerPad entries before and after for whole-vector stores. Codes are exact small floats.
  Buffer<float> owner_storage;
  Buffer<float> block_min;  // `secant`: min/max key per block of columns (secant.hpp)
  Buffer<float> block_max;
  // The stored depth values d of a D16 row (when the output depth is asked for): the SIMD
  // decode writes them, the SIMD resolve interpolates them (16-bit columns do not fit its plan).
  Buffer<float> stored_depth;
  const float* parallax = nullptr;  // column 0 of the padded row
};

// The plan from validated, normalised views (src/validate.hpp, CallViews: the depth and the
// output depth as depth buffers, unwanted outputs cleared), without the near limit when near_pass_needed() (Options::
// max_negative_parallax unset, and a method that searches from the near end): the caller then
// reduces nearest_key_in_rows() (kernels/rows.hpp) over every row (with std::max, starting from
// key_far, rows in order) and passes the result to set_near_key(). With the option set the plan
// is complete.
Frame plan_frame(const SourceView& source, const DepthDecoder& decoder, const ParallaxModel& model,
                 const Options& options, const TargetView& target);

// Whether the plan still needs the frame's nearest key (nearest_key_in_rows, set_near_key).
bool near_pass_needed(const Frame& f);

// The fields that follow from the near end of the rays: p_near, the march step, the padding.
void set_near_key(Frame& f, float key_near);

// Whether a pair's eyes are mirrored in the plan too: s flips from one eye to the other (b != 0).
// Then they have the same nearest key (eye k's key is s_k * p_k and both signs flip), so the
// right eye's near pass serves both, and the left eye's parallax row is the right eye's negated.
// With b = +-0 each eye does its own.
bool mirrored_eyes(const Frame& left, const Frame& right);

// Sizes `scratch` for any frame with f's widths and guard, whatever its near limit (the padding
// is sized for the widest the plan allows), so that later calls with the same sizes never
// allocate, whatever their depth. Valid before set_near_key(). False when out of memory (then
// the scratch must not be used for f).
[[nodiscard]] bool prepare_scratch(const Frame& f, RowScratch& scratch);

}  // namespace reproject::detail
