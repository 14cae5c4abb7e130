/* The C interface, compiled as C99: a frame reprojected through reproject.h must equal the C++
 * API's result (c_reference.cpp) bit for bit, for every method, single eye and pair; the same for
 * the engine formats (reproject_warp_buffers: every colour x depth format, 1 and 2 threads and the
 * job-system hook); plus the error codes and messages, the job-system hook and the versioned
 * options. Prints one line per check; exits non-zero if any failed. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "c_reference.h"
#include "reproject/reproject.h"

int reference_warp(const float* const* color_planes, int channels, const float* depth, int width, int height,
                   double near_plane, double far_plane, int method, int arch, float* const* out_color,
                   float* out_depth, uint8_t* out_status, float* out_source_x, int pair, float* const* left_color);

enum { W = 203, H = 61, C = 3, N = W * H }; /* odd width: SIMD tails are exercised */
static const double kNear = 0.1, kFar = 100.0;

static int failures = 0;
#define CHECK(cond, ...)                                  \
  do {                                                    \
    if (!(cond)) {                                        \
      fprintf(stderr, "FAILED %s:%d: ", __FILE__, __LINE__); \
      fprintf(stderr, __VA_ARGS__);                       \
      fprintf(stderr, "\n");                              \
      ++failures;                                         \
    }                                                     \
  } while (0)

static float color_in[C][N], depth_in[N];

/* A gradient with a box at z = 2 in front of a slanted wall, stored as standard depth. */
static void make_frame(const reproject_decoder* decoder) {
  int x, y;
  (void)decoder;
  for (y = 0; y < H; ++y) {
    for (x = 0; x < W; ++x) {
      const int box = x >= 70 && x < 130 && y >= 20 && y < 45;
      const double z = box ? 2.0 : 6.0 + 4.0 * x / W;
      color_in[0][y * W + x] = (float)x / W;
      color_in[1][y * W + x] = (float)y / H;
      color_in[2][y * W + x] = box ? 1.0f : 0.25f;
      /* standard: d = (1/n - 1/z) / (1/n - 1/f) */
      depth_in[y * W + x] = (float)((1.0 / kNear - 1.0 / z) / (1.0 / kNear - 1.0 / kFar));
    }
  }
}

static reproject_plane plane(const float* data) {
  reproject_plane p;
  p.data = data;
  p.width = W;
  p.height = H;
  p.stride = W;
  return p;
}
static reproject_mut_plane mut_plane(float* data) {
  reproject_mut_plane p;
  p.data = data;
  p.width = W;
  p.height = H;
  p.stride = W;
  return p;
}

typedef struct Output {
  float color[C][N];
  float depth[N];
  uint8_t status[N];
  float source_x[N];
} Output;

static reproject_target target_of(Output* out) {
  reproject_target t;
  int c;
  memset(&t, 0, sizeof t);
  t.color.layout = REPROJECT_LAYOUT_PLANAR;
  t.color.channels = C;
  for (c = 0; c < C; ++c) t.color.plane[c] = mut_plane(out->color[c]);
  t.depth = mut_plane(out->depth);
  t.status.data = out->status;
  t.status.width = W;
  t.status.height = H;
  t.status.stride = W;
  t.source_x = mut_plane(out->source_x);
  return t;
}

static reproject_source source_of(void) {
  reproject_source s;
  int c;
  memset(&s, 0, sizeof s);
  s.color.layout = REPROJECT_LAYOUT_PLANAR;
  s.color.channels = C;
  for (c = 0; c < C; ++c) s.color.plane[c] = plane(color_in[c]);
  s.depth = plane(depth_in);
  return s;
}

static int same_output(const Output* a, const Output* b) {
  /* Byte comparison: bit for bit, NaN patterns included. */
  return memcmp(a, b, sizeof *a) == 0;
}

/* A serial job system: counts how often it is asked to run. */
static int job_runs = 0;
static void serial_run(void* context, int32_t count, void (*task)(void*, int32_t), void* task_context) {
  int32_t i;
  ++*(int*)context;
  for (i = 0; i < count; ++i) task(task_context, i);
}

static Output c_out, cpp_out, c_left, cpp_left;

/* ---- Engine formats (reproject_warp_buffers): every colour format x depth format, C == C++. ---- */

/* Formats with their C++ names (the reference parses the name, not the C value) and bytes per
 * pixel. Depth float32 twice: as the `depth` float plane and as a float32 depth_buffer. */
typedef struct ColorCase { int32_t format; const char* name; int bytes; } ColorCase;
typedef struct DepthCase { int32_t format; const char* name; int bytes; int plane; } DepthCase;
static const ColorCase kColors[] = {{REPROJECT_COLOR_FLOAT32, "float32", 4},
                                    {REPROJECT_COLOR_RGBA8, "rgba8", 4},
                                    {REPROJECT_COLOR_RGBA8_SRGB, "rgba8_srgb", 4},
                                    {REPROJECT_COLOR_RGBA16F, "rgba16f", 8}};
static const DepthCase kDepths[] = {{REPROJECT_DEPTH_FORMAT_FLOAT32, "float32", 4, 1},
                                    {REPROJECT_DEPTH_FORMAT_FLOAT32, "float32", 4, 0},
                                    {REPROJECT_DEPTH_FORMAT_UNORM16, "unorm16", 2, 0},
                                    {REPROJECT_DEPTH_FORMAT_UNORM24_S8, "unorm24_s8", 4, 0},
                                    {REPROJECT_DEPTH_FORMAT_S8_UNORM24, "s8_unorm24", 4, 0},
                                    {REPROJECT_DEPTH_FORMAT_RGBA8_PACKED_LINEAR, "rgba8_packed_linear", 4, 0}};
static const float kLinearNear = 0.5f, kLinearFar = 20.0f; /* the packed-linear buffers' range */

/* Rows are padded (PAD bytes), so no stride equals width x bytes per pixel; padding bytes are
 * compared too (nothing may be written there). Storage is uint32_t for alignment; written through
 * memcpy. float32 colour is three planes, the packed formats use color[0]. */
enum { PAD = 8, ROW_MAX = 8 * W + PAD };
typedef struct Buffers {
  uint32_t color[3][H * ROW_MAX / 4];
  uint32_t depth[H * ROW_MAX / 4];
  uint8_t status[N];
  float source_x[N];
} Buffers;
static Buffers fmt_in, fmt_c, fmt_cpp, fmt_c_left, fmt_cpp_left;

