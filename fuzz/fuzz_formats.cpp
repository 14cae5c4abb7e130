// libFuzzer harness for the engine-native pixel formats (reproject/formats.hpp, docs/BEHAVIOUR.md
// "Pixel formats"): colour as rgba8, rgba8_srgb, rgba16f (ColorView::packed) or float
// (interleaved or planar), depth as a float plane or a depth buffer in float32, unorm16,
// unorm24_s8, s8_unorm24 or rgba8_packed_linear (SourceView::depth_buffer), through reproject()
// and reproject_pair(), each with the pool and with a ParallelFor. The fuzzer picks the size (up
// to 300 x 8), the guard band, the strides (bytes for the byte buffers, odd ones included) and
// the base pointers' misalignment, the formats, the packed-linear range, the raw bytes of colour
// and depth (any bits: NaN and infinite halves, any stencil; or runs of codes; or an in-range scene),
// which outputs exist (depth in the source's format, status, source_x), the decoder, the model,
// the options, and sometimes one invalid combination (formats that differ between source and
// target, both depth and depth_buffer set, a stride below the row, a misaligned float32 depth
// buffer, an empty packed-linear range, unknown enum values, a size off by one, a null buffer,
// an overlapping output, a guard band that leaves no columns, an invalid option).
//
// Every buffer is its own heap block of exactly the bytes its rows span (plus the base offset),
// with everything else (the offset, the gaps between rows) poisoned for ASan and filled with a
// known byte. What is checked, besides "no crash, no sanitizer report":
//  * the returned code is a known StatusCode with a non-empty message; a valid call returns ok,
//    an invalid one returns one of the codes its fault may give (and an empty frame is ok unless
//    the fault is one the library checks before the size: decoder, model, options, both depths);
//  * a call that fails writes nothing; no call writes outside its output rows (the gaps and the
//    offset keep their byte, read back after every call);
//  * per pixel of a successful call: status 0..3; source_x finite and consistent with the
//    status; colour and depth left alone exactly where the options say nothing is written;
//    `EdgeMode::black` writes zeros; written colour lies within the source row's range of that
//    channel (bytes, halves and floats alike, when the row's values are finite); unorm depth
//    codes within the row's codes (D16 exactly, D24 within one code) for affine decoders; the
//    stencil / A byte of written depth is one of the source row's;
//  * the public call equals detail::reproject_with() on the same kernels; threads 1 equals
//    threads 2 (and a ParallelFor) through reproject(); reproject_pair() equals two single calls;
//  * for every instruction set this CPU has (arch_supported), detail::compiled_kernels(arch)
//    equals detail::reference_kernels(arch) byte for byte (float and half colour: any NaN equals
//    any NaN; float depth too when the source depth is not all finite).
// A failed check prints what differed and aborts, so libFuzzer keeps the input.
#include <fuzzer/FuzzedDataProvider.h>
#include <sanitizer/asan_interface.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <vector>

#include "kernels/dispatch.hpp"
#include "src/reproject_internal.hpp"
#include "reproject/reproject.hpp"
#include "tests/support/arch_report.hpp"

