// Hardening: adversarial depth against every method x every supported instruction set x planar and
// interleaved colour, with every input and output plane placed against a PROT_NONE page, so a read
// (or write) that leaves a row faults instead of passing silently. Four placements:
//  * last_row_tail:  stride == row, the last row ends exactly where a protected page begins;
//  * first_row_head: stride == row, the first row starts exactly where a protected page ends;
//  * every_row_tail / every_row_head: each row on a page pair of its own, ending at (starting after)
//    a protected page, so every row, not only the first or last, is fenced.
// Each run checks: the status is ok (or the documented error), every pixel status is one of the
// four, source_x is finite, each output is what the resolve stage defines for that status (docs/
// docs/BEHAVIOUR.md), output depth is finite wherever the stored values it comes from are, and the
// result equals the scalar reference of the instruction set byte for byte (up to NaN payloads
// where the depth holds NaN).
#include <gtest/gtest.h>
#include <csignal>
#if defined(_WIN32)
#ifndef NOMINMAX
#define NOMINMAX  // windows.h would define min and max as macros
#endif
#include <windows.h>  // VirtualAlloc / VirtualProtect: the guard pages
#else
#include <signal.h>
#include <sys/mman.h>
#include <unistd.h>
#endif

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <functional>
#include <limits>
#include <memory>
#include <ostream>
#include <random>
#include <string>
#include <vector>

#include "kernels/dispatch.hpp"
#include "src/reproject_internal.hpp"
#include "reproject/reproject.hpp"
#include "tests/support/arch_report.hpp"

namespace reproject {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr float kSentinel = -7.25f;
constexpr std::uint8_t kStatusSentinel = 0xAB;
constexpr Method kMethods[] = {Method::scanline, Method::march16, Method::single, Method::secant, Method::exact};

// ---- a fault names the run it happened in ----------------------------------------------------------

char g_current_run[256] = "(no run)";
constexpr char kFaultHead[] = "\n*** hardening: memory fault outside a row (guard page) during run: ";

#if defined(_WIN32)
// Windows: a vectored handler sees the access violation first, writes, and lets it go on to the
// default (the process ends with STATUS_ACCESS_VIOLATION).
LONG CALLBACK on_fault(EXCEPTION_POINTERS* info) {
  if (info->ExceptionRecord->ExceptionCode == EXCEPTION_ACCESS_VIOLATION) {
    std::fputs(kFaultHead, stderr);
    std::fputs(g_current_run, stderr);
    std::fputs("\n", stderr);
  }
  return EXCEPTION_CONTINUE_SEARCH;
}

class FaultReporter : public ::testing::Environment {
 public:
  void SetUp() override { AddVectoredExceptionHandler(1, on_fault); }
};
#else
struct sigaction g_previous_segv;
struct sigaction g_previous_bus;

// Async-signal-safe: write(2) only. Then the previous handler (ASan's, in the sanitizer build, with
// its stack trace; else the default action) takes the re-executed faulting access.
void on_fault(int signal, siginfo_t* info, void*) {
  ssize_t ignored = write(STDERR_FILENO, kFaultHead, sizeof kFaultHead - 1);
  ignored = write(STDERR_FILENO, g_current_run, std::strlen(g_current_run));
  ignored = write(STDERR_FILENO, "\n", 1);
  (void)ignored;
  (void)info;
  sigaction(signal, signal == SIGSEGV ? &g_previous_segv : &g_previous_bus, nullptr);
}

class FaultReporter : public ::testing::Environment {
 public:
  void SetUp() override {
    struct sigaction action {};
    action.sa_sigaction = on_fault;
    action.sa_flags = SA_SIGINFO;
    sigemptyset(&action.sa_mask);
    sigaction(SIGSEGV, &action, &g_previous_segv);
    sigaction(SIGBUS, &action, &g_previous_bus);
  }
};
#endif
const auto* const g_fault_reporter = ::testing::AddGlobalTestEnvironment(new FaultReporter);

void set_run_label(const std::string& label) {
  std::snprintf(g_current_run, sizeof g_current_run, "%s", label.c_str());
}

// ---- planes against protected pages --------------------------------------------------------------

enum class Placement { last_row_tail, first_row_head, every_row_tail, every_row_head };
constexpr Placement kPlacements[] = {Placement::last_row_tail, Placement::first_row_head, Placement::every_row_tail,
                                     Placement::every_row_head};
const char* to_string(Placement p) {
  switch (p) {
    case Placement::last_row_tail: return "last_row_tail";
    case Placement::first_row_head: return "first_row_head";
    case Placement::every_row_tail: return "every_row_tail";
    case Placement::every_row_head: return "every_row_head";
  }
  return "?";
}

std::size_t page_size() {
#if defined(_WIN32)
  static const std::size_t size = [] {
    SYSTEM_INFO info;
    GetSystemInfo(&info);
    return static_cast<std::size_t>(info.dwPageSize);
  }();
#else
  static const std::size_t size = static_cast<std::size_t>(sysconf(_SC_PAGESIZE));
#endif
  return size;
}

// `height` rows of `row` elements of T in an anonymous mapping, fenced by PROT_NONE pages as
// `placement` says. Rows of one plane fit in a page for the every_row placements (asserted).
template <class T>
class GuardedPlane {
 public:
  GuardedPlane(Placement placement, int width, int height, int per_pixel, T fill)
      : width_(width), height_(height), row_(static_cast<std::ptrdiff_t>(width) * per_pixel) {
    const std::size_t page = page_size();
    const std::size_t row_bytes = static_cast<std::size_t>(row_) * sizeof(T);
    const auto pages_for = [page](std::size_t bytes) { return (bytes + page - 1) / page; };
    std::size_t guard_offset = 0;  // first protected page (contiguous placements)
    switch (placement) {
      case Placement::last_row_tail: {
        stride_ = row_;
        const std::size_t bytes = row_bytes * static_cast<std::size_t>(height);
        const std::size_t data_pages = std::max<std::size_t>(1, pages_for(bytes));
        map(data_pages + 1);
        guard_offset = data_pages * page;
        protect(guard_offset);
        data_ = reinterpret_cast<T*>(base_ + guard_offset - bytes);
        break;
      }
      case Placement::first_row_head: {
        stride_ = row_;
        const std::size_t bytes = row_bytes * static_cast<std::size_t>(height);
        map(1 + std::max<std::size_t>(1, pages_for(bytes)));
        protect(0);
        data_ = reinterpret_cast<T*>(base_ + page);
        break;
      }
      case Placement::every_row_tail:
      case Placement::every_row_head: {
        if (row_bytes > page) std::abort();  // the test's own sizes keep rows within a page
        stride_ = static_cast<std::ptrdiff_t>(2 * page / sizeof(T));
        map(2 * static_cast<std::size_t>(height) + 1);
        const bool tail = placement == Placement::every_row_tail;
        // Pages 2y and 2y + 1 hold row y: tail: the row ends page 2y, page 2y + 1 is protected;
        // head: page 2y is protected, the row starts page 2y + 1.
        for (int y = 0; y < height; ++y) protect((2 * static_cast<std::size_t>(y) + (tail ? 1 : 0)) * page);
        protect(2 * static_cast<std::size_t>(height) * page);  // past the last row's page pair
        data_ = reinterpret_cast<T*>(tail ? base_ + page - row_bytes : base_ + page);
        break;
      }
    }
    for (int y = 0; y < height; ++y) std::fill(row(y), row(y) + row_, fill);
  }
  ~GuardedPlane() {
#if defined(_WIN32)
    if (base_ != nullptr) VirtualFree(base_, 0, MEM_RELEASE);
#else
    if (base_ != nullptr) munmap(base_, map_bytes_);
#endif
  }
  GuardedPlane(const GuardedPlane&) = delete;
  GuardedPlane& operator=(const GuardedPlane&) = delete;