static int64_t color_stride(const ColorCase* cf) { return (int64_t)cf->bytes * W + PAD; }
static int64_t depth_stride(const DepthCase* df) { return (int64_t)df->bytes * W + PAD; }
static unsigned char* bytes_of(uint32_t* storage) { return (unsigned char*)storage; }
static void put(unsigned char* at, const void* value, size_t size) { memcpy(at, value, size); }

/* The frame of make_frame (a box at z = 2 before a slanted wall) in the given formats. Stencil
 * bytes and packed A vary per pixel, so carrying them from the right source pixel is checked. */
static void fill_formats(const ColorCase* cf, const DepthCase* df) {
  int x, y, c;
  memset(&fmt_in, 0x5A, sizeof fmt_in);
  for (y = 0; y < H; ++y) {
    for (x = 0; x < W; ++x) {
      const int box = x >= 70 && x < 130 && y >= 20 && y < 45;
      const double z = box ? 2.0 : 6.0 + 4.0 * x / W;
      const double d = (1.0 / kNear - 1.0 / z) / (1.0 / kNear - 1.0 / kFar); /* standard depth */
      const uint32_t stencil = (uint32_t)(x * 7 + y * 13) & 255u;
      unsigned char* color = bytes_of(fmt_in.color[0]) + y * color_stride(cf);
      unsigned char* depth = bytes_of(fmt_in.depth) + y * depth_stride(df);
      if (cf->format == REPROJECT_COLOR_FLOAT32) {
        const float rgb[3] = {(float)x / W, (float)y / H, box ? 1.0f : 0.25f};
        for (c = 0; c < 3; ++c) put(bytes_of(fmt_in.color[c]) + y * color_stride(cf) + 4 * x, &rgb[c], 4);
      } else if (cf->format == REPROJECT_COLOR_RGBA16F) {
        /* halves in [0.125, 1), the box's blue 1.0 */
        for (c = 0; c < 4; ++c) {
          const uint16_t half = c == 2 && box ? 0x3C00u : (uint16_t)(0x3000u + ((x * 37u + y * 11u + c * 5u) & 0x0FFFu));
          put(color + 8 * x + 2 * c, &half, 2);
        }
      } else {
        const unsigned char rgba[4] = {(unsigned char)(x * 255 / W), (unsigned char)(y * 255 / H),
                                       (unsigned char)(box ? 255 : 64), (unsigned char)stencil};
        put(color + 4 * x, rgba, 4);
      }
      if (df->format == REPROJECT_DEPTH_FORMAT_FLOAT32) {
        const float value = (float)d;
        put(depth + 4 * x, &value, 4);
      } else if (df->format == REPROJECT_DEPTH_FORMAT_UNORM16) {
        const uint16_t u = (uint16_t)lround(d * 65535.0);
        put(depth + 2 * x, &u, 2);
      } else if (df->format == REPROJECT_DEPTH_FORMAT_RGBA8_PACKED_LINEAR) {
        /* linear z over [near, far] as n / 255^3, n in base-255 digits R, G, B; A not depth */
        const long n = lround((z - kLinearNear) / (kLinearFar - kLinearNear) * 16581375.0);
        const unsigned char rgba[4] = {(unsigned char)(n / 65025), (unsigned char)(n / 255 % 255),
                                       (unsigned char)(n % 255), (unsigned char)stencil};
        put(depth + 4 * x, rgba, 4);
      } else {
        const uint32_t u = (uint32_t)lround(d * 16777215.0);
        const uint32_t word = df->format == REPROJECT_DEPTH_FORMAT_UNORM24_S8 ? u | stencil << 24 : u << 8 | stencil;
        put(depth + 4 * x, &word, 4);
      }
    }
  }
}

static reproject_source_buffers source_buffers(const ColorCase* cf, const DepthCase* df) {
  reproject_source_buffers s;
  int c;
  memset(&s, 0, sizeof s);
  if (cf->format == REPROJECT_COLOR_FLOAT32) {
    s.color.layout = REPROJECT_LAYOUT_PLANAR;
    s.color.channels = C;
    for (c = 0; c < C; ++c) {
      s.color.plane[c] = plane((const float*)fmt_in.color[c]);
      s.color.plane[c].stride = color_stride(cf) / 4;
    }
  } else {
    s.pixels.data = fmt_in.color[0];
    s.pixels.width = W;
    s.pixels.height = H;
    s.pixels.stride = color_stride(cf);
    s.pixels.format = cf->format;
  }
  if (df->plane) {
    s.depth = plane((const float*)fmt_in.depth);
    s.depth.stride = depth_stride(df) / 4;
  } else {
    s.depth_buffer.data = fmt_in.depth;
    s.depth_buffer.width = W;
    s.depth_buffer.height = H;
    s.depth_buffer.stride = depth_stride(df);
    s.depth_buffer.format = df->format;
    s.depth_buffer.linear_near = kLinearNear;
    s.depth_buffer.linear_far = kLinearFar;
  }
  return s;
}

static reproject_target_buffers target_buffers(Buffers* out, const ColorCase* cf, const DepthCase* df) {
  reproject_target_buffers t;
  int c;
  memset(&t, 0, sizeof t);
  if (cf->format == REPROJECT_COLOR_FLOAT32) {
    t.color.layout = REPROJECT_LAYOUT_PLANAR;
    t.color.channels = C;
    for (c = 0; c < C; ++c) {
      t.color.plane[c] = mut_plane((float*)out->color[c]);
      t.color.plane[c].stride = color_stride(cf) / 4;
    }
  } else {
    t.pixels.data = out->color[0];
    t.pixels.width = W;
    t.pixels.height = H;
    t.pixels.stride = color_stride(cf);
    t.pixels.format = cf->format;
  }
  if (df->plane) {
    t.depth = mut_plane((float*)out->depth);
    t.depth.stride = depth_stride(df) / 4;
  } else {
    t.depth_buffer.data = out->depth;
    t.depth_buffer.width = W;
    t.depth_buffer.height = H;
    t.depth_buffer.stride = depth_stride(df);
    t.depth_buffer.format = df->format;
  }
  t.status.data = out->status;
  t.status.width = W;
  t.status.height = H;
  t.status.stride = W;
  t.source_x = mut_plane(out->source_x);
  return t;
}

