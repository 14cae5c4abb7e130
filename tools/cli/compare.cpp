// `reproject compare`: every method on one frame or built-in scene. Speed (median of repeats at
// each thread count, against the scalar reference and against a streaming roofline), agreement
// with `exact` (DESIGN §7), and error against the true other eye where there is one.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <functional>
#include <mutex>
#include <thread>

#include "cli.hpp"
#include "imageio/stereo_views.hpp"
#include "quality.hpp"
#include "scene_setup.hpp"

namespace reproject::cli {
namespace {

namespace rs = reproject::scene;
namespace fs = std::filesystem;

// ---- The roofline ---------------------------------------------------------------------------------

// Persistent threads for the roofline loop, so that, like the library's own pool, a timed run
// pays no thread start-up. The calling thread is member 0.
class Crew {
 public:
  explicit Crew(int size) : size_(size) {
    for (int i = 1; i < size; ++i) workers_.emplace_back([this, i] { work(i); });
  }
  ~Crew() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      quit_ = true;
    }
    wake_.notify_all();
    for (std::thread& t : workers_) t.join();
  }
  Crew(const Crew&) = delete;
  Crew& operator=(const Crew&) = delete;

  // Calls job(i, size) once on each member and returns when all have returned.
  void run(const std::function<void(int, int)>& job) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      job_ = &job;
      pending_ = size_ - 1;
      ++generation_;
    }
    wake_.notify_all();
    job(0, size_);
    std::unique_lock<std::mutex> lock(mutex_);
    done_.wait(lock, [this] { return pending_ == 0; });
  }

 private:
  void work(int index) {
    unsigned long seen = 0;
    while (true) {
      const std::function<void(int, int)>* job = nullptr;
      {
        std::unique_lock<std::mutex> lock(mutex_);
        wake_.wait(lock, [&] { return quit_ || generation_ != seen; });
        if (quit_) return;
        seen = generation_;
        job = job_;
      }
      (*job)(index, size_);
      std::lock_guard<std::mutex> lock(mutex_);
      if (--pending_ == 0) done_.notify_one();
    }
  }

  int size_;
  std::vector<std::thread> workers_;
  std::mutex mutex_;
  std::condition_variable wake_, done_;
  const std::function<void(int, int)>* job_ = nullptr;
  unsigned long generation_ = 0;
  int pending_ = 0;
  bool quit_ = false;
};

// The bytes one eye must touch and nothing else: read the depth and colour planes, write colour,
// depth and status, row by row over contiguous bands as the library splits them. A method can
// not be faster than this loop at the same size and thread count (short of skipping outputs).
void stream_band(const SourceView& src, const TargetView& dst, int y0, int y1) {
  const int w = dst.color.width();
  for (int y = y0; y < y1; ++y) {
    for (int c = 0; c < dst.color.channels; ++c) {
      const float* in = src.color.plane[c].row(y);
      float* out = dst.color.plane[c].row(y);
      for (int x = 0; x < w; ++x) out[x] = in[x];
    }
    const float* d = src.depth.row(y);
    float* od = dst.depth.row(y);
    std::uint8_t* st = dst.status.row(y);
    for (int x = 0; x < w; ++x) {
      od[x] = d[x];
      st[x] = 0;
    }
  }
}

// ---- Runs and measures ------------------------------------------------------------------------------

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 == 1 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

struct Target {
  Image color, depth, source_x;
  std::vector<std::uint8_t> status;
  Target(int w, int h, int channels)
      : color(w, h, channels), depth(w, h, 1), source_x(w, h, 1), status(static_cast<std::size_t>(w) * h) {
    if (color.empty() || depth.empty() || source_x.empty()) fail(kExitRuntime, "out of memory for the outputs");
  }
  TargetView view(bool with_source_x) {
    TargetView t;
    t.color = color.mutable_color();
    t.depth = depth.mutable_plane();
    t.status = BytePlane{status.data(), color.width(), color.height(), color.width()};
    if (with_source_x) t.source_x = source_x.mutable_plane();
    return t;
  }
};

struct Result {
  Method method = Method::exact;
  std::vector<double> ms, scalar_ms;  // per thread count: the measured arch, and Arch::scalar
  double mean_dx = 0, max_dx = 0, within_half = 0, status_mismatch = 0;
  Quality quality;                            // against the true eye, when there is one
  double hole = 0, outside = 0, clipped = 0;  // % of pixels
};

