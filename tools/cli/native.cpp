// Engine-native pixel formats in `warp` and `pair` (docs/CLI.md "Native formats and raw dumps"):
// 8-bit PNG colour read as rgba8 / rgba8_srgb and half EXR colour as rgba16f, so that the library
// blends the file's own values and the output is written from its bytes with no float round trip;
// and .raw engine dumps of colour and depth in any ColorFormat / DepthFormat.
#include <cmath>
#include <cstring>

#include "cli.hpp"

namespace reproject::cli {
namespace {

const char kDepthFormats[] = "float32, unorm16, unorm24_s8, s8_unorm24, rgba8_packed_linear";
const char kRawColorFormats[] = "rgba8, rgba8_srgb, rgba16f";

// "WxH" with each side in 1..2^28 and at most 2^28 pixels (imageio's limit for any image).
void parse_size(const Flags& flags, int* width, int* height) {
  const std::string text = flags.text("size");
  const std::size_t x = text.find('x');
  const std::string w = x == std::string::npos ? "" : text.substr(0, x);
  const std::string h = x == std::string::npos ? "" : text.substr(x + 1);
  constexpr long long kMax = 1LL << 28;
  const bool digits = is_decimal(w, true) && is_decimal(h, true) && w[0] != '-' && w[0] != '+' && h[0] != '-' && h[0] != '+';
  const long long wv = digits && w.size() <= 10 ? std::atoll(w.c_str()) : 0;
  const long long hv = digits && h.size() <= 10 ? std::atoll(h.c_str()) : 0;
  if (wv < 1 || hv < 1 || wv > kMax || hv > kMax) flags.bad_value("size", "'" + text + "' is not WxH (two integers >= 1, e.g. 1920x1080)");
  if (wv * hv > kMax) flags.bad_value("size", "'" + text + "' exceeds the " + std::to_string(kMax) + "-pixel limit");
  *width = static_cast<int>(wv);
  *height = static_cast<int>(hv);
}

// "NEAR,FAR": two finite numbers, different.
void parse_linear_range(const Flags& flags, float* near_depth, float* far_depth) {
  const std::vector<std::string> items = flags.list("linear-range", "");
  double v[2] = {0.0, 0.0};
  bool ok = items.size() == 2;
  for (std::size_t i = 0; ok && i < 2; ++i) {
    ok = is_decimal(items[i], false);
    if (ok) v[i] = std::strtod(items[i].c_str(), nullptr);
    ok = ok && std::isfinite(static_cast<float>(v[i]));
  }
  if (!ok) flags.bad_value("linear-range", "'" + flags.text("linear-range") + "' is not NEAR,FAR (two decimal numbers)");
  if (static_cast<float>(v[0]) == static_cast<float>(v[1])) {
    flags.bad_value("linear-range", "'" + flags.text("linear-range") + "' is an empty range");
  }
  *near_depth = static_cast<float>(v[0]);
  *far_depth = static_cast<float>(v[1]);
}

// A raw input's header: --size, checked against the file's size (code 3 when they disagree).
io::ImageInfo raw_info(const std::string& path, const NativeSpec& spec, int bytes_per_pixel, const char* format_name,
                       int channels) {
  const std::uint64_t bytes = static_cast<std::uint64_t>(spec.width) * static_cast<std::uint64_t>(spec.height) *
                              static_cast<std::uint64_t>(bytes_per_pixel);
  const std::string what = "a " + size_text(spec.width, spec.height) + " " + format_name + " buffer (--size; " +
                           std::to_string(bytes_per_pixel) + " bytes per pixel, rows packed)";
  if (io::IoStatus s = io::check_raw_size(path, bytes, what); !s) {
    fail(s.error == io::IoError::out_of_memory ? kExitRuntime : kExitInput, s.message);
  }
  io::ImageInfo info;
  info.width = spec.width;
  info.height = spec.height;
  info.channels = channels;
  return info;
}

std::vector<std::uint8_t> read_raw_file(const std::string& path, const NativeSpec& spec, int bytes_per_pixel,
                                        int words, const char* format_name) {
  const std::uint64_t bytes = static_cast<std::uint64_t>(spec.width) * static_cast<std::uint64_t>(spec.height) *
                              static_cast<std::uint64_t>(bytes_per_pixel);
  std::vector<std::uint8_t> data;
  const std::string what = "a " + size_text(spec.width, spec.height) + " " + format_name + " buffer";
  if (io::IoStatus s = io::read_raw(path, bytes, words, what, &data); !s) {
    fail(s.error == io::IoError::out_of_memory ? kExitRuntime : kExitInput, s.message);
  }
  return data;
}

// The colour format the source is reprojected in, from its header and the outputs: an 8-bit PNG
// natively when every colour output is an 8-bit PNG too (the output keeps the input's bit depth),
// a half EXR when every one is an EXR (written half); else the float path (float32).
ColorFormat native_color_format(const NativeSpec& spec, const io::ImageInfo& info,
                                const std::vector<std::string>& color_outputs) {
  if (spec.float_color) return ColorFormat::float32;
  io::FileFormat wanted = io::FileFormat::unknown;
  ColorFormat format = ColorFormat::float32;
  if (info.format == io::FileFormat::png && info.bit_depth == 8) {
    wanted = io::FileFormat::png;
    format = spec.png_format;
  } else if (info.format == io::FileFormat::exr && info.bit_depth == 16) {
    wanted = io::FileFormat::exr;
    format = ColorFormat::rgba16f;
  } else {
    return ColorFormat::float32;
  }
  for (const std::string& out : color_outputs) {
    if (io::format_from_path(out) != wanted) return ColorFormat::float32;
  }
  return format;
}

}  // namespace

int raw_word_bytes(DepthFormat format) {
  switch (format) {
    case DepthFormat::unorm16: return 2;
    case DepthFormat::rgba8_packed_linear: return 1;
    default: return 4;  // float32 and the two 32-bit D24S8 words
  }
}
int raw_word_bytes(ColorFormat format) { return format == ColorFormat::rgba16f ? 2 : 1; }

std::vector<Flags::Spec> native_flags() {
  return {
      {"color-space", "SPACE",
       "8-bit PNG colour read natively is blended as linear (the bytes as they are, as the float path does) or "
       "srgb (in linear light, like a GPU's sRGB texture) [linear]"},
      {"float-color", nullptr, "reproject the colour as floats even when it could be read natively (for comparison)"},
      {"size", "WxH", "the size of the .raw inputs"},
      {"color-format", "FORMAT", "a .raw colour's format: rgba8, rgba8_srgb or rgba16f"},
      {"depth-format", "FORMAT", "a .raw depth's format: float32, unorm16, unorm24_s8, s8_unorm24, rgba8_packed_linear"},
      {"linear-range", "NEAR,FAR", "rgba8_packed_linear: the linear depths its 0 and 1 stand for"},
  };
}

NativeSpec native_spec_from_flags(const Flags& flags) {
  NativeSpec spec;
  flags.require("color");
  flags.require("depth");
  const std::string color = flags.text("color"), depth = flags.text("depth");
  spec.raw_color = is_raw_path(color);
  spec.raw_depth = is_raw_path(depth);
  spec.float_color = flags.has("float-color");

  if (spec.raw_color) {
    if (!flags.has("color-format")) {
      fail(kExitUsage, "--color: the .raw file '" + color + "' needs --color-format FORMAT (" + kRawColorFormats + ")");
    }
    const std::string name = flags.text("color-format");
    if (!parse_color_format(name.c_str(), &spec.color_format)) {
      flags.bad_value("color-format", "unknown raw colour format '" + name + "' (" + kRawColorFormats + ")");
    }
    if (spec.color_format == ColorFormat::float32) {
      flags.bad_value("color-format", "float32 colour is not read from a .raw file (" + std::string(kRawColorFormats) + ")");
    }
    flags.forbid("color-space", "a .raw colour (--color-format names how it blends)");
    flags.forbid("float-color", "a .raw colour (it is reprojected in its own format)");
  } else {
    flags.forbid("color-format", "--color '" + color + "': it names the format of a .raw colour file");
  }
  if (flags.has("color-space")) {
    const std::string v = flags.text("color-space");
    if (v == "srgb") spec.png_format = ColorFormat::rgba8_srgb;
    else if (v == "linear") spec.png_format = ColorFormat::rgba8;
    else flags.bad_value("color-space", "unknown colour space '" + v + "' (srgb, linear)");
    flags.forbid("float-color", "--color-space (the float path blends the stored values, as linear does)");
    if (io::format_from_path(color) != io::FileFormat::png) {
      flags.bad_value("color-space", "it applies to 8-bit PNG colour, and --color '" + color + "' is not a .png");
    }
  }

  if (spec.raw_depth) {
    if (!flags.has("depth-format")) {
      fail(kExitUsage, "--depth: the .raw file '" + depth + "' needs --depth-format FORMAT (" + kDepthFormats + ")");
    }
    const std::string name = flags.text("depth-format");
    if (!parse_depth_format(name.c_str(), &spec.depth_format)) {
      flags.bad_value("depth-format", "unknown depth format '" + name + "' (" + kDepthFormats + ")");
    }
    // The buffer is reprojected as it is: nothing may rewrite its values first.
    const std::string why = "a .raw depth (the buffer is reprojected as it is)";
    flags.forbid("depth-scale", why);
    flags.forbid("unknown-depth", why);
    if (flags.has("dilate-depth") && flags.integer("dilate-depth", 0, 0, 4096) > 0) flags.forbid("dilate-depth", why);
    if (spec.depth_format == DepthFormat::rgba8_packed_linear) {
      if (!flags.has("linear-range")) fail(kExitUsage, "--depth-format rgba8_packed_linear needs --linear-range NEAR,FAR");
      parse_linear_range(flags, &spec.linear_near, &spec.linear_far);
    } else {
      flags.forbid("linear-range", "--depth-format " + name + " (only rgba8_packed_linear has a range)");
    }
  } else {
    flags.forbid("depth-format", "--depth '" + depth + "': it names the format of a .raw depth file");
    flags.forbid("linear-range", "--depth '" + depth + "': it belongs to a .raw rgba8_packed_linear depth");
  }

  if (spec.raw_color || spec.raw_depth) {
    if (!flags.has("size")) fail(kExitUsage, "a .raw input needs --size WxH");
    parse_size(flags, &spec.width, &spec.height);
  } else {
    flags.forbid("size", "no .raw input (other files hold their size)");
  }
  return spec;
}

void check_color_output(const char* flag, const std::string& path, const NativeSpec& spec) {
  if (!spec.raw_color) {
    if (is_raw_path(path)) {
      fail(kExitUsage, std::string("--") + flag + ": '" + path + "': a .raw colour output needs a .raw colour input (--color-format)");
    }
    check_output_path(flag, path);
    return;
  }
  // A raw colour stays in its format: its bytes, or the file type that holds that format.
  const io::FileFormat own = spec.color_format == ColorFormat::rgba16f ? io::FileFormat::exr : io::FileFormat::png;
  if (!is_raw_path(path) && io::format_from_path(path) != own) {
    fail(kExitUsage, std::string("--") + flag + ": '" + path + "': a " + to_string(spec.color_format) +
                         " colour is written as .raw or ." + io::to_string(own));
  }
}

void check_depth_output(const char* flag, const std::string& path, const NativeSpec& spec) {
  if (!spec.raw_depth) {
    if (is_raw_path(path)) {
      fail(kExitUsage, std::string("--") + flag + ": '" + path + "': a .raw depth output needs a .raw depth input (--depth-format)");
    }
    check_output_path(flag, path);
    return;
  }
  const io::FileFormat f = io::format_from_path(path);
  if (!is_raw_path(path) && f != io::FileFormat::pfm && f != io::FileFormat::exr) {
    fail(kExitUsage, std::string("--") + flag + ": '" + path + "': a .raw " + to_string(spec.depth_format) +
                         " depth is written as .raw (its bytes), .pfm or .exr (its stored values as floats)");
  }
}

DepthBuffer RawDepth::view() const noexcept {
  DepthBuffer view = DepthBuffer::of(format, bytes.data(), width, height, stride());
  view.linear_near = linear_near;  // read by rgba8_packed_linear only
  view.linear_far = linear_far;
  return view;
}

MutableDepthBuffer RawDepth::mutable_view() noexcept {
  MutableDepthBuffer view = MutableDepthBuffer::of(format, bytes.data(), width, height, stride());
  view.linear_near = linear_near;
  view.linear_far = linear_far;
  return view;
}

ColorView Frame::color_view() const noexcept { return native_color() ? packed_color.view() : color.image.color(); }

SourceView Frame::source() const noexcept {
  SourceView source;
  source.color = color_view();
  if (native_depth()) source.depth_buffer = raw_depth.view();
  else source.depth = depth.plane(0);
  return source;
}

Frame load_source(const Flags& flags, const NativeSpec& spec, const DepthDecoder& decoder,
                  const std::vector<std::string>& color_outputs) {
  // Every flag is checked before the first file is read.
  (void)flags.number("depth-scale", 1.0, 0.0, HUGE_VAL, true);
  if (flags.has("unknown-depth")) {
    const std::string v = flags.text("unknown-depth");
    if (v != "nan" && v != "NaN" && v != "NAN") (void)flags.number("unknown-depth", 0.0);
  }
  const std::string color_path = flags.text("color"), depth_path = flags.text("depth");
  const io::ImageInfo color =
      spec.raw_color ? raw_info(color_path, spec, bytes_per_pixel(spec.color_format), to_string(spec.color_format), 4)
                     : color_info(color_path);
  const io::ImageInfo depth =
      spec.raw_depth ? raw_info(depth_path, spec, bytes_per_pixel(spec.depth_format), to_string(spec.depth_format), 1)
                     : depth_info(depth_path);
  if (color.width != depth.width || color.height != depth.height) {
    fail(kExitInput, "colour '" + color_path + "' is " + size_text(color.width, color.height) + " but depth '" +
                         depth_path + "' is " + size_text(depth.width, depth.height));
  }

  Frame frame;
  if (spec.raw_color) {
    io::PackedColor& packed = frame.packed_color;
    packed.bytes = read_raw_file(color_path, spec, bytes_per_pixel(spec.color_format), raw_word_bytes(spec.color_format),
                                 to_string(spec.color_format));
    packed.width = spec.width;
    packed.height = spec.height;
    packed.channels = 4;
    packed.format = spec.color_format;
    frame.color_from_raw = true;
  } else {
    const ColorFormat format = native_color_format(spec, color, color_outputs);
    if (format == ColorFormat::float32) {
      frame.color = read_color(color_path);
    } else {
      const io::IoStatus s = format == ColorFormat::rgba16f ? io::read_exr_packed(color_path, &frame.packed_color)
                                                            : io::read_png_packed(color_path, format, &frame.packed_color);
      if (!s) fail(s.error == io::IoError::out_of_memory ? kExitRuntime : kExitInput, s.message);
      frame.color.format = color.format;
      frame.color.bit_depth = color.bit_depth;
    }
  }

  if (spec.raw_depth) {
    RawDepth& raw = frame.raw_depth;
    raw.bytes = read_raw_file(depth_path, spec, bytes_per_pixel(spec.depth_format), raw_word_bytes(spec.depth_format),
                              to_string(spec.depth_format));
    raw.format = spec.depth_format;
    raw.width = spec.width;
    raw.height = spec.height;
    raw.linear_near = spec.linear_near;
    raw.linear_far = spec.linear_far;
  } else {
    DepthFile file = load_depth(flags, decoder);
    frame.depth_bits = file.bits;
    frame.depth_scale = file.scale;
    frame.unknown_filled = file.unknown_filled;
    frame.depth = std::move(file.depth);
  }
  return frame;
}

std::string formats_text(const Frame& frame) {
  std::string text = "colour ";
  if (frame.native_color()) {
    text += std::string(to_string(frame.packed_color.format)) + (frame.color_from_raw ? " (raw)" : " (native)");
  } else {
    text += "float32";
  }
  text += ", depth ";
  text += frame.native_depth() ? std::string(to_string(frame.raw_depth.format)) + " (raw)" : std::string("float32");
  return text;
}

Image stored_depth_values(const RawDepth& depth) {
  Image out(depth.width, depth.height, 1);
  if (out.empty()) fail(kExitRuntime, "out of memory for a " + size_text(depth.width, depth.height) + " depth");
  const int bpp = bytes_per_pixel(depth.format);
  for (int y = 0; y < depth.height; ++y) {
    const std::uint8_t* src = depth.bytes.data() + static_cast<std::ptrdiff_t>(y) * depth.stride();
    float* dst = out.plane_data() + y * out.stride();
    for (int x = 0; x < depth.width; ++x, src += bpp) {
      std::uint32_t word = 0;
      std::uint16_t code = 0;
      switch (depth.format) {
        case DepthFormat::float32: std::memcpy(&dst[x], src, sizeof(float)); break;
        case DepthFormat::unorm16:
          std::memcpy(&code, src, sizeof code);
          dst[x] = formats::unorm_to_float(code, 16);
          break;
        case DepthFormat::unorm24_s8:
          std::memcpy(&word, src, sizeof word);
          dst[x] = formats::unorm_to_float(word & 0xFFFFFFu, 24);
          break;
        case DepthFormat::s8_unorm24:
          std::memcpy(&word, src, sizeof word);
          dst[x] = formats::unorm_to_float(word >> 8, 24);
          break;
        case DepthFormat::rgba8_packed_linear:
          dst[x] = depth.linear_near + formats::packed_linear_value(src) * (depth.linear_far - depth.linear_near);
          break;
      }
    }
  }
  return out;
}

Image float_color_of(const ColorView& packed, int channels) {
  const int w = packed.width(), h = packed.height();
  Image out(w, h, channels);
  if (out.empty()) fail(kExitRuntime, "out of memory for a " + size_text(w, h) + " picture");
  static const int kPick[5][4] = {{}, {0}, {0, 3}, {0, 1, 2}, {0, 1, 2, 3}};  // as the writers pick them
  for (int y = 0; y < h; ++y) {
    const std::uint8_t* row = packed.pixels.row(y);
    for (int c = 0; c < channels; ++c) {
      float* dst = out.plane_data(c) + y * out.stride();
      const int k = kPick[channels][c];
      for (int x = 0; x < w; ++x) {
        if (packed.format == ColorFormat::rgba16f) {
          std::uint16_t half = 0;
          std::memcpy(&half, row + 8 * x + 2 * k, sizeof half);
          dst[x] = formats::half_to_float(half);
        } else {
          dst[x] = static_cast<float>(row[4 * x + k]) / 255.0f;
        }
      }
    }
  }
  return out;
}

}  // namespace reproject::cli
