#include "quality.hpp"

#include <algorithm>
#include <cstdio>

#include "reproject/metrics.hpp"

namespace reproject::cli {
namespace {

// The colour channels of a planar Image (its planes are one allocation, plane_data(c) apart).
FloatSamples color_samples(const Image& image, int channels) {
  const std::ptrdiff_t plane = channels > 1 ? image.plane_data(1) - image.plane_data(0) : 0;
  return FloatSamples::planar(image.plane_data(0), image.width(), image.height(), channels, image.stride(), plane);
}

// Mean absolute error over the colour channels of the pixels with `visible` set; NaN for none.
double mean_absolute_error(const Image& a, const Image& b, int channels, const std::vector<std::uint8_t>& visible) {
  const int w = a.width(), h = a.height();
  double sum = 0.0;
  long n = 0;
  for (int y = 0; y < h; ++y) {
    const std::uint8_t* m = visible.data() + static_cast<std::size_t>(y) * w;
    for (int c = 0; c < channels; ++c) {
      const float* pa = a.plane_data(c) + y * a.stride();
      const float* pb = b.plane_data(c) + y * b.stride();
      for (int x = 0; x < w; ++x) {
        if (m[x]) sum += std::fabs(static_cast<double>(pa[x]) - pb[x]);
      }
    }
    for (int x = 0; x < w; ++x) n += m[x] != 0;
  }
  return n > 0 ? sum / (static_cast<double>(n) * channels) : NAN;
}

}  // namespace

Quality score(const Image& image, const Image& truth, const std::vector<std::uint8_t>& visible) {
  Quality q;
  const int channels = std::min({image.channels(), truth.channels(), 3});
  const FloatSamples a = color_samples(image, channels), b = color_samples(truth, channels);
  QualityOptions whole_frame;
  QualityOptions visible_only;
  visible_only.mask = PlaneView<const std::uint8_t>{visible.data(), image.width(), image.height(), image.width()};
  // The library refuses what has no figure (an empty mask, a frame smaller than SSIM's window):
  // the figure is then NaN, printed as nan and written as null.
  if (!psnr(a, b, visible_only, &q.psnr)) q.psnr = NAN;
  q.mae = mean_absolute_error(image, truth, channels, visible);
  if (!psnr(a, b, whole_frame, &q.psnr_frame)) q.psnr_frame = NAN;
  if (!ssim(a, b, whole_frame, &q.ssim_frame)) q.ssim_frame = NAN;
  return q;
}

std::string describe_whole_frame(const Options& options, double exact_hole, double exact_outside) {
  const char* holes = options.hole_fill == HoleFill::background   ? "filled from the background side"
                      : options.hole_fill == HoleFill::foreground ? "filled from the foreground side"
                                                                  : "left 0 (--fill none)";
  const char* outside = options.edge == EdgeMode::clamp    ? "clamped to the source's edge column"
                        : options.edge == EdgeMode::black  ? "black (--edge black)"
                        : options.edge == EdgeMode::mirror ? "mirrored at the source's edge"
                                                           : "left 0 (--edge none)";
  char text[320];
  std::snprintf(text, sizeof text,
                "whole frame (scored too): every pixel; holes (exact: %.2f %%) %s, pixels outside the source's view "
                "(exact: %.2f %%) %s\n",
                exact_hole, holes, exact_outside, outside);
  return text;
}

}  // namespace reproject::cli
