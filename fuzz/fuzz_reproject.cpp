// libFuzzer harness for the public entry points (reproject, its ParallelFor overload and
// reproject_pair). The fuzzer picks sizes, strides, guard, layout, which outputs exist, the
// decoder, the parallax model, every option (valid or not), the instruction set, the thread
// count, and the depth values (raw bit patterns, or a table of awkward ones: NaN, +-Inf,
// negative, denormal, huge, exactly near and far).
//
// Every plane is its own heap block of exactly the size its rows span, with the gaps between rows
// (stride - row) poisoned for ASan, so any read or write outside a row is reported, not only one
// past the last row. What is checked, besides "no crash, no sanitizer report":
//  * the returned code is a known StatusCode and its message is non-empty;
//  * a call that fails writes nothing;
//  * per pixel: status is one of the four, source_x is finite and agrees with the status, colour
//    is written exactly where the options say it is, and is finite; output depth is finite for
//    depth inside the decoder's range;
//  * the result does not depend on the entry point or the thread count: it equals
//    detail::reproject_with() on the same kernels, and reproject_pair() equals two single calls;
//  * for every instruction set this CPU has, the SIMD kernels equal their scalar reference
//    (detail::reference_kernels) byte for byte when the depth is finite, and up to NaN payloads
//    otherwise.
// A failed check prints what differed and aborts, so libFuzzer keeps the input.
#include <fuzzer/FuzzedDataProvider.h>
#include <sanitizer/asan_interface.h>

#include <cfloat>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <memory>
#include <vector>

#include "kernels/dispatch.hpp"
#include "src/reproject_internal.hpp"
#include "reproject/reproject.hpp"
#include "tests/support/arch_report.hpp"

