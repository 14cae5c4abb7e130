// Hardening: several threads call the library at once on different frames (adversarial depth
// among them), sharing the library's pool, through every entry point (reproject with the pool,
// reproject with a caller's job system whose workers are foreign threads, reproject_pair) and
// with different thread counts. Every result must equal the same call made alone on one thread,
// byte for byte. CI runs this suite under ThreadSanitizer (the `Threads` filter of .ci/run), so a
// data race fails the build even when the bytes happen to come out right.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "reproject/reproject.hpp"

namespace reproject {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

// Planar RGB + depth, contiguous rows with an odd stride.
struct Frame {
  int width = 0;
  int height = 0;
  std::ptrdiff_t stride = 0;
  std::vector<float> color[3];
  std::vector<float> depth;

  SourceView view() const {
    SourceView v;
    for (int c = 0; c < 3; ++c) v.color.plane[c] = FloatPlane{color[c].data(), width, height, stride};
    v.color.channels = 3;
    v.depth = FloatPlane{depth.data(), width, height, stride};
    return v;
  }
};

struct Output {
  int width = 0;
  int height = 0;
  std::vector<float> color[3];
  std::vector<float> depth;
  std::vector<float> source_x;
  std::vector<std::uint8_t> status;

  Output(int w, int h) : width(w), height(h) {
    const std::size_t n = static_cast<std::size_t>(w) * h;
    for (auto& plane : color) plane.assign(n, -1.0f);
    depth.assign(n, -1.0f);
    source_x.assign(n, -1.0f);
    status.assign(n, 0xFF);
  }
  TargetView view() {
    TargetView v;
    for (int c = 0; c < 3; ++c) v.color.plane[c] = MutableFloatPlane{color[c].data(), width, height, width};
    v.color.channels = 3;
    v.depth = MutableFloatPlane{depth.data(), width, height, width};
    v.source_x = MutableFloatPlane{source_x.data(), width, height, width};
    v.status = BytePlane{status.data(), width, height, width};
    return v;
  }
  bool operator==(const Output& o) const {
    auto same = [](const std::vector<float>& a, const std::vector<float>& b) {
      return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
    };
    for (int c = 0; c < 3; ++c)
      if (!same(color[c], o.color[c])) return false;
    return same(depth, o.depth) && same(source_x, o.source_x) && status == o.status;
  }
};

// The depth of frame `kind`: 0 an ordinary scene, 1 near/far alternating every pixel, 2 NaN rows
// between ordinary ones, 3 a scene whose near parallax is wider than the image.
Frame make_frame(int kind, int width, int height, const DepthDecoder& decoder) {
  Frame f;
  f.width = width;
  f.height = height;
  f.stride = width + 3;
  const std::size_t n = static_cast<std::size_t>(f.stride) * height;
  for (int c = 0; c < 3; ++c) {
    f.color[c].assign(n, 0.0f);
    for (std::size_t i = 0; i < n; ++i) f.color[c][i] = static_cast<float>((i * 7 + c * 11) % 97) / 97.0f;
  }
  f.depth.assign(n, 0.0f);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const double z = 0.6 + ((x / 9 + y / 5) % 4) * 3.0 + 0.05 * (x % 9);
      float d = decoder.encode(z);
      if (kind == 1) d = decoder.encode((x + y) % 2 ? 0.5 : 50.0);
      if (kind == 2 && y % 3 == 1) d = kNaN;
      if (kind == 3 && x % 17 == 0) d = decoder.encode(0.5);
      f.depth[static_cast<std::size_t>(y) * f.stride + x] = d;
    }
  return f;
}

// A caller's job system whose workers are threads of its own, started per call: the library's
// tasks run on threads it has never seen.
struct SpawningJobs {
  static void run(void*, int count, void (*task)(void*, int), void* task_context) {
    std::atomic<int> next{0};
    auto work = [&] {
      for (int i = next.fetch_add(1); i < count; i = next.fetch_add(1)) task(task_context, i);
    };
    std::thread a(work), b(work);
    work();
    a.join();
    b.join();
  }
};

struct Job {
  int frame = 0;
  Method method = Method::exact;
  std::optional<float> max_negative_parallax;
  ParallaxModel model;
};

