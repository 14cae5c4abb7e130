#include "imageio/stereo_views.hpp"

#include <algorithm>
#include <cmath>
#include <exception>
#include <new>
#include <string>

#include "imageio/file_util.hpp"

namespace reproject::io {

// Dubois' red-cyan matrices (see the header). Rows are output R, G, B; columns input r, g, b. Each
// row of [left | right] sums to 1 (to the published precision), so equal white in both eyes stays
// white.
const float kDuboisLeft[3][3] = {
    {0.456100f, 0.500484f, 0.176381f},
    {-0.0400822f, -0.0378246f, -0.0157589f},
    {-0.0152161f, -0.0205971f, -0.00546856f},
};
const float kDuboisRight[3][3] = {
    {-0.0434706f, -0.0879388f, -0.00155529f},
    {0.378476f, 0.73364f, -0.0184503f},
    {-0.0721527f, -0.112961f, 1.2264f},
};

namespace {

using detail::failure;
using detail::sample;

// A view the functions below can read: 1-4 planar channels or interleaved RGBA, non-empty, data
// present, strides covering a row, every plane the same size.
IoStatus check_view(const ColorView& view, const char* name) {
  const bool interleaved = view.layout == ColorLayout::interleaved_rgba;
  if (interleaved ? view.channels != 4 : (view.channels < 1 || view.channels > 4)) {
    return failure(IoError::invalid_argument, std::string(name) + " has " + std::to_string(view.channels) +
                                                  " channels (1-4 planar, or interleaved RGBA)");
  }
  const int width = view.plane[0].width;
  const int height = view.plane[0].height;
  if (width < 1 || height < 1) {
    return failure(IoError::invalid_argument, std::string(name) + " is empty (" + detail::size_text(width, height) + ")");
  }
  const int planes = interleaved ? 1 : view.channels;
  const std::ptrdiff_t floats_per_pixel = interleaved ? 4 : 1;
  for (int c = 0; c < planes; ++c) {
    const FloatPlane& plane = view.plane[c];
    if (plane.data == nullptr) {
      return failure(IoError::invalid_argument, std::string(name) + ": plane " + std::to_string(c) + " has no data");
    }
    if (plane.width != width || plane.height != height) {
      return failure(IoError::size_mismatch, std::string(name) + ": size mismatch: plane " + std::to_string(c) +
                                                 " is " + detail::size_text(plane.width, plane.height) +
                                                 ", plane 0 is " + detail::size_text(width, height));
    }
    if (plane.stride < floats_per_pixel * width) {
      return failure(IoError::invalid_argument, std::string(name) + ": plane " + std::to_string(c) + " has stride " +
                                                    std::to_string(plane.stride) + " < row of " +
                                                    std::to_string(floats_per_pixel * width) + " floats");
    }
  }
  return {};
}

IoStatus check_pair(const ColorView& a, const char* a_name, const ColorView& b, const char* b_name,
                    bool same_channels) {
  if (IoStatus status = check_view(a, a_name); !status) return status;
  if (IoStatus status = check_view(b, b_name); !status) return status;
  if (a.width() != b.width() || a.height() != b.height()) {
    return failure(IoError::size_mismatch, std::string("size mismatch: ") + a_name + " is " +
                                               detail::size_text(a.width(), a.height()) + ", " + b_name + " is " +
                                               detail::size_text(b.width(), b.height()));
  }
  if (same_channels && a.channels != b.channels) {
    return failure(IoError::invalid_argument, std::string("channel count mismatch: ") + a_name + " has " +
                                                  std::to_string(a.channels) + ", " + b_name + " has " +
                                                  std::to_string(b.channels));
  }
  return {};
}

IoStatus allocate(Image* out, int width, int height, int channels) {
  *out = Image(width, height, channels);
  if (out->empty()) return failure(IoError::out_of_memory, "out of memory for a " + detail::size_text(width, height) + " image");
  return {};
}

// Copies `view` into `out` at (x0, y0), squeezing 2:1 horizontally or vertically when asked: output
// pixel i is the mean of source pixels 2i and 2i + 1, or source pixel 2i alone when 2i + 1 is past
// the edge.
enum class Squeeze { none, horizontal, vertical };

void place(const ColorView& view, Squeeze squeeze, int x0, int y0, Image* out) {
  const int width = view.width();
  const int height = view.height();
  const int out_width = squeeze == Squeeze::horizontal ? (width + 1) / 2 : width;
  const int out_height = squeeze == Squeeze::vertical ? (height + 1) / 2 : height;
  for (int c = 0; c < view.channels; ++c) {
    const MutableFloatPlane plane = out->mutable_plane(c);
    for (int y = 0; y < out_height; ++y) {
      float* target = plane.row(y0 + y) + x0;
      for (int x = 0; x < out_width; ++x) {
        switch (squeeze) {
          case Squeeze::none: target[x] = sample(view, c, x, y); break;
          case Squeeze::horizontal: {
            const int x1 = std::min(2 * x + 1, width - 1);
            target[x] = 0.5f * (sample(view, c, 2 * x, y) + sample(view, c, x1, y));
            break;
          }
          case Squeeze::vertical: {
            const int y1 = std::min(2 * y + 1, height - 1);
            target[x] = 0.5f * (sample(view, c, x, 2 * y) + sample(view, c, x, y1));
            break;
          }
        }
      }
    }
  }
}

std::array<float, 3> rgb_at(const ColorView& view, int x, int y) noexcept {
  if (view.channels <= 2) {
    const float grey = sample(view, 0, x, y);
    return {grey, grey, grey};
  }
  return {sample(view, 0, x, y), sample(view, 1, x, y), sample(view, 2, x, y)};
}

// Clamp to [0, 255]; NaN to 0 (as write_png would store it).
float clamp_255(float value) noexcept {
  if (!(value > 0.0f)) return 0.0f;
  return value < 255.0f ? value : 255.0f;
}

float clamp_unit(float value) noexcept { return value < 0.0f ? 0.0f : (value > 1.0f ? 1.0f : value); }

IoStatus side_by_side_impl(const ColorView& left, const ColorView& right, Image* out, StereoPacking packing) {
  if (IoStatus status = check_pair(left, "left image", right, "right image", true); !status) return status;
  const bool half = packing == StereoPacking::half;
  const int eye_width = half ? (left.width() + 1) / 2 : left.width();
  if (IoStatus status = allocate(out, 2 * eye_width, left.height(), left.channels); !status) return status;
  const Squeeze squeeze = half ? Squeeze::horizontal : Squeeze::none;
  place(left, squeeze, 0, 0, out);
  place(right, squeeze, eye_width, 0, out);
  return {};
}

IoStatus top_bottom_impl(const ColorView& left, const ColorView& right, Image* out, StereoPacking packing) {
  if (IoStatus status = check_pair(left, "left image", right, "right image", true); !status) return status;
  const bool half = packing == StereoPacking::half;
  const int eye_height = half ? (left.height() + 1) / 2 : left.height();
  if (IoStatus status = allocate(out, left.width(), 2 * eye_height, left.channels); !status) return status;
  const Squeeze squeeze = half ? Squeeze::vertical : Squeeze::none;
  place(left, squeeze, 0, 0, out);
  place(right, squeeze, 0, eye_height, out);
  return {};
}

IoStatus anaglyph_impl(const ColorView& left, const ColorView& right, Image* out, AnaglyphMethod method) {
  if (IoStatus status = check_pair(left, "left image", right, "right image", false); !status) return status;
  const int width = left.width();
  const int height = left.height();
  if (IoStatus status = allocate(out, width, height, 3); !status) return status;
  const MutableFloatPlane planes[3] = {out->mutable_plane(0), out->mutable_plane(1), out->mutable_plane(2)};
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const std::array<float, 3> l = rgb_at(left, x, y);
      const std::array<float, 3> r = rgb_at(right, x, y);
      if (method == AnaglyphMethod::plain) {
        planes[0].row(y)[x] = l[0];
        planes[1].row(y)[x] = r[1];
        planes[2].row(y)[x] = r[2];
        continue;
      }
      for (int k = 0; k < 3; ++k) {
        float sum = 0.0f;
        for (int c = 0; c < 3; ++c) sum += kDuboisLeft[k][c] * l[c] + kDuboisRight[k][c] * r[c];
        planes[k].row(y)[x] = clamp_255(sum);
      }
    }
  }
  return {};
}

