/* reproject's C interface: the library's reprojection, depth decoder, parallax model, arch queries
 * and job-system hook, for C and for every language that binds through a C ABI (C#, Rust, Zig, ...).
 * A thin layer over the C++ API of reproject.hpp: the same computation, bit for bit.
 *
 * Conventions
 *  - Plain structs of pointers, sizes and strides; enums are int32_t values (the REPROJECT_*
 *    constants below), never C enum types, whose size the compiler chooses.
 *  - Every call that can fail returns a reproject_status (REPROJECT_OK = 0, else the code of the
 *    C++ StatusCode). The message of the calling thread's last failure is
 *    reproject_last_error_message(). Nothing is thrown or longjmp'd across this interface.
 *  - Pointers: each declaration below says which arguments may be NULL; every other pointer
 *    argument is required (NULL is refused with REPROJECT_NULL_POINTER, nothing written). Inside
 *    the structs, a source buffer whose size or format is set must have data (REPROJECT_NULL_POINTER);
 *    an output whose data is NULL is not written (colour is required). A view's rows, (height - 1)
 *    strides plus one row, must be an offset the library can form and must end inside the address
 *    space: larger strides are refused (REPROJECT_INVALID_STRIDE), never wrapped.
 *  - Strides count elements (floats or bytes), not bytes, as in the C++ views; the engine-format
 *    views (reproject_pixels, reproject_depth_buffer) count bytes, as their C++ twins do.
 *  - Two pairs of entry points: reproject_warp / reproject_warp_pair take float colour and depth
 *    (reproject_source, reproject_target); reproject_warp_buffers / reproject_warp_pair_buffers
 *    take colour and depth in any format, float included (reproject_source_buffers,
 *    reproject_target_buffers). Both compute the same thing on float input.
 *
 * ABI
 *  - Stable: the names and values of the REPROJECT_* constants, the function signatures, and the
 *    layout of every struct except reproject_options. New constants and functions are only added.
 *  - reproject_options may grow at its end in later versions: its first field, struct_size, says
 *    how much of it the caller knows. Always fill it with reproject_options_init() (which sets
 *    struct_size to this header's sizeof and every field to the C++ default) and then change the
 *    fields you need; the library reads only the first struct_size bytes and takes the defaults
 *    for fields beyond them, so a program built against an older header keeps working (and a
 *    struct_size larger than the library knows, from a newer header, has its unknown tail ignored).
 *  - reproject_abi_version() returns REPROJECT_C_ABI_VERSION of the library that is linked; it
 *    changes only if one of the stable items above ever has to change.
 */
#ifndef REPROJECT_REPROJECT_H
#define REPROJECT_REPROJECT_H

#include <stddef.h>
#include <stdint.h>

#include "reproject/memory.h"
#include "reproject/status.h"