TEST(ThreadsHardening, ConcurrentCallersOnAdversarialFramesShareThePool) {
  const DepthDecoder decoder = DepthDecoder::from_near_far(DepthEncoding::reversed, 0.5, 50.0);
  const int width = 150;
  const int height = 40;
  std::vector<Frame> frames;
  for (int kind = 0; kind < 4; ++kind) frames.push_back(make_frame(kind, width, height, decoder));

  constexpr int kCallers = 4;
  constexpr int kRounds = 8;
  const Method methods[] = {Method::scanline, Method::march16, Method::single, Method::secant, Method::exact};
  // Each caller's jobs and their single-threaded answers (pairs: left and right eye).
  struct Expected {
    Job job;
    Output single = Output(width, height);
    Output left = Output(width, height);
    Output right = Output(width, height);
  };
  std::vector<std::vector<Expected>> expected(kCallers);
  for (int c = 0; c < kCallers; ++c) {
    for (int round = 0; round < kRounds; ++round) {
      Expected e;
      e.job.frame = (c + round) % 4;
      e.job.method = methods[(c * kRounds + round) % 5];
      if ((c + round) % 3 == 0) e.job.max_negative_parallax = 2.0f;
      e.job.model = ParallaxModel::from_stereo(0.04 + 0.01 * c, 2.0, width,
                                               round % 2 ? EyeDirection::centre_to_right : EyeDirection::right_to_left);
      Options o;
      o.method = e.job.method;
      o.max_negative_parallax = e.job.max_negative_parallax;
      o.threads = 1;
      const ParallaxModel mirrored{-e.job.model.a, -e.job.model.b};
      const SourceView source = frames[static_cast<std::size_t>(e.job.frame)].view();
      ASSERT_TRUE(reproject::reproject(source, decoder, e.job.model, o, e.single.view()).ok());
      ASSERT_TRUE(reproject::reproject(source, decoder, mirrored, o, e.left.view()).ok());
      e.right = e.single;
      expected[static_cast<std::size_t>(c)].push_back(std::move(e));
    }
  }

  std::atomic<int> failures{0};
  std::atomic<int> mismatches{0};
  std::atomic<bool> go{false};
  std::vector<std::thread> callers;
  for (int c = 0; c < kCallers; ++c) {
    callers.emplace_back([&, c] {
      while (!go.load()) std::this_thread::yield();
      for (int round = 0; round < kRounds; ++round) {
        const Expected& e = expected[static_cast<std::size_t>(c)][static_cast<std::size_t>(round)];
        Options o;
        o.method = e.job.method;
        o.max_negative_parallax = e.job.max_negative_parallax;
        o.threads = (c + round) % 4;  // 0: one per hardware thread
        const SourceView source = frames[static_cast<std::size_t>(e.job.frame)].view();
        const int entry = (c + 2 * round) % 3;
        if (entry == 2) {
          Output left(width, height), right(width, height);
          if (!reproject_pair(source, decoder, e.job.model, o, left.view(), right.view()).ok()) failures.fetch_add(1);
          if (!(left == e.left) || !(right == e.right)) mismatches.fetch_add(1);
        } else {
          Output out(width, height);
          const Status status = entry == 1 ? reproject::reproject(source, decoder, e.job.model, o, out.view(),
                                                                  ParallelFor{nullptr, SpawningJobs::run})
                                           : reproject::reproject(source, decoder, e.job.model, o, out.view());
          if (!status.ok()) failures.fetch_add(1);
          if (!(out == e.single)) mismatches.fetch_add(1);
        }
      }
    });
  }
  go.store(true);
  for (std::thread& t : callers) t.join();
  EXPECT_EQ(failures.load(), 0);
  EXPECT_EQ(mismatches.load(), 0);
}

// Callers that each force a different instruction set at the same time: per-call choices never
// leak into another call.
TEST(ThreadsHardening, ConcurrentCallersWithDifferentArches) {
  const DepthDecoder decoder = DepthDecoder::from_near_far(DepthEncoding::standard, 0.5, 50.0);
  const int width = 97;
  const int height = 24;
  const Frame frame = make_frame(1, width, height, decoder);
  const ParallaxModel model = ParallaxModel::from_stereo(0.05, 2.0, width, EyeDirection::centre_to_right);
  std::vector<Arch> arches;
  for (int a = 0; a < kArchCount; ++a)
    if (arch_supported(static_cast<Arch>(a))) arches.push_back(static_cast<Arch>(a));
  std::vector<Output> expected;
  for (Arch arch : arches) {
    Options o;
    o.method = Method::secant;
    o.arch = arch;
    o.threads = 1;
    expected.emplace_back(width, height);
    ASSERT_TRUE(reproject::reproject(frame.view(), decoder, model, o, expected.back().view()).ok());
  }
  std::atomic<int> mismatches{0};
  std::vector<std::thread> callers;
  for (std::size_t i = 0; i < 2 * arches.size(); ++i) {
    callers.emplace_back([&, i] {
      const std::size_t k = i % arches.size();
      for (int round = 0; round < 3; ++round) {
        Options o;
        o.method = Method::secant;
        o.arch = arches[k];
        o.threads = 2;
        Output out(width, height);
        if (!reproject::reproject(frame.view(), decoder, model, o, out.view()).ok() || !(out == expected[k]))
          mismatches.fetch_add(1);
      }
    });
  }
  for (std::thread& t : callers) t.join();
  EXPECT_EQ(mismatches.load(), 0);
}

}  // namespace
}  // namespace reproject