  T* row(int y) const { return data_ + static_cast<std::ptrdiff_t>(y) * stride_; }
  std::ptrdiff_t row_elements() const { return row_; }
  int height() const { return height_; }
  PlaneView<T> view() const { return PlaneView<T>{data_, width_, height_, stride_}; }
  PlaneView<const T> cview() const { return PlaneView<const T>{data_, width_, height_, stride_}; }

 private:
  void map(std::size_t pages) {
    map_bytes_ = pages * page_size();
#if defined(_WIN32)
    void* p = VirtualAlloc(nullptr, map_bytes_, MEM_RESERVE | MEM_COMMIT, PAGE_READWRITE);
    if (p == nullptr) std::abort();
#else
    void* p = mmap(nullptr, map_bytes_, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (p == MAP_FAILED) std::abort();
#endif
    base_ = static_cast<char*>(p);
  }
  void protect(std::size_t offset) {
#if defined(_WIN32)
    DWORD old = 0;
    if (!VirtualProtect(base_ + offset, page_size(), PAGE_NOACCESS, &old)) std::abort();
#else
    if (mprotect(base_ + offset, page_size(), PROT_NONE) != 0) std::abort();
#endif
  }

  int width_;
  int height_;
  std::ptrdiff_t row_;
  std::ptrdiff_t stride_ = 0;
  char* base_ = nullptr;
  std::size_t map_bytes_ = 0;
  T* data_ = nullptr;
};

// ---- a frame: depth rows, colour, and guarded source / target views --------------------------------

struct Scene {
  int source_width = 0;
  int height = 0;
  std::vector<float> depth;  // height x source_width, row-major
  float at(int x, int y) const { return depth[static_cast<std::size_t>(y) * source_width + x]; }
};

// Colour of channel c at source column x, row y: distinct and in [0, 1].
float color_value(int c, int x, int y) { return static_cast<float>((x * 7 + y * 13 + c * 5) % 64) / 64.0f; }

struct GuardedSource {
  std::vector<std::unique_ptr<GuardedPlane<float>>> color;
  std::unique_ptr<GuardedPlane<float>> depth;
  SourceView view;

