// reproject_golden: golden outputs, to prove that a kernel change changed no output bit.
//
// Renders two built-in scenes (room, edge) at 67x9, 130x7, 257x5 and 333x40, converts each view
// into every colour x depth format the library takes (float colour as 1, 3 or 4 planes or
// interleaved RGBA, rgba8, rgba8_srgb, rgba16f; float, unorm16, unorm24_s8, s8_unorm24,
// rgba8_packed_linear depth), and runs every method on every instruction set this build and CPU
// support under each option set of kOptionSets, so every option value meets every method and
// format. Outputs are prefilled with a fixed byte (pixels a call leaves alone are deterministic);
// every output byte, row padding included, goes into a 64-bit FNV-1a hash. Public API only.
//
// Output: one line per configuration, then a hash of all the lines and their count (the run time
// goes to stderr); a call that fails prints "error:<code>" for its hash and makes the exit status 1:
//   room/67x9/rgba8+unorm24_s8/single/avx2/fill:background,edge:clamp/single-eye 0123456789abcdef
//   total fedcba9876543210 95200
// A/B two builds (before and after a kernel change) and diff: no output, no bit changed.
//   build-a/bench/reproject_golden > a.txt && build-b/bench/reproject_golden > b.txt && diff a.txt b.txt
// Flags:
//   --arch NAME      only this instruction set (scalar, sse, avx2, avx512, neon)
//   --only REGEX     only the configurations whose line name matches REGEX (std::regex_search):
//                    e.g. to count one call's instructions per function (bench/instruction_count.py)
//   --canonical-nan  hash every NaN of a float or half output as one bit pattern (AArch64 and x86
//                    make NaNs of different signs): to compare builds on different processors
//   --versus-scalar  print no hashes; check, configuration by configuration, that each fused SIMD
//                    set (avx2, avx512, neon) gives the scalar reference's bytes, print each
//                    mismatch (with the buffers that differ) and a summary; exit status 1 on any.
//                    sse does not fuse multiply-adds, so its bits may differ from scalar's
//                    (reproject.hpp, Arch): the summary counts its differences, which are no error.
#include <algorithm>
#include <chrono>
#include <cinttypes>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iterator>
#include <optional>
#include <regex>
#include <string>
#include <type_traits>
#include <vector>

#include "reproject/reproject.hpp"
#include "scene.hpp"

namespace {

using namespace reproject;
namespace rs = reproject::scene;

constexpr std::uint64_t kFnvOffset = 14695981039346656037ull;
std::uint64_t fnv1a(const void* data, std::size_t size, std::uint64_t hash = kFnvOffset) {
  const auto* bytes = static_cast<const std::uint8_t*>(data);
  for (std::size_t i = 0; i < size; ++i) hash = (hash ^ bytes[i]) * 1099511628211ull;
  return hash;
}

std::string hex(std::uint64_t v) {
  char text[17];
  std::snprintf(text, sizeof text, "%016" PRIx64, v);
  return text;
}

enum class Kind : std::uint8_t { bytes, f32, f16 };  // how --canonical-nan reads a buffer

// Every NaN among the floats (Word = uint32_t) or halves (uint16_t) replaced by the quiet NaN.
template <class Word>
void canonicalise_nans(std::vector<std::uint8_t>& bytes, Word infinity, Word quiet_nan) {
  for (std::size_t i = 0; i + sizeof(Word) <= bytes.size(); i += sizeof(Word)) {
    Word v;
    std::memcpy(&v, &bytes[i], sizeof v);
    if (static_cast<Word>(v & (infinity | (infinity - 1))) > infinity) std::memcpy(&bytes[i], &quiet_nan, sizeof v);
  }
}

constexpr std::uint8_t kPrefill = 0xa5;  // as a float or a half: a small negative number, not NaN
constexpr int kPadBytes = 16;            // row padding of every buffer, inputs and outputs

// One output buffer, prefilled; the hash covers it whole.
struct Buffer {
  std::string name;  // "colour0".., "depth", "status", "source_x"; a pair's eyes add "left." / "right."
  Kind kind = Kind::bytes;
  std::vector<std::uint8_t> bytes;

