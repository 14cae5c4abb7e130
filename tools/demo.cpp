// reproject_demo: renders the default ray-cast scene's centre view, synthesises the right eye from
// it with every method, and prints each method's speed, its agreement with `exact` (DESIGN §7)
// and its error against the right eye the ray caster renders directly.
//
//   reproject_demo [--width N] [--height N] [--encoding NAME]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <thread>
#include <vector>

#include "reproject/reproject.hpp"
#include "scene.hpp"

namespace {

using namespace reproject;
namespace rs = reproject::scene;

[[noreturn]] void fail(const char* what, const Status& status) {
  std::fprintf(stderr, "reproject_demo: %s: %s: %s\n", what, to_string(status.code()), status.message());
  std::exit(1);
}

[[noreturn]] void fail(const char* message) {
  std::fprintf(stderr, "reproject_demo: %s\n", message);
  std::exit(2);
}

bool parse_int(const char* text, int* out) {
  char* end = nullptr;
  const long v = std::strtol(text, &end, 10);
  if (end == text || *end != '\0' || v < 1 || v > 65536) return false;
  *out = static_cast<int>(v);
  return true;
}

// One method's outputs, in the layout reproject() writes.
struct Outputs {
  Image color, depth, source_x;
  std::vector<std::uint8_t> status;

  Outputs(int w, int h) : color(w, h, 3), depth(w, h, 1), source_x(w, h, 1), status(static_cast<std::size_t>(w) * h) {}
  bool ok() const { return !color.empty() && !depth.empty() && !source_x.empty(); }
  TargetView view(int w, int h) {
    TargetView t;
    t.color = color.mutable_color();
    t.depth = depth.mutable_plane();
    t.status = BytePlane{status.data(), w, h, w};
    t.source_x = source_x.mutable_plane();
    return t;
  }
  PixelStatus at(int x, int y, int w) const { return static_cast<PixelStatus>(status[static_cast<std::size_t>(y) * w + x]); }
  float sx(int x, int y) const { return source_x.plane_data()[y * source_x.stride() + x]; }
};

struct Row {
  Method method;
  double ms = 0.0;
  double mean_dx = 0.0, max_dx = 0.0, within_half = 0.0, status_mismatch = 0.0;
  double psnr = 0.0, mae = 0.0;
  double hole = 0.0, outside = 0.0, clipped = 0.0;  // % of pixels
};

// Runs fn(first_row, row_step) on up to `threads` threads, rows interleaved.
template <class Fn>
void parallel_rows(int threads, Fn fn) {
  std::vector<std::thread> pool;
  for (int i = 1; i < threads; ++i) pool.emplace_back(fn, i, threads);
  fn(0, threads);
  for (std::thread& t : pool) t.join();
}

}  // namespace