  GuardedSource(const Scene& scene, bool interleaved, Placement placement) {
    const int w = scene.source_width;
    const int h = scene.height;
    const int planes = interleaved ? 1 : 3;
    for (int p = 0; p < planes; ++p) {
      color.push_back(std::make_unique<GuardedPlane<float>>(placement, w, h, interleaved ? 4 : 1, 0.0f));
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
          if (interleaved) {
            for (int c = 0; c < 4; ++c) color.back()->row(y)[4 * x + c] = color_value(c, x, y);
          } else {
            color.back()->row(y)[x] = color_value(p, x, y);
          }
        }
      view.color.plane[p] = color.back()->cview();
    }
    view.color.layout = interleaved ? ColorLayout::interleaved_rgba : ColorLayout::planar;
    view.color.channels = interleaved ? 4 : 3;
    depth = std::make_unique<GuardedPlane<float>>(placement, w, h, 1, 0.0f);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) depth->row(y)[x] = scene.at(x, y);
    view.depth = depth->cview();
  }
};

struct GuardedTarget {
  std::vector<std::unique_ptr<GuardedPlane<float>>> color;
  std::unique_ptr<GuardedPlane<float>> depth;
  std::unique_ptr<GuardedPlane<std::uint8_t>> status;
  std::unique_ptr<GuardedPlane<float>> source_x;
  TargetView view;
  int channels;
  bool interleaved;

  GuardedTarget(int width, int height, bool interleaved_rgba, Placement placement)
      : channels(interleaved_rgba ? 4 : 3), interleaved(interleaved_rgba) {
    for (int p = 0; p < (interleaved ? 1 : 3); ++p) {
      color.push_back(std::make_unique<GuardedPlane<float>>(placement, width, height, interleaved ? 4 : 1, kSentinel));
      view.color.plane[p] = color.back()->view();
    }
    view.color.layout = interleaved ? ColorLayout::interleaved_rgba : ColorLayout::planar;
    view.color.channels = channels;
    depth = std::make_unique<GuardedPlane<float>>(placement, width, height, 1, kSentinel);
    status = std::make_unique<GuardedPlane<std::uint8_t>>(placement, width, height, 1, kStatusSentinel);
    source_x = std::make_unique<GuardedPlane<float>>(placement, width, height, 1, kSentinel);
    view.depth = depth->view();
    view.status = status->view();
    view.source_x = source_x->view();
  }
  float color_at(int c, int t, int y) const {
    return interleaved ? color[0]->row(y)[4 * t + c] : color[static_cast<std::size_t>(c)]->row(y)[t];
  }
};

bool same_float_rows(const GuardedPlane<float>& x, const GuardedPlane<float>& y, bool nan_equal, std::string* why) {
  for (int r = 0; r < x.height(); ++r)
    for (std::ptrdiff_t i = 0; i < x.row_elements(); ++i) {
      const float a = x.row(r)[i];
      const float b = y.row(r)[i];
      if (std::memcmp(&a, &b, sizeof a) == 0 || (nan_equal && std::isnan(a) && std::isnan(b))) continue;
      char text[128];
      std::snprintf(text, sizeof text, "row %d element %td: %a vs reference %a", r, i, static_cast<double>(a),
                    static_cast<double>(b));
      *why = text;
      return false;
    }
  return true;
}

// Byte-identical outputs (any NaN equal to any NaN when `nan_equal`).
bool same_outputs(const GuardedTarget& x, const GuardedTarget& y, bool nan_equal, std::string* why) {
  for (std::size_t p = 0; p < x.color.size(); ++p)
    if (!same_float_rows(*x.color[p], *y.color[p], nan_equal, why)) return (*why = "colour " + *why), false;
  if (!same_float_rows(*x.depth, *y.depth, nan_equal, why)) return (*why = "depth " + *why), false;
  if (!same_float_rows(*x.source_x, *y.source_x, nan_equal, why)) return (*why = "source_x " + *why), false;
  for (int r = 0; r < x.status->height(); ++r)
    if (std::memcmp(x.status->row(r), y.status->row(r), static_cast<std::size_t>(x.status->row_elements())) != 0)
      return (*why = "status row " + std::to_string(r)), false;
  return true;
}

// ---- the adversarial cases ---------------------------------------------------------------------------

struct Case {
  std::string name;
  Scene scene;
  DepthDecoder decoder;
  ParallaxModel model;
  int guard = 0;
  StatusCode expected = StatusCode::ok;
  // Extra per-case expectation on a successful run; empty when the generic checks say it all.
  std::function<void(const Case&, const Options&, const GuardedTarget&, std::string*)> expect;
};

Scene make_scene(int width, int height, const std::function<float(int x, int y)>& value) {
  Scene scene;
  scene.source_width = width;
  scene.height = height;
  scene.depth.resize(static_cast<std::size_t>(width) * height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) scene.depth[static_cast<std::size_t>(y) * width + x] = value(x, y);
  return scene;
}

