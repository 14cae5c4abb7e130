// Every method against answers derived by hand from docs/DESIGN.md §2–§6 and
// docs/BEHAVIOUR.md, on rows whose geometry is simple enough to solve in closed form (planes,
// slanted planes, a box on a wall, the viewport edges), and `secant` against `exact` on random
// smooth rows and thin occluders.
//
// Conventions used throughout (docs/BEHAVIOUR.md "Coordinates"): x is in source columns, t' = t + guard,
// p(w) = a + b w, s = sign(b) (-1 when b <= 0), key s * p grows towards the viewer. Source colour
// channel 0 is the column index, so an output colour is the source x it was read at.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "reproject/reproject.hpp"
#include "support/arch_report.hpp"
#include "support/rows.hpp"

namespace {

using reproject::DepthEncoding;
using reproject::EdgeMode;
using reproject::EyeDirection;
using reproject::HoleFill;
using reproject::Method;
using reproject::Options;
using reproject::ParallaxModel;
using rptest::Encoding;
using rptest::RunResult;
using rptest::SourceFrame;
using rptest::Tally;

constexpr Method kAllMethods[] = {Method::scanline, Method::march16, Method::single, Method::secant,
                                  Method::exact};
// The methods documented as exact (scanline, exact) or within 1e-3 px on piecewise-planar rows
// with holes like exact (secant, DESIGN §6).
constexpr Method kExactLike[] = {Method::scanline, Method::secant, Method::exact};
constexpr EyeDirection kDirections[] = {EyeDirection::left_to_right, EyeDirection::right_to_left};

constexpr int kHit = 0;
constexpr int kHole = 1;
constexpr int kOutside = 2;
constexpr int kClipped = 3;

Encoding linear_encoding() { return {DepthEncoding::linear, 0.0, 0.0}; }
// A typical perspective buffer: 0 at near = 0.2, 1 at far = 100 (every surface here has w < 5).
Encoding standard_encoding() { return {DepthEncoding::standard, 0.2, 100.0}; }

int sign_of(const ParallaxModel& model) { return model.b > 0.0f ? 1 : -1; }
double parallax_of(const ParallaxModel& model, double w) {
  return static_cast<double>(model.a) + static_cast<double>(model.b) * w;
}
bool near_integer(double v, double eps) { return std::fabs(v - std::round(v)) < eps; }
const char* name(Method m) { return reproject::to_string(m); }
const char* name(EyeDirection d) { return reproject::to_string(d); }

// A pixel expected to be interpolated at source position x (hit, clipped, or outside with
// EdgeMode::clamp, where the interpolation clamps to the edge pixel): source_x within tol of x,
// channel 0 (the column) within tol of x clamped, and the other channels and the depth equal to
// the interpolation at the reported source_x (this part checks the resolve stage alone).
void check_interpolated(Tally& tally, const char* ctx, const RunResult& r, const SourceFrame& src,
                        const Encoding& enc, int t, int y, double x, double tol) {
  const int w = src.width;
  const double sx = r.out.x_at(t, y);
  if (!(std::fabs(sx - x) <= tol)) tally.fail("%s t=%d y=%d: source_x %.6f, expected %.6f", ctx, t, y, sx, x);
  const double c0 = r.out.color_at(0, t, y);
  if (!(std::fabs(c0 - rptest::color_at(0, x, w)) <= tol + 1e-4))
    tally.fail("%s t=%d y=%d: colour0 %.6f, expected %.6f", ctx, t, y, c0, rptest::color_at(0, x, w));
  for (int c = 1; c < src.channels; ++c) {
    const double got = r.out.color_at(c, t, y);
    const double want = rptest::color_at(c, sx, w);
    if (!(std::fabs(got - want) <= 2e-3))
      tally.fail("%s t=%d y=%d: colour%d %.6f, expected %.6f at x=%.6f", ctx, t, y, c, got, want, sx);
  }
  const double d = r.out.depth_at(t, y);
  const double dw = rptest::depth_interp(src, y, enc, sx);
  if (!(std::fabs(d - dw) <= 1e-4 * std::max(1.0, std::fabs(dw))))
    tally.fail("%s t=%d y=%d: depth %.7g, expected %.7g at x=%.6f", ctx, t, y, d, dw, sx);
}

// A hole pixel filled from source column `column` (or untouched with HoleFill::none).
void check_fill(Tally& tally, const char* ctx, const RunResult& r, const SourceFrame& src, int t, int y,
                int column, HoleFill fill) {
  for (int c = 0; c < src.channels; ++c) {
    const float got = r.out.color_at(c, t, y);
    const float want = fill == HoleFill::none ? rptest::kUntouched : rptest::column_color(c, column);
    if (!(got == want)) tally.fail("%s t=%d y=%d: hole colour%d %.6f, expected %.6f", ctx, t, y, c, got, want);
  }
  const double d = r.out.depth_at(t, y);
  const double want = fill == HoleFill::none ? rptest::kUntouched : src.depth_at(column, y);
  if (!(std::fabs(d - want) <= 1e-6 * std::max(1.0, std::fabs(want))))
    tally.fail("%s t=%d y=%d: hole depth %.7g, expected %.7g", ctx, t, y, d, want);
}

void check_status(Tally& tally, const char* ctx, const RunResult& r, int t, int y, int want) {
  const int got = r.out.status_at(t, y);
  if (got != want) tally.fail("%s t=%d y=%d: status %d, expected %d (source_x %.5f)", ctx, t, y, got, want, r.out.x_at(t, y));
}

std::string context(Method m, EyeDirection d, const Encoding& e, const std::string& extra = "") {
  return std::string(name(m)) + "/" + name(d) + "/" + e.name() + (extra.empty() ? "" : "/" + extra);
}

// --------------------------------------------------------------------------------------------
// Fronto-parallel planes: p is one constant, so every method's answer is x = t' - p exactly
// (march16 and single re-project with the one depth there is; scanline/secant/exact cross a flat
// line). Beyond the row the surface continues at the edge depth, so the crossing is t' - p there
// too and the pixel is outside exactly when t' - p is off [0, W - 1].
// --------------------------------------------------------------------------------------------

TEST(AnalyticPlane, FrontoParallelEveryMethodAtSeveralDepths) {
  const int width = 128;
  const double convergence = 2.0;
  for (const Encoding& enc : {linear_encoding(), standard_encoding()}) {
    for (EyeDirection dir : kDirections) {
      const ParallaxModel model = ParallaxModel::from_stereo(0.06, convergence, width, dir);
      ASSERT_TRUE(model.validate().ok()) << model.validate().message();
      // Nearer than, at, and farther than the convergence distance.
      for (double z : {0.9, 1.5, 2.0, 5.5, 40.0}) {
        SourceFrame src = rptest::make_source(width, 2, 3, reproject::ColorLayout::planar, 3);
        const float stored = enc.stored(1.0 / z);
        src.set_depth([&](int, int) { return stored; });
        const double p = parallax_of(model, enc.w(stored));
        for (std::optional<float> limit : {std::optional<float>(), std::optional<float>(30.0f)}) {
          for (Method method : kAllMethods) {
            Options options;
            options.method = method;
            options.max_negative_parallax = limit;
            const RunResult r = rptest::run(src, enc.decoder(), model, options);
            const std::string ctx = context(method, dir, enc, "z=" + std::to_string(z) + (limit ? "/limit30" : ""));
            ASSERT_TRUE(r.status.ok()) << ctx << ": " << r.status.message();
            Tally tally;
            int hits = 0;
            for (int y = 0; y < src.height; ++y) {
              for (int t = 0; t < width; ++t) {
                const double x = t - p;
                if (x > 1e-3 && x < width - 1 - 1e-3) {
                  ++hits;
                  check_status(tally, ctx.c_str(), r, t, y, kHit);
                  check_interpolated(tally, ctx.c_str(), r, src, enc, t, y, x, 1e-3);
                } else if (x < -1e-3 || x > width - 1 + 1e-3) {
                  check_status(tally, ctx.c_str(), r, t, y, kOutside);
                  check_interpolated(tally, ctx.c_str(), r, src, enc, t, y, x, 1e-3);
                }
              }
            }
            EXPECT_GT(hits, src.height * (width - 24)) << ctx;
            EXPECT_EQ(tally.count(), 0) << ctx << tally.report();
          }
        }
      }
    }
  }
}

TEST(AnalyticPlane, March16StepCountsAndSingleProbeAtConvergence) {
  const int width = 96;
  const double convergence = 2.0;
  const Encoding enc = linear_encoding();
  for (EyeDirection dir : kDirections) {
    const ParallaxModel model = ParallaxModel::from_stereo(0.07, convergence, width, dir);
    for (double z : {1.1, 2.0, 9.0}) {
      SourceFrame src = rptest::make_source(width, 1, 2);
      src.set_depth([&](int, int) { return z; });
      const double p = parallax_of(model, enc.w(static_cast<float>(z)));
      struct Variant {
        Method method;
        int steps;
        std::optional<float> probe;
        std::optional<float> limit;
      };
      std::vector<Variant> variants;
      for (int steps : {1, 8, 32, 1024})
        for (std::optional<float> limit : {std::optional<float>(), std::optional<float>(25.0f)})
          variants.push_back({Method::march16, steps, std::nullopt, limit});
      // single with the probe at the convergence plane (and anywhere else: the plane has one depth).
      variants.push_back({Method::single, 16, 0.0f, std::nullopt});
      variants.push_back({Method::single, 16, -3.0f, 25.0f});
      for (const Variant& v : variants) {
        Options options;
        options.method = v.method;
        options.march_steps = v.steps;
        options.probe_parallax = v.probe;
        options.max_negative_parallax = v.limit;
        const RunResult r = rptest::run(src, enc.decoder(), model, options);
        const std::string ctx = context(v.method, dir, enc, "z=" + std::to_string(z) + "/steps=" +
                                                                std::to_string(v.steps));
        ASSERT_TRUE(r.status.ok()) << ctx << ": " << r.status.message();
        Tally tally;
        for (int t = 0; t < width; ++t) {
          const double x = t - p;
          if (x > 1e-3 && x < width - 1 - 1e-3) {
            check_status(tally, ctx.c_str(), r, t, 0, kHit);
            check_interpolated(tally, ctx.c_str(), r, src, enc, t, 0, x, 1e-3);
          }
        }
        EXPECT_EQ(tally.count(), 0) << ctx << tally.report();
      }
    }
  }
}

// A wall needs P[j+1] - P[j] > tau, strictly: on a flat plane (differences exactly 0, every pixel
// stores the same value) tau = 0 makes no wall, for every method.
TEST(AnalyticPlane, ZeroThresholdMakesNoWallOnAFlatPlane) {
  const int width = 70;
  for (const Encoding& enc : {linear_encoding(), standard_encoding()}) {
    for (EyeDirection dir : kDirections) {
      const ParallaxModel model = ParallaxModel::from_stereo(0.06, 2.0, width, dir);
      SourceFrame src = rptest::make_source(width, 1, 1);
      const float stored = enc.stored(1.0 / 3.3);
      src.set_depth([&](int, int) { return stored; });
      const double p = parallax_of(model, enc.w(stored));
      for (Method method : kAllMethods) {
        Options options;
        options.method = method;
        options.hole_threshold = 0.0f;
        const RunResult r = rptest::run(src, enc.decoder(), model, options);
        const std::string ctx = context(method, dir, enc, "tau=0");
        ASSERT_TRUE(r.status.ok()) << ctx << ": " << r.status.message();
        Tally tally;
        for (int t = 0; t < width; ++t) {
          const double x = t - p;
          if (x > 1e-3 && x < width - 1 - 1e-3) check_status(tally, ctx.c_str(), r, t, 0, kHit);
        }
        EXPECT_EQ(tally.count(), 0) << ctx << tally.report();
      }
    }
  }
}

// --------------------------------------------------------------------------------------------
// Slanted plane: w linear in x, so P(x) = P_mid + k (x - x_mid) exactly (linear interpolation is
// exact for planes, DESIGN §5). With -1 < k <= tau there are no walls or folds and x + P(x) is
// increasing, so the one crossing of x + P(x) = t' is x* = (t' - P_mid + k x_mid) / (1 + k); off
// the row the surface continues flat at the edge value, giving x* = t' - P(edge).
// --------------------------------------------------------------------------------------------

struct Slant {
  double k;      // dP/dx, pixels per pixel
  double p_mid;  // P at x_mid
  double x_mid;
  double P(double x) const { return p_mid + k * (x - x_mid); }
  // The exact crossing for target t', using the flat continuation beyond [0, width - 1].
  double crossing(double t, int width) const {
    const double x = (t - p_mid + k * x_mid) / (1.0 + k);
    if (x < 0.0) return t - P(0.0);
    if (x > width - 1) return t - P(width - 1);
    return x;
  }
};

// Fills every row of `src` with the slanted plane P(x) (depth from w = (P - a) / b) and returns it.
// P_mid keeps the whole row on the finite side of infinity: sign(P - a) = s.
Slant make_slant(SourceFrame& src, const Encoding& enc, const ParallaxModel& model, double k) {
  const int s = sign_of(model);
  Slant slant{k, model.a + s * (3.0 + std::fabs(k) * src.width / 2.0), (src.width - 1) / 2.0};
  src.set_depth([&](int x, int) { return enc.stored((slant.P(x) - model.a) / model.b); });
  return slant;
}

// --------------------------------------------------------------------------------------------
// Vector body and scalar tail: every SIMD kernel runs whole vectors, then its scalar reference on
// the last W mod L columns. Where the two round differently, a flat plane's parallax steps at the
// boundary and tau = 0 sees a wall (AVX-512 once decoded its body unfused and its tail fused).
// Widths put the boundary on every lane count (4, 8, 16) and one either side of it; the planes
// are flat and slanted with P decreasing (p[j+1] - p[j] <= 0: no wall at tau = 0), every arch.
// --------------------------------------------------------------------------------------------

class BodyAndTail : public ::testing::TestWithParam<reproject::Arch> {};

TEST_P(BodyAndTail, ZeroThresholdSeesNoWallOnFlatOrSlantedPlanes) {
  const reproject::Arch arch = GetParam();
  if (!reproject::arch_supported(arch)) GTEST_SKIP() << reproject::not_run_reason(arch);
  const int widths[] = {3, 4, 5, 7, 8, 9, 15, 16, 17, 31, 32, 33, 63, 64, 65, 127, 128, 129};
  long runs = 0, walls = 0;
  for (int width : widths) {
    for (const Encoding& enc : {linear_encoding(), standard_encoding()}) {
      for (EyeDirection dir : kDirections) {
        const ParallaxModel model = ParallaxModel::from_stereo(0.06, 2.0, std::max(width, 40), dir);
        for (double k : {0.0, -0.3}) {
          SourceFrame src = rptest::make_source(width, 2, 1);
          const Slant slant = make_slant(src, enc, model, k);
          for (Method method : kAllMethods) {
            Options options;
            options.method = method;
            options.arch = arch;
            options.hole_threshold = 0.0f;
            const RunResult r = rptest::run(src, enc.decoder(), model, options);
            const std::string ctx = context(method, dir, enc, "width " + std::to_string(width) + (k == 0.0 ? " flat" : " slanted") +
                                                                  " " + reproject::to_string(arch));
            ASSERT_TRUE(r.status.ok()) << ctx << ": " << r.status.message();
            ++runs;
            Tally tally;
            for (int y = 0; y < 2; ++y) {
              for (int t = 0; t < width; ++t) {
                const double x = slant.crossing(t, width);
                if (x > 1e-3 && x < width - 1 - 1e-3) check_status(tally, ctx.c_str(), r, t, y, kHit);
              }
            }
            walls += tally.count();
            EXPECT_EQ(tally.count(), 0) << ctx << tally.report();
          }
        }
      }
    }
  }
  std::printf("%s: %ld runs at body/tail widths, %ld wall pixels at tau = 0\n", reproject::to_string(arch), runs, walls);
}

INSTANTIATE_TEST_SUITE_P(EveryArch, BodyAndTail,
                         ::testing::ValuesIn(reproject::every_arch()),
                         [](const ::testing::TestParamInfo<reproject::Arch>& info) {
                           return std::string(reproject::to_string(info.param));
                         });

TEST(AnalyticSlanted, ScanlineSecantExactWithinAHundredthOfThePlaneCrossing) {
  const int width = 160;
  for (const Encoding& enc : {linear_encoding(), standard_encoding()}) {
    for (EyeDirection dir : kDirections) {
      const ParallaxModel model = ParallaxModel::from_stereo(0.1, 2.0, width, dir);
      for (double k : {-0.6, -0.25, 0.3, 0.7}) {
        SourceFrame src = rptest::make_source(width, 2, 3);
        const Slant slant = make_slant(src, enc, model, k);
        for (Method method : kExactLike) {
          Options options;
          options.method = method;
          const RunResult r = rptest::run(src, enc.decoder(), model, options);
          const std::string ctx = context(method, dir, enc, "k=" + std::to_string(k));
          ASSERT_TRUE(r.status.ok()) << ctx << ": " << r.status.message();
          Tally tally;
          int hits = 0;
          for (int y = 0; y < src.height; ++y) {
            for (int t = 0; t < width; ++t) {
              const double x = slant.crossing(t, width);
              if (std::fabs(x) < 0.02 || std::fabs(x - (width - 1)) < 0.02) continue;
              const bool inside = x > 0.0 && x < width - 1;
              hits += inside;
              check_status(tally, ctx.c_str(), r, t, y, inside ? kHit : kOutside);
              check_interpolated(tally, ctx.c_str(), r, src, enc, t, y, x, 0.01);
            }
          }
          EXPECT_GT(hits, width / 2) << ctx;
          EXPECT_EQ(tally.count(), 0) << ctx << tally.report();
        }
      }
    }
  }
}

// The hole threshold decides what is a wall: on a plane whose parallax rises k = 0.3 px per pixel
// every segment is a wall when tau < 0.3 and none is when tau > 0.3, whatever the method (the
// resolve stage is shared). For the exact-like methods the fill is the wall's farther endpoint:
// column j + 1 when s < 0 (key -P falls with x), column j when s > 0, j = floor(x*).
TEST(AnalyticSlanted, HoleThresholdDecidesWhatIsAWall) {
  const int width = 80;
  const double k = 0.3;
  for (const Encoding& enc : {linear_encoding(), standard_encoding()}) {
    for (EyeDirection dir : kDirections) {
      const ParallaxModel model = ParallaxModel::from_stereo(0.08, 2.0, width, dir);
      const int s = sign_of(model);
      SourceFrame src = rptest::make_source(width, 1, 2);
      const Slant slant = make_slant(src, enc, model, k);
      for (Method method : kAllMethods) {
        for (float tau : {0.0f, 0.25f, 0.35f, 1.0f}) {
          Options options;
          options.method = method;
          options.hole_threshold = tau;
          const RunResult r = rptest::run(src, enc.decoder(), model, options);
          const std::string ctx = context(method, dir, enc, "tau=" + std::to_string(tau));
          ASSERT_TRUE(r.status.ok()) << ctx << ": " << r.status.message();
          const bool walls = tau < k;
          Tally tally;
          int holes = 0;
          for (int t = 0; t < width; ++t) {
            const int status = r.out.status_at(t, 0);
            if (status == kOutside) continue;
            holes += status == kHole;
            if (status != (walls ? kHole : kHit))
              tally.fail("%s t=%d: status %d, expected %d", ctx.c_str(), t, status, walls ? kHole : kHit);
          }
          if (walls) {
            EXPECT_GT(holes, width / 2) << ctx;
          }
          bool exact_like = false;
          for (Method m : kExactLike) exact_like |= m == method;
          if (walls && exact_like) {
            for (int t = 0; t < width; ++t) {
              const double x = slant.crossing(t, width);
              if (x < 0.01 || x > width - 1.01 || near_integer(x, 1e-3)) continue;
              const int j = static_cast<int>(std::floor(x));
              check_status(tally, ctx.c_str(), r, t, 0, kHole);
              check_fill(tally, ctx.c_str(), r, src, t, 0, s < 0 ? j + 1 : j, HoleFill::background);
            }
          }
          EXPECT_EQ(tally.count(), 0) << ctx << tally.report();
        }
      }
    }
  }
}

// --------------------------------------------------------------------------------------------
// A near box (columns j0..j1) on a far wall. Wall parallax p_f, box p_n, D = |p_f - p_n| > 1.
// s < 0 (b < 0, left→right): the right edge [j1, j1+1] rises by D: a wall; the left edge is a fold.
//   The sweep paints [q(j), q(j+1)) walking j upwards, q(x) = x + P(x), so
//   box:  t' in [j0 + p_n, j1 + p_n)        x* = t' - p_n
//   hole: t' in [j1 + p_n, j1 + 1 + p_f)    on the wall; background = column j1 + 1, foreground = j1
//   wall elsewhere: x* = t' - p_f (outside when off the row).
// s > 0 (b > 0, right→left): the left edge [j0-1, j0] rises by D: the wall; intervals (q(j), q(j+1)]
//   box:  t' in (j0 + p_n, j1 + p_n]        x* = t' - p_n
//   hole: t' in (j0 - 1 + p_f, j0 + p_n]    background = column j0 - 1, foreground = j0
// --------------------------------------------------------------------------------------------

struct Step {
  int width = 0;
  int j0 = 0, j1 = 0;  // box columns, inclusive
  double p_f = 0.0, p_n = 0.0;
  int s = -1;

