// PSNR and SSIM (include/reproject/metrics.hpp): figures of scikit-image's structural_similarity,
// closed forms that pin the window, the constants, the crop and the data range, layouts that must
// give the same bits, and every error.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <vector>

#include "reproject/metrics.hpp"

namespace reproject {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// A 23 x 17 RGB pair whose SSIM moves with every parameter: a dark red channel (luminance term
// and K1 matter), smooth green and blue with a texture, b a perturbed copy of a.
constexpr int kW = 23, kH = 17, kC = 3;
struct Pair {
  std::vector<std::uint8_t> a, b;  // H x W x C interleaved
};
Pair test_pair() {
  Pair p;
  p.a.resize(kW * kH * kC);
  p.b.resize(p.a.size());
  for (int y = 0; y < kH; ++y) {
    for (int x = 0; x < kW; ++x) {
      for (int c = 0; c < kC; ++c) {
        int a = 40 + x * 4 + y * 3 + c * 25 + (x * y + c) % 5 * 6;
        int b = std::min(255, std::max(0, a + (x * 7 + y * 11 + c * 3) % 13 * 4 - 24));
        if (c == 0) {
          a = (x + 2 * y) % 9 + 2;
          b = (x * 3 + y) % 7 + 5;
        }
        p.a[(y * kW + x) * kC + c] = static_cast<std::uint8_t>(a);
        p.b[(y * kW + x) * kC + c] = static_cast<std::uint8_t>(b);
      }
    }
  }
  return p;
}

ByteSamples rgb(const std::vector<std::uint8_t>& v) { return ByteSamples::interleaved(v.data(), kW, kH, kC, kW * kC); }

double ssim_of(const ByteSamples& a, const ByteSamples& b, const QualityOptions& options = {}) {
  double s = NAN;
  const Status status = ssim(a, b, options, &s);
  EXPECT_TRUE(status.ok()) << status.message();
  return s;
}
double ssim_of(const FloatSamples& a, const FloatSamples& b, const QualityOptions& options = {}) {
  double s = NAN;
  const Status status = ssim(a, b, options, &s);
  EXPECT_TRUE(status.ok()) << status.message();
  return s;
}
template <class T>
double psnr_of(const SampleView<T>& a, const SampleView<T>& b, const QualityOptions& options = {}) {
  double s = NAN;
  const Status status = psnr(a, b, options, &s);
  EXPECT_TRUE(status.ok()) << status.message();
  return s;
}

// ---- Against scikit-image --------------------------------------------------------------------
//
// The figures below are scikit-image 0.19.3's (Debian 12's python3-skimage), printed with %.17g
// from float64 copies of the same samples (so that they carry no float32 rounding of its own):
//
//   y, x, c = np.mgrid[0:17, 0:23, 0:3]
//   a = 40 + x * 4 + y * 3 + c * 25 + (x * y + c) % 5 * 6
//   b = np.clip(a + (x * 7 + y * 11 + c * 3) % 13 * 4 - 24, 0, 255)
//   a[..., 0] = (x[..., 0] + 2 * y[..., 0]) % 9 + 2;  b[..., 0] = (x[..., 0] * 3 + y[..., 0]) % 7 + 5
//   ssim = lambda a, b, r, **k: structural_similarity(a.astype(np.float64), b.astype(np.float64),
//       gaussian_weights=True, sigma=1.5, use_sample_covariance=False, data_range=r, **k)
//   ssim(a, b, 255, channel_axis=2); ssim(af, bf, 1.0, channel_axis=2) with af = (a / 255).astype(np.float32);
//   ssim(a[..., 1], b[..., 1], 255); ssim(a, b, 100, channel_axis=2);
//   _, s = ssim(a, b, 255, channel_axis=2, full=True); s[5:-5, 5:-5][mask[5:-5, 5:-5]].mean()
//       with mask = (x[..., 0] + 2 * y[..., 0]) % 3 == 0
//
// How far each figure moves when one thing is wrong (same images): radius 6 instead of 5
// (truncate 4.0): +1.8e-4; sigma 1.4: -9.4e-3; K1 = 0.02: +1.7e-3; K1 = 0: -7.0e-4; K2 = 0.02:
// -6.4e-2; data range 256: +6.0e-4; data range 1: -0.31; crop 4: +3.5e-4; crop 6: -1.1e-4;
// sample covariance: -4e-4. The tolerance, 1e-9, is far below all of them.
constexpr double kSkimageRgb = 0.64165420435993681;
constexpr double kSkimageRgbFloat = 0.64165419990115358;
constexpr double kSkimageGreen = 0.56977263659485822;
constexpr double kSkimageRgbRange100 = 0.48398603645702171;
constexpr double kSkimageRgbMasked = 0.64149707587021831;
constexpr double kTolerance = 1e-9;

TEST(MetricsSsim, MatchesScikitImageOnRgbBytes) {
  const Pair p = test_pair();
  EXPECT_NEAR(ssim_of(rgb(p.a), rgb(p.b)), kSkimageRgb, kTolerance);
}

TEST(MetricsSsim, MatchesScikitImageOnFloatsWithTheDefaultRangeOfOne) {
  const Pair p = test_pair();
  std::vector<float> a(p.a.size()), b(p.b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    a[i] = static_cast<float>(p.a[i] / 255.0);
    b[i] = static_cast<float>(p.b[i] / 255.0);
  }
  EXPECT_NEAR(ssim_of(FloatSamples::interleaved(a.data(), kW, kH, kC, kW * kC),
                      FloatSamples::interleaved(b.data(), kW, kH, kC, kW * kC)),
              kSkimageRgbFloat, kTolerance);
}

TEST(MetricsSsim, MatchesScikitImageOnOneChannelOfAnInterleavedImage) {
  const Pair p = test_pair();
  // The green channel read in place: pixel stride 3, starting at the second byte.
  const ByteSamples a{p.a.data() + 1, kW, kH, 1, kW * kC, kC, 1};
  const ByteSamples b{p.b.data() + 1, kW, kH, 1, kW * kC, kC, 1};
  EXPECT_NEAR(ssim_of(a, b), kSkimageGreen, kTolerance);
}

TEST(MetricsSsim, MatchesScikitImageWithAnExplicitDataRange) {
  const Pair p = test_pair();
  QualityOptions options;
  options.data_range = 100.0;
  EXPECT_NEAR(ssim_of(rgb(p.a), rgb(p.b), options), kSkimageRgbRange100, kTolerance);
}

TEST(MetricsSsim, MaskAveragesScikitImagesMapOverItsPixelsInsideTheCrop) {
  const Pair p = test_pair();
  std::vector<std::uint8_t> mask(kW * kH);
  for (int y = 0; y < kH; ++y) {
    for (int x = 0; x < kW; ++x) mask[y * kW + x] = (x + 2 * y) % 3 == 0 ? 7 : 0;  // any nonzero byte counts
  }
  QualityOptions options;
  options.mask = PlaneView<const std::uint8_t>{mask.data(), kW, kH, kW};
  EXPECT_NEAR(ssim_of(rgb(p.a), rgb(p.b), options), kSkimageRgbMasked, kTolerance);
}

TEST(MetricsSsim, FloatAndByteSamplesOfTheSameValuesGiveTheSameBits) {
  const Pair p = test_pair();
  std::vector<float> a(p.a.begin(), p.a.end()), b(p.b.begin(), p.b.end());
  QualityOptions range255;
  range255.data_range = 255.0;
  EXPECT_EQ(ssim_of(FloatSamples::interleaved(a.data(), kW, kH, kC, kW * kC),
                    FloatSamples::interleaved(b.data(), kW, kH, kC, kW * kC), range255),
            ssim_of(rgb(p.a), rgb(p.b)));
}

// ---- Closed forms ------------------------------------------------------------------------------

// The window as the definition states it (docs/QUALITY.md): exp(-k^2 / (2 * 1.5^2)) for
// k = -5..5, normalised; weight2d(dx, dy) = w(dx) w(dy).
double weight2d(int dx, int dy) {
  double sum = 0.0;
  for (int k = -5; k <= 5; ++k) sum += std::exp(-k * k / 4.5);
  return std::exp(-dx * dx / 4.5) / sum * std::exp(-dy * dy / 4.5) / sum;
}

// a = 0 everywhere, b = 1 at one pixel: at a map pixel whose window gives the impulse weight g,
// mu_a = 0, mu_b = g, var_a = 0, var_b = g - g^2, cov = 0, so SSIM = C1 C2 / ((g^2 + C1)(g - g^2 + C2));
// where the window misses the impulse, C1 C2 / (C1 C2) = 1. The mean over the crop weighs every one of the 121
// weights, so a wrong window (sigma, radius, normalisation) moves it.
double impulse_ssim(int width, int height, int ix, int iy) {
  const double c1 = 0.01 * 0.01, c2 = 0.03 * 0.03;
  double sum = 0.0;
  int n = 0;
  for (int y = 5; y < height - 5; ++y) {
    for (int x = 5; x < width - 5; ++x) {
      ++n;
      const int dx = ix - x, dy = iy - y;
      if (std::abs(dx) > 5 || std::abs(dy) > 5) {
        sum += 1.0;
        continue;
      }
      const double g = weight2d(dx, dy);
      sum += c1 * c2 / ((g * g + c1) * (g - g * g + c2));
    }
  }
  return sum / n;
}

TEST(MetricsSsim, ImpulseFollowsTheGaussianWindow) {
  const int w = 21, h = 21;
  std::vector<float> a(w * h, 0.0f), b(w * h, 0.0f);
  b[10 * w + 10] = 1.0f;
  const double expected = impulse_ssim(w, h, 10, 10);
  EXPECT_NEAR(ssim_of(FloatSamples::interleaved(a.data(), w, h, 1, w), FloatSamples::interleaved(b.data(), w, h, 1, w)),
              expected, 1e-12);
  EXPECT_LT(expected, 0.5);  // far from 1: the window's weights decide it
}

TEST(MetricsSsim, OnlyPixelsFiveFromTheBorderAreAveraged) {
  // The impulse two pixels from the left border: its window reaches map columns 0..7, of which
  // only 5, 6 and 7 are inside the crop. A crop of 4 or 6 would count other pixels.
  const int w = 21, h = 19;
  std::vector<float> a(w * h, 0.0f), b(w * h, 0.0f);
  b[9 * w + 2] = 1.0f;
  const double got =
      ssim_of(FloatSamples::interleaved(a.data(), w, h, 1, w), FloatSamples::interleaved(b.data(), w, h, 1, w));
  EXPECT_NEAR(got, impulse_ssim(w, h, 2, 9), 1e-12);
  EXPECT_GT(std::fabs(got - 1.0), 1e-3);  // the three columns inside the crop do count
}

// Flat images: the variances and covariance are 0, so SSIM is the luminance term alone,
// (2 a b + C1) / (a^2 + b^2 + C1) with C1 = (0.01 L)^2: K1 and the data range L, pinned.
double luminance(double a, double b, double range) {
  const double c1 = (0.01 * range) * (0.01 * range);
  return (2 * a * b + c1) / (a * a + b * b + c1);
}

TEST(MetricsSsim, FlatImagesGiveTheLuminanceTermWithTheDataRange) {
  const int w = 16, h = 12;
  std::vector<float> a(w * h, 0.05f), b(w * h, 0.02f);
  const FloatSamples fa = FloatSamples::interleaved(a.data(), w, h, 1, w), fb = FloatSamples::interleaved(b.data(), w, h, 1, w);
  EXPECT_NEAR(ssim_of(fa, fb), luminance(0.05f, 0.02f, 1.0), 1e-12);  // default range 1
  QualityOptions range4;
  range4.data_range = 4.0;
  EXPECT_NEAR(ssim_of(fa, fb, range4), luminance(0.05f, 0.02f, 4.0), 1e-12);
  EXPECT_GT(std::fabs(luminance(0.05f, 0.02f, 1.0) - luminance(0.05f, 0.02f, 4.0)), 0.1);

  std::vector<std::uint8_t> ba(w * h, 12), bb(w * h, 5);
  EXPECT_NEAR(ssim_of(ByteSamples::interleaved(ba.data(), w, h, 1, w), ByteSamples::interleaved(bb.data(), w, h, 1, w)),
              luminance(12, 5, 255.0), 1e-12);  // default range 255
}

TEST(MetricsSsim, ChannelsAreAveraged) {
  // Channel 0 equal (SSIM 1), channel 1 flat and different (the luminance term).
  const int w = 13, h = 11;
  std::vector<float> a(w * h * 2), b(w * h * 2);
  for (int i = 0; i < w * h; ++i) {
    a[2 * i] = b[2 * i] = static_cast<float>((i * 7919) % 101) / 100.0f;
    a[2 * i + 1] = 0.5f;
    b[2 * i + 1] = 0.25f;
  }
  EXPECT_NEAR(ssim_of(FloatSamples::interleaved(a.data(), w, h, 2, 2 * w), FloatSamples::interleaved(b.data(), w, h, 2, 2 * w)),
              (1.0 + luminance(0.5, 0.25, 1.0)) / 2, 1e-12);
}

TEST(MetricsSsim, EqualImagesScoreOne) {
  const Pair p = test_pair();
  EXPECT_NEAR(ssim_of(rgb(p.a), rgb(p.a)), 1.0, 1e-12);
}

TEST(MetricsSsim, NaNSampleGivesNaN) {
  std::vector<float> a(12 * 12, 0.5f), b(12 * 12, 0.5f);
  b[6 * 12 + 6] = NAN;
  EXPECT_TRUE(std::isnan(ssim_of(FloatSamples::interleaved(a.data(), 12, 12, 1, 12), FloatSamples::interleaved(b.data(), 12, 12, 1, 12))));
}

// ---- Layouts -----------------------------------------------------------------------------------

TEST(MetricsLayouts, InterleavedPlanarPaddedAndRgbaViewsGiveTheSameBits) {
  const Pair p = test_pair();
  const double reference_ssim = ssim_of(rgb(p.a), rgb(p.b));
  const double reference_psnr = psnr_of(rgb(p.a), rgb(p.b));
  // Planes with padded rows (stride 29), one allocation.
  const int stride = 29;
  std::vector<std::uint8_t> pa(stride * kH * kC, 0xEE), pb(pa.size(), 0x11);
  // RGBA with padded rows (stride 100 bytes), alpha not read.
  const int rgba_stride = 100;
  std::vector<std::uint8_t> qa(rgba_stride * kH, 0xEE), qb(qa.size(), 0x11);
  for (int y = 0; y < kH; ++y) {
    for (int x = 0; x < kW; ++x) {
      for (int c = 0; c < kC; ++c) {
        pa[c * stride * kH + y * stride + x] = p.a[(y * kW + x) * kC + c];
        pb[c * stride * kH + y * stride + x] = p.b[(y * kW + x) * kC + c];
        qa[y * rgba_stride + x * 4 + c] = p.a[(y * kW + x) * kC + c];
        qb[y * rgba_stride + x * 4 + c] = p.b[(y * kW + x) * kC + c];
      }
    }
  }
  const ByteSamples planar_a = ByteSamples::planar(pa.data(), kW, kH, kC, stride, stride * kH);
  const ByteSamples planar_b = ByteSamples::planar(pb.data(), kW, kH, kC, stride, stride * kH);
  const ByteSamples rgba_a{qa.data(), kW, kH, kC, rgba_stride, 4, 1};
  const ByteSamples rgba_b{qb.data(), kW, kH, kC, rgba_stride, 4, 1};
  EXPECT_EQ(ssim_of(planar_a, planar_b), reference_ssim);
  EXPECT_EQ(ssim_of(rgba_a, rgba_b), reference_ssim);
  EXPECT_EQ(ssim_of(planar_a, rgba_b), reference_ssim);  // a and b need not share a layout
  EXPECT_EQ(psnr_of(planar_a, planar_b), reference_psnr);
  EXPECT_EQ(psnr_of(rgba_a, rgba_b), reference_psnr);
}

// ---- PSNR --------------------------------------------------------------------------------------

TEST(MetricsPsnr, ConstantDifferenceGivesTheClosedForm) {
  const int w = 7, h = 5;
  std::vector<float> a(w * h, 0.5f), b(w * h, 0.625f);  // difference 1/8 exactly: MSE 1/64
  const FloatSamples fa = FloatSamples::interleaved(a.data(), w, h, 1, w), fb = FloatSamples::interleaved(b.data(), w, h, 1, w);
  EXPECT_NEAR(psnr_of(fa, fb), 10 * std::log10(64.0), 1e-12);  // 18.06 dB, range 1
  QualityOptions range2;
  range2.data_range = 2.0;
  EXPECT_NEAR(psnr_of(fa, fb, range2), 10 * std::log10(4.0 * 64.0), 1e-12);

  std::vector<std::uint8_t> ba(w * h, 100), bb(w * h, 105);
  EXPECT_NEAR(psnr_of(ByteSamples::interleaved(ba.data(), w, h, 1, w), ByteSamples::interleaved(bb.data(), w, h, 1, w)),
              10 * std::log10(255.0 * 255.0 / 25.0), 1e-12);  // 34.15 dB, range 255
}

TEST(MetricsPsnr, MaskAndChannelsWeighEverySampleOnce) {
  // Two channels; the left half differs by 10 in channel 0 only; the right half is equal.
  const int w = 8, h = 3;
  std::vector<std::uint8_t> a(w * h * 2, 50), b(w * h * 2, 50), left(w * h, 0), right(w * h, 0);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      if (x < w / 2) b[(y * w + x) * 2] = 60;
      (x < w / 2 ? left : right)[y * w + x] = 1;
    }
  }
  const ByteSamples va = ByteSamples::interleaved(a.data(), w, h, 2, 2 * w), vb = ByteSamples::interleaved(b.data(), w, h, 2, 2 * w);
  EXPECT_NEAR(psnr_of(va, vb), 10 * std::log10(255.0 * 255.0 / (100.0 / 4)), 1e-12);  // 1 sample in 4 differs
  QualityOptions options;
  options.mask = PlaneView<const std::uint8_t>{left.data(), w, h, w};
  EXPECT_NEAR(psnr_of(va, vb, options), 10 * std::log10(255.0 * 255.0 / (100.0 / 2)), 1e-12);
  options.mask.data = right.data();
  EXPECT_EQ(psnr_of(va, vb, options), kInf);  // equal where scored
}