  Buffer(std::string buffer_name, Kind buffer_kind, std::ptrdiff_t stride, int height)
      : name(std::move(buffer_name)), kind(buffer_kind), bytes(static_cast<std::size_t>(stride) * height, kPrefill) {}
  std::uint64_t hash(bool canonical_nan) const {
    if (!canonical_nan || kind == Kind::bytes) return fnv1a(bytes.data(), bytes.size());
    std::vector<std::uint8_t> copy = bytes;
    if (kind == Kind::f32) canonicalise_nans<std::uint32_t>(copy, 0x7f800000u, 0x7fc00000u);
    if (kind == Kind::f16) canonicalise_nans<std::uint16_t>(copy, 0x7c00u, 0x7e00u);
    return fnv1a(copy.data(), copy.size());
  }
};

// ---- formats ---------------------------------------------------------------------------------

struct ColorCase {
  const char* name;
  ColorFormat format;
  ColorLayout layout;
  int channels, pixel_bytes;  // pixel_bytes: per plane
};
constexpr ColorCase kColors[] = {
    {"float32x1", ColorFormat::float32, ColorLayout::planar, 1, 4},
    {"float32x3", ColorFormat::float32, ColorLayout::planar, 3, 4},
    {"float32x4", ColorFormat::float32, ColorLayout::planar, 4, 4},
    {"float32_rgba", ColorFormat::float32, ColorLayout::interleaved_rgba, 4, 16},
    {"rgba8", ColorFormat::rgba8, ColorLayout::interleaved_rgba, 4, 4},
    {"rgba8_srgb", ColorFormat::rgba8_srgb, ColorLayout::interleaved_rgba, 4, 4},
    {"rgba16f", ColorFormat::rgba16f, ColorLayout::interleaved_rgba, 4, 8},
};
constexpr DepthFormat kDepths[] = {DepthFormat::float32, DepthFormat::unorm16, DepthFormat::unorm24_s8,
                                   DepthFormat::s8_unorm24, DepthFormat::rgba8_packed_linear};

int planes_of(const ColorCase& c) { return c.layout == ColorLayout::planar ? c.channels : 1; }
int depth_bytes(DepthFormat f) { return f == DepthFormat::float32 ? 4 : bytes_per_pixel(f); }
std::ptrdiff_t row_bytes(int width, int pixel_bytes) { return std::ptrdiff_t{width} * pixel_bytes + kPadBytes; }

// A colour view (ColorView or MutableColorView) over 1..4 float planes or one interleaved plane.
template <class View, class Byte>
View color_view(const ColorCase& c, Byte* const* planes, int width, int height, std::ptrdiff_t stride) {
  using Float = typename std::conditional<std::is_const<Byte>::value, const float, float>::type;
  if (c.format != ColorFormat::float32) return View::packed(c.format, planes[0], width, height, stride);
  if (c.layout == ColorLayout::interleaved_rgba)
    return View::rgba(reinterpret_cast<Float*>(planes[0]), width, height, stride / 4);
  View view;
  view.channels = c.channels;
  for (int p = 0; p < c.channels; ++p) view.plane[p] = {reinterpret_cast<Float*>(planes[p]), width, height, stride / 4};
  return view;
}

// ---- sources ---------------------------------------------------------------------------------

// One rendered view in one colour and depth format, read through `view` with `decoder`.
// Not copyable in practice: `view` points into the vectors (moving them keeps their storage).
struct Source {
  std::vector<std::vector<std::uint8_t>> color;  // planes
  std::vector<std::uint8_t> depth;
  SourceView view;
  DepthDecoder decoder;
};

void store_color(const ColorCase& cc, const float rgba[4], std::uint8_t* const* planes) {
  for (int c = 0; c < 4; ++c) {
    const auto unorm8 = static_cast<std::uint8_t>(formats::float_to_unorm(rgba[c], 8));
    const std::uint16_t half = formats::float_to_half(rgba[c]);
    switch (cc.format) {
      case ColorFormat::float32:
        if (cc.layout == ColorLayout::interleaved_rgba) std::memcpy(planes[0] + 4 * c, &rgba[c], 4);
        else if (c < cc.channels) std::memcpy(planes[c], &rgba[c], 4);
        break;
      case ColorFormat::rgba8: planes[0][c] = unorm8; break;
      case ColorFormat::rgba8_srgb: planes[0][c] = c < 3 ? formats::linear_to_srgb(rgba[c]) : unorm8; break;
      case ColorFormat::rgba16f: std::memcpy(planes[0] + 2 * c, &half, 2); break;
    }
  }
}

// Depth z in the decoder's encoding (d), stored in the format; the stencil byte (D24S8) and the
// packed format's A byte hold a pattern that output depth must carry along.
void store_depth(DepthFormat df, double z, float d, std::uint32_t stencil, float near, float far, std::uint8_t* word) {
  const auto put = [word](auto value) { std::memcpy(word, &value, sizeof value); };
  switch (df) {
    case DepthFormat::float32: put(d); break;
    case DepthFormat::unorm16: put(static_cast<std::uint16_t>(formats::float_to_unorm(d, 16))); break;
    case DepthFormat::unorm24_s8: put(formats::float_to_unorm(d, 24) | stencil << 24); break;
    case DepthFormat::s8_unorm24: put(formats::float_to_unorm(d, 24) << 8 | stencil); break;
    case DepthFormat::rgba8_packed_linear:
      formats::pack_linear_value(static_cast<float>((z - near) / (far - near)), word);
      word[3] = static_cast<std::uint8_t>(stencil);
      break;
  }
}

Source make_source(const rs::Scene& scene, const rs::View& v, const ColorCase& cc, DepthFormat df,
                   DepthEncoding encoding) {
  const int w = v.width(), h = v.height();
  const std::ptrdiff_t cstride = row_bytes(w, cc.pixel_bytes), dstride = row_bytes(w, depth_bytes(df));
  const float near = static_cast<float>(scene.near_plane()), far = static_cast<float>(scene.far_plane());
  Source s;
  s.decoder = df == DepthFormat::rgba8_packed_linear ? DepthDecoder::linear() : scene.decoder(encoding);
  s.color.assign(planes_of(cc), std::vector<std::uint8_t>(static_cast<std::size_t>(cstride) * h, 0));
  s.depth.assign(static_cast<std::size_t>(dstride) * h, 0);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      // Alpha varies with the object seen (0 where none), so that it is content too.
      const std::uint8_t object = v.object[static_cast<std::size_t>(y) * w + x];
      float rgba[4] = {0, 0, 0, object == 255 ? 0.0f : 0.25f + 0.25f * static_cast<float>(object % 4)};
      for (int c = 0; c < 3; ++c) rgba[c] = v.color.plane_data(c)[y * v.color.stride() + x];
      std::uint8_t* planes[4];
      for (int p = 0; p < planes_of(cc); ++p) planes[p] = s.color[p].data() + y * cstride + x * cc.pixel_bytes;
      store_color(cc, rgba, planes);
      const double z = v.depth.plane_data(0)[y * v.depth.stride() + x];
      const std::uint32_t stencil = static_cast<std::uint32_t>(x * 7 + y * 3) & 0xffu;
      store_depth(df, z, s.decoder.encode(z), stencil, near, far, s.depth.data() + y * dstride + x * depth_bytes(df));
    }
  }
  std::vector<const std::uint8_t*> planes;
  for (const auto& p : s.color) planes.push_back(p.data());
  s.view.color = color_view<ColorView>(cc, planes.data(), w, h, cstride);
  if (df == DepthFormat::float32)
    s.view.depth = FloatPlane{reinterpret_cast<const float*>(s.depth.data()), w, h, dstride / 4};
  else if (df == DepthFormat::rgba8_packed_linear)
    s.view.depth_buffer = DepthBuffer::packed_linear(s.depth.data(), w, h, dstride, near, far);
  else
    s.view.depth_buffer = DepthBuffer::of(df, s.depth.data(), w, h, dstride);
  return s;
}

