// The host's memory (reproject/memory.hpp, docs/BEHAVIOUR.md "Memory"):
//  * every byte the library takes comes from the host's allocator and goes back to it, with the
//    size and alignment it was asked for; after release_memory() nothing is out;
//  * a call with the sizes of an earlier one takes nothing;
//  * set_allocator is refused while memory is held or a call runs;
//  * out of memory, tested as SQLite tests its malloc failures: an allocator that fails the k-th
//    allocation, for k = 1, 2, ... until a call completes without a failure, for each method, a
//    pair, one and two threads, a caller's job system, the engine formats, SSIM, the parallax
//    budget and Image. Every failed call returns out_of_memory, nothing is left out after
//    release_memory(), and the next call with a working allocator gives the same bytes as a call
//    that never failed.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <functional>
#include <map>
#include <mutex>
#include <new>
#include <string>
#include <vector>

#include "reproject/metrics.hpp"
#include "reproject/reproject.hpp"
#include "reproject/stereo.hpp"

namespace reproject {
namespace {

// An allocator that counts, checks what comes back, and can be told to fail the k-th allocation
// (counting from 1) and every later one, or only that one.
class TestAllocator {
 public:
  Allocator allocator() { return Allocator{&TestAllocator::allocate, &TestAllocator::deallocate, this}; }

  void fail_at(long k, bool only_that_one) {
    std::lock_guard<std::mutex> lock(mutex_);
    fail_at_ = k;
    only_one_ = only_that_one;
    calls_ = 0;
  }
  long calls() {
    std::lock_guard<std::mutex> lock(mutex_);
    return calls_;
  }
  long failures() {
    std::lock_guard<std::mutex> lock(mutex_);
    return failures_;
  }
  std::size_t outstanding() {
    std::lock_guard<std::mutex> lock(mutex_);
    std::size_t bytes = 0;
    for (const auto& block : blocks_) bytes += block.second.size;
    return bytes;
  }
  std::vector<std::string> errors() {
    std::lock_guard<std::mutex> lock(mutex_);
    return errors_;
  }

 private:
  struct Block {
    std::size_t size, alignment;
  };
  static void* allocate(void* user, std::size_t size, std::size_t alignment) {
    TestAllocator& self = *static_cast<TestAllocator*>(user);
    std::lock_guard<std::mutex> lock(self.mutex_);
    ++self.calls_;
    if (alignment == 0 || (alignment & (alignment - 1)) != 0 || alignment > 4096) {
      self.errors_.push_back("alignment " + std::to_string(alignment) + " is not a power of two <= 4096");
    }
    if (self.fail_at_ > 0 && (self.only_one_ ? self.calls_ == self.fail_at_ : self.calls_ >= self.fail_at_)) {
      ++self.failures_;
      return nullptr;
    }
    void* p = ::operator new(size, std::align_val_t(alignment), std::nothrow);
    if (p != nullptr) self.blocks_[p] = Block{size, alignment};
    return p;
  }
  static void deallocate(void* user, void* pointer, std::size_t size, std::size_t alignment) {
    TestAllocator& self = *static_cast<TestAllocator*>(user);
    std::lock_guard<std::mutex> lock(self.mutex_);
    auto it = self.blocks_.find(pointer);
    if (it == self.blocks_.end()) {
      self.errors_.push_back("deallocate of a pointer this allocator did not give");
      return;
    }
    if (it->second.size != size || it->second.alignment != alignment) {
      self.errors_.push_back("deallocate with size " + std::to_string(size) + " / alignment " + std::to_string(alignment) +
                             ", allocated as " + std::to_string(it->second.size) + " / " +
                             std::to_string(it->second.alignment));
    }
    ::operator delete(pointer, std::align_val_t(it->second.alignment), std::nothrow);
    self.blocks_.erase(it);
  }

  std::mutex mutex_;
  std::map<void*, Block> blocks_;
  std::vector<std::string> errors_;
  long calls_ = 0, failures_ = 0, fail_at_ = 0;
  bool only_one_ = false;
};

// The library back on the default allocator with nothing held, whatever a test did (declared
// after the test's allocator, so that it runs while that allocator still exists).
struct DefaultAllocatorAfter {
  ~DefaultAllocatorAfter() {
    release_memory();
    EXPECT_TRUE(set_allocator(nullptr).ok());
  }
};

// A frame with near objects, walls and holes: planar RGB float, and the same scene as rgba8 +
// D24S8 for the engine formats.
struct Scene {
  int width = 97, height = 23;
  std::vector<float> depth, color;
  std::vector<std::uint8_t> pixels;
  std::vector<std::uint32_t> d24s8;