TEST(MetricsPsnr, MatchesTheFormulaOnTestImages) {
  const Pair p = test_pair();
  double se = 0.0;
  for (std::size_t i = 0; i < p.a.size(); ++i) se += (p.a[i] - p.b[i]) * (p.a[i] - p.b[i]);
  EXPECT_NEAR(psnr_of(rgb(p.a), rgb(p.b)), 10 * std::log10(255.0 * 255.0 * p.a.size() / se), 1e-12);
}

// ---- Errors ------------------------------------------------------------------------------------

struct Failure {
  StatusCode code;
  const char* says;
};

template <class T>
void expect_both_fail(const SampleView<T>& a, const SampleView<T>& b, const QualityOptions& options, Failure f) {
  for (bool is_ssim : {false, true}) {
    double result = 1234.5;
    const Status status = is_ssim ? ssim(a, b, options, &result) : psnr(a, b, options, &result);
    EXPECT_EQ(status.code(), f.code) << (is_ssim ? "ssim: " : "psnr: ") << status.message();
    EXPECT_NE(std::strstr(status.message(), f.says), nullptr) << status.message() << " lacks '" << f.says << "'";
    EXPECT_EQ(std::strncmp(status.message(), is_ssim ? "ssim: " : "psnr: ", 6), 0) << status.message();
    EXPECT_EQ(result, 1234.5) << "written on failure";
  }
}

