// The stereo pipeline functions (include/reproject/stereo.hpp), each against an independent
// computation: DESIGN's formulas evaluated here in double, the stereo projection matrices that
// StereoCamera builds, and the ray-cast scenes (scene/), whose true depth and true eyes are
// known. The figures worth reading (PSNR with and without the halo filter, reconstruction
// errors, picking errors) are printed.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <random>
#include <thread>
#include <vector>

#include "reproject/depth.hpp"
#include "reproject/image.hpp"
#include "reproject/parallax.hpp"
#include "reproject/reproject.hpp"
#include "reproject/stereo.hpp"
#include "scene.hpp"

namespace reproject {
namespace {

namespace rs = reproject::scene;

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// ---------------------------------------------------------------------------------------------
// Shared helpers

// DESIGN §3's table, written out again in double: w = 1/z of a stored value.
double design_inverse_depth(DepthEncoding e, double d, double n, double f) {
  switch (e) {
    case DepthEncoding::linear:
      return 1.0 / d;
    case DepthEncoding::standard:
      return 1.0 / n + d * (n - f) / (n * f);
    case DepthEncoding::gl_ndc:
      return ((f + n) - d * (f - n)) / (2.0 * n * f);
    case DepthEncoding::reversed:
      return 1.0 / f + d * (f - n) / (n * f);
    case DepthEncoding::reversed_infinite:
      return d / n;
    case DepthEncoding::infinite:
      return (1.0 - d) / n;
    case DepthEncoding::disparity:
      return d;
  }
  return kNaN;
}

// docs/BEHAVIOUR.md: NaN and w < 0 are read as infinitely far.
double readable(double w) { return w >= 0.0 ? w : 0.0; }

// Order statistic at rank q (N - 1), linearly interpolated (the budget's documented definition).
double percentile_of_sorted(const std::vector<double>& sorted, double percent) {
  const double rank = percent / 100.0 * static_cast<double>(sorted.size() - 1);
  const std::size_t lo = static_cast<std::size_t>(std::floor(rank));
  const double frac = rank - static_cast<double>(lo);
  if (frac == 0.0 || lo + 1 >= sorted.size() || sorted[lo] == sorted[lo + 1]) return sorted[lo];
  return sorted[lo] + frac * (sorted[lo + 1] - sorted[lo]);
}

// Row-major 4x4 in double; D3D row-vector convention (clip = v P, P[r][c] = m[4r + c]).
struct Mat4 {
  double m[4][4] = {};
};

// D3DXMatrixPerspectiveOffCenterLH from a frustum's near-plane edges: standard depth (0 at near, 1 at
// far; far = inf gives the infinite form), or reversed (1 at near, 0 at far).
Mat4 d3d_perspective(const ViewFrustum& f, bool reversed = false) {
  const double l = f.left, r = f.right, b = f.bottom, t = f.top, n = f.near_plane, fa = f.far_plane;
  Mat4 P;
  P.m[0][0] = 2.0 * n / (r - l);
  P.m[1][1] = 2.0 * n / (t - b);
  P.m[2][0] = (l + r) / (l - r);
  P.m[2][1] = (t + b) / (b - t);
  P.m[2][3] = 1.0;
  if (reversed) {
    P.m[2][2] = n / (n - fa);
    P.m[3][2] = -fa * n / (n - fa);
  } else if (std::isinf(fa)) {
    P.m[2][2] = 1.0;
    P.m[3][2] = -n;
  } else {
    P.m[2][2] = fa / (fa - n);
    P.m[3][2] = -n * fa / (fa - n);
  }
  return P;
}

// D3DXMatrixOrthoOffCenterLH: z_ndc = (z - n) / (f - n).
Mat4 d3d_orthographic(const ViewFrustum& f) {
  const double l = f.left, r = f.right, b = f.bottom, t = f.top, n = f.near_plane, fa = f.far_plane;
  Mat4 P;
  P.m[0][0] = 2.0 / (r - l);
  P.m[1][1] = 2.0 / (t - b);
  P.m[2][2] = 1.0 / (fa - n);
  P.m[3][0] = (l + r) / (l - r);
  P.m[3][1] = (t + b) / (b - t);
  P.m[3][2] = n / (n - fa);
  P.m[3][3] = 1.0;
  return P;
}

void to_floats(const Mat4& P, float out[16]) {
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) out[4 * r + c] = static_cast<float>(P.m[r][c]);
}

Mat4 multiply(const Mat4& A, const Mat4& B) {
  Mat4 C;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      for (int k = 0; k < 4; ++k) C.m[i][j] += A.m[i][k] * B.m[k][j];
  return C;
}

// clip = (x, y, z, 1) M with a float matrix, evaluated in double.
void project_row(const float m[16], double x, double y, double z, double clip[4]) {
  const double v[4] = {x, y, z, 1.0};
  for (int c = 0; c < 4; ++c) {
    clip[c] = 0.0;
    for (int r = 0; r < 4; ++r) clip[c] += v[r] * static_cast<double>(m[4 * r + c]);
  }
}

// Whether an eye whose (float, D3D) matrix is m sees view point (x, y, z): inside its clip volume,
// with a relative tolerance for the float entries.
bool eye_sees(const float m[16], double x, double y, double z, double tol = 0.0) {
  double clip[4];
  project_row(m, x, y, z, clip);
  const double w = clip[3];
  if (!(w > 0.0)) return false;
  const double slack = tol * w;
  return std::fabs(clip[0]) <= w + slack && std::fabs(clip[1]) <= w + slack && clip[2] >= -slack &&
         clip[2] <= w + slack;
}

// The view point an eye's matrix puts at NDC (ndc_x, ndc_y) at distance z (clip.w = z for these
// matrices): solves clip.x = ndc_x z, clip.y = ndc_y z from the matrix entries alone.
void point_on_eye_ray(const float m[16], double ndc_x, double ndc_y, double z, double* x, double* y) {
  const double P00 = m[0], P11 = m[5], P20 = m[8], P21 = m[9], P30 = m[12], P31 = m[13];
  *y = (ndc_y * z - P21 * z - P31) / P11;
  *x = (ndc_x * z - P20 * z - P30) / P00;
}

double psnr(double squared_error_sum, double samples) {
  return squared_error_sum > 0.0 ? 10.0 * std::log10(samples / squared_error_sum) : kInf;
}

// ---------------------------------------------------------------------------------------------
// 1. Parallax budget

struct BudgetCase {
  DepthEncoding encoding;
  StereoCamera camera;
};

TEST(PipelineBudget, PercentilesMatchSortOfDesignParallax) {
  const rs::Scene scene = rs::Scene::make(rs::SceneId::room);
  const int width = 320, height = 180;
  rs::View view;
  ASSERT_TRUE(scene.render(scene.camera(width, height, rs::kCentreEye), &view, 2).ok());
  const double n = scene.near_plane(), f = scene.far_plane();
  const StereoCamera recommended = scene.recommended_stereo();
  // The second camera converges farther, so the floor's front and the near sphere (z 2 .. 2.95)
  // are nearer than c / 2 = 3 and count as uncomfortable.
  const BudgetCase cases[] = {
      {DepthEncoding::standard, recommended},          {DepthEncoding::reversed, recommended},
      {DepthEncoding::reversed_infinite, recommended}, {DepthEncoding::gl_ndc, StereoCamera{0.05, 6.0}},
      {DepthEncoding::linear, StereoCamera{0.05, 6.0}}, {DepthEncoding::infinite, StereoCamera{0.02, 2.5}},
  };
  const double eye_separation = 0.045;  // e.g. 6.5 cm eyes on a 1.45 m screen
  for (const BudgetCase& bc : cases) {
    SCOPED_TRACE(to_string(bc.encoding));
    const DepthDecoder decoder = scene.decoder(bc.encoding);
    const Image stored = rs::encode_depth(view.depth, decoder);
    ASSERT_FALSE(stored.empty());

    BudgetOptions options;
    options.eye_separation = eye_separation;
    ParallaxBudget budget;
    ASSERT_TRUE(parallax_budget(stored.plane(), decoder, bc.camera, options, &budget).ok());

    // The test's own parallax: DESIGN §3 from n and f in double, then §4's p = sigma S W (1 - c/z)
    // with sigma = +1 (left -> right).
    const double S = bc.camera.separation, c = bc.camera.convergence;
    std::vector<double> p;
    std::int64_t nearer = 0, farther = 0, beyond = 0, near_edge = 0, any = 0;
    const double limit = eye_separation * width;
    for (int y = 0; y < height; ++y) {
      for (int x = 0; x < width; ++x) {
        const double d = stored.plane_data()[y * stored.stride() + x];
        const double z = 1.0 / readable(design_inverse_depth(bc.encoding, d, n, f));
        const double parallax = S * width * (1.0 - c / z);
        p.push_back(parallax);
        nearer += z < c / 2.0;
        farther += z > 100.0 * c;
        beyond += std::fabs(parallax) > limit;
        any += z < c / 2.0 || z > 100.0 * c || std::fabs(parallax) > limit;
        // Pixels within rounding of a threshold may fall either side in float.
        near_edge += std::fabs(z - c / 2.0) < 1e-5 * c || std::fabs(std::fabs(parallax) - limit) < 1e-4;
      }
    }
    std::sort(p.begin(), p.end());
    const double tolerance = 2e-4;  // px: float decode and float storage of each value
    EXPECT_EQ(budget.pixels, static_cast<std::int64_t>(p.size()));
    EXPECT_NEAR(budget.min, p.front(), tolerance);
    EXPECT_NEAR(budget.max, p.back(), tolerance);
    std::printf("  budget %-17s S %.3f c %.2f: p min %+8.3f", to_string(bc.encoding), S, c, budget.min);
    for (int i = 0; i < kBudgetPercentileCount; ++i) {
      const double expected = percentile_of_sorted(p, kBudgetPercentiles[i]);
      EXPECT_NEAR(budget.percentile[i], expected, tolerance) << "percentile " << kBudgetPercentiles[i];
      EXPECT_NEAR(budget.percentile_of_eyes[i], expected / (eye_separation * width), tolerance / limit);
      if (i == 1 || i == 3 || i == 5) std::printf("  p%02.0f %+8.3f", kBudgetPercentiles[i], budget.percentile[i]);
    }
    std::printf("  max %+8.3f px; near %.2f%% far %.2f%% beyond %.2f%%\n", budget.max,
                100.0 * budget.nearer_than_half_convergence, 100.0 * budget.farther_than_100_convergence,
                100.0 * budget.beyond_limit);
    const double N = static_cast<double>(p.size());
    EXPECT_NEAR(budget.nearer_than_half_convergence * N, static_cast<double>(nearer), static_cast<double>(near_edge));
    EXPECT_NEAR(budget.farther_than_100_convergence * N, static_cast<double>(farther), 0.0);
    EXPECT_NEAR(budget.beyond_limit * N, static_cast<double>(beyond), static_cast<double>(near_edge));
    EXPECT_NEAR(budget.uncomfortable * N, static_cast<double>(any), static_cast<double>(near_edge));
    EXPECT_DOUBLE_EQ(budget.eye_parallax, limit);
    EXPECT_DOUBLE_EQ(budget.parallax_limit, limit);
    EXPECT_EQ(budget.unreadable, 0);
    if (c == 6.0) {
      EXPECT_GT(nearer, 0);  // the case is meant to exercise the share
    }
  }
}

TEST(PipelineBudget, SharesAndHistogramMatchCounts) {
  // Synthetic linear depth, log-uniform from c/10 to 1000 c, with unreadable values (NaN, negative:
  // read as infinity), zeros (infinitely near) and +inf.
  const StereoCamera camera{0.04, 3.0};
  const int width = 200, height = 100;
  Image depth(width, height, 1);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> exponent(-1.0, 3.0);
  int specials = 0;
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      float value = static_cast<float>(camera.convergence * std::pow(10.0, exponent(rng)));
      const int k = (y * width + x) % 997;
      if (k == 5) value = std::numeric_limits<float>::quiet_NaN();
      if (k == 6) value = -2.0f;
      if (k == 7) value = 0.0f;
      if (k == 8) value = std::numeric_limits<float>::infinity();
      specials += k >= 5 && k <= 8;
      depth.plane_data()[y * depth.stride() + x] = value;
    }
  }
  const DepthDecoder decoder = DepthDecoder::linear();
  const int bins = 40;
  BudgetOptions options;  // eye separation: the camera's (unset)
  options.parallax_limit = 5.0;
  options.histogram_bins = bins;
  options.histogram_min = -3.0 * camera.separation * width;
  options.histogram_max = camera.separation * width;
  std::vector<std::int64_t> counts(bins, -1);
  ParallaxBudget budget;
  ASSERT_TRUE(parallax_budget(depth.plane(), decoder, camera, options, &budget, counts.data()).ok());

  const double a = camera.separation * width, c = camera.convergence;
  std::vector<std::int64_t> expected(bins, 0);
  std::int64_t below = 0, above = 0, nearer = 0, farther = 0, beyond = 0, unreadable = 0, edge = 0, any = 0;
  const double lo = *options.histogram_min, hi = *options.histogram_max, bin_width = (hi - lo) / bins;
  std::vector<double> p;
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const double d = depth.plane_data()[y * depth.stride() + x];
      const double raw = 1.0 / d;
      unreadable += !(raw >= 0.0);
      const double w = readable(raw);
      const double parallax = std::isinf(w) ? -kInf : a * (1.0 - c * w);
      p.push_back(parallax);
      nearer += w > 2.0 / c;
      farther += w < 1.0 / (100.0 * c);
      beyond += std::fabs(parallax) > 5.0;
      any += w > 2.0 / c || w < 1.0 / (100.0 * c) || std::fabs(parallax) > 5.0;
      if (parallax < lo) {
        ++below;
      } else if (parallax > hi) {
        ++above;
      } else {
        const int bin = std::min(bins - 1, static_cast<int>(std::floor((parallax - lo) / bin_width)));
        ++expected[bin];
        // Within rounding of a bin edge: float storage may put it in the neighbour.
        const double offset = (parallax - lo) / bin_width;
        edge += std::fabs(offset - std::round(offset)) * bin_width < 1e-4;
      }
    }
  }
  std::sort(p.begin(), p.end());
  EXPECT_EQ(budget.unreadable, unreadable);
  EXPECT_EQ(unreadable, 2 * specials / 4);
  EXPECT_EQ(budget.below_histogram, below);
  EXPECT_EQ(budget.above_histogram, above);
  std::int64_t total = 0, difference = 0;
  for (int i = 0; i < bins; ++i) {
    total += counts[static_cast<std::size_t>(i)];
    difference += std::llabs(counts[static_cast<std::size_t>(i)] - expected[static_cast<std::size_t>(i)]);
  }
  EXPECT_EQ(total + below + above, static_cast<std::int64_t>(width) * height);
  EXPECT_LE(difference, 2 * edge);
  const double N = static_cast<double>(width) * height;
  EXPECT_DOUBLE_EQ(budget.nearer_than_half_convergence * N, static_cast<double>(nearer));
  EXPECT_DOUBLE_EQ(budget.farther_than_100_convergence * N, static_cast<double>(farther));
  EXPECT_DOUBLE_EQ(budget.beyond_limit * N, static_cast<double>(beyond));
  EXPECT_DOUBLE_EQ(budget.uncomfortable * N, static_cast<double>(any));
  EXPECT_EQ(budget.min, -kInf);  // linear depth 0
  EXPECT_NEAR(budget.max, a, 1e-5);  // infinity, +inf and the unreadable values
  EXPECT_DOUBLE_EQ(budget.eye_separation, camera.separation);
  for (int i = 0; i < kBudgetPercentileCount; ++i)
    EXPECT_NEAR(budget.percentile[i], percentile_of_sorted(p, kBudgetPercentiles[i]), 1e-4);
  std::printf("  synthetic: near %.2f%% far %.2f%% beyond 5 px %.2f%%, p05 %.3f p50 %.3f p95 %.3f px\n",
              100.0 * budget.nearer_than_half_convergence, 100.0 * budget.farther_than_100_convergence,
              100.0 * budget.beyond_limit, budget.percentile[1], budget.percentile[3], budget.percentile[5]);

  // Default histogram range: the finite parallax present; the -inf pixels fall below it.
  BudgetOptions automatic;
  automatic.histogram_bins = 16;
  std::vector<std::int64_t> auto_counts(16, 0);
  ASSERT_TRUE(parallax_budget(depth.plane(), decoder, camera, automatic, &budget, auto_counts.data()).ok());
  std::int64_t auto_total = 0;
  for (std::int64_t v : auto_counts) auto_total += v;
  const std::int64_t zeros = specials / 4;
  EXPECT_EQ(budget.below_histogram, zeros);
  EXPECT_EQ(budget.above_histogram, 0);
  EXPECT_EQ(auto_total + zeros, static_cast<std::int64_t>(width) * height);
  EXPECT_NEAR(budget.histogram_max, a, 1e-5);
}