IoStatus status_image_impl(const PlaneView<const std::uint8_t>& status, Image* out) {
  if (status.data == nullptr || status.width < 1 || status.height < 1) {
    return failure(IoError::invalid_argument,
                   "status plane is empty (" + detail::size_text(status.width, status.height) + ") or has no data");
  }
  if (status.stride < status.width) {
    return failure(IoError::invalid_argument, "status plane has stride " + std::to_string(status.stride) +
                                                  " < width " + std::to_string(status.width));
  }
  if (IoStatus result = allocate(out, status.width, status.height, 3); !result) return result;
  for (int y = 0; y < status.height; ++y) {
    const std::uint8_t* source = status.row(y);
    for (int x = 0; x < status.width; ++x) {
      const std::array<float, 3> color = status_color(source[x]);
      for (int c = 0; c < 3; ++c) out->mutable_plane(c).row(y)[x] = color[static_cast<std::size_t>(c)];
    }
  }
  return {};
}

float pixel_error(const ColorView& a, const ColorView& b, int x, int y) noexcept {
  float error = 0.0f;
  for (int c = 0; c < a.channels; ++c) {
    const float difference = std::fabs(sample(a, c, x, y) - sample(b, c, x, y));
    if (std::isnan(difference)) return difference;  // std::max would drop it
    error = std::max(error, difference);
  }
  return error;
}