// An ordinary scene for `decoder`: slanted planes and steps between 1.5 and 12 near planes.
float ordinary(const DepthDecoder& decoder, int x, int y) {
  const double n = decoder.encoding() == DepthEncoding::linear ? 0.5 : decoder.near_plane();
  const double z = n * (1.5 + ((x / 7 + y) % 3) * 4.0 + 0.1 * (x % 7));
  return decoder.encode(z);
}

// Output x of a flat row at parallax p: t' - p. The methods' intersections may round.
void expect_flat_row(int y, float p, const Case& c, const GuardedTarget& out, std::string* why) {
  const int tw = c.scene.source_width - 2 * c.guard;
  for (int t = 0; t < tw; ++t) {
    const float want = static_cast<float>(t + c.guard) - p;
    const float got = out.source_x->row(y)[t];
    if (!(std::fabs(got - want) <= 1e-4f * std::max(1.0f, std::fabs(want)))) {
      char text[160];
      std::snprintf(text, sizeof text, "row %d t %d: source_x %g, expected the flat row's %g (parallax %g)", y, t,
                    static_cast<double>(got), static_cast<double>(want), static_cast<double>(p));
      *why = text;
      return;
    }
  }
}

// The parallax the plan gives a stored value (docs/BEHAVIOUR.md), in double: NaN and farther than
// infinity -> p_far; nearer than L -> s L.
float defined_parallax(const Case& c, float d) {
  const double L = c.scene.source_width + 2.0;
  const double s = c.model.b > 0.0f ? 1.0 : -1.0;
  const double a = std::clamp(static_cast<double>(c.model.a), -L, L);
  const double w = c.decoder.is_affine() ? static_cast<double>(c.decoder.A()) * d + c.decoder.B() : 1.0 / d;
  const double p = static_cast<double>(c.model.a) + static_cast<double>(c.model.b) * w;
  if (!(s * p >= s * a)) return static_cast<float>(a);
  if (s * p > L) return static_cast<float>(s * L);
  return static_cast<float>(p);
}

