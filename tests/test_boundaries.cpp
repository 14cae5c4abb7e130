// The library's boundaries (issue 21) from C++: a view's byte extent is computed with overflow
// checks (src/view_bounds.hpp), overlap is decided on the bytes a view's rows cover (side-by-side
// buffers pass, any shared byte is refused), a missing buffer is an error, and Options::cancel
// stops a running call. The C interface's view of the same is tests/c/test_c_boundaries.c.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstring>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "reproject/reproject.hpp"
#include "reproject/stereo.hpp"
#include "src/view_bounds.hpp"

namespace reproject {
namespace {

using detail::check_view_bytes;
using detail::ViewBytes;
using detail::views_touch;

// ---- view_bounds: extents -----------------------------------------------------------------------

Status check(std::uintptr_t address, int width, int height, std::ptrdiff_t stride, int per_pixel = 1,
             int element_bytes = 4, ViewBytes* out = nullptr) {
  return check_view_bytes(reinterpret_cast<const void*>(address), width, height, stride, per_pixel, element_bytes,
                          "view", "elements", out);
}

TEST(ViewBounds, ExtentsThatFitAreAccepted) {
  ViewBytes v;
  ASSERT_TRUE(check(4096, 10, 3, 16, 1, 4, &v).ok());
  EXPECT_EQ(v.first, 4096u);
  EXPECT_EQ(v.rows, 3u);
  EXPECT_EQ(v.row, 40u);
  EXPECT_EQ(v.stride, 64u);
  // Interleaved RGBA: 4 floats a pixel.
  ASSERT_TRUE(check(4096, 10, 3, 40, 4, 4, &v).ok());
  EXPECT_EQ(v.row, 160u);
  // One row needs no more than its own bytes, whatever the stride (which must still fit in bytes).
  EXPECT_TRUE(check(4096, 10, 1, PTRDIFF_MAX / 4).ok());
  // The largest extent the kernels can address: PTRDIFF_MAX bytes.
  EXPECT_TRUE(check(4096, 1, 2, (PTRDIFF_MAX - 4) / 4, 1, 4).ok());
  // Empty views: only the stride >= row rule.
  EXPECT_TRUE(check(0, 0, 5, 0).ok());
  EXPECT_TRUE(check(4096, 7, 0, PTRDIFF_MAX).ok());
}

TEST(ViewBounds, StridesWhoseBytesOverflowAreRefused) {
  Status s = check(4096, 10, 8, PTRDIFF_MAX);
  EXPECT_EQ(s.code(), StatusCode::invalid_stride);
  EXPECT_STREQ(s.message(), "view: stride 9223372036854775807 elements: the stride in bytes overflows");
  s = check(4096, 10, 1, PTRDIFF_MAX / 4 + 1);  // one row, but the stride in bytes does not fit
  EXPECT_EQ(s.code(), StatusCode::invalid_stride) << s.message();
  s = check(4096, 1, 3, (PTRDIFF_MAX - 4) / 4);  // (3 - 1) strides overflow
  EXPECT_EQ(s.code(), StatusCode::invalid_stride);
  EXPECT_STREQ(s.message(), "view: stride 2305843009213693950 elements: the view's extent overflows (3 rows)");
  s = check(4096, 2, 2, (PTRDIFF_MAX - 4) / 4);  // the last row's end, one element past
  EXPECT_EQ(s.code(), StatusCode::invalid_stride) << s.message();
  s = check(4096, 10, 3, 9);
  EXPECT_EQ(s.code(), StatusCode::invalid_stride);
  EXPECT_STREQ(s.message(), "view: stride 9 is smaller than the row (10 elements)");
  EXPECT_EQ(check(4096, 10, 3, -40).code(), StatusCode::invalid_stride);
  EXPECT_EQ(check(4096, 0, 3, -1).code(), StatusCode::invalid_stride);  // strides stay positive
  // 2^62 floats: 2^64 bytes, which would wrap to 0 (every row onto row 0).
  EXPECT_EQ(check(4096, 10, 8, std::ptrdiff_t{1} << 62).code(), StatusCode::invalid_stride);
}

TEST(ViewBounds, ViewsPastTheEndOfTheAddressSpaceAreRefused) {
  const std::uintptr_t top = UINTPTR_MAX;
  Status s = check(top - 1023, 64, 8, 64);  // 2048 bytes from 1 KiB below the top
  EXPECT_EQ(s.code(), StatusCode::invalid_size);
  EXPECT_NE(std::string(s.message()).find("run past the end of the address space"), std::string::npos) << s.message();
  EXPECT_EQ(check(top - 2047, 64, 8, 64).code(), StatusCode::invalid_size);  // ends exactly at 2^64: wraps
  EXPECT_TRUE(check(top - 2051, 64, 8, 64).ok());  // ends 4 bytes below it
  // Bytes: the last byte just below the top one, so that one past it is still an address.
  EXPECT_TRUE(check(top - 2048, 256, 8, 256, 1, 1).ok());
  EXPECT_EQ(check(top - 2047, 256, 8, 256, 1, 1).code(), StatusCode::invalid_size);
}

TEST(ViewBounds, ElementsAreAligned) {
  // A float plane whose data lies between two floats (the C interface can be handed one).
  const Status s = check(4097, 10, 3, 16);
  EXPECT_EQ(s.code(), StatusCode::invalid_stride);
  EXPECT_STREQ(s.message(), "view: data 0x1001 is not aligned to its 4-byte elements");
  EXPECT_TRUE(check(4097, 10, 3, 16, 1, 1).ok());  // bytes may start anywhere
  EXPECT_TRUE(check(4097, 0, 3, 16).ok());          // an empty view reads nothing
}

// ---- view_bounds: touching ----------------------------------------------------------------------

// The reference: every byte of every row of both views.
bool touch_by_bytes(const ViewBytes& a, const ViewBytes& b) {
  for (std::uint64_t i = 0; i < a.rows; ++i)
    for (std::uint64_t j = 0; j < b.rows; ++j) {
      const std::uint64_t a0 = a.first + i * a.stride, b0 = b.first + j * b.stride;
      if (a0 < b0 + b.row && b0 < a0 + a.row && a.row > 0 && b.row > 0) return true;
    }
  return false;
}

TEST(ViewBounds, TouchingAgreesWithEveryByte) {
  std::mt19937 rng(21);
  int touching = 0, apart = 0;
  for (int n = 0; n < 200000; ++n) {
    auto view = [&rng]() {
      ViewBytes v;
      v.first = 1000 + rng() % 200;
      v.rows = rng() % 6;
      v.row = rng() % 12;
      v.stride = v.row + rng() % 20;
      if (v.stride == 0) v.stride = 1;
      return v;
    };
    const ViewBytes a = view(), b = view();
    const bool expected = touch_by_bytes(a, b);
    ASSERT_EQ(views_touch(a, b), expected) << "a " << a.first << "+" << a.rows << "x" << a.row << "/" << a.stride
                                           << ", b " << b.first << "+" << b.rows << "x" << b.row << "/" << b.stride;
    ASSERT_EQ(views_touch(b, a), expected);
    (expected ? touching : apart) += 1;
  }
  EXPECT_GT(touching, 20000);
  EXPECT_GT(apart, 20000);
}

TEST(ViewBounds, SideBySideHalvesDoNotTouchAndOneByteMoreDoes) {
  // One allocation of 1000 rows of 2 x 256 bytes: the left and right halves.
  const ViewBytes left{4096, 1000, 256, 512};
  ViewBytes right{4096 + 256, 1000, 256, 512};
  EXPECT_FALSE(views_touch(left, right));
  right.first -= 1;
  EXPECT_TRUE(views_touch(left, right));
  // Rows interleaved (even rows one view, odd rows the other) do not touch either.
  EXPECT_FALSE(views_touch(ViewBytes{4096, 500, 512, 1024}, ViewBytes{4096 + 512, 500, 512, 1024}));
  // A view whose one long row spans the other's rows touches them.
  EXPECT_TRUE(views_touch(ViewBytes{4096 + 300, 1, 100000, 100000}, right));
  // Views of very different strides: a byte plane in the gap between float rows.
  EXPECT_FALSE(views_touch(ViewBytes{4096, 100, 40, 100}, ViewBytes{4096 + 50, 100, 40, 100}));
  EXPECT_TRUE(views_touch(ViewBytes{4096, 100, 40, 100}, ViewBytes{4096 + 50, 10, 40, 1000}) ==
              touch_by_bytes(ViewBytes{4096, 100, 40, 100}, ViewBytes{4096 + 50, 10, 40, 1000}));
}

// ---- The API: side-by-side buffers ---------------------------------------------------------------

struct Frame {
  int width = 96;
  int height = 40;
  std::vector<float> depth;
  std::vector<float> color;  // RGBA, interleaved
  DepthDecoder decoder = DepthDecoder::from_near_far(DepthEncoding::standard, 1.0, 20.0);
  ParallaxModel model;

