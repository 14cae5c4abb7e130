// Image quality: PSNR and SSIM (include/reproject/metrics.hpp; the definitions are in
// docs/QUALITY.md).
//
// SSIM is computed in double, the precision scikit-image uses for 8-bit images: the variances are
// differences of large, nearly equal terms (E[x^2] - E[x]^2), and in float their rounding error
// where the values are near L (about 1e-7 L^2) is a part in 10^4 of C2 = 9e-4 L^2: as large as
// the agreement with scikit-image that docs/QUALITY.md states. The separable Gaussian runs over
// rows, then over columns through a ring of the last 11 filtered rows, so the working memory is
// 66 rows of doubles whatever the height, and every inner loop runs along a row with no
// dependence between columns, which the compiler vectorises for the baseline instruction set.
#include "reproject/metrics.hpp"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <type_traits>

#include "src/memory.hpp"

namespace reproject {
namespace {

constexpr int kRadius = kSsimRadius;
constexpr int kTaps = 2 * kRadius + 1;
constexpr std::ptrdiff_t kMaxOffset = std::numeric_limits<std::ptrdiff_t>::max();

template <class T>
constexpr double default_range() noexcept {
  return std::is_same<T, std::uint8_t>::value ? 255.0 : 1.0;
}

// *offset += (count - 1) * stride for a dimension of `count` entries, false when that overflows
// or the stride is unusable (negative, or 0 for more than one entry).
bool extend(std::ptrdiff_t* offset, int count, std::ptrdiff_t stride) noexcept {
  if (count <= 1) return true;
  if (stride < 1) return false;
  const std::ptrdiff_t steps = count - 1;
  if (stride > (kMaxOffset - *offset) / steps) return false;
  *offset += steps * stride;
  return true;
}

template <class T>
Status check_samples(const SampleView<T>& s, const char* fn, const char* name) noexcept {
  if (s.width < 0 || s.height < 0 || s.channels < 0)
    return Status(StatusCode::invalid_size, "%s: %s has a negative size %dx%dx%d", fn, name, s.width, s.height,
                  s.channels);
  if (s.width == 0 || s.height == 0 || s.channels == 0)
    return Status(StatusCode::invalid_size, "%s: %s is empty (%dx%dx%d): nothing to score", fn, name, s.width,
                  s.height, s.channels);
  if (s.data == nullptr) return Status(StatusCode::null_pointer, "%s: %s data is null", fn, name);
  struct Axis {
    const char* what;
    int count;
    std::ptrdiff_t stride;
  };
  const Axis axes[] = {{"row_stride", s.height, s.row_stride},
                       {"pixel_stride", s.width, s.pixel_stride},
                       {"channel_stride", s.channels, s.channel_stride}};
  for (const Axis& axis : axes) {
    if (axis.count > 1 && axis.stride < 1)
      return Status(StatusCode::invalid_stride, "%s: %s %s is %td for %d entries (must be >= 1 element)", fn, name,
                    axis.what, axis.stride, axis.count);
  }
  std::ptrdiff_t last = 0;
  for (const Axis& axis : axes) {
    if (!extend(&last, axis.count, axis.stride))
      return Status(StatusCode::invalid_stride,
                    "%s: %s strides (%td, %td, %td) for %dx%dx%d reach beyond the address range (ptrdiff_t)", fn,
                    name, s.row_stride, s.pixel_stride, s.channel_stride, s.width, s.height, s.channels);
  }
  return Status();
}

// Both images, the mask and the data range; on success *range is the range to use.
template <class T>
Status check_inputs(const SampleView<T>& a, const SampleView<T>& b, const QualityOptions& options, const char* fn,
                    double* range) noexcept {
  Status status = check_samples(a, fn, "a");
  if (!status) return status;
  status = check_samples(b, fn, "b");
  if (!status) return status;
  if (a.width != b.width || a.height != b.height || a.channels != b.channels)
    return Status(StatusCode::size_mismatch, "%s: a is %dx%dx%d but b is %dx%dx%d (width x height x channels)", fn,
                  a.width, a.height, a.channels, b.width, b.height, b.channels);
  const PlaneView<const std::uint8_t>& mask = options.mask;
  if (mask.data != nullptr) {
    if (mask.width != a.width || mask.height != a.height)
      return Status(StatusCode::size_mismatch, "%s: the mask is %dx%d but the images are %dx%d", fn, mask.width,
                    mask.height, a.width, a.height);
    if (mask.stride < mask.width)
      return Status(StatusCode::invalid_stride, "%s: mask stride %td is smaller than its width %d", fn, mask.stride,
                    mask.width);
    if (mask.height > 1 && mask.stride > (kMaxOffset - mask.width) / (mask.height - 1))
      return Status(StatusCode::invalid_stride, "%s: mask stride %td for %d rows reaches beyond the address range", fn,
                    mask.stride, mask.height);
  }
  *range = options.data_range ? *options.data_range : default_range<T>();
  if (!(std::isfinite(*range) && *range > 0.0))
    return Status(StatusCode::invalid_option, "%s: data_range %g must be finite and > 0", fn, *range);
  return Status();
}

// Mask pixels set in columns [x0, x1) of rows [y0, y1); every pixel when there is no mask.
long long count_set(const PlaneView<const std::uint8_t>& mask, int x0, int x1, int y0, int y1) noexcept {
  if (mask.data == nullptr) return static_cast<long long>(x1 - x0) * (y1 - y0);
  long long n = 0;
  for (int y = y0; y < y1; ++y) {
    const std::uint8_t* m = mask.row(y);
    for (int x = x0; x < x1; ++x) n += m[x] != 0;
  }
  return n;
}

// ---- PSNR --------------------------------------------------------------------------------------

template <class T>
Status psnr_of(const SampleView<T>& a, const SampleView<T>& b, const QualityOptions& options,
               double* result) noexcept {
  constexpr const char* fn = "psnr";
  if (result == nullptr) return Status(StatusCode::null_pointer, "%s: result is null", fn);
  double range = 0.0;
  Status status = check_inputs(a, b, options, fn, &range);
  if (!status) return status;
  const long long pixels = count_set(options.mask, 0, a.width, 0, a.height);
  if (pixels == 0) return Status(StatusCode::invalid_size, "%s: the mask has no pixel set: nothing to score", fn);

  // Four partial sums, so that the additions do not wait on each other.
  double sum[4] = {0.0, 0.0, 0.0, 0.0};
  for (int y = 0; y < a.height; ++y) {
    const std::uint8_t* m = options.mask.data != nullptr ? options.mask.row(y) : nullptr;
    for (int c = 0; c < a.channels; ++c) {
      const T* pa = a.data + y * a.row_stride + c * a.channel_stride;
      const T* pb = b.data + y * b.row_stride + c * b.channel_stride;
      for (int x = 0; x < a.width; ++x) {
        const double d = static_cast<double>(pa[x * a.pixel_stride]) - static_cast<double>(pb[x * b.pixel_stride]);
        if (m == nullptr || m[x] != 0) sum[x & 3] += d * d;
      }
    }
  }
  const double mse = (sum[0] + sum[1] + sum[2] + sum[3]) / (static_cast<double>(pixels) * a.channels);
  *result = mse == 0.0 ? std::numeric_limits<double>::infinity() : 10.0 * std::log10(range * range / mse);
  return Status();
}

// ---- SSIM --------------------------------------------------------------------------------------

// The window's weights as scipy.ndimage.gaussian_filter makes them (scikit-image's filter):
// exp(-x^2 / (2 sigma^2)) for x = -r..r, divided by their sum. weight[j] is the weight at
// distance j from the centre.
struct Window {
  double weight[kRadius + 1];
  Window() noexcept {
    double raw[kRadius + 1];
    double sum = 0.0;
    for (int j = 0; j <= kRadius; ++j) {
      raw[j] = std::exp(-0.5 / (kSsimSigma * kSsimSigma) * j * j);
      sum += j == 0 ? raw[j] : 2.0 * raw[j];
    }
    for (int j = 0; j <= kRadius; ++j) weight[j] = raw[j] / sum;
  }
};

// The five quantities SSIM filters: a, b, a^2, b^2, ab.
constexpr int kQuantities = 5;

// out[x] = the window over in[x .. x + 2r], centre in[x + r]: the centre first, then the pairs
// from the inside out (the order scipy's symmetric correlation uses).
void filter_row(const double* in, int out_width, const Window& w, double* out) noexcept {
  for (int x = 0; x < out_width; ++x) {
    const double* c = in + x + kRadius;
    double s = c[0] * w.weight[0];
    for (int j = 1; j <= kRadius; ++j) s += (c[-j] + c[j]) * w.weight[j];
    out[x] = s;
  }
}

// out[x] = the window down rows[0..2r][x], centre rows[r][x], in the order of filter_row. One
// pass with the eleven rows in named pointers, so that the compiler keeps the sum in a register
// and vectorises along x.
void filter_column(const double* const* rows, int width, const Window& w, double* __restrict out) noexcept {
  const double *r0 = rows[0], *r1 = rows[1], *r2 = rows[2], *r3 = rows[3], *r4 = rows[4], *r5 = rows[5];
  const double *r6 = rows[6], *r7 = rows[7], *r8 = rows[8], *r9 = rows[9], *r10 = rows[10];
  const double w0 = w.weight[0], w1 = w.weight[1], w2 = w.weight[2], w3 = w.weight[3], w4 = w.weight[4],
               w5 = w.weight[5];
  static_assert(kRadius == 5, "filter_column spells out the 11 taps");
  for (int x = 0; x < width; ++x) {
    double s = r5[x] * w0;
    s += (r4[x] + r6[x]) * w1;
    s += (r3[x] + r7[x]) * w2;
    s += (r2[x] + r8[x]) * w3;
    s += (r1[x] + r9[x]) * w4;
    s += (r0[x] + r10[x]) * w5;
    out[x] = s;
  }
}

// The SSIM map from the filtered a, b, a^2, b^2, ab (the terms of Wang et al. 2004, eq. 13, with
// population variances and covariance), into `out`.
void ssim_map(const double* const (&mean)[kQuantities], int width, double c1, double c2, double* out) noexcept {
  const double* ua = mean[0];
  const double* ub = mean[1];
  const double* uaa = mean[2];
  const double* ubb = mean[3];
  const double* uab = mean[4];
  for (int x = 0; x < width; ++x) {
    const double va = uaa[x] - ua[x] * ua[x], vb = ubb[x] - ub[x] * ub[x], vab = uab[x] - ua[x] * ub[x];
    const double a1 = 2.0 * ua[x] * ub[x] + c1, a2 = 2.0 * vab + c2;
    const double b1 = ua[x] * ua[x] + ub[x] * ub[x] + c1, b2 = va + vb + c2;
    out[x] = (a1 * a2) / (b1 * b2);
  }
}

// Sum of s[x] over the x with m[x] set (every x when m is null); NaN counts only where set.
double masked_sum(const double* s, const std::uint8_t* m, int n) noexcept {
  double sum[4] = {0.0, 0.0, 0.0, 0.0};
  if (m == nullptr) {
    for (int x = 0; x < n; ++x) sum[x & 3] += s[x];
  } else {
    for (int x = 0; x < n; ++x) sum[x & 3] += m[x] != 0 ? s[x] : 0.0;
  }
  return (sum[0] + sum[1]) + (sum[2] + sum[3]);
}

template <class T>
Status ssim_of(const SampleView<T>& a, const SampleView<T>& b, const QualityOptions& options,
               double* result) noexcept {
  constexpr const char* fn = "ssim";
  const detail::CallScope scope;
  if (result == nullptr) return Status(StatusCode::null_pointer, "%s: result is null", fn);
  double range = 0.0;
  Status status = check_inputs(a, b, options, fn, &range);
  if (!status) return status;
  const int width = a.width, height = a.height;
  if (width < kTaps || height < kTaps)
    return Status(StatusCode::invalid_size, "%s: the images are %dx%d; SSIM's %dx%d window needs at least %dx%d", fn,
                  width, height, kTaps, kTaps, kTaps, kTaps);
  // The map is defined where the window lies inside the image: kRadius from each border.
  const int inner_width = width - 2 * kRadius;
  const long long pixels = count_set(options.mask, kRadius, width - kRadius, kRadius, height - kRadius);
  if (pixels == 0)
    return Status(StatusCode::invalid_size,
                  "%s: the mask has no pixel set at least %d pixels from the border (where SSIM is defined)", fn,
                  kRadius);

  // Working rows: the five quantities of a source row (width each), the ring of the last kTaps
  // rows filtered along x, the window means and one row of the map (inner width each). Tried:
  // strips of 128 or 256 columns, to keep the ring in L1, made no measurable difference.
  const std::uint64_t doubles =
      static_cast<std::uint64_t>(kQuantities) * static_cast<std::uint64_t>(width) +
      static_cast<std::uint64_t>(kQuantities * (kTaps + 1) + 1) * static_cast<std::uint64_t>(inner_width);
  if (doubles > std::numeric_limits<std::size_t>::max() / sizeof(double))
    return Status(StatusCode::invalid_size, "%s: %dx%d needs more working memory than the address range", fn, width,
                  height);
  detail::Buffer<double> memory;  // the library's allocator (reproject/memory.hpp)
  if (!memory.reserve(static_cast<std::size_t>(doubles))) return detail::out_of_memory(fn, "SSIM's working rows");
  double* source[kQuantities];
  double* ring[kQuantities][kTaps];
  double* mean[kQuantities];
  double* next = memory.data();
  for (double*& row : source) {
    row = next;
    next += width;
  }
  for (auto& quantity : ring) {
    for (double*& row : quantity) {
      row = next;
      next += inner_width;
    }
  }
  for (double*& row : mean) {
    row = next;
    next += inner_width;
  }
  double* map = next;

  const Window window;
  const double c1 = (kSsimK1 * range) * (kSsimK1 * range), c2 = (kSsimK2 * range) * (kSsimK2 * range);
  double total = 0.0;
  for (int c = 0; c < a.channels; ++c) {
    for (int y = 0; y < height; ++y) {
      const T* pa = a.data + y * a.row_stride + c * a.channel_stride;
      const T* pb = b.data + y * b.row_stride + c * b.channel_stride;
      double* sa = source[0];
      double* sb = source[1];
      for (int x = 0; x < width; ++x) {
        sa[x] = static_cast<double>(pa[x * a.pixel_stride]);
        sb[x] = static_cast<double>(pb[x * b.pixel_stride]);
      }
      double* saa = source[2];
      double* sbb = source[3];
      double* sab = source[4];
      for (int x = 0; x < width; ++x) {
        saa[x] = sa[x] * sa[x];
        sbb[x] = sb[x] * sb[x];
        sab[x] = sa[x] * sb[x];
      }
      const int slot = y % kTaps;
      for (int q = 0; q < kQuantities; ++q) filter_row(source[q], inner_width, window, ring[q][slot]);
      if (y < kTaps - 1) continue;
      // Rows y - 2r .. y are in the ring: the map's row y - r.
      for (int q = 0; q < kQuantities; ++q) {
        const double* rows[kTaps];
        for (int k = 0; k < kTaps; ++k) rows[k] = ring[q][(y - (kTaps - 1) + k) % kTaps];
        filter_column(rows, inner_width, window, mean[q]);
      }
      ssim_map(mean, inner_width, c1, c2, map);
      const int map_y = y - kRadius;
      const std::uint8_t* m = options.mask.data != nullptr ? options.mask.row(map_y) + kRadius : nullptr;
      total += masked_sum(map, m, inner_width);
    }
  }
  *result = total / (static_cast<double>(pixels) * a.channels);
  return Status();
}

}  // namespace

Status psnr(const FloatSamples& a, const FloatSamples& b, const QualityOptions& options, double* result) noexcept {
  return psnr_of(a, b, options, result);
}
Status psnr(const ByteSamples& a, const ByteSamples& b, const QualityOptions& options, double* result) noexcept {
  return psnr_of(a, b, options, result);
}
Status ssim(const FloatSamples& a, const FloatSamples& b, const QualityOptions& options, double* result) noexcept {
  return ssim_of(a, b, options, result);
}
Status ssim(const ByteSamples& a, const ByteSamples& b, const QualityOptions& options, double* result) noexcept {
  return ssim_of(a, b, options, result);
}

}  // namespace reproject