int main(int argc, char** argv) {
  int width = 1920, height = 1080;
  DepthEncoding encoding = DepthEncoding::standard;
  for (int i = 1; i < argc; ++i) {
    const char* arg = argv[i];
    const bool has_value = i + 1 < argc;
    if (std::strcmp(arg, "--width") == 0 && has_value) {
      if (!parse_int(argv[++i], &width)) fail("--width wants an integer in 1..65536");
    } else if (std::strcmp(arg, "--height") == 0 && has_value) {
      if (!parse_int(argv[++i], &height)) fail("--height wants an integer in 1..65536");
    } else if (std::strcmp(arg, "--encoding") == 0 && has_value) {
      if (!parse_encoding(argv[++i], &encoding) || encoding == DepthEncoding::disparity) {
        fail("--encoding wants linear, standard, gl_ndc, reversed, reversed_infinite or infinite");
      }
    } else if (std::strcmp(arg, "--help") == 0 || std::strcmp(arg, "-h") == 0) {
      std::printf("usage: reproject_demo [--width N] [--height N] [--encoding NAME]\n");
      return 0;
    } else {
      std::fprintf(stderr, "reproject_demo: unknown or incomplete argument '%s' (try --help)\n", arg);
      return 2;
    }
  }
  const int threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));

  // --- Scene, camera, the true centre and right views ------------------------------------------
  const rs::Scene scene = rs::Scene::make(rs::SceneId::room);
  const rs::Camera centre = scene.camera(width, height, rs::kCentreEye);
  const rs::Camera right = centre.with_eye(rs::kRightEye);
  const ParallaxModel model = centre.stereo.parallax(width, EyeDirection::centre_to_right);
  if (Status s = model.validate(); !s.ok()) fail("parallax model", s);
  const DepthDecoder decoder = scene.decoder(encoding);
  if (Status s = decoder.validate(); !s.ok()) fail("depth decoder", s);

  const auto r0 = std::chrono::steady_clock::now();
  rs::View centre_view, right_view;
  if (Status s = scene.render(centre, &centre_view); !s.ok()) fail("render centre", s);
  const double render_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - r0).count();
  if (Status s = scene.render(right, &right_view); !s.ok()) fail("render right", s);
  const Image source_depth = rs::encode_depth(centre_view.depth, decoder);
  if (source_depth.empty()) fail("cannot allocate the encoded depth");

  double z_min = INFINITY, z_max = 0.0;
  for (int y = 0; y < height; ++y) {
    const float* z = centre_view.depth.plane_data() + y * centre_view.depth.stride();
    for (int x = 0; x < width; ++x) {
      z_min = std::min(z_min, static_cast<double>(z[x]));
      z_max = std::max(z_max, static_cast<double>(z[x]));
    }
  }
  std::printf("scene %s: %dx%d, horizontal fov %.1f deg, rendered in %.0f ms (%d threads)\n", scene.name(),
              width, height, centre.horizontal_fov * 180.0 / 3.14159265358979323846, render_ms, threads);
  std::printf("stereo: S = %.3f, c = %.4g, eye translation T = %.4g; centre -> right: a = %.4g px, b = %.4g px\n",
              centre.stereo.separation, centre.stereo.convergence, centre.stereo.eye_translation(centre.horizontal_fov),
              static_cast<double>(model.a), static_cast<double>(model.b));
  std::printf("depth: %s, near %.4g, far %.4g; visible z %.4g .. %.4g, parallax %.2f .. %.2f px\n", to_string(encoding),
              scene.near_plane(), scene.far_plane(), z_min, z_max, model.a + model.b / z_min, model.a + model.b / z_max);

  // --- Pixels visible in both views ---------------------------------------------------------------
  // A pixel of the true right view counts when the surface point it shows is also the first
  // surface the centre camera sees in that direction. Decided by tracing, not from the images: take
  // the right eye's hit point P (re-traced in double), project it into the centre view (same row,
  // column u_c), cast the centre ray through (u_c, row) and accept when that ray's first hit is P
  // itself (same depth to 1e-9 relative). u_c must lie within [0, width - 1], the part of the row
  // a reprojection can read from. Only these pixels have a right answer in the centre view, so
  // only they measure a method (disocclusions and the strip the centre never saw are excluded).
  std::vector<std::uint8_t> visible(static_cast<std::size_t>(width) * height, 0);
  parallel_rows(threads, [&](int first, int step) {
    for (int y = first; y < height; y += step) {
      for (int x = 0; x < width; ++x) {
        rs::Hit seen, from_centre;
        if (!scene.trace(right.ray(x, y), &seen)) continue;
        double u = 0.0;
        centre.project(seen.point, &u, nullptr);
        if (!(u >= 0.0 && u <= width - 1.0)) continue;
        if (!scene.trace(centre.ray(u, y), &from_centre)) continue;
        visible[static_cast<std::size_t>(y) * width + x] = std::fabs(from_centre.z - seen.z) <= 1e-9 * seen.z;
      }
    }
  });
  long visible_count = 0;
  for (std::uint8_t v : visible) visible_count += v;
  const double total = static_cast<double>(width) * height;
  std::printf("visible in both views: %.2f %% of the right view\n\n", 100.0 * visible_count / total);

  // --- Run every method ------------------------------------------------------------------------------
  SourceView source;
  source.color = centre_view.color.color();
  source.depth = source_depth.plane(0);

  // Colour error against the true right view over the visible pixels: PSNR over all channels
  // (peak 1) and mean absolute error.
  auto compare_to_truth = [&](const Image& color, double* psnr, double* mae) {
    double se = 0.0, ae = 0.0;
    for (int y = 0; y < height; ++y) {
      for (int x = 0; x < width; ++x) {
        if (!visible[static_cast<std::size_t>(y) * width + x]) continue;
        for (int c = 0; c < 3; ++c) {
          const double d = static_cast<double>(color.plane_data(c)[y * color.stride() + x]) -
                           right_view.color.plane_data(c)[y * right_view.color.stride() + x];
          se += d * d;
          ae += std::fabs(d);
        }
      }
    }
    const double n = 3.0 * visible_count;
    if (visible_count == 0) {  // a tiny frame can have none: nothing to measure, not an error
      *psnr = *mae = NAN;
      return;
    }
    *psnr = se > 0.0 ? 10.0 * std::log10(n / se) : INFINITY;
    *mae = ae / n;
  };

  const Method order[] = {Method::scanline, Method::march16, Method::single, Method::secant, Method::exact};
  // exact runs first: every other method is compared with it.
  const Method run_order[] = {Method::exact, Method::scanline, Method::march16, Method::single, Method::secant};
  Outputs exact_out(width, height);
  if (!exact_out.ok()) fail("cannot allocate the outputs");
  std::vector<Row> rows;
  for (Method method : run_order) {
    Outputs scratch(width, height);
    Outputs& out = method == Method::exact ? exact_out : scratch;
    if (!out.ok()) fail("cannot allocate the outputs");
    Options options;
    options.method = method;
    const TargetView target = out.view(width, height);
    double times[3];
    for (double& t : times) {
      const auto t0 = std::chrono::steady_clock::now();
      const Status s = reproject::reproject(source, decoder, model, options, target);
      t = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
      if (!s.ok()) {
        char what[64];
        std::snprintf(what, sizeof what, "reproject(%s)", to_string(method));
        fail(what, s);
      }
    }
    std::sort(times, times + 3);
    Row row;
    row.method = method;
    row.ms = times[1];

    // Agreement with exact on pixels both call hit; status mismatches over all pixels.
    double sum_dx = 0.0;
    long both_hit = 0, within = 0, mismatch = 0, holes = 0, outside = 0, clipped = 0;
    for (int y = 0; y < height; ++y) {
      for (int x = 0; x < width; ++x) {
        const PixelStatus s = out.at(x, y, width), e = exact_out.at(x, y, width);
        mismatch += s != e;
        holes += s == PixelStatus::hole;
        outside += s == PixelStatus::outside;
        clipped += s == PixelStatus::clipped;
        if (s != PixelStatus::hit || e != PixelStatus::hit) continue;
        const double dx = std::fabs(static_cast<double>(out.sx(x, y)) - exact_out.sx(x, y));
        ++both_hit;
        sum_dx += dx;
        row.max_dx = std::max(row.max_dx, dx);
        within += dx <= 0.5;
      }
    }
    row.mean_dx = both_hit > 0 ? sum_dx / both_hit : 0.0;
    row.within_half = both_hit > 0 ? 100.0 * within / both_hit : 0.0;
    row.status_mismatch = 100.0 * mismatch / total;
    row.hole = 100.0 * holes / total;
    row.outside = 100.0 * outside / total;
    row.clipped = 100.0 * clipped / total;
    compare_to_truth(out.color, &row.psnr, &row.mae);
    rows.push_back(row);
  }

  std::printf("%-9s %9s %9s %10s %9s %9s %9s %9s %9s   %s\n", "method", "ms", "Mpix/s", "mean|dx|", "max|dx|",
              "<=0.5px%", "status!=%", "PSNR dB", "MAE", "hole% outside% clipped%");
  for (Method method : order) {
    const Row& r = *std::find_if(rows.begin(), rows.end(), [&](const Row& x) { return x.method == method; });
    std::printf("%-9s %9.2f %9.1f %10.4f %9.3f %9.3f %9.3f %9.2f %9.5f   %.2f %.2f %.2f\n", to_string(method), r.ms,
                total / (r.ms * 1e3), r.mean_dx, r.max_dx, r.within_half, r.status_mismatch, r.psnr, r.mae, r.hole,
                r.outside, r.clipped);
  }
  // Reference point: the centre view itself, not reprojected, against the true right view.
  double psnr_identity = 0.0, mae_identity = 0.0;
  compare_to_truth(centre_view.color, &psnr_identity, &mae_identity);
  std::printf("\n(no reprojection: the centre view itself scores PSNR %.2f dB, MAE %.5f on the same pixels)\n",
              psnr_identity, mae_identity);
  return 0;
}
