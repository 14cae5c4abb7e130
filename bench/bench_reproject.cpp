// reproject_bench: Google Benchmark microbenchmarks of every method on every instruction set this
// CPU supports, on the built-in scene's centre view, with the memory roofline in the same binary
// (docs/PERFORMANCE.md; bench/run_benchmarks.py runs it and writes that page).
//
// Names (rates are per wall-clock second, see report_rates):
//   <method>/<arch>/<W>x<H>/threads:<n>             planar RGBA (4 float planes), the default
//   <method>/<arch>/1920x1080/threads:<n>/sep:<px>  parallax at infinity a = px, scene convergence
//   <method>/<arch>/1920x1080/threads:<n>/rgba      interleaved RGBA
//   pair_<method>/<arch>/1920x1080/threads:<n>      centre -> both eyes (reproject_pair)
//   pair_<method>/<arch>/1920x1080/threads:<n>/two_calls  the same as two reproject() calls
//   <method>/<arch>/1920x1080/threads:<n>/near:fixed  max_negative_parallax = |a| / 2 (an engine's
//                                                    fixed limit) instead of the frame's own
//   march16/<arch>/512x512/threads:1/grey           one colour plane: the frame fits in cache
//   roofline/<W>x<H>/threads:<n>[/grey]             the same bytes streamed by a plain copy
//   <method>/<arch>/<W>x<H>/threads:<n>/<colour>+<depth>  an engine-native frame (kPixelFormats,
//                                                    e.g. rgba8+unorm24_s8; rgba32f+float is the
//                                                    float baseline), colour output only, on the
//                                                    best arch and AVX2, at 1920x1080 and 3840x2160
//   roofline/<W>x<H>/threads:<n>/<colour>+<depth>    the same bytes touched by a plain copy
//   <method>/<arch>/1920x1080/threads:<n>/<colour>+<depth>/band:32  the same frame's rows 524..555
//                                                    only (single, march16, exact on
//                                                    rgba8+unorm24_s8 and rgba32f+float): after the
//                                                    first call the band stays in cache, so this is
//                                                    the kernel's computation without the memory wall
//   roofline/1920x1080/threads:<n>/<colour>+<depth>/band:32  the plain copy over the same band
//
// Counters: items = target pixels (both eyes for pair_; the band's own for band:), bytes = what one
// eye must touch: read depth + colour, write colour + depth + status (no source_x); for the
// <colour>+<depth> cases read depth + colour, write colour. Benchmarks never assert time.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <tuple>
#include <vector>

#include "reproject/reproject.hpp"
#include "scene.hpp"

namespace {

using namespace reproject;
namespace rs = reproject::scene;

struct Size {
  int width;
  int height;
};
constexpr Size kSizes[] = {{1280, 720}, {1920, 1080}, {3840, 2160}};
constexpr Size kFullHd = {1920, 1080};
constexpr Size kFormatSizes[] = {kFullHd, {3840, 2160}};  // the engine-native formats' sizes
// Small enough that depth, one colour plane and all outputs (17 B/px, 4.5 MB) stay in L2/L3:
// the kernels' arithmetic speed without the memory wall.
constexpr Size kInCache = {512, 512};
constexpr int kThreadCounts[] = {1, 2};
constexpr int kSeparations[] = {8, 32, 128};  // parallax at infinity, pixels
constexpr Method kMethods[] = {Method::scanline, Method::march16, Method::single, Method::secant, Method::exact};
// Every instruction set the library names, in its order.
std::vector<Arch> every_arch() {
  std::vector<Arch> archs;
  for (int a = 0; a < kArchCount; ++a) archs.push_back(static_cast<Arch>(a));
  return archs;
}

enum class Layout : std::uint8_t {
  planar_rgba,       // 4 float planes
  interleaved_rgba,  // one plane, 4 floats a pixel
  grey,              // 1 float plane
};

int channels_of(Layout layout) { return layout == Layout::grey ? 1 : 4; }

// Bytes one eye must touch per pixel: read depth + colour, write colour + depth + status.
std::int64_t bytes_per_pixel(Layout layout) {
  const std::int64_t color = 4 * channels_of(layout);
  return 4 + color + color + 4 + 1;
}

const rs::Scene& the_scene() {
  static const rs::Scene scene = rs::Scene::make(rs::SceneId::room);
  return scene;
}

const DepthDecoder& the_decoder() {
  static const DepthDecoder decoder = the_scene().decoder(DepthEncoding::standard);
  return decoder;
}

// The scene's recommended stereo camera (S = 3 % of the width, convergence mid-range), centre ->
// right eye: a = 0.015 W, so the parallax range grows with the width as it would in a game.
ParallaxModel default_model(int width) {
  return the_scene().camera(width, 1).stereo.parallax(width, EyeDirection::centre_to_right);
}

// Parallax at infinity of `separation_px` pixels at the scene's convergence: the separation
// sweep changes only the stereo strength, not where zero parallax lies.
ParallaxModel model_for_separation(int width, int separation_px) {
  StereoCamera stereo = the_scene().recommended_stereo();
  // centre -> right has sigma = 1/2, so a = S W / 2.
  stereo.separation = 2.0 * separation_px / width;
  return stereo.parallax(width, EyeDirection::centre_to_right);
}

// --- Frames, cached: ray casting a 4K view takes seconds, so each size is rendered once --------

struct Source {
  Image color;
  Image depth;  // standard encoding
  SourceView view() const {
    SourceView v;
    v.color = color.color();
    v.depth = depth.plane(0);
    return v;
  }
};

struct Outputs {
  Image color;
  Image depth;
  std::vector<std::uint8_t> status;
  int width = 0;
  int height = 0;

