// Rows split over threads (Options::threads, ParallelFor): the output never depends on how the
// rows were split or on which threads ran them, bit for bit, and concurrent callers sharing the
// library's pool each get their own single-threaded answer.
//
// The frames have a few hundred rows of random piecewise depth (near boxes, slopes, far
// background, a few non-finite values), so the near limit the default pass finds comes from a
// handful of rows in one band, rows differ in cost, and every method meets walls and holes.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "kernels/dispatch.hpp"
#include "src/reproject_internal.hpp"
#include "reproject/reproject.hpp"

namespace reproject {
namespace {

constexpr Method kMethods[] = {Method::scanline, Method::march16, Method::single, Method::secant, Method::exact};

struct Shape {
  int width = 233;   // source width, guard band included
  int height = 301;
  int guard = 0;
  bool interleaved = false;
  bool linear = true;     // DepthDecoder::linear(); else standard near 1 far 40
  bool mirrored = false;  // b > 0
};

DepthDecoder decoder_of(const Shape& shape) {
  return shape.linear ? DepthDecoder::linear() : DepthDecoder::from_near_far(DepthEncoding::standard, 1.0, 40.0);
}

ParallaxModel model_of(const Shape& shape) {
  return ParallaxModel::from_stereo(0.06, 3.0, shape.width - 2 * shape.guard,
                                    shape.mirrored ? EyeDirection::right_to_left : EyeDirection::left_to_right);
}

// Source planes with odd strides (one float of slack after each row).
struct SourceFrame {
  Shape shape;
  std::ptrdiff_t stride = 0;
  std::ptrdiff_t color_stride = 0;
  std::vector<float> depth;
  std::vector<float> color;  // planar: 3 planes one after the other; interleaved: one RGBA plane

  SourceView view() const {
    SourceView view;
    const int w = shape.width, h = shape.height;
    view.depth = FloatPlane{depth.data(), w, h, stride};
    if (shape.interleaved) {
      view.color = ColorView::rgba(color.data(), w, h, color_stride);
    } else {
      for (int c = 0; c < 3; ++c)
        view.color.plane[c] = FloatPlane{color.data() + c * color_stride * h, w, h, color_stride};
      view.color.channels = 3;
    }
    return view;
  }
};

SourceFrame make_source(const Shape& shape, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const DepthDecoder decoder = decoder_of(shape);
  SourceFrame frame;
  frame.shape = shape;
  frame.stride = shape.width + 1;
  frame.color_stride = shape.width * (shape.interleaved ? 4 : 1) + 1;
  frame.depth.assign(static_cast<std::size_t>(frame.stride * shape.height), 0.0f);
  frame.color.resize(static_cast<std::size_t>(frame.color_stride * shape.height * (shape.interleaved ? 1 : 3)));
  for (float& v : frame.color) v = static_cast<float>(unit(rng));
  // A few rows carry something much nearer than the rest: the default near limit is theirs.
  const int near_row = static_cast<int>(unit(rng) * (shape.height - 8));
  for (int y = 0; y < shape.height; ++y) {
    const bool very_near = y >= near_row && y < near_row + 5;
    int x = 0;
    while (x < shape.width) {
      const int length = 1 + static_cast<int>(unit(rng) * 40.0);
      const double roll = unit(rng);
      const double z0 = roll < 0.25 ? 35.0 : (very_near && roll < 0.5 ? 1.1 : 1.6 + 20.0 * unit(rng));
      const double slope = (unit(rng) - 0.5) * 0.3;
      for (int k = 0; k < length && x < shape.width; ++k, ++x) {
        // Only the very near rows come nearer than 2: the default near limit is theirs alone.
        float d = decoder.encode(std::max(z0 < 2.0 ? z0 : 2.0, z0 + slope * k));
        const double r = unit(rng);
        if (r < 0.003) d = std::numeric_limits<float>::quiet_NaN();
        else if (r < 0.005) d = std::numeric_limits<float>::infinity();
        frame.depth[static_cast<std::size_t>(y * frame.stride + x)] = d;
      }
    }
  }
  return frame;
}

// All outputs, pre-filled with a sentinel so unwritten pixels and the stride slack compare too.
struct Output {
  int width = 0, height = 0;
  bool interleaved = false;
  std::ptrdiff_t stride = 0, color_stride = 0;
  std::vector<float> color, depth, source_x;
  std::vector<std::uint8_t> status;

