// From flags to the library's inputs: the source frame, the depth decoder, the parallax model and
// the options. Every check that can be made before reading a pixel is made here, so that a bad
// flag costs no work and names itself.
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>

#include "cli.hpp"
#include "reproject/stereo.hpp"

namespace reproject::cli {

std::vector<Flags::Spec> source_flags() {
  return {
      {"color", "FILE", "source colour: .png (8/16-bit grey, grey+alpha, RGB, RGBA), .pfm, .exr"},
      {"depth", "FILE", "source depth or disparity, one channel: .png (8/16-bit grey), .pfm, .exr"},
      {"encoding", "NAME",
       "depth encoding: linear, standard, gl_ndc, reversed, reversed_infinite, infinite, disparity"},
      {"near", "Z", "near plane (standard, gl_ndc, reversed, reversed_infinite, infinite)"},
      {"far", "Z", "far plane (standard, gl_ndc, reversed)"},
      {"depth-scale", "K", "multiply stored depth values by K (PNG values are integers) [1]"},
      {"unknown-depth", "V", "stored value meaning 'no depth' (or nan): filled from the farther row neighbour"},
  };
}

std::vector<Flags::Spec> camera_flags(bool with_direction, bool with_disparity) {
  std::vector<Flags::Spec> specs = {
      {"separation", "S", "stereo separation, a fraction of the image width [0.03]"},
      {"convergence", "C", "view-space distance of the zero-parallax plane"},
  };
  if (with_disparity) {
    specs.push_back({"disparity", nullptr, "depth is a disparity map in pixels: p = -d left-to-right (+d right-to-left)"});
  }
  if (with_direction) {
    specs.push_back({"direction", "DIR",
                     "left-to-right, right-to-left, centre-to-left or centre-to-right [centre-to-right; "
                     "left-to-right with --disparity]"});
  }
  return specs;
}

std::vector<Flags::Spec> rig_flags() {
  return {
      {"interaxial", "D", "a renderer's rig: the eyes' distance, in the unit of --convergence (with --fov, instead of "
                          "--separation)"},
      {"fov", "DEG", "the rig camera's horizontal field of view in degrees, (0, 180): S = D / (2 C tan(fov / 2))"},
      {"relative-depth", nullptr, "depth is relative inverse depth (a depth model's output): 0 farthest .. 1 nearest, "
                                  "after --depth-scale [PNG: 1 / its largest code]"},
      {"max-parallax", "F", "--relative-depth: the eyes' parallax from 0 to 1, a fraction of the width [0.03]"},
      {"zero-plane", "V", "--relative-depth: the relative value seen on the screen (zero parallax), 0..1 [0.5]"},
  };
}

std::string arch_names(const char* last_separator) {
  std::string names;
  for (int a = 0; a < kArchCount; ++a) {
    if (a > 0) names += a + 1 == kArchCount ? last_separator : ", ";
    names += to_string(static_cast<Arch>(a));
  }
  return names;
}

std::vector<Flags::Spec> option_flags(bool with_method, bool with_guard, bool with_threads_arch) {
  // Specs hold C strings: this one lives as long as the program.
  static const std::string arch_help = "instruction set: " + arch_names(" or ") + " [the best supported]";
  std::vector<Flags::Spec> specs;
  if (with_method) specs.push_back({"method", "NAME", "scanline, march16, single, secant or exact [exact]"});
  specs.insert(specs.end(), {
      {"max-negative-parallax", "PX", "largest crossed parallax searched, pixels >= 0 [the frame's own]"},
      {"hole-threshold", "PX", "a segment whose parallax jumps by more than PX is a wall (hole) [1]"},
      {"fill", "MODE", "hole fill: background, foreground or none [background]"},
      {"edge", "MODE", "pixels from off the source row: clamp, none, black or mirror [clamp]"},
      {"dilate-depth", "R", "halo pre-filter: each source depth becomes the nearest within R columns, 0..4096 [0: off]"},
  });
  if (with_guard) specs.push_back({"guard", "N", "guard band: source columns on each side beyond the target [0]"});
  specs.insert(specs.end(), {
      {"probe-parallax", "PX", "single: parallax of its one sample [the far end]"},
      {"march-steps", "N", "march16: number of steps, 1..1024 [16]"},
      {"secant-max-steps", "N", "secant: most march steps per tile, 1..4096 [256]"},
  });
  if (with_threads_arch) {
    specs.insert(specs.end(), {
        {"threads", "N", "threads, 0 = one per hardware thread [0]"},
        {"arch", "NAME", arch_help.c_str()},
    });
  }
  return specs;
}

void check_status(const Status& status, const std::string& what) {
  if (status.code() == StatusCode::cancelled) fail_if_interrupted();  // the user stopped the command
  if (!status.ok()) fail(kExitRuntime, what + ": " + to_string(status.code()) + ": " + status.message());
}

namespace {

// "background, foreground, none": every name of an enum of the library, in its order.
template <class E>
std::string enum_names(int count) {
  std::string names;
  for (int i = 0; i < count; ++i) names += std::string(i ? ", " : "") + to_string(static_cast<E>(i));
  return names;
}

}  // namespace

namespace {

bool needs_near(DepthEncoding e) {
  return e != DepthEncoding::linear && e != DepthEncoding::disparity;
}
bool needs_far(DepthEncoding e) {
  return e == DepthEncoding::standard || e == DepthEncoding::gl_ndc || e == DepthEncoding::reversed;
}

DepthEncoding encoding_from_flags(const Flags& flags) {
  if (flags.has("relative-depth")) {
    flags.forbid("encoding", "--relative-depth (relative inverse depth is decoded as w = v)");
    flags.forbid("disparity", "--relative-depth");
    return DepthEncoding::disparity;  // w = d: docs/BEHAVIOUR.md "Relative inverse depth"
  }
  const bool disparity = flags.has("disparity");
  if (!flags.has("encoding")) {
    if (disparity) return DepthEncoding::disparity;
    flags.require("encoding");
  }
  DepthEncoding encoding = DepthEncoding::linear;
  const std::string name = flags.text("encoding");
  if (!parse_encoding(name.c_str(), &encoding)) {
    flags.bad_value("encoding", "unknown encoding '" + name +
                                    "' (linear, standard, gl_ndc, reversed, reversed_infinite, infinite, disparity)");
  }
  if (disparity && encoding != DepthEncoding::disparity) {
    flags.bad_value("encoding", "--disparity reads a disparity map; the encoding cannot be " + name);
  }
  return encoding;
}

}  // namespace

DepthDecoder decoder_from_flags(const Flags& flags) {
  const DepthEncoding encoding = encoding_from_flags(flags);
  const char* name = to_string(encoding);
  if (!needs_near(encoding)) flags.forbid("near", std::string("the ") + name + " encoding (it has no near plane)");
  if (!needs_far(encoding)) flags.forbid("far", std::string("the ") + name + " encoding (it has no far plane)");
  if (needs_near(encoding)) flags.require("near");
  if (needs_far(encoding)) flags.require("far");
  if (encoding == DepthEncoding::linear) return DepthDecoder::linear();
  if (encoding == DepthEncoding::disparity) return DepthDecoder::disparity();
  const double n = flags.number("near", 0.0, 0.0, HUGE_VAL, true);
  const double f = needs_far(encoding) ? flags.number("far", 0.0, n, HUGE_VAL, true) : 0.0;
  const DepthDecoder decoder = DepthDecoder::from_near_far(encoding, n, f);
  if (Status s = decoder.validate(); !s.ok()) fail(kExitUsage, std::string("--near/--far: ") + s.message());
  return decoder;
}

ParallaxModel model_from_flags(const Flags& flags, int width, EyeDirection* direction_out) {
  const bool disparity = flags.has("disparity") || flags.text("encoding") == "disparity";
  EyeDirection direction = disparity ? EyeDirection::left_to_right : EyeDirection::centre_to_right;
  if (flags.has("direction")) {
    const std::string name = flags.text("direction");
    if (!parse_direction(name.c_str(), &direction)) {
      flags.bad_value("direction", "unknown direction '" + name +
                                       "' (left-to-right, right-to-left, centre-to-left, centre-to-right)");
    }
  }
  if (direction_out != nullptr) *direction_out = direction;
  if (flags.has("relative-depth")) {
    for (const char* f : {"separation", "convergence", "interaxial", "fov"}) {
      flags.forbid(f, "--relative-depth (--max-parallax and --zero-plane set the parallax)");
    }
    const double max_parallax = flags.number("max-parallax", 0.03, 0.0, 1.0);
    const double zero_plane = flags.number("zero-plane", 0.5, 0.0, 1.0);
    return ParallaxModel::from_relative(max_parallax, zero_plane, width, direction);
  }
  for (const char* f : {"max-parallax", "zero-plane"}) {
    if (flags.has(f)) fail(kExitUsage, std::string("--") + f + " needs --relative-depth");
  }
  if (disparity) {
    flags.forbid("separation", "a disparity map (the disparity is the parallax)");
    flags.forbid("convergence", "a disparity map (the disparity is the parallax)");
    if (direction != EyeDirection::left_to_right && direction != EyeDirection::right_to_left) {
      flags.bad_value("direction", "a disparity map goes left-to-right or right-to-left");
    }
    return ParallaxModel::from_disparity(direction);
  }
  flags.require("convergence");
  const double convergence = flags.number("convergence", 0.0, 0.0, HUGE_VAL, true);
  double separation = 0.0;
  if (flags.has("interaxial") || flags.has("fov")) {
    flags.forbid("separation", "--interaxial and --fov (the rig gives the separation)");
    if (!flags.has("interaxial")) fail(kExitUsage, "--fov needs --interaxial D");
    if (!flags.has("fov")) fail(kExitUsage, "--interaxial needs --fov DEG");
    const double interaxial = flags.number("interaxial", 0.0, 0.0, HUGE_VAL);
    const double fov = flags.number("fov", 0.0, 0.0, 180.0, true);
    if (!(fov < 180.0)) flags.bad_value("fov", "'" + flags.text("fov") + "' is not below 180");
    constexpr double kPi = 3.14159265358979323846;
    separation = StereoCamera::from_rig(interaxial, convergence, fov * kPi / 180.0).separation;
  } else {
    separation = flags.number("separation", 0.03, 0.0, 1.0);
  }
  const ParallaxModel model = StereoCamera{separation, convergence}.parallax(width, direction);
  if (Status s = model.validate(); !s.ok()) fail(kExitUsage, std::string("--separation/--convergence: ") + s.message());
  return model;
}

Options options_from_flags(const Flags& flags, bool read_threads_arch) {
  Options o;
  o.cancel = interruption();  // Windows: a console control event stops the call
  // Flags a subcommand does not declare are never set, so these reads are safe for all of them.
  if (flags.has("method")) {
    const std::string name = flags.text("method");
    if (!parse_method(name.c_str(), &o.method)) {
      flags.bad_value("method", "unknown method '" + name + "' (scanline, march16, single, secant, exact)");
    }
  }
  if (flags.has("max-negative-parallax")) {
    o.max_negative_parallax = static_cast<float>(flags.number("max-negative-parallax", 0.0, 0.0, 1e9));
  }
  o.hole_threshold = static_cast<float>(flags.number("hole-threshold", 1.0, 0.0, 1e9));
  if (flags.has("fill") && !parse_hole_fill(flags.text("fill").c_str(), &o.hole_fill)) {
    flags.bad_value("fill", "unknown fill '" + flags.text("fill") + "' (" + enum_names<HoleFill>(kHoleFillCount) + ")");
  }
  if (flags.has("edge") && !parse_edge_mode(flags.text("edge").c_str(), &o.edge)) {
    flags.bad_value("edge", "unknown edge mode '" + flags.text("edge") + "' (" + enum_names<EdgeMode>(kEdgeModeCount) + ")");
  }
  o.guard = flags.integer("guard", 0, 0, 1 << 20);
  if (flags.has("probe-parallax")) o.probe_parallax = static_cast<float>(flags.number("probe-parallax", 0.0, -1e9, 1e9));
  o.march_steps = flags.integer("march-steps", 16, 1, 1024);
  o.secant_max_steps = flags.integer("secant-max-steps", 256, 1, 4096);
  if (read_threads_arch) {
    o.threads = flags.integer("threads", 0, 0, 1024);
    if (flags.has("arch")) o.arch = arch_from_flags(flags);
  }
  return o;
}

int dilate_radius_from_flags(const Flags& flags) { return flags.integer("dilate-depth", 0, 0, 4096); }

void dilate_depth(Image* depth, const DepthDecoder& decoder, int radius) {
  if (radius <= 0) return;
  Image dilated(depth->width(), depth->height(), 1);
  if (dilated.empty()) fail(kExitRuntime, "out of memory for the dilated depth");
  check_status(dilate_nearer_depth(depth->plane(0), decoder, radius, dilated.mutable_plane()), "dilate_nearer_depth");
  *depth = std::move(dilated);
}


void check_environment() {
  const char* forced = std::getenv("REPROJECT_FORCE_ARCH");
  Arch arch = Arch::scalar;
  if (forced != nullptr && *forced != '\0' && !parse_arch(forced, &arch)) {
    fail(kExitUsage, std::string("REPROJECT_FORCE_ARCH: unknown instruction set '") + forced + "' (" + arch_names() + ")");
  }
  const char* lookup = std::getenv("REPROJECT_SRGB_LOOKUP");
  if (lookup != nullptr && *lookup != '\0' && std::strcmp(lookup, "gathers") != 0 && std::strcmp(lookup, "permutes") != 0) {
    fail(kExitUsage, std::string("REPROJECT_SRGB_LOOKUP: unknown sRGB lookup '") + lookup + "' (gathers, permutes)");
  }
}

Arch arch_from_flags(const Flags& flags) {
  if (!flags.has("arch")) return selected_arch();
  const std::string name = flags.text("arch");
  Arch arch = Arch::scalar;
  if (!parse_arch(name.c_str(), &arch)) flags.bad_value("arch", "unknown instruction set '" + name + "' (" + arch_names() + ")");
  if (!arch_supported(arch)) {
    std::string supported;
    for (int a = 0; a < kArchCount; ++a) {
      if (arch_supported(static_cast<Arch>(a))) supported += std::string(supported.empty() ? "" : ", ") + to_string(static_cast<Arch>(a));
    }
    flags.bad_value("arch", name + " is not supported by this CPU (supported: " + supported + ")");
  }
  return arch;
}

long fill_unknown_depth(Image* depth, const std::vector<std::uint8_t>& unknown, const DepthDecoder& decoder) {
  const int w = depth->width(), h = depth->height();
  // The farthest stored value, for rows that hold no known depth at all.
  float farthest = 0.0f;
  switch (decoder.encoding()) {
    case DepthEncoding::disparity: farthest = 0.0f; break;
    case DepthEncoding::linear: farthest = std::numeric_limits<float>::infinity(); break;
    case DepthEncoding::reversed_infinite:
    case DepthEncoding::infinite: farthest = decoder.encode(std::numeric_limits<double>::infinity()); break;
    default: farthest = decoder.encode(decoder.far_plane()); break;
  }
  long filled = 0;
  for (int y = 0; y < h; ++y) {
    float* row = depth->plane_data() + y * depth->stride();
    const std::uint8_t* bad = unknown.data() + static_cast<std::size_t>(y) * w;
    int x = 0;
    while (x < w) {
      if (!bad[x]) {
        ++x;
        continue;
      }
      int end = x;
      while (end < w && bad[end]) ++end;
      // Run [x, end) is unknown: the gap is most likely a disocclusion or a surface the sensor
      // missed next to a nearer one, so the farther neighbour is the better guess.
      const bool has_left = x > 0, has_right = end < w;
      float value = farthest;
      if (has_left && has_right) {
        value = decoder.inverse_depth(row[x - 1]) <= decoder.inverse_depth(row[end]) ? row[x - 1] : row[end];
      } else if (has_left) {
        value = row[x - 1];
      } else if (has_right) {
        value = row[end];
      }
      for (int i = x; i < end; ++i) row[i] = value;
      filled += end - x;
      x = end;
    }
  }
  return filled;
}

DepthFile load_depth(const Flags& flags, const DepthDecoder& decoder) {
  flags.require("depth");
  // Relative inverse depth is 0..1: a PNG's integers are read as a fraction of its largest code.
  double default_scale = 1.0;
  if (flags.has("relative-depth") && io::format_from_path(flags.text("depth")) == io::FileFormat::png) {
    default_scale = 1.0 / ((1 << depth_info(flags.text("depth")).bit_depth) - 1);
  }
  const double scale = flags.number("depth-scale", default_scale, 0.0, HUGE_VAL, true);
  bool unknown_is_nan = false;
  float unknown_value = 0.0f;
  if (flags.has("unknown-depth")) {
    const std::string v = flags.text("unknown-depth");
    if (v == "nan" || v == "NaN" || v == "NAN") {
      unknown_is_nan = true;
    } else {
      unknown_value = static_cast<float>(flags.number("unknown-depth", 0.0));
    }
  }
  io::LoadedImage loaded = read_depth_file(flags.text("depth"));
  DepthFile file;
  file.bits = loaded.bit_depth;
  file.scale = scale;
  file.depth = std::move(loaded.image);
  const int w = file.depth.width(), h = file.depth.height();
  std::vector<std::uint8_t> unknown;
  const bool find_unknown = flags.has("unknown-depth");
  if (find_unknown) unknown.assign(static_cast<std::size_t>(w) * h, 0);
  const float k = static_cast<float>(scale);
  for (int y = 0; y < h; ++y) {
    float* row = file.depth.plane_data() + y * file.depth.stride();
    for (int x = 0; x < w; ++x) {
      // The unknown value is matched as stored, before scaling: it is a code, not a depth.
      if (find_unknown) {
        unknown[static_cast<std::size_t>(y) * w + x] = unknown_is_nan ? std::isnan(row[x]) : row[x] == unknown_value;
      }
      if (scale != 1.0) row[x] *= k;
    }
  }
  if (find_unknown) file.unknown_filled = fill_unknown_depth(&file.depth, unknown, decoder);
  return file;
}

io::ImageInfo frame_info(const Flags& flags) {
  flags.require("color");
  flags.require("depth");
  const std::string color_path = flags.text("color"), depth_path = flags.text("depth");
  const io::ImageInfo color = color_info(color_path), depth = depth_info(depth_path);
  if (color.width != depth.width || color.height != depth.height) {
    fail(kExitInput, "colour '" + color_path + "' is " + size_text(color.width, color.height) + " but depth '" +
                         depth_path + "' is " + size_text(depth.width, depth.height));
  }
  return color;
}

Frame load_frame(const Flags& flags, const DepthDecoder& decoder) {
  flags.require("color");
  flags.require("depth");
  // Every flag is checked before the first file is read.
  (void)flags.number("depth-scale", 1.0, 0.0, HUGE_VAL, true);
  if (flags.has("unknown-depth")) {
    const std::string v = flags.text("unknown-depth");
    if (v != "nan" && v != "NaN" && v != "NAN") (void)flags.number("unknown-depth", 0.0);
  }
  (void)frame_info(flags);
  Frame frame;
  frame.color = read_color(flags.text("color"));
  DepthFile depth = load_depth(flags, decoder);
  frame.depth_bits = depth.bits;
  frame.depth_scale = depth.scale;
  frame.unknown_filled = depth.unknown_filled;
  frame.depth = std::move(depth.depth);
  return frame;
}

}  // namespace reproject::cli