static RefView ref_view(Buffers* b, const ColorCase* cf, const DepthCase* df) {
  RefView r;
  int c;
  memset(&r, 0, sizeof r);
  r.color_format = cf->name;
  for (c = 0; c < 3; ++c) r.color[c] = b->color[c];
  r.color_stride = color_stride(cf);
  r.depth_format = df->name;
  r.depth_plane = df->plane;
  r.depth = b->depth;
  r.depth_stride = depth_stride(df);
  r.linear_near = kLinearNear;
  r.linear_far = kLinearFar;
  r.status = b->status;
  r.source_x = b->source_x;
  return r;
}

static int counting_runs = 0;

static int filled(const unsigned char* pixel, int bytes) {
  int i;
  for (i = 0; i < bytes; ++i)
    if (pixel[i] != 0xA5) return 0;
  return 1;
}
static int hits(const uint8_t* status) {
  int i, count = 0;
  for (i = 0; i < N; ++i) count += status[i] == REPROJECT_PIXEL_HIT;
  return count;
}

/* A valid decoder, model (eye direction `direction`) and default options for one call. */
static void good_arguments(reproject_decoder* decoder, reproject_parallax* model, int32_t direction,
                           reproject_options* options) {
  reproject_decoder_from_near_far(REPROJECT_DEPTH_STANDARD, kNear, kFar, decoder);
  reproject_parallax_from_stereo(0.03, 4.0, W, direction, model);
  reproject_options_init(options);
}

/* One bad field at a time on an rgba8 + D24S8 frame: a status code and a message naming it
 * (`words`, not read for REPROJECT_OK: the message is the last failure's). */
static void expect_refused(const reproject_source_buffers* source, const reproject_target_buffers* target,
                           reproject_status expected, const char* words, const char* what) {
  reproject_decoder decoder;
  reproject_parallax model;
  reproject_options options;
  reproject_status status;
  good_arguments(&decoder, &model, REPROJECT_LEFT_TO_RIGHT, &options);
  status = reproject_warp_buffers(source, &decoder, &model, &options, target, NULL);
  CHECK(status == expected, "%s: status %s, expected %s (%s)", what, reproject_status_name(status),
        reproject_status_name(expected), reproject_last_error_message());
  CHECK(status == REPROJECT_OK || strstr(reproject_last_error_message(), words) != NULL,
        "%s: message \"%s\" lacks \"%s\"", what, reproject_last_error_message(), words);
  printf("%-40s %s%s%s\n", what, reproject_status_name(status), status == REPROJECT_OK ? "" : ": ",
         status == REPROJECT_OK ? "" : reproject_last_error_message());
}

