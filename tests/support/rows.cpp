#include "support/rows.hpp"

#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <limits>

namespace rptest {

using reproject::ColorLayout;
using reproject::DepthEncoding;

float column_color(int channel, int column) {
  switch (channel) {
    case 0: return static_cast<float>(column);
    // Distinct and non-monotonic, so reading the wrong neighbour changes the value.
    case 1: return 100.0f + static_cast<float>((column * 37) % 23);
    case 2: return -50.0f + 0.25f * static_cast<float>((column * column) % 41);
    default: return 1000.0f + static_cast<float>((column * 13) % 7);
  }
}

double color_at(int channel, double x, int width) {
  const double xc = std::min(std::max(x, 0.0), static_cast<double>(width - 1));
  int j = static_cast<int>(std::floor(xc));
  if (j >= width - 1) return column_color(channel, width - 1);
  const double f = xc - j;
  return (1.0 - f) * column_color(channel, j) + f * column_color(channel, j + 1);
}

void SourceFrame::set_depth_row(int y, const std::function<double(int x)>& depth_of) {
  for (int x = 0; x < width; ++x) depth_at(x, y) = static_cast<float>(depth_of(x));
}

void SourceFrame::set_depth(const std::function<double(int x, int y)>& depth_of) {
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) depth_at(x, y) = static_cast<float>(depth_of(x, y));
}

reproject::SourceView SourceFrame::view() const {
  reproject::SourceView view;
  if (layout == ColorLayout::interleaved_rgba) {
    view.color = reproject::ColorView::rgba(color[0].data(), width, height, color_stride);
  } else {
    view.color.layout = ColorLayout::planar;
    view.color.channels = channels;
    for (int c = 0; c < channels; ++c)
      view.color.plane[c] = reproject::FloatPlane{color[c].data(), width, height, color_stride};
  }
  view.depth = reproject::FloatPlane{depth.data(), width, height, stride};
  return view;
}

SourceFrame make_source(int width, int height, int channels, ColorLayout layout, int pad) {
  SourceFrame s;
  s.width = width;
  s.height = height;
  s.layout = layout;
  s.channels = layout == ColorLayout::interleaved_rgba ? 4 : channels;
  s.stride = width + pad;
  s.color_stride = layout == ColorLayout::interleaved_rgba ? 4 * width + pad : s.stride;
  // Padding holds a huge value: if a kernel ever reads it into a result, the result is absurd.
  const float garbage = 9.0e8f;
  s.depth.assign(static_cast<std::size_t>(s.stride * std::max(height, 1)), garbage);
  const int planes = layout == ColorLayout::interleaved_rgba ? 1 : s.channels;
  for (int p = 0; p < planes; ++p) {
    s.color[p].assign(static_cast<std::size_t>(s.color_stride * std::max(height, 1)), garbage);
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) {
        if (layout == ColorLayout::interleaved_rgba) {
          for (int c = 0; c < 4; ++c)
            s.color[0][static_cast<std::size_t>(y * s.color_stride + 4 * x + c)] = column_color(c, x);
        } else {
          s.color[p][static_cast<std::size_t>(y * s.color_stride + x)] = column_color(p, x);
        }
      }
  }
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) s.depth_at(x, y) = 1.0f;
  return s;
}

float TargetFrame::color_at(int c, int x, int y) const {
  if (layout == ColorLayout::interleaved_rgba)
    return color[0][static_cast<std::size_t>(y * color_stride + 4 * x + c)];
  return color[c][static_cast<std::size_t>(y * color_stride + x)];
}

namespace {

// Is element i of a plane with `stride` and `row_elements` used elements per row inside the image?
bool inside(std::size_t i, std::ptrdiff_t stride, std::ptrdiff_t row_elements, int height) {
  const std::ptrdiff_t y = static_cast<std::ptrdiff_t>(i) / stride;
  const std::ptrdiff_t x = static_cast<std::ptrdiff_t>(i) % stride;
  return y < height && x < row_elements;
}

template <class T>
bool untouched(const std::vector<T>& v, T sentinel, std::ptrdiff_t stride, std::ptrdiff_t row_elements,
               int height, bool padding_only) {
  for (std::size_t i = 0; i < v.size(); ++i) {
    if (padding_only && inside(i, stride, row_elements, height)) continue;
    if (!(v[i] == sentinel)) return false;
  }
  return true;
}

}  // namespace

bool TargetFrame::padding_untouched() const {
  const bool interleaved = layout == ColorLayout::interleaved_rgba;
  const int planes = interleaved ? 1 : channels;
  for (int p = 0; p < planes; ++p)
    if (!untouched(color[p], kUntouched, color_stride, interleaved ? 4 * width : width, height, true))
      return false;
  return untouched(depth, kUntouched, stride, width, height, true) &&
         untouched(source_x, kUntouched, stride, width, height, true) &&
         untouched(status, kUntouchedStatus, stride, width, height, true);
}

bool TargetFrame::all_untouched() const {
  const int planes = layout == ColorLayout::interleaved_rgba ? 1 : channels;
  for (int p = 0; p < planes; ++p)
    if (!untouched(color[p], kUntouched, color_stride, 0, height, false)) return false;
  return untouched(depth, kUntouched, stride, 0, height, false) &&
         untouched(source_x, kUntouched, stride, 0, height, false) &&
         untouched(status, kUntouchedStatus, stride, 0, height, false);
}