TEST(PipelineBudget, RejectsBadInput) {
  Image depth(8, 4, 1);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 8; ++x) depth.plane_data()[y * depth.stride() + x] = 2.0f;
  const DepthDecoder decoder = DepthDecoder::linear();
  const StereoCamera camera{0.03, 3.0};
  ParallaxBudget budget;
  BudgetOptions options;
  auto code = [&](const FloatPlane& plane, const DepthDecoder& dec, const StereoCamera& cam, const BudgetOptions& opt,
                  ParallaxBudget* out, std::int64_t* hist = nullptr) {
    const Status s = parallax_budget(plane, dec, cam, opt, out, hist);
    EXPECT_GT(std::char_traits<char>::length(s.message()), 0u);
    return s.code();
  };
  EXPECT_EQ(code(depth.plane(), decoder, camera, options, nullptr), StatusCode::null_pointer);
  FloatPlane null_plane = depth.plane();
  null_plane.data = nullptr;
  EXPECT_EQ(code(null_plane, decoder, camera, options, &budget), StatusCode::null_pointer);
  FloatPlane narrow = depth.plane();
  narrow.stride = 4;
  EXPECT_EQ(code(narrow, decoder, camera, options, &budget), StatusCode::invalid_stride);
  FloatPlane negative = depth.plane();
  negative.width = -1;
  EXPECT_EQ(code(negative, decoder, camera, options, &budget), StatusCode::invalid_size);
  EXPECT_EQ(code(depth.plane(), DepthDecoder::disparity(), camera, options, &budget), StatusCode::invalid_decoder);
  EXPECT_EQ(code(depth.plane(), DepthDecoder::from_near_far(DepthEncoding::standard, 2.0, 1.0), camera, options,
                 &budget),
            StatusCode::invalid_decoder);
  EXPECT_EQ(code(depth.plane(), decoder, StereoCamera{0.03, 0.0}, options, &budget), StatusCode::invalid_model);
  EXPECT_EQ(code(depth.plane(), decoder, StereoCamera{kNaN, 3.0}, options, &budget), StatusCode::invalid_model);
  EXPECT_EQ(code(depth.plane(), decoder, StereoCamera{0.0, 3.0}, options, &budget), StatusCode::invalid_option)
      << "S = 0 and no eye separation: nothing to measure against";
  BudgetOptions bad = options;
  bad.eye_separation = kInf;
  EXPECT_EQ(code(depth.plane(), decoder, camera, bad, &budget), StatusCode::invalid_option);
  bad = options;
  bad.display_width = -3;
  EXPECT_EQ(code(depth.plane(), decoder, camera, bad, &budget), StatusCode::invalid_option);
  bad = options;
  bad.parallax_limit = -1.0;
  EXPECT_EQ(code(depth.plane(), decoder, camera, bad, &budget), StatusCode::invalid_option);
  bad = options;
  bad.histogram_bins = 10;
  EXPECT_EQ(code(depth.plane(), decoder, camera, bad, &budget), StatusCode::null_pointer);
  std::int64_t counts[10];
  bad.histogram_min = 1.0;
  EXPECT_EQ(code(depth.plane(), decoder, camera, bad, &budget, counts), StatusCode::invalid_option);
  bad.histogram_max = 1.0;
  EXPECT_EQ(code(depth.plane(), decoder, camera, bad, &budget, counts), StatusCode::invalid_option);
  bad.histogram_bins = -1;
  EXPECT_EQ(code(depth.plane(), decoder, camera, bad, &budget, counts), StatusCode::invalid_option);

  // An empty plane is valid: nothing measured, NaN statistics.
  FloatPlane empty = depth.plane();
  empty.width = 0;
  ASSERT_TRUE(parallax_budget(empty, decoder, camera, options, &budget).ok());
  EXPECT_EQ(budget.pixels, 0);
  EXPECT_TRUE(std::isnan(budget.percentile[3]));
}

