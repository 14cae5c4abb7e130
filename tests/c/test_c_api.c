/* The C interface, compiled as C99: a frame reprojected through reproject.h must equal the C++
 * API's result (c_reference.cpp) bit for bit, for every method, single eye and pair; plus the
 * error codes and messages, the job-system hook and the versioned options. Prints one line per
 * check; exits non-zero on the first failure. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

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
  CHECK(reproject_arch_supported(REPROJECT_ARCH_SCALAR) == 1, "scalar is always supported");
  CHECK(reproject_arch_supported(arch) == 1, "the selected arch %s is supported", reproject_arch_name(arch));
  printf("selected arch: %s\n", reproject_arch_name(arch));

  CHECK(reproject_decoder_from_near_far(REPROJECT_DEPTH_STANDARD, kNear, kFar, &decoder) == REPROJECT_OK, "%s",
        reproject_last_error_message());
  CHECK(reproject_parallax_from_stereo(0.03, 4.0, W, REPROJECT_LEFT_TO_RIGHT, &model) == REPROJECT_OK, "%s",
        reproject_last_error_message());
  CHECK(reproject_parallax_from_stereo(0.03, 4.0, W, REPROJECT_CENTRE_TO_RIGHT, &centre_to_right) == REPROJECT_OK,
        "%s", reproject_last_error_message());
  make_frame(&decoder);
  source = source_of();
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