  Scene() {
    const std::size_t n = static_cast<std::size_t>(width) * height;
    depth.resize(n);
    color.resize(3 * n);
    pixels.resize(4 * n);
    d24s8.resize(n);
    unsigned state = 777u;
    auto next = [&] { return (state = state * 1664525u + 1013904223u) >> 8; };
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) {
        const std::size_t i = static_cast<std::size_t>(y) * width + x;
        depth[i] = ((x / 13 + y / 7) % 3 == 0) ? 0.2f + 0.001f * (x % 13) : 0.7f + (next() % 100) * 0.002f;
        d24s8[i] = static_cast<std::uint32_t>(depth[i] * 16777215.0f) | (static_cast<std::uint32_t>(x & 0xff) << 24);
      }
    for (float& c : color) c = static_cast<float>(next() % 1000) / 1000.0f;
    for (std::uint8_t& b : pixels) b = static_cast<std::uint8_t>(next());
  }
  SourceView floats() const {
    SourceView view;
    view.depth = FloatPlane{depth.data(), width, height, width};
    const std::size_t n = static_cast<std::size_t>(width) * height;
    view.color = ColorView::planar({FloatPlane{color.data(), width, height, width},
                                    FloatPlane{color.data() + n, width, height, width},
                                    FloatPlane{color.data() + 2 * n, width, height, width}});
    return view;
  }
  SourceView engine() const {
    SourceView view;
    view.color = ColorView::packed(ColorFormat::rgba8, pixels.data(), width, height, 4 * width);
    view.depth_buffer = DepthBuffer::of(DepthFormat::unorm24_s8, d24s8.data(), width, height, 4 * width);
    return view;
  }
};

// Every output of a call, as bytes, in buffers the test owns (not the library's allocator's).
struct Outputs {
  std::vector<float> color[2], depth[2], x[2];
  std::vector<std::uint8_t> status[2], pixels[2];
  std::vector<std::uint32_t> d24s8[2];
  std::vector<double> numbers;