  Frame() : depth(static_cast<std::size_t>(width) * height), color(static_cast<std::size_t>(width) * height * 4) {
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) {
        const bool box = x > 30 && x < 60 && y > 10 && y < 30;
        const double z = box ? 2.0 : 4.0 + 0.05 * x;
        depth[static_cast<std::size_t>(y) * width + x] = static_cast<float>((1.0 - 1.0 / z) / (1.0 - 1.0 / 20.0));
        for (int c = 0; c < 4; ++c)
          color[(static_cast<std::size_t>(y) * width + x) * 4 + c] = static_cast<float>((x * 3 + y * 5 + c * 7) % 97) / 97;
      }
    model = StereoCamera{0.04, 3.0}.parallax(width, EyeDirection::left_to_right);
  }
};

TEST(Boundaries, SideBySideBuffersAreAcceptedAndGiveTheSameResult) {
  const Frame f;
  const int w = f.width, h = f.height;
  for (int threads : {1, 2}) {
    Options options;
    options.threads = threads;
    // Reference: buffers of their own.
    std::vector<float> out_color(f.color.size()), out_depth(f.depth.size());
    SourceView source;
    source.color = ColorView::rgba(f.color.data(), w, h, 4 * w);
    source.depth = FloatPlane{f.depth.data(), w, h, w};
    TargetView target;
    target.color = MutableColorView::rgba(out_color.data(), w, h, 4 * w);
    target.depth = MutableFloatPlane{out_depth.data(), w, h, w};
    ASSERT_TRUE(reproject(source, f.decoder, f.model, options, target).ok());

    // The colour and the depth each in one side-by-side allocation: left half in, right half out.
    std::vector<float> color_sbs(f.color.size() * 2, -1.0f), depth_sbs(f.depth.size() * 2, -1.0f);
    for (int y = 0; y < h; ++y) {
      std::copy_n(f.color.data() + static_cast<std::size_t>(y) * 4 * w, 4 * w, color_sbs.data() + static_cast<std::size_t>(y) * 8 * w);
      std::copy_n(f.depth.data() + static_cast<std::size_t>(y) * w, w, depth_sbs.data() + static_cast<std::size_t>(y) * 2 * w);
    }
    SourceView left_half;
    left_half.color = ColorView::rgba(color_sbs.data(), w, h, 8 * w);
    left_half.depth = FloatPlane{depth_sbs.data(), w, h, 2 * w};
    TargetView right_half;
    right_half.color = MutableColorView::rgba(color_sbs.data() + 4 * w, w, h, 8 * w);
    right_half.depth = MutableFloatPlane{depth_sbs.data() + w, w, h, 2 * w};
    const Status s = reproject(left_half, f.decoder, f.model, options, right_half);
    ASSERT_TRUE(s.ok()) << s.message();
    for (int y = 0; y < h; ++y) {
      ASSERT_EQ(0, std::memcmp(color_sbs.data() + static_cast<std::size_t>(y) * 8 * w + 4 * w,
                               out_color.data() + static_cast<std::size_t>(y) * 4 * w, 16 * static_cast<std::size_t>(w)))
          << "colour row " << y;
      ASSERT_EQ(0, std::memcmp(depth_sbs.data() + static_cast<std::size_t>(y) * 2 * w + w,
                               out_depth.data() + static_cast<std::size_t>(y) * w, 4 * static_cast<std::size_t>(w)))
          << "depth row " << y;
    }

    // One float of overlap per row is refused, and nothing is written.
    const std::vector<float> before = color_sbs;
    right_half.color = MutableColorView::rgba(color_sbs.data() + 4 * w - 1, w, h, 8 * w);
    const Status overlap = reproject(left_half, f.decoder, f.model, options, right_half);
    EXPECT_EQ(overlap.code(), StatusCode::aliasing) << overlap.message();
    EXPECT_STREQ(overlap.message(), "target colour overlaps source colour");
    EXPECT_EQ(color_sbs, before);
  }
}

TEST(Boundaries, PairIntoOneSideBySidePicture) {
  const Frame f;
  const int w = f.width, h = f.height;
  SourceView source;
  source.color = ColorView::rgba(f.color.data(), w, h, 4 * w);
  source.depth = FloatPlane{f.depth.data(), w, h, w};
  const ParallaxModel centre_to_right = StereoCamera{0.04, 3.0}.parallax(w, EyeDirection::centre_to_right);
  std::vector<float> picture(f.color.size() * 2);
  TargetView left, right;
  left.color = MutableColorView::rgba(picture.data(), w, h, 8 * w);
  right.color = MutableColorView::rgba(picture.data() + 4 * w, w, h, 8 * w);
  const Status s = reproject_pair(source, f.decoder, centre_to_right, Options(), left, right);
  EXPECT_TRUE(s.ok()) << s.message();
  right.color = MutableColorView::rgba(picture.data() + 4 * w - 4, w, h, 8 * w);  // one pixel shared
  const Status overlap = reproject_pair(source, f.decoder, centre_to_right, Options(), left, right);
  EXPECT_EQ(overlap.code(), StatusCode::aliasing);
  EXPECT_STREQ(overlap.message(), "left colour overlaps right colour");
}

TEST(Boundaries, StereoHelpersTakeSideBySideBuffersToo) {
  const Frame f;
  const int w = f.width, h = f.height;
  std::vector<float> sbs(f.depth.size() * 2);
  for (int y = 0; y < h; ++y)
    std::copy_n(f.depth.data() + static_cast<std::size_t>(y) * w, w, sbs.data() + static_cast<std::size_t>(y) * 2 * w);
  const FloatPlane in{sbs.data(), w, h, 2 * w};
  Status s = dilate_nearer_depth(in, f.decoder, 2, MutableFloatPlane{sbs.data() + w, w, h, 2 * w});
  EXPECT_TRUE(s.ok()) << s.message();
  s = dilate_nearer_depth(in, f.decoder, 2, MutableFloatPlane{sbs.data() + w - 1, w, h, 2 * w});
  EXPECT_EQ(s.code(), StatusCode::aliasing) << s.message();
  s = dilate_nearer_depth(in, f.decoder, 2, MutableFloatPlane{sbs.data() + w, w, h, PTRDIFF_MAX});
  EXPECT_EQ(s.code(), StatusCode::invalid_stride) << s.message();
  EXPECT_NE(std::string(s.message()).find("dilate_nearer_depth: output: stride"), std::string::npos) << s.message();
}

// ---- The API: missing buffers -------------------------------------------------------------------

TEST(Boundaries, ADepthBufferWithASizeAndNoDataIsAnError) {
  const Frame f;
  const int w = f.width, h = f.height;
  std::vector<float> out(f.color.size(), -1.0f);
  SourceView source;
  source.color = ColorView::rgba(f.color.data(), w, h, 4 * w);
  source.depth_buffer = DepthBuffer::of(DepthFormat::unorm16, nullptr, w, h, 2 * w);
  TargetView target;
  target.color = MutableColorView::rgba(out.data(), w, h, 4 * w);
  Status s = reproject(source, f.decoder, f.model, Options(), target);
  EXPECT_EQ(s.code(), StatusCode::null_pointer) << s.message();
  EXPECT_NE(std::string(s.message()).find("source depth_buffer: data is null"), std::string::npos) << s.message();
  source.depth_buffer = DepthBuffer{};  // no depth at all, for a colour of w x h
  s = reproject(source, f.decoder, f.model, Options(), target);
  EXPECT_EQ(s.code(), StatusCode::null_pointer) << s.message();
  EXPECT_TRUE(std::all_of(out.begin(), out.end(), [](float v) { return v == -1.0f; }));
  // An empty frame (colour and depth both empty) is still fine.
  source.color = ColorView::rgba(f.color.data(), 0, h, 4 * w);
  source.depth = FloatPlane{f.depth.data(), 0, h, w};
  EXPECT_TRUE(reproject(source, f.decoder, f.model, Options(), target).ok());
}

TEST(Boundaries, UnwantedOutputsAreNotLookedAt) {
  // An output with null data is not written, whatever else its struct holds (a stride whose
  // bytes would overflow is never formed: UBSan would see it).
  const Frame f;
  const int w = f.width, h = f.height;
  std::vector<float> out(f.color.size());
  SourceView source;
  source.color = ColorView::rgba(f.color.data(), w, h, 4 * w);
  source.depth = FloatPlane{f.depth.data(), w, h, w};
  TargetView target;
  target.color = MutableColorView::rgba(out.data(), w, h, 4 * w);
  target.depth = MutableFloatPlane{nullptr, w, h, PTRDIFF_MAX};
  target.source_x = MutableFloatPlane{nullptr, -5, h, -1};
  const Status s = reproject(source, f.decoder, f.model, Options(), target);
  EXPECT_TRUE(s.ok()) << s.message();
}

// ---- The API: cancellation ------------------------------------------------------------------------

TEST(Cancel, ASetFlagStopsTheCallBeforeItWrites) {
  const Frame f;
  const int w = f.width, h = f.height;
  for (Method method : {Method::scanline, Method::march16, Method::single, Method::secant, Method::exact}) {
    std::vector<float> out(f.color.size(), -1.0f);
    SourceView source;
    source.color = ColorView::rgba(f.color.data(), w, h, 4 * w);
    source.depth = FloatPlane{f.depth.data(), w, h, w};
    TargetView target;
    target.color = MutableColorView::rgba(out.data(), w, h, 4 * w);
    std::atomic<bool> cancel{true};
    Options options;
    options.method = method;
    options.cancel = &cancel;
    Status s = reproject(source, f.decoder, f.model, options, target);
    EXPECT_EQ(s.code(), StatusCode::cancelled) << s.message();
    EXPECT_STREQ(to_string(s.code()), "cancelled");
    EXPECT_TRUE(std::all_of(out.begin(), out.end(), [](float v) { return v == -1.0f; }));
    // Validation comes first.
    target.color.plane[0].stride = 4 * w - 1;
    EXPECT_EQ(reproject(source, f.decoder, f.model, options, target).code(), StatusCode::invalid_stride);
    target.color.plane[0].stride = 4 * w;
    // Unset, the call runs whole and equals one without a flag.
    cancel = false;
    ASSERT_TRUE(reproject(source, f.decoder, f.model, options, target).ok());
    std::vector<float> plain(f.color.size());
    target.color = MutableColorView::rgba(plain.data(), w, h, 4 * w);
    options.cancel = nullptr;
    ASSERT_TRUE(reproject(source, f.decoder, f.model, options, target).ok());
    EXPECT_EQ(out, plain) << to_string(method);
  }
}

// A flag set from another thread while an 8K frame runs at one thread (the slowest method on the
// scalar reference: seconds for the whole frame) stops it. How soon is printed, not asserted
// (timings belong to benchmarks; the Python test holds Ctrl-C to its 100 ms).
TEST(Cancel, AFlagSetDuringTheCallStopsIt) {
  const int w = 7680, h = 4320;
  std::vector<float> depth(static_cast<std::size_t>(w) * h), color(depth.size()), out(depth.size());
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const double z = 2.0 + 30.0 * x / w;
      depth[static_cast<std::size_t>(y) * w + x] = static_cast<float>((1.0 - 1.0 / z) / (1.0 - 1.0 / 100.0));
      color[static_cast<std::size_t>(y) * w + x] = static_cast<float>(x) / w;
    }
  SourceView source;
  source.color = ColorView::planar({FloatPlane{color.data(), w, h, w}});
  source.depth = FloatPlane{depth.data(), w, h, w};
  TargetView target;
  target.color = MutableColorView::planar({MutableFloatPlane{out.data(), w, h, w}});
  const DepthDecoder decoder = DepthDecoder::from_near_far(DepthEncoding::standard, 1.0, 100.0);
  const ParallaxModel model = StereoCamera{0.06, 2.0}.parallax(w, EyeDirection::left_to_right);
  for (bool pair : {false, true}) {
    std::atomic<bool> cancel{false};
    Options options;
    options.method = Method::scanline;
    options.arch = Arch::scalar;
    options.threads = 1;
    options.cancel = &cancel;
    std::vector<float> left_out(out.size());
    TargetView left = target;
    left.color = MutableColorView::planar({MutableFloatPlane{left_out.data(), w, h, w}});
    std::chrono::steady_clock::time_point set_at;
    std::thread canceller([&] {
      std::this_thread::sleep_for(std::chrono::milliseconds(300));
      set_at = std::chrono::steady_clock::now();
      cancel.store(true);
    });
    const auto start = std::chrono::steady_clock::now();
    const Status s = pair ? reproject_pair(source, decoder, model, options, left, target)
                          : reproject(source, decoder, model, options, target);
    const auto end = std::chrono::steady_clock::now();
    canceller.join();
    EXPECT_EQ(s.code(), StatusCode::cancelled) << s.message();
    std::printf("[ cancel   ] %s 8K scanline (scalar, 1 thread): returned %.1f ms after the flag was set, %.0f ms into "
                "the call\n",
                pair ? "pair" : "single", std::chrono::duration<double, std::milli>(end - set_at).count(),
                std::chrono::duration<double, std::milli>(set_at - start).count());
  }
}

