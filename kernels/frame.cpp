// The plan every method shares (docs/DESIGN.md §3–§5): kernels/frame.hpp's functions.
#include "kernels/frame.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "kernels/color_formats.hpp"
#include "kernels/depth_formats.hpp"
#include "kernels/secant.hpp"

namespace reproject::detail {
namespace {

float clampf(float v, float lo, float hi) { return std::min(std::max(v, lo), hi); }

}  // namespace

Frame plan_frame(const SourceView& source, const DepthDecoder& decoder, const ParallaxModel& model,
                 const Options& options, const TargetView& target) {
  Frame f;
  f.source = source;
  f.target = target;
  f.depth = source.depth_buffer;
  f.depth_out = target.depth_buffer;
  f.color_format = source.color.format;
  if (f.color_format == ColorFormat::rgba8_srgb) f.srgb = &srgb_tables();
  f.packed_near = f.depth.linear_near;
  f.packed_range = f.depth.linear_far - f.depth.linear_near;
  f.source_width = f.depth.width;
  f.height = f.depth.height;
  f.guard = options.guard;
  f.target_width = f.source_width - 2 * options.guard;

  f.a = model.a;
  f.b = model.b;
  f.affine = decoder.is_affine();
  if (f.affine) {
    // Rounded to float once, and clamped to the float range: with an absurd model (convergence
    // 1e37, say) b A overflows, and inf - inf would decode ordinary depths to NaN ("infinitely
    // far"). Clamped, they decode to parallax far beyond L, which is what the model means.
    const double largest = std::numeric_limits<float>::max();
    f.decode_scale = static_cast<float>(std::clamp(static_cast<double>(model.b) * decoder.A(), -largest, largest));
    f.decode_offset = static_cast<float>(
        std::clamp(static_cast<double>(model.a) + static_cast<double>(model.b) * decoder.B(), -largest, largest));
  }
  f.s = model.b > 0.0f ? 1.0f : -1.0f;
  f.limit = static_cast<float>(f.source_width + 2);
  f.p_far = clampf(model.a, -f.limit, f.limit);
  f.key_far = f.s * f.p_far;

  f.hole_threshold = options.hole_threshold;
  f.hole_fill = options.hole_fill;
  f.edge = options.edge;
  f.method = options.method;
  f.march_steps = options.march_steps;
  f.probe = options.probe_parallax ? clampf(*options.probe_parallax, -f.limit, f.limit) : f.p_far;
  f.secant_max_steps = options.secant_max_steps;

  f.near_from_frame = !options.max_negative_parallax;
  if (options.max_negative_parallax)
    set_near_key(f, std::max(std::min(*options.max_negative_parallax, f.limit), f.key_far));
  else if (!near_pass_needed(f))
    set_near_key(f, f.limit);  // nothing is nearer than L: nothing is clipped, as the frame's own limit says
  return f;
}

bool near_pass_needed(const Frame& f) {
  // `single` and `exact` neither start a search at the near end nor (with the frame's own near
  // limit) clip anything, so they skip the pass over the depth that finds it.
  return f.near_from_frame && f.method != Method::single && f.method != Method::exact;
}

void set_near_key(Frame& f, float key_near) {
  // + 0: a nearest key of zero is +0 whichever zero a max reduction happened to keep (std::max and
  // the vector max instructions keep different operands on ties), so every arch plans alike.
  f.key_near = key_near + 0.0f;
  f.p_near = f.s * f.key_near;
  f.march_step = (f.p_far - f.p_near) / static_cast<float>(f.march_steps);

  // Columns a search may read: x = t' - p for t' in [guard, guard + Wt - 1] and p between the
  // extremes below, plus one column for interpolation and one for rounding. Without a near pass
  // no search reads at the near end (single, exact with the frame's own limit).
  const float p_read = near_pass_needed(f) || !f.near_from_frame ? f.p_near : f.p_far;
  const float p_max = std::max({p_read, f.p_far, f.probe});
  const float p_min = std::min({p_read, f.p_far, f.probe});
  f.pad_left = static_cast<int>(std::max(0.0f, std::ceil(p_max - static_cast<float>(f.guard)))) + 2;
  f.pad_right = static_cast<int>(std::max(0.0f, std::ceil(-p_min - static_cast<float>(f.guard)))) + 3;
}

bool mirrored_eyes(const Frame& left, const Frame& right) {
  // b = +-0 (no stereo) gives both eyes s = -1: their keys are then not equal, and the left
  // eye's clamps are not the mirror of the right's.
  return left.s == -right.s;
}

bool prepare_scratch(const Frame& f, RowScratch& scratch) {
  // Every parallax the plan holds (p_near, p_far, probe) lies in [-limit, limit], so this is
  // set_near_key()'s padding at its widest.
  const int pad = static_cast<int>(std::max(0.0f, std::ceil(f.limit - static_cast<float>(f.guard))));
  const std::size_t padded = static_cast<std::size_t>(pad + 2) + f.source_width + static_cast<std::size_t>(pad + 3);
  const std::size_t targets = static_cast<std::size_t>(f.target_width);
  const std::size_t entries = secant_table_size(f.source_width);  // `secant`'s block table
  return scratch.parallax_storage.reserve(padded) && scratch.source_x.reserve(targets) && scratch.clipped.reserve(targets) &&
         scratch.owner_storage.reserve(targets + 2 * kOwnerPad) &&
         (!depth_row_kept(f) || scratch.stored_depth.reserve(static_cast<std::size_t>(f.source_width))) &&
         scratch.block_min.reserve(entries) && scratch.block_max.reserve(entries);
}

}  // namespace reproject::detail