std::vector<Case> adversarial_cases() {
  std::vector<Case> cases;
  const DepthDecoder standard = DepthDecoder::from_near_far(DepthEncoding::standard, 0.5, 50.0);
  const int W = 67;  // several 16-lane vectors and a tail of every vector width
  const int H = 3;
  for (EyeDirection dir : {EyeDirection::centre_to_right, EyeDirection::right_to_left}) {
    const std::string d = dir == EyeDirection::centre_to_right ? "/b_negative" : "/b_positive";
    const ParallaxModel model = ParallaxModel::from_stereo(0.05, 2.0, W, dir);

    {  // near and far alternating every pixel: a wall and a fold at every column
      Case c;
      c.name = "alternating_near_far" + d;
      c.decoder = standard;
      c.model = model;
      const float n = standard.encode(0.5), f = standard.encode(50.0);
      c.scene = make_scene(W, H, [=](int x, int y) { return (x + y) % 2 ? n : f; });
      cases.push_back(c);
      c.name = "alternating_near_far_guard" + d;
      c.guard = 5;
      cases.push_back(c);
    }
    {  // rows entirely NaN between ordinary rows: each NaN row is flat at infinity, p = p_far = a
      Case c;
      c.name = "all_nan_rows" + d;
      c.decoder = standard;
      c.model = model;
      c.scene = make_scene(W, 4, [&](int x, int y) { return y % 2 == 0 ? kNaN : ordinary(standard, x, y); });
      c.expect = [](const Case& k, const Options& o, const GuardedTarget& out, std::string* why) {
        const float L = static_cast<float>(k.scene.source_width + 2);
        const float p_far = std::clamp(k.model.a, -L, L);
        (void)o;  // a NaN row is as far as anything gets: never clipped, whatever the near limit
        for (int y = 0; y < k.scene.height; y += 2) {
          expect_flat_row(y, p_far, k, out, why);
          if (!why->empty()) return;
          // NaN stored values propagate to the output depth of every written pixel.
          for (int t = 0; t < k.scene.source_width - 2 * k.guard; ++t) {
            const float depth = out.depth->row(y)[t];
            if (!(std::isnan(depth) || depth == kSentinel)) {
              *why = "row " + std::to_string(y) + " t " + std::to_string(t) + ": depth " + std::to_string(depth) +
                     " from an all-NaN row";
              return;
            }
          }
        }
      };
      cases.push_back(c);
      c.name = "all_nan_frame" + d;
      c.scene = make_scene(W, 2, [](int, int) { return kNaN; });
      cases.push_back(c);
    }
    // Exactly at near and exactly at far, for every encoding; flat rows of either, then blocks.
    const DepthDecoder decoders[] = {
        DepthDecoder::linear(),
        standard,
        DepthDecoder::from_near_far(DepthEncoding::gl_ndc, 0.5, 50.0),
        DepthDecoder::from_near_far(DepthEncoding::reversed, 0.5, 50.0),
        DepthDecoder::from_near_far(DepthEncoding::reversed_infinite, 0.5, 0.0),
        DepthDecoder::from_near_far(DepthEncoding::infinite, 0.5, 0.0),
    };
    for (const DepthDecoder& decoder : decoders) {
      Case c;
      c.name = std::string("exactly_near_and_far/") + to_string(decoder.encoding()) + d;
      c.decoder = decoder;
      c.model = model;
      const bool linear = decoder.encoding() == DepthEncoding::linear;
      const float n = linear ? 0.5f : decoder.encode(decoder.near_plane());
      const float f = linear ? 50.0f : decoder.encode(decoder.far_plane());
      c.scene = make_scene(W, 3, [=](int x, int y) { return y == 0 ? n : y == 1 ? f : ((x / 5) % 2 ? n : f); });
      c.expect = [](const Case& k, const Options& o, const GuardedTarget& out, std::string* why) {
        if (o.max_negative_parallax) return;
        for (int y = 0; y < 2; ++y) {
          expect_flat_row(y, defined_parallax(k, k.scene.at(0, y)), k, out, why);
          if (!why->empty()) return;
        }
      };
      cases.push_back(c);
    }
    {  // parallax wider than the image, both at infinity and near
      Case c;
      c.name = "parallax_wider_than_image" + d;
      c.decoder = DepthDecoder::linear();
      const float sign = dir == EyeDirection::centre_to_right ? 1.0f : -1.0f;
      c.model = ParallaxModel{sign * 2.5f * W, -sign * 6.0f * W};
      c.scene = make_scene(W, H, [](int x, int y) { return 1.0f + static_cast<float>((x * 3 + y) % 5); });
      cases.push_back(c);
      c.name = "parallax_wider_than_image_far_only" + d;
      c.model = ParallaxModel{sign * 3.0f * W, 0.0f};
      cases.push_back(c);
    }
    {  // separation 0: a = b = 0, the identity
      Case c;
      c.name = "separation_zero" + d;
      c.decoder = standard;
      c.model = ParallaxModel::from_stereo(0.0, 2.0, W, dir);
      c.scene = make_scene(W, H, [&](int x, int y) { return ordinary(standard, x, y); });
      c.expect = [](const Case& k, const Options&, const GuardedTarget& out, std::string* why) {
        for (int y = 0; y < k.scene.height; ++y) {
          for (int t = 0; t < k.scene.source_width; ++t) {
            const bool same = out.source_x->row(y)[t] == static_cast<float>(t) && out.status->row(y)[t] == 0 &&
                              out.color_at(0, t, y) == color_value(0, t, y) && out.depth->row(y)[t] == k.scene.at(t, y);
            if (!same) {
              *why = "not the identity at row " + std::to_string(y) + " t " + std::to_string(t);
              return;
            }
          }
        }
      };
      cases.push_back(c);
    }
    {  // huge convergence: b ~ 1e30, every finite depth lands beyond L (off the row)
      Case c;
      c.name = "huge_convergence" + d;
      c.decoder = standard;
      c.model = ParallaxModel::from_stereo(0.05, 1e30, W, dir);
      c.scene = make_scene(W, H, [&](int x, int y) { return ordinary(standard, x, y); });
      c.expect = [](const Case& k, const Options& o, const GuardedTarget& out, std::string* why) {
        if (o.max_negative_parallax) return;
        for (int y = 0; y < k.scene.height; ++y)
          for (int t = 0; t < k.scene.source_width - 2 * k.guard; ++t)
            if (out.status->row(y)[t] != 2) {
              *why = "row " + std::to_string(y) + " t " + std::to_string(t) + ": status " +
                     std::to_string(out.status->row(y)[t]) + ", expected outside (parallax beyond L)";
              return;
            }
      };
      cases.push_back(c);
      // A convergence whose b overflows float: the model is refused.
      Case refused = c;
      refused.name = "convergence_overflowing_float" + d;
      refused.model = ParallaxModel::from_stereo(0.05, 1e300, W, dir);
      refused.expected = StatusCode::invalid_model;
      refused.expect = nullptr;
      cases.push_back(refused);
    }
    {  // width 1, and a 1-column target inside a guard band
      Case c;
      c.name = "width_one" + d;
      c.decoder = standard;
      c.model = ParallaxModel::from_stereo(0.05, 2.0, 1, dir);
      c.scene = make_scene(1, H, [&](int, int y) { return y == 1 ? kNaN : ordinary(standard, 0, y); });
      cases.push_back(c);
      c.name = "width_one_target_in_guard_band" + d;
      c.guard = 2;
      c.scene = make_scene(5, H, [&](int x, int y) { return ordinary(standard, x, y); });
      cases.push_back(c);
    }
    {  // decoded parallax overflowing float: linear depth of a denormal (1/d = inf), a slope that
       // overflows p = a + b w, and stored values of +-FLT_MAX for an affine encoding
      Case c;
      c.name = "decoded_parallax_overflows/reciprocal" + d;
      c.decoder = DepthDecoder::linear();
      const float sign = dir == EyeDirection::centre_to_right ? 1.0f : -1.0f;
      c.model = ParallaxModel{sign * 3.0f, -sign * FLT_MAX / 4.0f};
      const float tiny = std::numeric_limits<float>::denorm_min();
      c.scene = make_scene(W, H, [=](int x, int y) {
        return (x + y) % 4 == 0 ? tiny : (x % 4 == 1 ? 0.25f : (x % 4 == 2 ? FLT_MAX : 1e-30f));
      });
      cases.push_back(c);
      c.name = "decoded_parallax_overflows/affine" + d;
      c.decoder = standard;
      c.model = model;
      c.scene = make_scene(W, H, [&](int x, int y) {
        return (x + y) % 3 == 0 ? FLT_MAX : ((x + y) % 3 == 1 ? -FLT_MAX : ordinary(standard, x, y));
      });
      cases.push_back(c);
    }
    // Rows exactly as wide as one or several vectors: a full-width load that ends at the row's
    // last element must not take one more (the every_row_tail placement faults on it).
    for (int width : {4, 8, 16, 64}) {
      Case c;
      c.name = "vector_multiple_width_" + std::to_string(width) + d;
      c.decoder = standard;
      c.model = ParallaxModel::from_stereo(0.05, 2.0, width, dir);
      const float n = standard.encode(0.5), f = standard.encode(50.0);
      c.scene = make_scene(width, H, [=](int x, int y) { return y == 1 ? ((x / 3) % 2 ? n : f) : ordinary(standard, x, y); });
      cases.push_back(c);
    }
    {  // every non-finite and out-of-range kind at once
      Case c;
      c.name = "non_finite_mix" + d;
      c.decoder = standard;
      c.model = model;
      const float kinds[] = {kNaN, kInf, -kInf, -1.0f, -0.0f, 0.0f, std::numeric_limits<float>::denorm_min(), 1e30f, 2.0f};
      c.scene = make_scene(W, H, [&](int x, int y) {
        return (x * 5 + y) % 3 == 0 ? kinds[(x + y) % 9] : ordinary(standard, x, y);
      });
      cases.push_back(c);
    }
  }
  return cases;
}

