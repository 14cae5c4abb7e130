// Internal: what the SIMD resolve (kernels/resolve_simd.hpp) writes for one vector of target
// pixels, whichever path the vector takes: the row's context (its rows, outputs and colour path),
// and the colour and depth of L pixels from two column sets and a weight. Scalar twins in
// kernels/resolve.cpp (resolve_pixels, ColorRow::write).
#pragma once

#include <type_traits>

#include "kernels/color_formats_simd.hpp"
#include "kernels/depth_formats_simd.hpp"
#include "kernels/simd.hpp"

namespace reproject::detail {
namespace {  // one copy per arch TU (kernels/fma.hpp)

// How a row's colour is read and written: a float per lane and plane; a pixel per 128-bit
// register (float RGBA, rgba16f); a 32-bit word per lane (rgba8, rgba8_srgb with either sRGB
// lookup, Frame::srgb_lookup).
enum class ColorPath { planes, float_rgba, half_rgba, rgba8, rgba8_srgb, rgba8_srgb_permutes };

constexpr bool is_word_path(ColorPath path) {
  return path == ColorPath::rgba8 || path == ColorPath::rgba8_srgb || path == ColorPath::rgba8_srgb_permutes;
}

// Calls body(tag) with a compile-time tag of the colour path (as with_depth_format does for depth).
// rgba8_srgb_permutes exists on sets with sRGB permutes only (color_path_of).
template <class Arch, class Body>
void with_color_path(ColorPath path, const Body& body) {
  switch (path) {
    case ColorPath::planes: return body(std::integral_constant<ColorPath, ColorPath::planes>{});
    case ColorPath::float_rgba: return body(std::integral_constant<ColorPath, ColorPath::float_rgba>{});
    case ColorPath::half_rgba: return body(std::integral_constant<ColorPath, ColorPath::half_rgba>{});
    case ColorPath::rgba8: return body(std::integral_constant<ColorPath, ColorPath::rgba8>{});
    case ColorPath::rgba8_srgb: return body(std::integral_constant<ColorPath, ColorPath::rgba8_srgb>{});
    case ColorPath::rgba8_srgb_permutes:
      if constexpr (has_srgb_permutes<Arch>()) {
        return body(std::integral_constant<ColorPath, ColorPath::rgba8_srgb_permutes>{});
      }
      break;
  }
}

template <class Arch>
ColorPath color_path_of(const Frame& f) {
  switch (f.color_format) {
    case ColorFormat::rgba8: return ColorPath::rgba8;
    case ColorFormat::rgba8_srgb:
      return has_srgb_permutes<Arch>() && f.srgb_lookup == SrgbLookup::permutes ? ColorPath::rgba8_srgb_permutes
                                                                                : ColorPath::rgba8_srgb;
    case ColorFormat::rgba16f: return ColorPath::half_rgba;
    case ColorFormat::float32: break;
  }
  return f.source.color.layout == ColorLayout::interleaved_rgba ? ColorPath::float_rgba : ColorPath::planes;
}

// What every vector of row y shares: its rows, outputs and the frame's choices.
template <class Arch>
struct RowContext {
  using F = typename Lanes<Arch>::F;

  RowContext(const Frame& frame, int y, const RowScratch& scratch)
      : f(frame),
        path(color_path_of<Arch>(frame)),
        planes(path == ColorPath::planes ? frame.source.color.channels : 1),
        source_width(frame.source_width),
        parallax(scratch.parallax),
        source_x(scratch.source_x.data()),
        clipped(scratch.clipped.data()),
        float_depth(frame.depth.format == DepthFormat::float32),
        depth_words_read(!depth_row_kept(frame)),
        depth(depth_words_read ? reinterpret_cast<const float*>(frame.depth.row(y)) : scratch.stored_depth.data()),
        depth_bytes(bytes_per_pixel(frame.depth.format)),
        depth_out(frame.depth_out.data ? frame.depth_out.row(y) : nullptr),
        status_out(frame.target.status.data ? frame.target.status.row(y) : nullptr),
        x_out(frame.target.source_x.data ? frame.target.source_x.row(y) : nullptr),
        last(static_cast<float>(frame.source_width - 1)),
        tau(frame.hole_threshold),
        s(frame.s),
        fill_foreground(frame.hole_fill == HoleFill::foreground),
        holes_written(frame.hole_fill != HoleFill::none),
        edges_written(frame.edge != EdgeMode::none),
        mirror_edges(frame.edge == EdgeMode::mirror),
        black_edges(frame.edge == EdgeMode::black) {
    const bool float_planes = frame.color_format == ColorFormat::float32;
    // The next row's depth and colour, read while this row computes (the last row: itself).
    const int next = y + 1 < frame.height ? y + 1 : y;
    next_depth = frame.depth.row(next) + static_cast<std::ptrdiff_t>(frame.guard) * depth_bytes;
    next_source = float_planes ? reinterpret_cast<const std::uint8_t*>(frame.source.color.plane[0].row(next))
                               : frame.source.color.pixels.row(next);
    for (int c = 0; c < planes; ++c) {
      source[c] = float_planes ? reinterpret_cast<const std::uint8_t*>(frame.source.color.plane[c].row(y))
                               : frame.source.color.pixels.row(y);
      target[c] = float_planes ? reinterpret_cast<std::uint8_t*>(frame.target.color.plane[c].row(y))
                               : frame.target.color.pixels.row(y);
    }
  }