// ---------------------------------------------------------------------------------------------
// 2. Stereo culling frustum

struct CullingCase {
  const char* name;
  ViewFrustum mono;
  StereoCamera camera;
};

std::vector<CullingCase> culling_cases() {
  std::vector<CullingCase> cases;
  cases.push_back({"symmetric 60 deg 16:9", ViewFrustum::perspective(1.0471975511965976, 1920, 1080, 0.1, 500.0),
                   StereoCamera{0.03, 3.5}});
  ViewFrustum off_centre;
  off_centre.left = -0.07;
  off_centre.right = 0.12;
  off_centre.bottom = -0.04;
  off_centre.top = 0.09;
  off_centre.near_plane = 0.1;
  off_centre.far_plane = 200.0;
  cases.push_back({"off-centre", off_centre, StereoCamera{0.08, 2.0}});
  cases.push_back({"wide, infinite far", ViewFrustum::perspective(1.7, 800, 800, 0.05, kInf), StereoCamera{0.06, 10.0}});
  cases.push_back({"no separation", ViewFrustum::perspective(1.0, 640, 480, 0.5, 50.0), StereoCamera{0.0, 4.0}});
  return cases;
}

TEST(PipelineCulling, ContainsEveryPointEitherEyeSees) {
  for (const CullingCase& cc : culling_cases()) {
    SCOPED_TRACE(cc.name);
    CullingFrustum cull;
    ASSERT_TRUE(stereo_culling_frustum(cc.mono, cc.camera, &cull).ok());
    const double S = cc.camera.separation, c = cc.camera.convergence;
    EXPECT_NEAR(cull.pull_back, S == 0.0 ? 0.0 : c / (1.0 + 1.0 / S), 1e-15 * c);

    // The eyes' matrices: the mono D3D projection sheared by StereoCamera (the code under test
    // never sees them).
    float mono[16], eye[2][16];
    to_floats(d3d_perspective(cc.mono), mono);
    cc.camera.projection_d3d(mono, Eye::left, eye[0]);
    cc.camera.projection_d3d(mono, Eye::right, eye[1]);

    const double n = cc.mono.near_plane;
    const double far = std::isinf(cc.mono.far_plane) ? 1e5 : cc.mono.far_plane;
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> unit(0.0, 1.0), ndc(-1.0, 1.0);
    auto slack = [](double z) { return 2e-6 * (1.0 + std::fabs(z)); };
    int inside = 0, outside_both = 0;

    // Points on the eyes' own frustum boundaries (edges, corners, near and far planes), solved
    // from each eye's matrix: the hardest points for the bound.
    for (int e = 0; e < 2; ++e) {
      for (int i = 0; i < 4000; ++i) {
        const double z = n * std::pow(far / n, unit(rng));
        double nx = ndc(rng), ny = ndc(rng);
        if (i % 4 == 0) nx = i % 8 == 0 ? -1.0 : 1.0;  // on a side
        if (i % 3 == 0) ny = i % 6 == 0 ? -1.0 : 1.0;  // on the top or bottom
        double x, y;
        point_on_eye_ray(eye[e], nx, ny, z, &x, &y);
        ASSERT_TRUE(eye_sees(eye[e], x, y, z, 1e-5));
        EXPECT_TRUE(cull.contains(x, y, z, slack(z))) << "eye " << e << " point (" << x << ", " << y << ", " << z << ")";
        ++inside;
      }
      for (double z : {n, far}) {
        for (double nx : {-1.0, 1.0})
          for (double ny : {-1.0, 1.0}) {
            double x, y;
            point_on_eye_ray(eye[e], nx, ny, z, &x, &y);
            EXPECT_TRUE(cull.contains(x, y, z, slack(z))) << "eye " << e << " corner at z = " << z;
          }
      }
    }
    // Random points of a box around everything, classified by the matrices.
    const double half = (std::fabs(cc.mono.left) + std::fabs(cc.mono.right) + std::fabs(cc.mono.top) +
                         std::fabs(cc.mono.bottom)) / n;
    for (int i = 0; i < 20000; ++i) {
      const double z = -0.1 + (far * 1.1) * unit(rng) * unit(rng);
      const double x = half * (std::fabs(z) + 1.0) * ndc(rng), y = half * (std::fabs(z) + 1.0) * ndc(rng);
      const bool seen = eye_sees(eye[0], x, y, z) || eye_sees(eye[1], x, y, z);
      if (seen) {
        EXPECT_TRUE(cull.contains(x, y, z, slack(z))) << "(" << x << ", " << y << ", " << z << ")";
        ++inside;
      } else if (!cull.contains(x, y, z)) {
        ++outside_both;
      }
    }
    // Points outside the culling frustum are outside both eyes (the contrapositive, sampled).
    for (int i = 0; i < 20000; ++i) {
      const double z = n + (far - n) * unit(rng);
      const double x = half * (z + 1.0) * ndc(rng), y = half * (z + 1.0) * ndc(rng);
      if (cull.contains(x, y, z, slack(z))) continue;
      EXPECT_FALSE(eye_sees(eye[0], x, y, z, 1e-7) || eye_sees(eye[1], x, y, z, 1e-7));
    }
    std::printf("  culling %-22s Z = %.6f, tangents %.4f .. %.4f (mono %.4f .. %.4f); %d points seen, all inside\n",
                cc.name, cull.pull_back, cull.frustum.left / cull.frustum.near_plane,
                cull.frustum.right / cull.frustum.near_plane, cc.mono.left / n, cc.mono.right / n, inside);
    EXPECT_GT(outside_both, 0);
  }
}

