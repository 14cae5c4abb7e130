// `reproject warp` (one view to one eye) and `reproject pair` (a centre view to both eyes).
#include <cstdio>
#include <iterator>
#include <new>

#include "cli.hpp"
#include "imageio/stereo_views.hpp"

namespace reproject::cli {
namespace {

// Appended to --help: which path the colour takes, and the raw layout (docs/CLI.md).
const char kNativeHelp[] =
    "\n"
    "Colour is reprojected in the file's own format when every colour output has the input's file type and\n"
    "depth: an 8-bit PNG as rgba8 (--color-space srgb: rgba8_srgb), a half EXR as rgba16f; otherwise as\n"
    "floats (always with --float-color). The summary line names the path taken (\"colour rgba8 (native)\").\n"
    "A .raw input is an engine buffer's bytes: --size WxH, rows packed (stride W x bytes per pixel), words\n"
    "little-endian; its format is --color-format / --depth-format. Outputs of a .raw input keep its format.\n";

// One target eye's buffers, in the layout and formats reproject() writes for `frame`: float
// planes, or the source's packed colour format and raw depth format.
struct EyeBuffers {
  Image color, depth, source_x;
  io::PackedColor packed;  // native colour
  RawDepth raw_depth;      // raw depth, in the source's format and range
  std::vector<std::uint8_t> status;
  int width = 0, height = 0;