  const Frame& f;
  ColorPath path;
  int planes;
  int source_width;
  const std::uint8_t* source[4] = {};
  const std::uint8_t* next_source = nullptr;  // the next row's first plane
  const std::uint8_t* next_depth = nullptr;
  std::uint8_t* target[4] = {};
  const float* parallax;
  const float* source_x;
  const float* clipped;
  // Depth is interpolated from the row's own 32-bit columns (floats, or words decoded in
  // registers), or for D16 from the values the decode kept.
  bool float_depth;
  bool depth_words_read;
  const float* depth;
  int depth_bytes;
  std::uint8_t* depth_out;
  std::uint8_t* status_out;
  float* x_out;
  F last, tau, s;
  bool fill_foreground, holes_written, edges_written, mirror_edges, black_edges;
};

// Bytes of a pixel in one colour plane.
constexpr int pixel_bytes_of(ColorPath path) {
  return path == ColorPath::float_rgba ? 16 : path == ColorPath::half_rgba ? 8 : 4;
}

// The next row's depth and colour at the columns of target pixels [t, t + L), asked for while this
// row computes, so that the next row's decode and resolve find them in the cache instead of
// waiting for them stage by stage. Not the colour of float planes: their resolve reads a kilobyte
// ahead in each plane already, and four more prefetches per vector made them slower
// (docs/PERFORMANCE.md, "Measured design choices").
template <ColorPath Path, class Arch>
REPROJECT_ALWAYS_INLINE inline void prefetch_next_row(const RowContext<Arch>& row, int t) {
  constexpr int L = Lanes<Arch>::size;
  constexpr int kBytes = L * pixel_bytes_of(Path);
  REPROJECT_PREFETCH(row.next_depth + static_cast<std::ptrdiff_t>(t) * row.depth_bytes);
  if constexpr (Path != ColorPath::planes) {  // one plane of pixels
    const std::uint8_t* next = row.next_source + static_cast<std::ptrdiff_t>(t) * pixel_bytes_of(Path);
    for (int line = 0; line < kBytes; line += 64) REPROJECT_PREFETCH(next + line);
  }
}

// One output vector: lanes in `black` (when any_black) are zero, and with `masked` only the
// lanes in `write` are stored (the others keep the caller's values). The hit loop passes false
// for both, and the selects fold away.
template <class Arch>
REPROJECT_ALWAYS_INLINE inline void store_lanes(float* out, const xsimd::batch<float, Arch>& value,
                                                const xsimd::batch_bool<float, Arch>& write,
                                                const xsimd::batch_bool<float, Arch>& black, bool masked, bool any_black) {
  using F = xsimd::batch<float, Arch>;
  const F v = any_black ? xsimd::select(black, F(0.0f), value) : value;
  (masked ? xsimd::select(write, v, F::load_unaligned(out)) : v).store_unaligned(out);
}

// The colour of target pixels [t, t + L): columns j0 and j1 blended at frac (scalar twin:
// ColorRow::write). `fetch` reads a row's values at both column sets (ColumnFetch::visit).
template <ColorPath Path, class Arch, class Fma, class Fetch>
REPROJECT_ALWAYS_INLINE inline void write_color(const RowContext<Arch>& row, const Fetch& fetch, int t,
                                                 const xsimd::batch<float, Arch>& j0, const xsimd::batch<float, Arch>& j1,
                                                 const xsimd::batch<float, Arch>& frac,
                                                 const xsimd::batch_bool<float, Arch>& write,
                                                 const xsimd::batch_bool<float, Arch>& black, bool masked, bool any_black) {
  REPROJECT_LANE_TYPES(Arch);
  const std::ptrdiff_t out_byte = static_cast<std::ptrdiff_t>(t) * pixel_bytes_of(Path);
  if constexpr (Path == ColorPath::float_rgba || Path == ColorPath::half_rgba) {
    using Pixel = std::conditional_t<Path == ColorPath::float_rgba, FloatRgbaPixel, HalfRgbaPixel>;
    resolve_rgba_pixels<Arch, Fma, Pixel>(row.source[0], row.target[0] + out_byte, j0, j1, frac, ~write, black,
                                          masked || any_black);
  } else if constexpr (is_word_path(Path)) {
    F c0, c1;
    fetch(reinterpret_cast<const float*>(row.source[0]), c0, c1);
    // (first_lane, used for consecutive words, is where the consecutive mode is: sets with permutes.)
    constexpr bool consecutive = Fetch::mode == ColumnFetch<Arch>::Mode::consecutive && has_permute<Arch>();
    constexpr SrgbLookup lookup = Path == ColorPath::rgba8_srgb_permutes ? SrgbLookup::permutes : SrgbLookup::gathers;
    const I blended = blend_rgba8<Arch, Fma, Path != ColorPath::rgba8, consecutive, lookup>(row.f, bits_of<Arch>(c0),
                                                                                           bits_of<Arch>(c1), frac);
    store_lanes<Arch>(reinterpret_cast<float*>(row.target[0] + out_byte), float_bits<Arch>(blended), write, black, masked,
                      any_black);
  } else {
    for (int c = 0; c < row.planes; ++c) {
      // A kilobyte ahead in each colour plane: the hardware prefetcher alone tracks this many
      // streams less well (docs/PERFORMANCE.md, "Measured design choices").
      REPROJECT_PREFETCH(row.source[c] + 4 * t + 1024);
      F c0, c1;
      fetch(reinterpret_cast<const float*>(row.source[c]), c0, c1);
      store_lanes<Arch>(reinterpret_cast<float*>(row.target[c] + out_byte), vmadd<Fma>(frac, c1 - c0, c0), write, black,
                        masked, any_black);
    }
  }
}

// The output depth of target pixels [t, t + L) (scalar twin: interpolate_depth and depth_word in
// resolve_pixels).
template <class Arch, class Fma, class Fetch>
REPROJECT_ALWAYS_INLINE inline void write_depth(const RowContext<Arch>& row, const Fetch& fetch, int t,
                                                const xsimd::batch<float, Arch>& frac,
                                                const xsimd::batch_bool<float, Arch>& write, bool masked) {
  REPROJECT_LANE_TYPES(Arch);
  const Frame& f = row.f;
  const F one(1.0f);
  F d0, d1;
  fetch(row.depth, d0, d1);
  const I kept = bits_of<Arch>(d0);  // the word of column j0: its bits that are not depth
  if (row.depth_words_read && !row.float_depth) {
    d0 = depth_values_of_words<Arch, Fma>(f, kept);
    d1 = depth_values_of_words<Arch, Fma>(f, bits_of<Arch>(d1));
  }
  F d;
  if (f.affine) {
    d = vmadd<Fma>(frac, d1 - d0, d0);
  } else {
    const F w0 = vdiv(one, d0);
    d = vdiv(one, vmadd<Fma>(frac, vdiv(one, d1) - w0, w0));
  }
  std::uint8_t* out = row.depth_out + static_cast<std::ptrdiff_t>(t) * row.depth_bytes;
  const B none(false);
  if (row.float_depth) {
    store_lanes<Arch>(reinterpret_cast<float*>(out), d, write, none, masked, false);
  } else {
    const I words = depth_words<Arch>(f, d, kept);
    if (row.depth_bytes == 4) {
      store_lanes<Arch>(reinterpret_cast<float*>(out), float_bits<Arch>(words), write, none, masked, false);
    } else {
      store_u16<Arch>(words, write, masked, out);
    }
  }
}

}  // namespace
}  // namespace reproject::detail