// A convergence whose b is a valid float but whose product with the decoder's slope is not: the
// plan folds the decode into b A and a + b B, which overflow float. Unclamped, fma(+-inf, d, -+inf)
// would be NaN for every stored value and the frame would come out as if at infinity (a plain
// shift by a); the true parallax is far beyond L, so every pixel must be outside.
Case decode_coefficients_overflow_case() {
  const int W = 67;
  Case c;
  c.name = "decode_coefficients_overflow";
  c.decoder = DepthDecoder::from_near_far(DepthEncoding::standard, 0.01, 100.0);  // A ~ -100, B = 100
  c.model = ParallaxModel::from_stereo(0.05, 1e37, W, EyeDirection::centre_to_right);  // b ~ -1.7e37
  c.scene = make_scene(W, 3, [&](int x, int y) { return ordinary(c.decoder, x, y); });
  c.expect = [](const Case& k, const Options& o, const GuardedTarget& out, std::string* why) {
    if (o.max_negative_parallax) return;
    for (int y = 0; y < k.scene.height; ++y)
      for (int t = 0; t < k.scene.source_width - 2 * k.guard; ++t)
        if (out.status->row(y)[t] != 2) {
          *why = "row " + std::to_string(y) + " t " + std::to_string(t) + ": status " +
                 std::to_string(out.status->row(y)[t]) + ", expected outside (parallax beyond L)";
          return;
        }
  };
  return c;
}

// ---- one run and its checks --------------------------------------------------------------------------

// The options of each placement, so that the four placements also cover the options' branches.
Options options_for(Method method, int variant, int guard) {
  Options o;
  o.method = method;
  o.guard = guard;
  switch (variant) {
    case 0: o.threads = 1; break;
    case 1:
      o.threads = 2;
      o.hole_fill = HoleFill::foreground;
      o.edge = EdgeMode::none;
      o.max_negative_parallax = 1.5f;
      break;
    case 2:
      o.threads = 0;
      o.hole_fill = HoleFill::none;
      o.edge = EdgeMode::mirror;
      o.probe_parallax = -4.0f;
      break;
    default:
      o.threads = 1;
      o.edge = EdgeMode::black;
      o.march_steps = 5;
      o.secant_max_steps = 3;
      o.hole_threshold = 0.0f;
      break;
  }
  return o;
}

float lerp_color(const Case& c, int channel, float x, int y) {
  const int last = c.scene.source_width - 1;
  const int j0 = static_cast<int>(std::floor(x));
  const int j1 = std::min(j0 + 1, last);
  const float c0 = color_value(channel, j0, y);
  return c0 + (x - static_cast<float>(j0)) * (color_value(channel, j1, y) - c0);
}

// Output depth is defined (finite) when the stored values it may come from decode and
// interpolate without overflow.
bool depth_defined_near(const Case& c, float x, int y) {
  const int last = c.scene.source_width - 1;
  const float xc = std::clamp(x, 0.0f, static_cast<float>(last));
  const int j = static_cast<int>(std::floor(xc));
  for (int k = std::max(0, j - 1); k <= std::min(last, j + 2); ++k) {
    const float d = c.scene.at(k, y);
    if (!std::isfinite(d) || std::fabs(d) > 1e30f) return false;
    if (!c.decoder.is_affine() && !(d >= 1e-30f)) return false;
  }
  return true;
}