  TargetView view() {
    TargetView t;
    t.color = color.mutable_color();
    t.depth = depth.mutable_plane(0);
    t.status = BytePlane{status.data(), width, height, width};
    return t;  // source_x stays null: not requested
  }
};

const rs::View& centre_view(Size size) {
  static std::map<std::pair<int, int>, std::unique_ptr<rs::View>> cache;
  std::unique_ptr<rs::View>& view = cache[{size.width, size.height}];
  if (!view) {
    view = std::make_unique<rs::View>();
    const Status status = the_scene().render(the_scene().camera(size.width, size.height, rs::kCentreEye), view.get());
    if (!status.ok()) {
      std::fprintf(stderr, "reproject_bench: render %dx%d: %s\n", size.width, size.height, status.message());
      std::exit(1);
    }
  }
  return *view;
}

const Source& source_frame(Size size, Layout layout) {
  static std::map<std::tuple<int, int, Layout>, std::unique_ptr<Source>> cache;
  std::unique_ptr<Source>& frame = cache[{size.width, size.height, layout}];
  if (frame) return *frame;

  const rs::View& view = centre_view(size);
  frame = std::make_unique<Source>();
  frame->depth = rs::encode_depth(view.depth, the_decoder());
  const ColorLayout color_layout = layout == Layout::interleaved_rgba ? ColorLayout::interleaved_rgba : ColorLayout::planar;
  frame->color = Image(size.width, size.height, channels_of(layout), color_layout);
  if (frame->depth.empty() || frame->color.empty()) {
    std::fprintf(stderr, "reproject_bench: cannot allocate a %dx%d source\n", size.width, size.height);
    std::exit(1);
  }
  const std::ptrdiff_t in_stride = view.color.stride();
  const std::ptrdiff_t out_stride = frame->color.stride();
  for (int y = 0; y < size.height; ++y) {
    const float* r = view.color.plane_data(0) + y * in_stride;
    const float* g = view.color.plane_data(1) + y * in_stride;
    const float* b = view.color.plane_data(2) + y * in_stride;
    const std::uint8_t* object = view.object.data() + static_cast<std::size_t>(y) * size.width;
    for (int x = 0; x < size.width; ++x) {
      // Alpha is coverage (1 where the ray met an object), so the fourth plane carries content.
      const float rgba[4] = {r[x], g[x], b[x], object[x] != 255 ? 1.0f : 0.0f};
      if (layout == Layout::grey) {
        frame->color.plane_data(0)[y * out_stride + x] = 0.2126f * rgba[0] + 0.7152f * rgba[1] + 0.0722f * rgba[2];
      } else if (layout == Layout::interleaved_rgba) {
        std::memcpy(frame->color.plane_data(0) + y * out_stride + 4 * x, rgba, sizeof rgba);
      } else {
        for (int c = 0; c < 4; ++c) frame->color.plane_data(c)[y * out_stride + x] = rgba[c];
      }
    }
  }
  return *frame;
}

// Output buffers, shared by every benchmark of a size and layout (slot 1: the pair's second eye).
// Image zero-fills, so the pages are touched before any timing.
Outputs& output_frame(Size size, Layout layout, int slot) {
  static std::map<std::tuple<int, int, Layout, int>, std::unique_ptr<Outputs>> cache;
  std::unique_ptr<Outputs>& out = cache[{size.width, size.height, layout, slot}];
  if (!out) {
    out = std::make_unique<Outputs>();
    const ColorLayout color_layout = layout == Layout::interleaved_rgba ? ColorLayout::interleaved_rgba : ColorLayout::planar;
    out->color = Image(size.width, size.height, channels_of(layout), color_layout);
    out->depth = Image(size.width, size.height, 1);
    out->status.assign(static_cast<std::size_t>(size.width) * size.height, 0);
    out->width = size.width;
    out->height = size.height;
    if (out->color.empty() || out->depth.empty()) {
      std::fprintf(stderr, "reproject_bench: cannot allocate %dx%d outputs\n", size.width, size.height);
      std::exit(1);
    }
  }
  return *out;
}

// --- Engine-native frames: the same scene converted once to an engine's colour and depth formats --

// A `<colour>+<depth>` case's formats. Float colour is interleaved float RGBA; float depth is the
// float depth plane, as the float cases pass it.
struct PixelFormat {
  const char* name;
  ColorFormat color;
  DepthFormat depth;
};
constexpr PixelFormat kPixelFormats[] = {
    {"rgba32f+float", ColorFormat::float32, DepthFormat::float32},  // the float baseline
    {"rgba8+unorm24_s8", ColorFormat::rgba8, DepthFormat::unorm24_s8},
    {"rgba8_srgb+float", ColorFormat::rgba8_srgb, DepthFormat::float32},
    {"rgba8_srgb+unorm24_s8", ColorFormat::rgba8_srgb, DepthFormat::unorm24_s8},  // an engine's sRGB back buffer
    {"rgba16f+float", ColorFormat::rgba16f, DepthFormat::float32},
    {"rgba8+unorm16", ColorFormat::rgba8, DepthFormat::unorm16},
};

int color_bytes(const PixelFormat& format) {
  return format.color == ColorFormat::float32 ? 4 * static_cast<int>(sizeof(float)) : reproject::bytes_per_pixel(format.color);
}
int depth_bytes(const PixelFormat& format) {
  return format.depth == DepthFormat::float32 ? static_cast<int>(sizeof(float)) : reproject::bytes_per_pixel(format.depth);
}
// What a colour-only call touches per pixel: read colour + depth, write colour.
std::int64_t bytes_per_pixel(const PixelFormat& format) { return 2 * color_bytes(format) + depth_bytes(format); }

// Packed pixels as an engine holds them: rows padded to 64 bytes, 64-byte aligned, zero-filled
// (so that the pages are touched before any timing).
struct PackedBuffer {
  std::unique_ptr<std::uint8_t, void (*)(void*)> bytes{nullptr, std::free};
  std::ptrdiff_t stride = 0;

