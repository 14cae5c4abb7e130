// Internal: SIMD twin of kernels/resolve.cpp, the resolve stage every method shares
// (docs/DESIGN.md §6 "One resolve stage for all").
#pragma once

#include "kernels/color_formats_simd.hpp"
#include "kernels/depth_formats_simd.hpp"
#include "kernels/simd.hpp"

namespace reproject::detail {
namespace {  // one copy per arch TU (kernels/fma.hpp)

// Scalar twin: resolve_pixels.
template <class Arch, class Fma>
void simd_resolve(const Frame& f, int y, const RowScratch& scratch) {
  REPROJECT_LANE_TYPES(Arch);
  const bool interleaved = f.source.color.layout == ColorLayout::interleaved_rgba;
  const ColorFormat format = f.color_format;
  // rgba8 and rgba8_srgb: a pixel is a 32-bit word, read with the column plan like a float;
  // float RGBA and rgba16f: a pixel per 128-bit vector; float planes: a float per lane and plane.
  const bool word_pixels = format == ColorFormat::rgba8 || format == ColorFormat::rgba8_srgb;
  const bool vector_pixels = interleaved && !word_pixels;
  const int planes = interleaved ? 1 : f.source.color.channels;
  const std::uint8_t* source[4];
  std::uint8_t* target[4];
  for (int c = 0; c < planes; ++c) {
    source[c] = format == ColorFormat::float32 ? reinterpret_cast<const std::uint8_t*>(f.source.color.plane[c].row(y))
                                               : f.source.color.pixels.row(y);
    target[c] = format == ColorFormat::float32 ? reinterpret_cast<std::uint8_t*>(f.target.color.plane[c].row(y))
                                               : f.target.color.pixels.row(y);
  }
  const int pixel_bytes = format == ColorFormat::float32 ? (interleaved ? 16 : 4) : bytes_per_pixel(format);
  const float* parallax = scratch.parallax;
  // Depth is interpolated from the row's own 32-bit columns (floats, or words decoded in
  // registers), or for D16 from the values the decode kept.
  const std::uint8_t* depth_row = f.depth.row(y);
  const bool float_depth = f.depth.format == DepthFormat::float32;
  const bool depth_words_read = !depth_row_kept(f);
  const float* depth = depth_words_read ? reinterpret_cast<const float*>(depth_row) : scratch.stored_depth.data();
  const int depth_bytes = bytes_per_pixel(f.depth.format);
  std::uint8_t* depth_out = f.depth_out.data ? f.depth_out.row(y) : nullptr;
  std::uint8_t* status_out = f.target.status.data ? f.target.status.row(y) : nullptr;
  float* x_out = f.target.source_x.data ? f.target.source_x.row(y) : nullptr;
  const F zero(0.0f), one(1.0f), last(static_cast<float>(f.source_width - 1)), tau(f.hole_threshold), s(f.s);
  const bool fill_foreground = f.hole_fill == HoleFill::foreground;
  const bool edges_written = f.edge != EdgeMode::none;
  const bool mirror_edges = f.edge == EdgeMode::mirror;
  const bool black_edges = f.edge == EdgeMode::black;
  const bool holes_written = f.hole_fill != HoleFill::none;

  int t = 0;
  for (; t + L <= f.target_width; t += L) {
    const F x = F::load_unaligned(scratch.source_x.data() + t);
    const B clipped = load_flags<Arch>(scratch.clipped.data() + t);
    const B outside = ((x < zero) | (x > last)) & ~clipped;
    F xs = x;
    if (mirror_edges) {  // reflected about the edge pixel's centre (then clamped)
      xs = xsimd::select(outside & (x < zero), -x, xsimd::select(outside & (x > last), (last - x) + last, x));
    }
    const F xc = vmin(vmax(xs, zero), last);  // == x in the row
    F j0 = vfloor(xc);
    F j1 = vmin(j0 + one, last);
    F frac = xc - j0;
    // Every column read below lies in [j0, j1] (a fill picks one of the two).
    ColumnFetch<Arch> columns(j0, j1, f.source_width);
    F p0, p1;
    columns.fetch(parallax, p0, p1);
    const B hole = ((p1 - p0) > tau) & ~(clipped | outside);
    const bool any_hole = xsimd::any(hole);
    if (any_hole) {
      // A wall (DESIGN §5): the farther endpoint has the smaller key s * p.
      const B j1_farther = s * p1 < s * p0;
      const F farther = xsimd::select(j1_farther, j1, j0);
      const F nearer = xsimd::select(j1_farther, j0, j1);
      const F fill = fill_foreground ? nearer : farther;
      j0 = xsimd::select(hole, fill, j0);
      j1 = xsimd::select(hole, fill, j1);
      frac = xsimd::select(hole, zero, frac);
      columns.bind(j0, j1);
    }
    // Lanes whose colour and depth are left to the caller keep the target's values.
    const bool masked = (!edges_written && xsimd::any(outside)) || (!holes_written && any_hole);
    const B write = ~((outside & B(!edges_written)) | (hole & B(!holes_written)));
    auto store = [&](float* out, const F& value) {
      (masked ? xsimd::select(write, value, F::load_unaligned(out)) : value).store_unaligned(out);
    };
    const std::ptrdiff_t out_byte = static_cast<std::ptrdiff_t>(t) * pixel_bytes;
    if (vector_pixels) {
      const B black = outside & B(black_edges);
      const bool special = masked || (black_edges && xsimd::any(black));
      if (format == ColorFormat::rgba16f) {
        resolve_rgba_pixels<Arch, Fma, HalfRgbaPixel>(source[0], target[0] + out_byte, j0, j1, frac, ~write, black, special);
      } else {
        resolve_rgba_pixels<Arch, Fma, FloatRgbaPixel>(source[0], target[0] + out_byte, j0, j1, frac, ~write, black, special);
      }
    } else if (!word_pixels) {
      // A kilobyte ahead in each colour plane: a measured 1-3 % over the hardware prefetcher
      // alone, which tracks this many streams less well.
      for (int c = 0; c < planes; ++c) __builtin_prefetch(source[c] + 4 * t + 1024);
    }
    columns.visit([&](const auto& fetch) {
      auto store_color = [&](int c, const F& value) {
        store(reinterpret_cast<float*>(target[c] + out_byte), black_edges ? xsimd::select(outside, zero, value) : value);
      };
      if (vector_pixels) {
        // colour done above
      } else if (word_pixels) {  // one plane of words (not in the planes' loop: it kept registers on the stack)
        F c0, c1;
        fetch(reinterpret_cast<const float*>(source[0]), c0, c1);
        const auto w0 = bits_of<Arch>(c0), w1 = bits_of<Arch>(c1);
        store_color(0, float_bits<Arch>(format == ColorFormat::rgba8 ? blend_rgba8<Arch, Fma, false>(f, w0, w1, frac)
                                                                     : blend_rgba8<Arch, Fma, true>(f, w0, w1, frac)));
      } else {
        for (int c = 0; c < planes; ++c) {
          F c0, c1;
          fetch(reinterpret_cast<const float*>(source[c]), c0, c1);
          store_color(c, vmadd<Fma>(frac, c1 - c0, c0));
        }
      }
      if (depth_out) {
        F d0, d1;
        fetch(depth, d0, d1);
        const auto kept = bits_of<Arch>(d0);  // the word of column j0: its bits that are not depth
        if (depth_words_read && !float_depth) {
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
        float* out = reinterpret_cast<float*>(depth_out + static_cast<std::ptrdiff_t>(t) * depth_bytes);
        if (float_depth) {
          store(out, d);
        } else {
          const auto words = depth_words<Arch>(f, d, kept);
          if (depth_bytes == 4) {
            store(out, float_bits<Arch>(words));
          } else {
            store_u16<Arch>(words, write, masked, depth_out + 2 * static_cast<std::ptrdiff_t>(t));
          }
        }
      }
    });
    if (status_out) {
      store_bytes<Arch>(xsimd::select(clipped, F(3.0f), xsimd::select(outside, F(2.0f), xsimd::select(hole, one, zero))),
                        status_out + t);
    }
    if (x_out) x.store_unaligned(x_out + t);
  }
  resolve_pixels<Fma>(f, y, scratch, t, f.target_width);  // the tail
}

}  // namespace
}  // namespace reproject::detail