TEST(PipelineCulling, IsTight) {
  // Near plane close to the eyes, far plane far away: the eyes' frusta then reach both places where
  // the bound is attained (the eyes' centres of projection and infinity).
  for (CullingCase cc : culling_cases()) {
    SCOPED_TRACE(cc.name);
    if (cc.camera.separation == 0.0) continue;
    const double scale = cc.mono.near_plane / 1e-4;
    cc.mono.left /= scale;
    cc.mono.right /= scale;
    cc.mono.bottom /= scale;
    cc.mono.top /= scale;
    cc.mono.near_plane = 1e-4;
    cc.mono.far_plane = 1e6;
    CullingFrustum cull;
    ASSERT_TRUE(stereo_culling_frustum(cc.mono, cc.camera, &cull).ok());
    float mono[16], left[16], right[16];
    to_floats(d3d_perspective(cc.mono), mono);
    cc.camera.projection_d3d(mono, Eye::left, left);
    cc.camera.projection_d3d(mono, Eye::right, right);

    // Attained at the eyes: each eye's centre of projection (where its clip x and w vanish, from its
    // matrix: x = -P30 / P00 at z = 0) lies on the culling side plane of its side.
    const double left_eye_x = -static_cast<double>(left[12]) / left[0];
    const double right_eye_x = -static_cast<double>(right[12]) / right[0];
    auto distance = [&](int plane, double x, double y, double z) {
      const double* p = cull.planes[plane];
      return p[0] * x + p[1] * y + p[2] * z + p[3];
    };
    EXPECT_NEAR(distance(0, left_eye_x, 0.0, 0.0), 0.0, 1e-6 * cc.camera.convergence);
    EXPECT_NEAR(distance(1, right_eye_x, 0.0, 0.0), 0.0, 1e-6 * cc.camera.convergence);

    // Attained at infinity: the right eye's left edge (and the left eye's right edge) is parallel
    // to the culling side plane: direction (X, 0, 1) with ndc_x = -1 at w = 0.
    const double right_left_edge = (-1.0 - right[8]) / right[0];
    const double left_right_edge = (1.0 - left[8]) / left[0];
    EXPECT_NEAR(cull.planes[0][0] * right_left_edge + cull.planes[0][2], 0.0, 1e-6);
    EXPECT_NEAR(cull.planes[1][0] * left_right_edge + cull.planes[1][2], 0.0, 1e-6);

    // So nothing smaller works: shrink the culling frustum by 0.1 % in either parameter and a
    // point an eye sees falls out. (a) Tangent: the right eye's left edge far away.
    const double n_cull = cull.frustum.near_plane;
    const double L = cull.frustum.left / n_cull, R = cull.frustum.right / n_cull, T = cull.frustum.top / n_cull;
    const double h = 0.5 * (R - L);
    {
      const double z = 1e5;
      double x, y;
      point_on_eye_ray(right, -1.0, 0.0, z, &x, &y);
      ASSERT_TRUE(eye_sees(right, x, y, z, 1e-6));
      const double narrower = cull.origin[0] + (L + 1e-3 * h) * (z - cull.origin[2]);
      EXPECT_LT(x, narrower) << "a 0.1 % narrower frustum would cut the right eye's far left edge";
      EXPECT_GE(x, cull.origin[0] + L * (z - cull.origin[2]) - 1e-6 * z);
      point_on_eye_ray(left, 0.0, 1.0, z, &x, &y);  // the top edge, far
      const double lower = cull.origin[1] + (T - 1e-3 * h) * (z - cull.origin[2]);
      EXPECT_LT(lower, y) << "a 0.1 % flatter frustum would cut the eyes' far top edge";
    }
    // (b) Pull-back: the left eye's left edge at its near plane, with the origin moved 0.1 % of Z
    // forward along the frustum's centre ray.
    {
      const double z = cc.mono.near_plane;
      double x, y;
      point_on_eye_ray(left, -1.0, 0.0, z, &x, &y);
      ASSERT_TRUE(eye_sees(left, x, y, z, 1e-6));
      const double k = 1.0 - 1e-3;
      const double ox = cull.origin[0] * k, oz = cull.origin[2] * k;
      EXPECT_LT(x, ox + L * (z - oz)) << "a culling origin pulled back by 0.999 Z would cut the left eye";
    }
    std::printf("  culling %-22s tight: eye on plane within %.2e, edge parallel within %.2e\n", cc.name,
                std::fabs(distance(0, left_eye_x, 0.0, 0.0)),
                std::fabs(cull.planes[0][0] * right_left_edge + cull.planes[0][2]));
  }
}

TEST(PipelineCulling, RejectsBadInput) {
  CullingFrustum cull;
  const ViewFrustum mono = ViewFrustum::perspective(1.0, 640, 480, 0.1, 100.0);
  EXPECT_EQ(stereo_culling_frustum(mono, StereoCamera{0.03, 3.0}, nullptr).code(), StatusCode::null_pointer);
  EXPECT_EQ(stereo_culling_frustum(mono, StereoCamera{-0.03, 3.0}, &cull).code(), StatusCode::invalid_model);
  EXPECT_EQ(stereo_culling_frustum(mono, StereoCamera{0.03, kInf}, &cull).code(), StatusCode::invalid_model);
  ViewFrustum bad = mono;
  bad.near_plane = 0.0;
  EXPECT_EQ(stereo_culling_frustum(bad, StereoCamera{0.03, 3.0}, &cull).code(), StatusCode::invalid_option);
  bad = mono;
  bad.left = bad.right;
  EXPECT_EQ(stereo_culling_frustum(bad, StereoCamera{0.03, 3.0}, &cull).code(), StatusCode::invalid_option);
  bad = mono;
  bad.orthographic = true;
  EXPECT_EQ(stereo_culling_frustum(bad, StereoCamera{0.03, 3.0}, &cull).code(), StatusCode::invalid_option);
  EXPECT_EQ(stereo_culling_frustum(ViewFrustum::perspective(kNaN, 640, 480, 0.1, 100.0), StereoCamera{0.03, 3.0},
                                   &cull).code(),
            StatusCode::invalid_option);
}

// ---------------------------------------------------------------------------------------------
// 3. Picking

TEST(PipelinePicking, FindsTheRayCastDepthUnderTheCursor) {
  const int width = 480, height = 270;
  const rs::SceneId scenes[] = {rs::SceneId::room, rs::SceneId::near, rs::SceneId::edge, rs::SceneId::spheres};
  for (rs::SceneId id : scenes) {
    SCOPED_TRACE(rs::to_string(id));
    const rs::Scene scene = rs::Scene::make(id);
    const rs::Camera centre = scene.camera(width, height, rs::kCentreEye);
    const rs::Camera left_cam = centre.with_eye(rs::kLeftEye), right_cam = centre.with_eye(rs::kRightEye);
    rs::View left_view, right_view;
    ASSERT_TRUE(scene.render(left_cam, &left_view, 2).ok());
    ASSERT_TRUE(scene.render(right_cam, &right_view, 2).ok());
    const DepthDecoder decoder = scene.decoder(DepthEncoding::standard);
    const Image left_depth = rs::encode_depth(left_view.depth, decoder);
    const Image right_depth = rs::encode_depth(right_view.depth, decoder);
    const ParallaxModel model = centre.stereo.parallax(width, EyeDirection::left_to_right);
    ASSERT_TRUE(model.validate().ok());

    // Whether an eye sees point P at column u (same row): its ray there meets P itself, and the two
    // pixels the search interpolates between see P's object (no silhouette between them).
    auto sees = [&](const rs::Camera& cam, const rs::View& view, const rs::Hit& hit, int row, double* u) {
      cam.project(hit.point, u, nullptr);
      if (!(*u >= 0.0 && *u <= width - 1)) return false;
      rs::Hit again;
      if (!scene.trace(cam.ray(*u, row), &again) || std::fabs(again.z - hit.z) > 1e-9 * hit.z) return false;
      const int j = std::min(static_cast<int>(*u), width - 2);
      const std::uint8_t* ids = view.object.data() + static_cast<std::size_t>(row) * width;
      return ids[j] == hit.object && ids[j + 1] == hit.object;
    };

    std::vector<double> position_error, depth_error;
    int cursors = 0, source_right = 0, one_eye = 0, one_eye_right = 0;
    for (int row = 3; row < height; row += 9) {
      for (int col = 2; col < width; col += 5) {
        const double u = col + 0.25 * ((row / 9) % 4);  // sub-pixel cursors too
        rs::Hit truth;
        ASSERT_TRUE(scene.trace(centre.ray(u, row), &truth));
        double u_left = 0.0, u_right = 0.0;
        const bool in_left = sees(left_cam, left_view, truth, row, &u_left);
        const bool in_right = sees(right_cam, right_view, truth, row, &u_right);
        if (!in_left && !in_right) continue;  // a silhouette pixel: no clean answer to compare with
        PickResult picked;
        ASSERT_TRUE(pick(left_depth.plane(), right_depth.plane(), decoder, model, u, row, PickOptions(), &picked).ok());
        ++cursors;
        const PickSource expected = in_left && in_right ? PickSource::both : in_left ? PickSource::left : PickSource::right;
        const bool right_source = picked.source == expected;
        source_right += right_source;
        if (!(in_left && in_right)) {
          ++one_eye;
          one_eye_right += right_source;
        }
        // Both eyes' positions are those of the true point (the truth projects it exactly).
        double true_left, true_right;
        left_cam.project(truth.point, &true_left, nullptr);
        right_cam.project(truth.point, &true_right, nullptr);
        position_error.push_back(std::max(std::fabs(picked.left_x - true_left), std::fabs(picked.right_x - true_right)));
        depth_error.push_back(std::fabs(picked.depth - truth.z) / truth.z);
      }
    }
    ASSERT_GT(cursors, 1000);
    std::vector<double> sorted_pos = position_error, sorted_depth = depth_error;
    std::sort(sorted_pos.begin(), sorted_pos.end());
    std::sort(sorted_depth.begin(), sorted_depth.end());
    const double pos_median = percentile_of_sorted(sorted_pos, 50), pos_99 = percentile_of_sorted(sorted_pos, 99);
    const double depth_99 = percentile_of_sorted(sorted_depth, 99);
    std::printf("  pick %-8s %5d cursors: eye position error median %.2e px, p99 %.2e, max %.3f px; depth rel. "
                "error p99 %.2e, max %.2e; source right %.2f%% (one-eye cursors %d, %.1f%% right)\n",
                rs::to_string(id), cursors, pos_median, pos_99, sorted_pos.back(), depth_99, sorted_depth.back(),
                100.0 * source_right / cursors, one_eye, one_eye ? 100.0 * one_eye_right / one_eye : 100.0);
    EXPECT_LT(pos_99, 0.02) << "99 % of clean cursors within 0.02 px in both eyes";
    EXPECT_LT(sorted_pos.back(), 0.1);
    EXPECT_LT(depth_99, 1e-3);
    EXPECT_LT(sorted_depth.back(), 0.05);
    EXPECT_GT(static_cast<double>(source_right) / cursors, 0.97);
  }
}