static void format_errors(void) {
  const ColorCase* rgba8 = &kColors[1];
  const ColorCase* srgb = &kColors[2];
  const DepthCase* d24s8 = &kDepths[3];
  const DepthCase* d16 = &kDepths[2];
  const DepthCase* packed = &kDepths[5];
  const reproject_source_buffers good = source_buffers(rgba8, d24s8);
  const reproject_target_buffers good_target = target_buffers(&fmt_c, rgba8, d24s8);
  reproject_source_buffers s;
  reproject_target_buffers t;

  fill_formats(rgba8, d24s8);
  s = good;
  t = good_target;
  expect_refused(&s, &t, REPROJECT_OK, "ok", "rgba8 + unorm24_s8 (control)");

  /* Unknown format values: refused before any cast (256 + 1 would wrap onto rgba8 in 8 bits). */
  s.pixels.format = 4;
  expect_refused(&s, &t, REPROJECT_INVALID_OPTION, "pixels.format 4 is not a known colour format", "colour format 4");
  s.pixels.format = 256 + REPROJECT_COLOR_RGBA8;
  expect_refused(&s, &t, REPROJECT_INVALID_OPTION, "not a known colour format", "colour format 257");
  s.pixels.format = -1;
  expect_refused(&s, &t, REPROJECT_INVALID_OPTION, "not a known colour format", "colour format -1");
  s = good;
  t.pixels.format = 256 + REPROJECT_COLOR_RGBA8;
  expect_refused(&s, &t, REPROJECT_INVALID_OPTION, "target pixels.format 257", "target colour format 257");
  t = good_target;
  s.depth_buffer.format = 5;
  expect_refused(&s, &t, REPROJECT_INVALID_OPTION, "depth_buffer.format 5 is not a known depth format", "depth format 5");
  s.depth_buffer.format = 256 + REPROJECT_DEPTH_FORMAT_UNORM24_S8;
  expect_refused(&s, &t, REPROJECT_INVALID_OPTION, "not a known depth format", "depth format 258");
  s = good;
  t.depth_buffer.format = 256 + REPROJECT_DEPTH_FORMAT_UNORM24_S8;
  expect_refused(&s, &t, REPROJECT_INVALID_OPTION, "target depth_buffer.format 258", "target depth format 258");
  t = good_target;
  s.color.layout = 256 + REPROJECT_LAYOUT_PLANAR;
  expect_refused(&s, &t, REPROJECT_INVALID_OPTION, "color.layout 256", "colour layout 256");
  s = good;

  /* reserved fields must be 0 (so that a later version may use them). */
  s.pixels.reserved = 12345;
  expect_refused(&s, &t, REPROJECT_INVALID_OPTION, "pixels.reserved is 12345; it must be 0", "source pixels.reserved");
  s = good;
  s.depth_buffer.reserved = -7;
  expect_refused(&s, &t, REPROJECT_INVALID_OPTION, "depth_buffer.reserved is -7", "source depth_buffer.reserved");
  s = good;
  t.pixels.reserved = 99;
  expect_refused(&s, &t, REPROJECT_INVALID_OPTION, "target pixels.reserved is 99", "target pixels.reserved");
  t = good_target;
  t.depth_buffer.reserved = 1;
  expect_refused(&s, &t, REPROJECT_INVALID_OPTION, "target depth_buffer.reserved is 1", "target depth_buffer.reserved");
  t = good_target;

  /* Target formats unlike the source's. */
  t.pixels.format = REPROJECT_COLOR_RGBA8_SRGB;
  expect_refused(&s, &t, REPROJECT_SIZE_MISMATCH, "format rgba8_srgb, the source's is rgba8", "target colour rgba8_srgb");
  t = target_buffers(&fmt_c, srgb, d24s8);
  t.color.layout = REPROJECT_LAYOUT_PLANAR;
  t.pixels.format = REPROJECT_COLOR_FLOAT32;
  t.pixels.data = NULL;
  t.color.channels = 3;
  t.color.plane[0] = t.color.plane[1] = t.color.plane[2] = mut_plane(c_out.color[0]);
  expect_refused(&s, &t, REPROJECT_SIZE_MISMATCH, "format float32, the source's is rgba8", "target colour float32");
  t = good_target;
  t.depth_buffer.format = REPROJECT_DEPTH_FORMAT_UNORM16;
  expect_refused(&s, &t, REPROJECT_SIZE_MISMATCH, "format unorm16, the source depth is unorm24_s8", "target depth unorm16");
  t = good_target;
  t.depth_buffer.data = NULL;
  t.depth = mut_plane(c_out.depth);
  expect_refused(&s, &t, REPROJECT_SIZE_MISMATCH, "the source depth is unorm24_s8", "target float depth, source D24S8");
  t = good_target;

  /* Two of a kind set: both depths, both colours, pixels without a format. */
  s.depth = plane(depth_in);
  expect_refused(&s, &t, REPROJECT_INVALID_OPTION, "both depth (a float plane) and depth_buffer", "source: both depths");
  s = good;
  t.depth = mut_plane(c_out.depth);
  expect_refused(&s, &t, REPROJECT_INVALID_OPTION, "both depth (a float plane) and depth_buffer", "target: both depths");
  t = good_target;
  s.color.channels = C;
  s.color.plane[0] = plane(color_in[0]);
  expect_refused(&s, &t, REPROJECT_INVALID_OPTION, "both color (float planes) and pixels (rgba8)", "source: both colours");
  s = good;
  s.pixels.format = REPROJECT_COLOR_FLOAT32;
  expect_refused(&s, &t, REPROJECT_INVALID_OPTION, "pixels.data is set but pixels.format is float32", "pixels, format float32");
  s = good;

  /* Strides and sizes, in bytes: the C++ validation's codes and messages. */
  s.pixels.stride = 4 * W - 1;
  expect_refused(&s, &t, REPROJECT_INVALID_STRIDE, "stride 811 is smaller than the row (812", "pixels stride 4 W - 1");
  s = good;
  s.depth_buffer.stride = 4 * W - 2;
  expect_refused(&s, &t, REPROJECT_INVALID_STRIDE, "bytes) (unorm24_s8)", "depth_buffer stride 4 W - 2");
  s = good;
  t.depth_buffer.stride = 4 * W - 4;
  expect_refused(&s, &t, REPROJECT_INVALID_STRIDE, "target depth_buffer", "target depth_buffer stride 4 W - 4");
  t = good_target;
  s = source_buffers(srgb, d16);
  t = target_buffers(&fmt_c, srgb, d16);
  t.depth_buffer.stride = 2 * W - 1; /* D16: 2 bytes a pixel, so 4 W - 1 would pass */
  expect_refused(&s, &t, REPROJECT_INVALID_STRIDE, "smaller than the row (406", "D16 stride 2 W - 1");
  s = good;
  t = good_target;
  s.pixels.height = H - 1;
  expect_refused(&s, &t, REPROJECT_SIZE_MISMATCH, "size 203x60, expected 203x61", "pixels height H - 1");
  s = good;
  s.pixels.data = NULL;
  expect_refused(&s, &t, REPROJECT_NULL_POINTER, "data is null", "pixels data NULL");
  s = good;

  /* The packed-linear range of a zeroed struct (0, 0) is refused. */
  s = source_buffers(rgba8, packed);
  t = target_buffers(&fmt_c, rgba8, packed);
  s.depth_buffer.linear_near = s.depth_buffer.linear_far = 0.0f;
  expect_refused(&s, &t, REPROJECT_INVALID_OPTION, "rgba8_packed_linear range [0, 0]", "packed linear range [0, 0]");

  /* Null arguments. */
  s = good;
  t = good_target;
  CHECK(reproject_warp_buffers(NULL, NULL, NULL, NULL, &t, NULL) == REPROJECT_NULL_POINTER, "null source");
  CHECK(strstr(reproject_last_error_message(), "reproject_warp_buffers") != NULL, "%s", reproject_last_error_message());
  CHECK(reproject_warp_pair_buffers(&s, NULL, NULL, NULL, &t, &t, NULL) == REPROJECT_NULL_POINTER, "null decoder");
  CHECK(strstr(reproject_last_error_message(), "reproject_warp_pair_buffers") != NULL, "%s",
        reproject_last_error_message());
  {
    /* Each entry point names itself and the first null argument, in the order of its parameters. */
    const reproject_source fs = source_of();
    reproject_target ft = target_of(&c_out);
    reproject_decoder d;
    reproject_parallax m;
    reproject_options o;
    good_arguments(&d, &m, REPROJECT_CENTRE_TO_RIGHT, &o);
    CHECK(reproject_warp(&fs, NULL, &m, NULL, &ft, NULL) == REPROJECT_NULL_POINTER, "warp: null decoder");
    CHECK(strcmp(reproject_last_error_message(), "reproject_warp: decoder is null (source, decoder, model, options "
                 "and target are required)") == 0, "%s", reproject_last_error_message());
    CHECK(reproject_warp(&fs, &d, &m, &o, NULL, NULL) == REPROJECT_NULL_POINTER, "warp: null target");
    CHECK(strstr(reproject_last_error_message(), "reproject_warp: target is null") != NULL, "%s",
          reproject_last_error_message());
    CHECK(reproject_warp_pair(&fs, &d, NULL, &o, &ft, &ft, NULL) == REPROJECT_NULL_POINTER, "pair: null model");
    CHECK(strcmp(reproject_last_error_message(), "reproject_warp_pair: centre_to_right is null (centre, decoder, "
                 "model, options, left and right are required)") == 0, "%s", reproject_last_error_message());
    CHECK(reproject_warp_pair(&fs, &d, &m, &o, &ft, NULL, NULL) == REPROJECT_NULL_POINTER, "pair: null right");
    CHECK(strstr(reproject_last_error_message(), "reproject_warp_pair: right is null") != NULL, "%s",
          reproject_last_error_message());
    CHECK(reproject_warp_buffers(&s, &d, &m, NULL, &t, NULL) == REPROJECT_NULL_POINTER, "buffers: null options");
    CHECK(strcmp(reproject_last_error_message(), "reproject_warp_buffers: options is null (source, decoder, model, "
                 "options and target are required)") == 0, "%s", reproject_last_error_message());
    CHECK(reproject_warp_pair_buffers(&s, &d, &m, &o, NULL, &t, NULL) == REPROJECT_NULL_POINTER, "pair: null left");
    CHECK(strcmp(reproject_last_error_message(), "reproject_warp_pair_buffers: left is null (centre, decoder, model, "
                 "options, left and right are required)") == 0, "%s", reproject_last_error_message());
  }

  /* Names of the format values. */
  CHECK(strcmp(reproject_color_format_name(REPROJECT_COLOR_RGBA8_SRGB), "rgba8_srgb") == 0, "colour format name");
  CHECK(strcmp(reproject_color_format_name(REPROJECT_COLOR_RGBA16F), "rgba16f") == 0, "colour format name");
  CHECK(strcmp(reproject_color_format_name(4), "unknown") == 0, "unknown colour format name");
  CHECK(strcmp(reproject_depth_format_name(REPROJECT_DEPTH_FORMAT_S8_UNORM24), "s8_unorm24") == 0, "depth format name");
  CHECK(strcmp(reproject_depth_format_name(REPROJECT_DEPTH_FORMAT_RGBA8_PACKED_LINEAR), "rgba8_packed_linear") == 0,
        "depth format name");
  CHECK(strcmp(reproject_depth_format_name(-1), "unknown") == 0, "unknown depth format name");

  /* Every name function answers an unknown value as the C++ to_string does: "unknown", both for a
   * value inside the enums' 0..255 that no constant has and for one beyond it (256 + 1 must not
   * wrap onto 1's name). */
  CHECK(strcmp(reproject_status_name(REPROJECT_CANCELLED), "cancelled") == 0, "status name");
  CHECK(strcmp(reproject_status_name(REPROJECT_OUT_OF_MEMORY), "out_of_memory") == 0, "status name");
  CHECK(strcmp(reproject_status_name(REPROJECT_OUT_OF_MEMORY + 1), "unknown") == 0, "unknown status name");
  CHECK(strcmp(reproject_status_name(-1), "unknown") == 0, "negative status name");
  CHECK(strcmp(reproject_status_name(256 + REPROJECT_NULL_POINTER), "unknown") == 0, "status name beyond 255");
  CHECK(strcmp(reproject_method_name(REPROJECT_METHOD_EXACT), "exact") == 0, "method name");
  CHECK(strcmp(reproject_method_name(REPROJECT_METHOD_EXACT + 1), "unknown") == 0, "unknown method name");
  CHECK(strcmp(reproject_arch_name(REPROJECT_ARCH_NEON), "neon") == 0, "arch name");
  CHECK(strcmp(reproject_arch_name(REPROJECT_ARCH_NEON + 1), "unknown") == 0, "unknown arch name");
  CHECK(strcmp(reproject_arch_name(REPROJECT_ARCH_AUTO), "unknown") == 0, "REPROJECT_ARCH_AUTO names no arch");
  CHECK(strcmp(reproject_encoding_name(REPROJECT_DEPTH_DISPARITY), "disparity") == 0, "encoding name");
  CHECK(strcmp(reproject_encoding_name(255), "unknown") == 0, "unknown encoding name");
  CHECK(strcmp(reproject_encoding_name(256 + REPROJECT_DEPTH_STANDARD), "unknown") == 0, "encoding name beyond 255");
  CHECK(strcmp(reproject_color_format_name(256 + REPROJECT_COLOR_RGBA8), "unknown") == 0, "colour name beyond 255");
  CHECK(strcmp(reproject_depth_format_name(1000), "unknown") == 0, "depth format name beyond 255");
}