  PackedBuffer(int width, int height, int pixel_bytes) {
    stride = (static_cast<std::ptrdiff_t>(width) * pixel_bytes + 63) / 64 * 64;
    const std::size_t size = static_cast<std::size_t>(stride) * height;
#if defined(_WIN32)
    bytes = {static_cast<std::uint8_t*>(_aligned_malloc(size, 64)), _aligned_free};  // no aligned_alloc there
#else
    bytes.reset(static_cast<std::uint8_t*>(std::aligned_alloc(64, size)));
#endif
    if (!bytes) {
      std::fprintf(stderr, "reproject_bench: cannot allocate %dx%d packed pixels\n", width, height);
      std::exit(1);
    }
    std::memset(bytes.get(), 0, size);
  }
  std::uint8_t* row(int y) const { return bytes.get() + y * stride; }
};

// One source frame in a PixelFormat and its colour output. Float colour and float depth are the
// float frames themselves (source_frame, output_frame); the others are converted from them once.
struct FormatFrame {
  std::unique_ptr<PackedBuffer> color, depth, out_color;
  SourceView source;
  TargetView target;  // colour only
};

const FormatFrame& format_frame(Size size, const PixelFormat& format) {
  static std::map<std::tuple<int, int, std::string>, std::unique_ptr<FormatFrame>> cache;
  std::unique_ptr<FormatFrame>& frame = cache[{size.width, size.height, format.name}];
  if (frame) return *frame;
  frame = std::make_unique<FormatFrame>();
  const Source& floats = source_frame(size, Layout::interleaved_rgba);
  const int w = size.width;
  const int h = size.height;

  if (format.color == ColorFormat::float32) {
    frame->source.color = floats.color.color();
    frame->target.color = output_frame(size, Layout::interleaved_rgba, 0).color.mutable_color();
  } else {
    const int pixel_bytes = color_bytes(format);
    frame->color = std::make_unique<PackedBuffer>(w, h, pixel_bytes);
    frame->out_color = std::make_unique<PackedBuffer>(w, h, pixel_bytes);
    for (int y = 0; y < h; ++y) {
      const float* rgba = floats.color.plane_data(0) + y * floats.color.stride();
      std::uint8_t* out = frame->color->row(y);
      for (int i = 0; i < 4 * w; ++i) {
        const bool alpha = i % 4 == 3;
        if (format.color == ColorFormat::rgba16f) {
          const std::uint16_t half = formats::float_to_half(rgba[i]);
          std::memcpy(out + 2 * i, &half, sizeof half);
        } else if (format.color == ColorFormat::rgba8_srgb && !alpha) {
          out[i] = formats::linear_to_srgb(rgba[i]);
        } else {
          out[i] = static_cast<std::uint8_t>(reproject::formats::float_to_unorm(rgba[i], 8));
        }
      }
    }
    frame->source.color = ColorView::packed(format.color, frame->color->bytes.get(), w, h, frame->color->stride);
    frame->target.color = MutableColorView::packed(format.color, frame->out_color->bytes.get(), w, h, frame->out_color->stride);
  }

  if (format.depth == DepthFormat::float32) {
    frame->source.depth = floats.depth.plane(0);
  } else {
    // The stored value d of the float frame, as a D16 or D24 code; D24S8's stencil holds the
    // scene's object id, as an engine's stencil would hold some per-object mark.
    const rs::View& view = centre_view(size);
    frame->depth = std::make_unique<PackedBuffer>(w, h, depth_bytes(format));
    for (int y = 0; y < h; ++y) {
      const float* d = floats.depth.plane_data(0) + y * floats.depth.stride();
      const std::uint8_t* object = view.object.data() + static_cast<std::size_t>(y) * w;
      std::uint8_t* out = frame->depth->row(y);
      for (int x = 0; x < w; ++x) {
        if (format.depth == DepthFormat::unorm16) {
          const std::uint16_t code = static_cast<std::uint16_t>(formats::float_to_unorm(d[x], 16));
          std::memcpy(out + 2 * x, &code, sizeof code);
        } else {  // unorm24_s8: depth in bits 0-23, stencil in bits 24-31
          const std::uint32_t word = formats::float_to_unorm(d[x], 24) | static_cast<std::uint32_t>(object[x]) << 24;
          std::memcpy(out + 4 * x, &word, sizeof word);
        }
      }
    }
    frame->source.depth_buffer = DepthBuffer::of(format.depth, frame->depth->bytes.get(), w, h, frame->depth->stride);
  }
  return *frame;
}

// --- A band of rows: the same buffers, fewer rows ------------------------------------------------

// The band cases' height, and the first row of a band of `rows` rows in the middle of a frame
// `height` rows high (1080p: rows 524..555).
constexpr int kBandRows = 32;
constexpr Method kBandMethods[] = {Method::single, Method::march16, Method::exact};
int band_first_row(int height, int rows) { return (height - rows) / 2; }

// Rows [first, first + count) of a plane or depth buffer: data moved to row `first`, the height
// cut to `count`, width and stride unchanged. A view that is not set (no data) stays unset.
template <class Rows>
Rows band_of(Rows rows, int first, int count) {
  if (rows.data) {
    rows.data = rows.row(first);
    rows.height = count;
  }
  return rows;
}
template <class T>
ColorViewT<T> band_of(ColorViewT<T> color, int first, int count) {
  for (PlaneView<T>& plane : color.plane) plane = band_of(plane, first, count);
  color.pixels = band_of(color.pixels, first, count);
  return color;
}
SourceView band_of(SourceView view, int first, int count) {
  view.color = band_of(view.color, first, count);
  view.depth = band_of(view.depth, first, count);
  view.depth_buffer = band_of(view.depth_buffer, first, count);
  return view;
}
TargetView band_of(TargetView view, int first, int count) {
  view.color = band_of(view.color, first, count);
  view.depth = band_of(view.depth, first, count);
  view.status = band_of(view.status, first, count);
  view.source_x = band_of(view.source_x, first, count);
  view.depth_buffer = band_of(view.depth_buffer, first, count);
  return view;
}

// --- The reprojection benchmarks ---------------------------------------------------------------

struct Case {
  Method method = Method::exact;
  Arch arch = Arch::scalar;
  Size size = kFullHd;
  int threads = 1;
  Layout layout = Layout::planar_rgba;
  std::optional<int> separation_px;  // unset: the scene's recommended stereo
  bool fixed_near = false;  // max_negative_parallax = |a| / 2, as engines set it, not the frame's own
  bool pair = false;
  bool two_calls = false;  // a pair as two single-eye calls (the baseline reproject_pair must beat)
  const PixelFormat* format = nullptr;  // an engine-native frame, colour output only (not with pair)
  int band_rows = 0;  // > 0: only this many rows in the middle of the frame (band_of); 0: the whole frame
  bool warmed = false;
};

// Registered cases live here so that each benchmark keeps a stable pointer to its own.
std::deque<Case>& cases() {
  static std::deque<Case> all;
  return all;
}

// Every rate is per wall-clock second: the 2-thread benchmarks must be timed so, and the 1-thread
// ones and the roofline use the same clock so that ratios between them mean something. Google
// Benchmark would do it with UseRealTime(), but that appends "/real_time" to every name, and the
// names are fixed as `<method>/<arch>/<W>x<H>/threads:<n>`; so each benchmark times its own loop.
// (Google Benchmark's `real_time` column is wall time either way; only the iteration count is
// then chosen from the calling thread's CPU time, which at 2 threads is about half the rows'.)
class WallClock {
 public:
  double seconds() const { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count(); }