TEST(MetricsErrors, EveryBadInputIsAStatusWithAMessage) {
  std::vector<float> data(64 * 64 * 3, 0.5f);
  const FloatSamples good = FloatSamples::interleaved(data.data(), 20, 20, 3, 60);
  QualityOptions none;

  FloatSamples v = good;
  v.data = nullptr;
  expect_both_fail(v, good, none, {StatusCode::null_pointer, "a data is null"});
  v = good;
  v.width = -1;
  expect_both_fail(good, v, none, {StatusCode::invalid_size, "b has a negative size -1x20x3"});
  v = good;
  v.height = 0;
  expect_both_fail(v, v, none, {StatusCode::invalid_size, "empty"});
  v = good;
  v.channels = 0;
  expect_both_fail(v, v, none, {StatusCode::invalid_size, "empty"});
  v = good;
  v.pixel_stride = 0;  // a view whose strides were left unset
  expect_both_fail(good, v, none, {StatusCode::invalid_stride, "pixel_stride is 0 for 20 entries"});
  v = good;
  v.row_stride = -60;
  expect_both_fail(v, good, none, {StatusCode::invalid_stride, "row_stride is -60"});
  v = good;
  v.channel_stride = 0;
  expect_both_fail(v, good, none, {StatusCode::invalid_stride, "channel_stride is 0"});
  v = good;
  v.row_stride = std::numeric_limits<std::ptrdiff_t>::max() / 10;  // 19 rows of that overflow
  expect_both_fail(v, good, none, {StatusCode::invalid_stride, "beyond the address range"});
  v = good;
  v.pixel_stride = std::numeric_limits<std::ptrdiff_t>::max() / 19 + 1;
  expect_both_fail(v, good, none, {StatusCode::invalid_stride, "beyond the address range"});
  v = good;
  v.width = 21;
  expect_both_fail(good, v, none, {StatusCode::size_mismatch, "a is 20x20x3 but b is 21x20x3"});
  v = good;
  v.channels = 1;
  expect_both_fail(good, v, none, {StatusCode::size_mismatch, "b is 20x20x1"});

  std::vector<std::uint8_t> mask(20 * 20, 1);
  QualityOptions o;
  o.mask = PlaneView<const std::uint8_t>{mask.data(), 19, 20, 20};
  expect_both_fail(good, good, o, {StatusCode::size_mismatch, "the mask is 19x20 but the images are 20x20"});
  o.mask = PlaneView<const std::uint8_t>{mask.data(), 20, 20, 19};
  expect_both_fail(good, good, o, {StatusCode::invalid_stride, "mask stride 19 is smaller than its width 20"});
  o.mask = PlaneView<const std::uint8_t>{mask.data(), 20, 20, std::numeric_limits<std::ptrdiff_t>::max() / 2};
  expect_both_fail(good, good, o, {StatusCode::invalid_stride, "mask stride"});
  std::vector<std::uint8_t> empty(20 * 20, 0);
  o.mask = PlaneView<const std::uint8_t>{empty.data(), 20, 20, 20};
  expect_both_fail(good, good, o, {StatusCode::invalid_size, "the mask has no pixel set"});

  for (double bad : {0.0, -1.0, static_cast<double>(NAN), kInf}) {
    QualityOptions r;
    r.data_range = bad;
    expect_both_fail(good, good, r, {StatusCode::invalid_option, "data_range"});
  }

  double result = 0.0;
  EXPECT_EQ(psnr(good, good, none, nullptr).code(), StatusCode::null_pointer);
  EXPECT_EQ(ssim(good, good, none, nullptr).code(), StatusCode::null_pointer);
  EXPECT_TRUE(psnr(good, good, none, &result).ok());
}