/* Every method, one eye and the pair, at threads 1 and 2 and through the job-system hook: the
 * C call's outputs (colour, depth, status, source_x, the padding between rows) equal the C++
 * call's byte for byte. Returns the number of identical runs. */
static int formats_match_cxx(const ColorCase* cf, const DepthCase* df, int arch, int* runs) {
  static const int kThreads[] = {1, 2, 0}; /* 0: the caller's job system */
  reproject_decoder decoder;
  reproject_parallax model, centre_to_right;
  const int linear = df->format == REPROJECT_DEPTH_FORMAT_RGBA8_PACKED_LINEAR;
  int method, t, pair, same = 0;
  reproject_source_buffers source;
  RefView ref_source, ref_right, ref_left;

  if (linear) {
    CHECK(reproject_decoder_linear(&decoder) == REPROJECT_OK, "%s", reproject_last_error_message());
  } else {
    CHECK(reproject_decoder_from_near_far(REPROJECT_DEPTH_STANDARD, kNear, kFar, &decoder) == REPROJECT_OK, "%s",
          reproject_last_error_message());
  }
  reproject_parallax_from_stereo(0.03, 4.0, W, REPROJECT_LEFT_TO_RIGHT, &model);
  reproject_parallax_from_stereo(0.03, 4.0, W, REPROJECT_CENTRE_TO_RIGHT, &centre_to_right);
  fill_formats(cf, df);
  source = source_buffers(cf, df);
  ref_source = ref_view(&fmt_in, cf, df);
  ref_right = ref_view(&fmt_cpp, cf, df);
  ref_left = ref_view(&fmt_cpp_left, cf, df);

  for (method = REPROJECT_METHOD_SCANLINE; method <= REPROJECT_METHOD_EXACT; ++method) {
    for (t = 0; t < 3; ++t) {
      for (pair = 0; pair <= 1; ++pair) {
        reproject_options options;
        reproject_parallel_for jobs;
        reproject_target_buffers target, left;
        reproject_status status;
        int identical;
        memset(&fmt_c, 0xA5, sizeof fmt_c);
        memset(&fmt_cpp, 0xA5, sizeof fmt_cpp);
        memset(&fmt_c_left, 0xA5, sizeof fmt_c_left);
        memset(&fmt_cpp_left, 0xA5, sizeof fmt_cpp_left);
        reproject_options_init(&options);
        options.method = method;
        options.arch = arch;
        options.threads = kThreads[t] > 0 ? kThreads[t] : 1;
        jobs.context = &counting_runs;
        jobs.run = serial_run;
        target = target_buffers(&fmt_c, cf, df);
        left = target_buffers(&fmt_c_left, cf, df);
        status = pair ? reproject_warp_pair_buffers(&source, &decoder, &centre_to_right, &options, &left, &target,
                                                    kThreads[t] > 0 ? NULL : &jobs)
                      : reproject_warp_buffers(&source, &decoder, &model, &options, &target,
                                               kThreads[t] > 0 ? NULL : &jobs);
        CHECK(status == REPROJECT_OK, "%s x %s %s: %s", cf->name, df->name, reproject_method_name(method),
              reproject_last_error_message());
        CHECK(reference_warp_buffers(&ref_source, pair ? &ref_left : NULL, &ref_right, W, H, linear, kNear, kFar,
                                     method, arch, kThreads[t]) == 0,
              "%s x %s: reference failed", cf->name, df->name);
        /* written at all: mostly hits, and a pixel's colour no longer the fill pattern (every
         * pixel's colour is written with the default hole fill and edge mode) */
        CHECK(hits(fmt_c.status) > N / 2 &&
                  !filled(bytes_of(fmt_c.color[0]) + 30 * color_stride(cf) + 40 * cf->bytes, cf->bytes),
              "%s x %s %s: nothing written", cf->name, df->name, reproject_method_name(method));
        identical = memcmp(&fmt_c, &fmt_cpp, sizeof fmt_c) == 0 &&
                    (!pair || memcmp(&fmt_c_left, &fmt_cpp_left, sizeof fmt_c_left) == 0);
        CHECK(identical, "%s x %s%s %s %s: C and C++ outputs differ", cf->name, df->name, df->plane ? " (plane)" : "",
              reproject_method_name(method), pair ? "pair" : "single");
        same += identical;
        ++*runs;
      }
    }
  }
  return same;
}