IoStatus error_heat_map_impl(const ColorView& a, const ColorView& b, Image* out, float max_error) {
  if (!(max_error >= 0.0f) || !std::isfinite(max_error)) {
    return failure(IoError::invalid_argument,
                   "heat map maximum error " + std::to_string(max_error) + " (> 0, or 0 for the image's largest)");
  }
  if (IoStatus status = check_pair(a, "first image", b, "second image", true); !status) return status;
  const int width = a.width();
  const int height = a.height();
  float scale = max_error;
  if (scale == 0.0f) {
    for (int y = 0; y < height; ++y) {
      for (int x = 0; x < width; ++x) {
        const float error = pixel_error(a, b, x, y);
        if (std::isfinite(error)) scale = std::max(scale, error);
      }
    }
  }
  if (IoStatus status = allocate(out, width, height, 3); !status) return status;
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const float error = pixel_error(a, b, x, y);
      // scale == 0: every finite error is 0, drawn black; inf stays white, NaN magenta.
      const float t = scale > 0.0f ? error / scale : (error > 0.0f ? 1.0f : error * 0.0f);
      const std::array<float, 3> color = heat_color(t);
      for (int c = 0; c < 3; ++c) out->mutable_plane(c).row(y)[x] = color[static_cast<std::size_t>(c)];
    }
  }
  return {};
}

// Runs `body`, turning the exceptions a std::string can throw into an IoStatus and leaving `*out`
// empty on failure.
template <class Body>
IoStatus guarded(Image* out, const char* what, Body body) {
  if (out == nullptr) return failure(IoError::invalid_argument, std::string(what) + ": null output");
  try {
    IoStatus status = body();
    if (!status) *out = Image();
    return status;
  } catch (const std::bad_alloc&) {
    *out = Image();
    return failure(IoError::out_of_memory, std::string(what) + ": out of memory");
  }
}

}  // namespace

IoStatus side_by_side(const ColorView& left, const ColorView& right, Image* out, StereoPacking packing) {
  return guarded(out, "side_by_side", [&] { return side_by_side_impl(left, right, out, packing); });
}

IoStatus top_bottom(const ColorView& left, const ColorView& right, Image* out, StereoPacking packing) {
  return guarded(out, "top_bottom", [&] { return top_bottom_impl(left, right, out, packing); });
}

IoStatus anaglyph(const ColorView& left, const ColorView& right, Image* out, AnaglyphMethod method) {
  return guarded(out, "anaglyph", [&] { return anaglyph_impl(left, right, out, method); });
}

std::array<float, 3> status_color(std::uint8_t status) noexcept {
  switch (status) {
    case 0: return {0.0f, 0.0f, 0.0f};        // hit
    case 1: return {255.0f, 0.0f, 0.0f};      // hole
    case 2: return {0.0f, 128.0f, 255.0f};    // outside
    case 3: return {255.0f, 255.0f, 0.0f};    // clipped
    default: return {255.0f, 0.0f, 255.0f};   // not a PixelStatus
  }
}

IoStatus status_image(const PlaneView<const std::uint8_t>& status, Image* out) {
  return guarded(out, "status_image", [&] { return status_image_impl(status, out); });
}

std::array<float, 3> heat_color(float t) noexcept {
  if (std::isnan(t)) return {255.0f, 0.0f, 255.0f};
  const float s = 3.0f * clamp_unit(t);
  return {255.0f * clamp_unit(s), 255.0f * clamp_unit(s - 1.0f), 255.0f * clamp_unit(s - 2.0f)};
}

IoStatus error_heat_map(const ColorView& a, const ColorView& b, Image* out, float max_error) {
  return guarded(out, "error_heat_map", [&] { return error_heat_map_impl(a, b, out, max_error); });
}

}  // namespace reproject::io
