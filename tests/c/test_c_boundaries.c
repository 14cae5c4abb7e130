/* The C interface at its boundaries (issue 21), compiled as C99: strides whose byte offsets
 * overflow 64 bits, views that run past the end of the address space, missing buffers, the job
 * hook and options pointers, side-by-side buffers (one allocation, left half read, right half
 * written), and cancellation.
 *
 * Every buffer lives in one arena between two PROT_NONE pages, filled with a known byte; after
 * each call the arena is compared with a snapshot taken before it: a refused call changes no
 * byte, an accepted one none outside the rows of its outputs. Every case runs in a child process
 * (fork), so that a library that crashes on it fails that case and the others still run. Prints
 * one line per case; exits non-zero if any failed. */
#define _DEFAULT_SOURCE
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#if defined(_WIN32)
#include <windows.h> /* VirtualAlloc for the arena; each case in a child process of its own */
#else
#include <signal.h>
#include <sys/mman.h>
#include <sys/wait.h>
#include <unistd.h>
#endif

#include "reproject/reproject.h"

enum { W = 64, H = 8, N = W * H };
static const double kNear = 0.1, kFar = 100.0;

/* ---- The arena ---------------------------------------------------------------------------- */

enum { kArenaBytes = 1 << 20, kGap = 64, kCanary = 0xA5 };
static unsigned char* arena;      /* kArenaBytes between two PROT_NONE pages */
static unsigned char* snapshot;   /* the arena before the call under test */
static size_t arena_used;