/* The host's allocator through the C interface: a counting one, and one that has nothing. */
static long c_allocations = 0, c_outstanding = 0, c_refuse = 0;
/* C99 has no aligned allocation: malloc more, align by hand, keep malloc's pointer just before. */
static void* c_allocate(void* user, size_t size, size_t alignment) {
  unsigned char* raw;
  uintptr_t start;
  (void)user;
  if (c_refuse) return NULL;
  raw = (unsigned char*)malloc(size + alignment + sizeof(void*));
  if (raw == NULL) return NULL;
  start = ((uintptr_t)(raw + sizeof(void*)) + alignment - 1) & ~(uintptr_t)(alignment - 1);
  ((void**)start)[-1] = raw;
  ++c_allocations;
  c_outstanding += (long)size;
  return (void*)start;
}
static void c_deallocate(void* user, void* pointer, size_t size, size_t alignment) {
  (void)user;
  (void)alignment;
  c_outstanding -= (long)size;
  free(((void**)pointer)[-1]);
}

static void allocator_checks(const reproject_source* source, const reproject_decoder* decoder,
                             const reproject_parallax* model) {
  reproject_allocator host, half;
  reproject_options options;
  reproject_target target = target_of(&c_out);
  reproject_status status;
  host.allocate = c_allocate;
  host.deallocate = c_deallocate;
  host.user = NULL;
  half = host;
  half.deallocate = NULL;
  reproject_options_init(&options);
  options.threads = 2;
  reproject_release_memory();
  CHECK(reproject_memory_in_use() == 0, "memory in use after release: %lu", (unsigned long)reproject_memory_in_use());
  CHECK(reproject_set_allocator(&half) == REPROJECT_INVALID_OPTION, "an allocator without deallocate accepted");
  CHECK(reproject_set_allocator(&host) == REPROJECT_OK, "%s", reproject_last_error_message());
  CHECK(reproject_warp(source, decoder, model, &options, &target, NULL) == REPROJECT_OK, "%s",
        reproject_last_error_message());
  CHECK(c_allocations > 0 && c_outstanding > 0 && (size_t)c_outstanding == reproject_memory_in_use(),
        "the host's allocator: %ld allocations, %ld bytes out, the library says %lu", c_allocations, c_outstanding,
        (unsigned long)reproject_memory_in_use());
  CHECK(reproject_set_allocator(NULL) == REPROJECT_INVALID_OPTION, "set_allocator accepted while memory is held");
  reproject_release_memory();
  CHECK(c_outstanding == 0, "%ld bytes still out after reproject_release_memory()", c_outstanding);
  c_refuse = 1;
  status = reproject_warp(source, decoder, model, &options, &target, NULL);
  CHECK(status == REPROJECT_OUT_OF_MEMORY, "warp with no memory returned %s: %s", reproject_status_name(status),
        reproject_last_error_message());
  CHECK(strcmp(reproject_status_name(REPROJECT_OUT_OF_MEMORY), "out_of_memory") == 0, "status name");
  c_refuse = 0;
  reproject_release_memory();
  CHECK(c_outstanding == 0, "%ld bytes still out after a failed call", c_outstanding);
  CHECK(reproject_set_allocator(NULL) == REPROJECT_OK, "%s", reproject_last_error_message());
  printf("allocator: %ld allocations through the host's, all given back; no memory: REPROJECT_OUT_OF_MEMORY\n",
         c_allocations);
}