TEST(Cancel, AJobSystemsTasksStopToo) {
  const Frame f;
  const int w = f.width, h = f.height;
  std::vector<float> out(f.color.size(), -1.0f);
  SourceView source;
  source.color = ColorView::rgba(f.color.data(), w, h, 4 * w);
  source.depth = FloatPlane{f.depth.data(), w, h, w};
  TargetView target;
  target.color = MutableColorView::rgba(out.data(), w, h, 4 * w);
  struct Context {
    std::atomic<bool> cancel{false};
    int tasks = 0;
  } context;
  ParallelFor jobs;
  jobs.context = &context;
  jobs.run = [](void* c, int count, void (*task)(void*, int), void* task_context) {
    Context& ctx = *static_cast<Context*>(c);
    for (int i = 0; i < count; ++i) {
      task(task_context, i);
      ++ctx.tasks;
      ctx.cancel = true;  // after the first band
    }
  };
  Options options;
  options.cancel = &context.cancel;
  const Status s = reproject(source, f.decoder, f.model, options, target, jobs);
  EXPECT_EQ(s.code(), StatusCode::cancelled) << s.message();
  EXPECT_GT(context.tasks, 0);
  // The first band ran, the last did not.
  EXPECT_NE(out.front(), -1.0f);
  EXPECT_EQ(out.back(), -1.0f);
}

}  // namespace
}  // namespace reproject