TEST(PipelinePicking, DisparityMapsAndEdgeCases) {
  // A rectified pair's disparity (left -> right p = -d): a fronto-parallel plane at disparity 6 with a
  // nearer strip at disparity 14 in the left map, shifted by its own disparity in the right map.
  const int width = 64, height = 3;
  Image left(width, height, 1), right(width, height, 1);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      left.plane_data()[y * left.stride() + x] = (x >= 20 && x < 30) ? 14.0f : 6.0f;
      right.plane_data()[y * right.stride() + x] = (x >= 6 && x < 16) ? 14.0f : 6.0f;
    }
  }
  const DepthDecoder decoder = DepthDecoder::disparity();
  const ParallaxModel model = ParallaxModel::from_disparity(EyeDirection::left_to_right);
  PickResult r;
  // Mono column of the strip's centre: left 25, right 11 -> mono 18; parallax -14.
  ASSERT_TRUE(pick(left.plane(), right.plane(), decoder, model, 18.0, 1, PickOptions(), &r).ok());
  EXPECT_EQ(r.source, PickSource::both);
  EXPECT_NEAR(r.parallax, -14.0, 1e-9);
  EXPECT_NEAR(r.inverse_depth, 14.0, 1e-9);
  EXPECT_NEAR(r.left_x, 25.0, 1e-9);
  EXPECT_NEAR(r.right_x, 11.0, 1e-9);
  // The background at mono 45: left 48, right 42.
  ASSERT_TRUE(pick(left.plane(), right.plane(), decoder, model, 45.0, 1, PickOptions(), &r).ok());
  EXPECT_EQ(r.source, PickSource::both);
  EXPECT_NEAR(r.parallax, -6.0, 1e-9);
  // In the mono view the strip covers columns 13 .. 22. Background at mono 12 is at left 15 (seen)
  // and right 9 (behind the strip): the right eye's search ends on the strip's wall.
  ASSERT_TRUE(pick(left.plane(), right.plane(), decoder, model, 12.0, 1, PickOptions(), &r).ok());
  EXPECT_EQ(r.source, PickSource::left);
  EXPECT_NEAR(r.parallax, -6.0, 1e-9);
  EXPECT_NEAR(r.left_x, 15.0, 1e-9);
  // Background at mono 24: left 27 (behind the strip), right 21 (seen).
  ASSERT_TRUE(pick(left.plane(), right.plane(), decoder, model, 24.0, 1, PickOptions(), &r).ok());
  EXPECT_EQ(r.source, PickSource::right);
  EXPECT_NEAR(r.parallax, -6.0, 1e-9);
  EXPECT_NEAR(r.right_x, 21.0, 1e-9);
  // Background at mono 27: both eyes see it (left 30, right 24).
  ASSERT_TRUE(pick(left.plane(), right.plane(), decoder, model, 27.0, 1, PickOptions(), &r).ok());
  EXPECT_EQ(r.source, PickSource::both);
  EXPECT_NEAR(r.parallax, -6.0, 1e-9);

  EXPECT_EQ(pick(left.plane(), right.plane(), decoder, model, 10.0, 1, PickOptions(), nullptr).code(),
            StatusCode::null_pointer);
  EXPECT_EQ(pick(left.plane(), right.plane(), decoder, model, kNaN, 1, PickOptions(), &r).code(),
            StatusCode::invalid_option);
  EXPECT_EQ(pick(left.plane(), right.plane(), decoder, model, 10.0, 3, PickOptions(), &r).code(),
            StatusCode::invalid_option);
  EXPECT_EQ(pick(left.plane(), right.plane(), decoder, ParallaxModel{2.0f, 0.0f}, 10.0, 1, PickOptions(), &r).code(),
            StatusCode::invalid_model);
  FloatPlane small = right.plane();
  small.width = 10;
  EXPECT_EQ(pick(left.plane(), small, decoder, model, 10.0, 1, PickOptions(), &r).code(), StatusCode::size_mismatch);
  PickOptions bad;
  bad.hole_threshold = -1.0f;
  EXPECT_EQ(pick(left.plane(), right.plane(), decoder, model, 10.0, 1, bad, &r).code(), StatusCode::invalid_option);
  bad = PickOptions();
  bad.max_negative_parallax = kInf;
  EXPECT_EQ(pick(left.plane(), right.plane(), decoder, model, 10.0, 1, bad, &r).code(), StatusCode::invalid_option);
  // A limit nearer than the strip clips it: the strip is not found, the background behind it is not
  // seen either, so the answer is unreliable and says so.
  bad = PickOptions();
  bad.max_negative_parallax = 8.0f;
  ASSERT_TRUE(pick(left.plane(), right.plane(), decoder, model, 18.0, 1, bad, &r).ok());
  EXPECT_EQ(r.source, PickSource::none);
}

// ---------------------------------------------------------------------------------------------
// 4. Screen -> view-space reconstruction

// Projects a view point with a D3D matrix (double) and maps NDC to continuous pixel coordinates
// (centres at integers, row 0 at the top) and the stored value.
void to_screen(const Mat4& P, double x, double y, double z, int width, int height, double* px, double* py,
               double* stored) {
  const double v[4] = {x, y, z, 1.0};
  double clip[4] = {};
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) clip[c] += v[r] * P.m[r][c];
  *px = (clip[0] / clip[3] + 1.0) * 0.5 * width - 0.5;
  *py = (1.0 - clip[1] / clip[3]) * 0.5 * height - 0.5;
  *stored = clip[2] / clip[3];
}

TEST(PipelineReconstruction, RoundTripsProjectedPoints) {
  const int width = 1280, height = 720;
  ViewFrustum persp;
  persp.left = -0.09;
  persp.right = 0.11;
  persp.bottom = -0.05;
  persp.top = 0.065;
  persp.near_plane = 0.1;
  persp.far_plane = 100.0;
  ViewFrustum ortho = persp;
  ortho.orthographic = true;
  ortho.left = -40.0;
  ortho.right = 25.0;
  ortho.bottom = -12.0;
  ortho.top = 20.0;
  ortho.near_plane = 1.0;
  const struct {
    const char* name;
    ViewFrustum frustum;
    DepthEncoding encoding;
    Mat4 matrix;
  } cases[] = {
      {"perspective standard", persp, DepthEncoding::standard, d3d_perspective(persp)},
      {"perspective reversed", persp, DepthEncoding::reversed, d3d_perspective(persp, true)},
      {"orthographic standard", ortho, DepthEncoding::standard, d3d_orthographic(ortho)},
  };
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (const auto& c : cases) {
    SCOPED_TRACE(c.name);
    ScreenToView rec;
    ASSERT_TRUE(make_screen_to_view(c.frustum, c.encoding, width, height, &rec).ok());
    const ViewFrustum& f = c.frustum;
    double worst = 0.0;
    for (int i = 0; i < 20000; ++i) {
      const double z = f.near_plane + (f.far_plane - f.near_plane) * unit(rng);
      const double k = f.orthographic ? 1.0 : z / f.near_plane;
      const double x = (f.left + (f.right - f.left) * unit(rng)) * k;
      const double y = (f.bottom + (f.top - f.bottom) * unit(rng)) * k;
      double px, py, stored;
      to_screen(c.matrix, x, y, z, width, height, &px, &py, &stored);
      const ViewPoint p = rec.at_pixel(static_cast<float>(px), static_cast<float>(py), static_cast<float>(stored));
      const double scale = std::sqrt(x * x + y * y + z * z);
      worst = std::max(worst, std::sqrt((p.x - x) * (p.x - x) + (p.y - y) * (p.y - y) + (p.z - z) * (p.z - z)) / scale);
    }
    std::printf("  reconstruct %-22s round trip: max error %.2e of the distance\n", c.name, worst);
    EXPECT_LT(worst, c.encoding == DepthEncoding::standard && !f.orthographic ? 5e-4 : 1e-5);
  }

  // The plane version agrees with at_pixel, and the exact pixel-centre mapping holds: the corners of
  // the frustum are half a pixel outside the first and last centres.
  Image depth(4, 3, 1), X(4, 3, 1), Y(4, 3, 1), Z(4, 3, 1);
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 4; ++x) depth.plane_data()[y * depth.stride() + x] = 2.0f + x + 10.0f * y;
  ScreenToView rec;
  ASSERT_TRUE(make_screen_to_view(persp, DepthEncoding::linear, 4, 3, &rec).ok());
  ASSERT_TRUE(screen_to_view(rec, depth.plane(), X.mutable_plane(), Y.mutable_plane(), Z.mutable_plane()).ok());
  for (int y = 0; y < 3; ++y) {
    for (int x = 0; x < 4; ++x) {
      const float d = depth.plane_data()[y * depth.stride() + x];
      const ViewPoint p = rec.at_pixel(static_cast<float>(x), static_cast<float>(y), d);
      EXPECT_EQ(X.plane_data()[y * X.stride() + x], p.x);
      EXPECT_EQ(Y.plane_data()[y * Y.stride() + x], p.y);
      EXPECT_EQ(Z.plane_data()[y * Z.stride() + x], p.z);
    }
  }
  const ViewPoint corner = rec.at_pixel(-0.5f, -0.5f, 1.0f);
  EXPECT_NEAR(corner.x, persp.left / persp.near_plane, 1e-6);
  EXPECT_NEAR(corner.y, persp.top / persp.near_plane, 1e-6);
}

