// libFuzzer harness for the C interface (include/reproject/reproject.h) at its boundaries: the
// fuzzer fills reproject_source_buffers and one or two reproject_target_buffers field by field
// (sizes, strides from small to 2^63 - 1 and negative, formats and layouts valid or not, reserved
// fields), places every buffer in one arena between two PROT_NONE pages (or gives a NULL pointer,
// a stride whose byte offsets overflow, or an address near the top of memory), and picks the
// decoder, the model, the options (struct_size included), the job hook and the cancel flag.
//
// What is checked, besides "no crash, no sanitizer report" (the arena's guard pages fault on a
// read or write just outside it):
//  * the status is a known code, and a failure has a message;
//  * a call that fails changed no byte of the arena;
//  * a call that succeeds used only views that lie inside the arena, computed exactly (128-bit:
//    a stride that wraps would otherwise put its rows back inside), and changed no byte outside
//    the rows of its outputs. The arena is filled with a pattern that depends on the position,
//    so a byte copied from elsewhere is seen too.
// A failed check prints what it saw and aborts, so libFuzzer keeps the input.
// FUZZ_C_API_VERBOSE=1 prints every call's views and status, for replaying an input.
#include <fuzzer/FuzzedDataProvider.h>
#include <sys/mman.h>
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <algorithm>
#include <cstring>
#include <vector>

#include "reproject/reproject.h"