 private:
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

void report_rates(benchmark::State& state, double wall_seconds, std::int64_t pixels, double bytes_per_pixel) {
  const double items = static_cast<double>(state.iterations()) * static_cast<double>(pixels);
  state.counters["items_per_second"] = benchmark::Counter(items / wall_seconds);
  state.counters["bytes_per_second"] = benchmark::Counter(items * bytes_per_pixel / wall_seconds);
}

void bm_reproject(benchmark::State& state, Case* c) {
  SourceView source_view = c->format ? format_frame(c->size, *c->format).source : source_frame(c->size, c->layout).view();
  const ParallaxModel model =
      c->separation_px ? model_for_separation(c->size.width, *c->separation_px) : default_model(c->size.width);
  Options options;
  options.method = c->method;
  options.arch = c->arch;
  options.threads = c->threads;
  if (c->fixed_near) options.max_negative_parallax = 0.5f * std::fabs(model.a);
  TargetView eye = c->format ? format_frame(c->size, *c->format).target : output_frame(c->size, c->layout, 0).view();
  TargetView other_eye = c->pair ? output_frame(c->size, c->layout, 1).view() : TargetView{};
  const int rows = c->band_rows > 0 ? c->band_rows : c->size.height;
  if (c->band_rows > 0) {
    const int first = band_first_row(c->size.height, c->band_rows);
    source_view = band_of(source_view, first, rows);
    eye = band_of(eye, first, rows);
    other_eye = band_of(other_eye, first, rows);
  }
  const DepthDecoder& decoder = the_decoder();

  const ParallaxModel mirrored{-model.a, -model.b};  // the pair's left eye
  auto call = [&] {
    if (!c->pair) return reproject::reproject(source_view, decoder, model, options, eye);
    if (!c->two_calls) return reproject_pair(source_view, decoder, model, options, other_eye, eye);
    const Status left = reproject::reproject(source_view, decoder, mirrored, options, other_eye);
    return left.ok() ? reproject::reproject(source_view, decoder, model, options, eye) : left;
  };
  // One untimed call per benchmark, the first time it runs: it reports a configuration error
  // instead of timing it, and grows the per-thread scratch rows (and starts the pool, once
  // threads exist) so the first timed iteration is not a cold start. Later repetitions skip it:
  // the slowest cases (4K scalar scanline) should not pay it again.
  if (!c->warmed) {
    const Status status = call();
    if (!status.ok()) {
      state.SkipWithError(status.message());
      return;
    }
    c->warmed = true;
  }
  const WallClock clock;
  for (auto _ : state) {
    Status status = call();
    benchmark::DoNotOptimize(status);
  }
  const std::int64_t pixels = static_cast<std::int64_t>(c->size.width) * rows * (c->pair ? 2 : 1);
  report_rates(state, clock.seconds(), pixels, c->format ? bytes_per_pixel(*c->format) : bytes_per_pixel(c->layout));
}

std::string size_name(Size size) { return std::to_string(size.width) + "x" + std::to_string(size.height); }

void finish(benchmark::internal::Benchmark* b) { b->Unit(benchmark::kMillisecond); }

void register_case(const Case& c, const std::string& suffix) {
  cases().push_back(c);
  Case* stored = &cases().back();
  const std::string name = std::string(c.pair ? "pair_" : "") + to_string(c.method) + "/" + to_string(c.arch) + "/" +
                           size_name(c.size) + "/threads:" + std::to_string(c.threads) + suffix;
  finish(benchmark::RegisterBenchmark(name.c_str(), bm_reproject, stored));
}

// --- The roofline --------------------------------------------------------------------------------

// A persistent team for the roofline's 2-thread rows: the library splits rows over a persistent
// pool, so the roofline must not pay a thread start per iteration either. The calling thread
// runs the first band of rows; each helper one more band.
class RowTeam {
 public:
  explicit RowTeam(int threads) {
    for (int i = 1; i < threads; ++i) helpers_.emplace_back([this, i] { helper_loop(i); });
    bands_ = threads;
  }
  ~RowTeam() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stop_ = true;
    }
    wake_.notify_all();
    for (std::thread& t : helpers_) t.join();
  }
  RowTeam(const RowTeam&) = delete;
  RowTeam& operator=(const RowTeam&) = delete;