int main(void) {
  reproject_decoder decoder;
  reproject_parallax model, centre_to_right;
  reproject_options options;
  reproject_source source;
  reproject_target target, left;
  const float* planes_in[C];
  float* planes_out[C];
  float* planes_left[C];
  int method, c;
  const int arch = reproject_selected_arch();

  CHECK(reproject_abi_version() == REPROJECT_C_ABI_VERSION, "abi version %d", (int)reproject_abi_version());
  /* REPROJECT_EXPECTED_VERSION: the CMake project's version, passed by tests/CMakeLists.txt. */
  CHECK(reproject_version() != NULL && strcmp(reproject_version(), REPROJECT_EXPECTED_VERSION) == 0,
        "reproject_version() is '%s', the CMake project's version '%s'",
        reproject_version() ? reproject_version() : "(null)", REPROJECT_EXPECTED_VERSION);
  CHECK(reproject_arch_supported(REPROJECT_ARCH_SCALAR) == 1, "scalar is always supported");
  CHECK(reproject_arch_supported(arch) == 1, "the selected arch %s is supported", reproject_arch_name(arch));
  printf("selected arch: %s\n", reproject_arch_name(arch));

  CHECK(reproject_decoder_from_near_far(REPROJECT_DEPTH_STANDARD, kNear, kFar, &decoder) == REPROJECT_OK, "%s",
        reproject_last_error_message());
  CHECK(reproject_parallax_from_stereo(0.03, 4.0, W, REPROJECT_LEFT_TO_RIGHT, &model) == REPROJECT_OK, "%s",
        reproject_last_error_message());
  CHECK(reproject_parallax_from_stereo(0.03, 4.0, W, REPROJECT_CENTRE_TO_RIGHT, &centre_to_right) == REPROJECT_OK,
        "%s", reproject_last_error_message());
  {
    /* A rig whose interaxial spans 3 % of the convergence plane's width is the model above. */
    reproject_parallax rig, relative;
    const double fov = 1.2, interaxial = 0.03 * 2.0 * 4.0 * tan(0.6);
    CHECK(reproject_parallax_from_rig(interaxial, 4.0, fov, W, REPROJECT_LEFT_TO_RIGHT, &rig) == REPROJECT_OK, "%s",
          reproject_last_error_message());
    CHECK(fabsf(rig.a - model.a) <= 1e-5f * fabsf(model.a) && fabsf(rig.b - model.b) <= 1e-5f * fabsf(model.b),
          "rig a %g b %g, stereo a %g b %g", (double)rig.a, (double)rig.b, (double)model.a, (double)model.b);
    /* Relative inverse depth: 4 % of the width from v = 0 to 1, zero at v = 0.25. */
    CHECK(reproject_parallax_from_relative(0.04, 0.25, W, REPROJECT_LEFT_TO_RIGHT, &relative) == REPROJECT_OK, "%s",
          reproject_last_error_message());
    CHECK(relative.a == (float)(0.04 * W * 0.25) && relative.b == (float)(-0.04 * W), "relative a %g b %g",
          (double)relative.a, (double)relative.b);
  }
  make_frame(&decoder);
  source = source_of();
  allocator_checks(&source, &decoder, &model);
  for (c = 0; c < C; ++c) {
    planes_in[c] = color_in[c];
    planes_out[c] = cpp_out.color[c];
    planes_left[c] = cpp_left.color[c];
  }

  /* Every method, single eye and pair: the C interface equals the C++ API bit for bit. */
  for (method = REPROJECT_METHOD_SCANLINE; method <= REPROJECT_METHOD_EXACT; ++method) {
    int pair;
    for (pair = 0; pair <= 1; ++pair) {
      reproject_status status;
      memset(&c_out, 0xA5, sizeof c_out);
      memset(&cpp_out, 0xA5, sizeof cpp_out);
      memset(&c_left, 0xA5, sizeof c_left);
      memset(&cpp_left, 0xA5, sizeof cpp_left);
      reproject_options_init(&options);
      options.method = method;
      options.arch = arch;
      target = target_of(&c_out);
      left = target_of(&c_left);
      status = pair ? reproject_warp_pair(&source, &decoder, &centre_to_right, &options, &left, &target, NULL)
                    : reproject_warp(&source, &decoder, &model, &options, &target, NULL);
      CHECK(status == REPROJECT_OK, "%s: %s", reproject_method_name(method), reproject_last_error_message());
      CHECK(reference_warp(planes_in, C, depth_in, W, H, kNear, kFar, method, arch, planes_out, cpp_out.depth,
                           cpp_out.status, cpp_out.source_x, pair, planes_left) == 0,
            "reference failed");
      CHECK(same_output(&c_out, &cpp_out), "%s%s: C and C++ outputs differ", reproject_method_name(method),
            pair ? " pair (right)" : "");
      if (pair) {
        /* The reference writes only the left colour; compare that. */
        CHECK(memcmp(c_left.color, cpp_left.color, sizeof c_left.color) == 0, "%s pair (left colour) differs",
              reproject_method_name(method));
      }
      printf("%-8s %-6s C == C++ bit for bit: %s\n", reproject_method_name(method), pair ? "pair" : "single",
             same_output(&c_out, &cpp_out) ? "yes" : "NO");
    }
  }

  /* The caller's job system: used, and the same result. */
  {
    reproject_parallel_for jobs;
    jobs.context = &job_runs;
    jobs.run = serial_run;
    reproject_options_init(&options);
    options.arch = arch;
    target = target_of(&c_out);
    CHECK(reproject_warp(&source, &decoder, &model, &options, &target, &jobs) == REPROJECT_OK, "%s",
          reproject_last_error_message());
    CHECK(job_runs >= 1, "the job system was not used");
    CHECK(reference_warp(planes_in, C, depth_in, W, H, kNear, kFar, REPROJECT_METHOD_EXACT, arch, planes_out,
                         cpp_out.depth, cpp_out.status, cpp_out.source_x, 0, planes_left) == 0,
          "reference failed");
    CHECK(same_output(&c_out, &cpp_out), "job system: outputs differ");
    printf("job system hook: %d run(s), same output\n", job_runs);
  }

  /* Options from an older, shorter header: the fields it lacks take their defaults. */
  {
    reproject_options_init(&options);
    options.struct_size = (uint32_t)offsetof(reproject_options, arch);
    options.arch = 99; /* beyond struct_size: not read */
    target = target_of(&c_out);
    CHECK(reproject_warp(&source, &decoder, &model, &options, &target, NULL) == REPROJECT_OK,
          "short options: %s", reproject_last_error_message());
    options.struct_size = 0;
    CHECK(reproject_warp(&source, &decoder, &model, &options, &target, NULL) == REPROJECT_INVALID_OPTION,
          "struct_size 0 must be refused");
  }

  /* Errors: a code and the library's message, never a crash. */
  {
    reproject_decoder bad;
    reproject_parallax bad_model;
    reproject_status status;
    status = reproject_decoder_from_near_far(REPROJECT_DEPTH_STANDARD, -1.0, 10.0, &bad);
    CHECK(status == REPROJECT_INVALID_DECODER, "near -1: status %d", (int)status);
    CHECK(strstr(reproject_last_error_message(), "near") != NULL, "message: %s", reproject_last_error_message());
    printf("near -1: %s: %s\n", reproject_status_name(status), reproject_last_error_message());
    reproject_options_init(&options);
    target = target_of(&c_out);
    status = reproject_warp(&source, &bad, &model, &options, &target, NULL);
    CHECK(status == REPROJECT_INVALID_DECODER, "warp with a bad decoder: %d", (int)status);

    status = reproject_parallax_from_stereo(0.03, NAN, W, REPROJECT_LEFT_TO_RIGHT, &bad_model);
    CHECK(status == REPROJECT_INVALID_MODEL, "NaN convergence: %d", (int)status);

    /* Values beyond the C++ enums' uint8_t must not wrap onto valid ones (257 would be 1). */
    {
      const float projection[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 1, 0, 0, -0.1f, 0};
      reproject_parallax wrapped_model;
      status = reproject_decoder_from_near_far(REPROJECT_DEPTH_STANDARD + 256, 1.0, 10.0, &bad);
      CHECK(status == REPROJECT_INVALID_DECODER, "encoding 257: status %d", (int)status);
      CHECK(strstr(reproject_last_error_message(), "depth encoding 257") != NULL, "message: %s",
            reproject_last_error_message());
      CHECK(reproject_warp(&source, &bad, &model, &options, &target, NULL) == REPROJECT_INVALID_DECODER,
            "warp with encoding 257 must be refused");
      CHECK(strstr(reproject_last_error_message(), "depth encoding 257") != NULL, "warp message: %s",
            reproject_last_error_message());
      CHECK(isnan(reproject_decoder_inverse_depth(&bad, 0.5f)), "encoding 257 decodes to NaN");
      CHECK(reproject_decoder_from_d3d_projection(projection, REPROJECT_DEPTH_STANDARD + 256, &bad) ==
                REPROJECT_INVALID_DECODER, "d3d projection with encoding 257 must be refused");
      CHECK(reproject_decoder_from_gl_projection(projection, -1, &bad) == REPROJECT_INVALID_DECODER,
            "gl projection with encoding -1 must be refused");
      status = reproject_parallax_from_stereo(0.03, 4.0, W, REPROJECT_RIGHT_TO_LEFT + 256, &wrapped_model);
      CHECK(status == REPROJECT_INVALID_MODEL, "direction 257: status %d", (int)status);
      CHECK(strstr(reproject_last_error_message(), "eye direction 257") != NULL, "message: %s",
            reproject_last_error_message());
      CHECK(reproject_parallax_from_physical(0.065, 1.0, 4.0, W, -1, &wrapped_model) == REPROJECT_INVALID_MODEL,
            "direction -1 must be refused");
      CHECK(reproject_parallax_from_disparity(REPROJECT_LEFT_TO_RIGHT + 256, &wrapped_model) == REPROJECT_INVALID_MODEL,
            "disparity direction 256 must be refused");
      CHECK(reproject_parallax_from_rig(0.065, 1.95, 0.0, W, REPROJECT_LEFT_TO_RIGHT, &wrapped_model) ==
                REPROJECT_INVALID_MODEL, "a rig with no field of view must be refused");
      CHECK(reproject_parallax_from_relative(0.03, 1.5, W, REPROJECT_LEFT_TO_RIGHT, &wrapped_model) ==
                REPROJECT_INVALID_MODEL, "a relative zero plane of 1.5 must be refused");
      CHECK(strstr(reproject_last_error_message(), "zero-parallax plane") != NULL, "message: %s",
            reproject_last_error_message());
    }

    target.color.plane[1].stride = W - 1;
    status = reproject_warp(&source, &decoder, &model, &options, &target, NULL);
    CHECK(status == REPROJECT_INVALID_STRIDE, "short stride: %d (%s)", (int)status, reproject_last_error_message());
    printf("short stride: %s: %s\n", reproject_status_name(status), reproject_last_error_message());

    target = target_of(&c_out);
    target.color.plane[0].data = NULL;
    status = reproject_warp(&source, &decoder, &model, &options, &target, NULL);
    CHECK(status == REPROJECT_NULL_POINTER, "null colour: %d", (int)status);
    CHECK(reproject_warp(NULL, &decoder, &model, &options, &target, NULL) == REPROJECT_NULL_POINTER, "null source");

    options.method = 17;
    target = target_of(&c_out);
    CHECK(reproject_warp(&source, &decoder, &model, &options, &target, NULL) == REPROJECT_INVALID_OPTION,
          "method 17 must be refused");
    CHECK(strcmp(reproject_status_name(REPROJECT_ALIASING), "aliasing") == 0, "status name");
  }

  /* Engine formats: every colour format x depth format, C == C++ byte for byte. */
  {
    int cfi, dfi, runs = 0, same = 0;
    for (cfi = 0; cfi < (int)(sizeof kColors / sizeof kColors[0]); ++cfi) {
      for (dfi = 0; dfi < (int)(sizeof kDepths / sizeof kDepths[0]); ++dfi) {
        int pair_runs = 0;
        const int pair_same = formats_match_cxx(&kColors[cfi], &kDepths[dfi], arch, &pair_runs);
        printf("%-10s x %-19s %-6s: %d/%d runs C == C++ byte for byte\n", kColors[cfi].name, kDepths[dfi].name,
               kDepths[dfi].plane ? "plane" : "buffer", pair_same, pair_runs);
        runs += pair_runs;
        same += pair_same;
      }
    }
    CHECK(counting_runs > 0, "the job system was not used by the _buffers calls");
    printf("engine formats: %d/%d runs byte-identical (4 colour x 6 depth x 5 methods x {1, 2 threads, job hook} x "
           "{single, pair}); job hook ran %d time(s)\n",
           same, runs, counting_runs);
    format_errors();
  }

  /* The decoder's projection-matrix factory reads back near and far (D3D standard depth). */
  {
    const float f = 100.0f, n = 0.5f;
    float m[16] = {0};
    reproject_decoder from_matrix;
    m[0] = 1.0f;
    m[5] = 1.0f;
    m[10] = f / (f - n);
    m[11] = 1.0f;
    m[14] = -n * f / (f - n);
    CHECK(reproject_decoder_from_d3d_projection(m, REPROJECT_DEPTH_STANDARD, &from_matrix) == REPROJECT_OK, "%s",
          reproject_last_error_message());
    CHECK(fabs(from_matrix.near_plane - 0.5) < 1e-4 && fabs(from_matrix.far_plane - 100.0) < 1e-1,
          "near %g far %g", from_matrix.near_plane, from_matrix.far_plane);
    CHECK(fabsf(reproject_decoder_linear_depth(&from_matrix, 0.0f) - 0.5f) < 1e-4f, "z at d = 0");
  }

  if (failures != 0) {
    fprintf(stderr, "%d check(s) failed\n", failures);
    return 1;
  }
  printf("all C interface checks passed\n");
  return 0;
}