  Output() = default;
  explicit Output(const Shape& shape)
      : width(shape.width - 2 * shape.guard), height(shape.height), interleaved(shape.interleaved) {
    stride = width + 3;
    color_stride = width * (interleaved ? 4 : 1) + 3;
    color.assign(static_cast<std::size_t>(color_stride * height * (interleaved ? 1 : 3)), -7.0f);
    depth.assign(static_cast<std::size_t>(stride * height), -7.0f);
    source_x.assign(depth.size(), -7.0f);
    status.assign(depth.size(), 0xA5);
  }
  TargetView view() {
    TargetView view;
    if (interleaved) {
      view.color = MutableColorView::rgba(color.data(), width, height, color_stride);
    } else {
      for (int c = 0; c < 3; ++c)
        view.color.plane[c] = MutableFloatPlane{color.data() + c * color_stride * height, width, height, color_stride};
      view.color.channels = 3;
    }
    view.depth = MutableFloatPlane{depth.data(), width, height, stride};
    view.status = BytePlane{status.data(), width, height, stride};
    view.source_x = MutableFloatPlane{source_x.data(), width, height, stride};
    return view;
  }
};

template <class T>
bool same_bits(const std::vector<T>& x, const std::vector<T>& y) {
  return x.size() == y.size() && std::memcmp(x.data(), y.data(), x.size() * sizeof(T)) == 0;
}

// Which planes differ ("" when none), for the failure message.
std::string differences(const Output& x, const Output& y) {
  std::string out;
  if (!same_bits(x.color, y.color)) out += " colour";
  if (!same_bits(x.depth, y.depth)) out += " depth";
  if (!same_bits(x.status, y.status)) out += " status";
  if (!same_bits(x.source_x, y.source_x)) out += " source_x";
  return out;
}

// Job systems of a caller's own ----------------------------------------------------------------

// Runs the tasks on `threads` std::threads of its own, started per run (the caller only waits).
struct ThreadedJobs {
  int threads = 3;
  std::atomic<int> runs{0};

  static void run(void* context, int count, void (*task)(void*, int), void* task_context) {
    ThreadedJobs& self = *static_cast<ThreadedJobs*>(context);
    self.runs.fetch_add(1);
    std::atomic<int> next{0};
    std::vector<std::thread> pool;
    for (int t = 0; t < self.threads; ++t)
      pool.emplace_back([&] {
        for (int i = next.fetch_add(1); i < count; i = next.fetch_add(1)) task(task_context, i);
      });
    for (std::thread& thread : pool) thread.join();
  }
  ParallelFor jobs() { return ParallelFor{this, &ThreadedJobs::run}; }
};

// Runs the tasks on the calling thread, last index first.
struct ReverseJobs {
  int tasks_run = 0;