// Float Gauss-Jordan with partial pivoting: how a float 4x4 inverse is usually computed.
bool invert_float(const float in[4][4], float out[4][4]) {
  float a[4][8];
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) {
      a[i][j] = in[i][j];
      a[i][j + 4] = i == j ? 1.0f : 0.0f;
    }
  for (int c = 0; c < 4; ++c) {
    int p = c;
    for (int r = c + 1; r < 4; ++r)
      if (std::fabs(a[r][c]) > std::fabs(a[p][c])) p = r;
    if (a[p][c] == 0.0f) return false;
    for (int j = 0; j < 8; ++j) std::swap(a[c][j], a[p][j]);
    const float pivot = a[c][c];
    for (int j = 0; j < 8; ++j) a[c][j] /= pivot;
    for (int r = 0; r < 4; ++r) {
      if (r == c) continue;
      const float factor = a[r][c];
      for (int j = 0; j < 8; ++j) a[r][j] -= factor * a[c][j];
    }
  }
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) out[i][j] = a[i][j + 4];
  return true;
}

// The inverse-matrix route: (pixel_x + 0.5, pixel_y + 0.5, d, 1) times the float inverse of the
// concatenated [view x] projection x viewport matrix, divided by w; all in float.
void inverse_route(const float inverse[4][4], float px, float py, float d, float out[3]) {
  const float h[4] = {px + 0.5f, py + 0.5f, d, 1.0f};
  float o[4] = {0.0f, 0.0f, 0.0f, 0.0f};
  for (int c = 0; c < 4; ++c)
    for (int k = 0; k < 4; ++k) o[c] += h[k] * inverse[k][c];
  for (int i = 0; i < 3; ++i) out[i] = o[i] / o[3];
}

Mat4 viewport(int width, int height) {  // NDC -> (pixel + 0.5) coordinates, row vector
  Mat4 V;
  V.m[0][0] = 0.5 * width;
  V.m[3][0] = 0.5 * width;
  V.m[1][1] = -0.5 * height;
  V.m[3][1] = 0.5 * height;
  V.m[2][2] = 1.0;
  V.m[3][3] = 1.0;
  return V;
}

struct RouteErrors {
  double mean = 0.0, max = 0.0;
};

TEST(PipelineReconstruction, ScaleAndBiasBeatsInverseMatrixForFarPoints) {
  const int width = 1920, height = 1080;
  ViewFrustum f;
  f.left = -0.08;
  f.right = 0.1;
  f.bottom = -0.05;
  f.top = 0.06;
  f.near_plane = 0.1;
  f.far_plane = 1e4;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> unit(0.0, 1.0);

  // (a) View space, far points (z in 0.3 f .. f), with the projection x viewport inverted in float.
  for (const DepthEncoding encoding : {DepthEncoding::standard, DepthEncoding::reversed}) {
    SCOPED_TRACE(to_string(encoding));
    const bool reversed = encoding == DepthEncoding::reversed;
    const Mat4 P = d3d_perspective(f, reversed);
    float Pf[16];
    to_floats(P, Pf);  // the engine's float projection
    Mat4 Pd;
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) Pd.m[r][c] = Pf[4 * r + c];
    const Mat4 screen = multiply(Pd, viewport(width, height));
    float screen_f[4][4], inverse[4][4];
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) screen_f[r][c] = static_cast<float>(screen.m[r][c]);
    ASSERT_TRUE(invert_float(screen_f, inverse));
    ScreenToView rec;
    ASSERT_TRUE(make_screen_to_view(f, encoding, width, height, &rec).ok());

    RouteErrors ours, matrix;
    const int samples = 100000;
    for (int i = 0; i < samples; ++i) {
      const double z = f.far_plane * (0.3 + 0.7 * unit(rng));
      const int px = static_cast<int>(unit(rng) * width), py = static_cast<int>(unit(rng) * height);
      const double u = (px + 0.5) / width, v = (py + 0.5) / height;
      const double x = (f.left + u * (f.right - f.left)) * z / f.near_plane;
      const double y = (f.top + v * (f.bottom - f.top)) * z / f.near_plane;
      const double n = f.near_plane, fa = f.far_plane;
      const float d = static_cast<float>(reversed ? (n / (n - fa)) * (1.0 - fa / z) : (fa / (fa - n)) * (1.0 - n / z));
      const ViewPoint a = rec.at_pixel(static_cast<float>(px), static_cast<float>(py), d);
      float b[3];
      inverse_route(inverse, static_cast<float>(px), static_cast<float>(py), d, b);
      const double dist = std::sqrt(x * x + y * y + z * z);
      const double ea = std::sqrt((a.x - x) * (a.x - x) + (a.y - y) * (a.y - y) + (a.z - z) * (a.z - z)) / dist;
      const double eb = std::sqrt((b[0] - x) * (b[0] - x) + (b[1] - y) * (b[1] - y) + (b[2] - z) * (b[2] - z)) / dist;
      ours.mean += ea / samples;
      matrix.mean += eb / samples;
      ours.max = std::max(ours.max, ea);
      matrix.max = std::max(matrix.max, eb);
    }
    std::printf("  reconstruct view space, %-8s far points (n 0.1, f 1e4): scale-and-bias mean %.3e max %.3e; "
                "inverse matrix mean %.3e max %.3e (relative to distance)\n",
                to_string(encoding), ours.mean, ours.max, matrix.mean, matrix.max);
    if (reversed) {
      // Reversed depth is well conditioned at the far end: both routes are at float resolution.
      EXPECT_LT(ours.max, 4e-7);
      EXPECT_LE(ours.mean, matrix.mean * 1.25);
    } else {
      // Standard depth cancels at the far end; the float inverse adds its own rounding to it.
      EXPECT_LT(ours.mean, matrix.mean * 0.8);
      EXPECT_LE(ours.max, matrix.max);
    }
  }

  // (b) Points far from the world origin: the camera at (1e4, 30, -7e3), yawed; the engine
  // inverts the concatenated view x projection x viewport in float. Ours: view space by scale and
  // bias, then the camera's rigid transform in float (camera-relative reconstruction).
  for (const double offset : {0.0, 1e3, 1e4}) {
    const double yaw = 0.7, cy = std::cos(yaw), sy = std::sin(yaw);
    const double C[3] = {offset, 30.0, -0.7 * offset};
    const double Rot[3][3] = {{cy, 0.0, sy}, {0.0, 1.0, 0.0}, {-sy, 0.0, cy}};  // view = (p - C) Rot
    Mat4 view;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) view.m[i][j] = Rot[i][j];
    view.m[3][3] = 1.0;
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 3; ++i) view.m[3][j] -= C[i] * Rot[i][j];
    const Mat4 all = multiply(multiply(view, d3d_perspective(f, true)), viewport(width, height));
    float all_f[4][4], inverse[4][4];
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) all_f[r][c] = static_cast<float>(all.m[r][c]);
    ASSERT_TRUE(invert_float(all_f, inverse));
    ScreenToView rec;
    ASSERT_TRUE(make_screen_to_view(f, DepthEncoding::reversed, width, height, &rec).ok());
    float Rf[3][3], Cf[3];
    for (int i = 0; i < 3; ++i) {
      Cf[i] = static_cast<float>(C[i]);
      for (int j = 0; j < 3; ++j) Rf[i][j] = static_cast<float>(Rot[i][j]);
    }
    RouteErrors ours, matrix;
    const int samples = 100000;
    for (int i = 0; i < samples; ++i) {
      const double z = f.near_plane + (f.far_plane - f.near_plane) * unit(rng);
      const int px = static_cast<int>(unit(rng) * width), py = static_cast<int>(unit(rng) * height);
      const double u = (px + 0.5) / width, v = (py + 0.5) / height;
      const double x = (f.left + u * (f.right - f.left)) * z / f.near_plane;
      const double y = (f.top + v * (f.bottom - f.top)) * z / f.near_plane;
      double world[3];
      for (int k = 0; k < 3; ++k) world[k] = C[k] + Rot[k][0] * x + Rot[k][1] * y + Rot[k][2] * z;
      const double n = f.near_plane, fa = f.far_plane;
      const float d = static_cast<float>((n / (n - fa)) * (1.0 - fa / z));
      const ViewPoint a = rec.at_pixel(static_cast<float>(px), static_cast<float>(py), d);
      float wa[3], wb[3];
      for (int k = 0; k < 3; ++k) wa[k] = Cf[k] + (Rf[k][0] * a.x + Rf[k][1] * a.y + Rf[k][2] * a.z);
      inverse_route(inverse, static_cast<float>(px), static_cast<float>(py), d, wb);
      double ea = 0.0, eb = 0.0;
      for (int k = 0; k < 3; ++k) {
        ea += (wa[k] - world[k]) * (wa[k] - world[k]);
        eb += (wb[k] - world[k]) * (wb[k] - world[k]);
      }
      ea = std::sqrt(ea);  // world units
      eb = std::sqrt(eb);
      ours.mean += ea / samples;
      matrix.mean += eb / samples;
      ours.max = std::max(ours.max, ea);
      matrix.max = std::max(matrix.max, eb);
    }
    std::printf("  reconstruct world, camera %6.0f from the origin, reversed, z 0.1 .. 1e4: scale-and-bias mean "
                "%.3e max %.3e; inverse concatenated matrix mean %.3e max %.3e (world units)\n",
                std::sqrt(C[0] * C[0] + C[1] * C[1] + C[2] * C[2]), ours.mean, ours.max, matrix.mean, matrix.max);
    EXPECT_LT(ours.mean, matrix.mean / 2.0);
    EXPECT_LT(ours.max, matrix.max);
  }
}