namespace {

constexpr std::size_t kArenaBytes = std::size_t{1} << 16;

[[noreturn]] void fail(const char* what) {
  std::fprintf(stderr, "fuzz_c_api: check failed: %s\n", what);
  std::abort();
}
#define CHECK(condition)                \
  do {                                  \
    if (!(condition)) fail(#condition); \
  } while (0)

bool verbose() {
  static const bool on = std::getenv("FUZZ_C_API_VERBOSE") != nullptr;
  return on;
}

// kArenaBytes of memory between two PROT_NONE pages; made once, refilled per input.
struct Arena {
  unsigned char* bytes = nullptr;
  std::vector<unsigned char> pristine = std::vector<unsigned char>(kArenaBytes);  // the fill pattern
  std::vector<unsigned char> before = std::vector<unsigned char>(kArenaBytes);
  std::vector<unsigned char> written = std::vector<unsigned char>(kArenaBytes);  // 1: an input's rows, 2: an output's

  Arena() {
    const std::size_t page = static_cast<std::size_t>(sysconf(_SC_PAGESIZE));
    void* base = mmap(nullptr, kArenaBytes + 2 * page, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (base == MAP_FAILED) fail("mmap");
    auto* first = static_cast<unsigned char*>(base);
    if (mprotect(first, page, PROT_NONE) != 0 || mprotect(first + page + kArenaBytes, page, PROT_NONE) != 0)
      fail("mprotect");
    bytes = first + page;
    for (std::size_t i = 0; i < kArenaBytes; ++i) pristine[i] = static_cast<unsigned char>(i * 167u + (i >> 8) * 31u + 13u);
  }
  void fill() { std::memcpy(bytes, pristine.data(), kArenaBytes); }
};
Arena& arena() {
  static Arena* instance = new Arena();
  return *instance;
}

using u128 = unsigned __int128;

// How a view is placed.
enum class Placement { inside, null, overflowing_stride, top_of_memory };

// The rows a view covers, exactly: [first + y * stride, + row) for y < rows.
struct Rows {
  u128 first = 0;
  u128 rows = 0;
  u128 row = 0;
  __int128 stride = 0;
  bool valid_shape = false;  // width, height >= 0, stride >= row
};

Rows rows_of(const void* data, std::int32_t width, std::int32_t height, std::int64_t stride, int per_pixel,
             int element_bytes) {
  Rows r;
  r.first = reinterpret_cast<std::uintptr_t>(data);
  if (width < 0 || height < 0) return r;
  r.rows = static_cast<u128>(height);
  r.row = static_cast<u128>(width) * static_cast<u128>(per_pixel) * static_cast<u128>(element_bytes);
  r.stride = static_cast<__int128>(stride) * element_bytes;
  r.valid_shape = stride >= static_cast<std::int64_t>(width) * per_pixel;
  return r;
}

// Whether every row lies inside the arena (a used view of an accepted call must).
bool inside_arena(const Rows& r) {
  if (r.rows == 0 || r.row == 0) return true;
  if (!r.valid_shape || r.stride < 0) return false;
  const u128 begin = reinterpret_cast<std::uintptr_t>(arena().bytes);
  const u128 end = r.first + (r.rows - 1) * static_cast<u128>(r.stride) + r.row;
  return r.first >= begin && end <= begin + kArenaBytes;
}

// Adds `mark` to every byte of the view's rows in `marks`; false when a byte already had one
// (an output sharing a byte with an input or with another output, which an accepted call must not
// have: the arena check alone would not see a write into an input's bytes that are also an
// output's).
bool mark(const Rows& r, unsigned char mark, std::vector<unsigned char>* marks) {
  const u128 begin = reinterpret_cast<std::uintptr_t>(arena().bytes);
  bool alone = true;
  for (u128 y = 0; y < r.rows; ++y) {
    const u128 start = r.first + y * static_cast<u128>(r.stride) - begin;
    for (u128 i = 0; i < r.row; ++i) {
      unsigned char& m = (*marks)[static_cast<std::size_t>(start + i)];
      alone = alone && (m == 0 || (mark == 1 && m == 1));  // inputs may share bytes
      m = mark;
    }
  }
  return alone;
}

// Picks where a view of `height` rows of `row_elements` elements of `element_bytes` lies; returns
// its data pointer and sets its stride (in elements). A view of a valid shape that would not fit
// the arena is given no data: the library cannot know an allocation's size, so a view it accepts
// must be one the caller really has. The others (a stride whose byte offsets overflow, rows past
// the top of memory, a stride below the row, a negative size) the library must refuse.
struct ViewMaker {
  FuzzedDataProvider& in;
  std::size_t next = 0;  // a cursor, so that views tend not to overlap

  void* place(std::int64_t height, std::int64_t row_elements, int element_bytes, std::int64_t* stride) {
    static const std::int64_t kHuge[] = {INT64_MAX, INT64_MAX / 2, INT64_MAX / 4 + 1, std::int64_t{1} << 62,
                                         (std::int64_t{1} << 62) + 1, std::int64_t{1} << 61, (std::int64_t{1} << 61) + 3,
                                         std::int64_t{1} << 40, INT64_MIN, -1, 0};
    const int choice = in.ConsumeIntegralInRange(0, 15);
    const Placement placement = choice < 11 ? Placement::inside : choice < 13 ? Placement::null
                                : choice < 15                     ? Placement::overflowing_stride
                                                                  : Placement::top_of_memory;
    switch (in.ConsumeIntegralInRange(0, 3)) {
      case 0: *stride = row_elements; break;
      case 1: *stride = row_elements + in.ConsumeIntegralInRange<std::int64_t>(-3, 40); break;
      case 2: *stride = in.ConsumeIntegral<std::int64_t>(); break;
      default: *stride = kHuge[in.ConsumeIntegralInRange<std::size_t>(0, sizeof kHuge / sizeof kHuge[0] - 1)]; break;
    }
    const bool shaped = height >= 0 && row_elements >= 0 && *stride >= row_elements;
    u128 extent = 0;
    if (shaped && height > 0 && row_elements > 0)
      extent = static_cast<u128>(height - 1) * static_cast<u128>(*stride) * static_cast<u128>(element_bytes) +
               static_cast<u128>(row_elements) * static_cast<u128>(element_bytes);
    switch (placement) {
      case Placement::null: return nullptr;
      case Placement::overflowing_stride: {
        // A stride whose rows end beyond PTRDIFF_MAX bytes (the least such, or more); the first
        // row lies in the arena, so that a view of one row, which may have any stride, is real.
        if (height < 0 || row_elements < 0) return nullptr;
        const u128 row_bytes = static_cast<u128>(row_elements) * static_cast<u128>(element_bytes);
        if (row_bytes > kArenaBytes) return nullptr;
        if (height >= 2) {
          const u128 span = static_cast<u128>(height - 1) * static_cast<u128>(element_bytes);
          const u128 least = (static_cast<u128>(PTRDIFF_MAX) - row_bytes) / span + 1;
          const u128 more = in.ConsumeBool() ? 0 : in.ConsumeIntegral<std::uint64_t>() >> in.ConsumeIntegralInRange(0, 63);
          *stride = static_cast<std::int64_t>(std::min<u128>(least + more, static_cast<u128>(INT64_MAX)));
        } else {
          *stride = kHuge[in.ConsumeIntegralInRange<std::size_t>(0, 6)];
        }
        return arena().bytes + in.ConsumeIntegralInRange<std::size_t>(0, kArenaBytes - static_cast<std::size_t>(row_bytes));
      }
      case Placement::top_of_memory: {
        // Rows that run past the end of the address space: fewer bytes left than the view spans
        // (a view that fits up there would be accepted, and the library cannot know it is not ours).
        if (shaped && extent == 0) return nullptr;
        const u128 below_max = shaped && extent <= 4097 ? extent - 1 : 4096;
        return reinterpret_cast<void*>(UINTPTR_MAX -
                                       in.ConsumeIntegralInRange<std::uintptr_t>(0, static_cast<std::uintptr_t>(below_max)));
      }
      case Placement::inside: break;
    }
    if (shaped && extent > kArenaBytes) return nullptr;  // a real view this size is not in our arena
    // After the previous view, or anywhere (overlaps included); misaligned bases too.
    std::size_t offset = in.ConsumeBool() ? next : in.ConsumeIntegralInRange<std::size_t>(0, kArenaBytes - 1);
    offset += in.ConsumeIntegralInRange<std::size_t>(0, 7);
    if (offset >= kArenaBytes) offset = kArenaBytes - 1;
    if (offset + extent > kArenaBytes) offset = kArenaBytes - static_cast<std::size_t>(extent);  // at the guard page
    next = offset + static_cast<std::size_t>(extent) + in.ConsumeIntegralInRange<std::size_t>(0, 64);
    if (next >= kArenaBytes) next = 0;
    return arena().bytes + offset;
  }
};

struct Frame {
  std::int32_t width = 0;
  std::int32_t height = 0;
  std::int32_t color_format = REPROJECT_COLOR_FLOAT32;
  std::int32_t layout = REPROJECT_LAYOUT_PLANAR;
  std::int32_t channels = 3;
  std::int32_t depth_format = REPROJECT_DEPTH_FORMAT_FLOAT32;
  bool depth_plane = true;
};

int color_bytes(std::int32_t format) { return format == REPROJECT_COLOR_RGBA16F ? 8 : 4; }
int depth_bytes(std::int32_t format) { return format == REPROJECT_DEPTH_FORMAT_UNORM16 ? 2 : 4; }

// A size near the frame's (mostly equal), or anything.
std::int32_t near_size(FuzzedDataProvider& in, std::int32_t size) {
  switch (in.ConsumeIntegralInRange(0, 9)) {
    case 0: return in.ConsumeIntegralInRange<std::int32_t>(-2, 70);
    case 1: {
      const std::int64_t near = static_cast<std::int64_t>(size) + in.ConsumeIntegralInRange<std::int32_t>(-1, 1);
      return static_cast<std::int32_t>(std::min<std::int64_t>(std::max<std::int64_t>(near, INT32_MIN), INT32_MAX));
    }
    case 2: return in.ConsumeIntegral<std::int32_t>();
    default: return size;
  }
}
std::int32_t near_value(FuzzedDataProvider& in, std::int32_t value, std::int32_t low, std::int32_t high) {
  return in.ConsumeIntegralInRange(0, 7) == 0 ? in.ConsumeIntegralInRange(low, high) : value;
}

template <class Pointer, class Plane>
void fill_plane(FuzzedDataProvider& in, ViewMaker& views, Plane* p, std::int32_t width, std::int32_t height,
                int per_pixel) {
  p->width = near_size(in, width);
  p->height = near_size(in, height);
  p->data = static_cast<Pointer>(
      views.place(p->height, static_cast<std::int64_t>(p->width) * per_pixel, 4, &p->stride));
}

template <class Pointer, class Color>
void fill_color(FuzzedDataProvider& in, ViewMaker& views, Color* color, const Frame& f, std::int32_t width) {
  color->layout = near_value(in, f.layout, -1, 257);
  color->channels = near_value(in, f.channels, -1, 6);
  const bool interleaved = color->layout == REPROJECT_LAYOUT_INTERLEAVED_RGBA;
  for (int c = 0; c < (interleaved ? 1 : 4); ++c) {
    if (c < color->channels || in.ConsumeIntegralInRange(0, 7) == 0)
      fill_plane<Pointer>(in, views, &color->plane[c], width, f.height, interleaved ? 4 : 1);
  }
}

template <class Pointer, class Pixels>
void fill_pixels(FuzzedDataProvider& in, ViewMaker& views, Pixels* p, const Frame& f, std::int32_t width) {
  p->format = near_value(in, f.color_format, -1, 258);
  p->reserved = in.ConsumeIntegralInRange(0, 15) == 0 ? in.ConsumeIntegral<std::int32_t>() : 0;
  p->width = near_size(in, width);
  p->height = near_size(in, f.height);
  p->data = static_cast<Pointer>(
      views.place(p->height, static_cast<std::int64_t>(p->width) * color_bytes(p->format), 1, &p->stride));
}

template <class Pointer, class Buffer>
void fill_depth_buffer(FuzzedDataProvider& in, ViewMaker& views, Buffer* d, const Frame& f, std::int32_t width) {
  d->format = near_value(in, f.depth_format, -1, 258);
  d->reserved = in.ConsumeIntegralInRange(0, 15) == 0 ? in.ConsumeIntegral<std::int32_t>() : 0;
  d->linear_near = in.ConsumeBool() ? 0.5f : in.ConsumeFloatingPoint<float>();
  d->linear_far = in.ConsumeBool() ? 20.0f : in.ConsumeFloatingPoint<float>();
  d->width = near_size(in, width);
  d->height = near_size(in, f.height);
  d->data = static_cast<Pointer>(
      views.place(d->height, static_cast<std::int64_t>(d->width) * depth_bytes(d->format), 1, &d->stride));
}

void make_source(FuzzedDataProvider& in, ViewMaker& views, const Frame& f, reproject_source_buffers* s) {
  std::memset(s, 0, sizeof *s);
  if (f.color_format == REPROJECT_COLOR_FLOAT32 || in.ConsumeIntegralInRange(0, 15) == 0)
    fill_color<const float*>(in, views, &s->color, f, f.width);
  if (f.color_format != REPROJECT_COLOR_FLOAT32 || in.ConsumeIntegralInRange(0, 15) == 0)
    fill_pixels<const void*>(in, views, &s->pixels, f, f.width);
  if (f.depth_plane || in.ConsumeIntegralInRange(0, 15) == 0)
    fill_plane<const float*>(in, views, &s->depth, f.width, f.height, 1);
  if (!f.depth_plane || in.ConsumeIntegralInRange(0, 15) == 0)
    fill_depth_buffer<const void*>(in, views, &s->depth_buffer, f, f.width);
}

void make_target(FuzzedDataProvider& in, ViewMaker& views, const Frame& f, std::int32_t width,
                 reproject_target_buffers* t) {
  std::memset(t, 0, sizeof *t);
  if (f.color_format == REPROJECT_COLOR_FLOAT32 || in.ConsumeIntegralInRange(0, 15) == 0)
    fill_color<float*>(in, views, &t->color, f, width);
  if (f.color_format != REPROJECT_COLOR_FLOAT32 || in.ConsumeIntegralInRange(0, 15) == 0)
    fill_pixels<void*>(in, views, &t->pixels, f, width);
  if (in.ConsumeBool()) {
    if (f.depth_plane || in.ConsumeIntegralInRange(0, 15) == 0)
      fill_plane<float*>(in, views, &t->depth, width, f.height, 1);
    if (!f.depth_plane || in.ConsumeIntegralInRange(0, 15) == 0)
      fill_depth_buffer<void*>(in, views, &t->depth_buffer, f, width);
  }
  if (in.ConsumeBool()) {
    t->status.width = near_size(in, width);
    t->status.height = near_size(in, f.height);
    t->status.data = static_cast<std::uint8_t*>(views.place(t->status.height, t->status.width, 1, &t->status.stride));
  }
  if (in.ConsumeBool()) fill_plane<float*>(in, views, &t->source_x, width, f.height, 1);
}

// The views a call that succeeded used, as the documentation says it reads them.
template <class Color>
void color_rows(const Color& color, std::int32_t pixels_format, const void* pixels_data, std::int32_t width,
                std::int32_t height, std::int64_t stride, std::vector<Rows>* out) {
  if (pixels_format != REPROJECT_COLOR_FLOAT32) {
    out->push_back(rows_of(pixels_data, width, height, stride, color_bytes(pixels_format), 1));
    return;
  }
  const bool interleaved = color.layout == REPROJECT_LAYOUT_INTERLEAVED_RGBA;
  const int planes = interleaved ? 1 : std::min(std::max(color.channels, 0), 4);  // valid when the call was
  for (int c = 0; c < planes; ++c)
    out->push_back(rows_of(color.plane[c].data, color.plane[c].width, color.plane[c].height, color.plane[c].stride,
                           interleaved ? 4 : 1, 4));
}
void source_rows(const reproject_source_buffers& s, std::vector<Rows>* out) {
  color_rows(s.color, s.pixels.format, s.pixels.data, s.pixels.width, s.pixels.height, s.pixels.stride, out);
  if (s.depth_buffer.data != nullptr) {
    out->push_back(rows_of(s.depth_buffer.data, s.depth_buffer.width, s.depth_buffer.height, s.depth_buffer.stride,
                           depth_bytes(s.depth_buffer.format), 1));
  } else {
    out->push_back(rows_of(s.depth.data, s.depth.width, s.depth.height, s.depth.stride, 1, 4));
  }
}
void target_rows(const reproject_target_buffers& t, std::vector<Rows>* out) {
  color_rows(t.color, t.pixels.format, t.pixels.data, t.pixels.width, t.pixels.height, t.pixels.stride, out);
  if (t.depth_buffer.data != nullptr) {
    out->push_back(rows_of(t.depth_buffer.data, t.depth_buffer.width, t.depth_buffer.height, t.depth_buffer.stride,
                           depth_bytes(t.depth_buffer.format), 1));
  } else if (t.depth.data != nullptr) {
    out->push_back(rows_of(t.depth.data, t.depth.width, t.depth.height, t.depth.stride, 1, 4));
  }
  if (t.status.data != nullptr)
    out->push_back(rows_of(t.status.data, t.status.width, t.status.height, t.status.stride, 1, 1));
  if (t.source_x.data != nullptr)
    out->push_back(rows_of(t.source_x.data, t.source_x.width, t.source_x.height, t.source_x.stride, 1, 4));
}

void serial_run(void* context, std::int32_t count, void (*task)(void*, std::int32_t), void* task_context) {
  auto* cancel = static_cast<reproject_cancel*>(context);
  for (std::int32_t i = 0; i < count; ++i) {
    task(task_context, i);
    if (cancel != nullptr && i == 0) reproject_cancel_request(cancel);  // a cancel during the call
  }
}

void print_rows(const char* what, const std::vector<Rows>& rows) {
  const u128 begin = reinterpret_cast<std::uintptr_t>(arena().bytes);
  for (const Rows& r : rows)
    std::fprintf(stderr, "  %s: offset %lld, %llu rows of %llu bytes, stride %lld%s\n", what,
                 static_cast<long long>(r.first - begin), static_cast<unsigned long long>(r.rows),
                 static_cast<unsigned long long>(r.row), static_cast<long long>(r.stride),
                 inside_arena(r) ? "" : " (not inside the arena)");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  FuzzedDataProvider in(data, size);
  Arena& a = arena();
  a.fill();
  ViewMaker views{in};

  Frame f;
  f.width = in.ConsumeIntegralInRange<std::int32_t>(0, 64);
  f.height = in.ConsumeIntegralInRange<std::int32_t>(0, 6);
  f.color_format = in.ConsumeIntegralInRange<std::int32_t>(0, 3);
  f.layout = in.ConsumeIntegralInRange<std::int32_t>(0, 1);
  f.channels = f.layout == REPROJECT_LAYOUT_INTERLEAVED_RGBA ? 4 : in.ConsumeIntegralInRange<std::int32_t>(1, 4);
  if (f.color_format != REPROJECT_COLOR_FLOAT32) {
    f.layout = REPROJECT_LAYOUT_PLANAR;  // the packed views need no layout of the float planes
    f.channels = 0;
  }
  f.depth_plane = in.ConsumeBool();
  f.depth_format = f.depth_plane ? REPROJECT_DEPTH_FORMAT_FLOAT32
                                 : in.ConsumeIntegralInRange<std::int32_t>(0, REPROJECT_DEPTH_FORMAT_RGBA8_PACKED_LINEAR);
  const bool pair = in.ConsumeBool();

  reproject_options options;
  reproject_options_init(&options);
  options.guard = in.ConsumeIntegralInRange(0, 7) == 0 ? in.ConsumeIntegralInRange(-2, 40) : 0;
  const std::int32_t target_width = near_size(in, f.width - 2 * options.guard);

  reproject_source_buffers source;
  reproject_target_buffers left, right;
  make_source(in, views, f, &source);
  make_target(in, views, f, target_width, &right);
  if (pair) make_target(in, views, f, target_width, &left);

  reproject_decoder decoder;
  if (f.depth_format == REPROJECT_DEPTH_FORMAT_RGBA8_PACKED_LINEAR || in.ConsumeBool()) {
    reproject_decoder_linear(&decoder);
  } else {
    reproject_decoder_from_near_far(REPROJECT_DEPTH_STANDARD, 0.5, 50.0, &decoder);
  }
  if (in.ConsumeIntegralInRange(0, 15) == 0) decoder.encoding = in.ConsumeIntegral<std::int32_t>();
  reproject_parallax model;
  reproject_parallax_from_stereo(0.05, 3.0, f.width > 0 ? f.width : 1,
                                 pair ? REPROJECT_CENTRE_TO_RIGHT : REPROJECT_LEFT_TO_RIGHT, &model);
  if (in.ConsumeIntegralInRange(0, 15) == 0) {
    model.a = in.ConsumeFloatingPoint<float>();
    model.b = in.ConsumeFloatingPoint<float>();
  }

  options.method = in.ConsumeIntegralInRange(0, 15) == 0 ? in.ConsumeIntegralInRange(-1, 6)
                                                          : in.ConsumeIntegralInRange(0, REPROJECT_METHOD_EXACT);
  options.hole_fill = near_value(in, options.hole_fill, -1, 3);
  options.edge = near_value(in, options.edge, -1, 4);
  options.threads = in.ConsumeIntegralInRange(1, 2);
  if (in.ConsumeIntegralInRange(0, 7) == 0) options.arch = in.ConsumeIntegralInRange(-2, 4);
  reproject_cancel cancel;
  reproject_cancel_init(&cancel);
  const int cancelling = in.ConsumeIntegralInRange(0, 7);  // 0: requested before, 1: during (job hook)
  if (cancelling <= 1 || in.ConsumeBool()) options.cancel = &cancel;
  if (cancelling == 0) reproject_cancel_request(&cancel);
  switch (in.ConsumeIntegralInRange(0, 15)) {
    case 0: options.struct_size = static_cast<std::uint32_t>(offsetof(reproject_options, cancel)); break;
    case 1: options.struct_size = static_cast<std::uint32_t>(offsetof(reproject_options, cancel) + 4); break;
    case 2: options.struct_size = in.ConsumeIntegralInRange<std::uint32_t>(0, 200); break;
    default: break;
  }
  reproject_parallel_for jobs{cancelling == 1 ? &cancel : nullptr, serial_run};
  const int hook = in.ConsumeIntegralInRange(0, 7);  // 0, 1: the hook; 2: a hook without run
  if (hook == 2) jobs.run = nullptr;
  const reproject_parallel_for* jobs_pointer = hook <= 2 ? &jobs : nullptr;
  const reproject_options* options_pointer = in.ConsumeIntegralInRange(0, 31) == 0 ? nullptr : &options;

  std::vector<Rows> inputs, outputs;
  source_rows(source, &inputs);
  target_rows(right, &outputs);
  if (pair) target_rows(left, &outputs);
  if (verbose()) {
    std::fprintf(stderr, "fuzz_c_api: %dx%d %s, colour format %d layout %d channels %d, depth %s %d, guard %d, "
                 "depth_buffer %p %dx%d stride %lld, depth plane %p %dx%d stride %lld\n",
                 f.width, f.height, pair ? "pair" : "single", f.color_format, f.layout, f.channels,
                 f.depth_plane ? "plane" : "buffer", f.depth_format, options.guard, source.depth_buffer.data,
                 source.depth_buffer.width, source.depth_buffer.height, static_cast<long long>(source.depth_buffer.stride),
                 static_cast<const void*>(source.depth.data), source.depth.width, source.depth.height,
                 static_cast<long long>(source.depth.stride));
    print_rows("input", inputs);
    print_rows("output", outputs);
  }

  std::memcpy(a.before.data(), a.bytes, kArenaBytes);
  const reproject_status status =
      pair ? reproject_warp_pair_buffers(&source, &decoder, &model, options_pointer, &left, &right, jobs_pointer)
           : reproject_warp_buffers(&source, &decoder, &model, options_pointer, &right, jobs_pointer);

  if (verbose()) {
    std::fprintf(stderr, "fuzz_c_api: %s (%s)\n", reproject_status_name(status),
                 status == REPROJECT_OK ? "" : reproject_last_error_message());
  }

  CHECK(status >= REPROJECT_OK && status <= REPROJECT_CANCELLED);
  if (status != REPROJECT_OK) {
    CHECK(std::strlen(reproject_last_error_message()) > 0 && std::strcmp(reproject_last_error_message(), "ok") != 0);
  }
  if (status != REPROJECT_OK && status != REPROJECT_CANCELLED) {
    if (std::memcmp(a.before.data(), a.bytes, kArenaBytes) != 0) {
      print_rows("input", inputs);
      print_rows("output", outputs);
      std::fprintf(stderr, "status %s: %s\n", reproject_status_name(status), reproject_last_error_message());
      fail("a refused call wrote into the arena");
    }
    return 0;
  }
  // Accepted (or cancelled after validation): every view it could use is one the caller has.
  // An empty frame uses none (and may have any targets).
  const bool empty = source.depth_buffer.data != nullptr
                         ? source.depth_buffer.width == 0 || source.depth_buffer.height == 0
                         : source.depth.width == 0 || source.depth.height == 0;
  // written: 1 in an input's rows, 2 in an output's.
  std::fill(a.written.begin(), a.written.end(), 0);
  if (!empty) {
    for (const Rows& r : inputs) {
      if (!inside_arena(r)) {
        print_rows("input", inputs);
        fail("an accepted call has an input view outside the arena");
      }
      mark(r, 1, &a.written);
    }
    for (const Rows& r : outputs) {
      if (!inside_arena(r)) {
        print_rows("output", outputs);
        fail("an accepted call has an output view outside the arena");
      }
      if (!mark(r, 2, &a.written)) {
        print_rows("input", inputs);
        print_rows("output", outputs);
        fail("an accepted call has an output sharing a byte with an input or another output");
      }
    }
  }
  if (std::memcmp(a.before.data(), a.bytes, kArenaBytes) == 0) return 0;
  for (std::size_t i = 0; i < kArenaBytes; ++i) {
    if (a.bytes[i] != a.before[i] && a.written[i] != 2) {
      std::fprintf(stderr, "arena byte %zu changed from %u to %u; status %s\n", i, a.before[i], a.bytes[i],
                   reproject_status_name(status));
      print_rows("input", inputs);
      print_rows("output", outputs);
      fail("a call wrote outside the rows of its outputs");
    }
  }
  return 0;
}