  static void run(void* context, int count, void (*task)(void*, int), void* task_context) {
    ReverseJobs& self = *static_cast<ReverseJobs*>(context);
    for (int i = count - 1; i >= 0; --i) {
      task(task_context, i);
      ++self.tasks_run;
    }
  }
  ParallelFor jobs() { return ParallelFor{this, &ReverseJobs::run}; }
};

Output run_one(const SourceFrame& source, const Options& options, const ParallelFor* jobs = nullptr) {
  Output out(source.shape);
  const Status status = jobs ? reproject(source.view(), decoder_of(source.shape), model_of(source.shape), options, out.view(), *jobs)
                             : reproject(source.view(), decoder_of(source.shape), model_of(source.shape), options, out.view());
  EXPECT_TRUE(status.ok()) << status.message();
  return out;
}

struct PairOutput {
  Output left, right;
};

PairOutput run_pair(const SourceFrame& source, const Options& options, const ParallelFor* jobs = nullptr) {
  PairOutput out{Output(source.shape), Output(source.shape)};
  const SourceView view = source.view();
  const Status status =
      jobs ? reproject_pair(view, decoder_of(source.shape), model_of(source.shape), options, out.left.view(), out.right.view(), *jobs)
           : reproject_pair(view, decoder_of(source.shape), model_of(source.shape), options, out.left.view(), out.right.view());
  EXPECT_TRUE(status.ok()) << status.message();
  return out;
}

// The shapes and option sets every comparison runs over: both colour layouts, both decoder
// shapes, both directions, a guard band, and the near limit from the data or fixed.
std::vector<Shape> shapes() {
  std::vector<Shape> list;
  Shape a;
  list.push_back(a);
  Shape b;
  b.interleaved = true;
  b.linear = false;
  b.mirrored = true;
  b.guard = 6;
  b.height = 257;
  list.push_back(b);
  return list;
}

std::vector<Options> option_sets(const Shape& shape, Method method) {
  std::vector<Options> list;
  for (int variant = 0; variant < 3; ++variant) {
    Options options;
    options.method = method;
    options.guard = shape.guard;
    if (variant == 1) options.max_negative_parallax = 3.5f;  // no near pass, clips some rays
    if (variant == 2) {
      options.hole_fill = HoleFill::foreground;
      options.edge = EdgeMode::none;
    }
    list.push_back(options);
  }
  return list;
}

std::string label(const Shape& shape, const Options& options) {
  char text[160];
  std::snprintf(text, sizeof text, "%s %dx%d guard %d %s %s %s near %s fill %d edge %d", to_string(options.method),
                shape.width, shape.height, shape.guard, shape.interleaved ? "rgba" : "planar",
                shape.linear ? "linear" : "standard", shape.mirrored ? "b>0" : "b<0",
                options.max_negative_parallax ? "fixed" : "from data", static_cast<int>(options.hole_fill),
                static_cast<int>(options.edge));
  return text;
}

// ------------------------------------------------------------------------------------------------

// 1, 2, 3 threads and the default (one per hardware thread) give the same bits, every method,
// with and without the default near-limit pass. threads = 3 is honoured even on a machine with
// fewer hardware threads (the pool grows), so three threads really share the rows.
TEST(Threads, OneTwoThreeThreadsAreBitIdentical) {
  unsigned seed = 1;
  for (const Shape& shape : shapes()) {
    const SourceFrame source = make_source(shape, seed++);
    for (Method method : kMethods) {
      for (Options options : option_sets(shape, method)) {
        options.threads = 1;
        const Output one = run_one(source, options);
        for (int threads : {2, 3, 0}) {
          options.threads = threads;
          const Output many = run_one(source, options);
          EXPECT_EQ(differences(one, many), "") << label(shape, options) << ", threads " << threads;
        }
      }
    }
  }
}

// The explicit-kernel entry the SIMD tests use follows Options::threads too.
TEST(Threads, ReprojectWithHonoursThreads) {
  const Shape shape;
  const SourceFrame source = make_source(shape, 11);
  for (Method method : kMethods) {
    Options options;
    options.method = method;
    Output outputs[2] = {Output(shape), Output(shape)};
    for (int k = 0; k < 2; ++k) {
      options.threads = k == 0 ? 1 : 3;
      const Status status = detail::reproject_with(detail::reference_kernels(selected_arch()), source.view(),
                                                   decoder_of(shape), model_of(shape), options, outputs[k].view());
      ASSERT_TRUE(status.ok()) << status.message();
    }
    EXPECT_EQ(differences(outputs[0], outputs[1]), "") << to_string(method);
  }
}

// reproject_pair runs both eyes' rows in one phase: still the same bits for any thread count,
// and each eye equals a single reproject() with that eye's model (the left one mirrored).
TEST(Threads, PairIsBitIdenticalForAnyThreadCount) {
  unsigned seed = 21;
  for (const Shape& shape : shapes()) {
    const SourceFrame source = make_source(shape, seed++);
    for (Method method : kMethods) {
      for (Options options : option_sets(shape, method)) {
        options.threads = 1;
        const PairOutput one = run_pair(source, options);
        for (int threads : {2, 3}) {
          options.threads = threads;
          const PairOutput many = run_pair(source, options);
          EXPECT_EQ(differences(one.left, many.left), "") << label(shape, options) << ", left, threads " << threads;
          EXPECT_EQ(differences(one.right, many.right), "") << label(shape, options) << ", right, threads " << threads;
        }
        // The right eye is the model itself; the left its mirror.
        options.threads = 2;
        const Output right = run_one(source, options);
        EXPECT_EQ(differences(one.right, right), "") << label(shape, options) << ", right vs single";
        Output left(shape);
        const ParallaxModel model = model_of(shape);
        const Status status = reproject(source.view(), decoder_of(shape), ParallaxModel{-model.a, -model.b}, options, left.view());
        ASSERT_TRUE(status.ok()) << status.message();
        EXPECT_EQ(differences(one.left, left), "") << label(shape, options) << ", left vs single";
      }
    }
  }
}

// The caller's job system, whether it spreads the tasks over threads of its own or runs them
// backwards on the calling thread, gives the pool's bits, for reproject and reproject_pair.
TEST(Threads, CallersJobSystemMatchesThePool) {
  unsigned seed = 31;
  for (const Shape& shape : shapes()) {
    const SourceFrame source = make_source(shape, seed++);
    for (Method method : kMethods) {
      for (Options options : option_sets(shape, method)) {
        options.threads = 0;
        const Output pooled = run_one(source, options);
        const PairOutput pooled_pair = run_pair(source, options);
        // Options::threads is ignored by the job-system overloads.
        options.threads = 1;
        ThreadedJobs threaded;
        const ParallelFor threaded_jobs = threaded.jobs();
        ReverseJobs reverse;
        const ParallelFor reverse_jobs = reverse.jobs();
        for (const ParallelFor* jobs : {&threaded_jobs, &reverse_jobs}) {
          const char* name = jobs == &threaded_jobs ? "own threads" : "reverse order";
          const Output out = run_one(source, options, jobs);
          EXPECT_EQ(differences(pooled, out), "") << label(shape, options) << ", " << name;
          const PairOutput pair = run_pair(source, options, jobs);
          EXPECT_EQ(differences(pooled_pair.left, pair.left), "") << label(shape, options) << ", pair left, " << name;
          EXPECT_EQ(differences(pooled_pair.right, pair.right), "") << label(shape, options) << ", pair right, " << name;
        }
        // They were really used: one run per phase of each call (the near-limit pass is skipped
        // with an explicit limit, and by the methods that never search from the near end).
        const bool near_pass = !options.max_negative_parallax && method != Method::single && method != Method::exact;
        const int phases = near_pass ? 2 : 1;
        EXPECT_EQ(threaded.runs.load(), 2 * phases);
        EXPECT_GT(reverse.tasks_run, 2 * phases);
      }
    }
  }
}

TEST(Threads, NullJobSystemIsAnError) {
  const Shape shape;
  const SourceFrame source = make_source(shape, 41);
  Output out(shape), left(shape), right(shape);
  const ParallelFor null_jobs;  // run == nullptr
  Status status = reproject(source.view(), decoder_of(shape), model_of(shape), Options(), out.view(), null_jobs);
  EXPECT_EQ(status.code(), StatusCode::invalid_option) << status.message();
  EXPECT_NE(std::strstr(status.message(), "ParallelFor::run"), nullptr) << status.message();
  status = reproject_pair(source.view(), decoder_of(shape), model_of(shape), Options(), left.view(), right.view(), null_jobs);
  EXPECT_EQ(status.code(), StatusCode::invalid_option) << status.message();
  // Even on an empty frame: the argument is wrong whatever the frame.
  SourceView empty;
  status = reproject(empty, decoder_of(shape), model_of(shape), Options(), TargetView(), null_jobs);
  EXPECT_EQ(status.code(), StatusCode::invalid_option) << status.message();
  // Nothing was written.
  const Output untouched(shape);
  EXPECT_EQ(differences(out, untouched), "");
}

TEST(Threads, NegativeThreadCountIsAnError) {
  const Shape shape;
  const SourceFrame source = make_source(shape, 43);
  Output out(shape), left(shape), right(shape);
  Options options;
  options.threads = -1;
  Status status = reproject(source.view(), decoder_of(shape), model_of(shape), options, out.view());
  EXPECT_EQ(status.code(), StatusCode::invalid_option) << status.message();
  EXPECT_NE(std::strstr(status.message(), "threads"), nullptr) << status.message();
  status = reproject_pair(source.view(), decoder_of(shape), model_of(shape), options, left.view(), right.view());
  EXPECT_EQ(status.code(), StatusCode::invalid_option) << status.message();
  // Huge counts are fine (capped): the output is the same.
  options.threads = 1;
  const Output one = run_one(source, options);
  options.threads = 1 << 30;
  const Output capped = run_one(source, options);
  EXPECT_EQ(differences(one, capped), "");
}

// Several threads call reproject at once on different frames, sharing the pool (and its
// workers), with different thread counts: each result is its own single-threaded one.
TEST(Threads, ConcurrentCallersShareThePool) {
  constexpr int kCallers = 4;
  constexpr int kRounds = 6;
  std::vector<SourceFrame> sources;
  std::vector<Output> expected;
  std::vector<Options> options(kCallers);
  for (int c = 0; c < kCallers; ++c) {
    Shape shape;
    shape.height = 150 + 40 * c;
    shape.interleaved = c % 2 == 1;
    shape.mirrored = c >= 2;
    sources.push_back(make_source(shape, 100 + c));
    options[c].method = kMethods[c % kMethodCount];
    if (c == 3) options[c].max_negative_parallax = 2.0f;
    options[c].threads = 1;
    expected.push_back(run_one(sources[c], options[c]));
  }
  std::atomic<int> mismatches{0};
  std::atomic<int> failures{0};
  std::atomic<bool> go{false};
  std::vector<std::thread> callers;
  for (int c = 0; c < kCallers; ++c) {
    callers.emplace_back([&, c] {
      while (!go.load()) std::this_thread::yield();
      Options mine = options[c];
      for (int round = 0; round < kRounds; ++round) {
        mine.threads = (round + c) % 4;  // 0 (default), 1, 2, 3
        Output out(sources[c].shape);
        const Shape& shape = sources[c].shape;
        const Status status = reproject(sources[c].view(), decoder_of(shape), model_of(shape), mine, out.view());
        if (!status.ok()) failures.fetch_add(1);
        if (!differences(expected[c], out).empty()) mismatches.fetch_add(1);
      }
    });
  }
  go.store(true);
  for (std::thread& caller : callers) caller.join();
  EXPECT_EQ(failures.load(), 0);
  EXPECT_EQ(mismatches.load(), 0);
}

// A job system that, while it runs one call's tasks, has the same thread make another call
// (as a work-stealing system may): both results are right.
struct NestingJobs {
  const SourceFrame* inner_source = nullptr;
  Output* inner_out = nullptr;
  Options inner_options;
  bool nested = false;
  Status inner_status;