  // Calls rows(begin, end) for `bands_` contiguous bands covering [0, height); returns when all
  // bands are done.
  void run(int height, const std::function<void(int, int)>& rows) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      job_ = &rows;
      height_ = height;
      pending_ = static_cast<int>(helpers_.size());
      ++generation_;
    }
    wake_.notify_all();
    run_band(0, rows, height);
    std::unique_lock<std::mutex> lock(mutex_);
    done_.wait(lock, [this] { return pending_ == 0; });
  }

 private:
  void run_band(int band, const std::function<void(int, int)>& rows, int height) const {
    const int begin = static_cast<int>(static_cast<std::int64_t>(height) * band / bands_);
    const int end = static_cast<int>(static_cast<std::int64_t>(height) * (band + 1) / bands_);
    rows(begin, end);
  }
  void helper_loop(int band) {
    std::uint64_t seen = 0;
    for (;;) {
      const std::function<void(int, int)>* job;
      int height;
      {
        std::unique_lock<std::mutex> lock(mutex_);
        wake_.wait(lock, [&] { return stop_ || generation_ != seen; });
        if (stop_) return;
        seen = generation_;
        job = job_;
        height = height_;
      }
      run_band(band, *job, height);
      {
        std::lock_guard<std::mutex> lock(mutex_);
        --pending_;
      }
      done_.notify_one();
    }
  }

  std::vector<std::thread> helpers_;
  int bands_ = 1;
  std::mutex mutex_;
  std::condition_variable wake_;
  std::condition_variable done_;
  const std::function<void(int, int)>* job_ = nullptr;
  int height_ = 0;
  int pending_ = 0;
  std::uint64_t generation_ = 0;
  bool stop_ = false;
};

