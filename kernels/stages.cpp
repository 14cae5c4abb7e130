// The scalar references of the shared stages (the per-row parallax decode, the near-limit
// reduction and the resolve stage, DESIGN §5–§6 "One resolve stage for all") and the scalar
// kernel table. Compiled twice, like every scalar reference (see frame.hpp).
// Its SIMD twin: kernels/stages_simd.hpp.
#include <algorithm>
#include <cstring>

#include "kernels/frame.hpp"

namespace reproject {
namespace detail {
inline namespace REPROJECT_SCALAR_COPY {
namespace {

float clampf(float v, float lo, float hi) { return std::min(std::max(v, lo), hi); }

// A row's colour in its format: writes target pixel t as source columns j0 and j1 blended at
// `frac` (c0 + frac (c1 - c0) per channel with the table's FMA policy), or as zeros (`black`).
// Float values are blended as they are; rgba8 as the byte values, rgba8_srgb's R, G, B as their
// linear values, rgba16f as the halves' values; then each is stored in the format, rounded to
// nearest even (docs/BEHAVIOUR.md "Pixel formats").
template <class Fma>
struct ColorRow {
  ColorFormat format;
  const SrgbTables* srgb;
  const float* src[4];
  float* dst[4];
  int channels;
  int pixel_step;  // floats: 1 planar, 4 interleaved
  const std::uint8_t* src_bytes;
  std::uint8_t* dst_bytes;

  ColorRow(const Frame& f, int y) : format(f.color_format), srgb(f.srgb) {
    channels = f.source.color.channels;
    if (format != ColorFormat::float32) {
      src_bytes = f.source.color.pixels.row(y);
      dst_bytes = f.target.color.pixels.row(y);
      return;
    }
    const bool interleaved = f.source.color.layout == ColorLayout::interleaved_rgba;
    pixel_step = interleaved ? 4 : 1;
    for (int c = 0; c < channels; ++c) {
      const int plane = interleaved ? 0 : c;
      const int offset = interleaved ? c : 0;
      src[c] = f.source.color.plane[plane].row(y) + offset;
      dst[c] = f.target.color.plane[plane].row(y) + offset;
    }
  }
  static float blend(float frac, float c0, float c1) { return madd<Fma>(frac, c1 - c0, c0); }
  static std::uint8_t unorm8(float value) { return static_cast<std::uint8_t>(round_even(clamp_code(value, 255.0f))); }

  void write(int t, int j0, int j1, float frac, bool black) const {
    const std::ptrdiff_t a = j0, b = j1, out = t;
    switch (format) {
      case ColorFormat::float32:
        for (int c = 0; c < channels; ++c)
          dst[c][out * pixel_step] = black ? 0.0f : blend(frac, src[c][a * pixel_step], src[c][b * pixel_step]);
        return;
      case ColorFormat::rgba8:
      case ColorFormat::rgba8_srgb:
        for (int c = 0; c < 4; ++c) {
          const std::uint8_t c0 = src_bytes[4 * a + c], c1 = src_bytes[4 * b + c];
          std::uint8_t value = 0;
          if (black) {
          } else if (format == ColorFormat::rgba8_srgb && c < 3) {
            value = srgb_encode(*srgb, blend(frac, srgb->to_linear[c0], srgb->to_linear[c1]));
          } else {
            value = unorm8(blend(frac, static_cast<float>(c0), static_cast<float>(c1)));
          }
          dst_bytes[4 * out + c] = value;
        }
        return;
      case ColorFormat::rgba16f:
        for (int c = 0; c < 4; ++c) {
          std::uint16_t h0, h1, value = 0;
          std::memcpy(&h0, src_bytes + 8 * a + 2 * c, 2);
          std::memcpy(&h1, src_bytes + 8 * b + 2 * c, 2);
          if (!black) value = float_to_half(blend(frac, half_to_float(h0), half_to_float(h1)));
          std::memcpy(dst_bytes + 8 * out + 2 * c, &value, 2);
        }
        return;
    }
  }
};

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
void decode_parallax_columns(const Frame& f, const std::uint8_t* depth, float* parallax, float* stored, int begin,
                             int end) {
  for (int i = begin; i < end; ++i) {
    const float d = depth_value(f, depth, i);
    parallax[i] = decode_parallax<Fma>(f, d);
    if (stored) stored[i] = d;
  }
}

template <class Fma>
float nearest_key_in_columns(const Frame& f, const std::uint8_t* depth, int begin, int end, float nearest) {
  for (int i = begin; i < end; ++i) nearest = std::max(nearest, f.s * decode_parallax<Fma>(f, depth_value(f, depth, i)));
  return nearest;
}

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
        // A wall (§5): the farther endpoint has the smaller key s * p.
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

template void decode_parallax_columns<Fused>(const Frame&, const std::uint8_t*, float*, float*, int, int);
template void decode_parallax_columns<Unfused>(const Frame&, const std::uint8_t*, float*, float*, int, int);
template float nearest_key_in_columns<Fused>(const Frame&, const std::uint8_t*, int, int, float);
template float nearest_key_in_columns<Unfused>(const Frame&, const std::uint8_t*, int, int, float);
template void resolve_pixels<Fused>(const Frame&, int, const RowScratch&, int, int);
template void resolve_pixels<Unfused>(const Frame&, int, const RowScratch&, int, int);

namespace {

// The scalar references as whole-row kernels.
template <class Fma>
void scalar_decode(const Frame& f, const std::uint8_t* depth, float* parallax, float* stored) {
  decode_parallax_columns<Fma>(f, depth, parallax, stored, 0, f.source_width);
}
template <class Fma>
float scalar_nearest_key(const Frame& f, const std::uint8_t* depth) {
  return nearest_key_in_columns<Fma>(f, depth, 0, f.source_width, f.key_far);
}
template <class Fma, void (*Search)(const Frame&, RowScratch&, int, int)>
void scalar_search(const Frame& f, RowScratch& scratch) {
  Search(f, scratch, 0, f.target_width);
}
template <class Fma>
void scalar_resolve(const Frame& f, int y, const RowScratch& scratch) {
  resolve_pixels<Fma>(f, y, scratch, 0, f.target_width);
}
template <class Fma>
KernelTable make_scalar_table(const char* name) {
  KernelTable table{};
  table.name = name;
  table.decode = scalar_decode<Fma>;
  table.nearest_key = scalar_nearest_key<Fma>;
  table.search[static_cast<int>(Method::scanline)] = scalar_search<Fma, search_row_scanline<Fma>>;
  table.search[static_cast<int>(Method::march16)] = scalar_search<Fma, search_row_march<Fma>>;
  table.search[static_cast<int>(Method::single)] = scalar_search<Fma, search_row_single<Fma>>;
  table.search[static_cast<int>(Method::secant)] = scalar_search<Fma, search_row_secant<Fma>>;
  table.search[static_cast<int>(Method::exact)] = scalar_search<Fma, search_row_exact<Fma>>;
  table.resolve = scalar_resolve<Fma>;
  return table;
}

}  // namespace

const KernelTable& scalar_kernels(bool fused) {
  static const KernelTable fused_table = make_scalar_table<Fused>("scalar");
  static const KernelTable unfused_table = make_scalar_table<Unfused>("scalar-unfused");
  return fused ? fused_table : unfused_table;
}

}  // inline namespace REPROJECT_SCALAR_COPY
}  // namespace detail
}  // namespace reproject
