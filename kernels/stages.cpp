// The scalar references of the shared stages (the per-row parallax decode, the near-limit
// reduction and the resolve stage, DESIGN §5–§6 "One resolve stage for all") and the scalar
// kernel table. Compiled twice, like every scalar reference (see frame.hpp).
// Its SIMD twin: kernels/stages_simd.hpp.
#include <algorithm>

#include "kernels/frame.hpp"

namespace reproject {
namespace detail {
inline namespace REPROJECT_SCALAR_COPY {
namespace {

float clampf(float v, float lo, float hi) { return std::min(std::max(v, lo), hi); }

// Reads channel c of source pixel i and writes target pixel t, for either layout.
struct RowIo {
  const float* src[4];
  float* dst[4];
  int channels;
  int pixel_step;  // 1 planar, 4 interleaved

  RowIo(const Frame& f, int y) {
    channels = f.source.color.channels;
    const bool interleaved = f.source.color.layout == ColorLayout::interleaved_rgba;
    pixel_step = interleaved ? 4 : 1;
    for (int c = 0; c < channels; ++c) {
      const int plane = interleaved ? 0 : c;
      const int offset = interleaved ? c : 0;
      src[c] = f.source.color.plane[plane].row(y) + offset;
      dst[c] = f.target.color.plane[plane].row(y) + offset;
    }
  }
  float source(int c, int i) const { return src[c][static_cast<std::ptrdiff_t>(i) * pixel_step]; }
  float& target(int c, int t) const { return dst[c][static_cast<std::ptrdiff_t>(t) * pixel_step]; }
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
void decode_parallax_columns(const Frame& f, const float* depth, float* parallax, int begin, int end) {
  for (int i = begin; i < end; ++i) parallax[i] = decode_parallax<Fma>(f, depth[i]);
}

template <class Fma>
float nearest_key_in_columns(const Frame& f, const float* depth, int begin, int end, float nearest) {
  for (int i = begin; i < end; ++i) nearest = std::max(nearest, f.s * decode_parallax<Fma>(f, depth[i]));
  return nearest;
}

template <class Fma>
void resolve_pixels(const Frame& f, int y, const RowScratch& scratch, int t_begin, int t_end) {
  const RowIo io(f, y);
  const float* parallax = scratch.parallax;
  const float* depth = f.source.depth.row(y);
  float* depth_out = f.target.depth.data ? f.target.depth.row(y) : nullptr;
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
      for (int c = 0; c < io.channels; ++c) {
        const float c0 = io.source(c, j0);
        io.target(c, t) = black ? 0.0f : madd<Fma>(frac, io.source(c, j1) - c0, c0);
      }
      if (depth_out) depth_out[t] = interpolate_depth<Fma>(f, depth[j0], depth[j1], frac);
    }
    if (status_out) status_out[t] = static_cast<std::uint8_t>(status);
    if (x_out) x_out[t] = x;
  }
}

template void decode_parallax_columns<Fused>(const Frame&, const float*, float*, int, int);
template void decode_parallax_columns<Unfused>(const Frame&, const float*, float*, int, int);
template float nearest_key_in_columns<Fused>(const Frame&, const float*, int, int, float);
template float nearest_key_in_columns<Unfused>(const Frame&, const float*, int, int, float);
template void resolve_pixels<Fused>(const Frame&, int, const RowScratch&, int, int);
template void resolve_pixels<Unfused>(const Frame&, int, const RowScratch&, int, int);

namespace {

// The scalar references as whole-row kernels.
template <class Fma>
void scalar_decode(const Frame& f, const float* depth, float* parallax) {
  decode_parallax_columns<Fma>(f, depth, parallax, 0, f.source_width);
}
template <class Fma>
float scalar_nearest_key(const Frame& f, const float* depth) {
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