// Streams exactly the bytes a reprojected eye touches, on the same buffers: per row, copy depth
// and each colour row to the outputs and write the status row. memcpy/memset are the simplest
// loops that run at memory speed; everything a kernel does beyond this is its own cost.
void bm_roofline(benchmark::State& state, Size size, int threads, Layout layout) {
  const Source& source = source_frame(size, layout);
  Outputs& out = output_frame(size, layout, 0);
  const int planes = layout == Layout::interleaved_rgba ? 1 : channels_of(layout);
  const std::size_t color_row_bytes =
      static_cast<std::size_t>(size.width) * (layout == Layout::interleaved_rgba ? 4 : 1) * sizeof(float);
  const std::size_t depth_row_bytes = static_cast<std::size_t>(size.width) * sizeof(float);

  const std::function<void(int, int)> rows = [&](int begin, int end) {
    for (int y = begin; y < end; ++y) {
      for (int c = 0; c < planes; ++c) {
        std::memcpy(out.color.plane_data(c) + y * out.color.stride(), source.color.plane_data(c) + y * source.color.stride(),
                    color_row_bytes);
      }
      std::memcpy(out.depth.plane_data(0) + y * out.depth.stride(), source.depth.plane_data(0) + y * source.depth.stride(),
                  depth_row_bytes);
      std::memset(out.status.data() + static_cast<std::size_t>(y) * size.width, 0, static_cast<std::size_t>(size.width));
    }
  };
  RowTeam team(threads);
  team.run(size.height, rows);  // untimed: wakes the helper once
  const WallClock clock;
  for (auto _ : state) {
    team.run(size.height, rows);
    benchmark::ClobberMemory();
  }
  const std::int64_t pixels = static_cast<std::int64_t>(size.width) * size.height;
  report_rates(state, clock.seconds(), pixels, bytes_per_pixel(layout));
}