static void arena_init(void) {
#if defined(_WIN32)
  SYSTEM_INFO info;
  DWORD old;
  size_t page;
  unsigned char* base;
  GetSystemInfo(&info);
  page = info.dwPageSize;
  base = VirtualAlloc(NULL, kArenaBytes + 2 * page, MEM_RESERVE | MEM_COMMIT, PAGE_READWRITE);
  if (base == NULL) {
    fprintf(stderr, "VirtualAlloc failed\n");
    exit(2);
  }
  VirtualProtect(base, page, PAGE_NOACCESS, &old);
  VirtualProtect(base + page + kArenaBytes, page, PAGE_NOACCESS, &old);
#else
  const size_t page = (size_t)sysconf(_SC_PAGESIZE);
  unsigned char* base = mmap(NULL, kArenaBytes + 2 * page, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  if (base == MAP_FAILED) {
    perror("mmap");
    exit(2);
  }
  mprotect(base, page, PROT_NONE);
  mprotect(base + page + kArenaBytes, page, PROT_NONE);
#endif
  arena = base + page;
  snapshot = malloc(kArenaBytes);
  if (snapshot == NULL) exit(2);
}

static void arena_reset(void) {
  memset(arena, kCanary, kArenaBytes);
  arena_used = kGap;
}

/* `bytes` from the arena, 64-byte aligned, with a gap of canary bytes before the next block. */
static void* arena_alloc(size_t bytes) {
  void* p = arena + arena_used;
  arena_used += (bytes + kGap + 63) / 64 * 64;
  if (arena_used > kArenaBytes) {
    fprintf(stderr, "arena exhausted\n");
    exit(2);
  }
  return p;
}

static void take_snapshot(void) { memcpy(snapshot, arena, kArenaBytes); }

/* Rows an accepted call may write: [data + y * stride, + row) for y < height. */
typedef struct Rows {
  const void* data;
  int64_t height;
  int64_t row_bytes;
  int64_t stride_bytes;
} Rows;

static int inside(const Rows* rows, int count, size_t offset) {
  int i;
  for (i = 0; i < count; ++i) {
    const unsigned char* start = rows[i].data;
    int64_t y;
    if (start == NULL) continue;
    for (y = 0; y < rows[i].height; ++y) {
      const unsigned char* row = start + y * rows[i].stride_bytes;
      if (arena + offset >= row && arena + offset < row + rows[i].row_bytes) return 1;
    }
  }
  return 0;
}

/* The bytes that changed since the snapshot outside `rows` (count 0: anywhere). Reports the first. */
static int changed_outside(const Rows* rows, int count, const char* what) {
  size_t i, changed = 0, first = 0;
  for (i = 0; i < kArenaBytes; ++i) {
    if (arena[i] != snapshot[i] && !inside(rows, count, i)) {
      if (changed++ == 0) first = i;
    }
  }
  if (changed != 0)
    fprintf(stderr, "  %s: %lu byte(s) written outside the outputs' rows, the first at arena offset %lu\n", what,
            (unsigned long)changed, (unsigned long)first);
  return changed != 0;
}

/* ---- A frame in the arena ----------------------------------------------------------------- */

typedef struct Frame {
  float* color[3];
  float* depth;
  float* out_color[3];
  float* out_depth;
  uint8_t* out_status;
  float* out_source_x;
  reproject_source_buffers source;
  reproject_target_buffers target;
  reproject_decoder decoder;
  reproject_parallax model;
  reproject_options options;
} Frame;

static float standard_depth(double z) { return (float)((1.0 / kNear - 1.0 / z) / (1.0 / kNear - 1.0 / kFar)); }

static void fill_source(float* const color[3], int64_t color_stride, float* depth, int64_t depth_stride) {
  int x, y, c;
  for (y = 0; y < H; ++y) {
    for (x = 0; x < W; ++x) {
      const int box = x >= 20 && x < 40 && y >= 2 && y < 6;
      for (c = 0; c < 3; ++c) color[c][y * color_stride + x] = (float)(x + 7 * c) / W + (float)y / H;
      depth[y * depth_stride + x] = standard_depth(box ? 2.0 : 6.0 + 4.0 * x / W);
    }
  }
}

static reproject_plane plane(const float* data, int64_t stride) {
  reproject_plane p;
  p.data = data;
  p.width = W;
  p.height = H;
  p.stride = stride;
  return p;
}
static reproject_mut_plane mut_plane(float* data, int64_t stride) {
  reproject_mut_plane p;
  p.data = data;
  p.width = W;
  p.height = H;
  p.stride = stride;
  return p;
}

/* A valid float frame: 3 colour planes and depth in, every output out, each buffer its own block. */
static void make_frame(Frame* f) {
  int c;
  memset(f, 0, sizeof *f);
  arena_reset();
  for (c = 0; c < 3; ++c) f->color[c] = arena_alloc(N * sizeof(float));
  f->depth = arena_alloc(N * sizeof(float));
  for (c = 0; c < 3; ++c) f->out_color[c] = arena_alloc(N * sizeof(float));
  f->out_depth = arena_alloc(N * sizeof(float));
  f->out_status = arena_alloc(N);
  f->out_source_x = arena_alloc(N * sizeof(float));
  fill_source(f->color, W, f->depth, W);
  f->source.color.layout = f->target.color.layout = REPROJECT_LAYOUT_PLANAR;
  f->source.color.channels = f->target.color.channels = 3;
  for (c = 0; c < 3; ++c) {
    f->source.color.plane[c] = plane(f->color[c], W);
    f->target.color.plane[c] = mut_plane(f->out_color[c], W);
  }
  f->source.depth = plane(f->depth, W);
  f->target.depth = mut_plane(f->out_depth, W);
  f->target.status.data = f->out_status;
  f->target.status.width = W;
  f->target.status.height = H;
  f->target.status.stride = W;
  f->target.source_x = mut_plane(f->out_source_x, W);
  reproject_decoder_from_near_far(REPROJECT_DEPTH_STANDARD, kNear, kFar, &f->decoder);
  reproject_parallax_from_stereo(0.05, 4.0, W, REPROJECT_LEFT_TO_RIGHT, &f->model);
  reproject_options_init(&f->options);
  f->options.threads = 1;
}

static reproject_status warp(Frame* f) {
  return reproject_warp_buffers(&f->source, &f->decoder, &f->model, &f->options, &f->target, NULL);
}

/* ---- Checks ------------------------------------------------------------------------------- */

#define EXPECT(cond, ...)                                      \
  do {                                                         \
    if (!(cond)) {                                             \
      fprintf(stderr, "  FAILED %s:%d: ", __FILE__, __LINE__); \
      fprintf(stderr, __VA_ARGS__);                            \
      fprintf(stderr, "\n");                                   \
      ++failures;                                              \
    }                                                          \
  } while (0)

/* The call was refused with `expected`, a message holding each of the NULL-terminated `words`,
 * and no byte of the arena changed. */
static int refused(reproject_status status, reproject_status expected, const char* what, const char* const* words) {
  int failures = 0;
  const char* message = reproject_last_error_message();
  EXPECT(status == expected, "%s: status %s, expected %s (\"%s\")", what, reproject_status_name(status),
         reproject_status_name(expected), status == REPROJECT_OK ? "" : message);
  for (; status != REPROJECT_OK && *words != NULL; ++words)
    EXPECT(strstr(message, *words) != NULL, "%s: message \"%s\" lacks \"%s\"", what, message, *words);
  failures += changed_outside(NULL, 0, what);
  printf("  %-58s %s%s%s\n", what, reproject_status_name(status), status == REPROJECT_OK ? "" : ": ",
         status == REPROJECT_OK ? "" : message);
  return failures;
}

/* ---- Defect 1: strides whose byte offsets overflow, views past the end of the address space -- */

typedef struct StrideCase {
  const char* what;
  int field;        /* which view gets the stride */
  int64_t stride;   /* in the view's units (elements, or bytes for pixels and depth buffers) */
  const char* name; /* what the message must name */
} StrideCase;

enum { SRC_COLOR1, SRC_DEPTH, DST_COLOR0, DST_DEPTH, DST_STATUS, DST_SOURCE_X, SRC_PIXELS, SRC_DEPTH_BUFFER, DST_PIXELS,
       DST_DEPTH_BUFFER };

/* The frame as rgba8 pixels and D16 depth (for the byte-stride views). */
static void make_engine_frame(Frame* f) {
  unsigned char* pixels;
  unsigned char* d16;
  make_frame(f);
  pixels = arena_alloc(N * 4);
  d16 = arena_alloc(N * 2);
  memset(pixels, 0x40, N * 4);
  memset(d16, 0x30, N * 2);
  memset(&f->source.color, 0, sizeof f->source.color);
  memset(&f->target.color, 0, sizeof f->target.color);
  memset(&f->source.depth, 0, sizeof f->source.depth);
  memset(&f->target.depth, 0, sizeof f->target.depth);
  f->source.pixels.data = pixels;
  f->source.pixels.width = W;
  f->source.pixels.height = H;
  f->source.pixels.stride = 4 * W;
  f->source.pixels.format = REPROJECT_COLOR_RGBA8;
  f->target.pixels.data = arena_alloc(N * 4);
  f->target.pixels.width = W;
  f->target.pixels.height = H;
  f->target.pixels.stride = 4 * W;
  f->target.pixels.format = REPROJECT_COLOR_RGBA8;
  f->source.depth_buffer.data = d16;
  f->source.depth_buffer.width = W;
  f->source.depth_buffer.height = H;
  f->source.depth_buffer.stride = 2 * W;
  f->source.depth_buffer.format = REPROJECT_DEPTH_FORMAT_UNORM16;
  f->target.depth_buffer.data = arena_alloc(N * 2);
  f->target.depth_buffer.width = W;
  f->target.depth_buffer.height = H;
  f->target.depth_buffer.stride = 2 * W;
  f->target.depth_buffer.format = REPROJECT_DEPTH_FORMAT_UNORM16;
}

static int overflowing_stride(const StrideCase* k) {
  static const char* words[3];
  Frame f;
  int failures = 0;
  if (k->field >= SRC_PIXELS) {
    make_engine_frame(&f);
  } else {
    make_frame(&f);
  }
  switch (k->field) {
    case SRC_COLOR1: f.source.color.plane[1].stride = k->stride; break;
    case SRC_DEPTH: f.source.depth.stride = k->stride; break;
    case DST_COLOR0: f.target.color.plane[0].stride = k->stride; break;
    case DST_DEPTH: f.target.depth.stride = k->stride; break;
    case DST_STATUS: f.target.status.stride = k->stride; break;
    case DST_SOURCE_X: f.target.source_x.stride = k->stride; break;
    case SRC_PIXELS: f.source.pixels.stride = k->stride; break;
    case SRC_DEPTH_BUFFER: f.source.depth_buffer.stride = k->stride; break;
    case DST_PIXELS: f.target.pixels.stride = k->stride; break;
    case DST_DEPTH_BUFFER: f.target.depth_buffer.stride = k->stride; break;
  }
  words[0] = k->name;
  words[1] = "overflows";
  words[2] = NULL;
  take_snapshot();
  failures += refused(warp(&f), REPROJECT_INVALID_STRIDE, k->what, words);
  return failures;
}

static const StrideCase kStrideCases[] = {
    {"target colour stride INT64_MAX", DST_COLOR0, INT64_MAX, "target colour plane 0"},
    {"target colour stride 2^62 (every row onto row 0)", DST_COLOR0, (int64_t)1 << 62, "target colour plane 0"},
    {"source depth stride 2^61", SRC_DEPTH, (int64_t)1 << 61, "source depth"},
    {"source colour plane 1 stride INT64_MAX / 2", SRC_COLOR1, INT64_MAX / 2, "source colour plane 1"},
    {"target depth stride 2^62", DST_DEPTH, (int64_t)1 << 62, "target depth"},
    {"target status stride INT64_MAX", DST_STATUS, INT64_MAX, "target status"},
    {"target source_x stride 2^62 + 1", DST_SOURCE_X, ((int64_t)1 << 62) + 1, "target source_x"},
    {"source rgba8 pixels stride INT64_MAX", SRC_PIXELS, INT64_MAX, "source colour rgba8 pixels"},
    {"source unorm16 depth_buffer stride 2^62", SRC_DEPTH_BUFFER, (int64_t)1 << 62, "source depth_buffer"},
    {"target rgba8 pixels stride 2^62", DST_PIXELS, (int64_t)1 << 62, "target colour rgba8 pixels"},
    {"target unorm16 depth_buffer stride INT64_MAX", DST_DEPTH_BUFFER, INT64_MAX, "target depth_buffer"},
};

static int case_overflowing_strides(void) {
  int failures = 0;
  size_t i;
  for (i = 0; i < sizeof kStrideCases / sizeof kStrideCases[0]; ++i) failures += overflowing_stride(&kStrideCases[i]);
  return failures;
}

/* A view whose rows would run past the end of the address space (data near UINTPTR_MAX). */
static int case_view_past_the_address_space(void) {
  static const char* const words[] = {"target source_x", "address space", NULL};
  Frame f;
  int failures = 0;
  make_frame(&f);
  f.target.source_x.data = (float*)(uintptr_t)(UINTPTR_MAX - 1023); /* its rows span 2 KiB */
  take_snapshot();
  failures += refused(warp(&f), REPROJECT_INVALID_SIZE, "target source_x 1 KiB below the top of memory", words);
  return failures;
}

/* ---- Defect 2: missing buffers, job hook and options pointers ------------------------------- */

static int case_missing_buffers(void) {
  static const char* const buffer_words[] = {"source depth_buffer", "null", NULL};
  static const char* const depth_words[] = {"source depth", "null", NULL};
  static const char* const run_words[] = {"run", "null", NULL};
  static const char* const options_words[] = {"options", "null", NULL};
  static const char* const pixels_words[] = {"null", NULL};
  Frame f;
  int failures = 0;
  int context = 0;
  reproject_parallel_for jobs;
  reproject_source float_source;
  reproject_target float_target;

  /* A depth buffer with its size and format set and no data; the float plane zeroed. */
  make_frame(&f);
  memset(&f.source.depth, 0, sizeof f.source.depth);
  f.source.depth_buffer.width = W;
  f.source.depth_buffer.height = H;
  f.source.depth_buffer.stride = 2 * W;
  f.source.depth_buffer.format = REPROJECT_DEPTH_FORMAT_UNORM16;
  memset(&f.target.depth, 0, sizeof f.target.depth);
  take_snapshot();
  failures += refused(warp(&f), REPROJECT_NULL_POINTER, "depth_buffer: size and format set, data NULL", buffer_words);

  /* No depth at all (both zeroed) for a colour of W x H. */
  f.source.depth_buffer.width = f.source.depth_buffer.height = 0;
  f.source.depth_buffer.stride = 0;
  f.source.depth_buffer.format = 0;
  take_snapshot();
  failures += refused(warp(&f), REPROJECT_NULL_POINTER, "no depth (both zeroed), colour WxH", depth_words);

  /* The float plane with its size set and no data (the C++ check, for comparison). */
  make_frame(&f);
  f.source.depth.data = NULL;
  take_snapshot();
  failures += refused(warp(&f), REPROJECT_NULL_POINTER, "depth plane: size set, data NULL", depth_words);

  /* Packed pixels with a format and no data (the C++ check, for comparison). */
  make_engine_frame(&f);
  f.source.pixels.data = NULL;
  take_snapshot();
  failures += refused(warp(&f), REPROJECT_NULL_POINTER, "pixels: format set, data NULL", pixels_words);

  /* A job hook without run, with and without a context: never the pool in its place. */
  make_frame(&f);
  jobs.context = &context;
  jobs.run = NULL;
  take_snapshot();
  failures += refused(reproject_warp_buffers(&f.source, &f.decoder, &f.model, &f.options, &f.target, &jobs),
                      REPROJECT_INVALID_OPTION, "jobs.run NULL, context set", run_words);
  jobs.context = NULL;
  take_snapshot();
  failures += refused(reproject_warp_buffers(&f.source, &f.decoder, &f.model, &f.options, &f.target, &jobs),
                      REPROJECT_INVALID_OPTION, "jobs.run NULL, context NULL", run_words);

  /* Options are required, in every entry point. */
  take_snapshot();
  failures += refused(reproject_warp_buffers(&f.source, &f.decoder, &f.model, NULL, &f.target, NULL),
                      REPROJECT_NULL_POINTER, "reproject_warp_buffers: options NULL", options_words);
  take_snapshot();
  failures += refused(reproject_warp_pair_buffers(&f.source, &f.decoder, &f.model, NULL, &f.target, &f.target, NULL),
                      REPROJECT_NULL_POINTER, "reproject_warp_pair_buffers: options NULL", options_words);
  memset(&float_source, 0, sizeof float_source);
  memset(&float_target, 0, sizeof float_target);
  float_source.color = f.source.color;
  float_source.depth = f.source.depth;
  float_target.color = f.target.color;
  take_snapshot();
  failures += refused(reproject_warp(&float_source, &f.decoder, &f.model, NULL, &float_target, NULL),
                      REPROJECT_NULL_POINTER, "reproject_warp: options NULL", options_words);
  take_snapshot();
  failures += refused(reproject_warp_pair(&float_source, &f.decoder, &f.model, NULL, &float_target, &float_target, NULL),
                      REPROJECT_NULL_POINTER, "reproject_warp_pair: options NULL", options_words);
  return failures;
}

/* ---- Defect 3: side-by-side buffers ------------------------------------------------------- */

/* Rows of a float plane for changed_outside(). */
static Rows float_rows(const void* data, int64_t stride) {
  Rows r;
  r.data = data;
  r.height = H;
  r.row_bytes = W * (int64_t)sizeof(float);
  r.stride_bytes = stride * (int64_t)sizeof(float);
  return r;
}

/* Colour, depth and status of one call with side-by-side buffers against the same call on
 * buffers of their own: identical bytes, row by row. */
static int case_side_by_side(void) {
  static const char* const words[] = {"overlap", NULL};
  Frame f;
  int failures = 0, c, y;
  float* sbs_color[3];
  float* sbs_depth;
  float* left_color[3];
  Rows rows[5];
  reproject_status status;

  /* The reference: buffers of their own. */
  make_frame(&f);
  status = warp(&f);
  EXPECT(status == REPROJECT_OK, "reference: %s", reproject_last_error_message());
  {
    static float reference_color[3][N], reference_depth[N];
    for (c = 0; c < 3; ++c) memcpy(reference_color[c], f.out_color[c], sizeof reference_color[c]);
    memcpy(reference_depth, f.out_depth, sizeof reference_depth);

    /* Each colour plane and the depth: one allocation of H rows of 2W floats, the source in the
     * left half, the target in the right half, both with the stride 2W. */
    make_frame(&f);
    for (c = 0; c < 3; ++c) {
      sbs_color[c] = arena_alloc(2 * N * sizeof(float));
      left_color[c] = sbs_color[c];
    }
    sbs_depth = arena_alloc(2 * N * sizeof(float));
    fill_source(left_color, 2 * W, sbs_depth, 2 * W);
    for (c = 0; c < 3; ++c) {
      f.source.color.plane[c] = plane(sbs_color[c], 2 * W);
      f.target.color.plane[c] = mut_plane(sbs_color[c] + W, 2 * W);
      rows[c] = float_rows(sbs_color[c] + W, 2 * W);
    }
    f.source.depth = plane(sbs_depth, 2 * W);
    f.target.depth = mut_plane(sbs_depth + W, 2 * W);
    rows[3] = float_rows(sbs_depth + W, 2 * W);
    f.target.status.data = NULL;
    f.target.source_x.data = NULL;
    take_snapshot();
    status = warp(&f);
    EXPECT(status == REPROJECT_OK, "side by side: %s", reproject_last_error_message());
    printf("  %-58s %s%s%s\n", "colour and depth: left half in, right half out", reproject_status_name(status),
           status == REPROJECT_OK ? "" : ": ", status == REPROJECT_OK ? "" : reproject_last_error_message());
    failures += changed_outside(rows, 4, "side by side");
    if (status == REPROJECT_OK) {
      for (y = 0; y < H; ++y) {
        for (c = 0; c < 3; ++c)
          EXPECT(memcmp(sbs_color[c] + y * 2 * W + W, reference_color[c] + y * W, W * sizeof(float)) == 0,
                 "side by side: colour %d row %d differs from the reference", c, y);
        EXPECT(memcmp(sbs_depth + y * 2 * W + W, reference_depth + y * W, W * sizeof(float)) == 0,
               "side by side: depth row %d differs from the reference", y);
      }
    }

    /* One float of real overlap per row: refused, nothing written. */
    f.target.color.plane[1] = mut_plane(sbs_color[1] + W - 1, 2 * W);
    take_snapshot();
    failures += refused(warp(&f), REPROJECT_ALIASING, "target colour 1 one float into the source's rows", words);
    f.target.color.plane[1] = mut_plane(sbs_color[1] + W, 2 * W);
    f.target.depth = mut_plane(sbs_depth + W - 1, 2 * W);
    take_snapshot();
    failures += refused(warp(&f), REPROJECT_ALIASING, "target depth one float into the source's rows", words);
  }
  return failures;
}

/* The engine formats side by side: rgba8 pixels and D16 depth, source left, target right. */
static int case_side_by_side_engine(void) {
  Frame f;
  int failures = 0, y;
  unsigned char* pixels;
  unsigned char* d16;
  static unsigned char reference[N * 4];
  Rows rows[2];
  reproject_status status;

  make_engine_frame(&f);
  for (y = 0; y < N * 4; ++y) ((unsigned char*)f.source.pixels.data)[y] = (unsigned char)(y * 7);
  for (y = 0; y < N; ++y) ((uint16_t*)f.source.depth_buffer.data)[y] = (uint16_t)(40000 + (y % W) * 300);
  memset(&f.target.depth_buffer, 0, sizeof f.target.depth_buffer);
  status = warp(&f);
  EXPECT(status == REPROJECT_OK, "engine reference: %s", reproject_last_error_message());
  memcpy(reference, f.target.pixels.data, sizeof reference);

  pixels = arena_alloc(2 * N * 4);
  d16 = arena_alloc(2 * N * 2);
  for (y = 0; y < H; ++y) {
    memcpy(pixels + y * 8 * W, (const unsigned char*)f.source.pixels.data + y * 4 * W, 4 * W);
    memcpy(d16 + y * 4 * W, (const unsigned char*)f.source.depth_buffer.data + y * 2 * W, 2 * W);
  }
  f.source.pixels.data = pixels;
  f.source.pixels.stride = 8 * W;
  f.target.pixels.data = pixels + 4 * W;
  f.target.pixels.stride = 8 * W;
  f.source.depth_buffer.data = d16;
  f.source.depth_buffer.stride = 4 * W;
  f.target.status.data = d16 + 2 * W; /* the status bytes in the right half of the depth buffer's rows */
  f.target.status.stride = 4 * W;
  f.target.source_x.data = NULL;
  rows[0].data = pixels + 4 * W;
  rows[0].height = H;
  rows[0].row_bytes = 4 * W;
  rows[0].stride_bytes = 8 * W;
  rows[1].data = d16 + 2 * W;
  rows[1].height = H;
  rows[1].row_bytes = W;
  rows[1].stride_bytes = 4 * W;
  take_snapshot();
  status = warp(&f);
  EXPECT(status == REPROJECT_OK, "engine side by side: %s", reproject_last_error_message());
  printf("  %-58s %s%s%s\n", "rgba8 + D16: left half in, right half out", reproject_status_name(status),
         status == REPROJECT_OK ? "" : ": ", status == REPROJECT_OK ? "" : reproject_last_error_message());
  failures += changed_outside(rows, 2, "engine side by side");
  if (status == REPROJECT_OK) {
    for (y = 0; y < H; ++y)
      EXPECT(memcmp(pixels + y * 8 * W + 4 * W, reference + y * 4 * W, 4 * W) == 0,
             "engine side by side: row %d differs from the reference", y);
  }
  return failures;
}

/* Both eyes of a pair into one side-by-side output: left eye left half, right eye right half. */
static int case_pair_side_by_side(void) {
  Frame f;
  reproject_target_buffers left;
  reproject_parallax centre_to_right;
  int failures = 0, c;
  float* out[3];
  Rows rows[3];
  reproject_status status;

  make_frame(&f);
  reproject_parallax_from_stereo(0.05, 4.0, W, REPROJECT_CENTRE_TO_RIGHT, &centre_to_right);
  left = f.target;
  left.depth.data = NULL;
  left.status.data = NULL;
  left.source_x.data = NULL;
  f.target.depth.data = NULL;
  f.target.status.data = NULL;
  f.target.source_x.data = NULL;
  for (c = 0; c < 3; ++c) {
    out[c] = arena_alloc(2 * N * sizeof(float));
    left.color.plane[c] = mut_plane(out[c], 2 * W);
    f.target.color.plane[c] = mut_plane(out[c] + W, 2 * W);
    rows[c].data = out[c];
    rows[c].height = H;
    rows[c].row_bytes = 2 * W * (int64_t)sizeof(float); /* both halves are outputs */
    rows[c].stride_bytes = 2 * W * (int64_t)sizeof(float);
  }
  take_snapshot();
  status = reproject_warp_pair_buffers(&f.source, &f.decoder, &centre_to_right, &f.options, &left, &f.target, NULL);
  EXPECT(status == REPROJECT_OK, "pair side by side: %s", reproject_last_error_message());
  printf("  %-58s %s%s%s\n", "pair: left eye left half, right eye right half", reproject_status_name(status),
         status == REPROJECT_OK ? "" : ": ", status == REPROJECT_OK ? "" : reproject_last_error_message());
  failures += changed_outside(rows, 3, "pair side by side");
  return failures;
}

/* ---- Defect 7: cancellation ------------------------------------------------------------------ */

/* A job system that runs the first task, then requests the cancel in its context, then the rest:
 * a cancel that arrives while the call runs. */
typedef struct CancellingJobs {
  reproject_cancel* cancel;
  int32_t tasks_run;
} CancellingJobs;
static void cancelling_run(void* context, int32_t count, void (*task)(void*, int32_t), void* task_context) {
  CancellingJobs* jobs = context;
  int32_t i;
  for (i = 0; i < count; ++i) {
    task(task_context, i);
    ++jobs->tasks_run;
    if (i == 0) reproject_cancel_request(jobs->cancel);
  }
}

static int case_cancellation(void) {
  static const char* const words[] = {"cancel", NULL};
  static const char* const stride_words[] = {"stride", NULL};
  Frame f;
  reproject_cancel cancel;
  reproject_status status;
  CancellingJobs hook;
  reproject_parallel_for jobs;
  int failures = 0, c;
  static float uncancelled[3][N];

  make_frame(&f);
  reproject_cancel_init(&cancel);
  EXPECT(reproject_cancel_requested(&cancel) == 0, "a new cancel is not requested");
  f.options.cancel = &cancel;
  status = warp(&f);
  EXPECT(status == REPROJECT_OK, "not requested: %s", reproject_last_error_message());
  for (c = 0; c < 3; ++c) memcpy(uncancelled[c], f.out_color[c], sizeof uncancelled[c]);

  /* Requested before the call: nothing is run, so nothing is written. */
  make_frame(&f);
  reproject_cancel_init(&cancel);
  reproject_cancel_request(&cancel);
  EXPECT(reproject_cancel_requested(&cancel) == 1, "a requested cancel says so");
  f.options.cancel = &cancel;
  take_snapshot();
  failures += refused(warp(&f), REPROJECT_CANCELLED, "requested before the call", words);
  EXPECT(strcmp(reproject_status_name(REPROJECT_CANCELLED), "cancelled") == 0, "status name %s",
         reproject_status_name(REPROJECT_CANCELLED));

  /* An invalid call still reports what is wrong with it. */
  f.target.depth.stride = W - 1;
  take_snapshot();
  failures += refused(warp(&f), REPROJECT_INVALID_STRIDE, "requested, and a stride too small", stride_words);
  f.target.depth.stride = W;

  /* Requested while the call runs (by the job system, after the first band). */
  make_frame(&f);
  reproject_cancel_init(&cancel);
  f.options.cancel = &cancel;
  hook.cancel = &cancel;
  hook.tasks_run = 0;
  jobs.context = &hook;
  jobs.run = cancelling_run;
  status = reproject_warp_buffers(&f.source, &f.decoder, &f.model, &f.options, &f.target, &jobs);
  EXPECT(status == REPROJECT_CANCELLED, "requested during the call: %s (%s)", reproject_status_name(status),
         reproject_last_error_message());
  printf("  %-58s %s (after %d task(s))\n", "requested by the job system after its first task",
         reproject_status_name(status), (int)hook.tasks_run);
  /* Also for a pair. */
  make_frame(&f);
  reproject_cancel_init(&cancel);
  f.options.cancel = &cancel;
  {
    reproject_target_buffers left = f.target;
    float* left_color[3];
    for (c = 0; c < 3; ++c) {
      left_color[c] = arena_alloc(N * sizeof(float));
      left.color.plane[c] = mut_plane(left_color[c], W);
    }
    left.depth.data = NULL;
    left.status.data = NULL;
    left.source_x.data = NULL;
    hook.tasks_run = 0;
    status = reproject_warp_pair_buffers(&f.source, &f.decoder, &f.model, &f.options, &left, &f.target, &jobs);
    EXPECT(status == REPROJECT_CANCELLED, "pair, requested during the call: %s", reproject_status_name(status));
  }

  /* Initialised again: the next call runs, whole and identical. */
  make_frame(&f);
  reproject_cancel_init(&cancel);
  f.options.cancel = &cancel;
  status = warp(&f);
  EXPECT(status == REPROJECT_OK, "after init again: %s", reproject_last_error_message());
  for (c = 0; c < 3; ++c)
    EXPECT(memcmp(uncancelled[c], f.out_color[c], sizeof uncancelled[c]) == 0, "colour %d differs", c);

  /* An options struct from an older header (struct_size ends before `cancel`) has no cancel. */
  reproject_cancel_request(&cancel);
  f.options.struct_size = (uint32_t)offsetof(reproject_options, cancel);
  status = warp(&f);
  EXPECT(status == REPROJECT_OK, "older struct_size: %s", reproject_last_error_message());
  printf("  %-58s %s\n", "requested, options from an older header", reproject_status_name(status));
  return failures;
}

/* ---- Running the cases -------------------------------------------------------------------- */

typedef struct Case {
  const char* name;
  int (*run)(void);
} Case;

static const Case kCases[] = {
    {"defect 1: strides whose byte offsets overflow", case_overflowing_strides},
    {"defect 1: a view past the end of the address space", case_view_past_the_address_space},
    {"defect 2: missing buffers, job hook and options", case_missing_buffers},
    {"defect 3: side-by-side buffers", case_side_by_side},
    {"defect 3: side-by-side engine buffers", case_side_by_side_engine},
    {"defect 3: a pair into one side-by-side output", case_pair_side_by_side},
    {"defect 7: cancellation", case_cancellation},
};

#if defined(_WIN32)
/* Windows has no fork: each case runs in a child started as `<this program> <case number>`. A crash
 * ends the child with an exception code (STATUS_ACCESS_VIOLATION, 0xC0000005, and the like). */
static int run_case(size_t i, unsigned long* exception) {
  wchar_t self[MAX_PATH], command[MAX_PATH + 32];
  STARTUPINFOW startup;
  PROCESS_INFORMATION process;
  DWORD code = 2;
  *exception = 0;
  if (GetModuleFileNameW(NULL, self, MAX_PATH) == 0) return 2;
  swprintf(command, MAX_PATH + 32, L"\"%ls\" %u", self, (unsigned)i);
  memset(&startup, 0, sizeof startup);
  startup.cb = sizeof startup;
  if (!CreateProcessW(NULL, command, NULL, NULL, TRUE, 0, NULL, NULL, &startup, &process)) {
    fprintf(stderr, "CreateProcess failed: %lu\n", (unsigned long)GetLastError());
    return 2;
  }
  WaitForSingleObject(process.hProcess, INFINITE);
  GetExitCodeProcess(process.hProcess, &code);
  CloseHandle(process.hThread);
  CloseHandle(process.hProcess);
  if (code >= 0xC0000000u) *exception = code;
  return (int)code;
}
#endif

int main(int argc, char** argv) {
  size_t i;
  int failed = 0;
  arena_init();
  setvbuf(stdout, NULL, _IONBF, 0);
#if defined(_WIN32)
  if (argc == 2) return kCases[atoi(argv[1])].run() == 0 ? 0 : 1; /* a child: one case */
  for (i = 0; i < sizeof kCases / sizeof kCases[0]; ++i) {
    unsigned long exception = 0;
    int code;
    printf("%s\n", kCases[i].name);
    code = run_case(i, &exception);
    if (exception != 0) {
      printf("FAILED %s: the library crashed (exception 0x%08lx)\n", kCases[i].name, exception);
      ++failed;
    } else if (code != 0) {
      printf("FAILED %s\n", kCases[i].name);
      ++failed;
    }
  }
#else
  (void)argc;
  (void)argv;
  for (i = 0; i < sizeof kCases / sizeof kCases[0]; ++i) {
    pid_t child;
    int status = 0;
    printf("%s\n", kCases[i].name);
    child = fork();
    if (child < 0) {
      perror("fork");
      return 2;
    }
    if (child == 0) _exit(kCases[i].run() == 0 ? 0 : 1);
    waitpid(child, &status, 0);
    if (WIFSIGNALED(status)) {
      printf("FAILED %s: the library crashed (signal %d)\n", kCases[i].name, WTERMSIG(status));
      ++failed;
    } else if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
      printf("FAILED %s\n", kCases[i].name);
      ++failed;
    }
  }
#endif
  if (failed != 0) {
    printf("%d of %d case(s) failed\n", failed, (int)(sizeof kCases / sizeof kCases[0]));
    return 1;
  }
  printf("all %d boundary cases passed\n", (int)(sizeof kCases / sizeof kCases[0]));
  return 0;
}
