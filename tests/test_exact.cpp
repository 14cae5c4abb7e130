// The forward sweep (`exact`) against the plain gather
// oracle of DESIGN §5 on random piecewise-planar rows, and `scanline` against `exact`.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <random>
#include <vector>

#include "reproject/reproject.hpp"
#include "support/arch_report.hpp"
#include "support/oracle.hpp"

namespace reproject {
namespace {

// A frame of random piecewise-planar rows stored as disparity (w = d), with a random model.
struct RandomFrame {
  int width = 0;   // source width, guard included
  int height = 0;
  int guard = 0;
  ParallaxModel model;
  std::optional<float> max_negative_parallax;
  std::vector<float> depth;
  std::vector<float> color;  // one plane: the column index, so output colour reveals x
};

RandomFrame make_random_frame(std::mt19937& rng, int width, int height, int guard, bool clip) {
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  RandomFrame frame;
  frame.width = width;
  frame.height = height;
  frame.guard = guard;
  const float b_magnitude = 1.0f + 24.0f * unit(rng);
  frame.model.b = unit(rng) < 0.5f ? -b_magnitude : b_magnitude;
  frame.model.a = -30.0f + 60.0f * unit(rng);
  frame.depth.resize(static_cast<std::size_t>(width) * height);
  frame.color.resize(frame.depth.size());
  for (int y = 0; y < height; ++y) {
    int x = 0;
    while (x < width) {
      // A planar piece: w linear in x (DESIGN §5: exact for planar geometry), at a random depth;
      // jumps between pieces make walls (holes) and fold-overs.
      const int length = 1 + static_cast<int>(unit(rng) * 40.0f);
      const float w0 = unit(rng) < 0.15f ? 0.0f : 2.0f * unit(rng);
      const float slope = (unit(rng) - 0.5f) * 0.1f;
      for (int k = 0; k < length && x < width; ++k, ++x) {
        const std::size_t i = static_cast<std::size_t>(y) * width + x;
        frame.depth[i] = std::max(0.0f, w0 + slope * static_cast<float>(k));
        frame.color[i] = static_cast<float>(x);
      }
    }
  }
  if (clip) frame.max_negative_parallax = 0.4f * b_magnitude;  // nearer data than this is clipped
  return frame;
}

struct Output {
  std::vector<float> color, depth, source_x;
  std::vector<std::uint8_t> status;
};

Output run(const RandomFrame& frame, Method method) {
  const int target_width = frame.width - 2 * frame.guard;
  Output out;
  const std::size_t n = static_cast<std::size_t>(target_width) * frame.height;
  out.color.assign(n, -1.0f);
  out.depth.assign(n, -1.0f);
  out.source_x.assign(n, -1.0f);
  out.status.assign(n, 255);
  SourceView source;
  source.color = ColorView::planar({FloatPlane{frame.color.data(), frame.width, frame.height, frame.width}});
  source.depth = FloatPlane{frame.depth.data(), frame.width, frame.height, frame.width};
  TargetView target;
  target.color = MutableColorView::planar({MutableFloatPlane{out.color.data(), target_width, frame.height, target_width}});
  target.depth = MutableFloatPlane{out.depth.data(), target_width, frame.height, target_width};
  target.status = BytePlane{out.status.data(), target_width, frame.height, target_width};
  target.source_x = MutableFloatPlane{out.source_x.data(), target_width, frame.height, target_width};
  Options options;
  options.method = method;
  options.guard = frame.guard;
  options.max_negative_parallax = frame.max_negative_parallax;
  const Status status = reproject(source, DepthDecoder::disparity(), frame.model, options, target);
  EXPECT_TRUE(status.ok()) << status.message();
  return out;
}

// The oracle's view of one row, decoded and cleaned as docs/BEHAVIOUR.md states (computed here
// from those rules, not by the library).
std::vector<testing::OracleRow> oracle_rows(const RandomFrame& frame) {
  const float a = frame.model.a, b = frame.model.b;
  const double s = b > 0.0f ? 1.0 : -1.0;
  const double limit = frame.width + 2.0;
  const double p_far = std::clamp<double>(a, -limit, limit);
  std::vector<testing::OracleRow> rows(frame.height);
  double nearest_key = s * p_far;
  for (int y = 0; y < frame.height; ++y) {
    rows[y].s = s;
    rows[y].p_far = p_far;
    for (int x = 0; x < frame.width; ++x) {
      double p = std::fma(b, frame.depth[static_cast<std::size_t>(y) * frame.width + x], a);  // disparity: A = 1, B = 0
      if (!(s * p >= s * p_far)) p = p_far;
      if (s * p > limit) p = s * limit;
      rows[y].parallax.push_back(p);
      nearest_key = std::max(nearest_key, s * p);
    }
  }
  const double key_near = frame.max_negative_parallax
                              ? std::max(std::min<double>(*frame.max_negative_parallax, limit), s * p_far)
                              : nearest_key;
  for (auto& row : rows) row.p_near = s * key_near;
  return rows;
}

struct Agreement {
  long pixels = 0;
  long status_mismatches = 0;
  double worst_dx = 0.0;
  long count[4] = {0, 0, 0, 0};
};

TEST(Exact, SweepEqualsGatherOracleOnRandomPiecewisePlanarRows) {
  std::mt19937 rng(20261122);
  Agreement total;
  long color_errors = 0;
  for (int frame_index = 0; frame_index < 12; ++frame_index) {
    const int guard = frame_index % 3 == 2 ? 7 : 0;
    const RandomFrame frame = make_random_frame(rng, 181 + 17 * frame_index, 64, guard, frame_index % 2 == 1);
    const Output out = run(frame, Method::exact);
    const std::vector<testing::OracleRow> rows = oracle_rows(frame);
    const int target_width = frame.width - 2 * guard;
    for (int y = 0; y < frame.height; ++y) {
      for (int t = 0; t < target_width; ++t) {
        const std::size_t i = static_cast<std::size_t>(y) * target_width + t;
        const testing::OracleRay ray = testing::oracle_ray(rows[y], t + guard);
        ++total.pixels;
        ++total.count[static_cast<int>(ray.status)];
        if (out.status[i] != static_cast<std::uint8_t>(ray.status)) ++total.status_mismatches;
        total.worst_dx = std::max(total.worst_dx, std::fabs(out.source_x[i] - ray.x));
        // The resolve stage: colour = column index, so a hit's colour is x itself and a
        // background fill is the wall's farther endpoint.
        const int last = frame.width - 1;
        double expected = std::clamp(ray.x, 0.0, static_cast<double>(last));
        if (ray.status == PixelStatus::hole) {
          const int j = static_cast<int>(std::floor(ray.x));
          expected = rows[y].s * rows[y].parallax[j + 1] < rows[y].s * rows[y].parallax[j] ? j + 1 : j;
        }
        if (std::fabs(out.color[i] - expected) > 2e-3) ++color_errors;
      }
    }
  }
  std::printf("exact vs oracle: %ld pixels, hit %ld hole %ld outside %ld clipped %ld, worst |dx| %.3g px, "
              "status mismatches %ld\n",
              total.pixels, total.count[0], total.count[1], total.count[2], total.count[3], total.worst_dx,
              total.status_mismatches);
  EXPECT_GE(total.pixels, 100000);
  for (long c : total.count) EXPECT_GE(c, 500) << "every status must be exercised";
  EXPECT_EQ(total.status_mismatches, 0);
  EXPECT_LE(total.worst_dx, 1e-4);
  EXPECT_EQ(color_errors, 0);
}

TEST(Exact, ScanlineEqualsExactWhenTheRangeCoversTheData) {
  std::mt19937 rng(7);
  Agreement total;
  for (int frame_index = 0; frame_index < 8; ++frame_index) {
    RandomFrame frame = make_random_frame(rng, 160 + 31 * frame_index, 48, frame_index % 4 == 3 ? 5 : 0, false);
    if (frame_index % 2 == 1) frame.max_negative_parallax = 3.0f * std::fabs(frame.model.b) + 40.0f;  // wider than the data
    const Output exact = run(frame, Method::exact);
    const Output scanline = run(frame, Method::scanline);
    for (std::size_t i = 0; i < exact.status.size(); ++i) {
      ++total.pixels;
      ++total.count[exact.status[i]];
      if (exact.status[i] != scanline.status[i]) ++total.status_mismatches;
      total.worst_dx = std::max(total.worst_dx, static_cast<double>(std::fabs(exact.source_x[i] - scanline.source_x[i])));
    }
  }
  std::printf("scanline vs exact: %ld pixels, worst |dx| %.3g px, status mismatches %ld (clipped %ld)\n",
              total.pixels, total.worst_dx, total.status_mismatches, total.count[3]);
  EXPECT_EQ(total.count[3], 0);
  EXPECT_GE(total.count[1], 100);
  EXPECT_EQ(total.status_mismatches, 0);
  EXPECT_LE(total.worst_dx, 1e-3);
}

}  // namespace
}  // namespace reproject