// The same for a `<colour>+<depth>` frame: copy each colour row to the output, and read each depth
// row (summed, so that the reads cannot be dropped): the bytes a colour-only call touches.
std::uint64_t sum_words(const std::uint8_t* bytes, std::size_t count) {
  std::uint64_t sum = 0;
  std::size_t i = 0;
  for (; i + 8 <= count; i += 8) {
    std::uint64_t word;
    std::memcpy(&word, bytes + i, sizeof word);
    sum += word;
  }
  for (; i < count; ++i) sum += bytes[i];
  return sum;
}

// `band_rows` > 0: only that many rows in the middle of the frame, as the band cases (band_of).
void bm_roofline_format(benchmark::State& state, Size size, int threads, const PixelFormat* format, int band_rows) {
  const FormatFrame& frame = format_frame(size, *format);
  const int height = band_rows > 0 ? band_rows : size.height;
  const int first = band_rows > 0 ? band_first_row(size.height, band_rows) : 0;
  const ColorView& in = frame.source.color;
  const MutableColorView& out = frame.target.color;
  const bool float_color = format->color == ColorFormat::float32;
  const bool float_depth = format->depth == DepthFormat::float32;
  const std::size_t color_row_bytes = static_cast<std::size_t>(size.width) * color_bytes(*format);
  const std::size_t depth_row_bytes = static_cast<std::size_t>(size.width) * depth_bytes(*format);

  const std::function<void(int, int)> rows = [&](int begin, int end) {
    std::uint64_t sum = 0;
    for (int y = first + begin; y < first + end; ++y) {
      if (float_color) {
        std::memcpy(out.plane[0].row(y), in.plane[0].row(y), color_row_bytes);
      } else {
        std::memcpy(out.pixels.row(y), in.pixels.row(y), color_row_bytes);
      }
      const void* depth = float_depth ? static_cast<const void*>(frame.source.depth.row(y))
                                      : static_cast<const void*>(frame.source.depth_buffer.row(y));
      sum += sum_words(static_cast<const std::uint8_t*>(depth), depth_row_bytes);
    }
    benchmark::DoNotOptimize(sum);
  };
  RowTeam team(threads);
  team.run(height, rows);  // untimed: wakes the helper once
  const WallClock clock;
  for (auto _ : state) {
    team.run(height, rows);
    benchmark::ClobberMemory();
  }
  const std::int64_t pixels = static_cast<std::int64_t>(size.width) * height;
  report_rates(state, clock.seconds(), pixels, bytes_per_pixel(*format));
}

void register_roofline(Size size, int threads, Layout layout, const std::string& suffix) {
  const std::string name = "roofline/" + size_name(size) + "/threads:" + std::to_string(threads) + suffix;
  finish(benchmark::RegisterBenchmark(name.c_str(), bm_roofline, size, threads, layout));
}

