// `reproject budget`: the parallax budget of a depth buffer (a file, or a built-in scene's centre
// view) under a stereo camera: parallax_budget's figures as a table, and its histogram as a
// picture with the comfort limits marked.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "cli.hpp"
#include "reproject/stereo.hpp"
#include "scene_setup.hpp"

namespace reproject::cli {
namespace {

namespace rs = reproject::scene;

std::string fmt(const char* format, double v) {
  char text[64];
  std::snprintf(text, sizeof text, format, v);
  return text;
}

// ---- The histogram picture --------------------------------------------------------------------

constexpr int kPictureWidth = 1024, kPictureHeight = 512;
constexpr int kPlotLeft = 72, kPlotRight = kPictureWidth - 24, kPlotTop = 72, kPlotBottom = kPictureHeight - 56;
constexpr int kMaxBins = kPlotRight - kPlotLeft;  // at least one picture column per bar

struct Rgb {
  float r, g, b;
};
constexpr Rgb kBackground = {28, 28, 32};
constexpr Rgb kAxis = {150, 150, 150};
constexpr Rgb kComfortable = {90, 150, 220};
constexpr Rgb kBeyondLimit = {225, 60, 60};
constexpr Rgb kNearer = {255, 160, 40};
constexpr Rgb kFarther = {175, 110, 255};
constexpr Rgb kZero = {220, 220, 220};

// A vertical line at parallax `p` and what it stands for.
struct Mark {
  double p;
  Rgb color;
  bool dashed;
  std::string name;
};
// A legend entry: a swatch and its meaning.
struct Key {
  Rgb color;
  std::string text;
};

class Canvas {
 public:
  Canvas() : image_(kPictureWidth, kPictureHeight, 3) {
    if (image_.empty()) fail(kExitRuntime, "out of memory for the histogram picture");
    fill(0, 0, kPictureWidth, kPictureHeight, kBackground);
  }
  void fill(int x0, int y0, int x1, int y1, Rgb c) {  // [x0, x1) x [y0, y1), clipped
    x0 = std::max(x0, 0), y0 = std::max(y0, 0);
    x1 = std::min(x1, image_.width()), y1 = std::min(y1, image_.height());
    for (int y = y0; y < y1; ++y) {
      for (int x = x0; x < x1; ++x) {
        image_.plane_data(0)[y * image_.stride() + x] = c.r;
        image_.plane_data(1)[y * image_.stride() + x] = c.g;
        image_.plane_data(2)[y * image_.stride() + x] = c.b;
      }
    }
  }
  void text(int x, int y, const std::string& s, int scale = 1) { label(&image_, x, y, s, scale); }
  Image& image() { return image_; }

 private:
  Image image_;
};

// Picture column of parallax p on the plot's axis [lo, hi].
int column_of(double p, double lo, double hi) {
  return kPlotLeft + static_cast<int>(std::lround((p - lo) / (hi - lo) * (kPlotRight - kPlotLeft)));
}

// A "nice" tick step (1, 2 or 5 times a power of ten) giving about `target` ticks over `span`.
double tick_step(double span, int target) {
  const double raw = span / target;
  const double power = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 5.0}) {
    if (m * power >= raw) return m * power;
  }
  return 10.0 * power;
}

std::string number_text(double v) {
  if (std::fabs(v) < 1e-9) v = 0.0;
  char t[32];
  std::snprintf(t, sizeof t, "%g", v);
  return t;
}

