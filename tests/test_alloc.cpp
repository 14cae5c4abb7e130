// No heap allocation per call once warm: after one call with given sizes, the next call with the
// same sizes allocates nothing, for every method, on the calling thread only, on the library's
// pool, through a caller's job system and for a stereo pair; and validation never allocates.
//
// Its own executable: it replaces the global operator new/delete (every form) with counting
// versions, which count only while a measured call runs (on any thread: the pool's workers are
// counted too).
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <mutex>
#include <new>
#include <thread>
#include <vector>

#include "reproject/reproject.hpp"

namespace {

std::atomic<bool> g_counting{false};
std::atomic<long> g_allocations{0};

void* counted_malloc(std::size_t size) noexcept {
  if (g_counting.load(std::memory_order_relaxed)) g_allocations.fetch_add(1, std::memory_order_relaxed);
  return std::malloc(size == 0 ? 1 : size);
}

void* counted_aligned(std::size_t size, std::align_val_t alignment) noexcept {
  if (g_counting.load(std::memory_order_relaxed)) g_allocations.fetch_add(1, std::memory_order_relaxed);
  const std::size_t align = std::max(static_cast<std::size_t>(alignment), sizeof(void*));
  const std::size_t rounded = (std::max<std::size_t>(size, 1) + align - 1) / align * align;  // aligned_alloc wants a multiple
#if defined(_WIN32)
  return _aligned_malloc(rounded, align);  // Windows' C runtime has no aligned_alloc
#else
  return std::aligned_alloc(align, rounded);
#endif
}

// Out of line: inlined into a delete-expression, a direct free() of what operator new returned
// draws GCC's -Wmismatched-new-delete, although new and delete here are malloc and free.
[[gnu::noinline]] void release(void* p) noexcept { std::free(p); }
#if defined(_WIN32)
void release_aligned(void* p) noexcept { _aligned_free(p); }  // what _aligned_malloc returned
#else
void release_aligned(void* p) noexcept { release(p); }
#endif

// The throwing forms may not return null: without exceptions (REPROJECT_EXCEPTIONS=OFF) the
// process ends instead, as the standard library's own operator new does there.
void* or_throw(void* p) {
#if defined(__cpp_exceptions)
  if (p == nullptr) throw std::bad_alloc();
#else
  if (p == nullptr) std::abort();
#endif
  return p;
}

// Allocations made by fn() on any thread.
template <class Fn>
long count_allocations(Fn&& fn) {
  g_allocations.store(0);
  g_counting.store(true);
  fn();
  g_counting.store(false);
  return g_allocations.load();
}

}  // namespace