TEST(PipelineReconstruction, RejectsBadInput) {
  ScreenToView rec;
  const ViewFrustum f = ViewFrustum::perspective(1.0, 640, 480, 0.1, 100.0);
  EXPECT_EQ(make_screen_to_view(f, DepthEncoding::standard, 640, 480, nullptr).code(), StatusCode::null_pointer);
  EXPECT_EQ(make_screen_to_view(f, DepthEncoding::standard, 0, 480, &rec).code(), StatusCode::invalid_size);
  EXPECT_EQ(make_screen_to_view(f, DepthEncoding::disparity, 640, 480, &rec).code(), StatusCode::invalid_decoder);
  ViewFrustum inf = f;
  inf.far_plane = kInf;
  EXPECT_EQ(make_screen_to_view(inf, DepthEncoding::standard, 640, 480, &rec).code(), StatusCode::invalid_decoder);
  EXPECT_TRUE(make_screen_to_view(inf, DepthEncoding::reversed_infinite, 640, 480, &rec).ok());
  ViewFrustum ortho = f;
  ortho.orthographic = true;
  EXPECT_EQ(make_screen_to_view(ortho, DepthEncoding::infinite, 640, 480, &rec).code(), StatusCode::invalid_decoder);
  ortho.far_plane = kInf;
  EXPECT_EQ(make_screen_to_view(ortho, DepthEncoding::standard, 640, 480, &rec).code(), StatusCode::invalid_option);
  ViewFrustum nan_edge = f;
  nan_edge.top = kNaN;
  EXPECT_EQ(make_screen_to_view(nan_edge, DepthEncoding::standard, 640, 480, &rec).code(), StatusCode::invalid_option);

  ASSERT_TRUE(make_screen_to_view(f, DepthEncoding::standard, 4, 2, &rec).ok());
  Image depth(4, 2, 1), X(4, 2, 1), Y(4, 2, 1), Z(3, 2, 1);
  EXPECT_EQ(screen_to_view(rec, depth.plane(), X.mutable_plane(), Y.mutable_plane(), Z.mutable_plane()).code(),
            StatusCode::size_mismatch);
  EXPECT_EQ(screen_to_view(rec, depth.plane(), X.mutable_plane(), X.mutable_plane(), X.mutable_plane()).code(),
            StatusCode::aliasing);
  MutableFloatPlane null_plane = Y.mutable_plane();
  null_plane.data = nullptr;
  EXPECT_EQ(screen_to_view(rec, depth.plane(), X.mutable_plane(), null_plane, X.mutable_plane()).code(),
            StatusCode::null_pointer);
}

// ---------------------------------------------------------------------------------------------
// 5. 2D elements at a depth

TEST(PipelineDepthPlacement, ProjectsToTheIntendedParallax) {
  const int width = 1280, height = 720;
  const rs::Scene scene = rs::Scene::make(rs::SceneId::room);
  const rs::Camera centre = scene.camera(width, height, rs::kCentreEye);
  const rs::Camera left_cam = centre.with_eye(rs::kLeftEye), right_cam = centre.with_eye(rs::kRightEye);
  const StereoCamera stereo = centre.stereo;
  const ParallaxModel model = stereo.parallax(width, EyeDirection::left_to_right);
  const double c = stereo.convergence;
  for (const DepthEncoding encoding : {DepthEncoding::reversed, DepthEncoding::gl_ndc, DepthEncoding::linear}) {
    const DepthDecoder decoder = scene.decoder(encoding);
    double worst_position = 0.0, worst_parallax = 0.0, worst_depth = 0.0;
    for (const double z : {c, 0.5 * c, 0.75 * c, 2.0 * c, 4.0, 15.0}) {
      for (const double ndc_x : {-0.9, -0.3, 0.0, 0.55, 0.97}) {
        for (const double ndc_y : {-0.8, 0.1, 0.7}) {
          ClipPosition left, right;
          ASSERT_TRUE(place_at_depth(ndc_x, ndc_y, z, stereo, decoder, &left, &right).ok());
          auto pixel = [&](const ClipPosition& p, double* u, double* v) {
            *u = (p.x / p.w + 1.0) * 0.5 * width - 0.5;
            *v = (1.0 - p.y / p.w) * 0.5 * height - 0.5;
          };
          double ul, vl, ur, vr;
          pixel(left, &ul, &vl);
          pixel(right, &ur, &vr);
          // The truth: the point at depth z on the mono ray through the element, projected by the
          // ray caster's eye cameras.
          const double um = (ndc_x + 1.0) * 0.5 * width - 0.5, vm = (1.0 - ndc_y) * 0.5 * height - 0.5;
          const rs::Ray ray = centre.ray(um, vm);
          const rs::Vec3 point{ray.origin.x + z * ray.direction.x, ray.origin.y + z * ray.direction.y, z};
          double tl, tvl, tr, tvr;
          left_cam.project(point, &tl, &tvl);
          right_cam.project(point, &tr, &tvr);
          worst_position = std::max({worst_position, std::fabs(ul - tl), std::fabs(ur - tr), std::fabs(vl - tvl),
                                     std::fabs(vr - tvr)});
          worst_parallax = std::max(worst_parallax, std::fabs((ur - ul) - model.parallax(static_cast<float>(1.0 / z))));
          if (z == c) {
            EXPECT_NEAR(ur - ul, 0.0, 1e-4) << "zero parallax at the convergence plane";
          }
          EXPECT_EQ(left.z, right.z);
          worst_depth = std::max(worst_depth, std::fabs(decoder.linear_depth(left.z / left.w) - z) / z);
        }
      }
    }
    std::printf("  place_at_depth %-9s: eye positions within %.2e px of the ray caster's, parallax within %.2e px "
                "of the model, depth round trip %.2e\n",
                to_string(encoding), worst_position, worst_parallax, worst_depth);
    EXPECT_LT(worst_position, 2e-3);
    EXPECT_LT(worst_parallax, 2e-3);
    EXPECT_LT(worst_depth, 1e-5);
  }

  // At infinity the eyes are a = S W apart (parallel lines of sight for S = E).
  ClipPosition left, right;
  const DepthDecoder infinite = DepthDecoder::from_near_far(DepthEncoding::reversed_infinite, 0.1, 0.0);
  ASSERT_TRUE(place_at_depth(0.2, 0.0, kInf, stereo, infinite, &left, &right).ok());
  EXPECT_NEAR((right.x - left.x) * 0.5 * width, model.a, 1e-3);
  EXPECT_EQ(left.z, 0.0f);
  ClipPosition only;
  EXPECT_TRUE(place_at_depth(0.0, 0.0, c, stereo, infinite, &only, nullptr).ok());
  EXPECT_EQ(place_at_depth(0.0, 0.0, c, stereo, infinite, nullptr, nullptr).code(), StatusCode::null_pointer);
  EXPECT_EQ(place_at_depth(0.0, 0.0, 0.0, stereo, infinite, &left, &right).code(), StatusCode::invalid_option);
  EXPECT_EQ(place_at_depth(0.0, 0.0, kNaN, stereo, infinite, &left, &right).code(), StatusCode::invalid_option);
  EXPECT_EQ(place_at_depth(kInf, 0.0, c, stereo, infinite, &left, &right).code(), StatusCode::invalid_option);
  EXPECT_EQ(place_at_depth(0.0, 0.0, c, StereoCamera{0.03, -1.0}, infinite, &left, &right).code(),
            StatusCode::invalid_model);
  EXPECT_EQ(place_at_depth(0.0, 0.0, c, stereo, DepthDecoder::disparity(), &left, &right).code(),
            StatusCode::invalid_decoder);
}