  TargetView floats(int eye, int width, int height) {
    const std::size_t n = static_cast<std::size_t>(width) * height;
    color[eye].assign(3 * n, -1.0f);
    depth[eye].assign(n, -1.0f);
    x[eye].assign(n, -1.0f);
    status[eye].assign(n, 99);
    TargetView t;
    float* rgb = color[eye].data();
    t.color = MutableColorView::planar({MutableFloatPlane{rgb, width, height, width},
                                        MutableFloatPlane{rgb + n, width, height, width},
                                        MutableFloatPlane{rgb + 2 * n, width, height, width}});
    t.depth = MutableFloatPlane{depth[eye].data(), width, height, width};
    t.status = BytePlane{status[eye].data(), width, height, width};
    t.source_x = MutableFloatPlane{x[eye].data(), width, height, width};
    return t;
  }
  TargetView engine(int eye, int width, int height) {
    const std::size_t n = static_cast<std::size_t>(width) * height;
    pixels[eye].assign(4 * n, 7);
    d24s8[eye].assign(n, 7u);
    status[eye].assign(n, 99);
    TargetView t;
    t.color = MutableColorView::packed(ColorFormat::rgba8, pixels[eye].data(), width, height, 4 * width);
    t.depth_buffer = MutableDepthBuffer::of(DepthFormat::unorm24_s8, d24s8[eye].data(), width, height, 4 * width);
    t.status = BytePlane{status[eye].data(), width, height, width};
    return t;
  }
  bool operator==(const Outputs& o) const {
    for (int e = 0; e < 2; ++e) {
      if (color[e] != o.color[e] || depth[e] != o.depth[e] || x[e] != o.x[e] || status[e] != o.status[e] ||
          pixels[e] != o.pixels[e] || d24s8[e] != o.d24s8[e])
        return false;
    }
    return numbers == o.numbers;
  }
};

// A caller's job system on the calling thread (tasks in reverse order).
void reverse_run(void*, int count, void (*task)(void*, int), void* task_context) {
  for (int i = count - 1; i >= 0; --i) task(task_context, i);
}

struct Scenario {
  std::string name;
  std::function<Status(const Scene&, Outputs&)> call;
};

std::vector<Scenario> scenarios() {
  std::vector<Scenario> list;
  const DepthDecoder decoder = DepthDecoder::from_near_far(DepthEncoding::standard, 1.0, 20.0);
  for (Method method : {Method::scanline, Method::march16, Method::single, Method::secant, Method::exact}) {
    for (int threads : {1, 2}) {
      list.push_back({std::string(to_string(method)) + ", " + std::to_string(threads) + " thread(s)",
                      [=](const Scene& s, Outputs& out) {
                        Options options;
                        options.method = method;
                        options.threads = threads;
                        const ParallaxModel model = ParallaxModel::from_stereo(0.04, 4.0, s.width, EyeDirection::left_to_right);
                        return reproject(s.floats(), decoder, model, options, out.floats(0, s.width, s.height));
                      }});
    }
  }
  for (int threads : {1, 2}) {
    list.push_back({"pair, " + std::to_string(threads) + " thread(s)", [=](const Scene& s, Outputs& out) {
                      Options options;
                      options.threads = threads;
                      const ParallaxModel model = ParallaxModel::from_stereo(0.04, 4.0, s.width, EyeDirection::centre_to_right);
                      return reproject_pair(s.floats(), decoder, model, options, out.floats(0, s.width, s.height),
                                            out.floats(1, s.width, s.height));
                    }});
  }
  list.push_back({"job system", [=](const Scene& s, Outputs& out) {
                    Options options;
                    options.method = Method::exact;
                    const ParallaxModel model = ParallaxModel::from_stereo(0.04, 4.0, s.width, EyeDirection::left_to_right);
                    return reproject(s.floats(), decoder, model, options, out.floats(0, s.width, s.height),
                                     ParallelFor{nullptr, reverse_run});
                  }});
  list.push_back({"engine formats (rgba8 + D24S8), 2 threads", [=](const Scene& s, Outputs& out) {
                    Options options;
                    options.threads = 2;
                    options.method = Method::march16;
                    const ParallaxModel model = ParallaxModel::from_stereo(0.04, 4.0, s.width, EyeDirection::left_to_right);
                    return reproject(s.engine(), decoder, model, options, out.engine(0, s.width, s.height));
                  }});
  list.push_back({"ssim", [](const Scene& s, Outputs& out) {
                    double value = 0;
                    // The colour against itself one row down.
                    const std::ptrdiff_t plane = static_cast<std::ptrdiff_t>(s.width) * s.height;
                    const FloatSamples a = FloatSamples::planar(s.color.data(), s.width, s.height - 1, 3, s.width, plane);
                    const FloatSamples b =
                        FloatSamples::planar(s.color.data() + s.width, s.width, s.height - 1, 3, s.width, plane);
                    const Status status = ssim(a, b, QualityOptions{}, &value);
                    out.numbers = {value};
                    return status;
                  }});
  list.push_back({"parallax budget", [=](const Scene& s, Outputs& out) {
                    ParallaxBudget budget;
                    std::int64_t histogram[8] = {};
                    BudgetOptions options;
                    options.histogram_bins = 8;
                    const Status status = parallax_budget(FloatPlane{s.depth.data(), s.width, s.height, s.width}, decoder,
                                                          StereoCamera{0.04, 4.0}, options, &budget, histogram);
                    out.numbers = {budget.min, budget.max, budget.percentile[0], budget.percentile[1]};
                    for (std::int64_t h : histogram) out.numbers.push_back(static_cast<double>(h));
                    return status;
                  }});
  list.push_back({"Image", [](const Scene& s, Outputs& out) {
                    Image image;
                    const Status status = Image::create(s.width, s.height, 3, ColorLayout::planar, &image);
                    out.numbers = {static_cast<double>(image.stride()), image.empty() ? 1.0 : 0.0};
                    return status;
                  }});
  return list;
}

TEST(Memory, EveryByteFromTheHostsAllocatorAndBack) {
  TestAllocator host;  // before `restore`: it outlives the library's last deallocation
  DefaultAllocatorAfter restore;
  release_memory();
  ASSERT_EQ(memory_in_use(), 0u) << "the library holds memory before any call of this test";
  const Allocator a = host.allocator();
  ASSERT_TRUE(set_allocator(&a).ok());
  const Scene scene;
  std::vector<Image> images;
  for (const Scenario& scenario : scenarios()) {
    Outputs out;
    const Status status = scenario.call(scene, out);
    EXPECT_TRUE(status.ok()) << scenario.name << ": " << status.message();
    // What the library holds is exactly what the host's allocator has out.
    EXPECT_EQ(memory_in_use(), host.outstanding()) << scenario.name;
  }
  images.emplace_back(64, 8, 4, ColorLayout::interleaved_rgba);
  ASSERT_FALSE(images.back().empty());
  EXPECT_GT(host.calls(), 10) << "the calls took (almost) nothing from the host's allocator";
  EXPECT_GT(host.outstanding(), 0u) << "nothing cached: scratch should outlive the calls";
  // An Image the caller holds is the library's memory too: set_allocator waits for it.
  release_memory();
  EXPECT_EQ(host.outstanding(), memory_in_use());
  EXPECT_GE(memory_in_use(), 64u * 8 * 4 * sizeof(float)) << "the Image's pixels";
  const Status refused = set_allocator(nullptr);
  EXPECT_EQ(refused.code(), StatusCode::invalid_option) << refused.message();
  EXPECT_NE(std::string(refused.message()).find("bytes"), std::string::npos) << refused.message();
  images.clear();
  EXPECT_EQ(host.outstanding(), 0u) << "release_memory() left memory out";
  EXPECT_EQ(memory_in_use(), 0u);
  for (const std::string& error : host.errors()) ADD_FAILURE() << error;
  EXPECT_TRUE(set_allocator(nullptr).ok());
}

TEST(Memory, ACallWithTheSizesOfAnEarlierOneTakesNothing) {
  TestAllocator host;
  DefaultAllocatorAfter restore;
  release_memory();
  const Allocator a = host.allocator();
  ASSERT_TRUE(set_allocator(&a).ok());
  const Scene scene;
  for (const Scenario& scenario : scenarios()) {
    if (scenario.name == "ssim" || scenario.name == "parallax budget" || scenario.name == "Image") continue;  // per call
    Outputs first, second;
    ASSERT_TRUE(scenario.call(scene, first).ok()) << scenario.name;
    const long before = host.calls();
    ASSERT_TRUE(scenario.call(scene, second).ok()) << scenario.name;
    EXPECT_EQ(host.calls(), before) << scenario.name << ": the second call with the same sizes allocated";
    EXPECT_TRUE(first == second) << scenario.name;
  }
}

TEST(Memory, SetAllocatorRefusedWhileHeldOrRunning) {
  TestAllocator host;
  DefaultAllocatorAfter restore;
  release_memory();
  Allocator half = host.allocator();
  half.deallocate = nullptr;
  EXPECT_EQ(set_allocator(&half).code(), StatusCode::invalid_option);
  const Allocator a = host.allocator();
  ASSERT_TRUE(set_allocator(&a).ok());
  const Scene scene;
  Outputs out;
  ASSERT_TRUE(scenarios()[0].call(scene, out).ok());
  // Scratch is cached: another allocator now would free it with the wrong one.
  const Status held = set_allocator(nullptr);
  EXPECT_EQ(held.code(), StatusCode::invalid_option) << held.message();
  // From inside a running call (a job system's task): refused, naming the running call.
  struct Probe {
    static void run(void* context, int count, void (*task)(void*, int), void* task_context) {
      Status* seen = static_cast<Status*>(context);
      *seen = set_allocator(nullptr);
      for (int i = 0; i < count; ++i) task(task_context, i);
    }
  };
  release_memory();
  Status inside;
  Options options;
  const ParallaxModel model = ParallaxModel::from_stereo(0.04, 4.0, scene.width, EyeDirection::left_to_right);
  ASSERT_TRUE(reproject(scene.floats(), DepthDecoder::linear(), model, options, out.floats(0, scene.width, scene.height),
                        ParallelFor{&inside, Probe::run})
                  .ok());
  EXPECT_EQ(inside.code(), StatusCode::invalid_option) << inside.message();
  EXPECT_NE(std::string(inside.message()).find("running"), std::string::npos) << inside.message();
  release_memory();
  EXPECT_EQ(host.outstanding(), 0u);
  EXPECT_TRUE(set_allocator(nullptr).ok());
}

// A host allocator that ignores the alignment asked for: its block is refused (given back), and
// the call says out of memory rather than using misaligned memory.
TEST(Memory, MisalignedBlocksAreRefused) {
  DefaultAllocatorAfter restore;
  release_memory();
  struct Misaligned {
    static void* allocate(void*, std::size_t size, std::size_t) {
      unsigned char* p = static_cast<unsigned char*>(::operator new(size + 16, std::nothrow));
      return p == nullptr ? nullptr : p + 8;
    }
    static void deallocate(void*, void* pointer, std::size_t, std::size_t) {
      ::operator delete(static_cast<unsigned char*>(pointer) - 8);
    }
  };
  const Allocator a{Misaligned::allocate, Misaligned::deallocate, nullptr};
  ASSERT_TRUE(set_allocator(&a).ok());
  const Scene scene;
  Outputs out;
  const Status status = scenarios()[0].call(scene, out);
  EXPECT_EQ(status.code(), StatusCode::out_of_memory) << status.message();
  EXPECT_EQ(memory_in_use(), 0u);
}

TEST(OutOfMemory, EveryAllocationFailingInTurn) {
  TestAllocator host;
  DefaultAllocatorAfter restore;
  const Scene scene;
  const Allocator a = host.allocator();
  long failed_calls = 0;
  for (const Scenario& scenario : scenarios()) {
    release_memory();
    ASSERT_TRUE(set_allocator(nullptr).ok());
    Outputs expected;
    ASSERT_TRUE(scenario.call(scene, expected).ok()) << scenario.name;
    release_memory();
    // Both kinds of failure: every allocation from the k-th on, and only the k-th.
    for (bool only_one : {false, true}) {
      long k = 1;
      for (;; ++k) {
        release_memory();
        ASSERT_TRUE(set_allocator(&a).ok()) << scenario.name << ", k = " << k;
        host.fail_at(k, only_one);
        Outputs out;
        const Status status = scenario.call(scene, out);
        release_memory();
        EXPECT_EQ(host.outstanding(), 0u) << scenario.name << ", k = " << k << ": memory left out after the failure";
        ASSERT_TRUE(set_allocator(nullptr).ok()) << scenario.name << ", k = " << k;
        if (host.calls() < k) {  // the call needed fewer than k allocations: it never saw a failure
          ASSERT_TRUE(status.ok()) << scenario.name << ", k = " << k << ": " << status.message();
          EXPECT_TRUE(out == expected) << scenario.name << ": a call that never failed gave other bytes";
          break;
        }
        // A failure the call survived is one it could do without (the pool's memory: fewer
        // threads); otherwise it said out of memory.
        if (!status.ok()) {
          ++failed_calls;
          EXPECT_EQ(status.code(), StatusCode::out_of_memory) << scenario.name << ", k = " << k << ": " << status.message();
        } else {
          EXPECT_TRUE(out == expected) << scenario.name << ", k = " << k << ": succeeded past a failure with other bytes";
        }
        Outputs again;
        ASSERT_TRUE(scenario.call(scene, again).ok()) << scenario.name << " after k = " << k;
        EXPECT_TRUE(again == expected) << scenario.name << ": the call after a failure gave other bytes (k = " << k << ")";
        ASSERT_LT(k, 10000) << scenario.name << ": never completed";
      }
      std::printf("%s (%s): %ld allocation(s) failed in turn\n", scenario.name.c_str(),
                  only_one ? "only the k-th" : "the k-th and later", k - 1);
      EXPECT_GT(k, 1) << scenario.name << " allocated nothing: the loop tested no failure";
    }
  }
  EXPECT_GT(failed_calls, 20) << "too few calls returned out_of_memory for this test to mean anything";
  for (const std::string& error : host.errors()) ADD_FAILURE() << error;
}

}  // namespace
}  // namespace reproject