// Agreement with exact: |x - x*| on the pixels both hit; status mismatches over all pixels.
void agreement(const Target& out, const Target& exact, Result* r) {
  const int w = out.color.width(), h = out.color.height();
  double sum = 0.0;
  long both = 0, within = 0, mismatch = 0, count[4] = {0, 0, 0, 0};
  r->max_dx = 0.0;
  for (int y = 0; y < h; ++y) {
    const float* sx = out.source_x.plane_data() + y * out.source_x.stride();
    const float* ex = exact.source_x.plane_data() + y * exact.source_x.stride();
    for (int x = 0; x < w; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * w + x;
      const std::uint8_t s = out.status[i], e = exact.status[i];
      mismatch += s != e;
      ++count[s & 3];
      if (s != static_cast<std::uint8_t>(PixelStatus::hit) || e != static_cast<std::uint8_t>(PixelStatus::hit)) continue;
      const double dx = std::fabs(static_cast<double>(sx[x]) - ex[x]);
      ++both;
      sum += dx;
      r->max_dx = std::max(r->max_dx, dx);
      within += dx <= 0.5;
    }
  }
  const double total = static_cast<double>(w) * h;
  r->mean_dx = both > 0 ? sum / both : 0.0;
  r->within_half = both > 0 ? 100.0 * within / both : 100.0;
  r->status_mismatch = 100.0 * mismatch / total;
  r->hole = 100.0 * count[1] / total;
  r->outside = 100.0 * count[2] / total;
  r->clipped = 100.0 * count[3] / total;
}

// Outputs that differ by less than this everywhere (in 0..1) look the same: the methods that
// are exact to rounding (scanline, secant) share one row of the mosaic with exact.
constexpr float kSameColor = 1.0f / 1024.0f;

bool same_color(const Image& a, const Image& b) {
  for (int c = 0; c < a.channels(); ++c) {
    for (int y = 0; y < a.height(); ++y) {
      const float* pa = a.plane_data(c) + y * a.stride();
      const float* pb = b.plane_data(c) + y * b.stride();
      for (int x = 0; x < a.width(); ++x) {
        if (!(std::fabs(pa[x] - pb[x]) < kSameColor)) return false;
      }
    }
  }
  return true;
}

// JSON number, or null for NaN / infinity (JSON has neither).
std::string json_number(double v) {
  if (!std::isfinite(v)) return "null";
  char text[40];
  std::snprintf(text, sizeof text, "%.6g", v);
  return text;
}

std::string json_string(const std::string& s) {
  std::string out = "\"";
  for (char ch : s) {
    if (ch == '"' || ch == '\\') out += '\\';
    if (static_cast<unsigned char>(ch) < 0x20) {
      char esc[8];
      std::snprintf(esc, sizeof esc, "\\u%04x", ch);
      out += esc;
      continue;
    }
    out += ch;
  }
  return out + "\"";
}

// The window of size tw x th whose summed per-pixel error (over the methods that differ from
// exact) is largest: where the methods differ most, for the mosaic.
void worst_window(const std::vector<double>& error, int w, int h, int tw, int th, int* x0, int* y0) {
  // Summed-area table, (w + 1) x (h + 1).
  std::vector<double> sat(static_cast<std::size_t>(w + 1) * (h + 1), 0.0);
  for (int y = 0; y < h; ++y) {
    double row = 0.0;
    for (int x = 0; x < w; ++x) {
      row += error[static_cast<std::size_t>(y) * w + x];
      sat[static_cast<std::size_t>(y + 1) * (w + 1) + x + 1] = sat[static_cast<std::size_t>(y) * (w + 1) + x + 1] + row;
    }
  }
  auto sum = [&](int x, int y) {
    const auto at = [&](int xx, int yy) { return sat[static_cast<std::size_t>(yy) * (w + 1) + xx]; };
    return at(x + tw, y + th) - at(x, y + th) - at(x + tw, y) + at(x, y);
  };
  double best = -1.0;
  *x0 = (w - tw) / 2;
  *y0 = (h - th) / 2;
  for (int y = 0; y + th <= h; y += 8) {
    for (int x = 0; x + tw <= w; x += 8) {
      const double s = sum(x, y);
      if (s > best * (1.0 + 1e-12)) {  // first of equals: deterministic
        best = s;
        *x0 = x;
        *y0 = y;
      }
    }
  }
}

std::string fmt(const char* format, double v) {
  char text[64];
  std::snprintf(text, sizeof text, format, v);
  return text;
}

}  // namespace