namespace reproject {
namespace {

// Edge modes on a fronto-parallel row shifted by 5.5 px: the first target pixels come from off
// the row's left end. Colour = column index, so the output shows where each was read.
TEST(EdgeModes, ClampBlackMirrorAndNone) {
  const int width = 40;
  std::vector<float> depth(width, 1.0f), color(width);
  for (int x = 0; x < width; ++x) color[x] = static_cast<float>(x) + 100.0f;
  SourceView source;
  source.depth = FloatPlane{depth.data(), width, 1, width};
  source.color = ColorView::planar({FloatPlane{color.data(), width, 1, width}});
  const ParallaxModel model{5.5f, 0.0f};  // x* = t - 5.5 everywhere
  for (Arch arch : every_arch()) {
    if (!arch_supported(arch)) continue;
    for (EdgeMode edge : {EdgeMode::clamp, EdgeMode::black, EdgeMode::mirror, EdgeMode::none}) {
      std::vector<float> out(width, -1.0f), out_depth(width, -1.0f);
      std::vector<std::uint8_t> status(width, 9);
      TargetView target;
      target.color = MutableColorView::planar({MutableFloatPlane{out.data(), width, 1, width}});
      target.depth = MutableFloatPlane{out_depth.data(), width, 1, width};
      target.status = BytePlane{status.data(), width, 1, width};
      Options options;
      options.edge = edge;
      options.arch = arch;
      for (Method method : {Method::exact, Method::single, Method::scanline}) {
        options.method = method;
        ASSERT_TRUE(reproject(source, DepthDecoder::linear(), model, options, target).ok());
        for (int t = 0; t < width; ++t) {
          const float x = static_cast<float>(t) - 5.5f;
          SCOPED_TRACE(std::string(to_string(arch)) + " " + to_string(method) + " edge " +
                       std::to_string(static_cast<int>(edge)) + " t " + std::to_string(t));
          if (x >= 0.0f) {
            EXPECT_EQ(status[t], 0);
            EXPECT_NEAR(out[t], x + 100.0f, 1e-4);
            continue;
          }
          EXPECT_EQ(status[t], static_cast<int>(PixelStatus::outside));
          switch (edge) {
            case EdgeMode::clamp: EXPECT_EQ(out[t], 100.0f); EXPECT_EQ(out_depth[t], 1.0f); break;
            case EdgeMode::black: EXPECT_EQ(out[t], 0.0f); EXPECT_EQ(out_depth[t], 1.0f); break;
            case EdgeMode::mirror: EXPECT_NEAR(out[t], -x + 100.0f, 1e-4); break;
            case EdgeMode::none: EXPECT_EQ(out[t], -1.0f); EXPECT_EQ(out_depth[t], -1.0f); break;
          }
        }
        std::fill(out.begin(), out.end(), -1.0f);
        std::fill(out_depth.begin(), out_depth.end(), -1.0f);
      }
    }
  }
}

}  // namespace
}  // namespace reproject