// The resolve stage's definition, per pixel, from the output status and source_x.
void check_pixels(const Case& c, const Options& o, const GuardedTarget& out, std::string* why) {
  const int tw = c.scene.source_width - 2 * c.guard;
  const float last = static_cast<float>(c.scene.source_width - 1);
  char text[200];
  for (int y = 0; y < c.scene.height; ++y) {
    for (int t = 0; t < tw; ++t) {
      const int status = out.status->row(y)[t];
      const float x = out.source_x->row(y)[t];
      auto fail = [&](const char* what) {
        std::snprintf(text, sizeof text, "row %d t %d: %s (status %d, source_x %g)", y, t, what, status,
                      static_cast<double>(x));
        *why = text;
      };
      if (status > 3) return fail("status is not one of the four");
      if (!std::isfinite(x)) return fail("source_x is not finite");
      const bool written = status == 0 || status == 3 || (status == 2 && o.edge != EdgeMode::none) ||
                           (status == 1 && o.hole_fill != HoleFill::none);
      for (int ch = 0; ch < out.channels; ++ch) {
        const float v = out.color_at(ch, t, y);
        if (!written) {
          if (std::memcmp(&v, &kSentinel, sizeof v) != 0) return fail("colour written where it must not be");
          continue;
        }
        if (!std::isfinite(v)) return fail("colour is not finite");
        switch (status) {
          case 0:
            if (!(x >= 0.0f && x <= last)) return fail("a hit off the row");
            if (!(std::fabs(v - lerp_color(c, ch, x, y)) <= 1e-5f)) return fail("hit colour is not the source at x");
            break;
          case 1: {
            if (!(x >= 0.0f && x <= last)) return fail("a hole off the row");
            const int j = static_cast<int>(std::floor(x));
            const int j1 = std::min(j + 1, c.scene.source_width - 1);
            if (v != color_value(ch, j, y) && v != color_value(ch, j1, y)) return fail("hole colour is not a wall endpoint's");
            break;
          }
          case 2: {
            if (!(x < 0.0f || x > last)) return fail("outside inside the row");
            const int edge = x < 0.0f ? 0 : c.scene.source_width - 1;
            if (o.edge == EdgeMode::black) {
              if (v != 0.0f) return fail("outside colour is not black");
            } else if (o.edge == EdgeMode::mirror) {
              const float reflected = std::clamp(x < 0.0f ? -x : (last - x) + last, 0.0f, last);
              if (!(std::fabs(v - lerp_color(c, ch, reflected, y)) <= 1e-5f))
                return fail("outside colour is not the source at the reflected x");
            } else if (v != color_value(ch, edge, y)) {
              return fail("outside colour is not the edge pixel's");
            }
            break;
          }
          default:
            if (!(std::fabs(v - lerp_color(c, ch, std::clamp(x, 0.0f, last), y)) <= 1e-5f))
              return fail("clipped colour is not the source at the clamped x");
            break;
        }
      }
      const float depth = out.depth->row(y)[t];
      if (!written && std::memcmp(&depth, &kSentinel, sizeof depth) != 0) return fail("depth written where it must not be");
      // Where the depth was read: x, or its reflection for a mirrored outside pixel.
      const float read_x = status == 2 && o.edge == EdgeMode::mirror ? (x < 0.0f ? -x : (last - x) + last) : x;
      if (written && depth_defined_near(c, read_x, y) && !std::isfinite(depth))
        return fail("depth not finite from finite stored values");
    }
  }
}

bool all_depth_finite(const Scene& scene) {
  for (float d : scene.depth)
    if (!std::isfinite(d)) return false;
  return true;
}

std::vector<Arch> supported_arches() {
  std::vector<Arch> arches;
  for (int a = 0; a < kArchCount; ++a)
    if (arch_supported(static_cast<Arch>(a))) arches.push_back(static_cast<Arch>(a));
  return arches;
}

// The case with the model mirrored (a pair's left eye from a centre_to_right model).
Case mirror(const Case& c) {
  Case m = c;
  m.model = ParallaxModel{-c.model.a, -c.model.b};
  return m;
}

// A caller's job system that runs the tasks in reverse order on the calling thread ("any order").
void reversed_jobs(void*, int count, void (*task)(void*, int), void* task_context) {
  for (int i = count - 1; i >= 0; --i) task(task_context, i);
}