TEST(MetricsErrors, SsimNeedsAWholeWindowAndAMaskPixelInsideTheCrop) {
  std::vector<std::uint8_t> data(32 * 32, 9);
  double result = 5.0;
  const ByteSamples narrow = ByteSamples::interleaved(data.data(), 10, 30, 1, 10);
  Status status = ssim(narrow, narrow, {}, &result);
  EXPECT_EQ(status.code(), StatusCode::invalid_size);
  EXPECT_STREQ(status.message(), "ssim: the images are 10x30; SSIM's 11x11 window needs at least 11x11");
  EXPECT_TRUE(psnr(narrow, narrow, {}, &result).ok());  // PSNR has no window
  const ByteSamples smallest = ByteSamples::interleaved(data.data(), 11, 11, 1, 11);
  EXPECT_TRUE(ssim(smallest, smallest, {}, &result).ok());
  EXPECT_NEAR(result, 1.0, 1e-12);

  // A mask set only within 5 pixels of the border selects no pixel SSIM is defined at.
  const ByteSamples image = ByteSamples::interleaved(data.data(), 20, 20, 1, 20);
  std::vector<std::uint8_t> border(20 * 20, 0);
  for (int i = 0; i < 20; ++i) border[4 * 20 + i] = border[i * 20 + 15] = 1;
  QualityOptions o;
  o.mask = PlaneView<const std::uint8_t>{border.data(), 20, 20, 20};
  result = 5.0;
  status = ssim(image, image, o, &result);
  EXPECT_EQ(status.code(), StatusCode::invalid_size);
  EXPECT_NE(std::strstr(status.message(), "at least 5 pixels from the border"), nullptr) << status.message();
  EXPECT_EQ(result, 5.0);
  EXPECT_TRUE(psnr(image, image, o, &result).ok());
  border[10 * 20 + 14] = 1;  // the crop's last column
  EXPECT_TRUE(ssim(image, image, o, &result).ok());
}

}  // namespace
}  // namespace reproject