void* operator new(std::size_t size) { return or_throw(counted_malloc(size)); }
void* operator new[](std::size_t size) { return or_throw(counted_malloc(size)); }
void* operator new(std::size_t size, const std::nothrow_t&) noexcept { return counted_malloc(size); }
void* operator new[](std::size_t size, const std::nothrow_t&) noexcept { return counted_malloc(size); }
void* operator new(std::size_t size, std::align_val_t a) { return or_throw(counted_aligned(size, a)); }
void* operator new[](std::size_t size, std::align_val_t a) { return or_throw(counted_aligned(size, a)); }
void* operator new(std::size_t size, std::align_val_t a, const std::nothrow_t&) noexcept { return counted_aligned(size, a); }
void* operator new[](std::size_t size, std::align_val_t a, const std::nothrow_t&) noexcept { return counted_aligned(size, a); }
void operator delete(void* p) noexcept { release(p); }
void operator delete[](void* p) noexcept { release(p); }
void operator delete(void* p, std::size_t) noexcept { release(p); }
void operator delete[](void* p, std::size_t) noexcept { release(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { release(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { release(p); }
void operator delete(void* p, std::align_val_t) noexcept { release_aligned(p); }
void operator delete[](void* p, std::align_val_t) noexcept { release_aligned(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { release_aligned(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { release_aligned(p); }
void operator delete(void* p, std::align_val_t, const std::nothrow_t&) noexcept { release_aligned(p); }
void operator delete[](void* p, std::align_val_t, const std::nothrow_t&) noexcept { release_aligned(p); }

namespace reproject {
namespace {

constexpr Method kMethods[] = {Method::scanline, Method::march16, Method::single, Method::secant, Method::exact};

// A source with near and far rows, slopes and walls; planar RGB; all outputs requested.
struct Buffers {
  int width, height;
  std::vector<float> depth, color, out_color, out_depth, out_x, out_color2, out_depth2, out_x2;
  std::vector<std::uint8_t> out_status, out_status2;

  Buffers(int w, int h) : width(w), height(h) {
    const std::size_t n = static_cast<std::size_t>(w) * h;
    depth.resize(n);
    color.resize(3 * n);
    out_color.resize(3 * n);
    out_color2.resize(3 * n);
    out_depth.resize(n);
    out_depth2.resize(n);
    out_x.resize(n);
    out_x2.resize(n);
    out_status.resize(n);
    out_status2.resize(n);
    unsigned state = 12345u;
    auto next = [&] { return (state = state * 1664525u + 1013904223u) >> 8; };
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        depth[static_cast<std::size_t>(y) * w + x] = ((x / 17 + y / 9) % 3 == 0) ? 1.5f + 0.01f * (x % 17) : 8.0f + (next() % 100) * 0.05f;
    for (float& c : color) c = static_cast<float>(next() % 1000) / 1000.0f;
  }
  SourceView source() const {
    SourceView view;
    view.depth = FloatPlane{depth.data(), width, height, width};
    for (int c = 0; c < 3; ++c)
      view.color.plane[c] = FloatPlane{color.data() + static_cast<std::size_t>(c) * width * height, width, height, width};
    view.color.channels = 3;
    return view;
  }
  TargetView target(int which) {
    std::vector<float>& color = which == 0 ? out_color : out_color2;
    TargetView view;
    for (int c = 0; c < 3; ++c)
      view.color.plane[c] = MutableFloatPlane{color.data() + static_cast<std::size_t>(c) * width * height, width, height, width};
    view.color.channels = 3;
    view.depth = MutableFloatPlane{(which == 0 ? out_depth : out_depth2).data(), width, height, width};
    view.status = BytePlane{(which == 0 ? out_status : out_status2).data(), width, height, width};
    view.source_x = MutableFloatPlane{(which == 0 ? out_x : out_x2).data(), width, height, width};
    return view;
  }
};

const DepthDecoder kDecoder = DepthDecoder::linear();

ParallaxModel model_for(int width) { return ParallaxModel::from_stereo(0.05, 3.0, width, EyeDirection::left_to_right); }

// A caller's job system with two persistent threads of its own: nothing allocated per run.
class TwoThreadJobs {
 public:
  TwoThreadJobs() {
    for (std::thread& t : threads_) t = std::thread([this] { loop(); });
  }
  ~TwoThreadJobs() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stop_ = true;
    }
    wake_.notify_all();
    for (std::thread& t : threads_) t.join();
  }
  ParallelFor jobs() { return ParallelFor{this, &TwoThreadJobs::run}; }

 private:
  static void run(void* context, int count, void (*task)(void*, int), void* task_context) {
    TwoThreadJobs& self = *static_cast<TwoThreadJobs*>(context);
    std::unique_lock<std::mutex> lock(self.mutex_);
    self.task_ = task;
    self.task_context_ = task_context;
    self.count_ = count;
    self.next_.store(0);
    self.finished_ = 0;
    ++self.generation_;
    self.wake_.notify_all();
    self.done_.wait(lock, [&] { return self.finished_ == 2; });
  }
  void loop() {
    std::unique_lock<std::mutex> lock(mutex_);
    long seen = 0;
    for (;;) {
      wake_.wait(lock, [&] { return stop_ || generation_ != seen; });
      if (stop_) return;
      seen = generation_;
      lock.unlock();
      for (int i = next_.fetch_add(1); i < count_; i = next_.fetch_add(1)) task_(task_context_, i);
      lock.lock();
      if (++finished_ == 2) done_.notify_one();
    }
  }

  std::mutex mutex_;
  std::condition_variable wake_, done_;
  std::thread threads_[2];
  bool stop_ = false;
  long generation_ = 0;
  void (*task_)(void*, int) = nullptr;
  void* task_context_ = nullptr;
  int count_ = 0;
  std::atomic<int> next_{0};
  int finished_ = 0;
};

// Calling-thread job system: tasks in reverse order.
void reverse_run(void*, int count, void (*task)(void*, int), void* task_context) {
  for (int i = count - 1; i >= 0; --i) task(task_context, i);
}

// The counter works: it sees an allocation made on purpose, and the library's first call at a
// new size (its scratch, and the pool's threads on the pool's first use), so the zero counts
// below are measured, not assumed.
TEST(Allocations, TheCounterCountsAllocations) {
  const long on_purpose = count_allocations([] {
    void* volatile p = ::operator new(64);
    ::operator delete(p);
  });
  std::printf("an allocation made on purpose: %ld counted\n", on_purpose);
  EXPECT_EQ(on_purpose, 1);

  Buffers buffers(2000, 24);  // wider than any other test here: its scratch is new
  Options options;
  options.threads = 2;
  Status status;
  const long first = count_allocations([&] {
    status = reproject(buffers.source(), kDecoder, model_for(buffers.width), options, buffers.target(0));
  });
  ASSERT_TRUE(status.ok()) << status.message();
  std::printf("first call at a new size: %ld allocations\n", first);
  EXPECT_GT(first, 0);
}

struct Case {
  const char* how;
  int threads;            // Options::threads (pool overloads)
  const ParallelFor* jobs;  // non-null: the job-system overload
  bool pair;
};

TEST(Allocations, SecondCallAllocatesNothing) {
  Buffers buffers(640, 120);
  const ParallaxModel model = model_for(buffers.width);
  TwoThreadJobs two_threads;
  const ParallelFor own_threads = two_threads.jobs();
  const ParallelFor reverse{nullptr, &reverse_run};
  const Case cases[] = {
      {"threads 1", 1, nullptr, false},           {"threads 2", 2, nullptr, false},
      {"threads 0 (default)", 0, nullptr, false}, {"job system, 2 threads", 0, &own_threads, false},
      {"job system, reverse", 0, &reverse, false}, {"pair, threads 1", 1, nullptr, true},
      {"pair, threads 2", 2, nullptr, true},       {"pair, job system", 0, &own_threads, true},
  };
  for (const Case& c : cases) {
    for (Method method : kMethods) {
      for (bool near_from_data : {true, false}) {
        Options options;
        options.method = method;
        options.threads = c.threads;
        if (!near_from_data) options.max_negative_parallax = 4.0f;
        Status status;
        auto call = [&] {
          const SourceView source = buffers.source();
          if (c.pair) {
            status = c.jobs ? reproject_pair(source, kDecoder, model, options, buffers.target(0), buffers.target(1), *c.jobs)
                            : reproject_pair(source, kDecoder, model, options, buffers.target(0), buffers.target(1));
          } else {
            status = c.jobs ? reproject(source, kDecoder, model, options, buffers.target(0), *c.jobs)
                            : reproject(source, kDecoder, model, options, buffers.target(0));
          }
        };
        const long warm_up = count_allocations(call);
        ASSERT_TRUE(status.ok()) << status.message();
        const long second = count_allocations(call);
        ASSERT_TRUE(status.ok()) << status.message();
        std::printf("%-22s %-8s near %-9s: warm-up %3ld allocations, second call %ld\n", c.how, to_string(method),
                    near_from_data ? "from data" : "fixed", warm_up, second);
        EXPECT_EQ(second, 0) << c.how << " " << to_string(method) << (near_from_data ? " near from data" : " near fixed");
      }
    }
  }
}

// Engine formats: RGBA8 sRGB colour with D16 depth and depth output (whose values the decode
// keeps in the row scratch) and RGBA16F with D24S8: after a first call, nothing.
TEST(Allocations, EngineFormatsSecondCallAllocatesNothing) {
  const int width = 640, height = 120;
  std::vector<std::uint8_t> color(static_cast<std::size_t>(width) * height * 8, 0x40), out(color.size());
  std::vector<std::uint8_t> depth(static_cast<std::size_t>(width) * height * 4), depth_out(depth.size());
  for (std::size_t i = 0; i < depth.size(); ++i) depth[i] = static_cast<std::uint8_t>(i * 37 % 251);
  const DepthDecoder decoder = DepthDecoder::from_near_far(DepthEncoding::standard, 0.5, 50.0);
  struct Pair {
    ColorFormat color;
    DepthFormat depth;
  };
  for (const Pair& p : {Pair{ColorFormat::rgba8_srgb, DepthFormat::unorm16}, Pair{ColorFormat::rgba16f, DepthFormat::unorm24_s8}}) {
    const std::ptrdiff_t cpitch = static_cast<std::ptrdiff_t>(width) * bytes_per_pixel(p.color);
    const std::ptrdiff_t dpitch = static_cast<std::ptrdiff_t>(width) * bytes_per_pixel(p.depth);
    SourceView source;
    source.color = ColorView::packed(p.color, color.data(), width, height, cpitch);
    source.depth_buffer = DepthBuffer::of(p.depth, depth.data(), width, height, dpitch);
    TargetView target;
    target.color = MutableColorView::packed(p.color, out.data(), width, height, cpitch);
    target.depth_buffer = MutableDepthBuffer::of(p.depth, depth_out.data(), width, height, dpitch);
    for (Method method : kMethods) {
      for (int threads : {1, 2}) {
        Options options;
        options.method = method;
        options.threads = threads;
        Status status;
        auto call = [&] { status = reproject(source, decoder, model_for(width), options, target); };
        const long warm_up = count_allocations(call);
        ASSERT_TRUE(status.ok()) << status.message();
        const long second = count_allocations(call);
        std::printf("%s+%s %-8s threads %d: warm-up %3ld allocations, second call %ld\n", to_string(p.color),
                    to_string(p.depth), to_string(method), threads, warm_up, second);
        EXPECT_EQ(second, 0);
      }
    }
  }
}

// Validation builds its messages in the Status's own buffer.
TEST(Allocations, ValidationAllocatesNothing) {
  Buffers buffers(64, 8);
  const ParallaxModel model = model_for(buffers.width);
  TargetView bad_target = buffers.target(0);
  bad_target.depth.width = 63;  // size mismatch
  Options bad_options;
  bad_options.threads = -2;
  const ParallelFor null_jobs;
  Status results[5];
  const long count = count_allocations([&] {
    results[0] = reproject(buffers.source(), kDecoder, model, Options(), bad_target);
    results[1] = reproject(buffers.source(), kDecoder, model, bad_options, buffers.target(0));
    results[2] = reproject(buffers.source(), kDecoder, model, Options(), buffers.target(0), null_jobs);
    results[3] = reproject_pair(buffers.source(), kDecoder, model, Options(), buffers.target(0), buffers.target(0));
    results[4] = reproject(buffers.source(), DepthDecoder::from_near_far(DepthEncoding::standard, -1.0, 1.0), model,
                           Options(), buffers.target(0));
  });
  for (const Status& status : results) {
    EXPECT_FALSE(status.ok());
    std::printf("rejected: %s\n", status.message());
  }
  std::printf("validation failures: %ld allocations\n", count);
  EXPECT_EQ(count, 0);
}

}  // namespace
}  // namespace reproject
