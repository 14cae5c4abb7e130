// `reproject warp` (one view to one eye) and `reproject pair` (a centre view to both eyes).
#include <cstdio>
#include <iterator>

#include "cli.hpp"
#include "imageio/stereo_views.hpp"

namespace reproject::cli {
namespace {

// One target eye's buffers, in the layout reproject() writes.
struct EyeBuffers {
  Image color, depth, source_x;
  std::vector<std::uint8_t> status;

  EyeBuffers(int w, int h, int channels, bool want_source_x)
      : color(w, h, channels), depth(w, h, 1), status(static_cast<std::size_t>(w) * h) {
    if (want_source_x) source_x = Image(w, h, 1);
    if (color.empty() || depth.empty() || (want_source_x && source_x.empty())) {
      fail(kExitRuntime, "out of memory for a " + std::to_string(w) + "x" + std::to_string(h) + " target");
    }
  }
  TargetView view() {
    TargetView t;
    t.color = color.mutable_color();
    t.depth = depth.mutable_plane();
    t.status = BytePlane{status.data(), color.width(), color.height(), color.width()};
    if (!source_x.empty()) t.source_x = source_x.mutable_plane();
    return t;
  }
  // "98.21 % hit, 1.19 % hole, 0.60 % outside, 0.00 % clipped"
  std::string summary() const {
    long n[4] = {0, 0, 0, 0};
    for (std::uint8_t s : status) ++n[s & 3];
    const double total = static_cast<double>(status.size());
    char text[160];
    std::snprintf(text, sizeof text, "%.2f %% hit, %.2f %% hole, %.2f %% outside, %.2f %% clipped", 100.0 * n[0] / total,
                  100.0 * n[1] / total, 100.0 * n[2] / total, 100.0 * n[3] / total);
    return text;
  }
};

// Output depth in the depth file's units (stored value / K), so that it reads back like the input.
Image depth_in_file_units(const Image& depth, double scale) {
  Image out = depth;
  if (out.empty()) fail(kExitRuntime, "out of memory");
  if (scale != 1.0) {
    const float inv = static_cast<float>(1.0 / scale);
    for (int y = 0; y < out.height(); ++y) {
      float* row = out.plane_data() + y * out.stride();
      for (int x = 0; x < out.width(); ++x) row[x] *= inv;
    }
  }
  return out;
}

int depth_png_bits(const Frame& frame) {
  return frame.depth_bits == 8 ? 8 : 16;
}
int color_png_bits(const Frame& frame) {
  return frame.color.bit_depth == 16 ? 16 : 8;
}

void check_png_path(const char* flag, const std::string& path) {
  if (io::format_from_path(path) != io::FileFormat::png) {
    fail(kExitUsage, std::string("--") + flag + ": '" + path + "' must be a .png file (8-bit status values)");
  }
}

void check_float_path(const char* flag, const std::string& path) {
  const io::FileFormat f = io::format_from_path(path);
  if (f != io::FileFormat::pfm && f != io::FileFormat::exr) {
    fail(kExitUsage, std::string("--") + flag + ": '" + path + "' must be a .pfm or .exr file (float values)");
  }
}

int target_width(const Frame& frame, const Options& options) {
  const int w = frame.depth.width() - 2 * options.guard;
  if (w < 1) {
    fail(kExitUsage, "--guard: " + std::to_string(options.guard) + " columns on each side leave no target column of a " +
                         std::to_string(frame.depth.width()) + "-pixel-wide source");
  }
  return w;
}

SourceView source_of(const Frame& frame) {
  SourceView source;
  source.color = frame.color.image.color();
  source.depth = frame.depth.plane(0);
  return source;
}

}  // namespace

int run_warp(int argc, char** argv) {
  std::vector<Flags::Spec> specs = source_flags();
  const auto camera = camera_flags(true, true);
  const auto options = option_flags(true, true, true);
  specs.insert(specs.end(), camera.begin(), camera.end());
  specs.insert(specs.end(), options.begin(), options.end());
  specs.insert(specs.end(), {
      {"out", "FILE", "the target eye's colour (.png, .pfm, .exr)"},
      {"out-depth", "FILE", "its depth, in the source's encoding and file units (.png 16-bit, .pfm, .exr)"},
      {"status", "FILE", "its status, 8-bit .png: 0 hit, 1 hole, 2 outside, 3 clipped"},
      {"source-x", "FILE", "the source column each pixel came from (.pfm, .exr)"},
  });
  Flags flags("warp", specs);
  flags.parse(argc, argv, 2);
  if (flags.help()) {
    std::fputs(flags.usage("--color FILE --depth FILE (--encoding NAME ... --convergence C | --disparity) --out FILE [flags]").c_str(), stdout);
    return kExitOk;
  }
  flags.require("out");
  check_output_path("out", flags.text("out"));
  if (flags.has("out-depth")) check_output_path("out-depth", flags.text("out-depth"));
  if (flags.has("status")) check_png_path("status", flags.text("status"));
  if (flags.has("source-x")) check_float_path("source-x", flags.text("source-x"));
  check_distinct_outputs(flags, {"out", "out-depth", "status", "source-x"});

  const DepthDecoder decoder = decoder_from_flags(flags);
  const Options opts = options_from_flags(flags, true);
  const int dilate = dilate_radius_from_flags(flags);
  flags.require("color");
  flags.require("depth");
  // The model needs the target width, known only from the file; check its flags before reading.
  EyeDirection direction = EyeDirection::centre_to_right;
  (void)model_from_flags(flags, 1, &direction);

  OutputSet out;
  out.inputs(flags, {"color", "depth"});
  out.outputs(flags, {"out", "out-depth", "status", "source-x"});
  Frame frame = load_frame(flags, decoder);
  dilate_depth(&frame.depth, decoder, dilate);
  const int w = target_width(frame, opts), h = frame.depth.height();
  const ParallaxModel model = model_from_flags(flags, w, &direction);

  EyeBuffers eye(w, h, frame.color.image.channels(), flags.has("source-x"));
  check_status(reproject::reproject(source_of(frame), decoder, model, opts, eye.view()), "reproject");

  out.color(flags.text("out"), eye.color.color(), color_png_bits(frame));
  if (flags.has("out-depth")) {
    out.plane(flags.text("out-depth"), depth_in_file_units(eye.depth, frame.depth_scale).plane(0), depth_png_bits(frame));
  }
  if (flags.has("status")) out.bytes(flags.text("status"), eye.status.data(), w, h);
  if (flags.has("source-x")) out.plane(flags.text("source-x"), eye.source_x.plane(0));
  out.commit();
  std::printf("warp %s, %s%s: %dx%d -> %dx%d, %s%s\n", to_string(direction), to_string(opts.method),
              dilate > 0 ? (", depth dilated " + std::to_string(dilate) + " px").c_str() : "", frame.depth.width(), h,
              w, h, eye.summary().c_str(),
              frame.unknown_filled > 0 ? (", " + std::to_string(frame.unknown_filled) + " unknown depths filled").c_str() : "");
  return kExitOk;
}

int run_pair(int argc, char** argv) {
  std::vector<Flags::Spec> specs = source_flags();
  const auto camera = camera_flags(false, false);
  const auto options = option_flags(true, true, true);
  specs.insert(specs.end(), camera.begin(), camera.end());
  specs.insert(specs.end(), options.begin(), options.end());
  specs.insert(specs.end(), {
      {"out-left", "FILE", "left eye colour (.png, .pfm, .exr)"},
      {"out-right", "FILE", "right eye colour"},
      {"out-left-depth", "FILE", "left eye depth (source encoding and file units)"},
      {"out-right-depth", "FILE", "right eye depth"},
      {"status-left", "FILE", "left eye status, 8-bit .png (0 hit, 1 hole, 2 outside, 3 clipped)"},
      {"status-right", "FILE", "right eye status"},
      {"side-by-side", "FILE", "left | right in one image"},
      {"top-bottom", "FILE", "left over right in one image"},
      {"packing", "MODE", "side-by-side and top-bottom: full (twice the size) or half (each eye squeezed) [full]"},
      {"anaglyph", "FILE", "red (left) / cyan (right) anaglyph"},
      {"anaglyph-mode", "MODE", "dubois or plain [dubois]"},
  });
  Flags flags("pair", specs);
  flags.parse(argc, argv, 2);
  if (flags.help()) {
    std::fputs(flags.usage("--color FILE --depth FILE --encoding NAME [--near N --far F] --convergence C OUTPUTS [flags]").c_str(), stdout);
    return kExitOk;
  }
  const char* outputs[] = {"out-left", "out-right", "out-left-depth", "out-right-depth", "status-left",
                           "status-right", "side-by-side", "top-bottom", "anaglyph"};
  bool any = false;
  for (const char* o : outputs) {
    if (!flags.has(o)) continue;
    any = true;
    const std::string path = flags.text(o);
    if (std::string(o).rfind("status", 0) == 0) check_png_path(o, path);
    else check_output_path(o, path);
  }
  check_distinct_outputs(flags, std::vector<const char*>(std::begin(outputs), std::end(outputs)));
  if (!any) {
    fail(kExitUsage, "pair needs at least one output: --out-left, --out-right, --side-by-side, --top-bottom, --anaglyph, ...");
  }
  io::StereoPacking packing = io::StereoPacking::full;
  if (flags.has("packing")) {
    const std::string v = flags.text("packing");
    if (v == "half") packing = io::StereoPacking::half;
    else if (v != "full") flags.bad_value("packing", "unknown packing '" + v + "' (full, half)");
  }
  io::AnaglyphMethod anaglyph_mode = io::AnaglyphMethod::dubois;
  if (flags.has("anaglyph-mode")) {
    const std::string v = flags.text("anaglyph-mode");
    if (v == "plain") anaglyph_mode = io::AnaglyphMethod::plain;
    else if (v != "dubois") flags.bad_value("anaglyph-mode", "unknown anaglyph mode '" + v + "' (dubois, plain)");
  }
  if (flags.text("encoding") == "disparity") {
    flags.bad_value("encoding", "pair synthesises both eyes from a centre view with depth; a disparity map belongs to one eye (use warp --disparity)");
  }
  const DepthDecoder decoder = decoder_from_flags(flags);
  const Options opts = options_from_flags(flags, true);
  const int dilate = dilate_radius_from_flags(flags);
  flags.require("color");
  flags.require("depth");
  (void)model_from_flags(flags, 1, nullptr);

  OutputSet out;
  out.inputs(flags, {"color", "depth"});
  out.outputs(flags, std::vector<const char*>(std::begin(outputs), std::end(outputs)));
  Frame frame = load_frame(flags, decoder);
  dilate_depth(&frame.depth, decoder, dilate);
  const int w = target_width(frame, opts), h = frame.depth.height();
  const ParallaxModel to_right = model_from_flags(flags, w, nullptr);
  const int channels = frame.color.image.channels();
  EyeBuffers left(w, h, channels, false), right(w, h, channels, false);
  check_status(reproject::reproject_pair(source_of(frame), decoder, to_right, opts, left.view(), right.view()),
               "reproject_pair");

  const int bits = color_png_bits(frame);
  if (flags.has("out-left")) out.color(flags.text("out-left"), left.color.color(), bits);
  if (flags.has("out-right")) out.color(flags.text("out-right"), right.color.color(), bits);
  if (flags.has("out-left-depth")) {
    out.plane(flags.text("out-left-depth"), depth_in_file_units(left.depth, frame.depth_scale).plane(0), depth_png_bits(frame));
  }
  if (flags.has("out-right-depth")) {
    out.plane(flags.text("out-right-depth"), depth_in_file_units(right.depth, frame.depth_scale).plane(0), depth_png_bits(frame));
  }
  if (flags.has("status-left")) out.bytes(flags.text("status-left"), left.status.data(), w, h);
  if (flags.has("status-right")) out.bytes(flags.text("status-right"), right.status.data(), w, h);
  if (flags.has("side-by-side")) {
    Image packed;
    check_picture(io::side_by_side(left.color.color(), right.color.color(), &packed, packing), "side-by-side image");
    out.color(flags.text("side-by-side"), packed.color(), bits);
  }
  if (flags.has("top-bottom")) {
    Image packed;
    check_picture(io::top_bottom(left.color.color(), right.color.color(), &packed, packing), "top-bottom image");
    out.color(flags.text("top-bottom"), packed.color(), bits);
  }
  if (flags.has("anaglyph")) {
    // stereo_views works in 0..255 (Dubois clamps there); back to 0..1 for the colour writer.
    const Image l = to_picture_scale(left.color.color()), r = to_picture_scale(right.color.color());
    Image glyph;
    check_picture(io::anaglyph(l.color(), r.color(), &glyph, anaglyph_mode), "anaglyph");
    for (int c = 0; c < glyph.channels(); ++c) {
      for (int y = 0; y < glyph.height(); ++y) {
        float* row = glyph.plane_data(c) + y * glyph.stride();
        for (int x = 0; x < glyph.width(); ++x) row[x] *= 1.0f / 255.0f;
      }
    }
    out.color(flags.text("anaglyph"), glyph.color(), 8);
  }
  out.commit();
  std::printf("pair%s: %dx%d -> 2 x %dx%d; left %s; right %s\n",
              dilate > 0 ? (" (depth dilated " + std::to_string(dilate) + " px)").c_str() : "", frame.depth.width(), h, w, h,
              left.summary().c_str(), right.summary().c_str());
  return kExitOk;
}

}  // namespace reproject::cli