namespace {

using namespace reproject;

[[noreturn]] void fail(const char* what, int x = -1, int y = -1) {
  std::fprintf(stderr, "fuzz_formats: check failed: %s (x %d, y %d)\n", what, x, y);
  std::abort();
}
#define CHECK(condition)                \
  do {                                  \
    if (!(condition)) fail(#condition); \
  } while (0)
#define CHECK_AT(condition, x, y)             \
  do {                                        \
    if (!(condition)) fail(#condition, x, y); \
  } while (0)

constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr std::uint8_t kGapByte = 0xE7;           // offset and gaps of every block
constexpr std::uint32_t kFloatSentinel = 0xC0E80000u;  // -7.25f: unwritten float outputs
constexpr std::uint32_t kByteSentinel = 0xABABABABu;   // unwritten byte outputs (codes, halves, status)

// ---- Buffers ------------------------------------------------------------------------------------

// `rows` rows of `row` bytes, `stride` bytes apart (stride >= row), starting `offset` bytes into
// a heap block of exactly offset + the bytes the rows span. Outside the rows every byte is
// kGapByte and poisoned. Rows start filled with a 4-byte pattern (from each row's start).
class Block {
 public:
  Block() = default;
  Block(const Block&) = delete;
  Block& operator=(const Block&) = delete;
  ~Block() {
    if (storage_) {
      ASAN_UNPOISON_MEMORY_REGION(storage_, allocated_);
      std::free(storage_);
    }
  }

  void init(int rows, std::ptrdiff_t row, std::ptrdiff_t stride, int offset, std::uint32_t pattern) {
    rows_ = rows;
    row_ = row;
    stride_ = stride;
    offset_ = offset;
    pattern_ = pattern;
    const std::size_t span = rows > 0 && row > 0 ? static_cast<std::size_t>((rows - 1) * stride + row) : 0;
    allocated_ = std::max<std::size_t>(static_cast<std::size_t>(offset) + span, 1);
    void* memory = nullptr;
    if (posix_memalign(&memory, 64, allocated_) != 0) std::abort();
    storage_ = static_cast<std::uint8_t*>(memory);
    std::memset(storage_, kGapByte, allocated_);
    data_ = storage_ + offset;
    for (int y = 0; y < rows_; ++y)
      for (std::ptrdiff_t i = 0; i < row_; ++i) row_ptr(y)[i] = pattern_byte(i);
    poison();
  }

  std::uint8_t* data() const { return data_; }
  std::uint8_t* row_ptr(int y) const { return data_ + static_cast<std::ptrdiff_t>(y) * stride_; }
  std::ptrdiff_t stride() const { return stride_; }
  std::ptrdiff_t row_bytes() const { return row_; }
  int rows() const { return rows_; }
  std::uint8_t pattern_byte(std::ptrdiff_t i) const { return static_cast<std::uint8_t>(pattern_ >> (8 * (i & 3))); }

  // Bytes [begin, begin + count) of row y still hold the fill pattern.
  bool is_pattern(int y, std::ptrdiff_t begin, std::ptrdiff_t count) const {
    for (std::ptrdiff_t i = begin; i < begin + count; ++i)
      if (row_ptr(y)[i] != pattern_byte(i)) return false;
    return true;
  }
  bool untouched() const {
    for (int y = 0; y < rows_; ++y)
      if (!is_pattern(y, 0, row_)) return false;
    return true;
  }
  // FNV-1a of the rows' bytes.
  std::uint64_t hash() const {
    std::uint64_t h = 1469598103934665603ull;
    for (int y = 0; y < rows_; ++y)
      for (std::ptrdiff_t i = 0; i < row_; ++i) h = (h ^ row_ptr(y)[i]) * 1099511628211ull;
    return h;
  }
  // Every byte outside the rows (the base offset, the gaps) still holds kGapByte.
  bool gaps_intact() {
    if (!storage_) return true;
    ASAN_UNPOISON_MEMORY_REGION(storage_, allocated_);
    bool intact = true;
    for (std::size_t i = 0; i < allocated_ && intact; ++i) {
      const std::ptrdiff_t p = static_cast<std::ptrdiff_t>(i) - offset_;
      const bool in_row = p >= 0 && row_ > 0 && p / stride_ < rows_ && p % stride_ < row_;
      if (!in_row && storage_[i] != kGapByte) intact = false;
    }
    poison();
    return intact;
  }

 private:
  void poison() {
    ASAN_POISON_MEMORY_REGION(storage_, allocated_);
    for (int y = 0; y < rows_; ++y)
      if (row_ > 0) ASAN_UNPOISON_MEMORY_REGION(row_ptr(y), static_cast<std::size_t>(row_));
  }

  std::uint8_t* storage_ = nullptr;
  std::uint8_t* data_ = nullptr;
  std::size_t allocated_ = 0;
  int rows_ = 0;
  std::ptrdiff_t row_ = 0;
  std::ptrdiff_t stride_ = 0;
  int offset_ = 0;
  std::uint32_t pattern_ = 0;
};

// ---- What the fuzzer chose ----------------------------------------------------------------------

struct ColorSpec {
  ColorFormat format = ColorFormat::rgba8;  // float32: `interleaved` or `channels` planes
  bool interleaved = true;
  int channels = 4;
  int pad = 0;     // stride - row: bytes (packed) or floats (float32)
  int offset = 0;  // base misalignment in bytes (packed only)
};
struct DepthSpec {
  DepthFormat format = DepthFormat::float32;
  bool plane = false;  // float32 as the `depth` float plane instead of `depth_buffer`
  int pad = 0;         // stride - row: bytes (buffers) or floats (the float plane)
  int offset = 0;      // base misalignment in bytes (buffers other than float32)
  float linear_near = 0.0f, linear_far = 1.0f;
};

// One invalid thing, or none; each names the codes the library may answer it with.
enum class Fault : int {
  none,
  target_color_format,   // the target's colour format differs from the source's
  source_color_unknown,  // ColorFormat out of range
  target_color_unknown,
  source_depth_unknown,  // DepthFormat out of range
  target_depth_format,   // the output depth_buffer in another format than the source depth
  source_both_depths,    // depth and depth_buffer both set (checked before the frame size)
  target_both_depths,
  target_float_depth,    // a `depth` float plane output for a non-float source depth
  stride_too_small,
  float_depth_misaligned,
  packed_range,          // rgba8_packed_linear with a non-finite or empty range
  size_off,              // a view's width or height off by one, or negative
  null_data,
  color_shape,           // packed with planar layout / 3 channels; float with 0 or 5 channels
  guard_too_wide,
  bad_option,            // checked before the frame size
  color_layout_unknown,
  aliasing,
  count
};

unsigned bit(StatusCode code) { return 1u << static_cast<int>(code); }

struct Config {
  int width = 0, height = 0, target_width = 0;
  ColorSpec source_color, target_color;
  DepthSpec source_depth, target_depth;
  bool depth_out = false, status_out = false, source_x_out = false;
  int status_pad = 0, source_x_pad = 0;
  Fault fault = Fault::none;
  int variant = 0;  // which buffer or value the fault hits
  int api = 0;      // 0 reproject, 1 reproject + ParallelFor, 2 reproject_pair, 3 reproject_pair + ParallelFor
  int color_mode = 0, depth_mode = 0;
};

int color_bytes_per_pixel(const ColorSpec& c) {
  if (c.format == ColorFormat::float32) return c.interleaved ? 16 : 4;
  const int bpp = bytes_per_pixel(c.format);
  return bpp > 0 ? bpp : 4;  // an unknown format: a block of 4-byte pixels
}
int depth_bytes_per_pixel(DepthFormat f) {
  const int bpp = bytes_per_pixel(f);
  return bpp > 0 ? bpp : 4;
}
const char* float_layout(const ColorSpec& c) {
  return c.format != ColorFormat::float32 ? "" : c.interleaved ? " rgba" : " planar";
}
int color_blocks(const ColorSpec& c) { return c.format == ColorFormat::float32 && !c.interleaved ? c.channels : 1; }

void init_color_blocks(const ColorSpec& c, int width, int height, Block* blocks, std::uint32_t pattern) {
  const std::ptrdiff_t row = static_cast<std::ptrdiff_t>(width) * color_bytes_per_pixel(c);
  const bool floats = c.format == ColorFormat::float32;
  for (int k = 0; k < color_blocks(c); ++k)
    blocks[k].init(height, row, row + (floats ? 4 * c.pad : c.pad), floats ? 0 : c.offset, pattern);
}

template <class T>
ColorViewT<T> color_view(const ColorSpec& c, Block* blocks, int width, int height) {
  using View = ColorViewT<T>;
  if (c.format != ColorFormat::float32) return View::packed(c.format, blocks[0].data(), width, height, blocks[0].stride());
  if (c.interleaved) return View::rgba(reinterpret_cast<T*>(blocks[0].data()), width, height, blocks[0].stride() / 4);
  View view;
  view.layout = ColorLayout::planar;
  view.channels = c.channels;
  for (int k = 0; k < c.channels; ++k)
    view.plane[k] = PlaneView<T>{reinterpret_cast<T*>(blocks[k].data()), width, height, blocks[k].stride() / 4};
  return view;
}

void init_depth_block(const DepthSpec& d, int width, int height, Block& block, std::uint32_t pattern) {
  const std::ptrdiff_t row = static_cast<std::ptrdiff_t>(width) * depth_bytes_per_pixel(d.format);
  const bool aligned = d.plane || d.format == DepthFormat::float32;
  block.init(height, row, row + (d.plane ? 4 * d.pad : d.pad), aligned ? 0 : d.offset, pattern);
}

// ---- Source -------------------------------------------------------------------------------------

struct Source {
  Block color[4];
  Block depth;
  Block extra_depth;  // Fault::source_both_depths
  SourceView view;
  bool color_finite = true;  // every float / half colour value finite

  std::uint64_t hash() const {
    std::uint64_t h = depth.hash() ^ (extra_depth.hash() << 1);
    for (const Block& b : color) h = h * 31 + b.hash();
    return h;
  }
  bool depth_finite = true;  // every float32 depth value finite (other formats always are)
};

// Awkward values by index, for halves and floats.
std::uint16_t table_half(std::uint8_t k) {
  static const std::uint16_t kTable[] = {0x0000, 0x8000, 0x3c00, 0xbc00, 0x7bff, 0xfbff, 0x7c00, 0xfc00,
                                         0x7e00, 0x7c01, 0xfe00, 0x0001, 0x8001, 0x03ff, 0x0400, 0x3800};
  return kTable[k & 15];
}
float table_float(std::uint8_t k) {
  static const float kTable[] = {0.0f, -0.0f, 1.0f, -1.0f, 0.5f, FLT_MAX, -FLT_MAX, kInf,
                                 -kInf, kNaN, std::numeric_limits<float>::denorm_min(), FLT_MIN, 1e30f, -1e30f, 255.0f, 3.0f};
  return kTable[k & 15];
}

class ByteStream {
 public:
  explicit ByteStream(std::vector<std::uint8_t> bytes) : bytes_(std::move(bytes)) {}
  std::uint8_t next() { return bytes_.empty() ? 0 : bytes_[k_++ % bytes_.size()]; }
  std::uint32_t word(int bytes) {
    std::uint32_t w = 0;
    for (int b = 0; b < bytes; ++b) w |= static_cast<std::uint32_t>(next()) << (8 * b);
    return w;
  }

 private:
  std::vector<std::uint8_t> bytes_;
  std::size_t k_ = 0;
};

// Colour: mode 0 raw bytes; 1 awkward values (halves, floats) or raw bytes; 2 values in [0, 1]
// (halves, floats; bytes stay raw).
void fill_color(const Config& cfg, Source& src, ByteStream& in) {
  const ColorSpec& c = cfg.source_color;
  for (int k = 0; k < color_blocks(c); ++k) {
    for (int y = 0; y < cfg.height; ++y) {
      std::uint8_t* row = src.color[k].row_ptr(y);
      if (c.format == ColorFormat::rgba16f) {
        for (std::ptrdiff_t i = 0; i < src.color[k].row_bytes() / 2; ++i) {
          std::uint16_t h = cfg.color_mode == 0   ? static_cast<std::uint16_t>(in.word(2))
                            : cfg.color_mode == 1 ? table_half(in.next())
                                                  : formats::float_to_half(static_cast<float>(in.next()) / 255.0f);
          std::memcpy(row + 2 * i, &h, 2);
          src.color_finite = src.color_finite && (h & 0x7c00) != 0x7c00;
        }
      } else if (c.format == ColorFormat::float32) {
        for (std::ptrdiff_t i = 0; i < src.color[k].row_bytes() / 4; ++i) {
          float v;
          if (cfg.color_mode == 0) {
            const std::uint32_t bits = in.word(4);
            std::memcpy(&v, &bits, 4);
          } else {
            v = cfg.color_mode == 1 ? table_float(in.next()) : static_cast<float>(in.next()) / 255.0f;
          }
          std::memcpy(row + 4 * i, &v, 4);
          src.color_finite = src.color_finite && std::isfinite(v);
        }
      } else {
        for (std::ptrdiff_t i = 0; i < src.color[k].row_bytes(); ++i) row[i] = in.next();
      }
    }
  }
}

// Stores the stored value d (or, for packed linear, linear depth d) in the format.
void store_depth(const DepthSpec& d, float value, std::uint8_t stencil, std::uint8_t* px) {
  switch (d.format) {
    case DepthFormat::float32: std::memcpy(px, &value, 4); break;
    case DepthFormat::unorm16: {
      const std::uint16_t u = static_cast<std::uint16_t>(formats::float_to_unorm(value, 16));
      std::memcpy(px, &u, 2);
      break;
    }
    case DepthFormat::unorm24_s8:
    case DepthFormat::s8_unorm24: {
      const std::uint32_t u = formats::float_to_unorm(value, 24);
      const std::uint32_t w = d.format == DepthFormat::unorm24_s8 ? (u | static_cast<std::uint32_t>(stencil) << 24)
                                                                    : (u << 8 | stencil);
      std::memcpy(px, &w, 4);
      break;
    }
    case DepthFormat::rgba8_packed_linear:
      formats::pack_linear_value((value - d.linear_near) / (d.linear_far - d.linear_near), px);
      px[3] = stencil;
      break;
    default: std::memcpy(px, &value, 4); break;  // an unknown format: any bits
  }
}

// Depth: mode 0 raw bytes; 1 runs of one raw code (flat surfaces, walls between them); 2 an
// in-range scene of flat and sloped runs (view depth near .. 64 near, or disparity 0 .. 16 px)
// stored in the format.
void fill_depth(const Config& cfg, const DepthDecoder& decoder, Source& src, ByteStream& in) {
  const DepthSpec& d = cfg.source_depth;
  const int bpp = depth_bytes_per_pixel(d.format);
  for (int y = 0; y < cfg.height; ++y) {
    std::uint8_t* row = src.depth.row_ptr(y);
    int x = 0;
    while (x < cfg.width) {
      const int length = cfg.depth_mode == 0 ? 1 : 1 + (in.next() & 31);
      const std::uint32_t code = in.word(bpp);
      const double z0 = 1.0 + in.next() / 4.0;
      const double slope = (static_cast<int>(in.next()) - 128) / 512.0;
      for (int k = 0; k < length && x < cfg.width; ++k, ++x) {
        std::uint8_t* px = row + static_cast<std::ptrdiff_t>(x) * bpp;
        if (cfg.depth_mode == 0) {
          const std::uint32_t w = in.word(bpp);
          std::memcpy(px, &w, static_cast<std::size_t>(bpp));
        } else if (cfg.depth_mode == 1) {
          std::uint32_t w = code;
          if (bpp == 4 && d.format != DepthFormat::float32) {  // the stencil / A byte varies per pixel
            const std::uint8_t s = in.next();
            if (d.format == DepthFormat::s8_unorm24) w = (w & ~0xffu) | s;
            else w = (w & 0x00ffffffu) | static_cast<std::uint32_t>(s) << 24;
          }
          std::memcpy(px, &w, static_cast<std::size_t>(bpp));
        } else {
          const double z = std::max(1.0, z0 + slope * k);
          float value;
          if (decoder.encoding() == DepthEncoding::disparity) value = static_cast<float>((z - 1.0) / 4.0);
          else if (decoder.encoding() == DepthEncoding::linear || d.format == DepthFormat::rgba8_packed_linear)
            value = static_cast<float>(d.format == DepthFormat::rgba8_packed_linear
                                           ? d.linear_near + (z - 1.0) / 64.0 * (d.linear_far - d.linear_near)
                                           : z);
          else value = decoder.encode(decoder.near_plane() * z);
          store_depth(d, value, in.next(), px);
        }
        if (d.format == DepthFormat::float32) {
          float v;
          std::memcpy(&v, px, 4);
          src.depth_finite = src.depth_finite && std::isfinite(v);
        }
      }
    }
  }
}

// ---- Target -------------------------------------------------------------------------------------

std::uint32_t color_pattern(const ColorSpec& c) { return c.format == ColorFormat::float32 ? kFloatSentinel : kByteSentinel; }
std::uint32_t depth_pattern(const DepthSpec& d) {
  return d.plane || d.format == DepthFormat::float32 ? kFloatSentinel : kByteSentinel;
}

// A stride below the row: one byte / element short, zero, or negative.
std::ptrdiff_t small_stride(std::ptrdiff_t row, int variant) {
  return variant % 3 == 0 ? row - 1 : variant % 3 == 1 ? 0 : -row;
}

struct Target {
  Block color[4];
  Block depth;
  Block extra_depth;  // Fault::target_both_depths, target_float_depth
  Block status;
  Block source_x;
  TargetView view;

  Target(const Config& cfg, Source& src) {
    const int w = cfg.target_width, h = cfg.height;
    init_color_blocks(cfg.target_color, w, h, color, color_pattern(cfg.target_color));
    view.color = color_view<float>(cfg.target_color, color, w, h);
    if (cfg.depth_out) {
      const DepthSpec& d = cfg.target_depth;
      init_depth_block(d, w, h, depth, depth_pattern(d));
      if (d.plane) {
        view.depth = MutableFloatPlane{reinterpret_cast<float*>(depth.data()), w, h, depth.stride() / 4};
      } else {
        view.depth_buffer = MutableDepthBuffer::of(d.format, depth.data(), w, h, depth.stride());
        view.depth_buffer.linear_near = d.linear_near;
        view.depth_buffer.linear_far = d.linear_far;
      }
    }
    if (cfg.status_out) {
      status.init(h, w, w + cfg.status_pad, 0, kByteSentinel);
      view.status = BytePlane{status.data(), w, h, status.stride()};
    }
    if (cfg.source_x_out) {
      source_x.init(h, 4 * static_cast<std::ptrdiff_t>(w), 4 * static_cast<std::ptrdiff_t>(w + cfg.source_x_pad), 0,
                    kFloatSentinel);
      view.source_x = MutableFloatPlane{reinterpret_cast<float*>(source_x.data()), w, h, source_x.stride() / 4};
    }
    apply_fault(cfg, src);
  }

  void apply_fault(const Config& cfg, Source& src) {
    const int w = cfg.target_width, h = cfg.height, v = cfg.variant;
    switch (cfg.fault) {
      case Fault::target_color_unknown: view.color.format = static_cast<ColorFormat>(v % 2 ? 4 : 255); break;
      case Fault::target_both_depths:
      case Fault::target_float_depth:
        // A float plane beside the depth_buffer (both set), or instead of it (a float output
        // for a non-float source depth); Config made sure the output depth is a depth_buffer.
        extra_depth.init(h, 4 * static_cast<std::ptrdiff_t>(w), 4 * static_cast<std::ptrdiff_t>(w), 0, kFloatSentinel);
        view.depth = MutableFloatPlane{reinterpret_cast<float*>(extra_depth.data()), w, h, w};
        if (cfg.fault == Fault::target_float_depth) view.depth_buffer = MutableDepthBuffer();
        break;
      case Fault::stride_too_small:
        switch ((v / 3) % 5) {
          case 0:
            if (view.color.format == ColorFormat::float32)
              view.color.plane[0].stride = small_stride((view.color.layout == ColorLayout::interleaved_rgba ? 4 : 1) * w, v);
            else view.color.pixels.stride = small_stride(w * color_bytes_per_pixel(cfg.target_color), v);
            break;
          case 1:
            if (view.depth_buffer.data)
              view.depth_buffer.stride = small_stride(w * depth_bytes_per_pixel(cfg.target_depth.format), v);
            else if (view.depth.data) view.depth.stride = small_stride(w, v);
            break;
          case 2: if (view.status.data) view.status.stride = small_stride(w, v); break;
          case 3: if (view.source_x.data) view.source_x.stride = small_stride(w, v); break;
          default: break;  // the source's (build_source)
        }
        break;
      case Fault::float_depth_misaligned:
        // A base pointer off by 1..3 bytes (still inside the block; the view is refused before
        // anything is written).
        if (v % 2 == 0 && view.depth_buffer.data && view.depth_buffer.format == DepthFormat::float32)
          view.depth_buffer.data += 1 + v % 3;
        break;
      case Fault::packed_range:
        if (v % 2 == 0 && view.depth_buffer.data && view.depth_buffer.format == DepthFormat::rgba8_packed_linear) {
          static const float kBad[][2] = {{1.0f, 1.0f}, {kNaN, 1.0f}, {0.0f, kInf}, {-kInf, 0.0f}, {0.0f, 0.0f}};
          view.depth_buffer.linear_near = kBad[v / 2 % 5][0];
          view.depth_buffer.linear_far = kBad[v / 2 % 5][1];
        }
        break;
      case Fault::size_off: {
        const int delta = v % 3 == 0 ? 1 : v % 3 == 1 ? -1 : 0;
        auto off = [&](int& width, int& height) {
          if (delta == 0) height = -1;
          else if (v / 3 % 2) width += delta;
          else height += delta;
        };
        switch (v / 6 % 5) {
          case 0:
            if (view.color.format == ColorFormat::float32) off(view.color.plane[0].width, view.color.plane[0].height);
            else off(view.color.pixels.width, view.color.pixels.height);
            break;
          case 1:
            if (view.depth_buffer.data) off(view.depth_buffer.width, view.depth_buffer.height);
            else if (view.depth.data) off(view.depth.width, view.depth.height);
            break;
          case 2: if (view.status.data) off(view.status.width, view.status.height); break;
          case 3: if (view.source_x.data) off(view.source_x.width, view.source_x.height); break;
          default: break;  // the source colour's (Source)
        }
        break;
      }
      case Fault::null_data:
        if (v % 3 == 0) {
          if (view.color.format == ColorFormat::float32) view.color.plane[0].data = nullptr;
          else view.color.pixels.data = nullptr;
        }
        break;
      case Fault::color_shape:
        if (v % 4 == 2) {
          if (view.color.format != ColorFormat::float32) view.color.layout = ColorLayout::planar;
          else view.color.channels = view.color.layout == ColorLayout::planar ? 5 : 3;
        }
        break;
      case Fault::aliasing:
        // status over another output's bytes, or over the source colour.
        if (w > 0 && h > 0) {
          Block& over = v % 2 ? src.color[0] : color[0];
          view.status = BytePlane{over.data(), w, h, over.stride()};
        }
        break;
      default: break;
    }
  }

  bool untouched() const {
    for (const Block& b : color)
      if (!b.untouched()) return false;
    return depth.untouched() && extra_depth.untouched() && status.untouched() && source_x.untouched();
  }
  bool gaps_intact() {
    bool intact = true;
    for (Block& b : color) intact = b.gaps_intact() && intact;
    for (Block* b : {&depth, &extra_depth, &status, &source_x}) intact = b->gaps_intact() && intact;
    return intact;
  }
};

// Source buffers and views, with the source's share of the fault.
void build_source(const Config& cfg, const DepthDecoder& decoder, std::vector<std::uint8_t> bytes, Source& src) {
  const int w = cfg.width, h = cfg.height, v = cfg.variant;
  init_color_blocks(cfg.source_color, w, h, src.color, 0);
  init_depth_block(cfg.source_depth, w, h, src.depth, 0);
  const std::size_t half = bytes.size() / 2;
  ByteStream color_bytes(std::vector<std::uint8_t>(bytes.begin(), bytes.begin() + static_cast<std::ptrdiff_t>(half)));
  ByteStream depth_bytes(std::vector<std::uint8_t>(bytes.begin() + static_cast<std::ptrdiff_t>(half), bytes.end()));
  fill_color(cfg, src, color_bytes);
  fill_depth(cfg, decoder, src, depth_bytes);

  src.view.color = color_view<const float>(cfg.source_color, src.color, w, h);
  const DepthSpec& d = cfg.source_depth;
  if (d.plane) {
    src.view.depth = FloatPlane{reinterpret_cast<const float*>(src.depth.data()), w, h, src.depth.stride() / 4};
  } else {
    src.view.depth_buffer = DepthBuffer::of(d.format, src.depth.data(), w, h, src.depth.stride());
    src.view.depth_buffer.linear_near = d.linear_near;
    src.view.depth_buffer.linear_far = d.linear_far;
  }

  switch (cfg.fault) {
    case Fault::source_color_unknown: src.view.color.format = static_cast<ColorFormat>(v % 2 ? 4 : 200); break;
    case Fault::source_depth_unknown:
      src.view.depth_buffer.format = static_cast<DepthFormat>(v % 2 ? kDepthFormatCount : 254);
      break;
    case Fault::source_both_depths:
      if (d.plane) {
        src.extra_depth.init(h, 4 * static_cast<std::ptrdiff_t>(w), 4 * static_cast<std::ptrdiff_t>(w), 0, 0);
        src.view.depth_buffer = DepthBuffer::of(DepthFormat::float32, src.extra_depth.data(), w, h, 4 * w);
      } else {
        src.extra_depth.init(h, 4 * static_cast<std::ptrdiff_t>(w), 4 * static_cast<std::ptrdiff_t>(w), 0, 0);
        src.view.depth = FloatPlane{reinterpret_cast<const float*>(src.extra_depth.data()), w, h, w};
      }
      break;
    case Fault::stride_too_small:
      if ((v / 3) % 5 == 4) {
        if (v % 2) {
          if (d.plane) src.view.depth.stride = small_stride(w, v);
          else src.view.depth_buffer.stride = small_stride(w * depth_bytes_per_pixel(d.format), v);
        } else if (src.view.color.format == ColorFormat::float32) {
          const bool interleaved = src.view.color.layout == ColorLayout::interleaved_rgba;
          src.view.color.plane[interleaved ? 0 : src.view.color.channels - 1].stride = small_stride((interleaved ? 4 : 1) * w, v);
        } else {
          src.view.color.pixels.stride = small_stride(w * color_bytes_per_pixel(cfg.source_color), v);
        }
      }
      break;
    case Fault::float_depth_misaligned:
      if (v % 2 == 1 && !d.plane && d.format == DepthFormat::float32) {
        // Misaligned base (inside the block: the last row loses bytes it never reads, as the
        // view is refused) or a stride that is not a multiple of 4.
        if (v % 4 == 1) src.view.depth_buffer.data += 2;
        else src.view.depth_buffer.stride += 1 + v % 3;
      }
      break;
    case Fault::packed_range:
      if (v % 2 == 1 && d.format == DepthFormat::rgba8_packed_linear && !d.plane) {
        static const float kBad[][2] = {{5.0f, 5.0f}, {0.0f, kNaN}, {kInf, 1.0f}, {-3e38f, 3e38f}, {-0.0f, 0.0f}};
        src.view.depth_buffer.linear_near = kBad[v / 2 % 5][0];
        src.view.depth_buffer.linear_far = kBad[v / 2 % 5][1];
      }
      break;
    case Fault::size_off:
      if (v / 6 % 5 == 4) {
        const int delta = v % 3 == 0 ? 1 : v % 3 == 1 ? -1 : 0;
        int& width = src.view.color.format == ColorFormat::float32 ? src.view.color.plane[0].width : src.view.color.pixels.width;
        int& height = src.view.color.format == ColorFormat::float32 ? src.view.color.plane[0].height : src.view.color.pixels.height;
        if (delta == 0) width = -1;
        else if (v / 3 % 2) width += delta;
        else height += delta;
      }
      break;
    case Fault::null_data:
      if (v % 3 == 1) {
        if (src.view.color.format == ColorFormat::float32) src.view.color.plane[0].data = nullptr;
        else src.view.color.pixels.data = nullptr;
      } else if (v % 3 == 2) {
        src.view.depth_buffer = DepthBuffer();
        src.view.depth = FloatPlane{nullptr, w, h, w};
      }
      break;
    case Fault::color_shape:
      if (v % 4 == 0) {
        if (src.view.color.format != ColorFormat::float32) src.view.color.channels = 3;
        else src.view.color.channels = src.view.color.layout == ColorLayout::planar ? 0 : 2;
      } else if (v % 4 == 1) {
        // The other layout: planar planes read as interleaved (refused for any count but 4,
        // which is given 5), interleaved as 4 planes (planes 1..3 are null), packed as planar.
        if (src.view.color.format != ColorFormat::float32) {
          src.view.color.layout = ColorLayout::planar;
        } else if (src.view.color.layout == ColorLayout::planar) {
          src.view.color.layout = ColorLayout::interleaved_rgba;
          if (src.view.color.channels == 4) src.view.color.channels = 5;
        } else {
          src.view.color.layout = ColorLayout::planar;
        }
      }  // v % 4 == 3: the target's channel count or layout differs (set in the Config)
      break;
    case Fault::color_layout_unknown: src.view.color.layout = static_cast<ColorLayout>(2 + v % 3); break;
    default: break;
  }
}

// ---- Comparisons --------------------------------------------------------------------------------

// kind: 0 bytes, 1 halves, 2 floats. nan_equal: any NaN equals any NaN.
bool same_block(const Block& x, const Block& y, int kind, bool nan_equal, const char* name) {
  const int size = kind == 0 ? 1 : kind == 1 ? 2 : 4;
  for (int r = 0; r < x.rows(); ++r) {
    const std::uint8_t* a = x.row_ptr(r);
    const std::uint8_t* b = y.row_ptr(r);
    for (std::ptrdiff_t i = 0; i + size <= x.row_bytes(); i += size) {
      if (std::memcmp(a + i, b + i, static_cast<std::size_t>(size)) == 0) continue;
      if (nan_equal && kind == 1) {
        std::uint16_t ha, hb;
        std::memcpy(&ha, a + i, 2);
        std::memcpy(&hb, b + i, 2);
        if ((ha & 0x7fff) > 0x7c00 && (hb & 0x7fff) > 0x7c00) continue;
      }
      if (nan_equal && kind == 2) {
        float fa, fb;
        std::memcpy(&fa, a + i, 4);
        std::memcpy(&fb, b + i, 4);
        if (std::isnan(fa) && std::isnan(fb)) continue;
      }
      std::fprintf(stderr, "fuzz_formats: %s differs: row %d byte %td:", name, r, i);
      for (int k = 0; k < size; ++k) std::fprintf(stderr, " %02x/%02x", a[i + k], b[i + k]);
      std::fprintf(stderr, "\n");
      return false;
    }
  }
  return true;
}

// `nan_equal`: float and half colour NaNs compare equal; `depth_nan_equal`: float depth NaNs too.
bool same_target(const Config& cfg, const Target& x, const Target& y, bool nan_equal, bool depth_nan_equal) {
  const ColorSpec& c = cfg.target_color;
  const int color_kind = c.format == ColorFormat::float32 ? 2 : c.format == ColorFormat::rgba16f ? 1 : 0;
  for (int k = 0; k < color_blocks(c); ++k)
    if (!same_block(x.color[k], y.color[k], color_kind, nan_equal, "colour")) return false;
  const int depth_kind = cfg.target_depth.plane || cfg.target_depth.format == DepthFormat::float32 ? 2 : 0;
  return same_block(x.depth, y.depth, depth_kind, depth_nan_equal, "depth") &&
         same_block(x.status, y.status, 0, false, "status") && same_block(x.source_x, y.source_x, 2, false, "source_x");
}

// ---- Per-pixel checks ---------------------------------------------------------------------------

// Channel c of pixel x, row y: bytes as 0..255, halves and floats as their values.
template <class T>
double channel(const ColorViewT<T>& v, int x, int y, int c) {
  switch (v.format) {
    case ColorFormat::rgba8:
    case ColorFormat::rgba8_srgb: return v.pixels.row(y)[4 * x + c];
    case ColorFormat::rgba16f: {
      std::uint16_t h;
      std::memcpy(&h, v.pixels.row(y) + 8 * x + 2 * c, 2);
      return formats::half_to_float(h);
    }
    default: return v.layout == ColorLayout::interleaved_rgba ? v.plane[0].row(y)[4 * x + c] : v.plane[c].row(y)[x];
  }
}

// The depth code (unorm) and the non-depth byte (stencil, A; -1: none) of pixel x.
void depth_word(DepthFormat f, const std::uint8_t* row, int x, long* code, int* extra) {
  *code = -1;
  *extra = -1;
  std::uint32_t w = 0;
  switch (f) {
    case DepthFormat::unorm16: {
      std::uint16_t u;
      std::memcpy(&u, row + 2 * x, 2);
      *code = u;
      break;
    }
    case DepthFormat::unorm24_s8:
      std::memcpy(&w, row + 4 * x, 4);
      *code = w & 0xffffff;
      *extra = static_cast<int>(w >> 24);
      break;
    case DepthFormat::s8_unorm24:
      std::memcpy(&w, row + 4 * x, 4);
      *code = w >> 8;
      *extra = static_cast<int>(w & 0xff);
      break;
    case DepthFormat::rgba8_packed_linear: *extra = row[4 * x + 3]; break;
    default: break;
  }
}

void check_pixels(const Config& cfg, const Options& options, const DepthDecoder& decoder, const Source& src,
                  const Target& out) {
  if (!cfg.status_out) {
    // Without status nothing says which pixels were written; source_x alone must be finite.
    if (cfg.source_x_out)
      for (int y = 0; y < cfg.height; ++y)
        for (int t = 0; t < cfg.target_width; ++t) CHECK_AT(std::isfinite(out.view.source_x.row(y)[t]), t, y);
    return;
  }
  const ColorSpec& cs = cfg.source_color;
  const int channels = cs.format == ColorFormat::float32 && !cs.interleaved ? cs.channels : 4;
  const float last = static_cast<float>(cfg.width - 1);
  const DepthFormat df = cfg.source_depth.plane ? DepthFormat::float32 : cfg.source_depth.format;
  const int dbpp = depth_bytes_per_pixel(df);
  for (int y = 0; y < cfg.height; ++y) {
    // The source row's range per channel (skipped when a value is not finite or is so large that
    // a difference of two overflows), its depth codes and its stencil / A bytes.
    double lo[4], hi[4];
    bool range[4];
    for (int c = 0; c < channels; ++c) {
      lo[c] = INFINITY;
      hi[c] = -INFINITY;
      range[c] = true;
      for (int x = 0; x < cfg.width; ++x) {
        const double v = channel(src.view.color, x, y, c);
        if (!std::isfinite(v) || std::fabs(v) > 1e30) range[c] = false;
        lo[c] = std::min(lo[c], v);
        hi[c] = std::max(hi[c], v);
      }
    }
    long code_lo = LONG_MAX, code_hi = -1;
    bool stencils[256] = {};
    for (int x = 0; x < cfg.width; ++x) {
      long code;
      int extra;
      depth_word(df, src.depth.row_ptr(y), x, &code, &extra);
      if (code >= 0) code_lo = std::min(code_lo, code), code_hi = std::max(code_hi, code);
      if (extra >= 0) stencils[extra] = true;
    }
    const long code_tolerance = df == DepthFormat::unorm16 ? 0 : 1;

    for (int t = 0; t < cfg.target_width; ++t) {
      const int status = out.view.status.row(y)[t];
      CHECK_AT(status <= 3, t, y);
      if (cfg.source_x_out) {
        const float x = out.view.source_x.row(y)[t];
        CHECK_AT(std::isfinite(x), t, y);
        if (status == 0 || status == 1) CHECK_AT(x >= 0.0f && x <= last, t, y);
        if (status == 2) CHECK_AT(x < 0.0f || x > last, t, y);
      }
      const bool written = status == 0 || status == 3 || (status == 2 && options.edge != EdgeMode::none) ||
                           (status == 1 && options.hole_fill != HoleFill::none);
      const bool black = status == 2 && options.edge == EdgeMode::black;
      // Colour.
      if (cs.format == ColorFormat::float32) {
        for (int c = 0; c < channels; ++c) {
          const int block = cs.interleaved ? 0 : c;
          const std::ptrdiff_t byte = cs.interleaved ? 16 * t + 4 * c : 4 * t;
          if (!written) {
            CHECK_AT(out.color[block].is_pattern(y, byte, 4), t, y);
            continue;
          }
          const double v = channel(out.view.color, t, y, c);
          if (black) {
            CHECK_AT(v == 0.0, t, y);
          } else if (range[c]) {
            const double tolerance = 1e-6 * std::max(std::fabs(lo[c]), std::fabs(hi[c])) + 1e-37;
            CHECK_AT(v >= lo[c] - tolerance && v <= hi[c] + tolerance, t, y);
          }
        }
      } else {
        const int bpp = bytes_per_pixel(cs.format);
        if (!written) {
          CHECK_AT(out.color[0].is_pattern(y, static_cast<std::ptrdiff_t>(t) * bpp, bpp), t, y);
        } else {
          for (int c = 0; c < 4; ++c) {
            const double v = channel(out.view.color, t, y, c);
            if (black) CHECK_AT(v == 0.0, t, y);
            else if (range[c]) CHECK_AT(v >= lo[c] && v <= hi[c], t, y);  // exactly: rounding stays within the ends
          }
        }
      }
      // Depth.
      if (!cfg.depth_out) continue;
      if (!written) {
        CHECK_AT(out.depth.is_pattern(y, static_cast<std::ptrdiff_t>(t) * dbpp, dbpp), t, y);
        continue;
      }
      long code;
      int extra;
      depth_word(df, out.depth.row_ptr(y), t, &code, &extra);
      if (extra >= 0) CHECK_AT(stencils[extra], t, y);
      if (code >= 0 && decoder.is_affine())
        CHECK_AT(code >= code_lo - code_tolerance && code <= code_hi + code_tolerance, t, y);
    }
  }
}

// ---- Choices ------------------------------------------------------------------------------------

DepthDecoder make_decoder(FuzzedDataProvider& in, DepthFormat format) {
  // Packed linear depth is linear view depth: mostly the linear decoder.
  const int k = in.ConsumeIntegralInRange<int>(0, 7);
  if (k == 0 || (format == DepthFormat::rgba8_packed_linear && k < 6)) return DepthDecoder::linear();
  if (k == 1) return DepthDecoder::disparity();
  static const double kNear[] = {0.1, 0.5, 1.0, 10.0, 1e-30, 0.0};
  static const double kFarRatio[] = {2.0, 10.0, 100.0, 1e4, 1.0, 1e30};
  const auto encoding = static_cast<DepthEncoding>(in.ConsumeIntegralInRange<int>(0, 7));  // 7: none
  const double near_plane = kNear[in.ConsumeIntegralInRange<int>(0, 5)];
  return DepthDecoder::from_near_far(encoding, near_plane, near_plane * kFarRatio[in.ConsumeIntegralInRange<int>(0, 5)]);
}

ParallaxModel make_model(FuzzedDataProvider& in, int width) {
  const auto direction = static_cast<EyeDirection>(in.ConsumeIntegralInRange<int>(0, 4));  // 4: not a direction
  switch (in.ConsumeIntegralInRange<int>(0, 3)) {
    case 0: {
      static const double kSeparation[] = {0.0, 0.01, 0.03, 0.1, 0.5, -0.01};
      static const double kConvergence[] = {1.0, 0.5, 2.0, 10.0, 1e6, 0.0};
      const double separation = kSeparation[in.ConsumeIntegralInRange<int>(0, 5)];
      const double convergence = kConvergence[in.ConsumeIntegralInRange<int>(0, 5)];
      return ParallaxModel::from_stereo(separation, convergence, std::max(width, 1), direction);
    }
    case 1: return ParallaxModel::from_disparity(direction);
    default: {
      // Small multiples of the width: parallax inside and beyond the row.
      const float scale = static_cast<float>(std::max(width, 1)) / 16.0f;
      ParallaxModel model;
      model.a = scale * static_cast<float>(in.ConsumeIntegralInRange<int>(-24, 24));
      model.b = scale * static_cast<float>(in.ConsumeIntegralInRange<int>(-64, 64));
      return model;
    }
  }
}

Options make_options(FuzzedDataProvider& in, int width) {
  Options o;
  o.method = static_cast<Method>(in.ConsumeIntegralInRange<int>(0, kMethodCount - 1));
  o.hole_fill = static_cast<HoleFill>(in.ConsumeIntegralInRange<int>(0, 2));
  o.edge = static_cast<EdgeMode>(in.ConsumeIntegralInRange<int>(0, 3));
  static const float kThreshold[] = {1.0f, 0.0f, 0.5f, 4.0f, 1000.0f};
  o.hole_threshold = kThreshold[in.ConsumeIntegralInRange<int>(0, 4)];
  if (in.ConsumeBool()) {
    static const float kNear[] = {0.0f, 1.0f, 5.0f, 50.0f};
    const int k = in.ConsumeIntegralInRange<int>(0, 4);
    o.max_negative_parallax = k < 4 ? kNear[k] : static_cast<float>(width);
  }
  if (in.ConsumeBool()) o.probe_parallax = static_cast<float>(in.ConsumeIntegralInRange<int>(-64, 64)) / 4.0f;
  if (in.ConsumeBool()) o.march_steps = in.ConsumeIntegralInRange<int>(1, 40);
  if (in.ConsumeBool()) o.secant_max_steps = in.ConsumeIntegralInRange<int>(1, 40);
  if (in.ConsumeBool()) {
    const Arch arch = static_cast<Arch>(in.ConsumeIntegralInRange<int>(0, kArchCount - 1));
    if (arch_supported(arch)) o.arch = arch;
  }
  o.threads = in.ConsumeBool() ? 2 : 1;
  return o;
}

void make_bad_option(Options& o, int variant) {
  switch (variant % 11) {
    case 0: o.method = static_cast<Method>(kMethodCount); break;
    case 1: o.hole_fill = static_cast<HoleFill>(3); break;
    case 2: o.edge = static_cast<EdgeMode>(4); break;
    case 3: o.hole_threshold = variant % 2 ? -1.0f : kNaN; break;
    case 4: o.march_steps = variant % 2 ? 0 : 1025; break;
    case 5: o.secant_max_steps = variant % 2 ? 0 : 4097; break;
    case 6: o.max_negative_parallax = variant % 2 ? -1.0f : kInf; break;
    case 7: o.probe_parallax = kNaN; break;
    case 8: o.threads = -1; break;
    case 9: o.arch = static_cast<Arch>(kArchCount); break;
    default: o.guard = -1; break;
  }
}

DepthFormat pick_depth_format(int k, bool* plane) {
  *plane = k == 0;
  static const DepthFormat kFormats[] = {DepthFormat::float32,    DepthFormat::float32,    DepthFormat::unorm16,
                                         DepthFormat::unorm16,    DepthFormat::unorm24_s8, DepthFormat::unorm24_s8,
                                         DepthFormat::s8_unorm24, DepthFormat::s8_unorm24, DepthFormat::rgba8_packed_linear,
                                         DepthFormat::rgba8_packed_linear};
  return kFormats[k];
}

bool known_code(StatusCode code) {
  return static_cast<int>(code) >= 0 && static_cast<int>(code) <= static_cast<int>(StatusCode::invalid_option);
}

struct ParallelJobs {
  // Runs the tasks in reverse order on the calling thread: "any order" is part of the contract.
  static void run(void*, int count, void (*task)(void*, int), void* task_context) {
    for (int i = count - 1; i >= 0; --i) task(task_context, i);
  }
};

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  std::fprintf(stderr, "%s\n", reproject::arch_report("fuzz_formats").c_str());
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  FuzzedDataProvider in(data, size);
  Config cfg;

  // ---- the frame and its buffers ----
  cfg.width = in.ConsumeBool() ? in.ConsumeIntegralInRange<int>(0, 40) : in.ConsumeIntegralInRange<int>(0, 300);
  cfg.height = in.ConsumeIntegralInRange<int>(0, 8);
  ColorSpec& sc = cfg.source_color;
  switch (in.ConsumeIntegralInRange<int>(0, 7)) {
    case 0: case 1: sc.format = ColorFormat::rgba8; break;
    case 2: case 3: sc.format = ColorFormat::rgba8_srgb; break;
    case 4: case 5: sc.format = ColorFormat::rgba16f; break;
    case 6: sc.format = ColorFormat::float32; sc.interleaved = true; break;
    default:
      sc.format = ColorFormat::float32;
      sc.interleaved = false;
      sc.channels = in.ConsumeIntegralInRange<int>(1, 4);
      break;
  }
  sc.pad = sc.format == ColorFormat::float32 ? in.ConsumeIntegralInRange<int>(0, 3) : in.ConsumeIntegralInRange<int>(0, 9);
  sc.offset = in.ConsumeIntegralInRange<int>(0, 7);
  DepthSpec& sd = cfg.source_depth;
  sd.format = pick_depth_format(in.ConsumeIntegralInRange<int>(0, 9), &sd.plane);
  sd.pad = sd.plane || sd.format == DepthFormat::float32 ? in.ConsumeIntegralInRange<int>(0, 3)
                                                          : in.ConsumeIntegralInRange<int>(0, 9);
  if (!sd.plane && sd.format == DepthFormat::float32) sd.pad *= 4;  // bytes, whole floats
  sd.offset = in.ConsumeIntegralInRange<int>(0, 7);
  if (sd.format == DepthFormat::rgba8_packed_linear) {
    static const float kRange[][2] = {{0.0f, 1.0f},  {0.5f, 40.0f},  {1.0f, 100.0f}, {-5.0f, 5.0f},
                                      {10.0f, 1.0f}, {1e-3f, 1e-3f + 1e-9f}, {-1e38f, 1e38f}, {0.0f, 1e30f}};
    const int k = in.ConsumeIntegralInRange<int>(0, 8);
    if (k < 8) {
      sd.linear_near = kRange[k][0];
      sd.linear_far = kRange[k][1];
    } else {  // any finite, distinct pair of raw floats
      const std::uint32_t a = in.ConsumeIntegral<std::uint32_t>(), b = in.ConsumeIntegral<std::uint32_t>();
      std::memcpy(&sd.linear_near, &a, 4);
      std::memcpy(&sd.linear_far, &b, 4);
      if (!std::isfinite(sd.linear_near)) sd.linear_near = 0.0f;
      if (!std::isfinite(sd.linear_far) || sd.linear_far == sd.linear_near)
        sd.linear_far = sd.linear_near != 0.0f ? -sd.linear_near : 1.0f;
      // The library refuses a range whose length overflows (a fault of its own, packed_range).
      if (!std::isfinite(sd.linear_far - sd.linear_near)) sd.linear_far = sd.linear_near * 0.5f;
      if (sd.linear_far == sd.linear_near) sd.linear_far = 1.0f;
    }
  }

  // Outputs: colour always, in the source's format; depth in the source depth's format (the float
  // plane or a float32 depth_buffer, either way round, for float source depth).
  cfg.target_color = sc;
  cfg.target_color.pad = sc.format == ColorFormat::float32 ? in.ConsumeIntegralInRange<int>(0, 3)
                                                           : in.ConsumeIntegralInRange<int>(0, 9);
  cfg.target_color.offset = in.ConsumeIntegralInRange<int>(0, 7);
  cfg.depth_out = in.ConsumeBool();
  cfg.target_depth = sd;
  if (sd.format == DepthFormat::float32 && in.ConsumeIntegralInRange<int>(0, 3) == 0) cfg.target_depth.plane = !sd.plane;
  cfg.target_depth.pad = cfg.target_depth.plane || sd.format == DepthFormat::float32 ? in.ConsumeIntegralInRange<int>(0, 3)
                                                                                      : in.ConsumeIntegralInRange<int>(0, 9);
  if (!cfg.target_depth.plane && sd.format == DepthFormat::float32) cfg.target_depth.pad *= 4;
  cfg.target_depth.offset = in.ConsumeIntegralInRange<int>(0, 7);
  if (in.ConsumeIntegralInRange<int>(0, 3) == 0) {  // the output's own range fields (not used, but validated)
    cfg.target_depth.linear_near = 0.0f;
    cfg.target_depth.linear_far = 1.0f;
  }
  cfg.status_out = in.ConsumeIntegralInRange<int>(0, 3) != 0;
  cfg.source_x_out = in.ConsumeBool();
  cfg.status_pad = in.ConsumeIntegralInRange<int>(0, 9);
  cfg.source_x_pad = in.ConsumeIntegralInRange<int>(0, 3);
  cfg.api = in.ConsumeIntegralInRange<int>(0, 3);
  cfg.color_mode = in.ConsumeIntegralInRange<int>(0, 2);
  cfg.depth_mode = in.ConsumeIntegralInRange<int>(0, 2);

  const DepthDecoder decoder = make_decoder(in, sd.plane ? DepthFormat::float32 : sd.format);
  const ParallaxModel model = make_model(in, cfg.width);
  Options options = make_options(in, cfg.width);
  options.guard = in.ConsumeBool() ? 0 : in.ConsumeIntegralInRange<int>(0, std::max(0, (cfg.width - 1) / 2));

  // Half of the inputs are valid; the others carry one fault.
  const int fault_pick = in.ConsumeIntegralInRange<int>(0, 2 * static_cast<int>(Fault::count) - 2);
  cfg.fault = fault_pick < static_cast<int>(Fault::count) ? Fault::none
                                                          : static_cast<Fault>(fault_pick - static_cast<int>(Fault::count) + 1);
  cfg.variant = in.ConsumeIntegralInRange<int>(0, 59);

  // The codes each fault may give. `early`: checked before the frame size (an empty frame
  // reports it too); `late`: only a frame with pixels.
  unsigned early = 0, late = 0;
  if (!decoder.validate().ok()) early |= bit(StatusCode::invalid_decoder);
  if (!model.validate().ok()) early |= bit(StatusCode::invalid_model);
  const bool float_source_depth = sd.plane || sd.format == DepthFormat::float32;
  const int v = cfg.variant;
  switch (cfg.fault) {
    case Fault::none: break;
    case Fault::target_color_format: {
      ColorSpec& tc = cfg.target_color;
      const int k = (static_cast<int>(sc.format) + 1 + v % 3) % kColorFormatCount;
      tc.format = static_cast<ColorFormat>(k);
      tc.interleaved = true;
      tc.channels = 4;
      if (tc.format == ColorFormat::float32 && v % 2) {
        tc.interleaved = false;
        tc.channels = 1 + v % 4;
      }
      late |= bit(StatusCode::size_mismatch);
      break;
    }
    case Fault::source_color_unknown:
    case Fault::target_color_unknown: late |= bit(StatusCode::invalid_option); break;
    case Fault::source_depth_unknown:
      if (sd.plane) cfg.fault = Fault::none;  // a float plane has no format to get wrong
      else late |= bit(StatusCode::invalid_option);
      break;
    case Fault::target_depth_format: {
      cfg.depth_out = true;
      const DepthFormat source_format = float_source_depth ? DepthFormat::float32 : sd.format;
      cfg.target_depth.format = static_cast<DepthFormat>((static_cast<int>(source_format) + 1 + v % 4) % kDepthFormatCount);
      cfg.target_depth.plane = false;
      late |= bit(StatusCode::size_mismatch);
      break;
    }
    case Fault::source_both_depths: early |= bit(StatusCode::invalid_option); break;
    case Fault::target_both_depths:
    case Fault::target_float_depth:
      cfg.depth_out = true;
      cfg.target_depth.plane = false;  // the fault adds the float plane
      if (cfg.fault == Fault::target_both_depths) late |= bit(StatusCode::invalid_option);
      else if (float_source_depth) cfg.fault = Fault::none;  // a float plane output is right for float depth
      else late |= bit(StatusCode::size_mismatch);
      break;
    case Fault::stride_too_small: {
      const int which = (v / 3) % 5;
      if ((which == 1 && !cfg.depth_out) || (which == 2 && !cfg.status_out) || (which == 3 && !cfg.source_x_out))
        cfg.fault = Fault::none;
      else late |= bit(StatusCode::invalid_stride);
      break;
    }
    case Fault::float_depth_misaligned:
      if (v % 2 == 0 && cfg.depth_out && !cfg.target_depth.plane && cfg.target_depth.format == DepthFormat::float32)
        late |= bit(StatusCode::invalid_stride);
      else if (v % 2 == 1 && !sd.plane && sd.format == DepthFormat::float32)
        late |= bit(StatusCode::invalid_stride);
      else cfg.fault = Fault::none;
      break;
    case Fault::packed_range:
      // A target's range is not read (the output is stored with the source's): the bad range
      // stays in the target view and the call must succeed, as if it were not there.
      if (v % 2 == 0 && cfg.depth_out && !cfg.target_depth.plane && cfg.target_depth.format == DepthFormat::rgba8_packed_linear)
        break;
      else if (v % 2 == 1 && sd.format == DepthFormat::rgba8_packed_linear)
        late |= bit(StatusCode::invalid_option);
      else cfg.fault = Fault::none;
      break;
    case Fault::size_off: {
      const int which = v / 6 % 5;
      if ((which == 1 && !cfg.depth_out) || (which == 2 && !cfg.status_out) || (which == 3 && !cfg.source_x_out))
        cfg.fault = Fault::none;
      else late |= bit(StatusCode::size_mismatch) | bit(StatusCode::invalid_size);
      break;
    }
    case Fault::null_data: late |= bit(StatusCode::null_pointer); break;
    case Fault::color_shape:
      if (v % 4 == 3) {  // the target's layout or channel count differs from the source's
        ColorSpec& tc = cfg.target_color;
        if (sc.format != ColorFormat::float32) {
          cfg.fault = Fault::none;
        } else if (sc.interleaved) {
          tc.interleaved = false;
          tc.channels = 1 + v % 4;
        } else {
          tc.channels = sc.channels % 4 + 1;
        }
      }
      late |= bit(StatusCode::size_mismatch) | bit(StatusCode::null_pointer);
      break;
    case Fault::guard_too_wide:
      options.guard = (cfg.width + 1) / 2 + v % 3;
      late |= bit(StatusCode::invalid_size);
      break;
    case Fault::bad_option:
      make_bad_option(options, v);
      early |= bit(StatusCode::invalid_option);
      break;
    case Fault::color_layout_unknown: late |= bit(StatusCode::invalid_option); break;
    case Fault::aliasing: late |= bit(StatusCode::aliasing); break;
    default: break;
  }
  if (cfg.fault == Fault::none) late = 0;
  // A float32 depth_buffer takes whole floats of padding (its misalignment is Fault::float_depth_misaligned).
  for (DepthSpec* d : {&cfg.source_depth, &cfg.target_depth})
    if (!d->plane && d->format == DepthFormat::float32) d->pad &= ~3;
  cfg.target_width = std::max(0, cfg.width - 2 * std::max(0, options.guard));

  Source src;
  build_source(cfg, decoder, in.ConsumeRemainingBytes<std::uint8_t>(), src);

  const std::uint64_t source_hash = src.hash();
  if (std::getenv("FUZZ_FORMATS_VERBOSE")) {  // what an input means, when replaying it
    std::fprintf(stderr,
                 "fuzz_formats: %dx%d guard %d, colour %s%s (%d ch, pad %d, offset %d) -> %s%s, depth %s%s (pad %d, "
                 "offset %d, range %g %g) -> %s%s%s, status %d, source_x %d, api %d, modes %d %d, fault %d variant %d, "
                 "method %s, threads %d, decoder %s %g %g, model %g %g\n",
                 cfg.width, cfg.height, options.guard, to_string(sc.format), float_layout(sc), sc.channels, sc.pad,
                 sc.offset, to_string(cfg.target_color.format), float_layout(cfg.target_color),
                 to_string(sd.format), sd.plane ? " plane" : "", sd.pad, sd.offset, static_cast<double>(sd.linear_near),
                 static_cast<double>(sd.linear_far), cfg.depth_out ? to_string(cfg.target_depth.format) : "none",
                 cfg.depth_out && cfg.target_depth.plane ? " plane" : "", "", cfg.status_out, cfg.source_x_out, cfg.api,
                 cfg.color_mode, cfg.depth_mode, static_cast<int>(cfg.fault), cfg.variant, to_string(options.method),
                 options.threads, to_string(decoder.encoding()), decoder.near_plane(), decoder.far_plane(),
                 static_cast<double>(model.a), static_cast<double>(model.b));
  }

  // ---- the public call ----
  Target out(cfg, src);
  Target second(cfg, src);  // reproject_pair's left eye
  const ParallaxModel mirrored{-model.a, -model.b};
  Status status;
  const bool pair = cfg.api >= 2;
  if (cfg.api == 3) {
    const ParallelFor jobs{nullptr, ParallelJobs::run};
    status = reproject_pair(src.view, decoder, model, options, second.view, out.view, jobs);
  } else if (cfg.api == 2) {
    status = reproject_pair(src.view, decoder, model, options, second.view, out.view);
  } else if (cfg.api == 1) {
    const ParallelFor jobs{nullptr, ParallelJobs::run};
    status = reproject::reproject(src.view, decoder, model, options, out.view, jobs);
  } else {
    status = reproject::reproject(src.view, decoder, model, options, out.view);
  }
  if (std::getenv("FUZZ_FORMATS_VERBOSE")) std::fprintf(stderr, "fuzz_formats: answered %s\n", status.message());
  CHECK(known_code(status.code()));
  CHECK(status.message() != nullptr && status.message()[0] != '\0');
  CHECK(out.gaps_intact());
  CHECK(second.gaps_intact());
  CHECK(src.hash() == source_hash);  // inputs are only read
  const bool empty = cfg.width == 0 || cfg.height == 0;
  const unsigned expected = early ? early : empty ? 0u : late;
  if (expected == 0 && !status.ok()) {
    std::fprintf(stderr, "fuzz_formats: a valid call failed: %s: %s\n", to_string(status.code()), status.message());
    std::abort();
  }
  if (expected != 0 && (status.ok() || (expected & bit(status.code())) == 0)) {
    std::fprintf(stderr, "fuzz_formats: fault %d (variant %d) answered %s: %s\n", static_cast<int>(cfg.fault), cfg.variant,
                 to_string(status.code()), status.message());
    std::abort();
  }
  if (!status.ok()) {
    CHECK(out.untouched());
    CHECK(second.untouched());
    return 0;
  }
  if (empty) return 0;
  check_pixels(cfg, options, decoder, src, out);
  if (pair) check_pixels(cfg, options, decoder, src, second);

  // ---- the same call, every way round ----
  const Arch used = options.arch ? *options.arch : selected_arch();
  const int threads = options.threads;
  options.threads = 1;
  if (pair) {
    // The pair equals two single calls (each with the other thread count).
    Options single = options;
    single.threads = threads == 1 ? 2 : 1;
    Target left(cfg, src), right(cfg, src);
    CHECK(reproject::reproject(src.view, decoder, mirrored, single, left.view).ok());
    CHECK(reproject::reproject(src.view, decoder, model, single, right.view).ok());
    CHECK(same_target(cfg, second, left, false, false));
    CHECK(same_target(cfg, out, right, false, false));
  } else {
    // The public call equals reproject_with() on its kernels, and threads 1 equals threads 2.
    Target again(cfg, src), other(cfg, src);
    CHECK(detail::reproject_with(*detail::compiled_kernels(used), src.view, decoder, model, options, again.view).ok());
    CHECK(same_target(cfg, out, again, false, false));
    Options threaded = options;
    threaded.threads = cfg.api == 1 || threads == 1 ? 2 : 1;
    CHECK(reproject::reproject(src.view, decoder, model, threaded, other.view).ok());
    CHECK(same_target(cfg, out, other, false, false));
    CHECK(again.gaps_intact() && other.gaps_intact());
  }
  // Every instruction set the CPU has against its scalar reference.
  for (int a = 0; a < kArchCount; ++a) {
    const Arch arch = static_cast<Arch>(a);
    if (!arch_supported(arch)) continue;
    Target simd(cfg, src), reference(cfg, src);
    CHECK(detail::reproject_with(*detail::compiled_kernels(arch), src.view, decoder, model, options, simd.view).ok());
    CHECK(detail::reproject_with(detail::reference_kernels(arch), src.view, decoder, model, options, reference.view).ok());
    if (!same_target(cfg, simd, reference, true, !src.depth_finite)) {
      std::fprintf(stderr, "fuzz_formats: %s differs from its scalar reference (%s + %s%s, method %s)\n", to_string(arch),
                   to_string(sc.format), to_string(sd.format), sd.plane ? " plane" : "", to_string(options.method));
      std::abort();
    }
    CHECK(simd.gaps_intact());
  }
  return 0;
}