  EyeBuffers(int w, int h, const Frame& frame, bool want_source_x) : width(w), height(h) {
    bool allocated = true;
    try {
      status.resize(static_cast<std::size_t>(w) * h);
      if (frame.native_color()) {
        packed.width = w;
        packed.height = h;
        packed.channels = frame.packed_color.channels;
        packed.format = frame.packed_color.format;
        packed.bytes.resize(static_cast<std::size_t>(packed.stride()) * h);
      } else {
        color = Image(w, h, frame.color_channels());
      }
      if (frame.native_depth()) {
        raw_depth = frame.raw_depth;  // the format and range; then the target's size
        raw_depth.width = w;
        raw_depth.height = h;
        raw_depth.bytes.assign(static_cast<std::size_t>(raw_depth.stride()) * h, 0);
      } else {
        depth = Image(w, h, 1);
      }
      if (want_source_x) source_x = Image(w, h, 1);
    } catch (const std::bad_alloc&) {
      allocated = false;
    }
    allocated = allocated && (frame.native_color() || !color.empty()) && (frame.native_depth() || !depth.empty()) &&
                (!want_source_x || !source_x.empty());
    if (!allocated) fail(kExitRuntime, "out of memory for a " + std::to_string(w) + "x" + std::to_string(h) + " target");
  }
  TargetView view() {
    TargetView t;
    if (!packed.bytes.empty()) t.color = packed.mutable_view();
    else t.color = color.mutable_color();
    if (!raw_depth.bytes.empty()) t.depth_buffer = raw_depth.mutable_view();
    else t.depth = depth.mutable_plane();
    t.status = BytePlane{status.data(), width, height, width};
    if (!source_x.empty()) t.source_x = source_x.mutable_plane();
    return t;
  }
  // The colour as 0..1 floats with the source's channels (the stereo pictures are made in float).
  Image float_color() const { return !packed.bytes.empty() ? float_color_of(packed.view(), packed.channels) : color; }
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
// An EXR colour output keeps a half EXR input's type, as a PNG output keeps its bit depth.
bool color_exr_half(const Frame& frame) {
  return frame.color.format == io::FileFormat::exr && frame.color.bit_depth == 16;
}

void write_color(OutputSet& out, const std::string& path, const EyeBuffers& eye, const Frame& frame) {
  if (frame.native_color()) out.packed_color(path, eye.packed.view(), eye.packed.channels);
  else out.color(path, eye.color.color(), color_png_bits(frame), color_exr_half(frame));
}

// A picture made from both eyes (float), in the file type and depth the eyes would be written in.
void write_picture(OutputSet& out, const std::string& path, const Image& picture, const Frame& frame) {
  out.color(path, picture.color(), color_png_bits(frame), color_exr_half(frame));
}

void write_depth(OutputSet& out, const std::string& path, const EyeBuffers& eye, const Frame& frame) {
  if (!frame.native_depth()) {
    out.plane(path, depth_in_file_units(eye.depth, frame.depth_scale).plane(0), depth_png_bits(frame));
  } else if (is_raw_path(path)) {
    const RawDepth& d = eye.raw_depth;
    out.raw(path, d.bytes.data(), static_cast<std::size_t>(d.stride()), d.height, d.stride(), raw_word_bytes(d.format));
  } else {
    out.plane(path, stored_depth_values(eye.raw_depth).plane(0));
  }
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
  const int w = frame.width() - 2 * options.guard;
  if (w < 1) {
    fail(kExitUsage, "--guard: " + std::to_string(options.guard) + " columns on each side leave no target column of a " +
                         std::to_string(frame.width()) + "-pixel-wide source");
  }
  return w;
}

// Source flags, the native-format flags, then the camera and the options.
std::vector<Flags::Spec> frame_flags(bool warp) {
  std::vector<Flags::Spec> specs = source_flags();
  const auto native = native_flags();
  const auto camera = camera_flags(warp, warp);
  const auto rig = rig_flags();
  const auto options = option_flags(true, true, true);
  specs.insert(specs.end(), native.begin(), native.end());
  specs.insert(specs.end(), camera.begin(), camera.end());
  specs.insert(specs.end(), rig.begin(), rig.end());
  specs.insert(specs.end(), options.begin(), options.end());
  return specs;
}

}  // namespace

int run_warp(int argc, char** argv) {
  std::vector<Flags::Spec> specs = frame_flags(true);
  specs.insert(specs.end(), {
      {"out", "FILE", "the target eye's colour (.png, .pfm, .exr; .raw for a .raw colour)"},
      {"out-depth", "FILE", "its depth, in the source's encoding and file units (.png 16-bit, .pfm, .exr; .raw for a .raw depth)"},
      {"status", "FILE", "its status, 8-bit .png: 0 hit, 1 hole, 2 outside, 3 clipped"},
      {"source-x", "FILE", "the source column each pixel came from (.pfm, .exr)"},
  });
  Flags flags("warp", specs);
  flags.parse(argc, argv, 2);
  if (flags.help()) {
    std::fputs(flags.usage("--color FILE --depth FILE (--encoding NAME ... --convergence C | --disparity) --out FILE [flags]").c_str(), stdout);
    std::fputs(kNativeHelp, stdout);
    return kExitOk;
  }
  flags.require("out");
  flags.require("color");
  flags.require("depth");
  const NativeSpec native = native_spec_from_flags(flags);
  check_color_output("out", flags.text("out"), native);
  if (flags.has("out-depth")) check_depth_output("out-depth", flags.text("out-depth"), native);
  if (flags.has("status")) check_png_path("status", flags.text("status"));
  if (flags.has("source-x")) check_float_path("source-x", flags.text("source-x"));
  check_distinct_outputs(flags, {"out", "out-depth", "status", "source-x"});

  const DepthDecoder decoder = decoder_from_flags(flags);
  const Options opts = options_from_flags(flags, true);
  const int dilate = dilate_radius_from_flags(flags);
  // The model needs the target width, known only from the file; check its flags before reading.
  EyeDirection direction = EyeDirection::centre_to_right;
  (void)model_from_flags(flags, 1, &direction);

  OutputSet out;
  out.inputs(flags, {"color", "depth"});
  out.outputs(flags, {"out", "out-depth", "status", "source-x"});
  Frame frame = load_source(flags, native, decoder, {flags.text("out")});
  dilate_depth(&frame.depth, decoder, dilate);
  const int w = target_width(frame, opts), h = frame.height();
  const ParallaxModel model = model_from_flags(flags, w, &direction);

  EyeBuffers eye(w, h, frame, flags.has("source-x"));
  check_status(reproject::reproject(frame.source(), decoder, model, opts, eye.view()), "reproject");

  write_color(out, flags.text("out"), eye, frame);
  if (flags.has("out-depth")) write_depth(out, flags.text("out-depth"), eye, frame);
  if (flags.has("status")) out.bytes(flags.text("status"), eye.status.data(), w, h);
  if (flags.has("source-x")) out.plane(flags.text("source-x"), eye.source_x.plane(0));
  out.commit();
  std::printf("warp %s, %s%s, %s: %dx%d -> %dx%d, %s%s\n", to_string(direction), to_string(opts.method),
              dilate > 0 ? (", depth dilated " + std::to_string(dilate) + " px").c_str() : "", formats_text(frame).c_str(),
              frame.width(), h, w, h, eye.summary().c_str(),
              frame.unknown_filled > 0 ? (", " + std::to_string(frame.unknown_filled) + " unknown depths filled").c_str() : "");
  return kExitOk;
}

int run_pair(int argc, char** argv) {
  std::vector<Flags::Spec> specs = frame_flags(false);
  specs.insert(specs.end(), {
      {"out-left", "FILE", "left eye colour (.png, .pfm, .exr; .raw for a .raw colour)"},
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
    std::fputs(kNativeHelp, stdout);
    return kExitOk;
  }
  flags.require("color");
  flags.require("depth");
  const NativeSpec native = native_spec_from_flags(flags);
  const char* outputs[] = {"out-left", "out-right", "out-left-depth", "out-right-depth", "status-left",
                           "status-right", "side-by-side", "top-bottom", "anaglyph"};
  bool any = false;
  for (const char* o : outputs) {
    if (!flags.has(o)) continue;
    any = true;
    const std::string path = flags.text(o);
    const std::string name = o;
    if (name.rfind("status", 0) == 0) check_png_path(o, path);
    else if (name == "out-left" || name == "out-right") check_color_output(o, path, native);
    else if (name == "out-left-depth" || name == "out-right-depth") check_depth_output(o, path, native);
    else check_output_path(o, path);  // the stereo pictures: image files, made in float
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
  (void)model_from_flags(flags, 1, nullptr);

  OutputSet out;
  out.inputs(flags, {"color", "depth"});
  out.outputs(flags, std::vector<const char*>(std::begin(outputs), std::end(outputs)));
  // The stereo pictures are made in float from the eyes, so only the eyes' files decide the path.
  std::vector<std::string> color_outputs;
  for (const char* o : {"out-left", "out-right", "side-by-side", "top-bottom"}) {
    if (flags.has(o)) color_outputs.push_back(flags.text(o));
  }
  Frame frame = load_source(flags, native, decoder, color_outputs);
  dilate_depth(&frame.depth, decoder, dilate);
  const int w = target_width(frame, opts), h = frame.height();
  const ParallaxModel to_right = model_from_flags(flags, w, nullptr);
  EyeBuffers left(w, h, frame, false), right(w, h, frame, false);
  check_status(reproject::reproject_pair(frame.source(), decoder, to_right, opts, left.view(), right.view()),
               "reproject_pair");

  if (flags.has("out-left")) write_color(out, flags.text("out-left"), left, frame);
  if (flags.has("out-right")) write_color(out, flags.text("out-right"), right, frame);
  if (flags.has("out-left-depth")) write_depth(out, flags.text("out-left-depth"), left, frame);
  if (flags.has("out-right-depth")) write_depth(out, flags.text("out-right-depth"), right, frame);
  if (flags.has("status-left")) out.bytes(flags.text("status-left"), left.status.data(), w, h);
  if (flags.has("status-right")) out.bytes(flags.text("status-right"), right.status.data(), w, h);
  Image left_color, right_color;  // 0..1 floats, for the pictures
  if (flags.has("side-by-side") || flags.has("top-bottom") || flags.has("anaglyph")) {
    left_color = left.float_color();
    right_color = right.float_color();
  }
  if (flags.has("side-by-side")) {
    Image packed;
    check_picture(io::side_by_side(left_color.color(), right_color.color(), &packed, packing), "side-by-side image");
    write_picture(out, flags.text("side-by-side"), packed, frame);
  }
  if (flags.has("top-bottom")) {
    Image packed;
    check_picture(io::top_bottom(left_color.color(), right_color.color(), &packed, packing), "top-bottom image");
    write_picture(out, flags.text("top-bottom"), packed, frame);
  }
  if (flags.has("anaglyph")) {
    // stereo_views works in 0..255 (Dubois clamps there); back to 0..1 for the colour writer.
    const Image l = to_picture_scale(left_color.color()), r = to_picture_scale(right_color.color());
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
  std::printf("pair%s, %s: %dx%d -> 2 x %dx%d; left %s; right %s\n",
              dilate > 0 ? (" (depth dilated " + std::to_string(dilate) + " px)").c_str() : "", formats_text(frame).c_str(),
              frame.width(), h, w, h, left.summary().c_str(), right.summary().c_str());
  return kExitOk;
}

}  // namespace reproject::cli