// ---- option sets -----------------------------------------------------------------------------

struct OptionSet {
  std::string name;  // as below
  Options options;   // all but method and arch, which each call sets
  EyeDirection direction = EyeDirection::centre_to_right;
  DepthEncoding encoding = DepthEncoding::standard;  // of every depth format but packed linear
  bool depth_out = true, status_out = true, source_x_out = true, pair = false;
};

// The option sets, by name: "key:value" items joined by ',' (fill, edge: HoleFill and EdgeMode; dir:
// EyeDirection; near: max_negative_parallax; probe: probe_parallax; guard; march: march_steps;
// secant: secant_max_steps; tau: hole_threshold; enc: DepthEncoding; threads; out: the outputs
// besides colour, all when not named), then "/single-eye" or "/pair". Unnamed options keep their
// defaults, but threads is 1. Each set runs with every method and format.
const char* const kOptionSets[] = {
    "fill:background,edge:clamp/single-eye",
    "fill:foreground,edge:black/single-eye",
    "fill:none,edge:none,dir:centre-to-left/single-eye",
    "fill:background,edge:mirror,dir:left-to-right/single-eye",
    "fill:foreground,edge:clamp,dir:right-to-left,near:3/single-eye",
    "fill:background,edge:mirror,dir:centre-to-left,probe:4/single-eye",
    "fill:none,edge:black,guard:3/single-eye",
    "fill:background,edge:none,threads:2/single-eye",
    "fill:background,edge:clamp,dir:left-to-right,march:5,secant:3,tau:0.5/single-eye",  // coarse steps
    "fill:foreground,edge:mirror,enc:reversed/single-eye",
    "fill:background,edge:clamp,dir:right-to-left,out:colour/single-eye",
    "fill:none,edge:clamp,out:colour+status/single-eye",
    "fill:background,edge:black,near:2,threads:2,out:colour+depth+source_x/single-eye",
    "fill:background,edge:clamp/pair",
    "fill:none,edge:mirror,guard:3,threads:2/pair",
    "fill:foreground,edge:black,near:3,probe:-2,out:colour+status+source_x/pair",
    "fill:background,edge:none,enc:reversed,out:colour+depth+source_x/pair",
};