// ---------------------------------------------------------------------------------------------
// 6. Halo-reduction pre-filter

TEST(PipelineHalo, DilationPicksTheNearestInTheWindow) {
  // Against a brute-force window search with w from DESIGN §3 in double, for encodings where nearer
  // means smaller (standard, linear) and larger (reversed) stored values.
  const int width = 37, height = 5;
  std::mt19937 rng(9);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  const double n = 0.5, f = 80.0;
  for (const DepthEncoding encoding : {DepthEncoding::standard, DepthEncoding::reversed, DepthEncoding::linear,
                                       DepthEncoding::infinite}) {
    SCOPED_TRACE(to_string(encoding));
    const DepthDecoder decoder = DepthDecoder::from_near_far(encoding, n, f);
    Image depth(width, height, 1), out(width, height, 1);
    for (int y = 0; y < height; ++y) {
      for (int x = 0; x < width; ++x) {
        float value = encoding == DepthEncoding::linear ? 1.0f + 50.0f * unit(rng) : unit(rng);
        if ((x * 7 + y) % 11 == 0) value = std::numeric_limits<float>::quiet_NaN();
        if (y == 4 && x < 9) value = std::numeric_limits<float>::quiet_NaN();  // a window of only NaN
        depth.plane_data()[y * depth.stride() + x] = value;
      }
    }
    for (const int radius : {0, 1, 2, 5, 100}) {
      ASSERT_TRUE(dilate_nearer_depth(depth.plane(), decoder, radius, out.mutable_plane()).ok());
      for (int y = 0; y < height; ++y) {
        const float* in = depth.plane_data() + y * depth.stride();
        for (int x = 0; x < width; ++x) {
          int best = -1;
          double best_w = -kInf;
          for (int j = std::max(0, x - radius); j <= std::min(width - 1, x + radius); ++j) {
            const double w = design_inverse_depth(encoding, in[j], n, f);
            if (w >= 0.0 && w > best_w) {
              best = j;
              best_w = w;
            }
          }
          const float expected = best < 0 ? in[x] : in[best];
          const float got = out.plane_data()[y * out.stride() + x];
          if (std::isnan(expected)) {
            EXPECT_TRUE(std::isnan(got)) << "x " << x << " y " << y << " r " << radius;
          } else {
            EXPECT_EQ(got, expected) << "x " << x << " y " << y << " r " << radius;
          }
        }
      }
    }
  }
  Image depth(4, 2, 1), small(3, 2, 1);
  const DepthDecoder decoder = DepthDecoder::linear();
  EXPECT_EQ(dilate_nearer_depth(depth.plane(), decoder, -1, depth.mutable_plane()).code(), StatusCode::aliasing);
  Image other(4, 2, 1);
  EXPECT_EQ(dilate_nearer_depth(depth.plane(), decoder, -1, other.mutable_plane()).code(), StatusCode::invalid_option);
  EXPECT_EQ(dilate_nearer_depth(depth.plane(), decoder, 1, small.mutable_plane()).code(), StatusCode::size_mismatch);
  EXPECT_EQ(dilate_nearer_depth(depth.plane(), DepthDecoder::from_near_far(DepthEncoding::standard, -1.0, 2.0), 1,
                                other.mutable_plane()).code(),
            StatusCode::invalid_decoder);
  FloatPlane null_plane = depth.plane();
  null_plane.data = nullptr;
  EXPECT_EQ(dilate_nearer_depth(null_plane, decoder, 1, other.mutable_plane()).code(), StatusCode::null_pointer);
}

// A view rendered as an anti-aliasing renderer resolves it: colour averaged over k x k sub-pixel
// rays, depth from the pixel centre's ray (a depth buffer holds one surface per pixel). A fourth
// colour plane holds the foreground coverage (the share of sub-pixel rays that meet an object
// other than the room's floor and back wall), so that a reprojection carries it like colour.
struct ResolvedView {
  Image color;  // 4 planes: R, G, B, foreground coverage
  Image depth;  // linear z at the pixel centre
};

ResolvedView render_resolved(const rs::Scene& scene, const rs::Camera& camera, int k) {
  const int w = camera.width, h = camera.height;
  ResolvedView view{Image(w, h, 4), Image(w, h, 1)};
  const int floor = scene.find_object("floor"), wall = scene.find_object("back_wall");
  auto rows = [&](int first, int step) {
    for (int y = first; y < h; y += step) {
      for (int x = 0; x < w; ++x) {
        double rgb[3] = {0.0, 0.0, 0.0}, coverage = 0.0;
        for (int sy = 0; sy < k; ++sy) {
          for (int sx = 0; sx < k; ++sx) {
            rs::Hit hit;
            const double u = x - 0.5 + (sx + 0.5) / k, v = y - 0.5 + (sy + 0.5) / k;
            if (!scene.trace(camera.ray(u, v), &hit)) continue;
            for (int c = 0; c < 3; ++c) rgb[c] += hit.rgb[c];
            coverage += hit.object != floor && hit.object != wall;
          }
        }
        const double samples = static_cast<double>(k) * k;
        for (int c = 0; c < 3; ++c) view.color.plane_data(c)[y * view.color.stride() + x] = static_cast<float>(rgb[c] / samples);
        view.color.plane_data(3)[y * view.color.stride() + x] = static_cast<float>(coverage / samples);
        rs::Hit centre;
        view.depth.plane_data()[y * view.depth.stride() + x] =
            scene.trace(camera.ray(x, y), &centre) ? static_cast<float>(centre.z) : INFINITY;
      }
    }
  };
  std::thread other(rows, 1, 2);
  rows(0, 2);
  other.join();
  return view;
}

TEST(PipelineHalo, DilationReducesForegroundHalos) {
  const int width = 480, height = 270, k = 4;
  for (const rs::SceneId id : {rs::SceneId::room, rs::SceneId::near}) {
    SCOPED_TRACE(rs::to_string(id));
    const rs::Scene scene = rs::Scene::make(id);
    const rs::Camera centre = scene.camera(width, height, rs::kCentreEye);
    const rs::Camera right = centre.with_eye(rs::kRightEye);
    const ResolvedView source = render_resolved(scene, centre, k);
    const ResolvedView truth = render_resolved(scene, right, k);
    std::vector<std::uint8_t> visible;
    ASSERT_TRUE(scene.visible_in_both(right, centre, &visible, 2).ok());
    const DepthDecoder decoder = scene.decoder(DepthEncoding::standard);
    const Image stored = rs::encode_depth(source.depth, decoder);
    const ParallaxModel model = centre.stereo.parallax(width, EyeDirection::centre_to_right);

    struct Result {
      double psnr_all = 0.0, psnr_visible = 0.0;
      int halos = 0;
    };
    auto measure = [&](const FloatPlane& depth) {
      Image color(width, height, 4);
      SourceView src;
      src.color = source.color.color();
      src.depth = depth;
      TargetView dst;
      dst.color = color.mutable_color();
      Options options;
      options.threads = 1;
      const Status status = reproject(src, decoder, model, options, dst);
      EXPECT_TRUE(status.ok()) << status.message();
      Result r;
      double se_all = 0.0, se_visible = 0.0, n_visible = 0.0;
      for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
          const std::ptrdiff_t i = y * color.stride() + x, t = y * truth.color.stride() + x;
          double se = 0.0;
          for (int c = 0; c < 3; ++c) {
            const double d = static_cast<double>(color.plane_data(c)[i]) - truth.color.plane_data(c)[t];
            se += d * d;
          }
          se_all += se;
          if (visible[static_cast<std::size_t>(y) * width + x]) {
            se_visible += se;
            n_visible += 3.0;
          }
          // A halo: foreground colour (more than a quarter) where the true eye sees only background.
          r.halos += truth.color.plane_data(3)[t] == 0.0f && color.plane_data(3)[i] > 0.25f;
        }
      }
      r.psnr_all = psnr(se_all, 3.0 * width * height);
      r.psnr_visible = psnr(se_visible, n_visible);
      return r;
    };
    const Result without = measure(stored.plane());
    std::printf("  halo %-5s %dx%d, %dx%d AA, exact, centre->right: without filter  PSNR %.2f dB (visible %.2f dB), "
                "halo pixels %d\n",
                rs::to_string(id), width, height, k, k, without.psnr_all, without.psnr_visible, without.halos);
    EXPECT_GT(without.halos, 0) << "the scene should show halos to remove";
    Image dilated(width, height, 1);
    for (const int radius : {1, 2, 3}) {
      ASSERT_TRUE(dilate_nearer_depth(stored.plane(), decoder, radius, dilated.mutable_plane()).ok());
      const Result with = measure(dilated.plane());
      std::printf("  halo %-5s %*s with radius %d      PSNR %.2f dB (visible %.2f dB), halo pixels %d\n",
                  rs::to_string(id), 44, "", radius, with.psnr_all, with.psnr_visible, with.halos);
      EXPECT_LT(with.halos, without.halos) << "radius " << radius;
      if (radius == 1) {
        EXPECT_LT(with.halos, without.halos / 2) << "one pixel covers the anti-aliased edge";
      }
    }
  }
}

}  // namespace
}  // namespace reproject
