// The scalar reference of the resolve stage every method shares (docs/DESIGN.md §5–§6 "One
// resolve stage for all"): a method's source position x per target pixel becomes its status,
// colour, depth and source_x. Compiled twice, like every scalar reference
// (kernels/kernel_table.hpp). Its SIMD twin: kernels/resolve_simd.hpp.
#include <algorithm>
#include <cmath>

#include "kernels/color_formats.hpp"
#include "kernels/depth_formats.hpp"
#include "kernels/kernel_table.hpp"

namespace reproject::detail {
inline namespace REPROJECT_SCALAR_COPY {
namespace {

float clampf(float v, float lo, float hi) { return std::min(std::max(v, lo), hi); }

// Output depth between two stored values, in the space where a plane is linear: the stored value
// for affine encodings, 1/d for linear depth.
template <class Fma>
float interpolate_depth(const Frame& f, float d0, float d1, float frac) {
  if (f.affine) return madd<Fma>(frac, d1 - d0, d0);
  const float w0 = 1.0f / d0;
  const float w1 = 1.0f / d1;
  return 1.0f / madd<Fma>(frac, w1 - w0, w0);
}

}  // namespace

template <class Fma>
void resolve_pixels(const Frame& f, int y, const RowScratch& scratch, int t_begin, int t_end) {
  const ColorRow<Fma> color(f, y);
  const float* parallax = scratch.parallax;
  const std::uint8_t* depth_row = f.depth.row(y);
  const bool float_depth = f.depth.format == DepthFormat::float32;
  std::uint8_t* depth_out = f.depth_out.data ? f.depth_out.row(y) : nullptr;
  const int depth_bytes = bytes_per_pixel(f.depth.format);
  std::uint8_t* status_out = f.target.status.data ? f.target.status.row(y) : nullptr;
  float* x_out = f.target.source_x.data ? f.target.source_x.row(y) : nullptr;
  const int last = f.source_width - 1;
  const float last_column = static_cast<float>(last);

  for (int t = t_begin; t < t_end; ++t) {
    const float x = scratch.source_x[t];
    PixelStatus status;
    // Interpolation between columns j0 and j1 at `frac`; a fill copies column j0 (frac 0).
    int j0;
    int j1;
    float frac;
    bool write = true;
    bool black = false;
    if (scratch.clipped[t] || x < 0.0f || x > last_column) {
      status = scratch.clipped[t] ? PixelStatus::clipped : PixelStatus::outside;
      float xs = x;
      if (status == PixelStatus::outside) {
        write = f.edge != EdgeMode::none;
        black = f.edge == EdgeMode::black;
        // Reflected about the edge pixel's centre (then clamped, if still off the row).
        if (f.edge == EdgeMode::mirror) xs = x < 0.0f ? -x : (last_column - x) + last_column;
      }
      const float xc = clampf(xs, 0.0f, last_column);
      j0 = static_cast<int>(std::floor(xc));
      j1 = std::min(j0 + 1, last);
      frac = xc - static_cast<float>(j0);
    } else {
      j0 = static_cast<int>(std::floor(x));
      j1 = std::min(j0 + 1, last);
      frac = x - static_cast<float>(j0);
      if (parallax[j1] - parallax[j0] > f.hole_threshold) {
        // A wall (DESIGN §5): the farther endpoint has the smaller key s * p.
        status = PixelStatus::hole;
        const bool j1_farther = f.s * parallax[j1] < f.s * parallax[j0];
        const int farther = j1_farther ? j1 : j0;
        const int nearer = j1_farther ? j0 : j1;
        j0 = j1 = f.hole_fill == HoleFill::foreground ? nearer : farther;
        frac = 0.0f;
        write = f.hole_fill != HoleFill::none;
      } else {
        status = PixelStatus::hit;
      }
    }
    if (write) {
      color.write(t, j0, j1, frac, black);
      if (depth_out) {
        const float d = interpolate_depth<Fma>(f, depth_value(f, depth_row, j0), depth_value(f, depth_row, j1), frac);
        const std::uint32_t word = depth_word(f, d, depth_bytes == 4 && !float_depth ? load_u32(depth_row + 4 * static_cast<std::ptrdiff_t>(j0)) : 0u);
        if (depth_bytes == 2) {
          const std::uint16_t code = static_cast<std::uint16_t>(word);
          std::memcpy(depth_out + 2 * static_cast<std::ptrdiff_t>(t), &code, 2);
        } else {
          store_u32(depth_out + 4 * static_cast<std::ptrdiff_t>(t), word);
        }
      }
    }
    if (status_out) status_out[t] = static_cast<std::uint8_t>(status);
    if (x_out) x_out[t] = x;
  }
}

template void resolve_pixels<Fused>(const Frame&, int, const RowScratch&, int, int);
template void resolve_pixels<Unfused>(const Frame&, int, const RowScratch&, int, int);

}  // inline namespace REPROJECT_SCALAR_COPY
}  // namespace reproject::detail