bool parse_option_set(const std::string& name, OptionSet* s) {
  const std::size_t slash = name.find('/');
  const std::string items = name.substr(0, slash), call = slash == std::string::npos ? "" : name.substr(slash + 1);
  s->name = name;
  s->pair = call == "pair";
  s->options.threads = 1;
  Options& o = s->options;
  for (std::size_t at = 0, end; at < items.size(); at = end + 1) {
    end = std::min(items.find(',', at), items.size());
    const std::string item = items.substr(at, end - at);
    const std::size_t colon = item.find(':');
    const std::string key = item.substr(0, colon), value = colon == std::string::npos ? "" : item.substr(colon + 1);
    const char* v = value.c_str();
    const float number = std::strtof(v, nullptr);
    bool known = true;
    if (key == "fill") known = parse_hole_fill(v, &o.hole_fill);
    else if (key == "edge") known = parse_edge_mode(v, &o.edge);
    else if (key == "dir") known = parse_direction(v, &s->direction);
    else if (key == "enc") known = parse_encoding(v, &s->encoding);
    else if (key == "near") o.max_negative_parallax = number;
    else if (key == "probe") o.probe_parallax = number;
    else if (key == "tau") o.hole_threshold = number;
    else if (key == "guard") o.guard = static_cast<int>(number);
    else if (key == "threads") o.threads = static_cast<int>(number);
    else if (key == "march") o.march_steps = static_cast<int>(number);
    else if (key == "secant") o.secant_max_steps = static_cast<int>(number);
    else if (key == "out") {
      s->depth_out = value.find("+depth") != std::string::npos;
      s->status_out = value.find("+status") != std::string::npos;
      s->source_x_out = value.find("+source_x") != std::string::npos;
    } else known = false;
    if (!known) return false;
  }
  return s->pair || call == "single-eye";
}

// ---- one call --------------------------------------------------------------------------------

// Appends one eye's prefilled outputs to `buffers` and returns the view over them. `buffers` must
// not reallocate before the call (run reserves).
TargetView make_target(const ColorCase& cc, DepthFormat df, const OptionSet& set, int w, int h,
                       const std::string& prefix, std::vector<Buffer>& buffers) {
  const std::ptrdiff_t cstride = row_bytes(w, cc.pixel_bytes), dstride = row_bytes(w, depth_bytes(df));
  const std::ptrdiff_t fstride = row_bytes(w, 4), sstride = row_bytes(w, 1);
  const Kind color_kind = cc.format == ColorFormat::float32 ? Kind::f32
                           : cc.format == ColorFormat::rgba16f ? Kind::f16 : Kind::bytes;
  // An output's bytes; an unwanted one is null, with an empty buffer (hashed all the same).
  const auto add = [&](const std::string& name, Kind kind, std::ptrdiff_t stride, bool wanted) {
    buffers.emplace_back(prefix + name, kind, wanted ? stride : 0, h);
    return wanted ? buffers.back().bytes.data() : nullptr;
  };
  std::uint8_t* planes[4];
  for (int p = 0; p < planes_of(cc); ++p) planes[p] = add("colour" + std::to_string(p), color_kind, cstride, true);
  std::uint8_t* depth = add("depth", df == DepthFormat::float32 ? Kind::f32 : Kind::bytes, dstride, set.depth_out);
  std::uint8_t* status = add("status", Kind::bytes, sstride, set.status_out);
  std::uint8_t* source_x = add("source_x", Kind::f32, fstride, set.source_x_out);
  TargetView t;
  t.color = color_view<MutableColorView>(cc, planes, w, h, cstride);
  if (df == DepthFormat::float32)
    t.depth = MutableFloatPlane{reinterpret_cast<float*>(depth), w, h, dstride / 4};
  else
    t.depth_buffer = MutableDepthBuffer::of(df, depth, w, h, dstride);
  t.status = BytePlane{status, w, h, sstride};
  t.source_x = MutableFloatPlane{reinterpret_cast<float*>(source_x), w, h, fstride / 4};
  return t;
}