// Every method x supported instruction set x layout x placement of one case.
void run_case(const Case& c) {
  const bool finite = all_depth_finite(c.scene);
  const int tw = c.scene.source_width - 2 * c.guard;
  int runs = 0;
  for (Arch arch : supported_arches()) {
    for (Method method : kMethods) {
      for (bool interleaved : {false, true}) {
        for (int variant = 0; variant < 4; ++variant) {
          const Placement placement = kPlacements[variant];
          const std::string label = c.name + " " + to_string(method) + " " + to_string(arch) + " " +
                                    (interleaved ? "interleaved" : "planar") + " " + to_string(placement);
          SCOPED_TRACE(label);
          set_run_label(label);
          Options options = options_for(method, variant, c.guard);
          options.arch = arch;
          const GuardedSource source(c.scene, interleaved, placement);
          GuardedTarget out(tw, c.scene.height, interleaved, placement);
          const Status status = reproject::reproject(source.view, c.decoder, c.model, options, out.view);
          ++runs;
          ASSERT_EQ(status.code(), c.expected) << status.message();
          if (!status.ok()) continue;
          std::string why;
          check_pixels(c, options, out, &why);
          ASSERT_EQ(why, "") << "the resolve stage's definition";
          if (c.expect) {
            c.expect(c, options, out, &why);
            ASSERT_EQ(why, "") << "the case's defined output";
          }
          // The scalar reference of this instruction set, on the same guarded input.
          GuardedTarget reference(tw, c.scene.height, interleaved, placement);
          set_run_label(label + " (scalar reference)");
          ASSERT_TRUE(detail::reproject_with(detail::reference_kernels(arch), source.view, c.decoder, c.model, options,
                                             reference.view)
                          .ok());
          ASSERT_TRUE(same_outputs(out, reference, !finite, &why)) << "differs from the scalar reference: " << why;

          // The other entry points on the same guarded input: a pair (its right eye is this call;
          // its left eye mirrors the model) and a caller's job system.
          if (placement == Placement::every_row_tail) {
            GuardedTarget left(tw, c.scene.height, interleaved, placement);
            GuardedTarget right(tw, c.scene.height, interleaved, placement);
            set_run_label(label + " (reproject_pair)");
            ASSERT_TRUE(reproject_pair(source.view, c.decoder, c.model, options, left.view, right.view).ok());
            ASSERT_TRUE(same_outputs(right, out, false, &why)) << "the pair's right eye differs: " << why;
            const Case mirrored = mirror(c);
            check_pixels(mirrored, options, left, &why);
            ASSERT_EQ(why, "") << "the pair's left eye";
          } else if (placement == Placement::first_row_head) {
            GuardedTarget jobs_out(tw, c.scene.height, interleaved, placement);
            set_run_label(label + " (ParallelFor)");
            ASSERT_TRUE(reproject::reproject(source.view, c.decoder, c.model, options, jobs_out.view,
                                             ParallelFor{nullptr, reversed_jobs})
                            .ok());
            ASSERT_TRUE(same_outputs(jobs_out, out, false, &why)) << "the ParallelFor call differs: " << why;
          }
        }
      }
    }
  }
  set_run_label("(no run)");
  EXPECT_GT(runs, 0);
}

class Adversarial : public ::testing::TestWithParam<Case> {};

TEST_P(Adversarial, EveryMethodArchLayoutAndPlacement) { run_case(GetParam()); }

// gtest prints a parameter that fails: its name, not its bytes.
void PrintTo(const Case& c, std::ostream* os) { *os << c.name; }

// b A and a + b B overflow float: the plan clamps them, so ordinary depths still decode to
// parallax beyond L (every pixel outside), not to NaN ("infinitely far").
TEST(HardeningOverflow, DecodeCoefficientsOverflowIsNotInfinitelyFar) {
  run_case(decode_coefficients_overflow_case());
}

INSTANTIATE_TEST_SUITE_P(Hardening, Adversarial, ::testing::ValuesIn(adversarial_cases()),
                         [](const ::testing::TestParamInfo<Case>& info) {
                           std::string name = info.param.name;
                           for (char& ch : name)
                             if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
                           return name;
                         });

// The instruction sets this run covers, in the log (an unsupported one is skipped, not hidden).
TEST(HardeningArches, ReportSupported) {
  std::printf("%s\n", arch_report("adversarial").c_str());
  EXPECT_TRUE(arch_supported(Arch::scalar));
  EXPECT_EQ(supported_arches().front(), Arch::scalar);
}

// The guard pages work: a read one element past the last row faults (the harness itself is sound).
TEST(HardeningGuardPages, ReadPastTheRowFaults) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  for (Placement placement : kPlacements) {
    GuardedPlane<float> plane(placement, 13, 3, 1, 1.0f);
    const bool tail = placement == Placement::last_row_tail || placement == Placement::every_row_tail;
    const float* probe = tail ? plane.row(2) + 13 : plane.row(0) - 1;
    EXPECT_DEATH(
        {
          signal(SIGSEGV, SIG_DFL);
          volatile float v = *probe;
          (void)v;
        },
        "")
        << to_string(placement);
    if (placement == Placement::every_row_tail) {
      const float* middle = plane.row(0) + 13;
      EXPECT_DEATH(
          {
            signal(SIGSEGV, SIG_DFL);
            volatile float v = *middle;
            (void)v;
          },
          "");
    }
  }
}

}  // namespace
}  // namespace reproject