reproject::TargetView TargetFrame::view() {
  reproject::TargetView view;
  if (layout == ColorLayout::interleaved_rgba) {
    view.color = reproject::MutableColorView::rgba(color[0].data(), width, height, color_stride);
  } else {
    view.color.layout = ColorLayout::planar;
    view.color.channels = channels;
    for (int c = 0; c < channels; ++c)
      view.color.plane[c] = reproject::MutableFloatPlane{color[c].data(), width, height, color_stride};
  }
  if (want_depth) view.depth = reproject::MutableFloatPlane{depth.data(), width, height, stride};
  if (want_status) view.status = reproject::BytePlane{status.data(), width, height, stride};
  if (want_source_x) view.source_x = reproject::MutableFloatPlane{source_x.data(), width, height, stride};
  return view;
}

TargetFrame make_target(int width, int height, int channels, ColorLayout layout, int pad) {
  TargetFrame t;
  t.width = width;
  t.height = height;
  t.layout = layout;
  t.channels = layout == ColorLayout::interleaved_rgba ? 4 : channels;
  t.stride = width + pad;
  t.color_stride = layout == ColorLayout::interleaved_rgba ? 4 * width + pad : t.stride;
  // One spare row beyond the last: a write past the frame lands there and is caught.
  const std::size_t rows = static_cast<std::size_t>(std::max(height, 0) + 1);
  const int planes = layout == ColorLayout::interleaved_rgba ? 1 : t.channels;
  for (int p = 0; p < planes; ++p) t.color[p].assign(static_cast<std::size_t>(t.color_stride) * rows, kUntouched);
  t.depth.assign(static_cast<std::size_t>(t.stride) * rows, kUntouched);
  t.source_x.assign(static_cast<std::size_t>(t.stride) * rows, kUntouched);
  t.status.assign(static_cast<std::size_t>(t.stride) * rows, kUntouchedStatus);
  return t;
}

RunResult run(const SourceFrame& source, const reproject::DepthDecoder& decoder,
        const reproject::ParallaxModel& model, const reproject::Options& options, int pad,
        bool want_depth, bool want_status, bool want_source_x) {
  RunResult r;
  r.out = make_target(source.width - 2 * options.guard, source.height, source.channels, source.layout, pad);
  r.out.want_depth = want_depth;
  r.out.want_status = want_status;
  r.out.want_source_x = want_source_x;
  r.status = reproject::reproject(source.view(), decoder, model, options, r.out.view());
  return r;
}

double ref_inverse_depth(DepthEncoding encoding, double n, double f, double d) {
  switch (encoding) {
    case DepthEncoding::linear: return 1.0 / d;
    case DepthEncoding::standard: return 1.0 / n + d * (n - f) / (n * f);
    case DepthEncoding::gl_ndc: return ((f + n) - d * (f - n)) / (2.0 * n * f);
    case DepthEncoding::reversed: return 1.0 / f + d * (f - n) / (n * f);
    case DepthEncoding::reversed_infinite: return d / n;
    case DepthEncoding::infinite: return (1.0 - d) / n;
    case DepthEncoding::disparity: return d;
  }
  return std::numeric_limits<double>::quiet_NaN();
}

double ref_stored_value(DepthEncoding encoding, double n, double f, double w) {
  switch (encoding) {
    case DepthEncoding::linear: return 1.0 / w;
    case DepthEncoding::standard: return (w - 1.0 / n) * (n * f) / (n - f);
    case DepthEncoding::gl_ndc: return ((f + n) - 2.0 * n * f * w) / (f - n);
    case DepthEncoding::reversed: return (w - 1.0 / f) * (n * f) / (f - n);
    case DepthEncoding::reversed_infinite: return w * n;
    case DepthEncoding::infinite: return 1.0 - w * n;
    case DepthEncoding::disparity: return w;
  }
  return std::numeric_limits<double>::quiet_NaN();
}

reproject::DepthDecoder Encoding::decoder() const {
  if (encoding == DepthEncoding::linear) return reproject::DepthDecoder::linear();
  if (encoding == DepthEncoding::disparity) return reproject::DepthDecoder::disparity();
  return reproject::DepthDecoder::from_near_far(encoding, near_plane, far_plane);
}

std::vector<double> ref_parallax_row(const SourceFrame& source, int y, const Encoding& encoding,
                                     const reproject::ParallaxModel& model) {
  std::vector<double> p(static_cast<std::size_t>(source.width));
  for (int x = 0; x < source.width; ++x)
    p[static_cast<std::size_t>(x)] =
        static_cast<double>(model.a) + static_cast<double>(model.b) * encoding.w(source.depth_at(x, y));
  return p;
}

double interp_clamped(const std::vector<double>& p, double x) {
  const int w = static_cast<int>(p.size());
  if (x <= 0.0) return p.front();
  if (x >= w - 1) return p.back();
  const int j = static_cast<int>(std::floor(x));
  const double f = x - j;
  return (1.0 - f) * p[static_cast<std::size_t>(j)] + f * p[static_cast<std::size_t>(j + 1)];
}

double depth_interp(const SourceFrame& source, int y, const Encoding& encoding, double x) {
  const int w = source.width;
  const double xc = std::min(std::max(x, 0.0), static_cast<double>(w - 1));
  const int j = static_cast<int>(std::floor(xc));
  if (j >= w - 1) return source.depth_at(w - 1, y);
  const double f = xc - j;
  const double d0 = source.depth_at(j, y);
  const double d1 = source.depth_at(j + 1, y);
  if (encoding.encoding == DepthEncoding::linear) return 1.0 / ((1.0 - f) / d0 + f / d1);
  return (1.0 - f) * d0 + f * d1;
}

void Tally::fail(const char* format, ...) {
  ++count_;
  if (count_ > 8) return;  // the first few say enough
  char line[512];
  va_list args;
  va_start(args, format);
  std::vsnprintf(line, sizeof line, format, args);
  va_end(args);
  report_ += "\n  ";
  report_ += line;
}

}  // namespace rptest