Status run(const rs::Scene& scene, const Source& src, const ColorCase& cc, DepthFormat df, const OptionSet& set,
           Method method, Arch arch, std::vector<Buffer>& buffers) {
  Options o = set.options;
  o.method = method;
  o.arch = arch;
  const int w = src.view.color.width() - 2 * o.guard, h = src.view.color.height();
  // 12 px of parallax at infinity for a centre-to-side eye at every width (24 px side to side),
  // so that even the narrow frames have walls, holes and clipping; the scene's convergence.
  const ParallaxModel model = StereoCamera{24.0 / w, scene.recommended_stereo().convergence}.parallax(w, set.direction);
  buffers.clear();
  buffers.reserve(14);
  const TargetView first = make_target(cc, df, set, w, h, set.pair ? "left." : "", buffers);
  if (!set.pair) return reproject::reproject(src.view, src.decoder, model, o, first);
  const TargetView second = make_target(cc, df, set, w, h, "right.", buffers);
  return reproject_pair(src.view, src.decoder, model, o, first, second);
}

// Prints each configuration's line (or, with --versus-scalar, compares it with scalar's) and counts.
struct Report {
  bool canonical_nan = false, versus_scalar = false;
  std::uint64_t total = kFnvOffset;  // of every line printed
  long count = 0, errors = 0, compared = 0, mismatches = 0, sse_compared = 0, sse_differ = 0;
  std::vector<std::uint64_t> reference;  // --versus-scalar: the scalar call's hash of each buffer

  void add(const std::string& name, Arch arch, const Status& status, const std::vector<Buffer>& buffers) {
    ++count;
    if (!status) std::fprintf(stderr, "%s: %s\n", name.c_str(), status.message());
    errors += !status;
    std::vector<std::uint64_t> hashes;
    for (const Buffer& b : buffers) hashes.push_back(b.hash(canonical_nan));
    if (!versus_scalar) {
      const std::string hash = status ? hex(fnv1a(hashes.data(), hashes.size() * sizeof hashes[0]))
                                      : std::string("error:") + to_string(status.code());
      const std::string line = name + " " + hash + "\n";
      std::fputs(line.c_str(), stdout);
      total = fnv1a(line.data(), line.size(), total);
      return;
    }
    if (arch == Arch::scalar) reference = status ? hashes : std::vector<std::uint64_t>{};
    if (arch == Arch::scalar || !status || reference.empty()) return;
    std::string differ;  // the names of the buffers that differ
    for (std::size_t b = 0; b < hashes.size(); ++b)
      if (hashes[b] != reference[b]) differ += (differ.empty() ? "" : ",") + buffers[b].name;
    if (arch == Arch::sse) {  // unfused: need not match
      ++sse_compared;
      sse_differ += !differ.empty();
      return;
    }
    ++compared;
    mismatches += !differ.empty();
    if (!differ.empty()) std::printf("MISMATCH %s: %s\n", name.c_str(), differ.c_str());
  }
};

}  // namespace

