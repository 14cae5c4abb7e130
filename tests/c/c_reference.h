/* The C++ reference of test_c_api.c (c_reference.cpp), declared for both languages. */
#ifndef REPROJECT_TESTS_C_REFERENCE_H
#define REPROJECT_TESTS_C_REFERENCE_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* A view in any formats as raw pointers, for the reference to build its own C++ views from.
 * Formats go by name ("rgba8", "unorm24_s8", ...), parsed by the C++ API, so the reference does
 * not share the C constants' values with the code under test. */
typedef struct RefView {
  const char* color_format; /* "float32": three planes color[0..2]; packed: color[0] */
  void* color[3];
  int64_t color_stride;     /* bytes */
  const char* depth_format;
  int depth_plane;          /* float32 only: 1 as the float plane SourceView::depth, 0 as a depth_buffer */
  void* depth;              /* NULL: no depth output */
  int64_t depth_stride;     /* bytes */
  float linear_near, linear_far;
  uint8_t* status;          /* outputs only */
  float* source_x;
} RefView;

/* reproject() (left NULL) or reproject_pair() of `source` at width x height, every output set in
 * the RefViews written. linear_decoder: DepthDecoder::linear(), else standard near/far. The model
 * is StereoCamera{0.03, 4.0}: left_to_right for one eye, centre_to_right for a pair. threads > 0:
 * Options::threads; 0: a serial ParallelFor. Returns 0 when the C++ call succeeds. */
int reference_warp_buffers(const RefView* source, const RefView* left, const RefView* right, int width, int height,
                           int linear_decoder, double near_plane, double far_plane, int method, int arch, int threads);

#ifdef __cplusplus
}
#endif

#endif