  struct Expect {
    int status;
    double x;         // x* (for holes: on the wall segment)
    int background;   // hole fill columns
    int foreground;
    double margin;    // distance of t' from the nearest region boundary
  };

  Expect at(double t) const {
    Expect e{kHit, 0.0, 0, 0, 1e9};
    std::vector<double> bounds;
    if (s < 0) {
      bounds = {j0 + p_n, j1 + p_n, j1 + 1 + p_f, p_f, width - 1 + p_f};
      e.background = j1 + 1;
      e.foreground = j1;
      if (t >= j0 + p_n && t < j1 + p_n) {
        e.x = t - p_n;
      } else if (t >= j1 + p_n && t < j1 + 1 + p_f) {
        e.status = kHole;
        e.x = j1 + (t - (j1 + p_n)) / (1.0 + p_f - p_n);
      } else {
        e.x = t - p_f;
      }
    } else {
      bounds = {j0 - 1 + p_f, j0 + p_n, j1 + p_n, p_f, width - 1 + p_f};
      e.background = j0 - 1;
      e.foreground = j0;
      if (t > j0 + p_n && t <= j1 + p_n) {
        e.x = t - p_n;
      } else if (t > j0 - 1 + p_f && t <= j0 + p_n) {
        e.status = kHole;
        e.x = (j0 - 1) + (t - (j0 - 1 + p_f)) / (1.0 + p_n - p_f);
      } else {
        e.x = t - p_f;
      }
    }
    if (e.status == kHit && (e.x < 0.0 || e.x > width - 1)) e.status = kOutside;
    for (double b : bounds) e.margin = std::min(e.margin, std::fabs(t - b));
    return e;
  }
};

struct StepConfig {
  int width;
  double separation, convergence, z_far, z_near;
  int j0, j1;
};

Step make_step(SourceFrame& src, const Encoding& enc, const ParallaxModel& model, const StepConfig& c) {
  const float far_value = enc.stored(1.0 / c.z_far);
  const float near_value = enc.stored(1.0 / c.z_near);
  src.set_depth([&](int x, int) { return x >= c.j0 && x <= c.j1 ? near_value : far_value; });
  Step step;
  step.width = c.width;
  step.j0 = c.j0;
  step.j1 = c.j1;
  step.p_f = parallax_of(model, enc.w(far_value));
  step.p_n = parallax_of(model, enc.w(near_value));
  step.s = sign_of(model);
  return step;
}

const StepConfig kSteps[] = {
    {96, 0.08, 2.0, 6.0, 1.2, 40, 55},   // p_f = ±5.12, p_n = ∓5.12: a 10 px tear
    {96, 0.05, 2.0, 3.0, 1.45, 30, 37},  // p_f = ±1.6, p_n ≈ ∓1.82: a 3.4 px tear
    {128, 0.1, 1.5, 40.0, 0.9, 70, 72},  // a 3-column box far out of the screen
};

TEST(AnalyticStep, HolesExactlyAtTheDisocclusionWithEachFill) {
  for (const StepConfig& config : kSteps) {
    for (const Encoding& enc : {linear_encoding(), standard_encoding()}) {
      for (EyeDirection dir : kDirections) {
        const ParallaxModel model =
            ParallaxModel::from_stereo(config.separation, config.convergence, config.width, dir);
        SourceFrame src = rptest::make_source(config.width, 1, 3);
        const Step step = make_step(src, enc, model, config);
        ASSERT_GT(std::fabs(step.p_f - step.p_n), 1.0);
        for (Method method : kExactLike) {
          for (HoleFill fill : {HoleFill::background, HoleFill::foreground, HoleFill::none}) {
            Options options;
            options.method = method;
            options.hole_fill = fill;
            const RunResult r = rptest::run(src, enc.decoder(), model, options);
            const std::string ctx = context(method, dir, enc,
                                            "box" + std::to_string(config.j0) + "/fill" +
                                                std::to_string(static_cast<int>(fill)));
            ASSERT_TRUE(r.status.ok()) << ctx << ": " << r.status.message();
            Tally tally;
            int holes = 0;
            int expected_holes = 0;
            for (int t = 0; t < config.width; ++t) {
              const Step::Expect e = step.at(t);
              if (e.margin < 1e-3) continue;
              check_status(tally, ctx.c_str(), r, t, 0, e.status);
              holes += r.out.status_at(t, 0) == kHole;
              if (e.status == kHole) {
                ++expected_holes;
                check_fill(tally, ctx.c_str(), r, src, t, 0,
                           fill == HoleFill::foreground ? e.foreground : e.background, fill);
              } else {
                check_interpolated(tally, ctx.c_str(), r, src, enc, t, 0, e.x, 2e-3);
              }
            }
            // The tear is D + 1 pixels wide (minus the rounding to whole targets).
            EXPECT_GE(expected_holes, static_cast<int>(std::fabs(step.p_f - step.p_n))) << ctx;
            EXPECT_EQ(holes, expected_holes) << ctx;
            EXPECT_EQ(tally.count(), 0) << ctx << tally.report();
          }
        }
      }
    }
  }
}

// tau just above the tear D makes the tear an ordinary (stretched) segment: the hole pixels become
// hits interpolated along [j1, j1+1] (s < 0) or [j0-1, j0] (s > 0); just below, they stay holes.
TEST(AnalyticStep, HoleThresholdAroundTheTearSize) {
  const StepConfig& config = kSteps[0];
  const Encoding enc = linear_encoding();
  for (EyeDirection dir : kDirections) {
    const ParallaxModel model = ParallaxModel::from_stereo(config.separation, config.convergence, config.width, dir);
    SourceFrame src = rptest::make_source(config.width, 1, 2);
    const Step step = make_step(src, enc, model, config);
    const double tear = std::fabs(step.p_f - step.p_n);
    for (Method method : kExactLike) {
      for (double delta : {-0.25, 0.25}) {
        Options options;
        options.method = method;
        options.hole_threshold = static_cast<float>(tear + delta);
        const RunResult r = rptest::run(src, enc.decoder(), model, options);
        const std::string ctx = context(method, dir, enc, "tau=D" + std::to_string(delta));
        ASSERT_TRUE(r.status.ok()) << ctx << ": " << r.status.message();
        Tally tally;
        int tear_pixels = 0;
        for (int t = 0; t < config.width; ++t) {
          const Step::Expect e = step.at(t);
          if (e.margin < 1e-3) continue;
          if (e.status == kHole) {
            ++tear_pixels;
            if (delta < 0) {
              check_status(tally, ctx.c_str(), r, t, 0, kHole);
              check_fill(tally, ctx.c_str(), r, src, t, 0, e.background, HoleFill::background);
            } else {
              check_status(tally, ctx.c_str(), r, t, 0, kHit);
              check_interpolated(tally, ctx.c_str(), r, src, enc, t, 0, e.x, 2e-3);
            }
          } else {
            check_status(tally, ctx.c_str(), r, t, 0, e.status);
          }
        }
        EXPECT_GE(tear_pixels, 10) << ctx;
        EXPECT_EQ(tally.count(), 0) << ctx << tally.report();
      }
    }
  }
}

// --------------------------------------------------------------------------------------------
// march16 and single on the box: their answers are fully specified by docs/BEHAVIOUR.md (point samples at
// index floor(x + 0.5) clamped, the march's sample parallaxes p_k = p_near + k (p_far - p_near)/N,
// re-projection x = t' - P), so they are re-derived here in double for every pixel; pixels where a
// rounding tie could go either way are skipped.
// --------------------------------------------------------------------------------------------

struct RuleAnswer {
  bool ambiguous = false;
  int status = kHit;
  double x = 0.0;
};

RuleAnswer resolve(const std::vector<double>& P, double x, bool clipped, double tau) {
  RuleAnswer a;
  a.x = x;
  const int w = static_cast<int>(P.size());
  if (clipped) {
    a.status = kClipped;
  } else if (x < 0.0 || x > w - 1) {
    a.status = kOutside;
    a.ambiguous = std::fabs(x) < 1e-4 || std::fabs(x - (w - 1)) < 1e-4;
  } else {
    const int j = static_cast<int>(std::floor(x));
    a.ambiguous = near_integer(x, 1e-4);
    a.status = j < w - 1 && P[static_cast<std::size_t>(j + 1)] - P[static_cast<std::size_t>(j)] > tau ? kHole : kHit;
  }
  return a;
}

// Point sample of BEHAVIOUR: P[clamp(floor(x + 0.5))]; flags a rounding tie.
double point_sample(const std::vector<double>& P, double x, bool* tie) {
  const double v = x + 0.5;
  if (std::fabs(v - std::round(v)) < 1e-4) *tie = true;
  const int i = std::min(std::max(static_cast<int>(std::floor(v)), 0), static_cast<int>(P.size()) - 1);
  return P[static_cast<std::size_t>(i)];
}

RuleAnswer march16_rule(const std::vector<double>& P, double t, int s, double p_near, double p_far,
                        int steps, double tau) {
  bool tie = false;
  for (int k = 0; k <= steps; ++k) {
    const double pk = k == steps ? p_far : p_near + k * (p_far - p_near) / steps;
    const double sample = point_sample(P, t - pk, &tie);
    const double diff = s * sample - s * pk;
    if (diff != 0.0 && std::fabs(diff) < 1e-4) tie = true;
    if (diff >= 0.0) {
      RuleAnswer a = resolve(P, t - sample, k == 0 && s * sample > s * p_near, tau);
      a.ambiguous |= tie;
      return a;
    }
  }
  RuleAnswer a = resolve(P, t - p_far, false, tau);  // unreachable with finite depths
  a.ambiguous = true;
  return a;
}

RuleAnswer single_rule(const std::vector<double>& P, double t, int s, double p_near, double probe, double tau) {
  bool tie = false;
  const double sample = point_sample(P, t - probe, &tie);
  RuleAnswer a = resolve(P, t - sample, s * sample > s * p_near, tau);
  a.ambiguous |= tie;
  return a;
}

TEST(AnalyticRules, March16AndSingleFollowTheirRulesOnABox) {
  for (const StepConfig& config : kSteps) {
    const Encoding enc = linear_encoding();
    for (EyeDirection dir : kDirections) {
      const ParallaxModel model =
          ParallaxModel::from_stereo(config.separation, config.convergence, config.width, dir);
      SourceFrame src = rptest::make_source(config.width, 1, 2);
      const Step step = make_step(src, enc, model, config);
      const std::vector<double> P = rptest::ref_parallax_row(src, 0, enc, model);
      const int s = step.s;
      const double p_far = model.a;
      for (std::optional<float> limit : {std::optional<float>(), std::optional<float>(1.3f)}) {
        // Unset: the nearest parallax of the frame (the box); set: s * limit.
        const double p_near = limit ? s * static_cast<double>(*limit) : step.p_n;
        struct Variant {
          Method method;
          int steps;
          std::optional<float> probe;
        };
        const Variant variants[] = {{Method::march16, 8, std::nullopt},  {Method::march16, 16, std::nullopt},
                                    {Method::march16, 32, std::nullopt}, {Method::single, 16, std::nullopt},
                                    {Method::single, 16, 0.0f},          {Method::single, 16, static_cast<float>(step.p_n)}};
        for (const Variant& v : variants) {
          Options options;
          options.method = v.method;
          options.march_steps = v.steps;
          options.probe_parallax = v.probe;
          options.max_negative_parallax = limit;
          const RunResult r = rptest::run(src, enc.decoder(), model, options);
          const std::string ctx = context(v.method, dir, enc,
                                          "box" + std::to_string(config.j0) + "/N=" + std::to_string(v.steps) +
                                              (v.probe ? "/probe=" + std::to_string(*v.probe) : "") +
                                              (limit ? "/limit" : ""));
          ASSERT_TRUE(r.status.ok()) << ctx << ": " << r.status.message();
          Tally tally;
          int checked = 0;
          for (int t = 0; t < config.width; ++t) {
            const RuleAnswer e = v.method == Method::march16
                                     ? march16_rule(P, t, s, p_near, p_far, v.steps, 1.0)
                                     : single_rule(P, t, s, p_near, v.probe ? *v.probe : p_far, 1.0);
            if (e.ambiguous) continue;
            ++checked;
            check_status(tally, ctx.c_str(), r, t, 0, e.status);
            if (e.status == kHole) {
              const double sx = r.out.x_at(t, 0);
              if (!(std::fabs(sx - e.x) <= 1e-3)) tally.fail("%s t=%d: hole source_x %.5f, expected %.5f", ctx.c_str(), t, sx, e.x);
            } else {
              check_interpolated(tally, ctx.c_str(), r, src, enc, t, 0, e.x, 1e-3);
            }
          }
          EXPECT_GT(checked, config.width * 9 / 10) << ctx;
          EXPECT_EQ(tally.count(), 0) << ctx << tally.report();
        }
      }
    }
  }
}

// --------------------------------------------------------------------------------------------
// Viewport edges. A fronto plane at parallax p: target t' reads x = t' - p, which is off the row
// for the |p| targets on one side: outside. EdgeMode::clamp gives them the edge pixel's colour and
// depth; EdgeMode::none leaves both untouched (status and source_x are still written). A guard
// band of g >= |p| columns (source wider by 2g, t' = t + g) leaves no target outside.
// --------------------------------------------------------------------------------------------

TEST(AnalyticEdge, OutsideExactlyWhereTheSourceHasNoData) {
  const int width = 64;
  for (const Encoding& enc : {linear_encoding(), standard_encoding()}) {
    for (EyeDirection dir : kDirections) {
      const ParallaxModel model = ParallaxModel::from_stereo(0.1, 2.0, width, dir);
      // Row 0 far (outside on one side), row 1 near (outside on the other side).
      SourceFrame src = rptest::make_source(width, 2, 3);
      const float far_value = enc.stored(1.0 / 7.0);
      const float near_value = enc.stored(1.0 / 1.25);
      src.set_depth([&](int, int y) { return y == 0 ? far_value : near_value; });
      const double p_row[2] = {parallax_of(model, enc.w(far_value)), parallax_of(model, enc.w(near_value))};
      for (Method method : kAllMethods) {
        for (EdgeMode edge : {EdgeMode::clamp, EdgeMode::none}) {
          Options options;
          options.method = method;
          options.edge = edge;
          const RunResult r = rptest::run(src, enc.decoder(), model, options);
          const std::string ctx = context(method, dir, enc, edge == EdgeMode::clamp ? "clamp" : "none");
          ASSERT_TRUE(r.status.ok()) << ctx << ": " << r.status.message();
          Tally tally;
          for (int y = 0; y < 2; ++y) {
            const double p = p_row[y];
            int outside = 0;
            for (int t = 0; t < width; ++t) {
              const double x = t - p;
              const bool off = x < 0.0 || x > width - 1;
              outside += off;
              check_status(tally, ctx.c_str(), r, t, y, off ? kOutside : kHit);
              if (off && edge == EdgeMode::none) {
                const double sx = r.out.x_at(t, y);
                if (!(std::fabs(sx - x) <= 1e-3)) tally.fail("%s t=%d y=%d: source_x %.5f, expected %.5f", ctx.c_str(), t, y, sx, x);
                for (int c = 0; c < src.channels; ++c)
                  if (r.out.color_at(c, t, y) != rptest::kUntouched) tally.fail("%s t=%d y=%d: outside colour%d written", ctx.c_str(), t, y, c);
                if (r.out.depth_at(t, y) != rptest::kUntouched) tally.fail("%s t=%d y=%d: outside depth written", ctx.c_str(), t, y);
              } else {
                // With clamp, colour and depth of an outside pixel are the edge pixel's:
                // color_at and depth_interp clamp x to the row.
                check_interpolated(tally, ctx.c_str(), r, src, enc, t, y, x, 1e-3);
                if (off) {
                  const int edge_column = x < 0.0 ? 0 : width - 1;
                  if (r.out.color_at(1, t, y) != rptest::column_color(1, edge_column))
                    tally.fail("%s t=%d y=%d: outside colour1 is not the edge pixel's", ctx.c_str(), t, y);
                }
              }
            }
            // |p| targets (rounded up) have no source data.
            EXPECT_EQ(outside, static_cast<int>(std::ceil(std::fabs(p)))) << ctx << " row " << y << " p=" << p;
          }
          EXPECT_EQ(tally.count(), 0) << ctx << tally.report();
        }
      }
    }
  }
}

TEST(AnalyticEdge, GuardBandRemovesOutsidePixels) {
  const int target_width = 48;
  const Encoding enc = linear_encoding();
  for (EyeDirection dir : kDirections) {
    const ParallaxModel model = ParallaxModel::from_stereo(0.1, 2.0, target_width, dir);
    for (int guard : {3, 5, 8}) {
      const int width = target_width + 2 * guard;
      SourceFrame src = rptest::make_source(width, 2, 2);
      // Row 0 far (p = 0.1 * 48 * (1 - 2/7) ≈ ±3.43), row 1 near (p ≈ ∓3.84).
      src.set_depth([&](int, int y) { return y == 0 ? 7.0 : 1.1111111; });
      for (Method method : kAllMethods) {
        Options options;
        options.method = method;
        options.guard = guard;
        const RunResult r = rptest::run(src, enc.decoder(), model, options);
        const std::string ctx = context(method, dir, enc, "guard=" + std::to_string(guard));
        ASSERT_TRUE(r.status.ok()) << ctx << ": " << r.status.message();
        ASSERT_EQ(r.out.width, target_width);
        Tally tally;
        for (int y = 0; y < 2; ++y) {
          const double p = parallax_of(model, 1.0 / src.depth_at(0, y));
          int outside = 0;
          for (int t = 0; t < target_width; ++t) {
            const double x = t + guard - p;  // in source columns
            const bool off = x < 0.0 || x > width - 1;
            outside += off;
            check_status(tally, ctx.c_str(), r, t, y, off ? kOutside : kHit);
            check_interpolated(tally, ctx.c_str(), r, src, enc, t, y, x, 1e-3);
          }
          const int expected = std::max(0, static_cast<int>(std::ceil(std::fabs(p) - guard)));
          EXPECT_EQ(outside, expected) << ctx << " row " << y << " p=" << p;
          if (guard >= std::fabs(p)) {
            EXPECT_EQ(outside, 0) << ctx;
          }
        }
        EXPECT_EQ(tally.count(), 0) << ctx << tally.report();
      }
    }
  }
}

// --------------------------------------------------------------------------------------------
// Clipping. With Options::max_negative_parallax = m the ray of t' starts at x_near = t' - s m and
// is clipped when the surface there is strictly nearer: s P(x_near) > m (P interpolated, clamped
// beyond the row). Then x* = x_near and colour/depth are interpolated there. march16 and single
// decide with their point sample (docs/BEHAVIOUR.md) and re-project with it.
// --------------------------------------------------------------------------------------------

TEST(AnalyticClip, ClippedExactlyWhereTheNearEndIsBehindTheSurface) {
  const StepConfig config{96, 0.08, 2.0, 6.0, 1.0, 40, 55};  // box at p_n = ∓7.68: crossed by 7.68 px
  for (const Encoding& enc : {linear_encoding(), standard_encoding()}) {
    for (EyeDirection dir : kDirections) {
      const ParallaxModel model = ParallaxModel::from_stereo(config.separation, config.convergence, config.width, dir);
      SourceFrame src = rptest::make_source(config.width, 1, 2);
      const Step step = make_step(src, enc, model, config);
      const std::vector<double> P = rptest::ref_parallax_row(src, 0, enc, model);
      const int s = step.s;
      for (float m : {0.0f, 2.9f, 4.3f, 7.0f, 9.0f}) {
        for (Method method : kAllMethods) {
          Options options;
          options.method = method;
          options.max_negative_parallax = m;
          const RunResult r = rptest::run(src, enc.decoder(), model, options);
          const std::string ctx = context(method, dir, enc, "m=" + std::to_string(m));
          ASSERT_TRUE(r.status.ok()) << ctx << ": " << r.status.message();
          Tally tally;
          int clipped = 0;
          for (int t = 0; t < config.width; ++t) {
            const double x_near = t - s * static_cast<double>(m);
            bool want = false;
            double x = x_near;
            if (method == Method::march16 || method == Method::single) {
              bool tie = false;
              const double probe = method == Method::march16 ? x_near : t - static_cast<double>(model.a);
              const double sample = point_sample(P, probe, &tie);
              if (tie || std::fabs(s * sample - m) < 1e-4) continue;
              want = s * sample > m;
              x = t - sample;
            } else {
              const double key = s * rptest::interp_clamped(P, x_near);
              if (std::fabs(key - m) < 1e-3) continue;
              want = key > m;
            }
            clipped += want;
            const int got = r.out.status_at(t, 0);
            if ((got == kClipped) != want) {
              tally.fail("%s t=%d: status %d, clipped expected %d (x_near %.3f)", ctx.c_str(), t, got, want, x_near);
            } else if (want) {
              check_interpolated(tally, ctx.c_str(), r, src, enc, t, 0, x, 1e-3);
            }
          }
          if (m < 7.0f) {
            EXPECT_GT(clipped, 0) << ctx;
          }
          if (m > 7.68f) {
            EXPECT_EQ(clipped, 0) << ctx;
          }
          EXPECT_EQ(tally.count(), 0) << ctx << tally.report();
        }
      }
    }
  }
}

TEST(AnalyticClip, DefaultLimitClipsNothing) {
  for (const StepConfig& config : kSteps) {
    for (const Encoding& enc : {linear_encoding(), standard_encoding()}) {
      for (EyeDirection dir : kDirections) {
        const ParallaxModel model = ParallaxModel::from_stereo(config.separation, config.convergence, config.width, dir);
        SourceFrame src = rptest::make_source(config.width, 1, 1);
        make_step(src, enc, model, config);
        for (Method method : kAllMethods) {
          Options options;
          options.method = method;
          const RunResult r = rptest::run(src, enc.decoder(), model, options);
          ASSERT_TRUE(r.status.ok()) << r.status.message();
          int clipped = 0;
          for (int t = 0; t < config.width; ++t) clipped += r.out.status_at(t, 0) == kClipped;
          EXPECT_EQ(clipped, 0) << context(method, dir, enc);
        }
      }
    }
  }
}

// A ray that starts exactly on the surface hits there (DESIGN §5). Exactly representable numbers
// make the tie exact in float: S W = 8, c = 2 gives a = 8, b = -16, and depth 2 gives
// p = fma(-16, 0.5, 8) = 0 = s * m with m = 0.
TEST(AnalyticClip, RayStartingOnTheSurfaceHits) {
  const int width = 128;
  const Encoding enc = linear_encoding();
  for (EyeDirection dir : kDirections) {
    const ParallaxModel model = ParallaxModel::from_stereo(0.0625, 2.0, width, dir);
    ASSERT_EQ(std::fabs(model.a), 8.0f);
    ASSERT_EQ(std::fabs(model.b), 16.0f);
    SourceFrame src = rptest::make_source(width, 1, 2);
    src.set_depth([](int, int) { return 2.0; });
    for (Method method : kAllMethods) {
      Options options;
      options.method = method;
      options.max_negative_parallax = 0.0f;
      const RunResult r = rptest::run(src, enc.decoder(), model, options);
      const std::string ctx = context(method, dir, enc);
      ASSERT_TRUE(r.status.ok()) << ctx << ": " << r.status.message();
      Tally tally;
      for (int t = 0; t < width; ++t) {
        check_status(tally, ctx.c_str(), r, t, 0, kHit);
        check_interpolated(tally, ctx.c_str(), r, src, enc, t, 0, t, 1e-4);
      }
      EXPECT_EQ(tally.count(), 0) << ctx << tally.report();
    }
  }
}

// --------------------------------------------------------------------------------------------
// Outputs: every requested plane is written on every pixel of the target's width, nothing in the
// stride padding (or past the last row) is, and leaving out optional planes changes nothing else.
// Rows hold planes at different depths and a guard band exceeds every |p|, so every pixel is a hit
// at x = t + g - p.
// --------------------------------------------------------------------------------------------

TEST(AnalyticOutputs, AllPlanesWrittenAndNothingOutsideTheWidth) {
  const int target_width = 37;  // not a multiple of any vector width
  const int guard = 4;
  const int width = target_width + 2 * guard;
  const Encoding enc = linear_encoding();
  const double depths[3] = {1.0, 2.0, 8.0};
  for (reproject::ColorLayout layout : {reproject::ColorLayout::planar, reproject::ColorLayout::interleaved_rgba}) {
    for (EyeDirection dir : kDirections) {
      const ParallaxModel model = ParallaxModel::from_stereo(0.05, 2.0, target_width, dir);  // |p| <= 1.85
      SourceFrame src = rptest::make_source(width, 3, 4, layout, 5);
      src.set_depth([&](int, int y) { return depths[y]; });
      for (Method method : kAllMethods) {
        Options options;
        options.method = method;
        options.guard = guard;
        const std::string ctx = context(method, dir, enc, layout == reproject::ColorLayout::planar ? "planar" : "rgba");
        const RunResult full = rptest::run(src, enc.decoder(), model, options, 5);
        ASSERT_TRUE(full.status.ok()) << ctx << ": " << full.status.message();
        EXPECT_TRUE(full.out.padding_untouched()) << ctx;
        Tally tally;
        for (int y = 0; y < 3; ++y) {
          const double p = parallax_of(model, 1.0 / depths[y]);
          for (int t = 0; t < target_width; ++t) {
            check_status(tally, ctx.c_str(), full, t, y, kHit);
            check_interpolated(tally, ctx.c_str(), full, src, enc, t, y, t + guard - p, 1e-3);
          }
        }
        EXPECT_EQ(tally.count(), 0) << ctx << tally.report();

        // Each optional plane alone, and none: the colour and the requested planes are identical.
        for (int mask = 0; mask < 8; ++mask) {
          const bool want_depth = mask & 1, want_status = mask & 2, want_x = mask & 4;
          const RunResult part = rptest::run(src, enc.decoder(), model, options, 5, want_depth, want_status, want_x);
          ASSERT_TRUE(part.status.ok()) << ctx << " mask " << mask << ": " << part.status.message();
          EXPECT_TRUE(part.out.padding_untouched()) << ctx << " mask " << mask;
          EXPECT_EQ(part.out.color[0], full.out.color[0]) << ctx << " mask " << mask;
          for (int c = 1; c < 4 && layout == reproject::ColorLayout::planar; ++c)
            EXPECT_EQ(part.out.color[c], full.out.color[c]) << ctx << " mask " << mask;
          if (want_depth) {
            EXPECT_EQ(part.out.depth, full.out.depth) << ctx << " mask " << mask;
          }
          if (want_status) {
            EXPECT_EQ(part.out.status, full.out.status) << ctx << " mask " << mask;
          }
          if (want_x) {
            EXPECT_EQ(part.out.source_x, full.out.source_x) << ctx << " mask " << mask;
          }
        }
      }
    }
  }
}

// --------------------------------------------------------------------------------------------
// Group 6: secant against exact.
// --------------------------------------------------------------------------------------------

double uniform(std::mt19937& rng, double lo, double hi) {
  return lo + (hi - lo) * (static_cast<double>(rng()) / 4294967296.0);  // mt19937 is 32-bit
}

struct Agreement {
  long exact_hits = 0;
  long within = 0;           // secant also hit, |x - x*| <= 0.05
  long refined = 0;          // secant also hit, |x - x*| <= 2e-3 (refinement to 1e-3 px + rounding)
  long status_mismatch = 0;  // over all pixels
  long pixels = 0;
  double worst = 0.0;
  double percent() const { return exact_hits ? 100.0 * within / exact_hits : 100.0; }
  double percent_refined() const { return exact_hits ? 100.0 * refined / exact_hits : 100.0; }
};

Agreement compare_secant(const RunResult& exact, const RunResult& secant) {
  Agreement a;
  for (int y = 0; y < exact.out.height; ++y) {
    for (int t = 0; t < exact.out.width; ++t) {
      ++a.pixels;
      const int se = exact.out.status_at(t, y);
      const int ss = secant.out.status_at(t, y);
      a.status_mismatch += se != ss;
      if (se != kHit) continue;
      ++a.exact_hits;
      const double dx = std::fabs(exact.out.x_at(t, y) - secant.out.x_at(t, y));
      if (ss == kHit) a.worst = std::max(a.worst, dx);
      if (ss == kHit && dx <= 0.05) ++a.within;
      if (ss == kHit && dx <= 2e-3) ++a.refined;
    }
  }
  return a;
}

TEST(SecantSmooth, WithinFiveHundredthsOfExactOnRandomSmoothRows) {
  const int width = 512;
  const int height = 24;
  const Encoding enc = linear_encoding();
  struct Case {
    double separation;
    int max_steps;
  };
  // a = S * 512 up to 128 px; with w in [0.3, 1.5] and c = 1 the rays span up to ~1.2 a, far more
  // than 64 one-pixel steps: the cap is exercised (and forced with 8 and 16 steps).
  const Case cases[] = {{0.01, 64}, {0.04, 64}, {0.12, 64}, {0.25, 64}, {0.06, 8}, {0.25, 16}};
  for (const Case& c : cases) {
    for (EyeDirection dir : kDirections) {
      std::mt19937 rng(20240611u + static_cast<unsigned>(c.separation * 1000) + 7u * c.max_steps);
      SourceFrame src = rptest::make_source(width, height, 1);
      for (int y = 0; y < height; ++y) {
        // Inverse depth = a sum of four low-frequency sinusoids (0.5 to 4 periods per row).
        double amp[4], freq[4], phase[4];
        for (int k = 0; k < 4; ++k) {
          amp[k] = uniform(rng, 0.02, 0.15);
          freq[k] = uniform(rng, 0.5, 4.0);
          phase[k] = uniform(rng, 0.0, 6.283185307179586);
        }
        src.set_depth_row(y, [&](int x) {
          double w = 0.9;
          for (int k = 0; k < 4; ++k) w += amp[k] * std::sin(6.283185307179586 * freq[k] * x / width + phase[k]);
          return 1.0 / w;
        });
      }
      const ParallaxModel model = ParallaxModel::from_stereo(c.separation, 1.0, width, dir);
      Options options;
      options.method = Method::exact;
      const RunResult exact = rptest::run(src, enc.decoder(), model, options);
      options.method = Method::secant;
      options.secant_max_steps = c.max_steps;
      const RunResult secant = rptest::run(src, enc.decoder(), model, options);
      ASSERT_TRUE(exact.status.ok()) << exact.status.message();
      ASSERT_TRUE(secant.status.ok()) << secant.status.message();
      const Agreement a = compare_secant(exact, secant);
      std::printf("[ secant   ] S=%.2f steps=%d %-13s a=%7.2f: %.3f%% of %ld exact hits within 0.05 px, "
                  "%.3f%% within 2e-3 px (worst hit %.4f px), status mismatches %.3f%%\n",
                  c.separation, c.max_steps, name(dir), model.a, a.percent(), a.exact_hits, a.percent_refined(),
                  a.worst, 100.0 * a.status_mismatch / a.pixels);
      EXPECT_GE(a.percent(), 99.5) << "S=" << c.separation << " steps=" << c.max_steps << " " << name(dir);
      // DESIGN §6: the bracketed crossing is refined to 1e-3 px ("at most a few iterations", so a
      // little slack in the share).
      EXPECT_GE(a.percent_refined(), 99.0) << "S=" << c.separation << " steps=" << c.max_steps << " " << name(dir);
      EXPECT_GT(a.exact_hits, width * height / 4);
    }
  }
}

// A 2-column near object on a far wall covers one target pixel per row (its flat segment [j0, j0+1]
// maps to a 1-px interval). Over many columns (across 16-pixel tiles), sub-pixel offsets (a
// different wall depth per row) and separations, wherever exact hits that segment, secant must too,
// and every status (the hole beside the object included) must be exact's.
TEST(SecantThinOccluder, TwoPixelObjectNeverMissed) {
  // Object at columns 144..175 (+1): with |p_n| <= 110 px its target pixel stays inside [0, 319].
  const int width = 320;
  const int height = 32;
  const int first_column = 144;
  const Encoding enc = linear_encoding();
  long occluder_hits = 0;
  for (EyeDirection dir : kDirections) {
    for (double separation : {0.02, 0.045, 0.08, 0.13}) {
      for (double z_near : {0.55, 0.8, 1.3}) {
        const ParallaxModel model = ParallaxModel::from_stereo(separation, 2.0, width, dir);
        SourceFrame src = rptest::make_source(width, height, 1);
        src.set_depth([&](int x, int y) {
          const int j0 = first_column + y;
          return x == j0 || x == j0 + 1 ? z_near : 8.0 + 0.173 * y;
        });
        Options options;
        options.method = Method::exact;
        const RunResult exact = rptest::run(src, enc.decoder(), model, options);
        options.method = Method::secant;
        const RunResult secant = rptest::run(src, enc.decoder(), model, options);
        ASSERT_TRUE(exact.status.ok()) << exact.status.message();
        ASSERT_TRUE(secant.status.ok()) << secant.status.message();
        Tally tally;
        const std::string ctx = std::string(name(dir)) + "/S=" + std::to_string(separation) + "/z=" + std::to_string(z_near);
        for (int y = 0; y < height; ++y) {
          const int j0 = first_column + y;
          int row_hits = 0;
          for (int t = 0; t < width; ++t) {
            const double xe = exact.out.x_at(t, y);
            if (exact.out.status_at(t, y) != kHit || xe < j0 - 1e-4 || xe > j0 + 1 + 1e-4) continue;
            ++row_hits;
            const double xs = secant.out.x_at(t, y);
            if (secant.out.status_at(t, y) != kHit || !(std::fabs(xs - xe) <= 0.05))
              tally.fail("%s y=%d t=%d: exact hits the occluder at x=%.4f, secant status %d x=%.4f", ctx.c_str(), y, t, xe,
                         secant.out.status_at(t, y), xs);
          }
          // The segment maps to a half-open 1-px interval: exactly one target pixel (an
          // independent check on exact, so that the comparison is not vacuous).
          if (row_hits != 1) tally.fail("%s y=%d: exact hits the occluder on %d pixels, expected 1", ctx.c_str(), y, row_hits);
          occluder_hits += row_hits;
          // "Holes like exact" (DESIGN §6): the tear beside the object, too. Asserted at these
          // ranges (|p_n| <= 110 px); at |p_n| ~ 0.8 W (256 px on this row) secant's crossing on
          // the near-vertical wall was seen to land a few hundredths past the column, so ~1 % of
          // its hole pixels came out as hits.
          for (int t = 0; t < width; ++t) {
            if (exact.out.status_at(t, y) != secant.out.status_at(t, y))
              tally.fail("%s y=%d t=%d: exact status %d x=%.4f, secant status %d x=%.4f", ctx.c_str(), y, t,
                         exact.out.status_at(t, y), exact.out.x_at(t, y), secant.out.status_at(t, y), secant.out.x_at(t, y));
          }
        }
        EXPECT_EQ(tally.count(), 0) << ctx << tally.report();
      }
    }
  }
  std::printf("[ secant   ] thin occluder: %ld occluder pixels compared\n", occluder_hits);
}

}  // namespace