int main(int argc, char** argv) {
  Report report;
  std::optional<Arch> only;
  std::optional<std::regex> only_names;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    Arch a;
    if (arg == "--canonical-nan") {
      report.canonical_nan = true;
    } else if (arg == "--versus-scalar") {
      report.versus_scalar = true;
    } else if (arg == "--arch" && i + 1 < argc && parse_arch(argv[++i], &a)) {
      only = a;
    } else if (arg == "--only" && i + 1 < argc) {
      only_names = std::regex(argv[++i]);
    } else {
      std::fprintf(stderr,
                   "usage: %s [--arch scalar|sse|avx2|avx512|neon] [--only REGEX] [--canonical-nan] [--versus-scalar]\n",
                   argv[0]);
      return 2;
    }
  }
  if (only && !arch_supported(*only)) {
    std::fprintf(stderr, "reproject_golden: %s is not supported by this build and CPU\n", to_string(*only));
    return 2;
  }
  std::vector<OptionSet> option_sets(std::size(kOptionSets));
  for (std::size_t i = 0; i < option_sets.size(); ++i) {
    if (!parse_option_set(kOptionSets[i], &option_sets[i])) {
      std::fprintf(stderr, "reproject_golden: bad option set \"%s\"\n", kOptionSets[i]);
      return 2;
    }
  }
  std::vector<Arch> arches;  // in the library's order: scalar first, the reference of --versus-scalar
  for (int a = 0; a < kArchCount; ++a) {
    const Arch arch = static_cast<Arch>(a);
    if (arch_supported(arch) && (!only || arch == *only || (report.versus_scalar && arch == Arch::scalar)))
      arches.push_back(arch);
  }

  // With --only, a frame none of whose configurations match is neither rendered nor converted (so
  // that an emulator tracing one call traces little else).
  auto name_of = [&](const std::string& frame, Method method, Arch arch, const OptionSet& set) {
    return frame + to_string(method) + "/" + to_string(arch) + "/" + set.name;
  };
  auto any_match = [&](const std::string& frame) {
    if (!only_names) return true;
    for (int m = 0; m < kMethodCount; ++m)
      for (const OptionSet& set : option_sets)
        for (Arch arch : arches)
          if (std::regex_search(name_of(frame, static_cast<Method>(m), arch, set), *only_names)) return true;
    return false;
  };
  const rs::SceneId scenes[] = {rs::SceneId::room, rs::SceneId::edge};
  const struct { int width, height; } sizes[] = {{67, 9}, {130, 7}, {257, 5}, {333, 40}};
  const auto start = std::chrono::steady_clock::now();
  std::vector<Buffer> buffers;
  for (rs::SceneId id : scenes) {
    const rs::Scene scene = rs::Scene::make(id);
    for (const auto& size : sizes) {
      const std::string at_size = std::string(scene.name()) + "/" + std::to_string(size.width) + "x" +
                                  std::to_string(size.height) + "/";
      bool size_needed = false;
      for (const ColorCase& cc : kColors)
        for (DepthFormat df : kDepths) size_needed = size_needed || any_match(at_size + cc.name + "+" + to_string(df) + "/");
      if (!size_needed) continue;
      rs::View view;
      const Status rendered = scene.render(scene.camera(size.width, size.height), &view, 1);
      if (!rendered) {
        std::fprintf(stderr, "reproject_golden: render %s: %s\n", scene.name(), rendered.message());
        return 2;
      }
      for (const ColorCase& cc : kColors) {
        for (DepthFormat df : kDepths) {
          const std::string frame = at_size + cc.name + "+" + to_string(df) + "/";
          if (!any_match(frame)) continue;
          const Source sources[] = {make_source(scene, view, cc, df, DepthEncoding::standard),
                                    make_source(scene, view, cc, df, DepthEncoding::reversed)};
          for (int m = 0; m < kMethodCount; ++m) {
            const Method method = static_cast<Method>(m);
            for (const OptionSet& set : option_sets) {
              const Source& src = sources[set.encoding == DepthEncoding::standard ? 0 : 1];
              for (Arch arch : arches) {
                const std::string name = name_of(frame, method, arch, set);
                if (only_names && !std::regex_search(name, *only_names)) continue;
                const Status status = run(scene, src, cc, df, set, method, arch, buffers);
                report.add(name, arch, status, buffers);
              }
            }
          }
        }
      }
    }
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (!report.versus_scalar) {
    std::printf("total %s %ld\n", hex(report.total).c_str(), report.count);
  } else {
    std::printf("versus scalar: %ld configurations of fused SIMD sets compared, %ld mismatches", report.compared,
                report.mismatches);
    if (report.sse_compared)
      std::printf("; sse (unfused, need not match): %ld of %ld differ", report.sse_differ, report.sse_compared);
    std::printf("\n");
  }
  std::fprintf(stderr, "reproject_golden: %ld configurations (%ld failed calls) in %.1f s\n", report.count,
               report.errors, seconds);
  return report.errors || report.mismatches ? 1 : 0;
}