Image histogram_picture(const ParallaxBudget& b, const std::vector<std::int64_t>& counts, const std::vector<Mark>& marks,
                        const std::vector<Key>& keys, double half_convergence_p, double far_p, const std::string& title) {
  Canvas canvas;
  const int bins = static_cast<int>(counts.size());
  const double lo = b.histogram_min, hi = b.histogram_max;
  const std::int64_t peak = std::max<std::int64_t>(1, *std::max_element(counts.begin(), counts.end()));
  const int plot_w = kPlotRight - kPlotLeft, plot_h = kPlotBottom - kPlotTop;

  // Bars, coloured by where their centre lies: nearer than c/2, farther than 100 c, beyond the
  // parallax limit, or comfortable.
  for (int i = 0; i < bins; ++i) {
    const int x0 = kPlotLeft + static_cast<int>(static_cast<long>(i) * plot_w / bins);
    int x1 = kPlotLeft + static_cast<int>(static_cast<long>(i + 1) * plot_w / bins);
    if (x1 - x0 >= 4) --x1;  // a one-pixel gap between wide bars
    const double centre = lo + (i + 0.5) * (hi - lo) / bins;
    Rgb color = kComfortable;
    if (centre < half_convergence_p) color = kNearer;
    else if (centre > far_p) color = kFarther;
    else if (std::fabs(centre) > b.parallax_limit) color = kBeyondLimit;
    const double share = static_cast<double>(counts[static_cast<std::size_t>(i)]) / static_cast<double>(peak);
    int height = static_cast<int>(std::lround(share * plot_h));
    if (counts[static_cast<std::size_t>(i)] > 0) height = std::max(height, 1);  // present, however few
    canvas.fill(x0, kPlotBottom - height, std::max(x1, x0 + 1), kPlotBottom, color);
  }

  // Axes, ticks and their values.
  canvas.fill(kPlotLeft, kPlotBottom, kPlotRight + 1, kPlotBottom + 2, kAxis);
  canvas.fill(kPlotLeft - 2, kPlotTop, kPlotLeft, kPlotBottom + 2, kAxis);
  const double step = tick_step(hi - lo, 8);
  for (double t = std::ceil(lo / step) * step; t <= hi + step * 1e-9; t += step) {
    const int x = column_of(t, lo, hi);
    canvas.fill(x, kPlotBottom + 2, x + 1, kPlotBottom + 8, kAxis);
    const std::string v = number_text(t);
    canvas.text(x - static_cast<int>(v.size()) * 6 / 2, kPlotBottom + 10, v);
  }
  canvas.text(kPlotLeft + plot_w / 2 - 90, kPlotBottom + 30, "parallax, display pixels (left to right)");
  // One label row (11 px) above the plot, below the legend's off-the-chart line with a row between.
  canvas.text(kPlotLeft, kPlotTop - 11, "peak " + std::to_string(peak) + " pixels (" +
                                            fmt("%.2f", 100.0 * static_cast<double>(peak) / static_cast<double>(b.pixels)) +
                                            " % of the pixels)");

  // The comfort limits, drawn over the bars; those off the chart are named in the legend.
  std::string off_chart;
  for (const Mark& m : marks) {
    if (m.p < lo || m.p > hi) {
      off_chart += (off_chart.empty() ? "off the chart: " : ", ") + m.name;
      continue;
    }
    const int x = std::min(column_of(m.p, lo, hi), kPlotRight - 1);
    for (int y = kPlotTop; y < kPlotBottom; y += m.dashed ? 8 : plot_h) {
      canvas.fill(x - 1, y, x + 1, m.dashed ? std::min(y + 5, kPlotBottom) : kPlotBottom, m.color);
    }
  }

  // Title and legend: coloured swatches with their meaning.
  canvas.text(8, 8, title, 2);
  int x = 8;
  for (const Key& k : keys) {
    canvas.fill(x, 36, x + 10, 46, k.color);
    canvas.text(x + 14, 36, k.text);
    x += 14 + static_cast<int>(k.text.size()) * 6 + 4 + 16;
  }
  if (!off_chart.empty()) canvas.text(8, kPlotTop - 23, off_chart);
  return std::move(canvas.image());
}

}  // namespace