namespace {

using namespace reproject;

[[noreturn]] void fail(const char* what, int x = -1, int y = -1) {
  std::fprintf(stderr, "fuzz_reproject: check failed: %s (x %d, y %d)\n", what, x, y);
  std::abort();
}
#define CHECK(condition)              \
  do {                                \
    if (!(condition)) fail(#condition); \
  } while (0)
// The same, naming the pixel.
#define CHECK_AT(condition, x, y)             \
  do {                                        \
    if (!(condition)) fail(#condition, x, y); \
  } while (0)

constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

// A plane in a heap block of exactly (height - 1) * stride + row elements (row = width * per_pixel),
// the gaps between rows poisoned: only the rows themselves are addressable.
template <class T>
class Plane {
 public:
  Plane() = default;
  Plane(int width, int height, int per_pixel, int stride_extra, T fill)
      : width_(width), height_(height), row_(static_cast<std::ptrdiff_t>(width) * per_pixel),
        stride_(row_ + stride_extra) {
    const std::ptrdiff_t count = height > 0 && width > 0 ? (height - 1) * stride_ + row_ : 0;
    size_ = static_cast<std::size_t>(count);
    if (size_ == 0) return;
    data_.reset(new T[size_]);
    for (std::size_t i = 0; i < size_; ++i) data_[i] = fill;
    for (int y = 0; y + 1 < height; ++y) ASAN_POISON_MEMORY_REGION(data_.get() + y * stride_ + row_, stride_extra * sizeof(T));
  }
  ~Plane() {
    if (data_) ASAN_UNPOISON_MEMORY_REGION(data_.get(), size_ * sizeof(T));
  }
  Plane(Plane&& other) noexcept = default;
  Plane& operator=(Plane&& other) noexcept = default;

  T* data() const { return data_.get(); }
  // Null for an empty plane (no arithmetic on a null pointer).
  T* row(int y) const { return data_ ? data_.get() + y * stride_ : nullptr; }
  std::ptrdiff_t row_elements() const { return row_; }
  PlaneView<T> view() const { return PlaneView<T>{data_.get(), width_, height_, stride_}; }
  PlaneView<const T> cview() const { return PlaneView<const T>{data_.get(), width_, height_, stride_}; }
  int height() const { return height_; }

 private:
  int width_ = 0;
  int height_ = 0;
  std::ptrdiff_t row_ = 0;
  std::ptrdiff_t stride_ = 0;
  std::size_t size_ = 0;
  std::unique_ptr<T[]> data_;
};

// Row bytes of two planes of the same shape equal; `nan_equal`: any NaN equals any NaN (payloads
// and signs of NaN are not part of the contract for non-finite input).
bool same_rows(const Plane<float>& x, const Plane<float>& y, bool nan_equal) {
  for (int r = 0; r < x.height(); ++r) {
    const float* a = x.row(r);
    const float* b = y.row(r);
    for (std::ptrdiff_t i = 0; i < x.row_elements(); ++i) {
      if (std::memcmp(&a[i], &b[i], sizeof(float)) == 0) continue;
      if (nan_equal && std::isnan(a[i]) && std::isnan(b[i])) continue;
      std::fprintf(stderr, "fuzz_reproject: row %d element %td: %a vs %a\n", r, i, static_cast<double>(a[i]),
                   static_cast<double>(b[i]));
      return false;
    }
  }
  return true;
}
bool same_rows(const Plane<std::uint8_t>& x, const Plane<std::uint8_t>& y, bool) {
  for (int r = 0; r < x.height(); ++r)
    if (x.row_elements() > 0 && std::memcmp(x.row(r), y.row(r), static_cast<std::size_t>(x.row_elements())) != 0)
      return false;
  return true;
}

constexpr float kSentinel = -7.25f;
constexpr std::uint8_t kStatusSentinel = 0xAB;

// What the fuzzer chose about the frame's buffers.
struct Shape {
  int source_width = 0;
  int target_width = 0;  // source_width - 2 guard, when that is positive
  int height = 0;
  bool interleaved = false;
  int channels = 1;
  int stride_extra[4] = {0, 0, 0, 0};  // depth, colour, target colour, target depth/status/x
  bool with_depth = true;
  bool with_status = true;
  bool with_source_x = true;
};

struct Source {
  std::vector<Plane<float>> color;
  Plane<float> depth;
  SourceView view;
};

struct Target {
  std::vector<Plane<float>> color;
  Plane<float> depth;
  Plane<std::uint8_t> status;
  Plane<float> source_x;
  TargetView view;

  explicit Target(const Shape& s) {
    const int w = s.target_width;
    const int planes = s.interleaved ? 1 : s.channels;
    for (int c = 0; c < planes; ++c) color.emplace_back(w, s.height, s.interleaved ? 4 : 1, s.stride_extra[2], kSentinel);
    for (int c = 0; c < planes; ++c) view.color.plane[c] = color[static_cast<std::size_t>(c)].view();
    view.color.layout = s.interleaved ? ColorLayout::interleaved_rgba : ColorLayout::planar;
    view.color.channels = s.channels;
    if (s.with_depth) {
      depth = Plane<float>(w, s.height, 1, s.stride_extra[3], kSentinel);
      view.depth = depth.view();
    }
    if (s.with_status) {
      status = Plane<std::uint8_t>(w, s.height, 1, s.stride_extra[3], kStatusSentinel);
      view.status = status.view();
    }
    if (s.with_source_x) {
      source_x = Plane<float>(w, s.height, 1, s.stride_extra[3], kSentinel);
      view.source_x = source_x.view();
    }
  }
};

bool same_target(const Target& x, const Target& y, bool nan_equal) {
  for (std::size_t c = 0; c < x.color.size(); ++c)
    if (!same_rows(x.color[c], y.color[c], nan_equal)) return false;
  return same_rows(x.depth, y.depth, nan_equal) && same_rows(x.status, y.status, nan_equal) &&
         same_rows(x.source_x, y.source_x, nan_equal);
}

bool untouched(const Target& t) {
  auto all_float = [](const Plane<float>& p) {
    for (int r = 0; r < p.height(); ++r)
      for (std::ptrdiff_t i = 0; i < p.row_elements(); ++i)
        if (std::memcmp(&p.row(r)[i], &kSentinel, sizeof(float)) != 0) return false;
    return true;
  };
  for (const Plane<float>& p : t.color)
    if (!all_float(p)) return false;
  if (!all_float(t.depth) || !all_float(t.source_x)) return false;
  for (int r = 0; r < t.status.height(); ++r)
    for (std::ptrdiff_t i = 0; i < t.status.row_elements(); ++i)
      if (t.status.row(r)[i] != kStatusSentinel) return false;
  return true;
}

// Awkward values, picked by index; the rest come from raw bits.
float raw_float(FuzzedDataProvider& in) {
  const std::uint32_t bits = in.ConsumeIntegral<std::uint32_t>();
  float value;
  std::memcpy(&value, &bits, sizeof value);
  return value;
}
float pick_float(FuzzedDataProvider& in, float scale) {
  static const float kTable[] = {0.0f, -0.0f, 1.0f, -1.0f, 0.5f, 2.0f, 3.0f, 10.0f, 100.0f, 1e4f, 1e6f,
                                 1e30f, -1e30f, FLT_MAX, -FLT_MAX, kInf, -kInf, kNaN,
                                 std::numeric_limits<float>::denorm_min(), FLT_MIN, 1e-6f, -3.5f, 1000.5f};
  const int n = static_cast<int>(sizeof kTable / sizeof kTable[0]);
  const int k = in.ConsumeIntegralInRange<int>(0, n + 2);
  if (k < n) return kTable[k];
  if (k == n) return raw_float(in);
  // Small multiples of the frame's scale (e.g. its width): parallax just inside or beyond it.
  return scale * static_cast<float>(in.ConsumeIntegralInRange<int>(-48, 48)) / 16.0f;
}
double pick_plane(FuzzedDataProvider& in) {
  static const double kTable[] = {0.1, 1.0, 0.5, 10.0, 100.0, 1e4, 1e-30, 1e30, 1e300, 0.0, -1.0,
                                  std::numeric_limits<double>::infinity(), std::numeric_limits<double>::quiet_NaN(),
                                  std::numeric_limits<double>::denorm_min()};
  const int n = static_cast<int>(sizeof kTable / sizeof kTable[0]);
  const int k = in.ConsumeIntegralInRange<int>(0, n);
  return k < n ? kTable[k] : static_cast<double>(raw_float(in));
}

DepthDecoder make_decoder(FuzzedDataProvider& in) {
  switch (in.ConsumeIntegralInRange<int>(0, 3)) {
    case 0: return DepthDecoder::linear();
    case 1: return DepthDecoder::disparity();
    default: {
      // 7 is no encoding at all: an invalid decoder.
      const auto encoding = static_cast<DepthEncoding>(in.ConsumeIntegralInRange<int>(0, 7));
      const double near_plane = pick_plane(in);
      const double far_plane = in.ConsumeBool() ? near_plane * pick_plane(in) : pick_plane(in);
      return DepthDecoder::from_near_far(encoding, near_plane, far_plane);
    }
  }
}

ParallaxModel make_model(FuzzedDataProvider& in, int width) {
  const auto direction = static_cast<EyeDirection>(in.ConsumeIntegralInRange<int>(0, 4));  // 4: not a direction
  switch (in.ConsumeIntegralInRange<int>(0, 3)) {
    case 0: {
      static const double kSeparation[] = {0.0, 0.01, 0.03, 0.1, 1.0, 10.0, -0.01, 1e30};
      static const double kConvergence[] = {1.0, 0.5, 2.0, 10.0, 1e6, 1e30, 0.0, -1.0, FLT_MAX};
      const double separation = kSeparation[in.ConsumeIntegralInRange<int>(0, 7)];
      const double convergence = kConvergence[in.ConsumeIntegralInRange<int>(0, 8)];
      const int model_width = in.ConsumeBool() ? width : in.ConsumeIntegralInRange<int>(-1, 1 << 20);
      return ParallaxModel::from_stereo(separation, convergence, model_width, direction);
    }
    case 1: return ParallaxModel::from_disparity(direction);
    default: {
      ParallaxModel model;
      model.a = pick_float(in, static_cast<float>(width));
      model.b = pick_float(in, static_cast<float>(width));
      return model;
    }
  }
}

Options make_options(FuzzedDataProvider& in, int width) {
  Options options;
  options.method = static_cast<Method>(in.ConsumeIntegralInRange<int>(0, kMethodCount));  // kMethodCount: unknown
  if (in.ConsumeBool()) options.max_negative_parallax = pick_float(in, static_cast<float>(width));
  if (in.ConsumeBool()) options.hole_threshold = pick_float(in, 1.0f);
  options.hole_fill = static_cast<HoleFill>(in.ConsumeIntegralInRange<int>(0, 3));
  options.edge = static_cast<EdgeMode>(in.ConsumeIntegralInRange<int>(0, 4));  // 4: unknown
  if (in.ConsumeBool()) options.probe_parallax = pick_float(in, static_cast<float>(width));
  switch (in.ConsumeIntegralInRange<int>(0, 3)) {
    case 0: break;
    case 1: options.march_steps = in.ConsumeIntegralInRange<int>(1, 40); break;
    default: options.march_steps = in.ConsumeIntegralInRange<int>(-1, 1025); break;
  }
  switch (in.ConsumeIntegralInRange<int>(0, 3)) {
    case 0: break;
    case 1: options.secant_max_steps = in.ConsumeIntegralInRange<int>(1, 40); break;
    default: options.secant_max_steps = in.ConsumeIntegralInRange<int>(-1, 4097); break;
  }
  if (in.ConsumeBool()) options.arch = static_cast<Arch>(in.ConsumeIntegralInRange<int>(0, kArchCount));
  options.threads = in.ConsumeIntegralInRange<int>(-1, 3);
  return options;
}

// The depth values: raw bit patterns from the input, or per byte one of a table of awkward values
// (the decoder's exact near and far values among them), or an in-range scene.
void fill_depth(const std::vector<std::uint8_t>& bytes, int mode, const DepthDecoder& decoder, Plane<float>& depth,
                int width) {
  const float near_value = decoder.encode(decoder.near_plane());
  const float far_value = decoder.encode(decoder.far_plane());
  const float table[16] = {kNaN,
                           kInf,
                           -kInf,
                           -1.0f,
                           std::numeric_limits<float>::denorm_min(),
                           FLT_MAX,
                           -FLT_MAX,
                           0.0f,
                           -0.0f,
                           near_value,
                           far_value,
                           std::nextafter(near_value, 0.0f),
                           std::nextafter(far_value, kInf),
                           decoder.encode(2.0 * decoder.near_plane()),
                           -std::numeric_limits<float>::denorm_min(),
                           1e30f};
  std::size_t k = 0;
  auto next_byte = [&]() -> std::uint8_t { return bytes.empty() ? 0 : bytes[k++ % bytes.size()]; };
  for (int y = 0; y < depth.height(); ++y) {
    float* row = depth.row(y);
    for (int x = 0; x < width; ++x) {
      if (mode == 0) {
        std::uint32_t bits = 0;
        for (int b = 0; b < 4; ++b) bits |= static_cast<std::uint32_t>(next_byte()) << (8 * b);
        std::memcpy(&row[x], &bits, sizeof(float));
      } else if (mode == 1) {
        row[x] = table[next_byte() & 15];
      } else {
        // In range: view distance from just beyond near to 64 near, so every value decodes to a
        // finite parallax between the near and far ends (disparity: 0 .. 15.9 pixels).
        const std::uint8_t byte = next_byte();
        if (decoder.encoding() == DepthEncoding::disparity) {
          row[x] = static_cast<float>(byte) / 16.0f;
        } else {
          const double n = decoder.encoding() == DepthEncoding::linear ? 1.0 : decoder.near_plane();
          row[x] = decoder.encode(n * (1.0 + static_cast<double>(byte) / 4.0));
        }
      }
    }
  }
}

struct ParallelJobs {
  // Runs the tasks in reverse order on the calling thread: "any order" is part of the contract.
  static void run(void*, int count, void (*task)(void*, int), void* task_context) {
    for (int i = count - 1; i >= 0; --i) task(task_context, i);
  }
};

// The per-pixel checks of a successful call.
void check_pixels(const Shape& s, const Options& options, const Target& out, bool depth_in_range) {
  const float last = static_cast<float>(s.source_width - 1);
  for (int y = 0; y < s.height; ++y) {
    for (int t = 0; t < s.target_width; ++t) {
      int status = -1;
      if (s.with_status) {
        status = out.status.row(y)[t];
        CHECK_AT(status <= 3, t, y);
      }
      if (s.with_source_x) {
        const float x = out.source_x.row(y)[t];
        CHECK_AT(std::isfinite(x), t, y);
        if (status == 0 || status == 1) CHECK_AT(x >= 0.0f && x <= last, t, y);
        if (status == 2) CHECK_AT(x < 0.0f || x > last, t, y);
      }
      if (status < 0) continue;
      const bool written = status == 0 || status == 3 || (status == 2 && options.edge != EdgeMode::none) ||
                           (status == 1 && options.hole_fill != HoleFill::none);
      for (int c = 0; c < s.channels; ++c) {
        const float v = s.interleaved ? out.color[0].row(y)[4 * t + c] : out.color[static_cast<std::size_t>(c)].row(y)[t];
        if (written && status == 2 && options.edge == EdgeMode::black) {
          CHECK_AT(v == 0.0f, t, y);
        } else if (written) {
          // Source colour lies in [0, 1]; an interpolation stays there up to rounding.
          CHECK_AT(v >= -1e-3f && v <= 1.001f, t, y);
        } else {
          CHECK_AT(std::memcmp(&v, &kSentinel, sizeof v) == 0, t, y);
        }
      }
      if (s.with_depth) {
        const float d = out.depth.row(y)[t];
        if (!written) CHECK_AT(std::memcmp(&d, &kSentinel, sizeof d) == 0, t, y);
        else if (depth_in_range) CHECK_AT(std::isfinite(d), t, y);
      }
    }
  }
}

bool all_finite(const Plane<float>& p) {
  for (int y = 0; y < p.height(); ++y)
    for (std::ptrdiff_t i = 0; i < p.row_elements(); ++i)
      if (!std::isfinite(p.row(y)[i])) return false;
  return true;
}

bool known_code(StatusCode code) {
  return static_cast<int>(code) >= 0 && static_cast<int>(code) <= static_cast<int>(StatusCode::invalid_option);
}

}  // namespace

// Once per process: which instruction sets the every-arch check below can really run here.
extern "C" int LLVMFuzzerInitialize(int*, char***) {
  std::fprintf(stderr, "%s\n", reproject::arch_report("fuzz_reproject").c_str());
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  FuzzedDataProvider in(data, size);

  Shape s;
  // Mostly small frames (fast executions); sometimes wider, where the SIMD bodies and long
  // marches run; width 0 / height 0 are valid empty frames.
  s.source_width = in.ConsumeBool() ? in.ConsumeIntegralInRange<int>(0, 40) : in.ConsumeIntegralInRange<int>(0, 300);
  s.height = in.ConsumeIntegralInRange<int>(0, 4);
  s.interleaved = in.ConsumeBool();
  s.channels = s.interleaved ? 4 : in.ConsumeIntegralInRange<int>(1, 4);
  for (int& extra : s.stride_extra) extra = in.ConsumeIntegralInRange<int>(0, 3);
  s.with_depth = in.ConsumeBool();
  s.with_status = in.ConsumeBool();
  s.with_source_x = in.ConsumeBool();
  const int api = in.ConsumeIntegralInRange<int>(0, 2);  // reproject, reproject + ParallelFor, reproject_pair
  const int depth_mode = in.ConsumeIntegralInRange<int>(0, 2);

  const DepthDecoder decoder = make_decoder(in);
  const ParallaxModel model = make_model(in, s.source_width);
  Options options = make_options(in, s.source_width);
  options.guard = in.ConsumeBool() ? 0 : in.ConsumeIntegralInRange<int>(-1, s.source_width / 2 + 1);
  s.target_width = std::max(0, s.source_width - 2 * std::max(0, options.guard));
  // A claimed width beyond the library's maximum over a one-row buffer: must be refused before
  // anything is read (ASan reports it otherwise).
  const bool oversized = in.ConsumeIntegralInRange<int>(0, 63) == 0;

  Source source;
  for (int c = 0; c < (s.interleaved ? 1 : s.channels); ++c) {
    source.color.emplace_back(s.source_width, s.height, s.interleaved ? 4 : 1, s.stride_extra[1], 0.0f);
    Plane<float>& plane = source.color.back();
    for (int y = 0; y < s.height; ++y)
      for (std::ptrdiff_t i = 0; i < plane.row_elements(); ++i)
        plane.row(y)[i] = static_cast<float>((i * 7 + y * 3 + c * 5) % 17) / 16.0f;
    source.view.color.plane[c] = plane.cview();
  }
  source.view.color.layout = s.interleaved ? ColorLayout::interleaved_rgba : ColorLayout::planar;
  source.view.color.channels = s.channels;
  source.depth = Plane<float>(s.source_width, s.height, 1, s.stride_extra[0], 0.0f);
  fill_depth(in.ConsumeRemainingBytes<std::uint8_t>(), depth_mode, decoder, source.depth, s.source_width);
  source.view.depth = source.depth.cview();
  if (oversized) source.view.depth.width = (1 << 22) + 1;

  const bool depth_finite = all_finite(source.depth);
  // In the decoder's range: every value decodes to a finite inverse depth >= 0 without overflow
  // in the output interpolation.
  bool depth_in_range = depth_finite && decoder.validate().ok();
  for (int y = 0; y < s.height && depth_in_range; ++y) {
    for (int x = 0; x < s.source_width && depth_in_range; ++x) {
      const float d = source.depth.row(y)[x];
      const float w = decoder.inverse_depth(d);
      depth_in_range = std::isfinite(w) && w >= 0.0f && std::fabs(d) < 1e6f &&
                       (decoder.encoding() != DepthEncoding::linear || d >= 1e-6f);
    }
  }

  // ---- the public call ----
  Target out(s);
  Target second(s);  // reproject_pair's left eye
  Status status;
  const ParallaxModel mirrored{-model.a, -model.b};
  if (api == 2) {
    status = reproject_pair(source.view, decoder, model, options, second.view, out.view);
  } else if (api == 1) {
    ParallelFor jobs{nullptr, ParallelJobs::run};
    status = reproject::reproject(source.view, decoder, model, options, out.view, jobs);
  } else {
    status = reproject::reproject(source.view, decoder, model, options, out.view);
  }
  CHECK(known_code(status.code()));
  CHECK(status.message() != nullptr && status.message()[0] != '\0');
  if (oversized) CHECK(!status.ok());
  if (!status.ok()) {
    CHECK(untouched(out));
    CHECK(untouched(second));
    return 0;
  }
  if (s.source_width == 0 || s.height == 0) return 0;
  check_pixels(s, options, out, depth_in_range);
  if (api == 2) check_pixels(s, options, second, depth_in_range);

  // ---- the same call, every way round ----
  const Arch used = options.arch ? *options.arch : selected_arch();
  // The comparisons run on the calling thread: the first one below holds the public call (any
  // thread count, any entry point) to it, and the pool's hand-offs would only slow the fuzzer.
  options.threads = 1;
  // The public call equals reproject_with() on the same kernels (any entry point, any thread
  // count); the pair equals two single calls.
  {
    Target again(s);
    CHECK(detail::reproject_with(*detail::compiled_kernels(used), source.view, decoder, model, options, again.view).ok());
    CHECK(same_target(out, again, false));
    if (api == 2) {
      Target left(s);
      CHECK(detail::reproject_with(*detail::compiled_kernels(used), source.view, decoder, mirrored, options, left.view).ok());
      CHECK(same_target(second, left, false));
    }
  }
  // Every instruction set the CPU has against its scalar reference.
  for (int a = 0; a < kArchCount; ++a) {
    const Arch arch = static_cast<Arch>(a);
    if (!arch_supported(arch)) continue;
    Target simd(s);
    Target reference(s);
    CHECK(detail::reproject_with(*detail::compiled_kernels(arch), source.view, decoder, model, options, simd.view).ok());
    CHECK(detail::reproject_with(detail::reference_kernels(arch), source.view, decoder, model, options, reference.view).ok());
    if (!same_target(simd, reference, !depth_finite)) {
      std::fprintf(stderr, "fuzz_reproject: %s differs from its scalar reference (method %s, depth %s)\n",
                   to_string(arch), to_string(options.method), depth_finite ? "finite" : "non-finite");
      std::abort();
    }
  }
  return 0;
}