int run_compare(int argc, char** argv) {
  static const std::string arch_help = "instruction set measured: " + arch_names() + " [the best supported]";
  std::vector<Flags::Spec> specs = scene_flags();
  const auto source = source_flags();
  const auto camera = camera_flags(true, true);
  const auto options = option_flags(false, false, false);
  specs.insert(specs.end(), source.begin(), source.end());
  specs.insert(specs.end(), camera.begin(), camera.end());
  specs.insert(specs.end(), options.begin(), options.end());
  specs.insert(specs.end(), {
      {"truth", "FILE", "frames: the true target eye (colour), to score PSNR and MAE against"},
      {"truth-mask", "FILE", "frames: .png, nonzero where the truth is visible in both views [exact's hit pixels]"},
      {"methods", "LIST", "comma-separated methods [scanline,march16,single,secant,exact]"},
      {"threads", "LIST", "comma-separated thread counts to time [1,2]"},
      {"repeats", "N", "timed runs per measurement, the median is reported, 1..1000 [5]"},
      {"arch", "NAME", arch_help.c_str()},
      {"json", "FILE", "also write the table as JSON records"},
      {"images", "DIR", "write each method's output, error heat map, status and anaglyph, and methods.png"},
  });
  Flags flags("compare", specs);
  flags.parse(argc, argv, 2);
  if (flags.help()) {
    std::fputs(flags.usage("[--scene NAME --width N --height N | --color FILE --depth FILE ... [--truth FILE]] [flags]").c_str(), stdout);
    return kExitOk;
  }

  // ---- Flags -----------------------------------------------------------------------------------
  const bool frame_mode = flags.has("color") || flags.has("depth");
  if (frame_mode) {
    for (const char* f : {"scene", "width", "height", "fov"}) flags.forbid(f, "--color/--depth (they describe a built-in scene)");
  } else {
    for (const char* f : {"truth", "truth-mask", "near", "far", "depth-scale", "unknown-depth", "disparity"}) {
      flags.forbid(f, "a built-in scene (it has its own)");
    }
  }
  if (flags.has("truth-mask") && !flags.has("truth")) fail(kExitUsage, "--truth-mask needs --truth");
  std::vector<Method> methods;
  for (const std::string& name : flags.list("methods", "scanline,march16,single,secant,exact")) {
    Method m = Method::exact;
    if (!parse_method(name.c_str(), &m)) {
      flags.bad_value("methods", "unknown method '" + name + "' (scanline, march16, single, secant, exact)");
    }
    if (std::find(methods.begin(), methods.end(), m) != methods.end()) flags.bad_value("methods", "'" + name + "' is listed twice");
    methods.push_back(m);
  }
  std::vector<int> thread_counts;
  for (const std::string& t : flags.list("threads", "1,2")) {
    char* end = nullptr;
    const long v = std::strtol(t.c_str(), &end, 10);
    if (!is_decimal(t, true) || end == t.c_str() || *end != '\0' || v < 1 || v > 256) flags.bad_value("threads", "'" + t + "' is not a thread count in 1..256");
    if (std::find(thread_counts.begin(), thread_counts.end(), static_cast<int>(v)) != thread_counts.end()) {
      flags.bad_value("threads", "'" + t + "' is listed twice");
    }
    thread_counts.push_back(static_cast<int>(v));
  }
  const int repeats = flags.integer("repeats", 5, 1, 1000);
  const Arch arch = arch_from_flags(flags);
  const Options base = options_from_flags(flags, false);
  const int dilate = dilate_radius_from_flags(flags);
  const std::string dilate_note = dilate > 0 ? ", dilated " + std::to_string(dilate) + " px (nearer; halo pre-filter)" : "";
  if (flags.has("json") && fs::is_directory(flags.text("json"))) flags.bad_value("json", "'" + flags.text("json") + "' is a directory");
  if (flags.has("truth-mask") && io::format_from_path(flags.text("truth-mask")) != io::FileFormat::png) {
    flags.bad_value("truth-mask", "'" + flags.text("truth-mask") + "' must be a .png file");
  }
  if (frame_mode) {
    (void)decoder_from_flags(flags);
    (void)model_from_flags(flags, 1, nullptr);
  }

  // ---- Outputs, checked (and the images directory created) before the long run ------------------
  OutputSet out;
  out.inputs(flags, {"color", "depth", "truth", "truth-mask"});
  out.outputs(flags, {"json"});
  if (flags.has("images")) {
    const fs::path dir(flags.text("images"));
    out.make_directory(dir.string());
    const bool will_have_truth = !frame_mode || flags.has("truth");
    std::vector<std::string> names = {"source.png", "methods.png"};
    if (will_have_truth) names.insert(names.end(), {"truth.png", "truth_anaglyph.png"});
    for (Method m : methods) {
      for (const char* suffix : {".png", "_error.png", "_status.png", "_anaglyph.png"}) names.push_back(to_string(m) + std::string(suffix));
    }
    for (const std::string& name : names) out.expect("images", (dir / name).string());
  }

  // ---- Source, truth and the pixels that count --------------------------------------------------
  Image source_color, source_depth, truth;
  std::vector<std::uint8_t> measured;  // 1: visible in both views (scored against the truth)
  DepthDecoder decoder;
  ParallaxModel model;
  EyeDirection direction = EyeDirection::centre_to_right;
  std::string description;
  bool truth_mask_from_exact = false;
  if (!frame_mode) {
    const rs::Scene scene = rs::Scene::make(scene_from_flags(flags));
    const DepthEncoding encoding = scene_encoding(flags);
    if (flags.has("direction")) {
      const std::string name = flags.text("direction");
      if (!parse_direction(name.c_str(), &direction)) {
        flags.bad_value("direction", "unknown direction '" + name + "' (left-to-right, right-to-left, centre-to-left, centre-to-right)");
      }
    }
    const rs::Camera centre = scene_camera(flags, scene);
    double from = rs::kCentreEye, to = rs::kRightEye;
    switch (direction) {
      case EyeDirection::left_to_right: from = rs::kLeftEye; to = rs::kRightEye; break;
      case EyeDirection::right_to_left: from = rs::kRightEye; to = rs::kLeftEye; break;
      case EyeDirection::centre_to_left: from = rs::kCentreEye; to = rs::kLeftEye; break;
      case EyeDirection::centre_to_right: from = rs::kCentreEye; to = rs::kRightEye; break;
    }
    const rs::Camera src_cam = centre.with_eye(from), dst_cam = centre.with_eye(to);
    decoder = scene.decoder(encoding);
    check_status(decoder.validate(), "depth decoder");
    model = centre.stereo.parallax(centre.width, direction);
    check_status(model.validate(), "parallax model");
    const auto r0 = std::chrono::steady_clock::now();
    rs::View src_view, dst_view;
    check_status(scene.render(src_cam, &src_view), "render the source view");
    check_status(scene.render(dst_cam, &dst_view), "render the true target view");
    check_status(scene.visible_in_both(dst_cam, src_cam, &measured), "visibility");
    const double render_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - r0).count();
    source_color = std::move(src_view.color);
    truth = std::move(dst_view.color);
    source_depth = rs::encode_depth(src_view.depth, decoder);
    if (source_depth.empty()) fail(kExitRuntime, "out of memory encoding the depth");
    dilate_depth(&source_depth, decoder, dilate);
    float z_min = INFINITY, z_max = 0.0f;
    for (int y = 0; y < src_view.depth.height(); ++y) {
      const float* z = src_view.depth.plane_data() + y * src_view.depth.stride();
      for (int x = 0; x < src_view.depth.width(); ++x) {
        z_min = std::min(z_min, z[x]);
        z_max = std::max(z_max, z[x]);
      }
    }
    char text[512];
    std::snprintf(text, sizeof text,
                  "scene %s: %dx%d, horizontal fov %.4g deg, %s; source, true eye and visibility ray-cast in %.0f ms\n"
                  "stereo: S = %s, c = %s; %s: a = %.4g px, b = %.4g px\n"
                  "depth: %s, near %s, far %s%s; visible z %.4g .. %.4g, parallax %.2f .. %.2f px\n",
                  scene.name(), centre.width, centre.height,
                  centre.horizontal_fov * 180.0 / 3.14159265358979323846, rs::describe(scene.id()),
                  render_ms, exact_number(centre.stereo.separation).c_str(), exact_number(centre.stereo.convergence).c_str(),
                  to_string(direction), static_cast<double>(model.a), static_cast<double>(model.b), to_string(encoding),
                  exact_number(scene.near_plane()).c_str(), exact_number(scene.far_plane()).c_str(), dilate_note.c_str(),
                  static_cast<double>(z_min),
                  static_cast<double>(z_max), static_cast<double>(model.a) + model.b / z_min,
                  static_cast<double>(model.a) + model.b / z_max);
    description = text;
  } else {
    decoder = decoder_from_flags(flags);
    (void)model_from_flags(flags, 1, &direction);
    // Every header before any pixel: the truth and its mask must match the source.
    const io::ImageInfo source_info = frame_info(flags);
    const int w = source_info.width, h = source_info.height;
    auto check_size = [&](const char* what, const std::string& file, const io::ImageInfo& info) {
      if (info.width != w || info.height != h) {
        fail(kExitInput, std::string(what) + " '" + file + "' is " + size_text(info.width, info.height) + " but the source is " +
                             size_text(w, h));
      }
    };
    if (flags.has("truth")) {
      const std::string file = flags.text("truth");
      const io::ImageInfo info = color_info(file);
      check_size("truth", file, info);
      if ((info.channels >= 3) != (source_info.channels >= 3)) {
        fail(kExitInput, "truth '" + file + "' has " + std::to_string(info.channels) + " channels but the source colour has " +
                             std::to_string(source_info.channels) + " (grey vs colour)");
      }
    }
    if (flags.has("truth-mask")) {
      const std::string file = flags.text("truth-mask");
      const io::ImageInfo info = color_info(file);
      if (info.channels != 1) {
        fail(kExitInput, "truth mask '" + file + "' must be a grey PNG (1 channel), this one has " + std::to_string(info.channels));
      }
      check_size("truth mask", file, info);
    }

    Frame frame = load_frame(flags, decoder);
    model = model_from_flags(flags, frame.depth.width(), &direction);
    source_color = std::move(frame.color.image);
    source_depth = std::move(frame.depth);
    dilate_depth(&source_depth, decoder, dilate);
    if (flags.has("truth")) {
      truth = read_color(flags.text("truth")).image;
      if (flags.has("truth-mask")) {
        const io::LoadedImage m = read_depth_file(flags.text("truth-mask"));
        measured.assign(static_cast<std::size_t>(w) * h, 0);
        for (int y = 0; y < h; ++y) {
          for (int x = 0; x < w; ++x) measured[static_cast<std::size_t>(y) * w + x] = m.image.plane_data()[y * m.image.stride() + x] != 0.0f;
        }
      } else {
        truth_mask_from_exact = true;
      }
    }
    char text[512];
    std::snprintf(text, sizeof text, "frame %s: %dx%d, %s depth%s; %s: a = %.4g px, b = %.4g px\n", flags.text("color").c_str(), w, h,
                  to_string(decoder.encoding()), dilate_note.c_str(), to_string(direction), static_cast<double>(model.a), static_cast<double>(model.b));
    description = text;
  }
  const int w = source_depth.width(), h = source_depth.height();
  const int channels = source_color.channels();
  const bool has_truth = !truth.empty();
  SourceView src;
  src.color = source_color.color();
  src.depth = source_depth.plane(0);

  // ---- Quality: one run per method with source x; exact first (the reference) --------------------
  std::vector<Method> quality_order = methods;
  quality_order.erase(std::remove(quality_order.begin(), quality_order.end(), Method::exact), quality_order.end());
  quality_order.insert(quality_order.begin(), Method::exact);
  std::vector<Target> outputs;
  outputs.reserve(quality_order.size());
  std::vector<Result> results;
  for (Method m : quality_order) {
    outputs.emplace_back(w, h, channels);
    Options o = base;
    o.method = m;
    o.arch = arch;
    o.threads = 0;  // the output does not depend on it
    check_status(reproject::reproject(src, decoder, model, o, outputs.back().view(true)), std::string("reproject ") + to_string(m));
    if (m == Method::exact && truth_mask_from_exact) {
      measured.assign(outputs.back().status.size(), 0);
      for (std::size_t i = 0; i < measured.size(); ++i) measured[i] = outputs.back().status[i] == 0;
    }
    Result r;
    r.method = m;
    agreement(outputs.back(), outputs.front(), &r);
    if (has_truth) r.quality = score(outputs.back().color, truth, measured);
    results.push_back(r);
  }

  // ---- Speed -------------------------------------------------------------------------------------
  // Per thread count, every measurement (the roofline, each method at the measured arch and at
  // scalar) is warmed up once, then the repeats are interleaved: repeat k of each one runs before
  // repeat k + 1 of any, so that a change in the machine's background load hits them all alike
  // and the ratios (x scalar, /roofline) stay meaningful on a shared machine.
  Target timed(w, h, channels);
  const TargetView timed_view = timed.view(false);
  std::vector<double> roofline_ms;
  for (int t : thread_counts) {
    Crew crew(t);
    const std::function<void(int, int)> band = [&](int i, int n) {
      stream_band(src, timed_view, static_cast<int>(static_cast<long>(h) * i / n), static_cast<int>(static_cast<long>(h) * (i + 1) / n));
    };
    struct Job {
      std::function<void()> run;
      std::vector<double> ms;
    };
    std::vector<Job> jobs;
    jobs.push_back({[&] { crew.run(band); }, {}});
    // Per listed method: the measured arch, then the scalar reference (one job serves both when
    // they are one).
    std::vector<std::pair<Result*, std::size_t>> arch_job, scalar_job;
    for (Result& r : results) {
      if (std::find(methods.begin(), methods.end(), r.method) == methods.end()) continue;
      std::vector<Arch> archs = {arch};
      if (arch != Arch::scalar) archs.push_back(Arch::scalar);
      for (Arch a : archs) {
        Options o = base;
        o.method = r.method;
        o.arch = a;
        o.threads = t;
        const std::string what = std::string("reproject ") + to_string(r.method);
        jobs.push_back({[&, o, what] { check_status(reproject::reproject(src, decoder, model, o, timed_view), what); }, {}});
        if (a == arch) arch_job.emplace_back(&r, jobs.size() - 1);
        if (a == Arch::scalar) scalar_job.emplace_back(&r, jobs.size() - 1);
      }
    }
    for (Job& j : jobs) j.run();  // warm-up
    for (int k = 0; k < repeats; ++k) {
      for (Job& j : jobs) {
        const auto t0 = std::chrono::steady_clock::now();
        j.run();
        j.ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
      }
    }
    roofline_ms.push_back(median(jobs[0].ms));
    for (const auto& [r, i] : arch_job) r->ms.push_back(median(jobs[i].ms));
    for (const auto& [r, i] : scalar_job) r->scalar_ms.push_back(median(jobs[i].ms));
  }

  // ---- The table -----------------------------------------------------------------------------------
  long measured_count = 0;
  for (std::uint8_t v : measured) measured_count += v;
  const double pixels = static_cast<double>(w) * h;
  std::string report = description;
  if (has_truth) {
    report += fmt("visible in both views (scored): %.2f %% of the target", 100.0 * measured_count / pixels);
    report += truth_mask_from_exact ? " (exact's hit pixels)\n" : "\n";
    report += describe_whole_frame(base, results.front().hole, results.front().outside);
  }
  report += std::string("arch ") + to_string(arch) + ", median of " + std::to_string(repeats) + " runs; roofline (stream " +
            std::to_string(channels + 1) + " planes in, " + std::to_string(channels + 1) + " + status out):";
  for (std::size_t i = 0; i < thread_counts.size(); ++i) {
    report += fmt(" %.2f ms", roofline_ms[i]) + " at " + std::to_string(thread_counts[i]) + (thread_counts[i] == 1 ? " thread" : " threads");
    report += i + 1 < thread_counts.size() ? "," : "\n\n";
  }
  // Header: a column per thread count for each speed measure, then the quality columns.
  const int nt = static_cast<int>(thread_counts.size());
  auto group = [&](const char* title) {
    std::string g = title;
    const std::size_t width = static_cast<std::size_t>(nt) * 8;
    if (g.size() < width) g = std::string(width - g.size(), ' ') + g;
    return g;
  };
  std::string h1 = std::string(9, ' ') + group("Mpix/s") + " " + group("x scalar") + " " + group("/roofline") + " ";
  std::string h2 = "method   ";
  for (int g = 0; g < 3; ++g) {
    for (int t : thread_counts) {
      const std::string col = std::to_string(t) + " thr";
      h2 += std::string(col.size() < 7 ? 7 - col.size() : 0, ' ') + col + " ";
    }
  }
  h1 += "    vs exact:                                  ";
  h2 += "  mean|dx|  max|dx| <=0.5px%  status!=%";
  // With a truth: visible in both, then the statuses, then the whole frame they explain (its
  // title above its first column, or a space after the previous title when that is longer).
  if (has_truth) {
    h1 += "vs true eye, visible in both:";
    h2 += "   PSNR dB      MAE";
  }
  h2 += "  hole% outside% clipped%";
  if (has_truth) {
    h1 += std::string(h1.size() < h2.size() + 3 ? h2.size() + 3 - h1.size() : 1, ' ') + "whole frame:";
    h2 += "   PSNR dB    SSIM";
  }
  report += h1 + "\n" + h2 + "\n";
  std::string json = "[\n";
  bool first_record = true;
  for (Method m : methods) {
    const Result& r = *std::find_if(results.begin(), results.end(), [&](const Result& x) { return x.method == m; });
    std::string line = std::string(to_string(m)) + std::string(9 - std::string(to_string(m)).size(), ' ');
    for (int i = 0; i < nt; ++i) line += fmt("%7.1f ", pixels / (r.ms[i] * 1e3));
    for (int i = 0; i < nt; ++i) line += fmt("%7.2f ", r.scalar_ms[i] / r.ms[i]);
    for (int i = 0; i < nt; ++i) line += fmt("%7.2f ", r.ms[i] / roofline_ms[i]);
    line += fmt("  %8.4f", r.mean_dx) + fmt(" %8.3f", r.max_dx) + fmt(" %8.3f", r.within_half) + fmt(" %9.3f", r.status_mismatch);
    if (has_truth) line += fmt("  %8.2f", r.quality.psnr) + fmt(" %8.5f", r.quality.mae);
    line += fmt("  %5.2f", r.hole) + fmt(" %7.2f", r.outside) + fmt(" %7.2f", r.clipped);
    if (has_truth) line += fmt("  %8.2f", r.quality.psnr_frame) + fmt(" %7.4f", r.quality.ssim_frame);
    report += line + "\n";
    for (int i = 0; i < nt; ++i) {
      json += std::string(first_record ? "" : ",\n") + "  {\"method\": " + json_string(to_string(m)) +
              ", \"arch\": " + json_string(to_string(arch)) + ", \"threads\": " + std::to_string(thread_counts[i]) +
              ", \"mpix_per_s\": " + json_number(pixels / (r.ms[i] * 1e3)) +
              ", \"speedup_vs_scalar\": " + json_number(r.scalar_ms[i] / r.ms[i]) +
              ", \"time_vs_roofline\": " + json_number(r.ms[i] / roofline_ms[i]) +
              ", \"mean_abs_dx\": " + json_number(r.mean_dx) + ", \"max_abs_dx\": " + json_number(r.max_dx) +
              ", \"within_half_px\": " + json_number(r.within_half) + ", \"status_mismatch\": " + json_number(r.status_mismatch) +
              ", \"psnr\": " + json_number(r.quality.psnr) + ", \"mae\": " + json_number(r.quality.mae) +
              ", \"psnr_whole_frame\": " + json_number(r.quality.psnr_frame) +
              ", \"ssim_whole_frame\": " + json_number(r.quality.ssim_frame) + ", \"hole\": " + json_number(r.hole) +
              ", \"outside\": " + json_number(r.outside) + ", \"clipped\": " + json_number(r.clipped) +
              ", \"ms\": " + json_number(r.ms[i]) + ", \"scalar_ms\": " + json_number(r.scalar_ms[i]) +
              ", \"roofline_ms\": " + json_number(roofline_ms[i]) + ", \"width\": " + std::to_string(w) +
              ", \"height\": " + std::to_string(h) + ", \"dilate_depth\": " + std::to_string(dilate) + "}";
      first_record = false;
    }
  }
  json += "\n]\n";
  if (has_truth) {
    const Quality q = score(source_color, truth, measured);
    report += fmt("\n(no reprojection: the source view itself scores PSNR %.2f dB", q.psnr) + fmt(", MAE %.5f on the same pixels", q.mae) +
              fmt("; whole frame PSNR %.2f dB", q.psnr_frame) + fmt(", SSIM %.4f)\n", q.ssim_frame);
  }
  std::fputs(report.c_str(), stdout);
  std::fflush(stdout);

  // ---- Files -----------------------------------------------------------------------------------------
  if (flags.has("json")) out.text(flags.text("json"), json);
  if (flags.has("images")) {
    const fs::path dir(flags.text("images"));
    const bool target_is_right = direction == EyeDirection::left_to_right || direction == EyeDirection::centre_to_right;
    // Error maps against the truth; without one, against exact's output (every pixel counts).
    const Image& reference = has_truth ? truth : outputs.front().color;
    std::vector<std::uint8_t> all(static_cast<std::size_t>(w) * h, 1);
    const std::vector<std::uint8_t>& mask = has_truth ? measured : all;
    constexpr float kFullScale = 64.0f;  // of 255: an error of a quarter of the range is white
    const Image source_picture = to_picture_scale(source_color.color());
    const Image reference_picture = to_picture_scale(reference.color());
    out.picture((dir / "source.png").string(), source_picture);
    if (has_truth) out.picture((dir / "truth.png").string(), reference_picture);
    if (has_truth) {
      Image glyph;
      check_picture(target_is_right ? io::anaglyph(source_picture.color(), reference_picture.color(), &glyph)
                                    : io::anaglyph(reference_picture.color(), source_picture.color(), &glyph),
                    "anaglyph");
      out.picture((dir / "truth_anaglyph.png").string(), glyph);
    }
    std::vector<Image> heat(quality_order.size()), pictures(quality_order.size());
    std::vector<double> error_sum(static_cast<std::size_t>(w) * h, 0.0);
    for (std::size_t i = 0; i < quality_order.size(); ++i) {
      const std::string name = to_string(quality_order[i]);
      const bool listed = std::find(methods.begin(), methods.end(), quality_order[i]) != methods.end();
      pictures[i] = to_picture_scale(outputs[i].color.color());
      check_picture(io::error_heat_map(pictures[i].color(), reference_picture.color(), &heat[i], kFullScale), "error heat map");
      mark_unmeasured(&heat[i], mask.data());
      if (!listed) continue;  // exact ran as the reference only
      out.picture((dir / (name + ".png")).string(), pictures[i]);
      out.picture((dir / (name + "_error.png")).string(), heat[i]);
      Image status;
      check_picture(io::status_image(BytePlane{outputs[i].status.data(), w, h, w}, &status), "status image");
      out.picture((dir / (name + "_status.png")).string(), status);
      Image glyph;
      check_picture(target_is_right ? io::anaglyph(source_picture.color(), pictures[i].color(), &glyph)
                                    : io::anaglyph(pictures[i].color(), source_picture.color(), &glyph),
                    "anaglyph");
      out.picture((dir / (name + "_anaglyph.png")).string(), glyph);
    }
    // methods.png: rows of (output | error) crops at 1:1, one row per visibly distinct output
    // (methods within kSameColour of each other share a row, named "a ~ b"), where the methods
    // differ most; the first row shows the reference and the source.
    std::vector<std::size_t> shown;        // indices into quality_order, in `methods` order
    std::vector<std::string> row_names;
    for (Method m : methods) {
      const std::size_t i = static_cast<std::size_t>(std::find(quality_order.begin(), quality_order.end(), m) - quality_order.begin());
      bool merged = false;
      for (std::size_t k = 0; k < shown.size(); ++k) {
        if (same_color(outputs[shown[k]].color, outputs[i].color)) {
          row_names[k] += std::string(" ~ ") + to_string(m);
          merged = true;
          break;
        }
      }
      if (merged) continue;
      shown.push_back(i);
      row_names.push_back(to_string(m));
      if (same_color(outputs[i].color, outputs.front().color)) continue;  // no worse than exact
      for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
          const std::size_t p = static_cast<std::size_t>(y) * w + x;
          if (!mask[p]) continue;
          error_sum[p] += heat[i].plane_data(0)[y * heat[i].stride() + x] + heat[i].plane_data(1)[y * heat[i].stride() + x];
        }
      }
    }
    const int tile_w = std::min(w, 474), tile_h = std::min(h, std::max(1, tile_w * 9 / 16));
    int x0 = 0, y0 = 0;
    worst_window(error_sum, w, h, tile_w, tile_h, &x0, &y0);
    std::vector<Image> tiles;
    tiles.reserve(2 + 2 * shown.size());
    const int scale = tile_w >= 300 ? 2 : 1;
    tiles.push_back(crop(reference_picture, x0, y0, tile_w, tile_h));
    label(&tiles.back(), 4, 4, has_truth ? "true eye" : "exact", scale);
    tiles.push_back(crop(source_picture, x0, y0, tile_w, tile_h));
    label(&tiles.back(), 4, 4, "source view", scale);
    for (std::size_t k = 0; k < shown.size(); ++k) {
      tiles.push_back(crop(pictures[shown[k]], x0, y0, tile_w, tile_h));
      label(&tiles.back(), 4, 4, row_names[k], scale);
      tiles.push_back(crop(heat[shown[k]], x0, y0, tile_w, tile_h));
      label(&tiles.back(), 4, 4, has_truth ? "error vs true eye" : "difference from exact", scale);
    }
    std::vector<const Image*> refs;
    for (const Image& t : tiles) refs.push_back(&t);
    out.picture((dir / "methods.png").string(), mosaic(refs, 2, 4));
    std::printf("\nimages: %s (methods.png: crops at x %d..%d, y %d..%d)\n", dir.string().c_str(), x0, x0 + tile_w - 1, y0,
                y0 + tile_h - 1);
  }
  out.commit();
  if (flags.has("json")) std::printf("json: %s\n", flags.text("json").c_str());
  return kExitOk;
}

}  // namespace reproject::cli