#ifdef __cplusplus
extern "C" {
#endif

#define REPROJECT_C_ABI_VERSION 1

/* Methods (C++ Method). */
#define REPROJECT_METHOD_SCANLINE 0
#define REPROJECT_METHOD_MARCH16 1
#define REPROJECT_METHOD_SINGLE 2
#define REPROJECT_METHOD_SECANT 3
#define REPROJECT_METHOD_EXACT 4

/* Instruction sets (C++ Arch); REPROJECT_ARCH_AUTO: selected_arch(). */
#define REPROJECT_ARCH_AUTO (-1)
#define REPROJECT_ARCH_SCALAR 0
#define REPROJECT_ARCH_SSE 1
#define REPROJECT_ARCH_AVX2 2
#define REPROJECT_ARCH_AVX512 3
#define REPROJECT_ARCH_NEON 4 /* AArch64 */

/* Per-pixel status bytes (C++ PixelStatus). */
#define REPROJECT_PIXEL_HIT 0
#define REPROJECT_PIXEL_HOLE 1
#define REPROJECT_PIXEL_OUTSIDE 2
#define REPROJECT_PIXEL_CLIPPED 3

/* Hole fill and edge modes (C++ HoleFill, EdgeMode). */
#define REPROJECT_FILL_BACKGROUND 0
#define REPROJECT_FILL_FOREGROUND 1
#define REPROJECT_FILL_NONE 2
#define REPROJECT_EDGE_CLAMP 0
#define REPROJECT_EDGE_NONE 1
#define REPROJECT_EDGE_BLACK 2
#define REPROJECT_EDGE_MIRROR 3

/* Depth encodings (C++ DepthEncoding). */
#define REPROJECT_DEPTH_LINEAR 0
#define REPROJECT_DEPTH_STANDARD 1
#define REPROJECT_DEPTH_GL_NDC 2
#define REPROJECT_DEPTH_REVERSED 3
#define REPROJECT_DEPTH_REVERSED_INFINITE 4
#define REPROJECT_DEPTH_INFINITE 5
#define REPROJECT_DEPTH_DISPARITY 6

/* Eye directions (C++ EyeDirection). */
#define REPROJECT_LEFT_TO_RIGHT 0
#define REPROJECT_RIGHT_TO_LEFT 1
#define REPROJECT_CENTRE_TO_LEFT 2
#define REPROJECT_CENTRE_TO_RIGHT 3

/* Colour layouts (C++ ColorLayout). */
#define REPROJECT_LAYOUT_PLANAR 0
#define REPROJECT_LAYOUT_INTERLEAVED_RGBA 1

/* Colour formats (C++ ColorFormat). FLOAT32 is the float planes of reproject_color; the others
 * are packed interleaved R, G, B, A pixels (reproject_pixels): RGBA8 (UNORM bytes), RGBA8_SRGB
 * (the same bytes, R, G, B sRGB-encoded: blended in linear light), RGBA16F (IEEE halves, 8 bytes a
 * pixel). docs/BEHAVIOUR.md "Pixel formats" says how each is read, blended and stored. */
#define REPROJECT_COLOR_FLOAT32 0
#define REPROJECT_COLOR_RGBA8 1
#define REPROJECT_COLOR_RGBA8_SRGB 2
#define REPROJECT_COLOR_RGBA16F 3

/* Depth formats (C++ DepthFormat): how a depth buffer stores the value the decoder decodes.
 * FLOAT32: a float; UNORM16 (D16): u / 65535; UNORM24_S8: a 32-bit word, depth in bits 0-23,
 * stencil in bits 24-31 (D3D / Vulkan D24_UNORM_S8_UINT); S8_UNORM24: stencil in bits 0-7, depth in
 * bits 8-31 (OpenGL GL_UNSIGNED_INT_24_8); RGBA8_PACKED_LINEAR: linear depth packed into R, G, B
 * over the buffer's [linear_near, linear_far] (use it with reproject_decoder_linear). Output depth
 * keeps the stencil byte (or A) of the source pixel it came from. */
#define REPROJECT_DEPTH_FORMAT_FLOAT32 0
#define REPROJECT_DEPTH_FORMAT_UNORM16 1
#define REPROJECT_DEPTH_FORMAT_UNORM24_S8 2
#define REPROJECT_DEPTH_FORMAT_S8_UNORM24 3
#define REPROJECT_DEPTH_FORMAT_RGBA8_PACKED_LINEAR 4

/* A plane: row y starts at data + y * stride (elements). */
typedef struct reproject_plane {
  const float* data;
  int32_t width;
  int32_t height;
  int64_t stride;
} reproject_plane;

typedef struct reproject_mut_plane {
  float* data;
  int32_t width;
  int32_t height;
  int64_t stride;
} reproject_mut_plane;

typedef struct reproject_byte_plane {
  uint8_t* data;
  int32_t width;
  int32_t height;
  int64_t stride;
} reproject_byte_plane;

/* Colour: planar (1..4 planes) or one interleaved RGBA plane (channels = 4, plane[0] only). */
typedef struct reproject_color {
  int32_t layout;
  int32_t channels;
  reproject_plane plane[4];
} reproject_color;

typedef struct reproject_mut_color {
  int32_t layout;
  int32_t channels;
  reproject_mut_plane plane[4];
} reproject_mut_color;

typedef struct reproject_source {
  reproject_color color;
  reproject_plane depth;
} reproject_source;

/* Colour is required; depth, status and source_x are written when their data is not NULL. */
typedef struct reproject_target {
  reproject_mut_color color;
  reproject_mut_plane depth;
  reproject_byte_plane status;
  reproject_mut_plane source_x;
} reproject_target;

/* Packed RGBA pixels in an engine format (C++ ColorView::packed): row y starts at
 * (const uint8_t*)data + y * stride, stride in bytes (>= width * 4, or * 8 for RGBA16F). */
typedef struct reproject_pixels {
  const void* data;
  int32_t width;
  int32_t height;
  int64_t stride;   /* bytes */
  int32_t format;   /* REPROJECT_COLOR_RGBA8, _RGBA8_SRGB, _RGBA16F; FLOAT32 (0): not used */
  int32_t reserved; /* 0 (anything else is refused: kept for a later version) */
} reproject_pixels;

typedef struct reproject_mut_pixels {
  void* data;
  int32_t width;
  int32_t height;
  int64_t stride;   /* bytes */
  int32_t format;   /* the source's */
  int32_t reserved; /* 0 (refused otherwise) */
} reproject_mut_pixels;

/* A depth buffer in any REPROJECT_DEPTH_FORMAT_* (C++ DepthBuffer): row y starts at
 * (const uint8_t*)data + y * stride, stride in bytes (>= width * bytes per pixel; FLOAT32 rows on
 * 4-byte boundaries). linear_near and linear_far are read for RGBA8_PACKED_LINEAR only: the linear
 * depth the packed value spans (finite, different); a zeroed struct leaves them 0, which is refused. */
typedef struct reproject_depth_buffer {
  const void* data;
  int32_t width;
  int32_t height;
  int64_t stride; /* bytes */
  int32_t format; /* REPROJECT_DEPTH_FORMAT_* */
  float linear_near;
  float linear_far;
  int32_t reserved; /* 0 (refused otherwise) */
} reproject_depth_buffer;

/* An output depth buffer: in the source's format; its linear range is not read (packed output is
 * stored with the source's range). */
typedef struct reproject_mut_depth_buffer {
  void* data;
  int32_t width;
  int32_t height;
  int64_t stride; /* bytes */
  int32_t format; /* the source's */
  float linear_near;
  float linear_far;
  int32_t reserved; /* 0 (refused otherwise) */
} reproject_mut_depth_buffer;

/* A source in any formats (C++ SourceView), for reproject_warp_buffers; zero it, then set:
 *  - colour: float planes in `color` (pixels.format REPROJECT_COLOR_FLOAT32, i.e. 0, and pixels
 *    otherwise zeroed), or packed pixels in `pixels` (a packed pixels.format, `color` zeroed);
 *  - depth: a float plane in `depth`, or a buffer in any format in `depth_buffer`: exactly one.
 * Setting both halves of either pair is refused (REPROJECT_INVALID_OPTION), as are unknown formats. */
typedef struct reproject_source_buffers {
  reproject_color color;
  reproject_pixels pixels;
  reproject_plane depth;
  reproject_depth_buffer depth_buffer;
} reproject_source_buffers;

/* Outputs in the source's formats (C++ TargetView): colour in `color` or `pixels` as for the
 * source; depth, when wanted, in `depth` for a source `depth` plane or in `depth_buffer` (the
 * source's depth format) for a source `depth_buffer`; status and source_x as in reproject_target.
 * Outputs whose data is NULL are not written (colour is required). */
typedef struct reproject_target_buffers {
  reproject_mut_color color;
  reproject_mut_pixels pixels;
  reproject_mut_plane depth;
  reproject_mut_depth_buffer depth_buffer;
  reproject_byte_plane status;
  reproject_mut_plane source_x;
} reproject_target_buffers;

/* A depth decoder, by value: its encoding and planes. Made by the reproject_decoder_* factories
 * (an invalid one is refused by the calls that use it, with the decoder's message). */
typedef struct reproject_decoder {
  int32_t encoding;
  int32_t reserved; /* 0 */
  double near_plane;
  double far_plane;
} reproject_decoder;

/* p(w) = a + b w pixels (C++ ParallaxModel). */
typedef struct reproject_parallax {
  float a;
  float b;
} reproject_parallax;

/* A request to stop running calls (C++ Options::cancel): the caller owns it, initialises it with
 * reproject_cancel_init before any other use, points options.cancel at it, and
 * calls reproject_cancel_request from any thread, or from a signal handler (a lock-free store),
 * while calls run. A call reads it between blocks of a few rows and then returns
 * REPROJECT_CANCELLED soon after (an 8K frame within a few tens of milliseconds at one thread);
 * its outputs are then unspecified (some rows written, others not). It stays requested until
 * reproject_cancel_init is called again. Touch its bytes only through these functions, and do not
 * move or free it while a call that uses it runs. */
typedef struct reproject_cancel {
  int32_t state; /* opaque */
} reproject_cancel;

void reproject_cancel_init(reproject_cancel* cancel);               /* NULL: no-op */
void reproject_cancel_request(reproject_cancel* cancel);            /* NULL: no-op; async-signal-safe */
int32_t reproject_cancel_requested(const reproject_cancel* cancel); /* 1 or 0; NULL: 0 */

/* C++ Options; the optional fields have a has_ flag (0: unset, the C++ default). Fill with
 * reproject_options_init() first: see ABI above. */
typedef struct reproject_options {
  uint32_t struct_size;
  int32_t method;
  int32_t has_max_negative_parallax;
  float max_negative_parallax;
  float hole_threshold;
  int32_t hole_fill;
  int32_t edge;
  int32_t guard;
  int32_t has_probe_parallax;
  float probe_parallax;
  int32_t march_steps;
  int32_t secant_max_steps;
  int32_t arch; /* REPROJECT_ARCH_AUTO or an REPROJECT_ARCH_* */
  int32_t threads;
  /* Added after the fields above (a shorter struct_size from an older header leaves it NULL):
   * NULL, the default, is a call that cannot be stopped. */
  const reproject_cancel* cancel;
} reproject_options;

/* The caller's job system (C++ ParallelFor): run must call task(task_context, i) once for every i
 * in [0, count), on any threads in any order, and return when all calls have returned. run is
 * required (a struct with run NULL is refused with REPROJECT_INVALID_OPTION, not replaced by the
 * library's pool); context is passed to run as it is and may be NULL. */
typedef struct reproject_parallel_for {
  void* context;
  void (*run)(void* context, int32_t count, void (*task)(void* task_context, int32_t index), void* task_context);
} reproject_parallel_for;

int32_t reproject_abi_version(void);
/* The library's version, "MAJOR.MINOR.PATCH" (C++ reproject::version()): a static string, never
 * NULL; do not free it. Unlike reproject_abi_version(), it changes with every release. */
const char* reproject_version(void);

/* The calling thread's last failure message ("ok" if none yet). Each thread has its own: the
 * pointer is to that thread's buffer, and the text stays valid (and unchanged) until the same thread
 * makes another call of this interface that fails; calls that succeed leave it as it is. Never NULL;
 * do not free it. Copy it before the thread's next call if you keep it. */
const char* reproject_last_error_message(void);
/* Short stable names, e.g. "invalid_stride", "secant", "avx2", "standard": the C++ to_string's.
 * "unknown" for any other value (REPROJECT_ARCH_AUTO included). */
const char* reproject_status_name(reproject_status status);
const char* reproject_method_name(int32_t method);
const char* reproject_arch_name(int32_t arch);
const char* reproject_encoding_name(int32_t encoding);
const char* reproject_color_format_name(int32_t format);       /* "float32", "rgba8", "rgba8_srgb", "rgba16f" */
const char* reproject_depth_format_name(int32_t format);       /* "float32", "unorm16", "unorm24_s8", ... */

int32_t reproject_arch_supported(int32_t arch); /* 1 or 0 */
int32_t reproject_selected_arch(void);

void reproject_options_init(reproject_options* options); /* NULL: no-op */

/* Decoder factories (C++ DepthDecoder). Each fills *out (also when it fails, with a decoder the
 * reprojection refuses) and returns its validation. out is required; a NULL matrix m is refused
 * (REPROJECT_INVALID_DECODER, as the C++ factories do). */
reproject_status reproject_decoder_from_near_far(int32_t encoding, double near_plane, double far_plane,
                                                 reproject_decoder* out);
reproject_status reproject_decoder_linear(reproject_decoder* out);
reproject_status reproject_decoder_disparity(reproject_decoder* out);
reproject_status reproject_decoder_from_d3d_projection(const float m[16], int32_t encoding, reproject_decoder* out);
reproject_status reproject_decoder_from_gl_projection(const float m[16], int32_t encoding, reproject_decoder* out);
/* w = 1/z and z for a stored value; NaN for an invalid decoder or a NULL one. */
float reproject_decoder_inverse_depth(const reproject_decoder* decoder, float stored);
float reproject_decoder_linear_depth(const reproject_decoder* decoder, float stored);

/* Parallax factories (C++ ParallaxModel); each returns the model's validation. out is required. */
reproject_status reproject_parallax_from_stereo(double separation, double convergence, int32_t width,
                                                int32_t direction, reproject_parallax* out);
reproject_status reproject_parallax_from_physical(double interocular, double screen_width, double convergence,
                                                  int32_t width, int32_t direction, reproject_parallax* out);
reproject_status reproject_parallax_from_disparity(int32_t direction, reproject_parallax* out);
/* A renderer's stereo rig (C++ StereoCamera::from_rig(...).parallax(width, direction)): interaxial
 * and convergence distances in one unit, the horizontal field of view in radians. */
reproject_status reproject_parallax_from_rig(double interaxial, double convergence, double horizontal_fov,
                                             int32_t width, int32_t direction, reproject_parallax* out);
/* Relative inverse depth, decoded by reproject_decoder_disparity (C++ ParallaxModel::from_relative):
 * max_parallax a fraction of the width, zero_plane in 0..1. */
reproject_status reproject_parallax_from_relative(double max_parallax, double zero_plane, int32_t width,
                                                  int32_t direction, reproject_parallax* out);

/* reproject() and reproject_pair(). Required: source (centre), decoder, model (centre_to_right),
 * options (from reproject_options_init), target (left and right). jobs may be NULL: the library's
 * own thread pool (options.threads); a non-NULL jobs must have run set. */
reproject_status reproject_warp(const reproject_source* source, const reproject_decoder* decoder,
                                const reproject_parallax* model, const reproject_options* options,
                                const reproject_target* target, const reproject_parallel_for* jobs);
reproject_status reproject_warp_pair(const reproject_source* centre, const reproject_decoder* decoder,
                                     const reproject_parallax* centre_to_right, const reproject_options* options,
                                     const reproject_target* left, const reproject_target* right,
                                     const reproject_parallel_for* jobs);

/* The same two calls on buffers in any format (reproject_source_buffers): the targets are written
 * in the source's colour and depth formats. Same options, decoder, model and jobs as above; unknown
 * format values are refused with REPROJECT_INVALID_OPTION, and everything the C++ validation
 * refuses (a stride too small, target formats unlike the source's, ...) comes back with its code
 * and message. */
reproject_status reproject_warp_buffers(const reproject_source_buffers* source, const reproject_decoder* decoder,
                                        const reproject_parallax* model, const reproject_options* options,
                                        const reproject_target_buffers* target, const reproject_parallel_for* jobs);
reproject_status reproject_warp_pair_buffers(const reproject_source_buffers* centre, const reproject_decoder* decoder,
                                             const reproject_parallax* centre_to_right,
                                             const reproject_options* options, const reproject_target_buffers* left,
                                             const reproject_target_buffers* right, const reproject_parallel_for* jobs);

#ifdef __cplusplus
}
#endif

#endif /* REPROJECT_REPROJECT_H */