int run_budget(int argc, char** argv) {
  std::vector<Flags::Spec> specs = scene_flags();
  for (const Flags::Spec& s : source_flags()) {
    if (std::string(s.name) != "color") specs.push_back(s);
  }
  specs.insert(specs.end(), {
      {"separation", "S", "stereo separation, a fraction of the image width, 0..1 [0.03]"},
      {"convergence", "C", "view-space distance of the zero-parallax plane [the scene's: 3.5; required with --depth]"},
      {"interocular", "M", "viewer's eye separation, with --screen-width (same unit) [E = S]"},
      {"screen-width", "M", "physical width of the displayed image, with --interocular"},
      {"limit", "PX", "largest comfortable |parallax|, display pixels [E x width: parallel eyes]"},
      {"bins", "N", "histogram bars, 1..928 [64]"},
      {"histogram", "FILE", "write the histogram as a 1024x512 8-bit .png picture"},
  });
  Flags flags("budget", specs);
  flags.parse(argc, argv, 2);
  if (flags.help()) {
    std::fputs(flags.usage("(--depth FILE --encoding NAME [--near N --far F] --convergence C | --scene NAME [--width N "
                           "--height N]) [--separation S] [--interocular M --screen-width M] [--limit PX] [--bins N] "
                           "[--histogram FILE.png]")
                   .c_str(),
               stdout);
    return kExitOk;
  }

  // ---- Flags, all checked before any work ---------------------------------------------------------
  const bool file_mode = flags.has("depth");
  if (file_mode) {
    for (const char* f : {"scene", "width", "height", "fov"}) flags.forbid(f, "--depth (they describe a built-in scene)");
  } else {
    for (const char* f : {"near", "far", "depth-scale", "unknown-depth"}) flags.forbid(f, "a built-in scene (it has its own)");
  }
  if (flags.has("histogram")) {
    const std::string h = flags.text("histogram");
    if (io::format_from_path(h) != io::FileFormat::png) flags.bad_value("histogram", "'" + h + "' must be a .png file (a picture)");
  }
  const int bins = flags.integer("bins", 64, 1, kMaxBins);
  if (flags.has("interocular") != flags.has("screen-width")) {
    fail(kExitUsage, flags.has("interocular") ? "--interocular needs --screen-width M" : "--screen-width needs --interocular M");
  }
  BudgetOptions options;
  options.histogram_bins = 0;
  if (flags.has("interocular")) {
    const double interocular = flags.number("interocular", 0.0, 0.0, HUGE_VAL, true);
    const double screen = flags.number("screen-width", 0.0, 0.0, HUGE_VAL, true);
    options.eye_separation = interocular / screen;
  }
  if (flags.has("limit")) options.parallax_limit = flags.number("limit", 0.0, 0.0, 1e9);

  DepthDecoder decoder;
  StereoCamera camera;
  std::string source;
  Image depth;
  long unknown_filled = 0;
  if (file_mode) {
    if (flags.text("encoding") == "disparity" || flags.has("disparity")) {
      flags.bad_value("encoding", "a budget needs depth; a disparity map is already the parallax");
    }
    decoder = decoder_from_flags(flags);
    flags.require("convergence");
    camera.separation = flags.number("separation", 0.03, 0.0, 1.0);
    camera.convergence = flags.number("convergence", 0.0, 0.0, HUGE_VAL, true);
  } else {
    (void)scene_from_flags(flags);
    (void)scene_encoding(flags);
  }
  if (flags.has("separation") && flags.number("separation", 0.03) == 0.0 && !options.eye_separation) {
    flags.bad_value("separation", "0 is no stereo; the eye separation then needs --interocular and --screen-width");
  }

  OutputSet out;
  out.inputs(flags, {"depth"});
  out.outputs(flags, {"histogram"});

  // ---- The depth -------------------------------------------------------------------------------------
  if (file_mode) {
    DepthFile file = load_depth(flags, decoder);
    depth = std::move(file.depth);
    unknown_filled = file.unknown_filled;
    char text[512];
    std::snprintf(text, sizeof text, "depth %s: %dx%d, %s", flags.text("depth").c_str(), depth.width(), depth.height(),
                  to_string(decoder.encoding()));
    source = text;
    if (decoder.encoding() != DepthEncoding::linear) source += ", near " + exact_number(decoder.near_plane());
    if (flags.has("far")) source += ", far " + exact_number(decoder.far_plane());
    if (file.scale != 1.0) source += ", scale " + exact_number(file.scale);
    if (unknown_filled > 0) source += ", " + std::to_string(unknown_filled) + " unknown depths filled";
  } else {
    const rs::Scene scene = rs::Scene::make(scene_from_flags(flags));
    const DepthEncoding encoding = scene_encoding(flags);
    const rs::Camera centre = scene_camera(flags, scene);
    camera = centre.stereo;
    decoder = scene.decoder(encoding);
    check_status(decoder.validate(), "depth decoder");
    rs::View view;
    check_status(scene.render(centre, &view), "render the centre view");
    depth = rs::encode_depth(view.depth, decoder);
    if (depth.empty()) fail(kExitRuntime, "out of memory encoding the depth");
    char text[512];
    std::snprintf(text, sizeof text, "scene %s: %dx%d centre view, horizontal fov %.4g deg, %s depth, near %s, far %s",
                  scene.name(), centre.width, centre.height, centre.horizontal_fov * 180.0 / 3.14159265358979323846,
                  to_string(encoding), exact_number(scene.near_plane()).c_str(), exact_number(scene.far_plane()).c_str());
    source = text;
  }

  // ---- The budget: once for the figures and the parallax present, once for the histogram over a
  // range that also shows the comfort limits near it --------------------------------------------------
  ParallaxBudget b;
  check_status(parallax_budget(depth.plane(0), decoder, camera, options, &b), "parallax_budget");
  const double sw = camera.separation * b.display_width;
  const double half_convergence_p = -sw, far_p = 0.99 * sw;  // z = c/2 and z = 100 c
  // Solid lines first, so that a dashed limit on the same column still shows over them.
  std::vector<Mark> marks;
  if (sw > 0.0) {
    marks.push_back({half_convergence_p, kNearer, false, "z = c/2 (" + fmt("%.4g", half_convergence_p) + " px)"});
    marks.push_back({far_p, kFarther, false, "z = 100 c (" + fmt("%.4g", far_p) + " px)"});
  }
  marks.push_back({-b.parallax_limit, kBeyondLimit, true, "limit -" + fmt("%.4g", b.parallax_limit) + " px"});
  marks.push_back({b.parallax_limit, kBeyondLimit, true, "limit +" + fmt("%.4g", b.parallax_limit) + " px"});
  marks.push_back({0.0, kZero, true, "0: z = c"});
  std::vector<Key> keys = {{kComfortable, "comfortable"},
                           {kBeyondLimit, "beyond the limit +-" + fmt("%.4g", b.parallax_limit) + " px"}};
  if (sw > 0.0) {
    keys.push_back({kNearer, "nearer than c/2: p under " + fmt("%.4g", half_convergence_p)});
    keys.push_back({kFarther, "farther than 100 c: p over " + fmt("%.4g", far_p)});
  }
  keys.push_back({kZero, "p = 0: z = c"});
  double lo = b.histogram_min, hi = b.histogram_max;
  const double span = hi - lo;
  for (const Mark& m : marks) {
    // A limit within half the content's span of it is drawn; farther ones would squash the bars.
    if (m.p < lo && m.p >= b.histogram_min - 0.5 * span) lo = m.p;
    if (m.p > hi && m.p <= b.histogram_max + 0.5 * span) hi = m.p;
  }
  const double pad = 0.03 * (hi - lo);
  options.histogram_bins = bins;
  options.histogram_min = lo - pad;
  options.histogram_max = hi + pad;
  std::vector<std::int64_t> counts(static_cast<std::size_t>(bins), 0);
  check_status(parallax_budget(depth.plane(0), decoder, camera, options, &b, counts.data()), "parallax_budget");

  if (flags.has("histogram")) {
    const Image picture = histogram_picture(b, counts, marks, keys, half_convergence_p, far_p,
                                            "parallax histogram, " + std::to_string(b.display_width) + " px wide, " +
                                                std::to_string(bins) + " bins");
    out.picture(flags.text("histogram"), picture);
  }
  out.commit();

  // ---- The table ----------------------------------------------------------------------------------------
  std::string report = "budget " + source + "\n";
  report += "stereo: S = " + exact_number(camera.separation) + ", c = " + exact_number(camera.convergence) +
            "; display width W = " + std::to_string(b.display_width) + " px\n";
  report += "eye separation E = " + fmt("%.6g", b.eye_separation) +
            (flags.has("interocular") ? " (interocular / screen width)" : " (unset: the camera's S)") +
            "; parallel eyes at E W = " + fmt("%.3f", b.eye_parallax) + " px; limit " + fmt("%.3f", b.parallax_limit) +
            (flags.has("limit") ? " px\n\n" : " px (E W)\n\n");
  report += "          parallax px    of eyes\n";
  auto row = [&](const std::string& name, double px, double eyes) {
    std::string line = "  " + name;
    line.resize(10, ' ');
    report += line + fmt("%13.3f", px) + fmt("%11.4f", eyes) + "\n";
  };
  row("min", b.min, b.min_of_eyes);
  for (int i = 0; i < kBudgetPercentileCount; ++i) {
    row("p" + fmt("%g", kBudgetPercentiles[i]), b.percentile[i], b.percentile_of_eyes[i]);
  }
  row("max", b.max, b.max_of_eyes);
  const double c = camera.convergence;
  report += "\npixels " + std::to_string(b.pixels) + " (" + std::to_string(b.unreadable) + " unreadable: NaN or behind the eye, measured as infinitely far)\n";
  auto share = [&](const std::string& name, double s) {
    std::string line = name;
    line.resize(40, ' ');
    report += line + fmt("%8.3f %%", 100.0 * s) + "\n";
  };
  share("beyond the limit (|p| > " + fmt("%.4g", b.parallax_limit) + " px)", b.beyond_limit);
  share("nearer than c/2 (z < " + fmt("%.4g", c / 2) + ")", b.nearer_than_half_convergence);
  share("farther than 100 c (z > " + fmt("%.4g", 100 * c) + ")", b.farther_than_100_convergence);
  share("uncomfortable (any of them)", b.uncomfortable);
  report += "histogram: " + std::to_string(bins) + " bins over " + fmt("%.3f", b.histogram_min) + " .. " +
            fmt("%.3f", b.histogram_max) + " px; " + std::to_string(b.below_histogram) + " below, " +
            std::to_string(b.above_histogram) + " above" +
            (flags.has("histogram") ? "; written to " + flags.text("histogram") : std::string()) + "\n";
  std::fputs(report.c_str(), stdout);
  return kExitOk;
}

}  // namespace reproject::cli
