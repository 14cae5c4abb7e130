// Image quality: PSNR and SSIM of an image against a reference, over float32 or 8-bit samples of
// any layout (H x W, H x W x C interleaved, C planes), with an optional mask of the pixels scored.
// docs/QUALITY.md defines both figures exactly; SSIM is the one scikit-image's
// structural_similarity computes with gaussian_weights=True, sigma=1.5,
// use_sample_covariance=False.
//
// Like the rest of the library, every call validates its inputs completely, returns a Status
// (nothing throws) and writes its result only on success. SSIM allocates its working rows (66
// rows of doubles of the width, never a whole image) once per call; PSNR allocates nothing.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>

#include "reproject/image.hpp"
#include "reproject/status.hpp"

namespace reproject {

// The samples of one image: height x width pixels of `channels` values each. Value c of pixel
// (x, y) is data[y * row_stride + x * pixel_stride + c * channel_stride]. Strides are in elements
// (not bytes), like PlaneView's. A stride must be >= 1 when its dimension has more than one entry
// (a stride of 0 would read one value as many: it is refused as a view left unset) and is ignored
// otherwise; the last value's offset must fit in ptrdiff_t.
template <class T>
struct SampleView {
  const T* data = nullptr;
  int width = 0;
  int height = 0;
  int channels = 1;
  std::ptrdiff_t row_stride = 0;
  std::ptrdiff_t pixel_stride = 1;
  std::ptrdiff_t channel_stride = 1;

  // H x W x C, the channels of a pixel next to each other (RGB, RGBA): row_stride >= width * channels.
  static SampleView interleaved(const T* data, int width, int height, int channels, std::ptrdiff_t row_stride) noexcept {
    return SampleView{data, width, height, channels, row_stride, channels, 1};
  }
  // C planes of one allocation, plane c at data + c * plane_stride (Image's planar layout).
  static SampleView planar(const T* data, int width, int height, int channels, std::ptrdiff_t row_stride,
                           std::ptrdiff_t plane_stride) noexcept {
    return SampleView{data, width, height, channels, row_stride, 1, plane_stride};
  }
  // One channel: a plane.
  static SampleView plane(const PlaneView<const T>& p) noexcept {
    return SampleView{p.data, p.width, p.height, 1, p.stride, 1, 1};
  }
};

using FloatSamples = SampleView<float>;
using ByteSamples = SampleView<std::uint8_t>;

struct QualityOptions {
  // The pixels scored: nonzero bytes, one per pixel, the images' width and height. data null:
  // every pixel. PSNR averages the squared error over the mask's pixels; SSIM averages its map
  // over the mask's pixels inside the area where SSIM is defined (kSsimRadius from each border).
  PlaneView<const std::uint8_t> mask;
  // The range of the values: PSNR's peak and SSIM's L (C1 = (K1 L)^2, C2 = (K2 L)^2); finite and
  // > 0. Unset: 1 for float samples, 255 for 8-bit ones.
  std::optional<double> data_range;
};

// SSIM's constants (Wang et al. 2004, as scikit-image uses them with gaussian_weights=True): a
// Gaussian window of sigma 1.5 truncated at 3.5 sigma, radius int(3.5 * 1.5 + 0.5) = 5 (11 x 11).
constexpr double kSsimSigma = 1.5;
constexpr int kSsimRadius = 5;
constexpr double kSsimK1 = 0.01;
constexpr double kSsimK2 = 0.03;

// Peak signal-to-noise ratio of `a` against `b` in dB: 10 log10(L^2 / MSE), the mean squared
// difference taken over every channel of the scored pixels. +infinity when the images are equal
// there; NaN when a sample is NaN or infinite.
Status psnr(const FloatSamples& a, const FloatSamples& b, const QualityOptions& options, double* result) noexcept;
Status psnr(const ByteSamples& a, const ByteSamples& b, const QualityOptions& options, double* result) noexcept;

// Mean structural similarity of `a` and `b`: the SSIM map of each channel, computed from
// Gaussian-weighted means, variances and covariance (population, not sample) over the 11 x 11
// window, averaged over the scored pixels whose window lies inside the image, then over the
// channels. The images must be at least 11 x 11. 1 (to rounding) for equal images; NaN when a
// sample is NaN or infinite.
Status ssim(const FloatSamples& a, const FloatSamples& b, const QualityOptions& options, double* result) noexcept;
Status ssim(const ByteSamples& a, const ByteSamples& b, const QualityOptions& options, double* result) noexcept;

}  // namespace reproject