  static void run(void* context, int count, void (*task)(void*, int), void* task_context) {
    NestingJobs& self = *static_cast<NestingJobs*>(context);
    for (int i = 0; i < count; ++i) {
      task(task_context, i);
      if (!self.nested && i == count / 2) {
        self.nested = true;
        const Shape& shape = self.inner_source->shape;
        self.inner_status = reproject(self.inner_source->view(), decoder_of(shape), model_of(shape), self.inner_options,
                                      self.inner_out->view());
      }
    }
  }
};

TEST(Threads, NestedCallOnTheSameThread) {
  Shape outer_shape;
  Shape inner_shape;
  inner_shape.width = 517;  // wider: the nested call needs bigger scratch than the outer one holds
  inner_shape.height = 97;
  const SourceFrame outer = make_source(outer_shape, 51);
  const SourceFrame inner = make_source(inner_shape, 52);
  for (Method method : kMethods) {
    Options options;
    options.method = method;
    options.threads = 1;
    const Output outer_expected = run_one(outer, options);
    const Output inner_expected = run_one(inner, options);
    Output inner_out(inner_shape);
    NestingJobs nesting;
    nesting.inner_source = &inner;
    nesting.inner_out = &inner_out;
    nesting.inner_options = options;
    nesting.inner_options.threads = 2;
    const ParallelFor jobs{&nesting, &NestingJobs::run};
    const Output outer_out = run_one(outer, options, &jobs);
    ASSERT_TRUE(nesting.nested);
    EXPECT_TRUE(nesting.inner_status.ok()) << nesting.inner_status.message();
    EXPECT_EQ(differences(outer_expected, outer_out), "") << to_string(method) << ", outer";
    EXPECT_EQ(differences(inner_expected, inner_out), "") << to_string(method) << ", inner";
  }
}

// Frames with fewer rows than threads, and a single row.
TEST(Threads, FewerRowsThanThreads) {
  for (int height : {1, 2, 3, 5}) {
    Shape shape;
    shape.height = height;
    const SourceFrame source = make_source(shape, 60 + height);
    for (Method method : kMethods) {
      Options options;
      options.method = method;
      options.threads = 1;
      const Output one = run_one(source, options);
      options.threads = 3;
      EXPECT_EQ(differences(one, run_one(source, options)), "") << to_string(method) << " height " << height;
      ReverseJobs reverse;
      const ParallelFor jobs = reverse.jobs();
      EXPECT_EQ(differences(one, run_one(source, options, &jobs)), "") << to_string(method) << " height " << height;
    }
  }
}

}  // namespace
}  // namespace reproject