void register_all() {
  std::vector<Arch> archs;
  for (Arch arch : every_arch())
    if (arch_supported(arch)) archs.push_back(arch);

  // Every method on every arch at each thread count, from a template case.
  auto register_methods = [&](Case c, const std::string& suffix) {
    for (int threads : kThreadCounts) {
      for (Method method : kMethods) {
        for (Arch arch : archs) {
          c.method = method;
          c.arch = arch;
          c.threads = threads;
          register_case(c, suffix);
        }
      }
    }
  };
  // Size scaling, planar RGBA: per size and thread count, the roofline just before the methods.
  for (Size size : kSizes) {
    for (int threads : kThreadCounts) {
      register_roofline(size, threads, Layout::planar_rgba, "");
      for (Method method : kMethods) {
        for (Arch arch : archs) {
          Case c;
          c.method = method;
          c.arch = arch;
          c.size = size;
          c.threads = threads;
          register_case(c, "");
        }
      }
    }
  }
  // Separation sweep at 1080p.
  for (int separation : kSeparations) {
    Case c;
    c.separation_px = separation;
    register_methods(c, "/sep:" + std::to_string(separation));
  }
  // Interleaved RGBA and centre -> both eyes, 1080p.
  Case interleaved;
  interleaved.layout = Layout::interleaved_rgba;
  register_methods(interleaved, "/rgba");
  Case pair;
  pair.pair = true;
  register_methods(pair, "");
  pair.two_calls = true;
  register_methods(pair, "/two_calls");
  // A fixed near limit (the engine's choice) instead of the frame's own, 1080p.
  Case fixed_near;
  fixed_near.fixed_near = true;
  register_methods(fixed_near, "/near:fixed");
  // Engine-native formats at 1080p and 4K, colour output only: every method on the best arch and
  // on AVX2 (the other archs add run time, not information), after each format's roofline.
  std::vector<Arch> format_archs;
  if (arch_supported(Arch::avx2)) format_archs.push_back(Arch::avx2);
  if (archs.back() != Arch::avx2) format_archs.push_back(archs.back());
  // A format's roofline at a size and thread count, then `methods` on each of format_archs;
  // `band_rows` > 0: only that many rows in the middle of the frame (band_of).
  auto register_format_cases = [&](Size size, int threads, const PixelFormat& format, int band_rows,
                                   const auto& methods) {
    const std::string suffix =
        std::string("/") + format.name + (band_rows > 0 ? "/band:" + std::to_string(band_rows) : std::string());
    const std::string roof = "roofline/" + size_name(size) + "/threads:" + std::to_string(threads) + suffix;
    finish(benchmark::RegisterBenchmark(roof.c_str(), bm_roofline_format, size, threads, &format, band_rows));
    for (Method method : methods) {
      for (Arch arch : format_archs) {
        Case c;
        c.method = method;
        c.arch = arch;
        c.size = size;
        c.threads = threads;
        c.format = &format;
        c.band_rows = band_rows;
        register_case(c, suffix);
      }
    }
  };
  for (Size size : kFormatSizes) {
    for (int threads : kThreadCounts) {
      for (const PixelFormat& format : kPixelFormats) {
        register_format_cases(size, threads, format, 0, kMethods);
      }
    }
  }
  // Computation alone: the 1080p packed and float frames' middle 32 rows, which stay in cache
  // from one call to the next, so the time is the kernel's work without the memory wall.
  for (int threads : kThreadCounts) {
    for (const PixelFormat& format : kPixelFormats) {
      if (std::strcmp(format.name, "rgba8+unorm24_s8") != 0 && std::strcmp(format.name, "rgba32f+float") != 0) continue;
      register_format_cases(kFullHd, threads, format, kBandRows, kBandMethods);
    }
  }
  // In cache: one colour plane at 512x512, march16 on every arch.
  register_roofline(kInCache, 1, Layout::grey, "/grey");
  for (Arch arch : archs) {
    Case c;
    c.method = Method::march16;
    c.arch = arch;
    c.size = kInCache;
    c.layout = Layout::grey;
    register_case(c, "/grey");
  }
}

void add_context() {
  std::string supported;
  for (Arch arch : every_arch()) {
    if (!arch_supported(arch)) continue;
    if (!supported.empty()) supported += ",";
    supported += to_string(arch);
  }
  const StereoCamera stereo = the_scene().recommended_stereo();
  char text[160];
  benchmark::AddCustomContext("reproject_archs", supported);
  benchmark::AddCustomContext("reproject_selected_arch", to_string(selected_arch()));
  // AVX-512's rgba8_srgb reads the sRGB tables by gathers or by permutes, the faster on this
  // processor timed at the first call, unless REPROJECT_SRGB_LOOKUP names one (docs/BEHAVIOUR.md).
  const char* lookup_env = std::getenv("REPROJECT_SRGB_LOOKUP");
  const std::string lookup = lookup_env ? lookup_env : "";
  benchmark::AddCustomContext("reproject_srgb_lookup", lookup == "gathers" || lookup == "permutes"
                                                           ? "REPROJECT_SRGB_LOOKUP=" + lookup
                                                           : std::string("timed at the first call"));
  std::snprintf(text, sizeof text, "%s, standard depth encoding, near %g, far %g", the_scene().name(),
                the_scene().near_plane(), the_scene().far_plane());
  benchmark::AddCustomContext("reproject_scene", text);
  std::snprintf(text, sizeof text, "separation %g, convergence %.6g; 1080p centre->right a = %.4g px, b = %.6g px",
                stereo.separation, stereo.convergence, static_cast<double>(default_model(1920).a),
                static_cast<double>(default_model(1920).b));
  benchmark::AddCustomContext("reproject_stereo", text);
  std::snprintf(text, sizeof text, "%lld bytes/px (RGBA), %lld bytes/px (grey)",
                static_cast<long long>(bytes_per_pixel(Layout::planar_rgba)),
                static_cast<long long>(bytes_per_pixel(Layout::grey)));
  benchmark::AddCustomContext("reproject_bytes_per_pixel", text);
  std::string formats;
  for (const PixelFormat& format : kPixelFormats) {
    formats += std::string(formats.empty() ? "" : ", ") + format.name + " " + std::to_string(bytes_per_pixel(format));
  }
  benchmark::AddCustomContext("reproject_format_bytes_per_pixel", formats + " (bytes/px, colour output only)");
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  add_context();
  register_all();
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
